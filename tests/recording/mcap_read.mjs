// Reads an MCAP file with the reference TypeScript reader, @mcap/core's
// McapIndexedReader (footer, summary, chunk and message indexes, CRCs
// checked), zstd chunks decompressed by fzstd, over a file handle; prints
// JSON: messages per topic (every message read), the Statistics record's
// counts, the attachments' and metadata records' names (and the metadata
// records' key-values, metadataRecords), bytes read. With --topics, only
// the messages of those topics (comma-separated) are read, as a player of
// one session would, and nothing else: bytesRead then says what that cost.
//
//   node tests/recording/mcap_read.mjs FILE [--topics T1,T2]
//
// The packages come from GROUNDSIM_MCAP_NODE_MODULES, else web/node_modules
// (npm install in web/). Exit 2 with a reason when the file cannot be read.
import { open } from "node:fs/promises";
import { createRequire } from "node:module";
import path from "node:path";
import { fileURLToPath } from "node:url";

const file = process.argv[2];
const only = process.argv[3] === "--topics" ? (process.argv[4] ?? "").split(",").filter(Boolean) : undefined;
if (!file || (process.argv[3] !== undefined && !only?.length)) {
  console.error("usage: node mcap_read.mjs FILE.mcap [--topics T1,T2]");
  process.exit(2);
}
const modules =
  process.env.GROUNDSIM_MCAP_NODE_MODULES ||
  path.join(path.dirname(fileURLToPath(import.meta.url)), "..", "..", "web", "node_modules");
// resolved from that node_modules folder, wherever this script lives
const require = createRequire(path.join(modules, "resolve-from-here.js"));
const { McapIndexedReader } = require("@mcap/core");
const fzstd = require("fzstd");

const handle = await open(file, "r");
let bytesRead = 0;
const readable = {
  size: async () => BigInt((await handle.stat()).size),
  read: async (offset, size) => {
    const buffer = new Uint8Array(Number(size));
    let done = 0;
    while (done < buffer.length) {
      const { bytesRead: n } = await handle.read(buffer, done, buffer.length - done, Number(offset) + done);
      if (n === 0) throw new Error(`short read at ${Number(offset) + done}`);
      done += n;
    }
    bytesRead += buffer.length;
    return buffer;
  },
};

try {
  const reader = await McapIndexedReader.Initialize({
    readable,
    decompressHandlers: {
      zstd: (data, size) => fzstd.decompress(data, new Uint8Array(Number(size))),
    },
  });
  const topics = {};
  let lastLogTime = -1n;
  let ordered = true;
  for await (const m of reader.readMessages(only ? { topics: only } : {})) {
    const topic = reader.channelsById.get(m.channelId)?.topic ?? `#${m.channelId}`;
    topics[topic] = (topics[topic] ?? 0) + 1;
    if (m.logTime < lastLogTime) ordered = false;
    lastLogTime = m.logTime;
  }
  const attachments = [];
  const metadata = [];
  const metadataRecords = {};
  if (!only) {
    for await (const a of reader.readAttachments()) attachments.push(a.name);
    for await (const m of reader.readMetadata()) {
      metadata.push(m.name);
      metadataRecords[m.name] = Object.fromEntries(m.metadata);
    }
  }
  const s = reader.statistics;
  const statistics = s && {
    messageCount: Number(s.messageCount),
    schemaCount: s.schemaCount,
    channelCount: s.channelCount,
    attachmentCount: s.attachmentCount,
    metadataCount: s.metadataCount,
    chunkCount: s.chunkCount,
    channelMessageCounts: Object.fromEntries(
      [...s.channelMessageCounts].map(([id, n]) => [String(id), Number(n)]),
    ),
  };
  console.log(
    JSON.stringify({
      library: reader.header.library,
      topics,
      ordered,
      statistics,
      chunkIndexes: reader.chunkIndexes.length,
      attachments,
      metadata,
      metadataRecords,
      bytesRead,
      fileSize: Number(await readable.size()),
    }),
  );
} catch (e) {
  console.error(`mcap_read.mjs: ${file}: ${e.message}`);
  process.exitCode = 2;
} finally {
  await handle.close();
}

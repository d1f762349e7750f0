// McapReader: reads MCAP files (https://mcap.dev/spec), ours and others'.
//
// A complete file (footer and summary) is read through its index: opening
// it reads the header, the footer and the summary only, and readMessages()
// reads only the chunks that hold the requested channels in the requested
// time range (plus, with a channel filter, those channels' message indexes).
// A file without them (the writer crashed, or the file was cut) is read by
// scanning the data section's record headers once at open: whole chunks
// are used, a record cut by the end of the file is ignored (endNote() says
// how much). A complete file without chunk indexes (other writers' unchunked
// files) has its messages found by the same scan. A file that ends with the
// magic but is otherwise malformed is an error, not a cut file.
//
// Hostile input: every length is checked against the file and the record
// that holds it; a record loaded into memory is at most 1 GiB
// (mcap::kMaxLoadBytes), a chunk's uncompressed size too, and decompressed
// memory is only touched as zstd produces it. Errors are std::runtime_error
// naming the file and the offset of the record at fault. CRCs (chunks,
// attachments, summary) are verified whenever the bytes they cover are read;
// the data section's CRC by verify().
//
// Not thread-safe: one reader, one thread at a time.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "recording/mcap_format.hpp"

namespace groundsim::recording {

struct McapMessage {
  std::uint16_t channel;
  std::uint32_t sequence;
  std::uint64_t log_time, publish_time;  // ns
  std::string data;
};

struct McapChannelInfo {
  std::uint16_t id, schema_id;
  std::string topic, message_encoding;
  std::map<std::string, std::string> metadata;
};

struct McapSchemaInfo {
  std::uint16_t id;
  std::string name, encoding, data;
};

// One chunk as the index (or the scan) describes it: for tools ("mcap
// info") and tests.
struct McapChunkInfo {
  std::uint64_t offset = 0, length = 0;  // the whole Chunk record in the file
  std::uint64_t message_start_time = 0, message_end_time = 0;
  std::string compression;               // "zstd" or "" (none)
  std::uint64_t compressed_size = 0, uncompressed_size = 0;
  std::vector<std::uint16_t> channels;   // from its message indexes; empty: not indexed
};

class McapReader {
 public:
  // Opens path and reads the header, then the footer and summary, or scans.
  // Throws std::runtime_error with the reason: cannot open, not MCAP (bad
  // magic, too short), unsupported version, truncated header, a corrupt
  // summary (CRC mismatch, lengths past the file), ...
  explicit McapReader(const std::string& path);
  ~McapReader();
  McapReader(const McapReader&) = delete;
  McapReader& operator=(const McapReader&) = delete;

  // Footer and summary present: read by index. False: a crashed or cut file,
  // read by scanning.
  bool complete() const { return complete_; }
  // "complete", or what the scan found, e.g. "incomplete: no footer; 12
  // whole chunks up to log time 29.98 s, 3411 bytes of a cut record ignored".
  std::string endNote() const { return end_note_; }

  // From the summary, or the data section's records. Other writers may keep
  // Schema and Channel records inside chunks only: in a scanned file those
  // appear as readMessages() decompresses the chunks holding them.
  const std::map<std::uint16_t, McapChannelInfo>& channels() const { return channels_; }
  const std::map<std::uint16_t, McapSchemaInfo>& schemas() const { return schemas_; }
  // Messages per channel: the Statistics record's when the file is complete
  // (and has one), else counted from message indexes (or, for a chunk
  // without them, by decompressing it). Channels without messages are absent.
  std::map<std::uint16_t, std::uint64_t> messageCounts() const;

  // Calls f for every message of the given channels (empty: all) with
  // t0 <= log_time <= t1, in log_time order (ties: file order). Only the
  // chunks whose index says they hold those channels and overlap [t0, t1]
  // are read; at once in memory: the chunks whose time ranges overlap the
  // message being delivered. Chunk CRCs are checked (an error names the
  // chunk's offset).
  void readMessages(const std::function<void(const McapMessage&)>& f,
                    const std::set<std::uint16_t>& channels = {}, std::uint64_t t0 = 0,
                    std::uint64_t t1 = UINT64_MAX);

  // (name, data) of every attachment, CRCs checked.
  std::vector<std::pair<std::string, std::string>> attachments();
  // Metadata records by name (a later record of the same name wins).
  std::map<std::string, std::map<std::string, std::string>> metadata();

  std::vector<McapChunkInfo> chunks() const;

  // Reads everything: the data section's CRC (DataEnd's, when present and
  // not 0), every chunk (decompressed, CRC) and attachment (CRC). Throws on
  // the first mismatch. readMessages() does not do this: it would read the
  // whole file to deliver one session.
  void verify();

  // Bytes the reads so far took from the file (all of them: header, footer,
  // summary, chunks, indexes), e.g. to check that one session reads a small
  // part of a file holding many.
  std::uint64_t bytesRead() const { return bytes_read_; }

 private:
  struct ChunkRef;  // these four: mcap_reader_detail.hpp, mcap_scan.cpp, mcap_chunks.cpp
  struct Loaded;
  class Scanner;     // scan()'s steps
  class Delivery;    // readMessages()'s steps

  std::string readAt(std::uint64_t offset, std::uint64_t n, const char* what) const;
  void readInto(char* dst, std::uint64_t offset, std::uint64_t n) const;
  [[noreturn]] void fail(const std::string& why) const;

  void readHeader();
  bool readFooterAndSummary();  // false: no footer, or no summary (scan)
  void parseSummary(const std::string& summary, std::uint64_t summary_start);
  void scan(std::uint64_t end);
  void addSchema(mcap::Cursor& c);
  void addChannel(mcap::Cursor& c);

  // The chunk's records, decompressed and CRC-checked (storage in out).
  std::string_view loadChunk(const ChunkRef& r, Loaded& out) const;
  std::vector<std::pair<std::uint64_t, std::uint64_t>> readMessageIndex(std::uint64_t offset,
                                                                        std::uint16_t channel) const;
  std::map<std::uint16_t, std::uint64_t> countChunk(const ChunkRef& r) const;

  std::string path_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
  std::uint64_t data_start_ = 0;      // after the Header record
  std::uint64_t data_end_offset_ = 0;  // the DataEnd record, 0: none found
  bool complete_ = false;
  std::string end_note_;
  mutable std::uint64_t bytes_read_ = 0;
  mutable void* zstd_ = nullptr;  // ZSTD_DCtx*, created at the first compressed chunk, reused

  std::map<std::uint16_t, McapChannelInfo> channels_;
  std::map<std::uint16_t, McapSchemaInfo> schemas_;
  std::vector<ChunkRef> refs_;  // chunks (and, in scanned files, loose messages)
  std::vector<mcap::AttachmentIndex> attachment_refs_;  // offset and length at least
  std::vector<mcap::MetadataIndex> metadata_refs_;
  bool have_statistics_ = false;
  mcap::Statistics statistics_;
  mutable bool counted_ = false;
  mutable std::map<std::uint16_t, std::uint64_t> counts_;
};

}  // namespace groundsim::recording

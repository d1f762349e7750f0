// A well-behaved Foxglove client on a thread of its own (a worker of
// foxglove_hostile.mjs), so that the test's own hostile sends (megabytes of
// text built and masked on the main thread) never keep it from reading: it
// subscribes to one topic and reports what it got when asked.
import { parentPort, workerData } from 'node:worker_threads';
import { createRequire } from 'node:module';

const require = createRequire(`${workerData.nodeModules}/`);
const WebSocket = require('ws');
const ws = new WebSocket(workerData.url, [workerData.protocol]);
const seqs = [];
const statuses = [];
let closed = null, channel = null;
ws.on('message', (buf, isBinary) => {
  if (!isBinary) {
    const m = JSON.parse(buf.toString());
    if (m.op === 'status') statuses.push(m);
    if (m.op === 'advertise' && channel === null) {
      const ch = m.channels.find((c) => c.topic === workerData.topic);
      if (ch) {
        channel = ch.id;
        ws.send(JSON.stringify({ op: 'subscribe', subscriptions: [{ id: 1, channelId: ch.id }] }));
      }
    }
    return;
  }
  seqs.push(JSON.parse(buf.subarray(13).toString()).seq);
});
ws.on('close', (code) => { closed = code; });
ws.on('error', () => {});
parentPort.on('message', () => {
  let gaps = 0, backwards = 0;
  for (let i = 1; i < seqs.length; ++i) {
    const d = seqs[i] - seqs[i - 1];
    if (d <= 0) ++backwards; else gaps += d - 1;
  }
  parentPort.postMessage({ count: seqs.length, gaps, backwards, statuses, closed });
});

// Bad and slow Foxglove clients never affect the others. Against the real
// groundsim-server and groundsim-web (--foxglove-port, the default outbox
// of 1,024 messages; a session publishing 2 x 200 messages a second):
//
// - a good client (on a thread of its own, foxglove_reader.mjs) subscribes
//   to a session's states and keeps receiving all of them (seq with no gap)
//   through everything below;
// - a hostile client's malformed JSON, non-objects, missing or unknown ops,
//   ops needing capabilities the server does not offer, bad and unknown
//   ids, a reused subscription id, a binary message and messages over the
//   64 KiB limit (100 KiB, 4 MiB) each get a status error (level 2) naming
//   the field, and the client stays connected; then a message over the
//   16 MiB hard limit closes that client alone;
// - a client that stops reading (its socket paused) loses the oldest of its
//   outbox, counted in /metrics, gets a status warning saying how many when
//   it reads again, and its states still arrive in order;
// - afterwards a new client connects and receives.
import * as f from './foxglove_common.mjs';

// the default outbox: a client must stop reading for seconds to lose anything
const OUTBOX = 1024;
const { http, ws } = await f.startServices(['--foxglove-outbox', String(OUTBOX)]);
const id = f.createSession('sedan.json', '--publish-rate', '200');
console.log(`groundsim create: ${id}`);

async function subscribed(protocol, subId, topics = ['state']) {
  const c = f.rawClient(ws, [protocol]);
  await c.open();
  await f.until(`the session's channels at a ${protocol} client`, () => topics.every((t) => c.topic(`/${id}/${t}`)));
  c.send({ op: 'subscribe', subscriptions: topics.map((t, i) => ({ id: subId + i, channelId: c.topic(`/${id}/${t}`).id })) });
  await f.until('its first states', () => c.data.length > 0);
  return c;
}
const states = (c, sub) => c.data.filter((d) => d.sub === sub).map((d) => d.json);

// the good client reads on a thread of its own: this one's big sends would stall it
const { Worker } = await import('node:worker_threads');
const goodWorker = new Worker(new URL('./foxglove_reader.mjs', import.meta.url), {
  workerData: { url: ws, protocol: 'foxglove.websocket.v1', topic: `/${id}/state`,
    nodeModules: process.env.GROUNDSIM_WEB_NODE_MODULES } });
const good = () => new Promise((resolve) => { goodWorker.once('message', resolve); goodWorker.postMessage('report'); });
await f.until('states at the good client', async () => (await good()).count > 20);

// ---- hostile messages: each a status error naming the field ---------------------------
const h = await subscribed('foxglove.sdk.v1', 1);
const stateId = h.topic(`/${id}/state`).id;
const hostile = [
  ['{"op":"subscribe",', 'malformed JSON'],
  ['[1,2,3]', 'must be a JSON object'],
  [{ subscriptions: [] }, '/op: missing'],
  [{ op: 5 }, '/op: must be a string'],
  [{ op: 'dance' }, 'unknown op "dance"'],
  [{ op: 'advertise', channels: [] }, 'needs the capability clientPublish'],
  [{ op: 'getParameters', parameterNames: [] }, 'needs the capability parameters'],
  [{ op: 'subscribe' }, '/subscriptions: missing'],
  [{ op: 'subscribe', subscriptions: 3 }, '/subscriptions: must be an array'],
  [{ op: 'subscribe', subscriptions: [{ id: -1, channelId: stateId }] }, '/subscriptions/0/id: must be an unsigned'],
  [{ op: 'subscribe', subscriptions: [{ id: 2 ** 32, channelId: stateId }] }, '/subscriptions/0/id: at most 4294967295'],
  [{ op: 'subscribe', subscriptions: [{ id: 9, channelId: 'x' }] }, '/subscriptions/0/channelId: must be an unsigned'],
  [{ op: 'subscribe', subscriptions: [{ id: 9, channelId: 987654 }] }, '/subscriptions/0/channelId: unknown channel 987654'],
  [{ op: 'subscribe', subscriptions: [{ id: 1, channelId: 1 }] }, '/subscriptions/0/id: subscription 1 is in use'],
  [{ op: 'subscribe', subscriptions: [{ id: 9, channelId: stateId }] }, '/subscriptions/0/channelId: channel ' + stateId + ' is already subscribed'],
  [{ op: 'unsubscribe', subscriptionIds: [42] }, '/subscriptionIds/0: unknown subscription 42'],
  [{ op: 'unsubscribe', subscriptionIds: ['a'] }, '/subscriptionIds/0: must be an unsigned'],
  [Buffer.from([1, 0, 0, 0, 0, 1, 2, 3]), 'binary message'],
  ['{"op":"subscribe","pad":"' + 'x'.repeat(100 * 1024) + '"}', 'at most 65536'],
  ['x'.repeat(4 * 1024 * 1024), 'refused message of 4194304 bytes: at most 65536'],
];
// errors only: this client may fall behind too while it sends megabytes (a warning then)
const errors = () => h.statuses.filter((s) => s.level === 2);
for (const [msg, expect] of hostile) {
  const before = errors().length;
  if (Buffer.isBuffer(msg)) h.ws.send(msg); else h.send(msg);
  await f.until(`a status for ${String(JSON.stringify(msg)).slice(0, 60)}`, () => errors().length > before);
  const s = errors().at(-1);
  if (s.level !== 2 || !s.message.includes(expect))
    await f.fail(`for ${String(JSON.stringify(msg)).slice(0, 80)}: expected an error with "${expect}", got ${JSON.stringify(s)}`);
  console.log(`status error: ${s.message.slice(0, 120)}`);
}
if (h.closed) await f.fail(`the hostile client was closed: ${JSON.stringify(h.closed)}`);
// its own subscription still works: the refusals changed nothing
const hBefore = h.data.length;
await f.until('states still at the hostile client', () => h.data.length > hBefore + 20);

// a message over the hard limit: that client is closed, saying why
h.ws.send('x'.repeat(20 * 1024 * 1024));
await f.until('the hostile client closed', () => h.closed, 30000);
if (h.closed.code !== 1009 || !h.closed.reason.includes('16777216'))
  await f.fail(`closed with ${JSON.stringify(h.closed)}, expected 1009 (message too big) and the limit`);
console.log(`a 20 MiB message: closed ${h.closed.code} "${h.closed.reason}"`);

// ---- a client that stops reading ------------------------------------------------------
const slow = await subscribed('foxglove.sdk.v1', 1, ['state', 'car_state']);
const m0 = await f.metrics(http);
slow.ws._socket.pause();  // stops reading: the kernel's buffers fill, then the bridge's outbox
const t0 = Date.now();
await f.until('the bridge to drop the oldest of the slow client\'s outbox', async () =>
  (await f.metrics(http)).groundsim_web_foxglove_messages_dropped_total > m0.groundsim_web_foxglove_messages_dropped_total + 200,
60000, 250);
const stalledMs = Date.now() - t0;
const m1 = await f.metrics(http);
slow.ws._socket.resume();
// The warnings (at most one per 5 s: the first may come while the kernel
// still takes a little, the rest with the next one) add up to what the
// metrics counted during the stall, at least.
const during = m1.groundsim_web_foxglove_messages_dropped_total - m0.groundsim_web_foxglove_messages_dropped_total;
const warnings = () => slow.statuses.filter((s) => s.level === 1 && /dropped \d+ messages/.test(s.message));
const told = () => warnings().reduce((sum, s) => sum + Number(s.message.match(/dropped (\d+) messages/)[1]), 0);
await f.until(`status warnings telling of ${during} drops`, () => told() >= during, 20000);
const warning = warnings().at(-1);
const slowStates = states(slow, 1);
const ssq = f.seqCheck(slowStates);
if (ssq.backwards) await f.fail(`the slow client's states out of order: ${JSON.stringify(ssq)}`);
if (ssq.gaps === 0) await f.fail('the slow client lost nothing: it did not stall');
console.log(`slow client: stalled ${stalledMs} ms, ${m1.groundsim_web_foxglove_messages_dropped_total} dropped ` +
  `(metrics), ${slowStates.length} states in order with ${ssq.gaps} missing; ${warnings().length} warning(s) telling of ` +
  `${told()}, the last "${warning.message}"`);

// ---- the good client saw none of it -----------------------------------------------------------
const g = await good();
if (g.backwards || g.gaps) await f.fail(`the good client's states: ${JSON.stringify(g)}`);
if (g.statuses.length) await f.fail(`the good client got statuses: ${JSON.stringify(g.statuses)}`);
if (g.closed !== null) await f.fail('the good client was closed');
await f.until('the good client still receiving', async () => (await good()).count > g.count + 20);

// ---- and a new one connects ---------------------------------------------------------------
const late = await subscribed('foxglove.sdk.v1', 5);
const m2 = await f.metrics(http);
if (!(m2.groundsim_web_foxglove_client_errors_total >= hostile.length + 1)) await f.fail(`client errors: ${JSON.stringify(m2)}`);
if (m2.groundsim_web_foxglove_clients_closed_total !== 1) await f.fail(`clients closed: ${m2.groundsim_web_foxglove_clients_closed_total}`);
console.log(`metrics: client errors ${m2.groundsim_web_foxglove_client_errors_total}, closed ${m2.groundsim_web_foxglove_clients_closed_total}, ` +
  `dropped ${m2.groundsim_web_foxglove_messages_dropped_total}, clients ${m2.groundsim_web_foxglove_clients}`);
late.ws.close();
const goodCount = (await good()).count;
await goodWorker.terminate();
f.cli('stop', id);
await f.pass(`${hostile.length} hostile messages answered, a 20 MiB message closed its client alone, a stalled client's ` +
  `oldest dropped (${m1.groundsim_web_foxglove_messages_dropped_total}); the good client got ${goodCount} states with no gap`);

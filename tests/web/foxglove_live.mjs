// Foxglove's WebSocket protocol, live: the bridge's --foxglove-port endpoint
// against a real groundsim-server over LCM, with the client library
// Foxglove's own tools used (npm @foxglove/ws-protocol, subprotocol
// foxglove.websocket.v1) and a raw client asking for foxglove.sdk.v1, the
// only subprotocol today's Foxglove SDK servers accept.
//
// - both handshakes answer with the subprotocol asked for (sdk.v1 when a
//   client offers both); anything else is refused with 400 and the reason;
// - a session created with `groundsim create` is advertised: state, events,
//   applied, and car_state (a road car) with encoding json and a JSON Schema;
// - subscribed, its states arrive as message-data frames whose JSON
//   validates against the advertised schema (and declares no field the
//   schema lacks), seq strictly increasing with no gap, timestamps the
//   bridge's receive time (ns since the Unix epoch);
// - unsubscribed, they stop; the session stopped, its channels are
//   unadvertised;
// - the bridge's /metrics counts the clients and messages, and promtool
//   finds them clean (without promtool the test ends SKIP, after the other
//   checks, naming it: never a PASS that did not check).
// "No more" is judged against the bridge's own ordering, not a wall-clock
// wait: an unsubscribe is followed by a second one, whose status error
// ("unknown subscription") comes after every frame sent before it, then 50
// more states at the other client; an unadvertise comes after every frame
// of its channel (their queue is emptied with it), and another session's
// states (behind them in the same queue) are waited for.
// Figures printed: messages per second to a client and the delay from the
// bridge's receive timestamp to the client's reading of the frame.
import * as f from './foxglove_common.mjs';

const { FoxgloveClient } = f.require('@foxglove/ws-protocol');
const Ajv2020 = f.require('ajv/dist/2020').default;
const ajv = new Ajv2020({ strict: false, allErrors: true });

// A copy of a schema in which every object declares all its fields: a field
// the schema does not describe fails validation (schema drift).
function closed(schema) {
  if (Array.isArray(schema)) return schema.map(closed);
  if (!schema || typeof schema !== 'object') return schema;
  const out = {};
  for (const [k, v] of Object.entries(schema)) out[k] = closed(v);
  if (out.type === 'object' && out.properties) out.additionalProperties = false;
  return out;
}

const { http, ws } = await f.startServices();
console.log(`bridge ${http}, foxglove ${ws}`);

// ---- refusals: no subprotocol of ours -------------------------------------------
for (const protocols of [['foo.bar.v1'], []]) {
  const c = f.rawClient(ws, protocols);
  await f.until(`a refusal of ${JSON.stringify(protocols)}`, () => c.refused);
  if (c.refused.status !== 400 || !c.refused.body.includes('foxglove.sdk.v1'))
    await f.fail(`subprotocols ${JSON.stringify(protocols)}: ${JSON.stringify(c.refused)}`);
  console.log(`refused ${JSON.stringify(protocols)}: ${c.refused.status} ${c.refused.body.trim()}`);
}
{
  const both = f.rawClient(ws, ['foxglove.websocket.v1', 'foxglove.sdk.v1']);
  await both.open();
  if (both.ws.protocol !== 'foxglove.sdk.v1') await f.fail(`offered both, got ${both.ws.protocol}`);
  both.ws.close();
}

// ---- client A: @foxglove/ws-protocol's FoxgloveClient (foxglove.websocket.v1) --------
const aSocket = new f.WebSocket(ws, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
const a = new FoxgloveClient({ ws: aSocket });
const aChannels = new Map();
const aStatus = [];
let aInfo = null;
const aData = new Map();  // subscription -> [{ns, at, json}]
a.on('serverInfo', (i) => { aInfo = i; });
a.on('status', (s) => aStatus.push(s));
a.on('error', (e) => f.fail(`client A: ${e}`));
a.on('advertise', (chs) => { for (const c of chs) aChannels.set(c.id, c); });
let aAtUnadvertise = null;  // client A's count of states when the session's channels went
a.on('unadvertise', (ids) => {
  for (const id of ids) {
    if (stateChId !== null && id === stateChId) aAtUnadvertise = aData.get(aState).length;
    aChannels.delete(id);
  }
});
let stateChId = null, aState = null;
a.on('message', ({ subscriptionId, timestamp, data }) => {
  const json = JSON.parse(new TextDecoder().decode(data));
  if (!aData.has(subscriptionId)) aData.set(subscriptionId, []);
  aData.get(subscriptionId).push({ ns: timestamp, at: performance.timeOrigin + performance.now(), json });
});
await f.until('client A to get serverInfo and the first advertise', () => aInfo && aChannels.size > 0);
if (aSocket.protocol !== 'foxglove.websocket.v1') await f.fail(`client A got subprotocol ${aSocket.protocol}`);
console.log(`serverInfo: ${JSON.stringify(aInfo)}`);
if (![...aChannels.values()].some((c) => c.topic === '/events')) await f.fail('no /events channel');

// ---- client B: raw, foxglove.sdk.v1 ---------------------------------------------
const b = f.rawClient(ws, ['foxglove.sdk.v1']);
await b.open();
if (b.ws.protocol !== 'foxglove.sdk.v1') await f.fail(`client B got subprotocol ${b.ws.protocol}`);
await f.until('client B to get serverInfo and advertise', () => b.texts.length >= 2);
if (b.texts[0].op !== 'serverInfo' || b.texts[1].op !== 'advertise')
  await f.fail(`client B's first messages: ${JSON.stringify(b.texts.map((t) => t.op))}`);

// ---- a session comes: its channels are advertised --------------------------------
const createdAt = Date.now();
const id = f.createSession('sedan.json', '--publish-rate', '100');
console.log(`groundsim create: ${id}`);
const topic = (c, t) => [...c.values()].find((ch) => ch.topic === t);
const wanted = ['state', 'events', 'applied', 'car_state'].map((s) => `/${id}/${s}`);
await f.until(`channels ${wanted.join(', ')} at client A`, () => wanted.every((t) => topic(aChannels, t)));
await f.until('the same at client B', () => wanted.every((t) => b.topic(t)));
const stateCh = topic(aChannels, `/${id}/state`);
stateChId = stateCh.id;
for (const t of wanted) {
  const ch = topic(aChannels, t);
  if (ch.encoding !== 'json' || ch.schemaEncoding !== 'jsonschema' || !ch.schemaName.startsWith('groundsim.'))
    await f.fail(`channel ${t}: ${JSON.stringify({ ...ch, schema: '...' })}`);
}
console.log(`advertised: ${wanted.map((t) => `${t} (${topic(aChannels, t).schemaName})`).join(', ')}`);
const validate = ajv.compile(JSON.parse(stateCh.schema));
const validateClosed = ajv.compile(closed(JSON.parse(stateCh.schema)));
const carCh = topic(aChannels, `/${id}/car_state`);
const validateCar = ajv.compile(closed(JSON.parse(carCh.schema)));

// ---- subscribed: states flow ----------------------------------------------------
aState = a.subscribe(stateCh.id);
const aCar = a.subscribe(carCh.id);
const bStateCh = b.topic(`/${id}/state`);
b.send({ op: 'subscribe', subscriptions: [{ id: 7, channelId: bStateCh.id }] });
await f.until('100 states at client A', () => (aData.get(aState) || []).length >= 100);
const t0 = Date.now(), n0 = aData.get(aState).length;
await f.until('300 more states at client A', () => aData.get(aState).length >= n0 + 300, 120000);
const rate = (aData.get(aState).length - n0) / ((Date.now() - t0) / 1000);
const states = aData.get(aState);
for (const [i, m] of states.entries()) {
  if (!validate(m.json)) await f.fail(`state ${i} does not validate: ${ajv.errorsText(validate.errors)}`);
  if (!validateClosed(m.json)) await f.fail(`state ${i} has a field its schema lacks: ${ajv.errorsText(validateClosed.errors)}`);
  if (m.json.session_id !== id) await f.fail(`state ${i} of session ${m.json.session_id}`);
}
for (const [i, m] of (aData.get(aCar) || []).entries())
  if (!validateCar(m.json)) await f.fail(`car state ${i} does not validate: ${ajv.errorsText(validateCar.errors)}`);
const sq = f.seqCheck(states.map((m) => m.json));
if (sq.backwards || sq.gaps) await f.fail(`client A's states: ${JSON.stringify(sq)} (seq must increase by 1)`);
for (let i = 1; i < states.length; ++i)
  if (states[i].ns < states[i - 1].ns) await f.fail(`timestamps go back at state ${i}`);
const delays = states.map((m) => m.at - Number(m.ns) / 1e6);
// the receive time on this machine's clock: after the session was created,
// before the client read the frame (1 ms for the clocks' rounding)
for (const [i, m] of states.entries()) {
  const ms = Number(m.ns) / 1e6;
  if (!(ms >= createdAt - 1 && ms <= m.at + 1))
    await f.fail(`state ${i}'s timestamp ${ms} ms is not a receive time: the session was created at ${createdAt}, the frame read at ${m.at}`);
}
console.log(`client A: ${states.length} states, seq ${states[0].json.seq}..${states.at(-1).json.seq} with no gap, ` +
  `${rate.toFixed(1)} states/s, ${(aData.get(aCar) || []).length} car states; receive timestamp to client: ` +
  `median ${f.percentile(delays, 0.5).toFixed(2)} ms, p99 ${f.percentile(delays, 0.99).toFixed(2)} ms`);

await f.until('states at client B', () => b.data.length >= 50);
if (b.data.some((d) => d.sub !== 7)) await f.fail('client B got data for a subscription it did not make');
const bsq = f.seqCheck(b.data.map((d) => d.json));
if (bsq.backwards || bsq.gaps) await f.fail(`client B's states: ${JSON.stringify(bsq)}`);
if (!b.data.every((d) => validate(d.json))) await f.fail('a state at client B does not validate');
console.log(`client B (foxglove.sdk.v1): ${b.data.length} states, no gap`);
if (aStatus.length || b.statuses.length) await f.fail(`status messages: ${JSON.stringify([...aStatus, ...b.statuses])}`);

// ---- metrics ----------------------------------------------------------------------
const m = await f.metrics(http);
console.log(`metrics: clients ${m.groundsim_web_foxglove_clients}, subscriptions ${m.groundsim_web_foxglove_subscriptions}, ` +
  `sent ${m.groundsim_web_foxglove_messages_sent_total}, refused handshakes ${m.groundsim_web_foxglove_handshakes_refused_total}`);
if (m.groundsim_web_foxglove_clients !== 2 || m.groundsim_web_foxglove_subscriptions !== 3 ||
    m.groundsim_web_foxglove_handshakes_refused_total !== 2 || !(m.groundsim_web_foxglove_messages_sent_total > 150))
  await f.fail(`metrics: ${JSON.stringify(m)}`);

// promtool (Debian's prometheus) finds the text clean; without it the test
// ends SKIP after its other checks
let promtool = null;
{
  const { spawnSync } = await import('node:child_process');
  const text = await (await fetch(`${http}metrics`)).text();
  const r = spawnSync(process.env.GROUNDSIM_PROMTOOL || 'promtool', ['check', 'metrics'], { input: text, encoding: 'utf8' });
  if (r.error) promtool = `promtool not installed (${r.error.code}; Debian's prometheus, scripts/setup.sh): /metrics not checked by it`;
  else if (r.status !== 0) await f.fail(`promtool check metrics: ${r.stdout}${r.stderr}`);
  else console.log('promtool check metrics: clean');
}

// ---- unsubscribed: no more -----------------------------------------------------------
// the second unsubscribe is refused (the first took the subscription): its
// status comes after every frame the bridge sent before it
b.send({ op: 'unsubscribe', subscriptionIds: [7] });
b.send({ op: 'unsubscribe', subscriptionIds: [7] });
await f.until('client B\'s second unsubscribe refused', () => b.statuses.length > 0, 60000);
if (!(b.statuses.length === 1 && b.statuses[0].level === 2 && b.statuses[0].message.includes('unknown subscription 7')))
  await f.fail(`client B's statuses after unsubscribing twice: ${JSON.stringify(b.statuses)}`);
const bStopped = b.data.length, aNow = aData.get(aState).length;
await f.until('50 more states at client A', () => aData.get(aState).length >= aNow + 50, 60000);
if (b.data.length !== bStopped) await f.fail(`client B got ${b.data.length - bStopped} states after unsubscribing`);

// ---- the session goes: its channels are unadvertised -------------------------------------
f.cli('stop', id);
await f.until(`the session's channels unadvertised at A`, () => wanted.every((t) => !topic(aChannels, t)), 60000);
await f.until('and at B', () => wanted.every((t) => !b.topic(t)), 60000);
const m2 = await f.metrics(http);
if (m2.groundsim_web_foxglove_subscriptions !== 0) await f.fail(`subscriptions left: ${m2.groundsim_web_foxglove_subscriptions}`);
// another session's states come after anything of the first that was
// still queued for client A
const id2 = f.createSession('plain.json', '--publish-rate', '100');
await f.until(`session ${id2}'s state channel at client A`, () => topic(aChannels, `/${id2}/state`), 60000);
const aState2 = a.subscribe(topic(aChannels, `/${id2}/state`).id);
await f.until(`5 states of ${id2} at client A`, () => (aData.get(aState2) || []).length >= 5, 60000);
if (aData.get(aState).length !== aAtUnadvertise)
  await f.fail(`client A got ${aData.get(aState).length - aAtUnadvertise} states of ${id} after its channel was unadvertised`);
f.cli('stop', id2);
if (promtool) f.skip(`${promtool}; every other check passed`);
await f.pass(`${states.length} states to the npm client at ${rate.toFixed(1)}/s, the raw sdk.v1 client too; ` +
  'channels advertised and unadvertised with the session');

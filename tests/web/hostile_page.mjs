// One page cannot take the server (docs/front-end.md, Fairness), against a
// plain groundsim-server and groundsim-web as the README starts them: a
// hostile page sends, on one WebSocket, 80 creates of sedan.json in fast
// mode with 8 cars at 1000 Hz, 80 real-time creates of 8 cars (leaving
// between them), and a flood
// of 3000 pings. Meanwhile a second, well-behaved browser creates a session
// and drives it:
// - every hostile create is answered: refused naming the limit and its
//   groundsim-web flag (--browser-modes, --browser-sessions,
//   --browser-creates), or created; it never holds more than
//   --browser-sessions (2) at once on the server;
// - the flood is read no faster than --browser-messages (200 a second after
//   a second's burst): its last pong comes at least 14.8 s after the page's
//   socket opened, a bound a loaded machine only makes looser. That is what
//   bounds the hostile page's share of the bridge's thread; the good page
//   keeps receiving its states and a second good browser creates and drives
//   meanwhile;
// - the good page's share of its session's states (states received / seqs
//   published) before and during the flood is printed, not judged: the
//   bridge skips a state for a page when its thread has not finished
//   writing the last, so the share is the bridge thread's CPU time, which
//   the machine's load takes as well as the flood (within 10 % of before
//   was the verdict; at load 25 a fair bridge gave 79 % against 90 %);
// - after the hostile page closes, every session it made ends (the bridge's
//   --orphan-stop, 8 s: the time taken is printed).
// The pages run without drawing (?render=0): what is checked is what they
// receive.
import * as h from './harness.mjs';

const { url } = await h.startServices();
await h.launch();

// ---- the good page: its share of states without the hostile page -----------
const quiet = `${url}?render=0`;
const good = await h.newPage(quiet);
const mine = await h.createAndDrive(good, 'plain.json');
const mark = () => good.evaluate(() => ({ states: window.groundsim.states, seq: window.groundsim.lastState.seq }));
const share = async (seqs) => {
  const a = await mark();
  await h.until(`${seqs} more states published`, async () => (await mark()).seq >= a.seq + seqs, 120000, 50);
  const b = await mark();
  return (b.states - a.states) / (b.seq - a.seq);
};
const before = await share(300);
console.log(`good page: ${(100 * before).toFixed(1)} % of its session's states before the hostile page`);

// ---- the hostile page ------------------------------------------------------------
const hostile = await h.newPage(quiet);
const wsUrl = url.replace('http', 'ws') + 'ws';
await hostile.evaluate((u) => {
  const w = window.hostile = { errors: [], created: [], pongs: 0, open: false, sent: 0, openAt: null, lastAt: null };
  const ws = w.ws = new WebSocket(u);
  ws.onmessage = (e) => {
    const m = JSON.parse(e.data);
    if (m.op === 'error') w.errors.push(m);
    if (m.op === 'created') w.created.push(m.session);
    if (m.op === 'pong') {
      w.pongs = Math.max(w.pongs, m.t);
      if (m.t === 3000) w.lastAt = performance.now();
    }
  };
  ws.onopen = () => {
    w.open = true;
    w.openAt = performance.now();
    const send = (m) => { ws.send(m); ++w.sent; };
    for (let k = 0; k < 80; ++k)
      send(JSON.stringify({ op: 'create', config: 'sedan.json', mode: 'fast', vehicles: 8, publish_rate: 1000, drive: false }));
    for (let k = 0; k < 80; ++k) {
      send(JSON.stringify({ op: 'create', config: 'sedan.json', vehicles: 8, drive: true }));
      if (k % 8 === 7) send('{"op":"leave"}');  // back to the lobby between creates, as a page does
    }
    for (let k = 1; k <= 3000; ++k) send(JSON.stringify({ op: 'ping', t: k }));
  };
}, wsUrl);
await h.until('the hostile page to connect', () => hostile.evaluate(() => window.hostile.open));

// the good page still creates and drives while the flood is read
const during = await share(300);
const stillReading = await hostile.evaluate(() => window.hostile.pongs < 3000);
console.log(`good page: ${(100 * during).toFixed(1)} % of its session's states during the flood ` +
  `(${(100 * before).toFixed(1)} % before; printed, not judged${stillReading ? '' : '; the flood was read before this window ended'})`);
if (!(during > 0)) await h.fail('the good page got no states during the flood');
const second = await h.newPage(quiet);
const again = await h.createAndDrive(second, 'plain.json');
console.log(`a second good browser created and drives ${again}`);

// every hostile message answered, in order: the last pong comes last
await h.until('the hostile flood to be read', () => hostile.evaluate(() => window.hostile.pongs === 3000), 120000, 200);
const seen = await hostile.evaluate(() => ({ errors: window.hostile.errors, created: window.hostile.created,
  sent: window.hostile.sent, took: (window.hostile.lastAt - window.hostile.openAt) / 1000 }));
// read at 200 a second after a burst of 200: (sent - 200) / 200 s at least
const least = (seen.sent - 200) / 200;
console.log(`the flood's ${seen.sent} messages read in ${seen.took.toFixed(1)} s (--browser-messages 200: at least ${least.toFixed(1)} s)`);
if (!(seen.took >= least - 0.1)) await h.fail(`the flood of ${seen.sent} messages was read in ${seen.took} s, faster than --browser-messages allows (${least} s)`);
const reasons = new Map();
for (const e of seen.errors) {
  const flag = (e.reason.match(/--[a-z-]+/) || ['(none)'])[0];
  reasons.set(flag, (reasons.get(flag) || 0) + 1);
}
console.log(`hostile page: ${seen.created.length} created, refusals by flag: ${JSON.stringify([...reasons])}`);
const fast = seen.errors.filter((e) => e.field === '/mode' && e.reason.includes('--browser-modes'));
if (fast.length !== 80) await h.fail(`expected the 80 fast creates refused naming --browser-modes, got ${fast.length}`);
const unnamed = seen.errors.filter((e) => !/--browser-(modes|sessions|creates)/.test(e.reason));
if (unnamed.length) await h.fail(`refusals that name no limit: ${JSON.stringify(unnamed.slice(0, 3))}`);
if (seen.created.length + seen.errors.length !== 160) await h.fail(`${seen.created.length} created + ${seen.errors.length} refused of 160 creates`);

// on the server: never more than --browser-sessions of the hostile's at once
const live = () => {
  const out = h.cli('list');
  return seen.created.filter((id) => out.includes(id));
};
const now = live();
console.log(`hostile sessions running while it is connected: ${now.length}`);
if (now.length > 2) await h.fail(`${now.length} of the hostile page's sessions run at once (--browser-sessions 2)`);


// ---- the hostile page leaves: what it made ends ------------------------------------
await hostile.close();
const t0 = Date.now();
await h.until('every hostile session to end', () => live().length === 0, 60000, 250);
console.log(`the hostile page's sessions ended ${((Date.now() - t0) / 1000).toFixed(1)} s after it left (--orphan-stop 8 s)`);
if (!h.cli('list').includes(mine)) await h.fail(`the good page's session ${mine} ended with the hostile page's`);
await h.pass(`the flood read in ${seen.took.toFixed(1)} s (at least ${least.toFixed(1)}); states ${(100 * before).toFixed(1)} % -> ${(100 * during).toFixed(1)} % during it; ${seen.created.length} hostile creates taken of 160`);

// Contact between bodies in the browser (issue 19). Two players in one
// session of tests/web/data/contact/push.json (two sedans nose to tail,
// 3.3 m apart; the bridge offers that folder's scenarios): player one
// drives the car behind into the other, whose driver (player two) does
// nothing. Both pages show the hit (the HUD line names the pair), and the
// car in front is pushed more than 1 m. Then a session of
// configs/contact/crash.json, created with the command line client and
// spectated, is drawn with its static concrete barrier where the scene
// placed it (on the ground: its centre half its 1 m height up). Between
// the two, datagrams that are no contact_state_t on the session's contact
// channel are logged and dropped by the bridge, which serves on.
// The players' pages run without drawing (?render=0: what is checked there
// is the hits they show, their HUD and states); the spectator's is drawn.
// Durations are the session's (simulated time), waits are for conditions.
import dgram from 'node:dgram';
import { fileURLToPath } from 'node:url';
import * as h from './harness.mjs';
import { CONFIGS } from './harness.mjs';

const data = fileURLToPath(new URL('./data/contact', import.meta.url));
const { url, bridge } = await h.startServices({ bridgeArgs: ['--configs', data] });
let bridgeLog = '';
bridge.stderr.on('data', (d) => { bridgeLog += d; });
await h.launch();
const one = await h.newPage(`${url}?render=0`), two = await h.newPage(`${url}?render=0`);
const session = await h.createAndDrive(one, 'push.json', 2);
await h.until('the session in the lobby', () => two.evaluate((id) => !!document.querySelector(`tr[data-session="${id}"]`), session));
await two.click(`tr[data-session="${session}"] button[data-act="drive"]`);
await h.until('player two to drive', () => two.evaluate(() => window.groundsim.role === 'drive' && window.groundsim.states > 2));
const roles = await Promise.all([one, two].map((p) => p.evaluate(() => [window.groundsim.role, window.groundsim.vehicle])));
if (roles[0][1] !== 0 || roles[1][1] !== 1) await h.fail(`wrong roles ${JSON.stringify(roles)}`);
await Promise.all([one, two].map((p) => h.caughtUp(p, session)));
const contacts0 = await two.evaluate(() => window.groundsim.contacts);
console.log(`contact states received by player two so far: ${contacts0}`);

const pos = (page, k) => page.evaluate((i) => window.groundsim.lastState.vehicles[i].p, k);
// the hits a page has shown (each at its last point), its HUD lines, and both cars' positions now
const shown = (page) => page.evaluate(() => ({
  hits: window.groundsim.hits.shown.map((x) => ({ ...x })),
  hud: document.getElementById('hud-hits').textContent,
  cars: window.groundsim.lastState.vehicles.map((v) => v.p),
}));
// the car in front at rest, its driver idle, for 1.5 s of simulated time
const start = await pos(two, 1), start0 = await pos(two, 0);
const [ti, tj] = await h.simWait(two, 1.5);
const still = await pos(two, 1);
const drift = Math.hypot(still[0] - start[0], still[1] - start[1]);
console.log(`car 1 idle for ${(tj - ti).toFixed(2)} s: moved ${drift.toFixed(3)} m`);
if (drift > 0.2) await h.fail(`car 1 moves by itself (${drift} m in 1.5 s): the push would prove nothing`);

// player one holds W until its page shows the hit, then lets go
let hudOne = '', hudTwo = '';
await h.holdUntil(one, 'w', 'a hit shown on player one\'s page', async () => {
  const s = await shown(one);
  if (s.hits.length) hudOne = s.hud;
  return s.hits.length > 0;
}, 60000);
const hitTwo = await h.until('the hit shown on player two\'s page too', async () => {
  const s = await shown(two);
  if (s.hits.length) hudTwo = s.hud;
  return s.hits.length > 0 && s;
}, 30000, 50);
const hitOne = await shown(one);
console.log(`player one: ${JSON.stringify(hitOne.hits)} HUD "${hudOne}", cars at ${JSON.stringify(hitOne.cars)}`);
console.log(`player two: ${JSON.stringify(hitTwo.hits)} HUD "${hudTwo}"`);
const pair = (x) => [x.a, x.b].sort().join('+') === 'pushed+pusher';
// flashed where they touch: between where the pusher started and where the
// car in front is now (a slow page reads this after both moved on), on their line
const between = (x, cars) => x.p && x.p[0] > start0[0] && x.p[0] < cars[1][0] && Math.abs(x.p[1] - cars[1][1]) < 1.5 &&
  x.p[2] > 0 && x.p[2] < 2;
for (const [who, s, hud] of [['one', hitOne, hudOne], ['two', hitTwo, hudTwo]]) {
  if (!s.hits.some(pair)) await h.fail(`player ${who}'s page shows no hit between pusher and pushed: ${JSON.stringify(s.hits)}`);
  if (!(hud.includes('pusher') && hud.includes('pushed'))) await h.fail(`player ${who}'s HUD does not name the pair: "${hud}"`);
  if (!s.hits.some((x) => pair(x) && between(x, s.cars)))
    await h.fail(`player ${who}'s page flashed the hit away from the cars (${JSON.stringify(s.cars)}): ${JSON.stringify(s.hits)}`);
}

// the car in front was pushed, while its own driver sent nothing but zeros
const moved = await h.until('car 1 to be pushed more than 1 m', async () => {
  const p = await pos(two, 1);
  const d = Math.hypot(p[0] - start[0], p[1] - start[1]);
  return d > 1.0 && d;
}, 30000, 100).catch(async () => h.fail(`car 1 moved ${JSON.stringify(await pos(two, 1))} from ${JSON.stringify(start)}: not pushed 1 m`));
const idle = await two.evaluate(() => JSON.parse(window.groundsim.lastControls));
console.log(`car 1 pushed ${moved.toFixed(2)} m; player two's controls ${JSON.stringify(idle)}`);
if (idle.throttle !== 0 || idle.brake !== 0) await h.fail(`player two's car was driven: ${JSON.stringify(idle)}`);
// the ended hit arrives as the server's event too: without it, a failure
const events = await h.until('the ended hit as an event', () => one.evaluate(() => window.groundsim.hitEvents), 60000)
  .catch(() => 0);
console.log(`"hit: " events on player one's page: ${events}`);
if (!(events > 0)) await h.fail('the server\'s hit event never reached player one\'s page');

// bad datagrams on the contact channel (LCM's small-message framing: magic,
// sequence number, channel, payload): counted, logged and dropped
const lcmPublish = (channel, payload, seqno) => new Promise((resolve) => {
  const sock = dgram.createSocket('udp4'), head = Buffer.alloc(8);
  head.writeUInt32BE(0x4c433032, 0);
  head.writeUInt32BE(seqno, 4);
  sock.send(Buffer.concat([head, Buffer.from(`${channel}\0`), payload]), 7667, '239.255.76.67', () => { sock.close(); resolve(); });
});
const channel = `GROUNDSIM_CONTACT_${session}`;
// contact_state_t's fingerprint as the server sends it (the first 8 bytes of
// a real message on the channel): a constant here went stale when the type
// changed (protocol 2), and the two datagrams below were then refused for
// their fingerprint, never reaching the decoder's bounds they are about
const fingerprint = await new Promise((resolve, reject) => {
  const sock = dgram.createSocket({ type: 'udp4', reuseAddr: true });
  const timer = setTimeout(() => { sock.close(); reject(new Error(`no message on ${channel} in 60 s`)); }, 60000);
  sock.on('message', (buf) => {
    if (buf.length < 8 || buf.readUInt32BE(0) !== 0x4c433032) return;  // small messages only
    const end = buf.indexOf(0, 8);
    if (end < 0 || buf.toString('latin1', 8, end) !== channel || buf.length < end + 9) return;
    clearTimeout(timer);
    sock.close();
    resolve(Buffer.from(buf.subarray(end + 1, end + 9)));
  });
  sock.bind(7667, () => sock.addMembership('239.255.76.67'));
});
console.log(`contact_state_t's fingerprint on the bus: ${fingerprint.toString('hex')}`);
await lcmPublish(channel, Buffer.alloc(0), 1);
await lcmPublish(channel, Buffer.from('not a contact_state_t'), 2);
await lcmPublish(channel, Buffer.from(Array.from({ length: 300 }, (_, i) => (i * 37 + 11) & 255)), 3);
// contact_state_t's fingerprint, then a session id whose length runs past
// the datagram, and an object count of 2^31 - 1
const word = (n) => { const b = Buffer.alloc(4); b.writeInt32BE(n); return b; };
await lcmPublish(channel, Buffer.concat([fingerprint, Buffer.alloc(16), word(1000), Buffer.from('s1')]), 4);
await lcmPublish(channel, Buffer.concat([fingerprint, Buffer.alloc(16), word(3), Buffer.from('s1\0'), Buffer.alloc(8), word(0x7fffffff)]), 5);
await h.until('the bridge to log the bad datagrams', () => (bridgeLog.match(/undecodable message on GROUNDSIM_CONTACT_/g) || []).length >= 5, 15000)
  .catch(() => h.fail(`the bridge did not report the bad contact datagrams: ${bridgeLog.slice(-2000)}`));
// the last two (the right fingerprint) refused by the decoder, not for their fingerprint
const refusals = bridgeLog.match(/undecodable message on GROUNDSIM_CONTACT_[^\n]*/g);
for (const r of refusals) console.log(r);
if (refusals.filter((r) => /fingerprint/.test(r)).length !== 2)
  await h.fail(`expected the two foreign datagrams refused for their fingerprint and the others decoded and refused: ${JSON.stringify(refusals)}`);
const before = await one.evaluate(() => window.groundsim.contacts);
await h.until('contact states after the bad datagrams', async () => (await one.evaluate(() => window.groundsim.contacts)) > before + 5, 30000);
console.log('5 bad contact datagrams logged and dropped; contact states still arrive');

// a scenario with objects: its static barrier is drawn where the scene
// placed it (the players' pages closed first: software WebGL takes a core each)
for (const p of [one, two]) await p.context().close();
const crash = h.cli('create', `${CONFIGS}/contact/crash.json`, '--duration', '-1').trim().split('\n').pop().trim();
const spectator = await h.newPage(`${url}?session=${crash}`);
await h.until('states of the crash session', () => spectator.evaluate(() => window.groundsim.states > 2));
const objects = await spectator.evaluate(() => ({ n: window.groundsim.objectMeshes, list: window.groundsim.objects.describe() }));
console.log(`crash.json drawn with ${objects.n} object meshes: ${JSON.stringify(objects.list)}`);
const barrier = objects.list.find((o) => o.name === 'barrier');
if (!(objects.n >= 1) || !barrier) await h.fail('the crash scenario\'s barrier is not drawn');
if (barrier.kind !== 'barrier') await h.fail(`the barrier is drawn as a ${barrier.kind}`);
if (Math.abs(barrier.p[0] - 40) > 1e-6 || Math.abs(barrier.p[1]) > 1e-6 || Math.abs(barrier.p[2] - 0.5) > 1e-6)
  await h.fail(`the barrier is drawn at ${barrier.p}, not [40, 0, 0.5]`);
await h.until('its contact states', () => spectator.evaluate(() => window.groundsim.contacts > 0), 30000);
// its first frames compile the shaders (seconds in software WebGL): until then the canvas is sky
await h.until('its ground', () => spectator.evaluate(() => window.groundsim.groundGrids > 0));
let stats = null;
await h.until('the spectator\'s view drawn', async () => (stats = await h.canvasStats(spectator)).std >= 10, 60000, 500)
  .catch(() => h.fail(`the spectator's view is blank: ${JSON.stringify(stats)}`));
await h.pass(`hit shown on both pages, car 1 pushed ${moved.toFixed(2)} m; crash.json's barrier drawn`);

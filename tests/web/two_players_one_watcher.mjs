// Two browser contexts drive two cars of one session while a third watches
// both. Player one creates a two-car session from the lobby and gets car 0;
// player two joins from the lobby with "drive" and gets car 1; each holds W
// for its own car only: player one first, then player two. The watcher sees
// both cars drawn and, in its states, car 0 moving while car 1 waits, then
// car 1 moving too. Each player is refused a third car; the watcher cannot drive.
// The players' pages run without drawing (?render=0: their keys and states
// are what counts); the watcher's view is drawn and checked.
import * as h from './harness.mjs';

const { url } = await h.startServices();
await h.launch();
const one = await h.newPage(`${url}?render=0`), two = await h.newPage(`${url}?render=0`), watcher = await h.newPage(url);
const session = await h.createAndDrive(one, 'plain.json', 2);
for (const p of [two, watcher])
  await h.until('the session in the lobby', () => p.evaluate((id) => !!document.querySelector(`tr[data-session="${id}"]`), session));
await two.click(`tr[data-session="${session}"] button[data-act="drive"]`);
await watcher.click(`tr[data-session="${session}"] button[data-act="spectate"]`);
await h.until('player two to drive', () => two.evaluate(() => window.groundsim.role === 'drive' && window.groundsim.states > 2));
await h.until('the watcher to see states', () => watcher.evaluate(() => window.groundsim.states > 2));
const roles = await Promise.all([one, two, watcher].map((p) => p.evaluate(() => [window.groundsim.role, window.groundsim.vehicle])));
console.log(`roles: ${JSON.stringify(roles)}`);
if (roles[0][1] !== 0 || roles[1][1] !== 1 || roles[2][0] !== 'spectate') await h.fail(`wrong roles ${JSON.stringify(roles)}`);

// both cars start rolling: stop them
await Promise.all([h.stopCars(one, [0]), h.stopCars(two, [1])]);
// what the watcher sees from here on is the server's present, not a backlog
const behind = await Promise.all([one, two, watcher].map((p) => h.caughtUp(p, session)));
console.log(`pages behind the server: ${behind.map((b) => b.toFixed(2))} s`);
// speeds as means over 4 s of simulated time (a line fitted to the
// positions): a car released from the handbrake rocks on its undamped
// contacts, +-0.3 m/s, and one sample of its speed holds the whole swing
const speeds = () => h.meanRolling(watcher, [0, 1], 4.0);
const rest = await speeds();
// each holds W until the watcher sees its car 1.5 m/s faster (at most 60 s);
// released, it coasts, still 1 m/s faster over the next 4 s
const faster = (k) => async () => (await h.rolling(watcher, k)) > rest[k] + 1.5;
await h.holdUntil(one, 'w', 'car 0 to speed up', faster(0), 60000).catch(() => {});
const afterOne = await speeds();
await h.holdUntil(two, 'w', 'car 1 to speed up', faster(1), 60000).catch(() => {});
const afterTwo = await speeds();
const fmt = (v) => v.map((x) => x.toFixed(3)).join(', ');
console.log(`watcher sees (mean m/s over 4 s): rest ${fmt(rest)}, after player one ${fmt(afterOne)}, after player two ${fmt(afterTwo)}`);
if (!(afterOne[0] > rest[0] + 1)) await h.fail('player one did not move car 0');
// a car nobody drives keeps its mean speed within about 0.15 m/s (after the
// handbrake it drifts at up to 0.1 m/s either way as it rocks), far from
// the metres per second of a driven one
if (!(Math.abs(afterOne[1] - rest[1]) < 0.3)) await h.fail('car 1 moved when player one pressed W');
if (!(afterTwo[1] > rest[1] + 1)) await h.fail('player two did not move car 1');
const drawn = await watcher.evaluate(() => window.groundsim.vehicles.length);
if (drawn !== 2) await h.fail(`the watcher draws ${drawn} cars`);
const stats = await h.canvasStats(watcher);
if (stats.std < 10) await h.fail(`the watcher's view is blank: ${JSON.stringify(stats)}`);
// the watcher cannot drive, and no third driver fits in a two-car session
const errs = await watcher.evaluate(async (id) => {
  const g = window.groundsim;
  g.errors = [];
  g.send({ op: 'controls', throttle: 1 });
  g.send({ op: 'join', session: id, role: 'drive' });
  // both answers, however long a busy machine takes (at most 60 s)
  const t0 = performance.now();
  while (g.errors.length < 2 && performance.now() - t0 < 60000) await new Promise((r) => setTimeout(r, 50));
  return g.errors.map((e) => `${e.request} ${e.field}: ${e.reason}`);
}, session);
console.log(`watcher refused: ${JSON.stringify(errs)}`);
if (!errs.some((e) => e.startsWith('controls') && e.includes('not driving'))) await h.fail('a spectator could send controls');
if (!errs.some((e) => e.startsWith('join /role') && e.includes('every vehicle'))) await h.fail('a third driver was let in');
await h.pass(`two drivers, one watcher: ${afterTwo.map((v) => v.toFixed(2))} m/s`);

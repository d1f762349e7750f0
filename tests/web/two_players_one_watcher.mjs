// Two browser contexts drive two cars of one session while a third watches
// both. Player one creates a two-car session from the lobby and gets car 0;
// player two joins from the lobby with "drive" and gets car 1; each holds W
// for its own car only: player one first, then player two. The watcher sees
// both cars drawn and, in its states, car 0 moving while car 1 waits, then
// car 1 moving too. Each player is refused a third car; the watcher cannot drive.
import * as h from './harness.mjs';

const { url } = await h.startServices();
await h.launch();
const one = await h.newPage(url), two = await h.newPage(url), watcher = await h.newPage(url);
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
const speeds = async () => [await h.rolling(watcher, 0), await h.rolling(watcher, 1)];
await watcher.waitForTimeout(300);
const rest = await speeds();
// each holds W until the watcher sees its car 1 m/s faster (at most 30 s)
const faster = (k) => async () => (await h.rolling(watcher, k)) > rest[k] + 1;
await h.holdUntil(one, 'w', 'car 0 to speed up', faster(0)).catch(() => {});
const afterOne = await speeds();
await h.holdUntil(two, 'w', 'car 1 to speed up', faster(1)).catch(() => {});
await watcher.waitForTimeout(200);
const afterTwo = await speeds();
console.log(`watcher sees: rest ${rest}, after player one ${afterOne}, after player two ${afterTwo}`);
if (!(afterOne[0] > rest[0] + 1)) await h.fail('player one did not move car 0');
// a released car creeps (~0.1 m/s in a second on undamped contacts): far from a driven one
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
  await new Promise((r) => setTimeout(r, 1000));
  return g.errors.map((e) => `${e.request} ${e.field}: ${e.reason}`);
}, session);
console.log(`watcher refused: ${JSON.stringify(errs)}`);
if (!errs.some((e) => e.startsWith('controls') && e.includes('not driving'))) await h.fail('a spectator could send controls');
if (!errs.some((e) => e.startsWith('join /role') && e.includes('every vehicle'))) await h.fail('a third driver was let in');
await h.pass(`two drivers, one watcher: ${afterTwo.map((v) => v.toFixed(2))} m/s`);

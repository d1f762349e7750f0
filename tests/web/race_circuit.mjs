// The shipped circuit (configs/race/circuit.json: walls, kerbs, a heightfield)
// as a player meets it: W held from the grid runs into the first corner's
// wall (a hit); Backspace puts the car back (the key to it printed), upright, 2 m past
// the last gate it passed (the gate's centre and heading from the race
// layout) and protected for 3 s (the respawn event says until when), at
// once in simulated time (pressed with the session paused, it comes at the
// paused instant); reversing from there for more than a second shows
// WRONG WAY. The page runs without drawing (?render=0): what is checked is
// its state and DOM.
import * as h from './harness.mjs';

const { url } = await h.startServices();
await h.launch();
const page = await h.newPage(`${url}?render=0`);
await h.createAndDrive(page, 'race/circuit.json');
await h.until('the race layout', () => page.evaluate(() => window.groundsim.race.active), 60000, 50);
await page.keyboard.down('w');  // held from before or after go: the car goes at go
await h.until('a hit with a wall', () => page.evaluate(() => window.groundsim.hitEvents > 0), 90000, 50);
await page.keyboard.up('w');
const crash = await page.evaluate(() => { const g = window.groundsim; return { t: g.lastState.t, p: g.lastState.vehicles[g.vehicle].p }; });
console.log(`hit a wall at t = ${crash.t.toFixed(2)} s, (${crash.p.map((x) => x.toFixed(1)).join(', ')})`);

// pedals up (the page's throttle ramps down after the key), then respawn;
// the first state after the respawn event's instant is where the server put
// the car
await h.until('the throttle released', () => page.evaluate(() => JSON.parse(window.groundsim.lastControls).throttle === 0), 60000, 20);
// each state marked with whether the respawn event came before it
await page.evaluate(() => {
  const g = window.groundsim;
  g.testStates = [];
  g.stateListeners.push((m) => {
    const v = m.vehicles[g.vehicle];
    g.testStates.push({ t: m.t, p: v.p, q: v.q, status: m.status, after: g.race.events.some((x) => x.type === 'respawn') });
  });
});
// with the session's clock stopped: a respawn that waits for anything (a
// protection, a countdown) would not come while it stands still
const simBefore = await h.pause(page);
const wall0 = Date.now();
await page.keyboard.press('Backspace');
const back = await h.until('the respawned car', () => page.evaluate(() => {
  const g = window.groundsim, e = g.race.events.find((x) => x.type === 'respawn');
  // the first state the server published after it
  const s = e && g.testStates.find((x) => x.after);
  return s ? { e, p: s.p, q: s.q, s_t: s.t, status: s.status, gates: g.race.layout.gates } : null;
}), 60000, 10);
const wallRespawn = (Date.now() - wall0) / 1000;
const [lx, ly, rx, ry] = back.gates[back.e.gate];
const ex = rx - lx, ey = ry - ly, n = Math.hypot(ex, ey), fx = -ey / n, fy = ex / n;
const want = [(lx + rx) / 2 + 2 * fx, (ly + ry) / 2 + 2 * fy];
const off = Math.hypot(back.p[0] - want[0], back.p[1] - want[1]);
const [, qx, qy] = back.q;
const tilt = 2 * Math.asin(Math.min(1, Math.hypot(qx, qy)));
console.log(`respawned after gate ${back.e.gate} ${wallRespawn.toFixed(2)} s of wall time after the key (printed, not judged): ${off.toFixed(3)} m from 2 m past it, ${(tilt * 180 / Math.PI).toFixed(2)} deg off upright, protected until ${back.e.protected_until}`);
// how soon: the key to the respawn is a latency through the page, the
// bridge and the server, on this machine 0.07 s unloaded and past 1 s under
// a loaded CI: a figure printed here (docs/front-end.md), not a verdict.
// Asserted: the respawn waits for nothing (it comes at the paused instant)
// and the server publishes the car where it put it in the frame after it,
// of that same instant, still paused (to 1e-9 s: the event's t and the
// state's are printed by different JSON writers)
const simRespawn = back.e.t - simBefore, firstFrame = back.s_t - back.e.t;
console.log(`respawn ${simRespawn.toFixed(3)} s of simulated time after the pause; shown ${firstFrame.toFixed(3)} s after it (status ${back.status})`);
if (!(Math.abs(firstFrame) < 1e-9 && back.status === 2)) await h.fail(`the respawned car was first shown ${firstFrame} s after the respawn (status ${back.status})`);
if (!(Math.abs(simRespawn) < 1e-9)) await h.fail(`respawn came ${simRespawn} s of simulated time after the key, pressed with the session paused`);
if (!(off < 0.05)) await h.fail(`respawned ${off} m from 2 m past gate ${back.e.gate}`);
if (!(tilt < 0.1)) await h.fail(`respawned ${tilt} rad off upright`);
if (!(Math.abs(back.e.protected_until - back.e.t - 3) < 1e-9)) await h.fail(`protected until ${back.e.protected_until}`);
await h.resume(page);

await page.keyboard.down('s');
const ww = await h.until('WRONG WAY', () => page.evaluate(() => {
  const g = window.groundsim;
  return g.race.mine.wrongWay && document.getElementById('race-notice').textContent === 'WRONG WAY' ? g.lastState.t : null;
}), 60000, 50).catch(() => null);
await page.keyboard.up('s');
if (!ww) await h.fail('no WRONG WAY notice while reversing');
await h.pass(`hit at ${crash.t.toFixed(1)} s; respawn at once (${wallRespawn.toFixed(2)} s of wall time), ${off.toFixed(3)} m; WRONG WAY at t = ${ww.toFixed(2)} s`);

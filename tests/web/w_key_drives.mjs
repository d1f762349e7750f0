// Pressing W drives the car and releasing it lets go: on the plane (mu 0.5)
// full throttle accelerates the car at up to mu g = 4.9 m/s^2, so W held
// adds metres per second along its heading, seen in the HUD and in the
// server's own states (groundsim watch, not through the bridge); the HUD
// shows it in km/h. W is held until the page and the server both show the
// car 1 m/s faster (the simulated time it took is printed), not for a fixed
// wall time. After the release the throttle the page sends returns to 0
// and the car only coasts: over a second of simulated time its speed gains
// less than a tenth of what the held key added per second (both rates from
// the page's states, on the session's clock; the second starts once the
// release reached the server, which on a loaded machine takes longer, and
// how long after the release that was is printed).
// The page runs without drawing (?render=0): what is checked is its states,
// controls and HUD (DOM).
import * as h from './harness.mjs';

const { url } = await h.startServices();
await h.launch();
const page = await h.newPage(`${url}?render=0`);
const session = await h.createAndDrive(page, 'plain.json');
// the scenario starts rolling at ~1.1 m/s: handbrake to a stop first
await h.stopCars(page);
const v0 = await h.rolling(page, 0), server0 = h.serverSpeeds(session)[0];
console.log(`at rest: page ${v0.toFixed(3)} m/s, server ${server0} m/s, HUD ${await h.hudSpeedKmh(page)} km/h`);
// car 0's speed along its heading in every state the page gets: [t, v]
await page.evaluate(() => {
  const g = window.groundsim;
  g.testRoll = [];
  g.stateListeners.push((m) => {
    const v = m.vehicles[0], [w, x, y, z] = v.q;
    const fx = 1 - 2 * (y * y + z * z), fy = 2 * (x * y + w * z), n = Math.hypot(fx, fy) || 1;
    g.testRoll.push([m.t, (fx * v.v[0] + fy * v.v[1]) / n]);
  });
});

const t0 = await h.simTime(page);
let vPressed = v0, serverPressed = server0, hudPressed = 0;
await h.holdUntil(page, 'w', 'the page and the server to show the car 1 m/s faster', async () => {
  vPressed = await h.rolling(page, 0);
  if (!(vPressed > v0 + 1.0)) return false;
  hudPressed = await h.hudSpeedKmh(page);
  serverPressed = h.serverSpeeds(session)[0];
  return serverPressed > server0 + 1.0;
}, 120000).catch(() => {});
const tRelease = await h.simTime(page);
console.log(`W held ${(tRelease - t0).toFixed(2)} s of simulated time: page ${vPressed.toFixed(3)} m/s, server ${serverPressed} m/s, HUD ${hudPressed} km/h`);
if (!(vPressed > v0 + 1.0)) await h.fail(`holding W did not speed the car up: ${v0} -> ${vPressed} m/s`);
if (!(serverPressed > server0 + 1.0)) await h.fail(`the server's states show no speed-up: ${server0} -> ${serverPressed} m/s`);

await h.until('the throttle to return to 0', () => page.evaluate(() => window.groundsim.lastControls &&
  JSON.parse(window.groundsim.lastControls).throttle === 0), 60000, 20);
// the held rate: from the first state 0.2 m/s up to the release
const held = await page.evaluate((tr) => window.groundsim.testRoll.filter((r) => r[0] <= tr), tRelease);
const a = held.find((r) => r[1] > v0 + 0.2), b = held[held.length - 1];
const gainHeld = (b[1] - a[1]) / (b[0] - a[0]);
// after the release: the first second of simulated time (from a state past
// the release) over which the car gained less than a tenth of that; the
// car keeps speeding up until the release reaches the server, and would for
// good with the throttle left on (a constant torque: 30 s of simulated time
// is waited for, a ceiling)
const coast = await h.until('a second of coasting after the release', () => page.evaluate(([tr, rate]) => {
  const rows = window.groundsim.testRoll.filter((r) => r[0] >= tr);
  let j = 0;
  for (let i = 0; i < rows.length; ++i) {
    while (j < rows.length && rows[j][0] < rows[i][0] + 1.0) ++j;
    if (j >= rows.length) break;
    const span = rows[j][0] - rows[i][0], gain = rows[j][1] - rows[i][1];
    if (gain < 0.1 * rate * span) return { from: rows[i][0], span, vRel: rows[i][1], vLater: rows[j][1], gain };
  }
  const last = rows[rows.length - 1];
  return last && last[0] > tr + 30 ? { none: true, v: last[1], t: last[0] } : null;
}, [tRelease, gainHeld]), 120000, 100);
console.log(`held: +${gainHeld.toFixed(2)} m/s per s from t = ${a[0].toFixed(2)} to ${b[0].toFixed(2)} s; ` +
  (coast.none ? `no second of coasting in 30 s after the release (at ${coast.v.toFixed(2)} m/s)`
    : `coasting ${(coast.from - tRelease).toFixed(2)} s of simulated time after the release: ${coast.vRel.toFixed(3)} -> ${coast.vLater.toFixed(3)} m/s in ${coast.span.toFixed(2)} s`));
if (coast.none) await h.fail(`the car kept accelerating after W was released: ${coast.v} m/s at t = ${coast.t} s`);
const gainAfter = coast.gain;
// the HUD, drawn from the interpolated states, shows the coasting speed
const hud = await h.until('the HUD to show the speed', async () => {
  const kmh = await h.hudSpeedKmh(page), v = await h.rolling(page, 0);
  return Math.abs(kmh / 3.6 - v) < 0.15 * v && kmh;
}, 60000).catch(() => null);
console.log(`HUD ${hud} km/h while coasting at ${(await h.pageSpeed(page, 0)).toFixed(3)} m/s`);
if (!(hud > 3.6)) await h.fail(`the HUD does not show the car's speed (${await h.hudSpeedKmh(page)} km/h)`);
await h.pass(`W: +${(vPressed - v0).toFixed(2)} m/s in ${(tRelease - t0).toFixed(2)} s; released: ${gainAfter.toFixed(3)} m/s in ${coast.span.toFixed(2)} s`);

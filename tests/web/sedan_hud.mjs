// The sedan (configs/sedan.json, kind road_car) driven from the page: the
// bridge sends the page's normalized controls as controls_t, and the HUD
// shows the engaged gear and the engine rpm from car_state_t. Holding W
// from rest puts the car in gear with the engine above idle (900 rpm) and
// adds metres per second to the server's own speed (groundsim watch); the
// applied throttle the server reports is the page's. W is held until all
// of that is seen (the simulated time it took is printed), not for a fixed
// wall time: a loaded machine or a slow server takes longer, never less.
// The page runs without drawing (?render=0): the HUD is DOM and the wheels'
// angles the scene's, set each frame whether or not it is drawn.
import * as h from './harness.mjs';

const { url } = await h.startServices();
await h.launch();
const page = await h.newPage(`${url}?render=0`);
const session = await h.createAndDrive(page, 'sedan.json');
await h.until('the road car state to arrive', () => page.evaluate(() => window.groundsim.car !== null));
await h.stopCars(page);
const server0 = h.serverSpeeds(session)[0];

const hud = () => page.evaluate(() => ({ gear: document.getElementById('hud-gear').textContent,
  rpm: parseFloat(document.getElementById('hud-rpm').textContent), applied: window.groundsim.car.cars[0].throttle,
  t: window.groundsim.lastState.t }));
const t0 = await h.simTime(page);
await page.keyboard.down('w');
// the HUD and the applied throttle read together, at a moment the car is
// in gear above idle under the page's throttle, and the server's speed
let shown = await hud(), serverPressed = server0;
await h.until('the HUD in gear above idle under throttle and the server 1 m/s faster', async () => {
  const x = await hud();
  if (!(/^[1-6]$/.test(x.gear) && x.rpm > 900 && x.applied > 0)) return false;
  shown = x;
  serverPressed = h.serverSpeeds(session)[0];
  return serverPressed > server0 + 1.0;
}, 120000, 100).catch(async () => { if (!(shown.applied > 0)) shown = await hud(); });
const { gear, rpm, applied } = shown;
await page.keyboard.up('w');
console.log(`W held ${(shown.t - t0).toFixed(2)} s of simulated time: server ${server0} -> ${serverPressed} m/s, HUD gear ${gear}, ${rpm} rpm, applied throttle ${applied}`);
if (!/^[1-6]$/.test(gear)) await h.fail(`the HUD shows gear '${gear}', not a forward gear of the sedan's six`);
if (!(rpm > 900)) await h.fail(`the HUD shows ${rpm} rpm under throttle (idle is 900)`);
if (!(applied > 0)) await h.fail(`the server applies throttle ${applied} while W is held`);
if (!(serverPressed > server0 + 1.0)) await h.fail(`the server's states show no speed-up: ${server0} -> ${serverPressed} m/s`);

// its four wheels are drawn from the car's struts (not model wheels), and
// holding A turns the front ones left (+z) while the rear ones stay straight
const drawn = await page.evaluate(() => window.groundsim.vehicles[window.groundsim.followed].wheels.length);
if (drawn !== 4) await h.fail(`the page draws ${drawn} wheels for the sedan, not 4`);
// A held until the front wheels are drawn steered (as the server steers
// them: its steer angle is printed), the rear ones read at that frame
const steered = () => page.evaluate(() => ({ drawn: window.groundsim.vehicles[window.groundsim.followed].wheels.map((w) => w.pivot.rotation.z),
  server: window.groundsim.car.cars[0].steer_angle }));
await page.keyboard.down('a');
let steer = await steered();
await h.until('the front wheels drawn steered', async () => { steer = await steered(); return steer.drawn[0] > 0.05 && steer.drawn[1] > 0.05; }, 60000, 20)
  .catch(() => {});
await page.keyboard.up('a');
const steerDrawn = steer.drawn, steerServer = steer.server;
console.log(`A held: drawn wheel angles ${steerDrawn.map((a) => a.toFixed(3)).join(' ')} rad, server ${steerServer} rad`);
if (!(steerDrawn[0] > 0.05 && steerDrawn[1] > 0.05)) await h.fail(`front wheels drawn at ${steerDrawn[0]}, ${steerDrawn[1]} rad while A is held`);
if (steerDrawn[2] !== 0 || steerDrawn[3] !== 0) await h.fail(`rear wheels drawn steered: ${steerDrawn[2]}, ${steerDrawn[3]}`);
await h.pass(`sedan: gear ${gear}, ${rpm} rpm, +${(serverPressed - server0).toFixed(2)} m/s in ${(shown.t - t0).toFixed(2)} s`);

// Replays in the browser: a race recorded with `groundsim record` (the
// sprint stage of tests/web/data/race: gates at x = 10, 40, 70 m, a 3 s
// countdown, one lap; the sedan driven at full throttle by `groundsim
// drive`) is listed in the lobby by the bridge's /recordings, opened with a
// click, and played on a timeline:
// - the scene is the session's own, from the scenario in the file: the
//   sedan's body, the race's track ribbon, ground grids from the recording;
// - scrubbing to 10 % and 90 % moves the drawn car to the recorded positions
//   at those times (to 5 cm; fetched here with at=T from the same bridge);
// - "jump to lap" lists the server's lap and takes the playhead to its
//   start, where the car crosses the start gate (x = 10 m; to 0.1 m);
// - playing advances the playhead, at most at 1x (no faster than the wall
//   clock: a bound a loaded machine only makes looser).
// The page runs without drawing (?render=0): the car's place is the
// scene's, set each frame whether or not it is drawn.
import { spawn } from 'node:child_process';
import { mkdtempSync } from 'node:fs';
import { tmpdir } from 'node:os';
import * as h from './harness.mjs';

const dir = mkdtempSync(`${tmpdir()}/groundsim-replays-`);
const data = new URL('./data/race', import.meta.url).pathname;
await h.startServer();
const tokens = `${dir}/tokens.json`;
const run = (args, input) => {
  const p = spawn(h.CLI, [...args, '--lcm-url', h.LCM_URL, '--token-file', tokens], { stdio: ['pipe', 'pipe', 'pipe'] });
  p.out = ''; p.err = '';
  p.stdout.on('data', (d) => { p.out += d; });
  p.stderr.on('data', (d) => { p.err += d; });
  p.done = new Promise((r) => p.on('exit', (code) => r(code)));
  if (input) p.stdin.end(input);
  return p;
};
const recorder = run(['record', '--create', `${data}/sprint.json`, '--session-duration', '13', '--publish-rate', '50',
  '--out', `${dir}/sprint.mcap`, '--repair-wait', '1']);
const sid = await h.until('the recorded session', () => recorder.out.trim().split('\n')[0], 60000);
const driver = run(['drive', sid, '--controls', 'car', '--hold'], 'throttle 1\nwait 11\nquit\n');
const [rc, dc] = await Promise.all([recorder.done, driver.done]);
if (rc !== 0) await h.fail(`the recorder exited ${rc}: ${recorder.err}`);
if (dc !== 0) await h.fail(`the driver exited ${dc}: ${driver.err}`);
const { url } = await h.startBridge(['--recordings', dir]);
await h.launch();
const page = await h.newPage(`${url}?render=0`, { width: 1280, height: 720 });
await h.until('the recording in the lobby', () => page.evaluate(() => !!document.querySelector('#lobby-replays button[data-act="replay"]')), 60000);
await page.click('#lobby-replays button[data-act="replay"]');
await h.until('the replay loaded and drawn', () => page.evaluate(() => {
  const r = window.groundsim.replay;
  return r && r.loaded && window.groundsim.vehicles.length === 1 && r.lapList;
}), 60000);
const span = await page.evaluate(() => { const r = window.groundsim.replay; return { t0: r.t0, t1: r.t1, name: r.name, session: r.session }; });
if (!(span.t1 - span.t0 > 12)) await h.fail(`the recording spans ${span.t1 - span.t0} s, not the session's 13`);
// the session's own scene, from the file's scenario
const scene = await page.evaluate(() => {
  const g = window.groundsim, l = g.replayLayout;
  return { layout: !!l, roadCar: !!(l && l.vehicles[0].road_car), race: !!(l && l.race), ribbon: !!g.track.mesh };
});
if (!scene.layout || !scene.roadCar || !scene.race || !scene.ribbon) await h.fail(`the replay is not drawn in its scene: ${JSON.stringify(scene)}`);
await h.until('a ground grid from the recording', () => page.evaluate(() => window.groundsim.groundGrids > 0), 30000);
await page.click('#tl-play');  // it starts playing: pause
await page.waitForFunction(() => !window.groundsim.replay.playing);

// a frame drawn after now (the car's place is set each frame)
const nextFrame = async () => {
  const f0 = await page.evaluate(() => window.groundsim.frames);
  await h.until('a frame', () => page.evaluate((f) => window.groundsim.frames > f, f0), 60000, 20);
};
async function scrubTo(fraction) {
  await page.$eval('#tl-scrub', (el, v) => { el.value = String(v); el.dispatchEvent(new Event('input', { bubbles: true })); }, Math.round(fraction * 1000));
  const t = span.t0 + (span.t1 - span.t0) * fraction;
  await h.until('the car drawn at the scrubbed time', () => page.evaluate((t) => {
    const g = window.groundsim;
    return g.replay.shown && Math.abs(g.replay.shown.t - t) < 0.03;
  }, t), 30000, 50).catch(async (e) => {
    const r = await page.evaluate(async () => { const r = window.groundsim.replay; const w = r.windows.get(0); let f; try { f = r.frame(0).t; } catch (e) { f = String(e.stack); } return { t0: r.t0, t1: r.t1, t: r.t, shown: r.shown && r.shown.t, f, n: w && w.states && w.states.length, error: r.error, chunk: r.chunk, windows: [...r.windows.keys()], frames: window.groundsim.frames }; });
    await h.fail(`${e.message}: wanted t=${t}, replay ${JSON.stringify(r)}`);
  });
  await nextFrame();
  const drawn = await page.evaluate(() => window.groundsim.vehicles[0].root.position.toArray());
  const rec = await (await fetch(`${url}recordings/${span.name}/states?session=${span.session}&at=${t}`)).json();
  return { t, drawn, recorded: rec.states[0].vehicles[0].position };
}
const a = await scrubTo(0.1), b = await scrubTo(0.9);
const dist = (p, q) => Math.hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
console.log(JSON.stringify({ a, b }));
for (const s of [a, b]) if (dist(s.drawn, s.recorded) > 0.05) await h.fail(`at t=${s.t} the car is drawn at ${s.drawn}, recorded at ${s.recorded}`);
if (!(dist(a.drawn, b.drawn) > 1)) await h.fail(`scrubbing did not move the car: ${a.drawn} -> ${b.drawn}`);

// the lap the server timed: it starts when the countdown ends
const laps = await page.evaluate(() => window.groundsim.replay.lapList);
if (laps.length !== 1) await h.fail(`the timeline lists ${laps.length} laps, not the sprint's 1: ${JSON.stringify(laps)}`);
if (!(laps[0].start > 3)) await h.fail(`the lap starts at ${laps[0].start} s, before the end of the 3 s countdown`);
await page.selectOption('#tl-laps', String(laps[0].start));
await h.until('the car drawn at the lap\'s start', () => page.evaluate((t) => {
  const r = window.groundsim.replay;
  return Math.abs(r.t - t) < 1e-6 && r.shown && Math.abs(r.shown.t - t) < 1e-6;
}, laps[0].start), 60000);
await nextFrame();
const atStart = await page.evaluate(() => window.groundsim.vehicles[0].root.position.toArray());
console.log(`lap 1: ${laps[0].lap_time.toFixed(3)} s from t = ${laps[0].start.toFixed(3)} s, the car drawn there at x = ${atStart[0].toFixed(3)} m`);
if (Math.abs(atStart[0] - 10) > 0.1) await h.fail(`at the lap's start the car is drawn at x = ${atStart[0]}, not at the start gate's 10 m`);

await scrubTo(0.1);
const t1 = await page.evaluate(() => window.groundsim.replay.t);
const w1 = Date.now();
await page.click('#tl-play');
// at 1x: the playhead follows the wall clock (from the next frame drawn:
// a software renderer under load draws one every few seconds)
await h.until('the playhead to advance', () => page.evaluate((t1) => window.groundsim.replay.t > t1 + 0.5, t1), 30000, 100)
  .catch(() => h.fail(`playing did not advance the playhead from ${t1}`));
const t2 = await page.evaluate(() => window.groundsim.replay.t), wall = (Date.now() - w1) / 1000;
console.log(`played ${wall.toFixed(2)} s of wall time: playhead ${t1.toFixed(2)} -> ${t2.toFixed(2)} s`);
if (t2 - t1 > wall + 0.1) await h.fail(`the playhead ran ahead of 1x: ${t2 - t1} s in ${wall} s`);
if (process.env.GROUNDSIM_SCREENSHOT) await page.screenshot({ path: process.env.GROUNDSIM_SCREENSHOT });
await h.pass(`scrubbed ${dist(a.drawn, b.drawn).toFixed(2)} m along the recording`);

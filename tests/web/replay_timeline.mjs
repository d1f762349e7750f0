// Replays in the browser: a session recorded with `groundsim record`
// (configs/plain.json: the report's car rolling from spun wheels, 5 s) is
// listed in the lobby by the bridge's /recordings, opened with a click,
// and played on a timeline. Scrubbing to 10 % and 90 % of it moves the
// drawn car to the recorded positions at those times (to 5 cm; fetched
// here with at=T from the same bridge), and playing advances the playhead.
import { mkdtempSync } from 'node:fs';
import { tmpdir } from 'node:os';
import * as h from './harness.mjs';

const dir = mkdtempSync(`${tmpdir()}/groundsim-replays-`);
await h.startServer();
h.cli('record', '--create', `${h.CONFIGS}/plain.json`, '--out', `${dir}/plain.mcap`, '--mode', 'fast', '--publish-rate', '50', '--repair-wait', '1');
const { url } = await h.startBridge(['--recordings', dir]);
await h.launch();
const page = await h.newPage(url, { width: 1280, height: 720 });
await h.until('the recording in the lobby', () => page.evaluate(() => !!document.querySelector('#lobby-replays button[data-act="replay"]')), 15000);
await page.click('#lobby-replays button[data-act="replay"]');
await h.until('the replay loaded and drawn', () => page.evaluate(() => {
  const r = window.groundsim.replay;
  return r && r.loaded && window.groundsim.vehicles.length === 1;
}), 20000);
const span = await page.evaluate(() => { const r = window.groundsim.replay; return { t0: r.t0, t1: r.t1, name: r.name, session: r.session }; });
if (!(span.t1 - span.t0 > 4)) await h.fail(`the recording spans ${span.t1 - span.t0} s, not the scenario's 5`);
await page.click('#tl-play');  // it starts playing: pause
await page.waitForFunction(() => !window.groundsim.replay.playing);

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
  await page.waitForTimeout(100);
  const drawn = await page.evaluate(() => window.groundsim.vehicles[0].root.position.toArray());
  const rec = await (await fetch(`${url}recordings/${span.name}/states?session=${span.session}&at=${t}`)).json();
  return { t, drawn, recorded: rec.states[0].vehicles[0].position };
}
const a = await scrubTo(0.1), b = await scrubTo(0.9);
const dist = (p, q) => Math.hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
console.log(JSON.stringify({ a, b }));
for (const s of [a, b]) if (dist(s.drawn, s.recorded) > 0.05) await h.fail(`at t=${s.t} the car is drawn at ${s.drawn}, recorded at ${s.recorded}`);
if (!(dist(a.drawn, b.drawn) > 1)) await h.fail(`scrubbing did not move the car: ${a.drawn} -> ${b.drawn}`);

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

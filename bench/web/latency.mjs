// End-to-end latency of the front end: from a key press in the page to the
// first state that reflects it, browser -> bridge -> server -> bridge ->
// browser, in a real-time session publishing at 60 Hz. The key is the
// handbrake (space): it locks the rear wheels at once (no ramp), so the
// rear wheels' spin drops within a few physics steps of the command
// arriving; a state reflects the press when their mean spin is 0.05 rad/s
// below the last state before it (coasting loses ~0.003 rad/s per frame).
// Also reports the page's frame rate in headless Chromium (SwiftShader).
// Run: bench/web/latency.sh [TRIALS]
import * as h from '../../tests/web/harness.mjs';

const trials = parseInt(process.argv[2] || '30', 10);
const draw = process.argv[3] !== 'norender';
const { url } = await h.startServices();
await h.launch();
const page = await h.newPage(`${url}?render=${draw ? 1 : 0}`, { width: 640, height: 360 });
await page.evaluate(() => window.groundsim.send({ op: 'create', config: 'plain.json', publish_rate: 60, drive: true }));
await h.until('the session', () => page.evaluate(() => window.groundsim.role === 'drive' && window.groundsim.states > 5));
await page.evaluate(() => {
  const g = window.groundsim;
  g.bench = { armed: false, base: 0, pressT: 0, results: [] };
  window.addEventListener('keydown', (e) => {
    if (e.key === ' ' && g.bench.armed) g.bench.pressT = performance.now();
  }, true);
  g.stateListeners.push((m, now) => {
    const b = g.bench, v = m.vehicles[g.vehicle];
    const rear = (v.spin[2] + v.spin[3]) / 2;
    if (!b.armed) { b.base = rear; return; }
    if (b.pressT && rear < b.base - 0.05) {
      b.results.push(now - b.pressT);
      b.armed = false;
      b.pressT = 0;
    } else if (!b.pressT) b.base = rear;
  });
});
const lat = [];
for (let i = 0; i < trials; ++i) {
  await h.hold(page, 'w', 800);  // up to speed, then coast
  await page.waitForTimeout(400);
  await page.evaluate(() => { window.groundsim.bench.armed = true; });
  await page.waitForTimeout(100);
  await page.keyboard.down(' ');
  const r = await h.until('the state reflecting the press', () => page.evaluate(() =>
    !window.groundsim.bench.armed && window.groundsim.bench.results.slice(-1)[0]), 5000, 5).catch(() => null);
  await page.waitForTimeout(150);
  await page.keyboard.up(' ');
  if (r) lat.push(r);
}
const fps = await page.evaluate(() => window.groundsim.fps);
lat.sort((a, b) => a - b);
const q = (p) => lat[Math.min(lat.length - 1, Math.floor(p * lat.length))];
console.log(`latency key press -> state, ${lat.length}/${trials} trials at 60 Hz publish rate, drawing ${draw ? 'on' : 'off'}:`);
console.log(`  p50 ${q(0.5).toFixed(1)} ms  p99 ${q(0.99).toFixed(1)} ms  min ${lat[0].toFixed(1)} ms  max ${lat[lat.length - 1].toFixed(1)} ms`);
console.log(`  page frame rate ${fps.toFixed(1)} frames/s (640x360, headless Chromium, SwiftShader)`);
await h.pass();

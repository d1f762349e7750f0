// End-to-end latency of the front end: from a key press in the page to the
// first state that reflects it, browser -> bridge -> server -> bridge ->
// browser, in a real-time session publishing at 60 Hz. The key is the
// handbrake (space): it locks the rear wheels at once (no ramp), so the
// rear wheels' spin drops within a few physics steps of the command
// arriving; a state reflects the press when their mean spin is 0.05 rad/s
// below the last state before it (coasting loses ~0.003 rad/s per frame).
// Also reports the page's frame rate in headless Chromium (SwiftShader).
// Run: bench/web/latency.sh [TRIALS] [norender] [trace]
// trace: the server and the bridge stamp each hop (GROUNDSIM_TRACE, see
// server/lcm/latency_trace.hpp), the page stamps its sends and receipts, and
// the figures come with a breakdown per hop (latency_trace.mjs).
import { mkdtempSync, readFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import * as h from '../../tests/web/harness.mjs';
import { breakdown } from './latency_trace.mjs';

const trials = parseInt(process.argv[2] || '30', 10);
const flags = process.argv.slice(3);
const draw = !flags.includes('norender'), trace = flags.includes('trace');
const traceFile = `${mkdtempSync(`${tmpdir()}/groundsim-latency-`)}/trace.txt`;
if (trace) process.env.GROUNDSIM_TRACE = traceFile;
const { url } = await h.startServices();
await h.launch();
const page = await h.newPage(`${url}?render=${draw ? 1 : 0}`, { width: 640, height: 360 });
await page.evaluate(() => window.groundsim.send({ op: 'create', config: 'plain.json', publish_rate: 60, drive: true }));
await h.until('the session', () => page.evaluate(() => window.groundsim.role === 'drive' && window.groundsim.states > 5));
await page.evaluate((tracing) => {
  const g = window.groundsim;
  // off: the page's clock minus the bridge's steady clock, from the states'
  // arrival stamps (the smallest difference: the quickest delivery, ~0.1 ms)
  g.bench = { armed: false, base: 0, pressT: 0, results: [], recv: new Map(), sends: [], off: Infinity };
  window.addEventListener('keydown', (e) => {
    if (e.key === ' ' && g.bench.armed) g.bench.pressT = performance.now();
  }, true);
  if (tracing) {
    const send = WebSocket.prototype.send;
    WebSocket.prototype.send = function (data) {
      const t = performance.now();
      const r = send.call(this, data);
      const m = JSON.parse(data);
      if (m.op === 'controls' && g.bench.pressT) g.bench.sends.push({ seq: m.seq, handbrake: m.handbrake, t });
      return r;
    };
  }
  g.stateListeners.push((m, now) => {
    const b = g.bench, v = m.vehicles[g.vehicle];
    if (tracing) {
      b.recv.set(m.seq, now);
      b.off = Math.min(b.off, now - 1000 * m.wall);
    }
    const rear = (v.spin[2] + v.spin[3]) / 2;
    if (!b.armed) { b.base = rear; return; }
    if (b.pressT && rear < b.base - 0.05) {
      const sent = b.sends.find((s) => s.handbrake);
      b.results.push({ ms: now - b.pressT, press: b.pressT, seq: m.seq, at: now, sent });
      b.armed = false;
      b.pressT = 0;
      b.sends = [];
    } else if (!b.pressT) b.base = rear;
  });
}, trace);
const lat = [], results = [];
for (let i = 0; i < trials; ++i) {
  await h.hold(page, 'w', 800);  // up to speed, then coast
  await page.waitForTimeout(400);
  await page.evaluate(() => { window.groundsim.bench.armed = true; });
  await page.waitForTimeout(100);
  await page.keyboard.down(' ');
  const r = await h.until('the state reflecting the press', () => page.evaluate(() => {
    const b = window.groundsim.bench;
    return !b.armed && b.results[b.results.length - 1];
  }), 5000, 20).catch(() => null);
  await page.waitForTimeout(150);
  await page.keyboard.up(' ');
  if (r) { lat.push(r.ms); results.push(r); }
}
const fps = await page.evaluate(() => window.groundsim.fps);
const speed = await h.rolling(page, 0);
lat.sort((a, b) => a - b);
const q = (p) => lat[Math.min(lat.length - 1, Math.floor(p * lat.length))];
console.log(`latency key press -> state, ${lat.length}/${trials} trials at 60 Hz publish rate, drawing ${draw ? 'on' : 'off'}:`);
console.log(`  p50 ${q(0.5).toFixed(1)} ms  p99 ${q(0.99).toFixed(1)} ms  min ${lat[0].toFixed(1)} ms  max ${lat[lat.length - 1].toFixed(1)} ms`);
console.log(`  ${lat.filter((x) => x > 50).length} of ${lat.length} trials above 50 ms`);
console.log(`  page frame rate ${fps.toFixed(1)} frames/s (640x360, headless Chromium, SwiftShader); car at ${speed.toFixed(1)} m/s at the end`);
if (trace) {
  const { recv, off } = await page.evaluate(() => ({ recv: [...window.groundsim.bench.recv.entries()], off: window.groundsim.bench.off }));
  console.log(breakdown(readFileSync(traceFile, 'utf8'), results, new Map(recv), off));
}
await h.pass();

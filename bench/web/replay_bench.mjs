// A long replay in the browser: how fast a 10-minute, 8-car recording opens
// and seeks (the goal: open under 1 s, a seek anywhere under 200 ms).
// Timing only: nothing here passes or fails on a figure.
//
// 1. Records bench/web/eight_sedans.json (8 road cars driving
//    figure-of-eights for 600 s of simulated time) with
//    `groundsim record --create ... --mode fast --publish-rate 60` from a
//    real groundsim-server (or takes an existing file: --mcap FILE).
// 2. Serves it with `groundsim-web --recordings DIR` and times the bridge's
//    answers alone with curl: the listing, the file, scene, events, ground,
//    the page's 8 s windows (/states?from=&to=&max=5000) and at= scrubs.
// 3. Opens `/?replay=NAME&rsession=ID` in headless Chromium (SwiftShader)
//    OPENS times, each in a fresh context, and times navigation start ->
//    the first replayed frame drawn (performance.now() in the page, after
//    the frame's render call), with the page's requests (Resource Timing).
// 4. Pauses and scrubs (#tl-scrub, as a user) to SEEKS random positions
//    over the whole recording, timing the input event -> the first frame
//    drawn at that time, and checks the drawn car against the recorded
//    states around that time (from the bridge, interpolated).
// Run: bench/web/replay_bench.sh [SEEKS] [OPENS] [--mcap FILE] [--render0]
import { spawnSync } from 'node:child_process';
import { copyFileSync, mkdtempSync, statSync, writeFileSync } from 'node:fs';
import { SourceMap } from 'node:module';
import { tmpdir } from 'node:os';
import * as h from '../../tests/web/harness.mjs';

const args = process.argv.slice(2);
const opt = (k) => { const i = args.indexOf(k); return i >= 0 ? args.splice(i, 2)[1] : null; };
const flag = (k) => { const i = args.indexOf(k); return i >= 0 ? !!args.splice(i, 1) : false; };
const mcapIn = opt('--mcap'), outFile = opt('--out'), render0 = flag('--render0'), profile = flag('--profile');
const SEEKS = parseInt(args[0] || '20', 10), OPENS = parseInt(args[1] || '5', 10);
const SCENARIO = new URL('./eight_sedans.json', import.meta.url).pathname;
const lines = [];
const say = (s = '') => { console.log(s); lines.push(s); };
const q = (xs, p) => { const s = [...xs].sort((a, b) => a - b); return s[Math.min(s.length - 1, Math.floor(p * s.length))]; };
const stats = (xs, unit = 'ms', d = 0) => xs.length
  ? `p50 ${q(xs, 0.5).toFixed(d)} ${unit}, p95 ${q(xs, 0.95).toFixed(d)} ${unit}, max ${Math.max(...xs).toFixed(d)} ${unit} (n=${xs.length})`
  : 'none';
// a seeded generator: the same positions every run
let seed = 12345;
const rand = () => ((seed = (seed * 1103515245 + 12345) % 2147483648) / 2147483648);

say(`# replay bench ${new Date().toISOString()} (bench/web/replay_bench.sh ${process.argv.slice(2).join(' ')})`);
if (process.env.GROUNDSIM_BENCH_NOTE) say(`variant: ${process.env.GROUNDSIM_BENCH_NOTE}`);
say(`host: ${spawnSync('nproc').stdout.toString().trim()} cores, load ${spawnSync('cat', ['/proc/loadavg']).stdout.toString().trim()}`);
const dir = mkdtempSync(`${tmpdir()}/groundsim-replay-bench-`);
const NAME = 'eight_sedans.mcap', file = `${dir}/${NAME}`;
await h.startServer();
if (mcapIn) {
  copyFileSync(mcapIn, file);
  say(`recording: ${mcapIn} (given)`);
} else {
  const w0 = Date.now();
  const r = spawnSync(h.CLI, ['record', '--create', SCENARIO, '--mode', 'fast', '--publish-rate', '60', '--out', file,
    '--repair-wait', '3', '--lcm-url', h.LCM_URL],
  { encoding: 'utf8', timeout: 1800000, env: { ...process.env, XDG_STATE_HOME: dir } });
  if (r.status !== 0) await h.fail(`groundsim record: exit ${r.status}: ${r.stderr}`);
  say(`recording: groundsim record --create bench/web/eight_sedans.json --mode fast --publish-rate 60: ${((Date.now() - w0) / 1000).toFixed(1)} s wall`);
  for (const l of r.stderr.split('\n')) if (/^record [0-9A-F]+ states|messages received/.test(l)) say(`  ${l}`);
}
const insp = spawnSync(h.CLI, ['inspect', file], { encoding: 'utf8' }).stdout;
for (const l of insp.split('\n')) if (/\/state |\/car_state|\/contact /.test(l)) say(`  ${l.replace(/\s+/g, ' ')}`);
say(`  file: ${(statSync(file).size / 1e6).toFixed(1)} MB (${file})`);

const { url } = await h.startBridge(['--recordings', dir, '--quiet']);
const info = await (await fetch(`${url}recordings/${NAME}`)).json();
const sess = info.sessions[0], ID = sess.id, T0 = sess.t0, T1 = sess.t1;
say(`  session ${ID}: ${sess.states} states, t ${T0}..${T1} s (${(sess.states / (T1 - T0)).toFixed(1)} states/s)`);
const cut = (t) => t.toFixed(6);

// ---- the bridge alone (curl) ----
say('\n## HTTP alone (curl: time to first byte / total; the bridge reads the file per request)');
function curl(path) {
  const r = spawnSync('curl', ['-s', '-o', '/dev/null', '-w', '%{http_code} %{size_download} %{time_starttransfer} %{time_total}', `${url}${path}`], { encoding: 'utf8' });
  const [code, size, ttfb, total] = r.stdout.trim().split(' ');
  if (code !== '200') throw new Error(`GET ${path}: HTTP ${code}`);
  return { size: +size, ttfb: 1000 * ttfb, total: 1000 * total };
}
const base = `recordings/${NAME}`, sq = `session=${ID}`;
const windows = [];
const nWin = Math.ceil((T1 - T0) / 8);
const http = {
  'GET /recordings': () => curl('recordings'),
  'GET /recordings/NAME': () => curl(base),
  'GET .../scene (first: builds the scene)': () => curl(`${base}/scene?${sq}`),
  'GET .../events': () => curl(`${base}/events?${sq}`),
  'GET .../ground': () => curl(`${base}/ground?${sq}&cx=${(rand() * 300).toFixed(1)}&cy=${(rand() * 300).toFixed(1)}`),
  'GET .../states 8 s window, max=5000': () => {
    const k = Math.floor(rand() * nWin), from = T0 + 8 * k;
    windows.push(k);
    return curl(`${base}/states?${sq}&from=${cut(from)}&to=${cut(Math.min(T1, from + 8))}&max=5000`);
  },
  'GET .../states at=T (scrub)': () => curl(`${base}/states?${sq}&at=${cut(T0 + rand() * (T1 - T0))}`),
};
const httpRuns = { 'GET .../scene (first: builds the scene)': 1, 'GET .../states 8 s window, max=5000': SEEKS, 'GET .../states at=T (scrub)': SEEKS };
const httpRes = {};
for (const [what, fn] of Object.entries(http)) {
  const rs = [];
  for (let i = 0; i < (httpRuns[what] || 10); ++i) rs.push(fn());
  httpRes[what] = rs;
  say(`${what}: ${(rs[0].size / 1e3).toFixed(1)} kB; first byte ${stats(rs.map((r) => r.ttfb), 'ms', 1)}; total ${stats(rs.map((r) => r.total), 'ms', 1)}`);
}

// ---- the page ----
const browser = await h.launch();
say(`\n## Browser: headless Chromium (SwiftShader), 1280 x 720${render0 ? ', ?render=0 (no drawing)' : ''}`);
// In the page: the first replayed frame's time after its render call (a
// microtask queued by a frame listener runs once the animation frame's
// callback, render included, has returned), and a seek's wanted frame.
const hook = () => {
  window.__bench = { first: null, want: null, frames: [] };
  const iv = setInterval(() => {
    const g = window.groundsim;
    if (!g || !g.frameListeners) return;
    clearInterval(iv);
    g.frameListeners.push((s, now) => {
      const b = window.__bench;
      b.frames.push(now);
      if (b.frames.length > 200) b.frames.shift();
      if (s && g.replay && b.first === null) {
        b.first = -1;
        queueMicrotask(() => { b.first = performance.now(); b.firstT = s.t; });
      }
      const w = b.want;
      if (w && s && g.replay && Math.abs(s.t - w.t) < 0.03) {
        b.want = null;
        const p = g.vehicles[0].root.position.toArray();
        queueMicrotask(() => w.done({ drawn: performance.now(), t: s.t, p }));
      }
    });
  }, 1);
};
const opens = [];
let page = null;
for (let i = 0; i < OPENS; ++i) {
  if (page) await page.context().close();
  page = await newReplayPage();
  const r = await page.evaluate(() => {
    const res = performance.getEntriesByType('resource').map((e) => ({
      name: e.name.replace(location.origin, '').replace(/\?.*/, ''), start: e.startTime, end: e.responseEnd, bytes: e.encodedBodySize,
    }));
    const nav = performance.getEntriesByType('navigation')[0];
    return { first: window.__bench.first, dcl: nav.domContentLoadedEventEnd, load: nav.loadEventEnd, res };
  });
  const first = r.res.find((e) => e.name === `/recordings/${NAME}`);
  r.replayPart = first ? r.first - first.start : NaN;
  opens.push(r);
  const rs = r.res
    .map((e) => `${e.name.replace(`/recordings/${NAME}`, 'R')} ${e.start.toFixed(0)}-${e.end.toFixed(0)}`).join(', ');
  say(`open ${i + 1}: first replayed frame drawn at ${r.first.toFixed(0)} ms after navigation start, ${r.replayPart.toFixed(0)} ms after the replay's first request (DOMContentLoaded ${r.dcl.toFixed(0)} ms; requests ms: ${rs})`);
}
say(`open (navigation -> first replayed frame drawn): ${stats(opens.map((o) => o.first))}`);
say(`  of which the replay's own part (its first request, GET /recordings/NAME after the WebSocket opened -> the frame): ${stats(opens.map((o) => o.replayPart))}`);
if (profile) await profileOpen();

// --profile: one more open under the V8 sampling profiler (CDP): the page's
// main-thread time up to the first replayed frame, by function (self time)
async function profileOpen() {
  const ctx = await browser.newContext({ viewport: { width: 1280, height: 720 } });
  const p = await ctx.newPage();
  await p.addInitScript(hook);
  const cdp = await ctx.newCDPSession(p);
  await cdp.send('Profiler.enable');
  await cdp.send('Profiler.setSamplingInterval', { interval: 250 });
  await cdp.send('Profiler.start');
  await p.goto(`${url}?replay=${encodeURIComponent(NAME)}&rsession=${ID}${render0 ? '&render=0' : ''}`);
  await h.until('the first replayed frame', () => p.evaluate(() => window.__bench.first > 0), 120000, 20);
  const first = await p.evaluate(() => window.__bench.first);
  const { profile: pr } = await cdp.send('Profiler.stop');
  const byId = new Map(pr.nodes.map((n) => [n.id, n]));
  // names from the bundle's source map (the bridge serves it beside bundle.js)
  let map = null;
  try { map = new SourceMap(await (await fetch(`${url}bundle.js.map`)).json()); } catch { map = null; }
  const where = (f) => {
    const e = map && /bundle\.js/.test(f.url) ? map.findEntry(f.lineNumber, f.columnNumber) : null;
    return e && e.originalSource ? `${e.originalSource.replace(/.*node_modules\//, '').replace(/.*\/src\//, 'web/src/')}:${e.originalLine + 1}` : `${f.url.replace(/.*\//, '')}:${f.lineNumber + 1}`;
  };
  const self = new Map();
  pr.samples.forEach((id, i) => {
    const n = byId.get(id), f = n.callFrame;
    const key = f.url ? where(f) : f.functionName;
    self.set(key, (self.get(key) || 0) + (pr.timeDeltas[i] || 0) / 1000);
  });
  const total = [...self.values()].reduce((a, b) => a + b, 0);
  say(`profiled open: first replayed frame at ${first.toFixed(0)} ms; ${total.toFixed(0)} ms sampled, self time by function:`);
  for (const [k, v] of [...self.entries()].sort((a, b) => b[1] - a[1]).slice(0, 20)) say(`  ${v.toFixed(0).padStart(6)} ms  ${k}`);
  await ctx.close();
}

async function newReplayPage() {
  const ctx = await browser.newContext({ viewport: { width: 1280, height: 720 } });
  const p = await ctx.newPage();
  p.on('pageerror', (e) => console.error(`[page] ${e.message}`));
  await p.addInitScript(hook);
  await p.goto(`${url}?replay=${encodeURIComponent(NAME)}&rsession=${ID}${render0 ? '&render=0' : ''}`);
  await h.until('the first replayed frame', () => p.evaluate(() => window.__bench.first > 0), 120000, 20);
  return p;
}

// ---- seeks ----
await h.until('the replay to start playing', () => page.evaluate(() => window.groundsim.replay.playing), 60000, 20);
await page.click('#tl-play');  // pause: the playhead stays where it is put
await page.waitForFunction(() => !window.groundsim.replay.playing);
await page.waitForTimeout(1000);
const fps = await page.evaluate(() => window.groundsim.fps);
say(`frames/s while paused: ${fps.toFixed(1)} (a seek waits for the next frame)`);
const seeks = [];
for (let i = 0; i < SEEKS; ++i) {
  const v = Math.floor(rand() * 1001), t = T0 + (T1 - T0) * v / 1000;
  const r = await page.evaluate(([v, t]) => new Promise((resolve) => {
    const b = window.__bench, t0 = performance.now(), k = window.groundsim.replay.index(t);
    const cached = !!(window.groundsim.replay.windows.get(k) || {}).states;
    const timer = setTimeout(() => { b.want = null; resolve({ timeout: true }); }, 30000);
    b.want = {
      t,
      done: (x) => {
        clearTimeout(timer);
        const res = performance.getEntriesByType('resource').filter((e) => e.startTime >= t0 && e.name.includes('/states'))
          .map((e) => ({ fetch: e.responseEnd - e.startTime, ttfb: e.responseStart - e.startTime, end: e.responseEnd - t0, bytes: e.encodedBodySize }));
        resolve({ ...x, ms: x.drawn - t0, cached, res });
      },
    };
    const el = document.getElementById('tl-scrub');
    el.value = String(v);
    el.dispatchEvent(new Event('input', { bubbles: true }));
  }), [v, t]);
  if (r.timeout) { say(`seek ${i + 1} to ${t.toFixed(2)} s: no frame at that time within 30 s`); continue; }
  // the recorded states around t, interpolated as the page does (linearly)
  const body = await (await fetch(`${url}${base}/states?${sq}&from=${cut(Math.max(T0, r.t - 0.05))}&to=${cut(Math.min(T1, r.t + 0.05))}&max=100`)).json();
  const st = body.states;
  let j = 0;
  while (j + 1 < st.length && st[j + 1].t <= r.t) ++j;
  const a = st[j], bb = st[Math.min(j + 1, st.length - 1)], u = bb.t > a.t ? (r.t - a.t) / (bb.t - a.t) : 0;
  const rec = a.vehicles[0].position.map((x, d) => x + (bb.vehicles[0].position[d] - x) * u);
  r.err = Math.hypot(...rec.map((x, d) => x - r.p[d]));
  r.target = t;
  seeks.push(r);
  const f = r.res[0];
  say(`seek ${String(i + 1).padStart(2)} to ${t.toFixed(2).padStart(6)} s: drawn after ${r.ms.toFixed(0).padStart(5)} ms` +
      (f ? ` (window fetched in ${f.fetch.toFixed(0)} ms, first byte ${f.ttfb.toFixed(0)} ms, ${(f.bytes / 1e3).toFixed(0)} kB)` : r.cached ? ' (window cached)' : '') +
      `; car at (${r.p.map((x) => x.toFixed(2)).join(', ')}), ${(100 * r.err).toFixed(1)} cm from the recording`);
  await page.waitForTimeout(300);
}
const moved = seeks.length > 1 ? Math.max(...seeks.map((s) => Math.hypot(...s.p.map((x, d) => x - seeks[0].p[d])))) : 0;
say(`seek (scrub input -> frame drawn at that time): ${stats(seeks.map((s) => s.ms))}`);
say(`  of which the window's fetch (uncached seeks): ${stats(seeks.filter((s) => s.res.length).map((s) => s.res[0].fetch))}`);
say(`  drawn car vs recorded position: max ${(100 * Math.max(...seeks.map((s) => s.err))).toFixed(1)} cm; the car moved up to ${moved.toFixed(1)} m between seeks`);

// A window's cost in the page without a frame: a fresh Replay of the same
// recording (the page's own class) loads windows it has not seen: fetch,
// JSON, fromRecorded; and the same fetch's text and JSON.parse alone.
const loads = await page.evaluate(async ([ks]) => {
  const r = window.groundsim.replay, R = r.constructor, out = [];
  for (const k of ks) {
    const x = new R(r.name, r.session);
    x.t0 = r.t0; x.t1 = r.t1; x.loaded = true;
    const a = performance.now();
    await x.load(k);
    const b = performance.now();
    const res = await fetch(x.url(x.t0 + 8 * k, Math.min(x.t1, x.t0 + 8 * k + 8)));
    const text = await res.text();
    const c = performance.now();
    JSON.parse(text);
    const d = performance.now();
    // what a seek would wait for with a short window around T first (0.5 s)
    const t = x.t0 + 8 * k + 4, e = performance.now();
    const small = await (await fetch(x.url(t - 0.25, t + 0.25))).json();
    const f = performance.now();
    out.push({ load: b - a, fetchText: c - b, parse: d - c, bytes: text.length, states: (x.windows.get(k) || {}).states?.length,
      small: f - e, smallStates: small.states.length });
  }
  return out;
}, [[3, 17, 29, 41, 55, 63, 70, 11, 37, 49]]);
say(`window load in the page, no frame (Replay.load: fetch + JSON + fromRecorded, ${loads[0].states} states, ${(loads[0].bytes / 1e6).toFixed(2)} MB): ${stats(loads.map((l) => l.load))}`);
say(`  the same window's fetch + text: ${stats(loads.map((l) => l.fetchText))}; JSON.parse alone: ${stats(loads.map((l) => l.parse))}`);
say(`  a 0.5 s window (${loads[0].smallStates} states) fetched and parsed instead: ${stats(loads.map((l) => l.small))}`);

say('\n## Summary');
say(`open: ${stats(opens.map((o) => o.first))} (goal < 1000 ms); the replay's own part ${stats(opens.map((o) => o.replayPart))}`);
say(`seek: ${stats(seeks.map((s) => s.ms))} (goal < 200 ms)`);
say(`HTTP 8 s window: ${stats(httpRes['GET .../states 8 s window, max=5000'].map((r) => r.total), 'ms', 1)}, at=T: ${stats(httpRes['GET .../states at=T (scrub)'].map((r) => r.total), 'ms', 1)}`);
if (outFile) writeFileSync(outFile, `${lines.join('\n')}\n`);
await h.pass(outFile ? `written to ${outFile}` : '');

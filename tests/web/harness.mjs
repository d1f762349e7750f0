// What every browser test shares: the real groundsim-server and
// groundsim-web (bound to 127.0.0.1, port chosen by the kernel) on the
// private LCM bus of the test's network namespace (netns_run.sh), and
// Debian's Chromium driven by playwright-core, rendering WebGL 2 in software
// (SwiftShader). Tests end by calling pass() or fail(); a test that cannot
// run here (no Chromium) exits 77, which CTest reports as skipped.
import { spawn, spawnSync } from 'node:child_process';
import { createRequire } from 'node:module';
import { existsSync, mkdtempSync } from 'node:fs';
import { tmpdir } from 'node:os';

const env = process.env;
export const SERVER = env.GROUNDSIM_SERVER, BRIDGE = env.GROUNDSIM_WEB, CLI = env.GROUNDSIM_CLI;
export const CONFIGS = env.GROUNDSIM_CONFIG_DIR;
export const LCM_URL = 'udpm://239.255.76.67:7667?ttl=0';
export const CHROMIUM = env.GROUNDSIM_CHROMIUM || '/usr/bin/chromium';
// no network: background services of Chromium would try to reach out
export const CHROMIUM_ARGS = ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
  '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run',
  '--disable-quic', '--disable-default-apps', '--mute-audio',
  // several pages play at once in one browser: none of them is "in the background"
  '--disable-background-timer-throttling', '--disable-renderer-backgrounding', '--disable-backgrounding-occluded-windows'];

const children = [];
let browser = null;

export function skip(reason) {
  console.log(`SKIP: ${reason}`);
  process.exit(77);
}

export async function cleanup() {
  if (browser) await browser.close().catch(() => {});
  browser = null;
  for (const c of children) if (c.exitCode === null) c.kill('SIGTERM');
  await new Promise((r) => setTimeout(r, 300));
  for (const c of children) if (c.exitCode === null) c.kill('SIGKILL');
}

export async function pass(msg = '') {
  await cleanup();
  console.log(`PASS ${msg}`);
  process.exit(0);
}

export async function fail(msg) {
  console.error(`FAIL: ${msg}`);
  await cleanup();
  process.exit(1);
}

// whatever ends this process ends the services too
process.on('exit', () => { for (const c of children) if (c.exitCode === null) c.kill('SIGKILL'); });
process.on('uncaughtException', (e) => fail(e && e.stack ? e.stack : String(e)));
process.on('unhandledRejection', (e) => fail(e && e.stack ? e.stack : String(e)));

function start(cmd, args, name) {
  const c = spawn(cmd, args, { stdio: ['ignore', 'pipe', 'pipe'] });
  c.output = '';
  c.stdout.on('data', (d) => { c.output += d; });
  c.stderr.on('data', (d) => { process.stderr.write(`[${name}] ${d}`); });
  children.push(c);
  return c;
}

// Generous: a page under a slow server (the ASan suite) may take many times
// its usual second; a timeout is only how long a failure takes to report.
export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

export async function until(what, fn, timeoutMs = 60000, everyMs = 100) {
  const t0 = Date.now();
  for (;;) {
    const v = await fn();
    if (v) return v;
    if (Date.now() - t0 > timeoutMs) throw new Error(`timed out after ${timeoutMs} ms waiting for ${what}`);
    await new Promise((r) => setTimeout(r, everyMs));
  }
}

// Resolves once the server listens: a request published before it has
// subscribed would be lost, and a slow build (the ASan suite) takes seconds.
// (Without Chromium a test that launches a browser is skipped at launch();
// the Foxglove tests, with no browser, run.)
export async function startServer() {
  const server = start(SERVER, ['--lcm-url', LCM_URL, '--workers', '1'], 'server');
  await until('the server to be ready', () => server.output.includes('groundsim-server ready'));
  return server;
}

// groundsim-web on 127.0.0.1, a port chosen by the kernel; returns its URL.
export async function startBridge(bridgeArgs = []) {
  const bridge = start(BRIDGE, ['--lcm-url', LCM_URL, '--bind', '127.0.0.1', '--port', '0', ...bridgeArgs], 'bridge');
  const url = await until('the bridge to print its URL', () => {
    const m = bridge.output.match(/open (http:\/\/127\.0\.0\.1:\d+\/)/);
    return m && m[1];
  }, 60000);
  return { url, bridge };
}

// groundsim-server and groundsim-web; returns the page's URL.
export async function startServices({ bridgeArgs = [] } = {}) {
  const server = await startServer();
  const { url, bridge } = await startBridge(bridgeArgs);
  return { url, bridge, server };
}

export async function launch() {
  if (!existsSync(CHROMIUM)) skip(`no Chromium at ${CHROMIUM} (apt-get install chromium, or scripts/setup-web.sh)`);
  const require = createRequire(`${env.GROUNDSIM_WEB_NODE_MODULES}/`);
  const { chromium } = require('playwright-core');
  browser = await chromium.launch({ executablePath: CHROMIUM, headless: true, args: CHROMIUM_ARGS });
  return browser;
}

// `context`: more options of the browser context (recordVideo, ...).
export async function newPage(url, size = { width: 960, height: 540 }, context = {}) {
  const ctx = await browser.newContext({ viewport: size, ...context });
  const page = await ctx.newPage();
  page.on('pageerror', (e) => console.error(`[page] ${e.message}`));
  await page.goto(url);
  await until('the page to connect', () => page.evaluate(() => window.groundsim && window.groundsim.configs.length > 0));
  return page;
}

// Creates a session from the lobby (as a user would: pick, click) and waits
// until this page drives it and draws its states.
export async function createAndDrive(page, config, cars = 1) {
  await page.selectOption('#create-config', config);
  await page.fill('#create-vehicles', String(cars));
  await page.click('#create-drive');
  await until('the session to be joined', () => page.evaluate(() => window.groundsim.role === 'drive' && window.groundsim.states > 2));
  return page.evaluate(() => window.groundsim.session);
}

// The `groundsim` command line client on the same bus (60 s: a ceiling for a
// hung request only; a loaded machine answers late).
// Its tokens file goes to a directory of this test, not the user's.
const stateHome = mkdtempSync(`${tmpdir()}/groundsim-web-test-`);
export function cli(...args) {
  const r = spawnSync(CLI, [...args, '--lcm-url', LCM_URL],
    { encoding: 'utf8', timeout: 60000, env: { ...process.env, XDG_STATE_HOME: stateHome } });
  if (r.status !== 0) throw new Error(`groundsim ${args.join(' ')}: exit ${r.status}${r.signal ? ` (${r.signal})` : ''}${r.error ? ` (${r.error.message})` : ''}: ${r.stderr}`);
  return r.stdout;
}

// Spread of the canvas' pixel values: a blank or one-colour frame is 0.
export async function canvasStats(page) {
  return page.evaluate(() => {
    const src = document.querySelector('#view canvas');
    const c = document.createElement('canvas');
    c.width = 160; c.height = 90;
    const g = c.getContext('2d');
    g.drawImage(src, 0, 0, c.width, c.height);
    const d = g.getImageData(0, 0, c.width, c.height).data;
    const colours = new Set();
    let sum = 0, sum2 = 0, n = 0;
    for (let i = 0; i < d.length; i += 4) {
      const y = 0.299 * d[i] + 0.587 * d[i + 1] + 0.114 * d[i + 2];
      sum += y; sum2 += y * y; n++;
      colours.add((d[i] >> 4) << 8 | (d[i + 1] >> 4) << 4 | (d[i + 2] >> 4));
    }
    const mean = sum / n;
    return { mean, std: Math.sqrt(Math.max(0, sum2 / n - mean * mean)), colours: colours.size };
  });
}

// Speeds (m/s) of every vehicle in `groundsim watch`'s next state line: what
// the server publishes, read without the bridge.
export function serverSpeeds(session) {
  const out = cli('watch', session, '--count', '1');
  const line = out.trim().split('\n').pop();
  return [...line.matchAll(/speed=(-?[0-9.]+) m\/s/g)].map((m) => parseFloat(m[1]));
}

export const hudSpeedKmh = (page) => page.evaluate(() => parseFloat(document.getElementById('hud-speed').textContent));
// Speed (m/s) of car i along its heading, horizontally. The body's speed
// also holds its bouncing on undamped contact springs (up to 0.3 m/s on
// plain.json at rest), and the wheels' spin their vibration; this does not.
export const rolling = (page, i) => page.evaluate((k) => {
  const v = window.groundsim.lastState.vehicles[k], [w, x, y, z] = v.q;
  const fx = 1 - 2 * (y * y + z * z), fy = 2 * (x * y + w * z), n = Math.hypot(fx, fy) || 1;
  return (fx * v.v[0] + fy * v.v[1]) / n;
}, i);
export const pageSpeed = (page, i) => page.evaluate((k) => window.groundsim.lastState.vehicles[k].speed, i);

// Mean speed (m/s) of each listed car along its heading, horizontally, over
// the next `span` s of simulated time in the page's states: the slope of a
// least-squares line through its positions. A car released from the
// handbrake rocks on its undamped contacts for good (on plain.json up to
// +-0.3 m/s, +-9 cm, a period of about 2.2 s); one sample of its speed holds
// that whole swing, and over a window near one period so do a displacement
// over the time and a fitted slope (0.1 m/s). Over 4 s the slope's share of
// a +-10 cm swing is at most 0.03 m/s for periods of 1.2 to 3.5 s.
export const meanRolling = (page, cars, span = 4.0, timeoutMs = 60000) => page.evaluate(([ks, span, timeoutMs]) =>
  new Promise((resolve, reject) => {
    const g = window.groundsim;
    let first = null;
    const rows = [];  // [t, distance along each car's first heading]
    const fn = (m) => {
      if (!first) first = m;
      rows.push([m.t - first.t, ks.map((k) => {
        const a = first.vehicles[k], b = m.vehicles[k], [w, x, y, z] = a.q;
        const fx = 1 - 2 * (y * y + z * z), fy = 2 * (x * y + w * z), n = Math.hypot(fx, fy) || 1;
        return (fx * (b.p[0] - a.p[0]) + fy * (b.p[1] - a.p[1])) / n;
      })]);
      if (m.t - first.t < span || rows.length < 3) return;
      done();
      const mt = rows.reduce((a, r) => a + r[0], 0) / rows.length;
      resolve(ks.map((_, j) => {
        const ms = rows.reduce((a, r) => a + r[1][j], 0) / rows.length;
        let num = 0, den = 0;
        for (const [t, d] of rows) { num += (t - mt) * (d[j] - ms); den += (t - mt) * (t - mt); }
        return num / den;
      }));
    };
    const timer = setTimeout(() => { done(); reject(new Error(`no ${span} s of states in ${timeoutMs} ms`)); }, timeoutMs);
    const done = () => { clearTimeout(timer); g.stateListeners = g.stateListeners.filter((f) => f !== fn); };
    g.stateListeners.push(fn);
  }), [cars, span, timeoutMs]);

// Simulated time of the session's next state on the bus (groundsim watch).
export function serverTime(session) {
  const m = cli('watch', session, '--count', '1').match(/t=(-?[0-9.]+)/);
  if (!m) throw new Error(`no state of session ${session} on the bus`);
  return parseFloat(m[1]);
}

// Waits until the page's newest state is within `margin` s of the server's.
// A page that just joined compiles its shaders in its first frames; under
// software WebGL on a busy machine that blocks its main thread for seconds
// (10-20 s seen with three pages and a parallel build), while the states
// queue in the socket, and the page then shows, and the test would read,
// seconds-old states until it has caught up.
export async function caughtUp(page, session, margin = 0.5) {
  let behind = null;
  await until('the page to catch up with the server\'s states', async () => {
    const server = serverTime(session);
    const t = await page.evaluate(() => (window.groundsim.lastState ? window.groundsim.lastState.t : null));
    behind = t === null ? null : server - t;
    return behind !== null && behind < margin;
  }, 120000, 200);
  return behind;
}
// The simulated time of the page's newest state.
export const simTime = (page) => page.evaluate(() => (window.groundsim.lastState ? window.groundsim.lastState.t : null));

// Waits until the page has received states `span` s of simulated time past
// its newest one now (a duration on the session's clock, not the wall's: a
// loaded machine or a slow server only makes it take longer); returns the
// simulated times [from, to].
export async function simWait(page, span, what = `${span} s of simulated time`, timeoutMs = 120000) {
  const from = await simTime(page);
  const to = await until(what, async () => {
    const t = await simTime(page);
    return t !== null && t >= from + span && t;
  }, timeoutMs, 20);
  return [from, to];
}

// Pauses the page's session as its driver does (P) and waits for a state
// that shows it paused; returns that state's simulated time, where the
// session's clock now stands until it resumes.
export async function pause(page) {
  await page.keyboard.press('p');
  return until('the session to pause', () => page.evaluate(() => {
    const s = window.groundsim.lastState;
    return s && s.status === 2 && { t: s.t, seq: s.seq };
  }), 60000, 20).then((s) => s.t);
}
// Resumes it (P again) and waits for a running state.
export async function resume(page) {
  await page.keyboard.press('p');
  await until('the session to resume', () => page.evaluate(() => window.groundsim.lastState.status === 1), 60000, 20);
}

export async function hold(page, key, ms) {
  await page.keyboard.down(key);
  await page.waitForTimeout(ms);
  await page.keyboard.up(key);
}

// Holds a key until done() holds (a server slower than real time, e.g.
// under ASan, needs longer than a fixed hold's wall time to respond).
export async function holdUntil(page, key, what, done, timeoutMs = 30000) {
  await page.keyboard.down(key);
  try {
    await until(what, done, timeoutMs, 50);
  } finally {
    await page.keyboard.up(key);
  }
}

// Holds the handbrake (space) until every listed car of the page's state is still.
export async function stopCars(page, cars = [0], timeoutMs = 60000) {
  await page.keyboard.down(' ');
  try {
    // for half a second: a car rocking on its tyres passes 0
    let still = 0;
    await until('the cars to stop', async () => {
      let ok = true;
      for (const k of cars) ok = ok && Math.abs(await rolling(page, k)) < 0.05;
      still = ok ? still + 1 : 0;
      return still >= 10;
    }, timeoutMs, 50);
  } finally {
    await page.keyboard.up(' ');
  }
}

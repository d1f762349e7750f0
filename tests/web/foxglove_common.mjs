// What the Foxglove endpoint's tests share: the real groundsim-server and
// groundsim-web (--foxglove-port 0: a port chosen by the kernel, printed)
// on the private LCM bus of the test's network namespace (netns_run.sh),
// the `groundsim` CLI to create and stop sessions, and the npm packages of
// web/package.json (ws, @foxglove/ws-protocol, ajv) from the build tree.
// No browser: these clients are what Foxglove and Lichtblick are on the
// wire. Tests end by calling pass() or fail().
import { spawn, spawnSync } from 'node:child_process';
import { createRequire } from 'node:module';
import { mkdtempSync } from 'node:fs';
import { tmpdir } from 'node:os';

const env = process.env;
export const LCM_URL = 'udpm://239.255.76.67:7667?ttl=0';
export const CONFIGS = env.GROUNDSIM_CONFIG_DIR;
export const require = createRequire(`${env.GROUNDSIM_WEB_NODE_MODULES}/`);
export const WebSocket = require('ws');

const children = [];

export async function cleanup() {
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

export async function until(what, fn, timeoutMs = 30000, everyMs = 50) {
  const t0 = Date.now();
  for (;;) {
    const v = await fn();
    if (v) return v;
    if (Date.now() - t0 > timeoutMs) throw new Error(`timed out after ${timeoutMs} ms waiting for ${what}`);
    await new Promise((r) => setTimeout(r, everyMs));
  }
}
export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

// groundsim-server, then groundsim-web with a Foxglove port; returns the
// page's http URL and the Foxglove ws URL.
export async function startServices(bridgeArgs = []) {
  const server = start(env.GROUNDSIM_SERVER, ['--lcm-url', LCM_URL, '--workers', '1'], 'server');
  await until('the server to be ready', () => server.output.includes('groundsim-server ready'));
  const bridge = start(env.GROUNDSIM_WEB, ['--lcm-url', LCM_URL, '--bind', '127.0.0.1', '--port', '0',
    '--foxglove-port', '0', ...bridgeArgs], 'bridge');
  const urls = await until('the bridge to print its URLs', () => {
    const http = bridge.output.match(/open (http:\/\/127\.0\.0\.1:\d+\/)/);
    const ws = bridge.output.match(/foxglove (ws:\/\/127\.0\.0\.1:\d+\/)/);
    return http && ws && { http: http[1], ws: ws[1] };
  }, 15000);
  return { ...urls, server, bridge };
}

const stateHome = mkdtempSync(`${tmpdir()}/groundsim-foxglove-test-`);
export function cli(...args) {
  const r = spawnSync(env.GROUNDSIM_CLI, [...args, '--lcm-url', LCM_URL],
    { encoding: 'utf8', timeout: 20000, env: { ...process.env, XDG_STATE_HOME: stateHome } });
  if (r.status !== 0) throw new Error(`groundsim ${args.join(' ')}: exit ${r.status}: ${r.stderr}`);
  return r.stdout;
}
// A session of `config` until stopped; returns its id.
export function createSession(config, ...more) {
  return cli('create', `${CONFIGS}/${config}`, '--duration', '-1', ...more).trim().split('\n').pop().trim();
}

// The bridge's GET /metrics as {name: value} (unlabelled samples only).
export async function metrics(httpUrl) {
  const text = await (await fetch(`${httpUrl}metrics`)).text();
  const out = {};
  for (const line of text.split('\n')) {
    const m = line.match(/^([a-z_]+) (\S+)$/);
    if (m) out[m[1]] = Number(m[2]);
  }
  return out;
}

// A raw protocol client on the `ws` package: JSON text messages collected
// by op, binary message-data frames parsed by hand (0x01, u32 subscription,
// u64 ns, little-endian, then the JSON).
export function rawClient(url, protocols) {
  const ws = new WebSocket(url, protocols);
  const c = { ws, texts: [], statuses: [], channels: new Map(), data: [], closed: null, refused: null };
  ws.on('message', (buf, isBinary) => {
    if (!isBinary) {
      const m = JSON.parse(buf.toString());
      c.texts.push(m);
      if (m.op === 'status') c.statuses.push(m);
      if (m.op === 'advertise') for (const ch of m.channels) c.channels.set(ch.id, ch);
      if (m.op === 'unadvertise') for (const id of m.channelIds) c.channels.delete(id);
      return;
    }
    if (buf[0] !== 1) throw new Error(`binary opcode ${buf[0]}, expected 1 (message data)`);
    c.data.push({ sub: buf.readUInt32LE(1), ns: buf.readBigUInt64LE(5), json: JSON.parse(buf.subarray(13).toString()),
      at: performance.timeOrigin + performance.now() });
  });
  ws.on('close', (code, reason) => { c.closed = { code, reason: reason.toString() }; });
  ws.on('unexpected-response', (req, res) => {
    let body = '';
    res.on('data', (d) => { body += d; });
    res.on('end', () => { c.refused = { status: res.statusCode, body }; });
  });
  ws.on('error', () => {});
  c.open = () => new Promise((resolve, reject) => {
    ws.once('open', resolve);
    ws.once('error', reject);
  });
  c.send = (obj) => ws.send(typeof obj === 'string' ? obj : JSON.stringify(obj));
  c.topic = (topic) => [...c.channels.values()].find((ch) => ch.topic === topic);
  return c;
}

// seq of a list of states: [gaps, out of order]
export function seqCheck(states) {
  let gaps = 0, backwards = 0;
  for (let i = 1; i < states.length; ++i) {
    const d = states[i].seq - states[i - 1].seq;
    if (d <= 0) ++backwards; else gaps += d - 1;
  }
  return { gaps, backwards };
}

export function percentile(xs, p) {
  const s = [...xs].sort((a, b) => a - b);
  return s.length ? s[Math.min(s.length - 1, Math.floor(p * s.length))] : NaN;
}

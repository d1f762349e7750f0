// What the Foxglove endpoint's tests share: the real groundsim-server and
// groundsim-web (--foxglove-port 0: a port chosen by the kernel, printed)
// on the private LCM bus of the test's network namespace (netns_run.sh),
// the `groundsim` CLI to create and stop sessions, and the npm packages of
// web/package.json (ws, @foxglove/ws-protocol, ajv) from the build tree.
// No browser: these clients are what Foxglove and Lichtblick are on the
// wire. Tests end by calling pass() or fail().
// The services, the CLI and pass/fail/until are the browser tests' harness
// (harness.mjs); only a browser is not launched.
import { createRequire } from 'node:module';
import * as h from './harness.mjs';

const env = process.env;
export const { LCM_URL, CONFIGS, pass, fail, skip, cleanup, sleep, cli } = h;
export const require = createRequire(`${env.GROUNDSIM_WEB_NODE_MODULES}/`);
export const WebSocket = require('ws');

// these tests poll their clients more often than a page; the ceiling only
// ends a hung test (a loaded machine or a sanitized build is slower)
export const until = (what, fn, timeoutMs = 60000, everyMs = 50) => h.until(what, fn, timeoutMs, everyMs);

// groundsim-server, then groundsim-web with a Foxglove port; returns the
// page's http URL and the Foxglove ws URL.
export async function startServices(bridgeArgs = []) {
  const server = await h.startServer();
  const { url, bridge } = await h.startBridge(['--foxglove-port', '0', ...bridgeArgs]);
  const ws = await until('the bridge to print its Foxglove URL', () => {
    const m = bridge.output.match(/foxglove (ws:\/\/127\.0\.0\.1:\d+\/)/);
    return m && m[1];
  }, 60000);
  return { http: url, ws, server, bridge };
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

// Hostile WebSocket input leaves the bridge serving: not JSON, too deep,
// too large, unknown ops and fields, wrong types and ranges, binary frames,
// controls without a car, driving a session it holds no token for. Each is
// answered with an error naming the field, and afterwards the same
// connection and a fresh page still work (a session is created and driven).
// The pages run without drawing (?render=0).
import * as h from './harness.mjs';

const { url, bridge } = await h.startServices();
await h.launch();
const page = await h.newPage(`${url}?render=0`);
const answers = await page.evaluate(async (wsUrl) => {
  const ws = new WebSocket(wsUrl);
  const got = [];
  ws.onmessage = (e) => { const m = JSON.parse(e.data); if (m.op === 'error' || m.op === 'pong') got.push(m); };
  await new Promise((r) => { ws.onopen = r; });
  const bad = [
    'not json {', '[1,2,3]', '{"no_op":1}', '{"op":7}', '{"op":"fly"}',
    '{"op":"controls","throttle":2}', '{"op":"controls","throttle":"full"}', '{"op":"controls","steer":0.1,"extra":1}',
    '{"op":"join","session":"../../etc"}', '{"op":"join","session":"ABCDEF12","role":"drive"}',
    '{"op":"create","config":"../secret.json"}', '{"op":"ground","cx":1e7,"cy":0}',
    JSON.stringify({ op: 'ping', t: 1, pad: 'x'.repeat(5000) }),
    '{"op":"ping","t":' + '['.repeat(50) + ']'.repeat(50) + '}',
  ];
  for (const b of bad) ws.send(b);
  ws.send(new Uint8Array([1, 2, 3]));
  ws.send('{"op":"ping","t":42}');
  // the bridge answers in order: the pong comes after every refusal
  const t0 = performance.now();
  while (!got.some((m) => m.op === 'pong' && m.t === 42) && performance.now() - t0 < 60000)
    await new Promise((r) => setTimeout(r, 50));
  return got;
}, url.replace('http', 'ws') + 'ws');
for (const a of answers) console.log(JSON.stringify(a));
const errors = answers.filter((a) => a.op === 'error');
const fields = errors.map((e) => e.field);
for (const want of ['/op', '/throttle', '/extra', '/session', '/role', '/config', '/cx'])
  if (!fields.includes(want)) await h.fail(`no error naming ${want}: ${JSON.stringify(fields)}`);
if (errors.length !== 15) await h.fail(`expected 15 refusals, got ${errors.length}`);
if (!answers.some((a) => a.op === 'pong' && a.t === 42)) await h.fail('the connection stopped answering after bad input');
if (bridge.exitCode !== null) await h.fail(`the bridge exited (${bridge.exitCode})`);
const fresh = await h.newPage(`${url}?render=0`);
await h.createAndDrive(fresh, 'plain.json');
await h.pass(`${errors.length} refusals, bridge still serving`);

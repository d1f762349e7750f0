// What a Foxglove client gets from the bridge's --foxglove-port: messages
// per second and the delay from the bridge's receive timestamp (the frame's
// ns) to the client reading the frame, on the real groundsim-server and
// groundsim-web. Run by hand in a network namespace of its own, from a
// build directory's binaries:
//   GROUNDSIM_SERVER=build/server/lcm/groundsim-server GROUNDSIM_WEB=build/web/bridge/groundsim-web \
//   GROUNDSIM_CLI=build/client/groundsim GROUNDSIM_CONFIG_DIR=configs \
//   GROUNDSIM_WEB_NODE_MODULES=build/web/node_modules \
//   tests/integration/netns_run.sh node bench/web/foxglove_rate.mjs [SECONDS]
// 1. a realtime sedan session asked for 100 states/s: the delay;
// 2. one and four fast-mode sessions (the cheap parabola scene, 10,000
//    states per simulated second, as fast as the server publishes), one
//    client subscribed to all: the most it gets, with the outbox's drops
//    (/metrics) and seq gaps.
import * as f from '../../tests/web/foxglove_common.mjs';

const seconds = Number(process.argv[2] || 10);
const { http, ws } = await f.startServices();

// `n` sessions of `config`, one client subscribed to every one's states.
async function measure(n, config, args, label) {
  const ids = Array.from({ length: n }, () => f.createSession(config, ...args));
  const c = f.rawClient(ws, ['foxglove.sdk.v1']);
  await c.open();
  await f.until('their state channels', () => ids.every((id) => c.topic(`/${id}/state`)));
  c.send({ op: 'subscribe', subscriptions: ids.map((id, i) => ({ id: i, channelId: c.topic(`/${id}/state`).id })) });
  await f.until('the first states', () => c.data.length > 10 * n);
  const m0 = await f.metrics(http);
  const n0 = c.data.length, t0 = performance.now();
  await f.sleep(seconds * 1000);
  const got = c.data.slice(n0);
  const dt = (performance.now() - t0) / 1000;
  const m1 = await f.metrics(http);
  const delays = got.map((d) => d.at - Number(d.ns) / 1e6);
  let gaps = 0, backwards = 0;
  for (let i = 0; i < n; ++i) {
    const sq = f.seqCheck(got.filter((d) => d.sub === i).map((d) => d.json));
    gaps += sq.gaps;
    backwards += sq.backwards;
  }
  const bytes = got.reduce((s, d) => s + JSON.stringify(d.json).length, 0);
  console.log(`${label}: ${(got.length / dt).toFixed(0)} states/s to one client (${(bytes / got.length).toFixed(0)} B ` +
    `of JSON each), seq gaps ${gaps}, out of order ${backwards}, dropped by the outbox ` +
    `${m1.groundsim_web_foxglove_messages_dropped_total - m0.groundsim_web_foxglove_messages_dropped_total}; ` +
    `receive timestamp to client: median ${f.percentile(delays, 0.5).toFixed(2)} ms, ` +
    `p99 ${f.percentile(delays, 0.99).toFixed(2)} ms, max ${Math.max(...delays).toFixed(2)} ms`);
  c.ws.close();
  for (const id of ids) f.cli('stop', id);
}

await measure(1, 'sedan.json', ['--publish-rate', '100'], 'realtime sedan, 100 Hz asked');
await measure(1, 'parabola.json', ['--mode', 'fast', '--publish-rate', '10000'], 'fast parabola');
await measure(4, 'parabola.json', ['--mode', 'fast', '--publish-rate', '10000'], '4 fast parabolas');
await f.pass();

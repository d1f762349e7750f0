// A TCP relay between the browser and groundsim-web that holds every chunk
// for `delayMs` in each direction: a round trip of 2 x delayMs added to
// HTTP and the WebSocket alike. This kernel has no netem, and Chromium's
// network emulation does not apply to WebSockets (crbug.com/563644), so the
// delay is the test's own. Chunks keep their order when delayMs changes
// (a chunk never leaves before the one read before it).
import net from 'node:net';

export async function startDelayRelay(targetPort, delayMs) {
  const relay = { delayMs, sockets: new Set() };
  const pipe = (from, to) => {
    let last = 0;
    const at = () => { last = Math.max(Date.now() + relay.delayMs, last); return last - Date.now(); };
    from.on('data', (d) => setTimeout(() => { if (!to.destroyed) to.write(d); }, at()));
    // end, not destroy: a write the kernel has not taken yet (a large
    // file) still goes out before the close
    from.on('end', () => setTimeout(() => to.end(), at()));
    from.on('close', () => setTimeout(() => to.end(), at()));
    from.on('error', () => to.destroy());
  };
  const server = net.createServer((client) => {
    const upstream = net.connect(targetPort, '127.0.0.1');
    client.setNoDelay(true);
    upstream.setNoDelay(true);
    relay.sockets.add(client);
    relay.sockets.add(upstream);
    pipe(client, upstream);
    pipe(upstream, client);
  });
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  relay.url = `http://127.0.0.1:${server.address().port}/`;
  relay.close = () => { for (const s of relay.sockets) s.destroy(); server.close(); };
  return relay;
}

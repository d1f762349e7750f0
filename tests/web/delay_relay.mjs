// A TCP relay between the browser and groundsim-web that holds every chunk
// for `delayMs` in each direction: a round trip of 2 x delayMs added to
// HTTP and the WebSocket alike. This kernel has no netem, and Chromium's
// network emulation does not apply to WebSockets (crbug.com/563644), so the
// delay is the test's own. Chunks keep their order when delayMs changes
// (a chunk never leaves before the one read before it).
import net from 'node:net';

// jitterMs: each chunk held up to that much longer, at random (uniform);
// order is kept, so a late chunk holds back those behind it, as on TCP.
export async function startDelayRelay(targetPort, delayMs, jitterMs = 0) {
  const relay = { delayMs, jitterMs, sockets: new Set() };
  // one queue per direction and one timer at its head: chunks leave in the
  // order they came (timers of different durations may fire out of order)
  const pipe = (from, to) => {
    const queue = [];
    let last = 0, timer = null;
    const pump = () => {
      timer = null;
      while (queue.length && queue[0].due <= Date.now()) {
        const { data } = queue.shift();
        if (data === null) to.end(); else if (!to.destroyed) to.write(data);
      }
      if (queue.length) timer = setTimeout(pump, queue[0].due - Date.now());
    };
    const push = (data) => {
      last = Math.max(Date.now() + relay.delayMs + Math.random() * relay.jitterMs, last);
      queue.push({ due: last, data });
      if (!timer) timer = setTimeout(pump, last - Date.now());
    };
    from.on('data', (d) => push(d));
    // end, not destroy: a write the kernel has not taken yet (a large
    // file) still goes out before the close
    from.on('end', () => push(null));
    from.on('close', () => push(null));
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

// The per-hop breakdown of latency.mjs's trials from the trace the server
// and the bridge wrote (GROUNDSIM_TRACE, server/lcm/latency_trace.hpp) and
// the page's own stamps (performance.now(), moved onto the steady clock by
// `off`). Lines (times in us of the steady clock):
//   ctl SESSION PAGE_SEQ DRIVE_SEQ RX PUB   the bridge got a controls message, published drive_t
//                                           (DRIVE_SEQ -1: not sent, a newer one came within 4 ms)
//   drx SESSION DRIVE_SEQ RECV              the server's LCM thread got a drive_t
//   spub SESSION SEQ PUB DRIVE_RECV DRIVE_APPLIED   a state published, with the last drive applied
//   srx SESSION SEQ T                       the bridge's LCM thread got a state
//   wsend PEER SEQ T                        the bridge started writing that state to a browser
// A trial follows the press: the page's first controls with the handbrake on,
// the drive_t that carried it, the first state published after the session
// applied it, that state through the bridge to the page, and the state that
// showed the press (the detector's threshold may need one more frame).
export const HOPS = [
  ['page: key press -> WebSocket send', (x) => x.sent - x.press],
  ['WebSocket in: page -> bridge', (x) => x.ctlRx - x.sent],
  ['bridge: controls -> drive_t published', (x) => x.drivePub - x.ctlRx],
  ['LCM: bridge -> server', (x) => x.serverRx - x.drivePub],
  ['server: received -> applied by the session', (x) => x.applied - x.serverRx],
  ['server: applied -> state published (frame boundary)', (x) => x.statePub - x.applied],
  ['LCM: server -> bridge', (x) => x.bridgeRx - x.statePub],
  ['bridge: state -> WebSocket write', (x) => x.wsSend - x.bridgeRx],
  ['WebSocket out: bridge -> page', (x) => x.pageRx - x.wsSend],
  ['page: first state after -> state showing it', (x) => x.detect - x.pageRx],
];

function parse(text) {
  const t = { ctl: [], drx: new Map(), spub: [], srx: new Map(), wsend: [] };
  for (const line of text.split('\n')) {
    const f = line.trim().split(/\s+/);
    const n = (i) => Number(f[i]) / 1000;  // us -> ms
    if (f[0] === 'ctl') t.ctl.push({ bseq: Number(f[2]), dseq: Number(f[3]), rx: n(4), pub: n(5) });
    else if (f[0] === 'drx') t.drx.set(Number(f[2]), n(3));
    else if (f[0] === 'spub') t.spub.push({ seq: Number(f[2]), pub: n(3), recv: n(4), applied: n(5) });
    else if (f[0] === 'srx') t.srx.set(Number(f[2]), n(3));
    else if (f[0] === 'wsend') t.wsend.push({ seq: Number(f[2]), t: n(3) });
  }
  return t;
}

// One trial's stamps (ms, system clock), or a reason it cannot be followed.
function follow(t, r, pageRecv, off) {
  if (!r.sent) return { why: 'no controls sent after the press' };
  const ctl = t.ctl.find((c) => c.bseq === r.sent.seq);
  if (!ctl) return { why: `page seq ${r.sent.seq} not in the bridge's trace` };
  const carrier = ctl.dseq >= 0 ? ctl : t.ctl.find((c) => c.bseq > ctl.bseq && c.dseq >= 0);
  if (!carrier) return { why: 'no drive_t after a dropped controls message' };
  const serverRx = t.drx.get(carrier.dseq);
  if (serverRx === undefined) return { why: `drive seq ${carrier.dseq} not received by the server` };
  // the drive's receive stamp is the frame's, to the microsecond
  const pub = t.spub.find((s) => s.recv >= serverRx - 0.0005);
  if (!pub) return { why: 'no state after the drive' };
  const ws = t.wsend.find((w) => w.seq >= pub.seq);
  const rxSeq = [...pageRecv.keys()].filter((s) => s >= pub.seq).sort((a, b) => a - b)[0];
  return {
    dropped: ctl.dseq < 0, press: r.press - off, sent: r.sent.t - off, ctlRx: ctl.rx, drivePub: carrier.pub, serverRx,
    applied: pub.applied, statePub: pub.pub, bridgeRx: t.srx.get(pub.seq), wsSend: ws ? ws.t : NaN,
    pageRx: pageRecv.get(rxSeq) - off, detect: r.at - off, total: r.ms,
    seqs: `page ${r.sent.seq} -> drive ${carrier.dseq} -> state ${pub.seq}, shown by state ${r.seq}`,
  };
}

const fmt = (v) => (Number.isFinite(v) ? v.toFixed(2).padStart(7) : '      -');

export function breakdown(text, results, pageRecv, off) {
  const t = parse(text);
  const xs = [], lost = [];
  for (const r of results) {
    const x = follow(t, r, pageRecv, off);
    if (x.why) lost.push(x.why); else xs.push(x);
  }
  const q = (vals, p) => vals[Math.min(vals.length - 1, Math.floor(p * vals.length))];
  const out = [`per hop over ${xs.length} traced trials (ms: p50 p99 max)` +
    (lost.length ? `; ${lost.length} not followed: ${[...new Set(lost)].join('; ')}` : '')];
  // the first state the session published after applying the press, as it
  // reached the page: what the press costs end to end; the detector's row
  // above adds the states it took to see the handbrake in the wheels' spin
  const reached = ['key press -> first state after it, at the page', (x) => x.pageRx - x.press];
  for (const [name, f] of [...HOPS, reached, ['total: key press -> state showing it', (x) => x.total]]) {
    const v = xs.map(f).filter(Number.isFinite).sort((a, b) => a - b);
    if (v.length) out.push(`  ${name.padEnd(52)} ${fmt(q(v, 0.5))} ${fmt(q(v, 0.99))} ${fmt(v[v.length - 1])}`);
  }
  const dropped = xs.filter((x) => x.dropped).length;
  out.push(`  presses whose controls the bridge did not send (a newer one came within 4 ms): ${dropped} of ${xs.length}`);
  out.push('the slowest trials, hop by hop (ms, in the order above):');
  for (const x of [...xs].sort((a, b) => b.total - a.total).slice(0, 5))
    out.push(`  ${fmt(x.total)} = ${HOPS.map(([, f]) => fmt(f(x)).trim()).join(' + ')}${x.dropped ? '  (superseded)' : ''}  ${x.seqs}`);
  return out.join('\n');
}

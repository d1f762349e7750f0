// The round trip to the bridge, measured by the page, and the notice a
// lagging player sees. A ping ({op: 'ping', t}) goes out every PING_MS; the
// bridge answers with the same t (docs/front-end.md, browser protocol).
// The round trip used for prediction is the median of the last few (one
// slow answer does not move the own car's lead); the notice shows while
// that median is above LAG_RTT_MS, or while no message has come for
// STALL_MS (a stalled link sends no pongs to measure).
import { session } from './session.js';

const PING_MS = 500;
const LAG_RTT_MS = 200;    // a round trip the page no longer hides well (game-notes: < 100 ms good, > 200 ms "very bad")
const STALL_MS = 1500;
const WINDOW = 5;

export class LagMeter {
  constructor(net) {
    this.net = net;
    this.samples = [];
    this.lastHeard = performance.now();
    // what tests read: window.groundsim.net
    this.info = { rtt: null, rttLast: null, lagging: false, pings: 0, pongs: 0 };
    this.el = document.createElement('div');
    this.el.id = 'lag-notice';
    this.el.className = 'hidden';
    Object.assign(this.el.style, {
      position: 'absolute', top: '48px', left: '50%', transform: 'translateX(-50%)', padding: '6px 14px',
      background: 'rgba(160, 30, 20, 0.85)', color: '#fff', font: 'bold 15px sans-serif', borderRadius: '4px',
      zIndex: 20, pointerEvents: 'none',
    });
    document.body.appendChild(this.el);
    setInterval(() => this.ping(), PING_MS);
    setInterval(() => this.show(), 250);
  }
  ping() {
    if (!this.net.open) return;
    this.net.send({ op: 'ping', t: performance.now() });
    this.info.pings++;
  }
  heard() { this.lastHeard = performance.now(); }
  onPong(m) {
    if (typeof m.t !== 'number') return;
    const rtt = performance.now() - m.t;
    this.info.pongs++;
    this.info.rttLast = rtt;
    this.samples.push(rtt);
    if (this.samples.length > WINDOW) this.samples.shift();
    const sorted = [...this.samples].sort((a, b) => a - b);
    this.info.rtt = sorted[Math.floor(sorted.length / 2)];
  }
  // seconds, for prediction's lead (0 until measured)
  rttS() { return (this.info.rtt || 0) / 1000; }
  show() {
    const silent = performance.now() - this.lastHeard;
    const inSession = !!session.id && !session.replay;
    let text = '';
    if (this.net.open && silent > STALL_MS) text = `LAG: nothing from the server for ${(silent / 1000).toFixed(1)} s`;
    else if (this.info.rtt !== null && this.info.rtt > LAG_RTT_MS) text = `LAG: ${Math.round(this.info.rtt)} ms round trip`;
    this.info.lagging = !!text && inSession;
    this.el.textContent = text;
    this.el.classList.toggle('hidden', !this.info.lagging);
  }
}

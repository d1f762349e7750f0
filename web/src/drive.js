// The own car's controls: the input's ramps advanced by the time since the
// last call (whoever calls: the frame loop, the timer, a key event) and sent
// to the bridge when they changed or every SEND_PERIOD_MS, so the server's
// command timeout never fires; also while the tab's animation frames are
// throttled (hidden or headless), and a key press goes out at once, not at
// the next frame (latency).
import { session } from './session.js';

const SEND_PERIOD_MS = 50;

// forward speed (m/s) of a vehicle state along its heading
function forwardSpeed(v) {
  const [w, x, y, z] = v.q;
  const fx = 1 - 2 * (y * y + z * z), fy = 2 * (x * y + w * z), fz = 2 * (x * z - w * y);
  return fx * v.v[0] + fy * v.v[1] + fz * v.v[2];
}

export class Driver {
  // onControls(c): every control update, sent or not (the own car's
  // prediction takes it at once); onAction(name): the input's one-shot
  // actions (camera, reset, pause, figure)
  constructor(input, net, onControls, onAction) {
    this.input = input;
    this.net = net;
    this.onControls = onControls;
    this.onAction = onAction;
    this.lastSend = 0;
    this.lastInput = performance.now();
    this.controlsSent = 0;     // controls messages sent (their seq)
    this.lastControls = null;  // the last controls sent, as JSON
    const own = () => session.lastState && session.lastState.vehicles[session.vehicle];
    setInterval(() => { if (session.role === 'drive' && performance.now() - this.lastSend > SEND_PERIOD_MS) this.drive(own()); }, SEND_PERIOD_MS);
    input.onChange = () => this.drive(own());
  }
  drive(v) {
    const t = performance.now();
    const dt = Math.min(0.1, (t - this.lastInput) / 1000);
    this.lastInput = t;
    for (const a of this.input.takeActions()) this.onAction(a);
    if (!session.driving) return;
    const c = this.input.update(dt, v ? forwardSpeed(v) : 0);
    this.onControls(c);
    const key = JSON.stringify(c), now = performance.now();
    if (key !== this.lastControls || now - this.lastSend > SEND_PERIOD_MS) {
      this.net.send({ op: 'controls', ...c, seq: this.controlsSent++ });
      this.lastControls = key;
      this.lastSend = now;
    }
  }
}

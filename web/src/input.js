// Keys (press and release) and the Gamepad API -> normalized controls.
// Throttle, brake and steering ramp while a key is held and return when it
// is released; an analog gamepad sets them directly. The gear is automatic:
// holding brake at a standstill engages reverse, throttle engages drive.
const KICK = 0.3, RISE = 2.0, FALL = 4.0, STEER_RISE = 2.5, STEER_BACK = 4.0, DEADZONE = 0.08;

function approach(x, target, rate, dt) {
  return x < target ? Math.min(target, x + rate * dt) : Math.max(target, x - rate * dt);
}

export class Input {
  constructor(target = window) {
    this.down = new Set();
    this.c = { throttle: 0, brake: 0, steer: 0, handbrake: false, gear: 1 };
    this.pads = () => (navigator.getGamepads ? navigator.getGamepads() : []);
    this.actions = [];
    this.onChange = null;  // called at every key press and release
    target.addEventListener('keydown', (e) => {
      if (e.target && e.target.tagName === 'INPUT') return;
      const k = e.key.toLowerCase();
      if (!e.repeat) {
        if (k === 'r') this.actions.push('reset');
        if (k === 'p') this.actions.push('pause');
        if (k === 'c') this.actions.push('camera');
        if (k === 'f') this.actions.push('figure');
      }
      const fresh = !this.down.has(k);
      this.down.add(k);
      if ([' ', 'arrowup', 'arrowdown', 'arrowleft', 'arrowright'].includes(k)) e.preventDefault();
      if (fresh && this.onChange) this.onChange();
    });
    target.addEventListener('keyup', (e) => {
      this.down.delete(e.key.toLowerCase());
      if (this.onChange) this.onChange();
    });
    target.addEventListener('blur', () => this.down.clear());
  }
  held(...keys) { return keys.some((k) => this.down.has(k)); }
  // Advances the ramps by dt seconds; speed (m/s, signed along the car) picks the gear.
  update(dt, forwardSpeed) {
    const c = this.c;
    let up = this.held('w', 'arrowup'), back = this.held('s', 'arrowdown');
    let steerT = (this.held('a', 'arrowleft') ? 1 : 0) - (this.held('d', 'arrowright') ? 1 : 0);
    const pad = [...this.pads()].find((p) => p && p.connected);
    let analog = null;
    if (pad) {
      const rt = pad.buttons[7] ? pad.buttons[7].value : 0, lt = pad.buttons[6] ? pad.buttons[6].value : 0;
      const sx = pad.axes[0] || 0;
      if (rt > DEADZONE || lt > DEADZONE || Math.abs(sx) > DEADZONE)
        analog = { go: rt, stop: lt, steer: Math.abs(sx) > DEADZONE ? -sx : 0, hand: !!(pad.buttons[0] && pad.buttons[0].pressed) };
    }
    // what the driver asks for: "go" along the gear, "stop"
    let go, stop;
    if (analog) {
      go = analog.go; stop = analog.stop;
      c.steer = analog.steer;
      c.handbrake = analog.hand;
      up = go > DEADZONE; back = stop > DEADZONE;
    } else {
      c.steer = approach(c.steer, steerT, steerT === 0 ? STEER_BACK : STEER_RISE, dt);
      c.handbrake = this.held(' ');
    }
    // automatic gear: at a standstill the pedal held picks the direction
    const still = Math.abs(forwardSpeed) < 0.3;
    if (still && back && !up) c.gear = -1;
    if (still && up && !back) c.gear = 1;
    const accel = c.gear >= 0 ? up : back, decel = c.gear >= 0 ? back : up;
    if (analog) {
      c.throttle = c.gear >= 0 ? go : stop;
      c.brake = c.gear >= 0 ? stop : go;
    } else {
      // a press acts at once (from KICK), then ramps to full
      c.throttle = approach(accel ? Math.max(KICK, c.throttle) : c.throttle, accel ? 1 : 0, accel ? RISE : FALL, dt);
      c.brake = approach(decel ? Math.max(KICK, c.brake) : c.brake, decel ? 1 : 0, decel ? RISE * 2 : FALL, dt);
    }
    return c;
  }
  takeActions() { const a = this.actions; this.actions = []; return a; }
}

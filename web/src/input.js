// Keys (press and release), the Gamepad API (gamepads and wheels, remapped
// on a screen: RemapScreen, key G) and touch (TouchControls, on a touch
// screen) -> normalized controls. Throttle, brake and steering ramp while a
// key is held and return when it is released; an analog gamepad or a touch
// sets them directly. The gear is automatic: holding brake at a standstill
// engages reverse, throttle engages drive.
const KICK = 0.3, RISE = 2.0, FALL = 4.0, STEER_RISE = 2.5, STEER_BACK = 4.0, DEADZONE = 0.08;
// keyboard steering eased with speed: the rate towards a lock falls as
// 1 / (1 + |v| / EASE_SPEED) (half at 12 m/s, a third at 24 m/s), so a tap
// at speed is a small correction, not a swerve; returning to the centre and
// counter-steering keep the full rate (a speed-coupled rate that also slows
// counter-steer traps a car in a spin: RoR#3117)
const EASE_SPEED = 12.0;

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
    this.mapping = loadMapping();
    this.touch = null;     // TouchControls on a touch screen (touch())
    target.addEventListener('keydown', (e) => {
      if (e.target && e.target.tagName === 'INPUT') return;
      const k = e.key.toLowerCase();
      if (!e.repeat) {
        if (k === 'r') this.actions.push('reset');
        if (k === 'p') this.actions.push('pause');
        if (k === 'c') this.actions.push('camera');
        if (k === 'f') this.actions.push('figure');
        if (k === 'backspace' || k === 't') this.actions.push('respawn');  // a race's: back to the last gate
        if (k === 'g') this.actions.push('remap');  // the gamepad / wheel remap screen
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
      const m = this.mapping;
      const rt = readControl(pad, m.throttle), lt = readControl(pad, m.brake);
      const sx = readControl(pad, m.steer), hand = readControl(pad, m.handbrake) > 0.5;
      if (rt > DEADZONE || lt > DEADZONE || Math.abs(sx) > DEADZONE || hand)
        analog = { go: rt, stop: lt, steer: Math.abs(sx) > DEADZONE ? -sx : 0, hand };
    }
    // touch controls (a phone): they act like a pad while touched
    if (!analog && this.touch && this.touch.active()) analog = this.touch.read();
    // what the driver asks for: "go" along the gear, "stop"
    let go, stop;
    if (analog) {
      go = analog.go; stop = analog.stop;
      c.steer = analog.steer;
      c.handbrake = analog.hand;
      up = go > DEADZONE; back = stop > DEADZONE;
    } else {
      const away = steerT !== 0 && (c.steer === 0 || Math.sign(steerT) === Math.sign(c.steer));
      const rate = away ? STEER_RISE / (1 + Math.abs(forwardSpeed) / EASE_SPEED) : STEER_BACK;
      c.steer = approach(c.steer, steerT, rate, dt);
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
  // Touch controls on a touch screen (a phone): shown while a session is driven.
  touchControls(parent = document.body) {
    if (!this.touch) this.touch = new TouchControls(parent, (a) => this.actions.push(a));
    return this.touch;
  }
}

// ---- gamepads and wheels: a mapping per control, remapped on a screen ----------------
// A control is a button (value 0..1) or an axis (raw -1..1) with its resting
// and full values, as the remap screen saw them: pedals of wheels rest at 1.0
// and go to -1.0 on some axis, a stick steers on axes[0]. The standard
// mapping's defaults: right trigger throttle, left trigger brake, left stick
// steering, A handbrake.
const MAP_KEY = 'groundsim.padmap';
export const DEFAULT_MAPPING = {
  throttle: { button: 7 }, brake: { button: 6 },
  steer: { axis: 0, rest: 0, full: 1, centred: true },  // full: the value at full right lock
  handbrake: { button: 0 },
};
function loadMapping() {
  try {
    const m = JSON.parse(localStorage.getItem(MAP_KEY) || 'null');
    if (m && typeof m === 'object') return { ...DEFAULT_MAPPING, ...m };
  } catch { /* none stored */ }
  return { ...DEFAULT_MAPPING };
}
// A control's value: 0..1 (steer: -1..1, + = right)
export function readControl(pad, c) {
  if (!c) return 0;
  if (Number.isInteger(c.button)) return pad.buttons[c.button] ? pad.buttons[c.button].value : 0;
  if (!Number.isInteger(c.axis)) return 0;
  const raw = pad.axes[c.axis] || 0, span = c.full - c.rest;
  if (Math.abs(span) < 0.1) return 0;
  const v = (raw - c.rest) / span;
  return c.centred ? Math.max(-1, Math.min(1, v)) : Math.max(0, Math.min(1, v));
}

// The remap screen: for each control, "set" waits for the control to be
// moved (a button pressed, or an axis moved by more than half its range from
// where it rested when "set" was clicked) and keeps it.
export class RemapScreen {
  constructor(input, parent = document.body) {
    this.input = input;
    const el = document.createElement('div');
    el.id = 'remap';
    el.className = 'panel hidden';
    el.style.cssText = 'top:50%;left:50%;transform:translate(-50%,-50%);min-width:320px;z-index:5';
    parent.appendChild(el);
    this.el = el;
    this.waiting = null;
    this.render();
  }
  toggle(on = this.el.classList.contains('hidden')) { this.el.classList.toggle('hidden', !on); this.render(); }
  render() {
    const m = this.input.mapping;
    const name = (c) => (!c ? '-' : Number.isInteger(c.button) ? `button ${c.button}` : `axis ${c.axis} (${c.rest.toFixed(1)} -> ${c.full.toFixed(1)})`);
    const pad = [...this.input.pads()].find((p) => p && p.connected);
    this.el.innerHTML = `<h2 style="margin:0 0 6px;font-size:16px">gamepad / wheel controls</h2>
      <div style="font-size:12px;color:#bbb">${pad ? pad.id.replace(/</g, '&lt;') : 'no gamepad: connect one and press a button'}</div>
      <table>${['throttle', 'brake', 'steer', 'handbrake'].map((k) => `<tr><td>${k}</td><td>${name(m[k])}</td>
        <td><button data-k="${k}">${this.waiting && this.waiting.k === k ? (k === 'steer' ? 'turn right...' : 'press...') : 'set'}</button></td></tr>`).join('')}</table>
      <button data-reset="1">defaults</button> <button data-close="1">close</button>`;
    this.el.querySelectorAll('button[data-k]').forEach((b) => b.addEventListener('click', () => this.wait(b.dataset.k)));
    this.el.querySelector('button[data-reset]').addEventListener('click', () => { this.input.mapping = { ...DEFAULT_MAPPING }; this.save(); });
    this.el.querySelector('button[data-close]').addEventListener('click', () => this.toggle(false));
  }
  wait(k) {
    const pad = [...this.input.pads()].find((p) => p && p.connected);
    if (!pad) return;
    this.waiting = { k, axes: [...pad.axes], buttons: pad.buttons.map((b) => b.value) };
    this.render();
    const poll = () => {
      if (!this.waiting || this.waiting.k !== k) return;
      const p = [...this.input.pads()].find((q) => q && q.connected);
      const w = this.waiting;
      if (p) {
        const bi = p.buttons.findIndex((b, i) => b.value > 0.5 && (w.buttons[i] || 0) < 0.5);
        const ai = p.axes.findIndex((a, i) => Math.abs(a - (w.axes[i] || 0)) > 0.5);
        if (k !== 'steer' && bi >= 0) return this.keep(k, { button: bi });
        if (ai >= 0) {
          const rest = w.axes[ai];
          // steering: a stick rests at 0 and is centred; a pedal axis rests at one end
          const c = k === 'steer' ? { axis: ai, rest: Math.abs(rest) < 0.3 ? 0 : rest, full: Math.sign(p.axes[ai] - rest), centred: true }
                                  : { axis: ai, rest, full: Math.sign(p.axes[ai] - rest) * 2 + rest };
          if (k !== 'steer') c.full = Math.max(-1, Math.min(1, c.full));
          return this.keep(k, c);
        }
      }
      requestAnimationFrame(poll);
    };
    requestAnimationFrame(poll);
  }
  keep(k, c) {
    this.input.mapping = { ...this.input.mapping, [k]: c };
    this.waiting = null;
    this.save();
  }
  save() {
    try { localStorage.setItem(MAP_KEY, JSON.stringify(this.input.mapping)); } catch { /* memory only */ }
    this.render();
  }
}

// ---- touch: a steering pad at the left, pedals and respawn at the right -------------
// Each touch is followed by its identifier, so steering and a pedal work
// at once (two thumbs).
export class TouchControls {
  constructor(parent, onAction) {
    const el = document.createElement('div');
    el.id = 'touch';
    el.style.cssText = 'position:absolute;inset:auto 0 0 0;height:42%;display:none;touch-action:none;user-select:none;z-index:4';
    const zone = (css, text) => {
      const z = document.createElement('div');
      z.style.cssText = `position:absolute;bottom:12px;border-radius:14px;background:rgba(255,255,255,0.12);color:#eee;
        display:flex;align-items:center;justify-content:center;font:600 15px system-ui;${css}`;
      z.textContent = text;
      el.appendChild(z);
      return z;
    };
    this.pad = zone('left:12px;width:44%;height:70%', '◀ steer ▶');
    this.gas = zone('right:12px;width:22%;height:70%', 'GO');
    this.brake = zone('right:calc(24% + 18px);width:18%;height:70%', 'BRAKE');
    this.respawn = zone('right:12px;bottom:calc(70% + 24px);width:22%;height:22%', 'respawn');
    parent.appendChild(el);
    this.el = el;
    this.touches = new Map();  // identifier -> {zone, x0, x}
    const on = (e) => {
      e.preventDefault();
      for (const t of e.changedTouches) {
        const zoneOf = [this.pad, this.gas, this.brake, this.respawn].find((z) => {
          const r = z.getBoundingClientRect();
          return t.clientX >= r.left && t.clientX <= r.right && t.clientY >= r.top && t.clientY <= r.bottom;
        });
        if (e.type === 'touchstart' && zoneOf) {
          if (zoneOf === this.respawn) onAction('respawn');
          else this.touches.set(t.identifier, { zone: zoneOf, x0: t.clientX, x: t.clientX });
        } else if (e.type === 'touchmove' && this.touches.has(t.identifier)) this.touches.get(t.identifier).x = t.clientX;
        else if (e.type === 'touchend' || e.type === 'touchcancel') this.touches.delete(t.identifier);
      }
    };
    for (const type of ['touchstart', 'touchmove', 'touchend', 'touchcancel']) el.addEventListener(type, on, { passive: false });
  }
  show(on) { this.el.style.display = on ? '' : 'none'; }
  active() { return this.el.style.display !== 'none' && this.touches.size > 0; }
  // steer: the steering touch's offset from where it began, full lock at a quarter of the pad's width
  read() {
    let go = 0, stop = 0, steer = 0;
    const w = Math.max(40, this.pad.getBoundingClientRect().width / 4);
    for (const t of this.touches.values()) {
      if (t.zone === this.gas) go = 1;
      else if (t.zone === this.brake) stop = 1;
      else if (t.zone === this.pad) steer = -Math.max(-1, Math.min(1, (t.x - t.x0) / w));
    }
    return { go, stop, steer, hand: false };
  }
}

// Smooth motion between states: states arrive at the session's publish
// rate, frames are drawn at the display's rate. A playback clock runs at the
// measured real-time factor a little behind the newest state and each frame
// interpolates the two states around it (positions linearly, orientations
// by slerp), or carries the newest on for a bounded time when the next is
// late (extrapolateVehicle). No three.js here: the module is plain data.

export function slerp(a, b, u) {  // quaternions [w, x, y, z]
  let dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  let bb = b;
  if (dot < 0) { dot = -dot; bb = b.map((x) => -x); }
  if (dot > 0.9995) {
    const q = a.map((x, i) => x + (bb[i] - x) * u);
    const n = Math.hypot(...q);
    return q.map((x) => x / n);
  }
  const th = Math.acos(dot), s = Math.sin(th);
  const wa = Math.sin((1 - u) * th) / s, wb = Math.sin(u * th) / s;
  return a.map((x, i) => wa * x + wb * bb[i]);
}

const lerp = (a, b, u) => a.map((x, i) => x + (b[i] - x) * u);

// When the playback clock runs past the newest state (a state late on the
// network), cars go on along their velocities for at most this long rather
// than stopping and jumping when it comes; BeamMP predicts up to 0.3 s.
export const MAX_EXTRAPOLATION_S = 0.2;

// A vehicle state carried on by h seconds: position along v, orientation
// turned by the angular velocity w (world) over h.
export function extrapolateVehicle(a, h) {
  if (!(h > 0)) return a;
  const [wx, wy, wz] = a.w, ang = Math.hypot(wx, wy, wz) * h;
  let q = a.q;
  if (ang > 1e-12) {
    const k = Math.sin(ang / 2) / (ang / h), d = [Math.cos(ang / 2), wx * k, wy * k, wz * k];
    q = [d[0] * q[0] - d[1] * q[1] - d[2] * q[2] - d[3] * q[3],
      d[0] * q[1] + d[1] * q[0] + d[2] * q[3] - d[3] * q[2],
      d[0] * q[2] - d[1] * q[3] + d[2] * q[0] + d[3] * q[1],
      d[0] * q[3] + d[1] * q[2] - d[2] * q[1] + d[3] * q[0]];
  }
  return { ...a, p: a.p.map((x, i) => x + a.v[i] * h), q };
}

export function interpolateVehicle(a, b, u) {
  if (!b || a === b) return a;
  return {
    ...a,
    p: lerp(a.p, b.p, u), q: slerp(a.q, b.q, u), v: lerp(a.v, b.v, u), w: lerp(a.w, b.w, u),
    speed: a.speed + (b.speed - a.speed) * u,
    spin: lerp(a.spin, b.spin, u), N: lerp(a.N, b.N, u),
  };
}

// Objects with mass (contact states), matched by name.
export function interpolateObjects(a, b, u) {
  if (!a || !b || a === b) return b || a || null;
  const before = new Map(a.map((o) => [o.name, o]));
  return b.map((ob) => {
    const oa = before.get(ob.name);
    return oa ? { ...ob, p: lerp(oa.p, ob.p, u), q: slerp(oa.q, ob.q, u) } : ob;
  });
}

export class Playback {
  constructor() { this.reset(); }
  reset() {
    this.states = [];       // ascending t
    this.clock = null;      // sim time being shown
    this.rate = 1;          // measured real-time factor
    this.interval = 0.02;   // measured s of sim time between states
    this.rateWindow = [];   // [wall s, sim t]
    this.contacts = new Map();  // seq -> objects of a contact state whose state has not come yet
    this.extrapolated = 0;      // s past the newest state the last frame drew (0: interpolated)
  }
  // A contact state (objects with mass) joins the state of the same seq,
  // whichever of the two arrives first.
  pushContact(m) {
    const s = this.states.find((x) => x.seq === m.seq);
    if (s) { s.objects = m.objects; return; }
    this.contacts.set(m.seq, m.objects);
    if (this.contacts.size > 16) this.contacts.delete(this.contacts.keys().next().value);
  }
  push(state, wallS) {
    if (this.contacts.has(state.seq)) {
      state.objects = this.contacts.get(state.seq);
      this.contacts.delete(state.seq);
    }
    const last = this.states[this.states.length - 1];
    if (last && state.t < last.t - 1e-9) this.states = [];  // reset or a replay restarted
    if (last && Math.abs(state.t - last.t) < 1e-12) { this.states[this.states.length - 1] = state; return; }
    if (last) this.interval = 0.9 * this.interval + 0.1 * Math.max(1e-4, state.t - last.t);
    this.states.push(state);
    if (this.states.length > 64) this.states.shift();
    // the bridge's arrival stamp when there is one: this page's own clock
    // stalls while a slow (software) renderer draws
    if (typeof state.wall === 'number') wallS = state.wall;
    this.rateWindow.push([wallS, state.t]);
    while (this.rateWindow.length > 2 && wallS - this.rateWindow[0][0] > 2.0) this.rateWindow.shift();
    const [w0, t0] = this.rateWindow[0];
    if (wallS - w0 > 0.25) this.rate = (state.t - t0) / (wallS - w0);
  }
  newest() { return this.states[this.states.length - 1] || null; }
  // The state to draw after dtWall seconds of wall time.
  frame(dtWall) {
    const n = this.states.length;
    if (!n) return null;
    const newest = this.states[n - 1];
    const target = newest.t - 1.5 * this.interval;
    if (this.clock === null || Math.abs(this.clock - target) > Math.max(0.5, 5 * this.interval)) this.clock = target;
    else this.clock += dtWall * Math.max(0, this.rate) + (target - this.clock) * 0.05;
    if (newest.status !== 1) this.clock = Math.min(this.clock, newest.t);  // paused or over: hold
    let i = n - 1;
    while (i > 0 && this.states[i - 1].t > this.clock) --i;
    const b = this.states[i], a = i > 0 ? this.states[i - 1] : b;
    const u = b.t > a.t ? Math.min(1, Math.max(0, (this.clock - a.t) / (b.t - a.t))) : 1;
    const ahead = Math.min(MAX_EXTRAPOLATION_S, this.clock - newest.t);
    if (b === newest && ahead > 0 && newest.status === 1) {
      this.extrapolated = ahead;
      return { ...b, t: this.clock, vehicles: b.vehicles.map((v) => extrapolateVehicle(v, ahead)), objects: b.objects || null };
    }
    this.extrapolated = 0;
    return {
      ...b,
      t: a.t + (b.t - a.t) * u,
      vehicles: b.vehicles.map((vb, k) => interpolateVehicle(a.vehicles[k] || vb, vb, u)),
      objects: interpolateObjects(a.objects, b.objects, u),  // null: none known for these two
    };
  }
}

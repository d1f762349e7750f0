// Replays in the browser: a recorded session the bridge serves
// (GET /recordings/NAME/states, docs/logging.md) played back on a timeline:
// play, pause, speed, scrub, jump; the page's free camera meanwhile.
// States are fetched in windows of CHUNK s of simulation time around the
// playhead (the next one ahead of time), at most KEEP windows kept; a
// frame interpolates the two states around the playhead as a live session's
// frames do (interp.js), the objects with mass (cones, barriers) too.
import { interpolateObjects, interpolateVehicle } from './interp.js';

const KEEP = 12;
const PEEK = 0.25;  // s each side of a seek's instant fetched first

// a recorder's state message (server/protocol/message_json.cpp) as the
// bridge's live "state" message
export function fromRecorded(m, session) {
  return {
    op: 'state', session, seq: m.seq, t: m.t, status: m.status, health: m.health, reason: m.status_reason,
    vehicles: (m.vehicles || []).map((v) => ({
      name: v.name, p: v.position, q: v.orientation, v: v.velocity, w: v.angular_velocity, speed: v.speed,
      spin: v.wheel_spin || [], N: v.normal_force || [], F: v.friction_force || [], slip: v.slip || [],
      contact: v.in_contact || [],
    })),
  };
}

// forward speed along the body's x, horizontally
function forward(v) {
  const [w, x, y, z] = v.q;
  const fx = 1 - 2 * (y * y + z * z), fy = 2 * (x * y + w * z), n = Math.hypot(fx, fy) || 1;
  return (fx * v.v[0] + fy * v.v[1]) / n;
}

export class Replay {
  constructor(name, session, fetchFn = (u) => fetch(u)) {
    this.name = name;
    this.session = session;
    this.fetch = fetchFn;
    this.t0 = 0; this.t1 = 0; this.t = 0;
    this.playing = false;
    this.speed = 1;
    this.chunk = 8;            // s per window; halved when a window comes back cut (a fast publish rate)
    this.windows = new Map();  // index -> {states, promise}
    this.requests = 0;         // windows fetched, for tests
    this.shown = null;         // the state drawn last
    this.error = null;
  }
  url(from, to) {
    return `${this.base()}/states?${this.q()}&from=${from.toFixed(6)}&to=${to.toFixed(6)}&max=5000&contacts=1`;
  }
  // reads the recording's span and its first window
  async open() {
    const r = await this.fetch(`/recordings/${encodeURIComponent(this.name)}`);
    const f = await r.json();
    if (!r.ok) throw new Error(f.error || `HTTP ${r.status}`);
    const s = (f.sessions || []).find((x) => x.id === this.session);
    if (!s) throw new Error(`session ${this.session} is not in ${this.name}`);
    this.t0 = s.t0; this.t1 = s.t1; this.t = s.t0;
    // the first frame from a peek (a few states); its window behind it
    const first = this.peek(this.t);
    this.load(this.index(this.t));
    await first;
    if (!(this.quick && this.quick.states && this.quick.states.length)) await this.load(this.index(this.t));
    this.loaded = !this.error;
    if (this.error) throw new Error(this.error);
    return this;
  }
  base() { return `/recordings/${encodeURIComponent(this.name)}`; }
  q() { return `session=${encodeURIComponent(this.session)}`; }
  // The session's scene (GET .../scene: the layout a live "joined" carries),
  // or null with sceneError saying why (a file without the scenario).
  async scene() {
    try {
      const r = await this.fetch(`${this.base()}/scene?${this.q()}`);
      const body = await r.json();
      if (!r.ok) throw new Error(body.error || `HTTP ${r.status}`);
      return body.layout;
    } catch (e) {
      this.sceneError = String(e.message || e);
      return null;
    }
  }
  // The ground around (x, y) as a live "ground" message, or null.
  async ground(x, y) {
    try {
      const r = await this.fetch(`${this.base()}/ground?${this.q()}&cx=${x.toFixed(3)}&cy=${y.toFixed(3)}`);
      return r.ok ? await r.json() : null;
    } catch {
      return null;
    }
  }
  // The laps the server timed (its race events), each with its start time
  // (the lap event's t less its lap_time), in time order; [] without a race.
  async laps() {
    try {
      const r = await this.fetch(`${this.base()}/events?${this.q()}`);
      if (!r.ok) return [];
      const body = await r.json();
      const out = [];
      for (const m of body.events || []) {
        if (typeof m.reason !== 'string' || !m.reason.startsWith('race: ')) continue;
        let e;
        try { e = JSON.parse(m.reason.slice(6)); } catch { continue; }
        if (e.type === 'lap' && Number.isFinite(e.t) && Number.isFinite(e.lap_time))
          out.push({ car: e.car | 0, lap: e.lap, lap_time: e.lap_time, best: !!e.best, start: e.t - e.lap_time, end: e.t });
      }
      this.lapList = out.sort((a, b) => a.start - b.start);
      return this.lapList;
    } catch {
      return [];
    }
  }
  index(t) { return Math.floor((t - this.t0) / this.chunk); }
  load(k) {
    const have = this.windows.get(k);
    if (have) return have.promise;
    const from = this.t0 + k * this.chunk, to = Math.min(this.t1, from + this.chunk);
    const w = { states: null };
    w.promise = (async () => {
      this.requests++;
      const r = await this.fetch(this.url(from, to));
      const body = await r.json();
      if (!r.ok) throw new Error(body.error || `HTTP ${r.status}`);
      if (body.more && this.chunk > 0.25) {  // cut: smaller windows from now on
        this.chunk /= 2;
        this.windows.clear();
        return this.load(this.index(from));
      }
      w.states = this.decode(body);
      return w.states;
    })().catch((e) => { this.error = String(e.message || e); this.windows.delete(k); });
    this.windows.set(k, w);
    while (this.windows.size > KEEP) this.windows.delete(this.windows.keys().next().value);
    return w.promise;
  }
  // A window's answer as states, each with the objects with mass of its
  // contact state (cones knocked over move in the replay too).
  decode(body) {
    const objects = new Map((body.contacts || []).map((c) => [c.seq, (c.objects || []).map((o) => ({ name: o.name, p: o.position, q: o.orientation }))]));
    return body.states.map((m) => ({ ...fromRecorded(m, this.session), objects: objects.get(m.seq) || null }));
  }
  seek(t) {
    this.t = Math.max(this.t0, Math.min(this.t1, t));
    const k = this.index(this.t), w = this.windows.get(k);
    if (!(w && w.states)) this.peek(this.t);
    this.load(k);
  }
  // A short span around t (PEEK s each side, a few states), drawn while
  // the whole window behind it loads: a seek shows its frame after a small
  // request, not after CHUNK s of states.
  peek(t) {
    const from = Math.max(this.t0, t - PEEK), to = Math.min(this.t1, t + PEEK);
    const p = { from, to, states: null };
    this.quick = p;
    return (async () => {
      const r = await this.fetch(this.url(from, to));
      const body = await r.json();
      if (r.ok && this.quick === p) p.states = this.decode(body);
    })().catch(() => {});
  }
  jump(dt) { this.seek(this.t + dt); }
  toggle() {
    if (!this.playing && this.t >= this.t1) this.t = this.t0;
    this.playing = !this.playing;
  }
  // The state to draw after dtWall s of wall time: the playhead advances at
  // the chosen speed while playing; null until its window has loaded.
  frame(dtWall) {
    if (!this.loaded) return null;  // the span is not known yet: no window to ask for
    if (this.playing) {
      this.t = Math.min(this.t1, this.t + dtWall * this.speed);
      if (this.t >= this.t1) this.playing = false;
    }
    const k = this.index(this.t);
    this.load(k);
    if (this.playing && this.t + 2 > this.t0 + (k + 1) * this.chunk) this.load(k + 1);  // ahead of time
    const w = this.windows.get(k), q = this.quick;
    let states = w && w.states;
    if (states) this.quick = null;
    else if (q && q.states && this.t >= q.from && this.t <= q.to) states = q.states;
    if (!states || !states.length) return this.shown;
    let i = 0;
    while (i + 1 < states.length && states[i + 1].t <= this.t) ++i;
    const a = states[i], b = states[Math.min(i + 1, states.length - 1)];
    const u = b.t > a.t ? Math.min(1, Math.max(0, (this.t - a.t) / (b.t - a.t))) : 0;
    const dt = b.t - a.t;
    this.shown = {
      ...a,
      t: a.t + (b.t - a.t) * u,
      vehicles: a.vehicles.map((va, j) => {
        const vb = b.vehicles[j] || va;
        const v = interpolateVehicle(va, vb, u);
        // braking, for the brake lights: slowing along the heading faster
        // than rolling and air drag would (the recording has no controls here)
        const dv = dt > 0 ? (Math.abs(forward(vb)) - Math.abs(forward(va))) / dt : 0;
        v.braking = dv < -2.5 && Math.abs(forward(va)) > 0.5;
        return v;
      }),
      objects: interpolateObjects(a.objects, b.objects, u),
    };
    return this.shown;
  }
}

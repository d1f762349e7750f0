// Client-side prediction of the own car (docs/game.md, Prediction). The
// server is authoritative and its states reach the page a round trip after
// the keys that shaped them; the page therefore runs the physics core
// itself (WebAssembly: web/wasm, predictor.js + predictor.wasm served by the
// bridge) on the session's scenario, with the player's controls, ahead of
// the newest state by the measured round trip: where the server will be
// when a control sent now arrives. The own car is drawn from that local
// run, so a key moves it on the next frame.
//
// Reconciliation: each server state (time t) goes to gs_reconcile, which
// takes the local state saved at t, gives its car the server's chassis
// (state_t does not carry the whole core state: the rest stays local) and
// replays the steps since t with their recorded controls. What that changes
// in the present is not shown at once: the difference becomes an offset of
// the drawn car that decays with SMOOTH_S, unless it is larger than
// BeamMP's teleport threshold (1 m + 0.5 m per m/s), where it is snapped.
const SMOOTH_S = 0.1;      // time constant of a correction's fade on screen
const MAX_LEAD_S = 0.5;    // never predict further ahead of the newest state
const MAX_STEP_S = 0.5;    // sim time one frame may step (a stalled tab catches up over frames)
const MAX_STEPS = 20000;   // steps one call may take (the report's car: 1 s at 50 us)
const REPLAY_SHARE = 0.25; // at most this share of wall time spent replaying

let modulePromise = null;
// The Emscripten module, loaded once as a classic script (MODULARIZE):
// null when the bridge serves no predictor (built without emcc).
function loadModule() {
  if (!modulePromise) {
    modulePromise = new Promise((resolve) => {
      const s = document.createElement('script');
      s.src = '/predictor.js';
      s.onload = () => window.GroundsimPredictor({ locateFile: (f) => `/${f}` }).then(resolve, () => resolve(null));
      s.onerror = () => resolve(null);
      document.head.appendChild(s);
    });
  }
  return modulePromise;
}

const qmul = (a, b) => [
  a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
  a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
  a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
  a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]];
const qconj = (q) => [q[0], -q[1], -q[2], -q[3]];
// the rotation q scaled to the fraction u of its angle (u in [0, 1])
function qpow(q, u) {
  const w = Math.min(1, Math.abs(q[0])), s = q[0] < 0 ? -1 : 1;
  const th = Math.acos(w), sn = Math.sin(th);
  if (sn < 1e-9) return [1, 0, 0, 0];
  const k = Math.sin(u * th) / sn;
  return [Math.cos(u * th), s * q[1] * k, s * q[2] * k, s * q[3] * k];
}

export class Prediction {
  constructor() {
    this.enabled = new URLSearchParams(location.search).get('predict') !== '0';
    this.m = null;
    this.clear();
    // what tests read: window.groundsim.prediction
    this.info = { active: false, reason: '', lead: 0, error: 0, replayed: 0, corrections: 0, snaps: 0, drawn: null, t: 0 };
  }
  clear() {
    this.active = false;
    this.vehicle = -1;
    this.newest = null;     // { t, arrival (ms), status }
    this.clock = null;      // the sim time the local run is driven to
    this.off = [0, 0, 0];   // drawn minus predicted position, fading
    this.qoff = [1, 0, 0, 0];
    this.lastReplay = 0;    // ms: when, and how long the last replay took
    this.replayMs = 0;
    this.session = null;
    this.doc = null;
    this.gridGround = false;
  }
  // A driver joined `session` as `vehicle` with the scenario's text (the
  // bridge's `joined`); spectators predict nothing.
  async start(session, vehicle, scenarioText, scale) {
    this.clear();
    this.scale = scale || null;  // the bridge's mapping of controls to torques (--drive-torque ...)
    Object.assign(this.info, { active: false, reason: '', error: 0, replayed: 0, corrections: 0, snaps: 0, placed: 0,
      restarts: 0, restartReason: '', grids: 0, ground: null, maxLead: 0, drawn: null });
    if (!this.enabled) return this.stop('off (?predict=0)');
    if (!scenarioText || vehicle < 0) return this.stop('no scenario from the bridge');
    this.session = session;
    const m = await loadModule();
    if (this.session !== session) return undefined;  // left meanwhile
    if (!m) return this.stop('no predictor served (built without emscripten)');
    this.m = m;
    let doc;
    try { doc = JSON.parse(scenarioText); } catch { return this.stop('scenario is not JSON'); }
    // corrections move the car by hand: the local run's energy bookkeeping
    // (divergence by energy growth) means nothing here
    doc.physics = doc.physics || {};
    doc.physics.limits = { ...(doc.physics.limits || {}), max_energy_growth: 1e9 };
    this.vehicle = vehicle;
    // a ground this build cannot read (its PNG, its expression: no libpng
    // or muParser in WebAssembly) is replaced by the bridge's grid of it
    // around the car, the one the page draws (onGround)
    const g = doc.ground || {};
    this.doc = doc;
    this.gridGround = g.type === 'expression' || typeof g.file === 'string' ||
      !!(g.friction_map && typeof g.friction_map.file === 'string');
    if (this.gridGround) {
      this.info.reason = 'waiting for the ground grid';
      // a grid that came while the module loaded
      if (this.lastGrid && this.lastGrid.session === session) this.groundIn(this.lastGrid);
      return undefined;
    }
    return this.guard(() => this.create(doc));
  }
  create(doc) {
    const m = this.m;
    if (m.ccall('gs_create', 'number', ['string', 'number'], [JSON.stringify(doc), this.vehicle]) !== 0)
      return this.stop(`scenario not predictable here: ${m.ccall('gs_error', 'string', [], [])}`);
    this.dt = m._gs_dt();
    if (this.scale) m._gs_scale(this.scale.drive_torque, this.scale.brake_torque, this.scale.steer);
    this.poseCount = 64;  // vehicles a scene may hold (the bridge's --max-vehicles at most)
    this.poseBuf = m._malloc(13 * 8 * this.poseCount);
    this.active = true;
    Object.assign(this.info, { active: true, reason: '', dt: this.dt });
    return undefined;
  }
  // From the scenario's start again, placed at the next server state.
  restart(t, why) {
    this.m._gs_reset(t);
    this.newest = null;
    this.info.restarts = (this.info.restarts || 0) + 1;
    this.info.restartReason = why;
    return null;
  }
  // The bridge's grid of the ground around the car ({x0, y0, n, step, z},
  // metres): the local run's ground when the scenario's own cannot be read
  // here. Each new grid (the car moved a quarter of it) rebuilds the scene
  // and the run goes on; beyond its edge a heightfield continues flat.
  // The page's frame loop and message handlers must not stop on an error of
  // the local run (an exception or abort in the module): prediction stops,
  // says why, and the own car is drawn from the server's states again.
  guard(fn) {
    try { return fn(); } catch (e) { this.stop(`stopped: ${(e && e.message) || e}`); return null; }
  }
  onGround(grid) { this.guard(() => this.groundIn(grid)); }
  onState(s, nowMs) { this.guard(() => this.stateIn(s, nowMs)); }
  frame(dtWall, rttS, rate, nowMs) {
    const t0 = performance.now();
    const out = this.guard(() => this.frameOut(dtWall, rttS, rate, nowMs));
    // what prediction costs a frame, and a correction (ms, smoothed)
    if (out) this.info.frameMs = 0.95 * (this.info.frameMs || 0) + 0.05 * (performance.now() - t0);
    return out;
  }
  groundIn(grid) {
    this.lastGrid = grid;
    if (!this.gridGround || !this.m || grid.session !== this.session || !grid.z) return;
    const g = this.doc.ground, n = grid.n, rows = [];
    let fill = grid.z.find((h) => h !== null);
    if (fill === undefined) return;
    for (let i = 0; i < n; ++i) {
      rows.push(grid.z.slice(i * n, (i + 1) * n).map((h) => { if (h !== null) fill = h; return fill; }));
    }
    const ground = { type: 'heightfield', heights: rows, cell_size: grid.step, origin: [grid.x0, grid.y0] };
    if (g.friction_patches) ground.friction_patches = g.friction_patches;
    const doc = { ...this.doc, ground };
    if (!this.active) {
      this.create(doc);
      this.info.ground = this.active ? 'grid' : null;
      return;
    }
    if (this.m.ccall('gs_rebuild', 'number', ['string'], [JSON.stringify(doc)]) !== 0)
      this.stop(`ground grid refused: ${this.m.ccall('gs_error', 'string', [], [])}`);
    else this.info.grids = (this.info.grids || 0) + 1;
  }
  stop(reason) {
    this.active = false;
    this.session = null;
    this.info.active = false;
    this.info.reason = reason;
    return undefined;
  }
  setControls(c) {
    if (!this.active) return;
    this.m._gs_controls(c.throttle, c.brake, c.steer, c.handbrake ? 1 : 0, c.gear);
  }
  pose() {
    const ptr = this.m._gs_pose() / 8, h = this.m.HEAPF64;
    return { p: [h[ptr], h[ptr + 1], h[ptr + 2]], q: [h[ptr + 3], h[ptr + 4], h[ptr + 5], h[ptr + 6]],
      v: [h[ptr + 7], h[ptr + 8], h[ptr + 9]], w: [h[ptr + 10], h[ptr + 11], h[ptr + 12]] };
  }
  // A server state of the session: the own car's chassis corrects the local run.
  stateIn(s, nowMs) {
    if (!this.active || s.session !== this.session) return;
    const v = s.vehicles[this.vehicle];
    if (!v) return;
    const first = !this.newest;
    if (!first && s.t < this.newest.t - 1e-9) {  // reset: back to the scenario's start
      this.restart(s.t, `session reset (t ${this.newest.t.toFixed(3)} -> ${s.t.toFixed(3)})`);
      this.clock = null;
    }
    this.newest = { t: s.t, arrival: nowMs, status: s.status };
    // replays cost (lead / dt) steps each: with a small dt (the report's
    // car, 50 us) not every state is used, at most REPLAY_SHARE of the time
    if (!first && nowMs - this.lastReplay < this.replayMs / REPLAY_SHARE) return;
    // a page whose frames are slow (a busy machine) has not stepped the
    // local run past this state yet: step it there first (controls in force)
    const behind = s.t - this.m._gs_time();
    if (!first && behind > 0.5 * this.dt && behind < 2 * MAX_STEP_S && behind / this.dt < MAX_STEPS &&
        this.m._gs_step(Math.round(behind / this.dt)) !== 0)
      return this.restart(s.t, `local run diverged at t ${this.m._gs_time().toFixed(3)}`);
    const before = this.pose();
    const h = this.m.HEAPF64, b = this.poseBuf / 8, count = Math.min(s.vehicles.length, this.poseCount);
    for (let k = 0; k < count; ++k) {
      const x = s.vehicles[k];
      [...x.p, ...x.q, ...x.v, ...x.w].forEach((y, i) => { h[b + 13 * k + i] = y; });
    }
    const t0 = performance.now();
    const n = this.m._gs_reconcile(s.t, this.poseBuf, count);
    this.replayMs = performance.now() - t0;
    this.info.replayMs = 0.95 * (this.info.replayMs || 0) + 0.05 * this.replayMs;
    if (n === -2) return this.restart(s.t, `replay from t ${s.t.toFixed(3)} diverged`);
    this.lastReplay = nowMs;
    // the prediction's error: the local run at t against the server's state
    // (a placement compares other times: not counted)
    if (n >= 0) this.info.error = this.m._gs_last_error();
    this.info.replayed = n;
    if (n === -1) this.info.placed = (this.info.placed || 0) + 1;  // no saved state at t: placed at the present
    this.info.corrections++;
    const after = this.pose();
    // keep the car where it was drawn, and let the difference fade
    const d = [0, 1, 2].map((i) => this.off[i] + before.p[i] - after.p[i]);
    const speed = Math.hypot(...after.v);
    if (first || Math.hypot(...d) > 1 + 0.5 * speed) {
      this.off = [0, 0, 0];
      this.qoff = [1, 0, 0, 0];
      if (!first) this.info.snaps++;
    } else {
      this.off = d;
      this.qoff = qmul(qmul(this.qoff, before.q), qconj(after.q));
    }
  }
  // Steps the local run to the present of the server plus a round trip and
  // returns the own car's pose to draw (null when not predicting).
  frameOut(dtWall, rttS, rate, nowMs) {
    if (!this.active || !this.newest) return null;
    const n = this.newest;
    const running = n.status === 1;
    rate = running ? Math.max(0, Math.min(4, rate || 1)) : 0;
    const target = Math.min(n.t + MAX_LEAD_S, n.t + ((nowMs - n.arrival) / 1000 + rttS) * rate);
    if (this.clock === null || Math.abs(this.clock - target) > 0.25) this.clock = target;
    else this.clock += dtWall * rate + (target - this.clock) * 0.1;
    this.clock = Math.min(this.clock, n.t + MAX_LEAD_S);
    if (!running) this.clock = Math.min(this.clock, this.m._gs_time());
    const steps = Math.min(Math.floor((this.clock - this.m._gs_time()) / this.dt + 1e-6), Math.ceil(MAX_STEP_S / this.dt), MAX_STEPS);
    if (steps > 0 && this.m._gs_step(steps) !== 0) return this.restart(n.t, `local run diverged at t ${this.m._gs_time().toFixed(3)}`);
    const fade = Math.exp(-dtWall / SMOOTH_S);
    this.off = this.off.map((x) => x * fade);
    this.qoff = qpow(this.qoff, fade);
    const p = this.pose();
    const drawn = { p: p.p.map((x, i) => x + this.off[i]), q: qmul(this.qoff, p.q), v: p.v, w: p.w, t: this.m._gs_time() };
    this.info.lead = drawn.t - n.t;
    this.info.offset = Math.hypot(...this.off);  // m: a correction still fading on screen
    this.info.maxLead = Math.max(this.info.maxLead || 0, this.info.lead);
    this.info.t = drawn.t;
    this.info.drawn = drawn;
    return drawn;
  }
}

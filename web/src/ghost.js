// The lap ghosts (docs/front-end.md, Races), drawn translucent beside the
// car on later laps at the same time into the lap, from the states the
// server published:
//  - Ghost: the own car's best lap, kept per scenario (in memory and in
//    localStorage);
//  - RivalGhost: the session's fastest lap by any other car, a player's or
//    a bot's, with its driver's name (kept for the session).
// A ghost passes through everything: it is drawn, never simulated.
import * as THREE from 'three';
import { session } from './session.js';
import { Vehicle } from './vehicle.js';

const MAX_SAMPLES = 60 * 60 * 10;  // 10 min at 60 Hz: a longer lap keeps no ghost
const STORE = 'groundsim.ghost.';

function slerpQ(a, b, u) {
  const qa = new THREE.Quaternion(a[1], a[2], a[3], a[0]), qb = new THREE.Quaternion(b[1], b[2], b[3], b[0]);
  qa.slerp(qb, u);
  return [qa.w, qa.x, qa.y, qa.z];
}

// A lap's pose tau seconds into it, interpolated between its states
// ({lap_time, samples: [[tau, x, y, z, qw, qx, qy, qz]]}); null outside it.
function poseAt(lap, tau) {
  const s = lap && lap.samples;
  if (!s || s.length < 2 || tau < s[0][0] || tau > s[s.length - 1][0]) return null;
  let lo = 0, hi = s.length - 1;
  while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (s[mid][0] <= tau) lo = mid; else hi = mid; }
  const a = s[lo], b = s[hi], u = b[0] > a[0] ? (tau - a[0]) / (b[0] - a[0]) : 0;
  const p = [0, 1, 2].map((k) => a[1 + k] + u * (b[1 + k] - a[1 + k]));
  return { p, q: slerpQ(a.slice(4, 8), b.slice(4, 8), u) };
}

// A translucent car of `layout`, named `name` ('' : no label).
function buildGhostVehicle(scene, layout, color, name) {
  const v = new Vehicle(scene, layout, color, name);
  v.root.traverse((m) => {
    if (!m.isMesh) return;
    m.material = m.material.clone();
    m.material.transparent = true;
    m.material.opacity = 0.3;
    m.material.depthWrite = false;
    m.castShadow = false;
  });
  v.root.name = 'ghost';
  return v;
}

// A lap being recorded from the published states: {start, samples}.
function tapeStart(t) { return { start: t, samples: [] }; }
function tapePush(tape, t, v, minGap = 0) {
  if (!tape || !v || tape.samples.length >= MAX_SAMPLES || t < tape.start - 0.1) return;
  const n = tape.samples.length;
  if (n && t - tape.start - tape.samples[n - 1][0] < minGap) return;
  tape.samples.push([t - tape.start, ...v.p, ...v.q]);
}

// The states of the last RECENT_S simulated s, each vehicle's position and
// orientation, oldest first. A race event and the states travel apart, so a
// lap's start may reach the page after the states that follow it (under
// load, seen 0.19 s after): its tape takes those from here.
const RECENT_S = 2;
const RECENT_MAX = 1024;  // states kept at most (a session publishing faster than 500 a simulated s)
class RecentStates {
  constructor() { this.states = []; }
  push(m) {
    const last = this.states.length ? this.states[this.states.length - 1].t : null;
    if (last !== null && m.t < last) this.states = [];  // a reset: time went back
    if (m.t === last) return;                           // paused: the same instant again
    if (this.states.length >= RECENT_MAX) this.states.shift();
    this.states.push({ t: m.t, vehicles: (m.vehicles || []).map((v) => v && v.p && v.q && { p: [...v.p], q: [...v.q] }) });
    while (this.states[0].t < m.t - RECENT_S) this.states.shift();
  }
  // car's kept states from the tape's start on into it (none when the start
  // came first, as it does unless events lag: the tape is then as before)
  into(tape, car, minGap = 0) {
    for (const r of this.states) if (r.t >= tape.start) tapePush(tape, r.t, r.vehicles[car], minGap);
  }
  clear() { this.states = []; }
}

// Draws `lap` at tau into it on `holder.vehicle` (built on first need by
// make()); records where in holder.shown ({tau, p}) or hides it.
function drawLap(holder, lap, tau, make) {
  const pose = lap && tau !== null ? poseAt(lap, tau) : null;
  if (!pose) {
    if (holder.vehicle) holder.vehicle.root.visible = false;
    holder.shown = null;
    return;
  }
  if (!holder.vehicle) holder.vehicle = make();
  if (!holder.vehicle) return;
  holder.vehicle.root.visible = true;
  holder.vehicle.update({ p: pose.p, q: pose.q, w: [0, 0, 0], v: [0, 0, 0], speed: 0, spin: [], N: [] }, 0, 0, null, false);
  holder.shown = { tau, p: pose.p };
}

export class Ghost {
  constructor(scene) {
    this.scene = scene;
    this.vehicle = null;
    this.key = null;        // the scenario it belongs to
    this.best = null;       // {lap_time, samples: [[tau, x, y, z, qw, qx, qy, qz]]}
    this.rec = null;        // the lap being recorded: {start, samples}
    this.cut = null;        // a finished lap waiting for its last state: {t, lap_time, best}
    this.playStart = null;  // simulated time the lap being driven started (ghost time 0)
    this.shown = null;      // where the ghost was last drawn: {tau, p}
    this.recent = new RecentStates();  // for a lap whose start arrives after its first states
  }

  // The scenario the session runs (ghosts are kept per scenario).
  use(key, layout) {
    this.key = key;
    this.layout = layout;
    this.best = null;
    try {
      const s = localStorage.getItem(STORE + key);
      if (s) this.best = JSON.parse(s);
    } catch { this.best = null; }
    this.rec = null; this.cut = null; this.playStart = null;
    this.recent.clear();
  }

  // the own car's lap started at t (simulated): record it, and race the ghost from it
  lapStarted(t) {
    this.rec = tapeStart(t);
    this.recent.into(this.rec, session.followed);
    this.playStart = t;
  }
  // the own car completed a lap at e.t: keep it when it is the best (once
  // the states up to e.t are in: events come before the frame that follows)
  lapDone(e) {
    if (e.best && this.rec) this.cut = { t: e.t, lap_time: e.lap_time, rec: this.rec };
  }

  // every state received (raw, not interpolated)
  onState(m) {
    this.recent.push(m);
    const v = m.vehicles[session.followed];
    if (!v) return;
    tapePush(this.rec, m.t, v);
    if (!this.cut) return;
    if (this.cut.rec !== this.rec) tapePush(this.cut.rec, m.t, v);
    if (m.t >= this.cut.t) {
      this.best = { lap_time: this.cut.lap_time, samples: this.cut.rec.samples };
      try { localStorage.setItem(STORE + this.key, JSON.stringify(this.best)); } catch { /* full: memory only */ }
      this.cut = null;
    }
  }

  // The ghost's pose tau seconds into its lap.
  pose(tau) { return poseAt(this.best, tau); }

  // per drawn state
  frame(s) {
    drawLap(this, this.best, this.playStart === null ? null : s.t - this.playStart,
            () => (this.layout ? buildGhostVehicle(this.scene, this.layout, 0x9fd8ff, '') : null));
  }

  clear() {
    if (this.vehicle) this.vehicle.dispose(this.scene);
    this.vehicle = null;
    this.recent.clear();
    this.rec = null; this.cut = null; this.playStart = null; this.shown = null;
  }
}

// The session's fastest lap by another car than the one followed (a
// player's or a bot's): every other car's current lap is recorded (at most
// RIVAL_RATE samples a second, for at most MAX_RIVALS cars), and a lap
// event faster than the kept one replaces it once its states are in. It is
// drawn in amber with its driver's name, at the own lap's time into it,
// and kept through the session's resets.
const RIVAL_RATE = 30;   // samples a second
const MAX_RIVALS = 16;   // cars recorded at once

export class RivalGhost {
  constructor(scene) {
    this.scene = scene;
    this.vehicle = null;
    this.key = null;        // the session
    this.layouts = [];      // the session's vehicles' layouts, by car
    this.best = null;       // {car, name, lap_time, samples}
    this.tapes = new Map(); // car -> its current lap being recorded
    this.recent = new RecentStates();  // for a lap whose start arrives after its first states
    this.cut = null;        // the faster lap waiting for its last state: {car, name, t, lap_time, tape}
    this.playStart = null;  // the own lap's start (simulated s)
    this.shown = null;
  }

  // The race of session `key` with its cars' layouts: the lap kept stays
  // through a reset of the same session, never into another.
  use(key, layouts) {
    this.clear();
    this.layouts = layouts || [];
    if (key !== this.key) this.best = null;
    this.key = key;
  }
  ownLapStarted(t) { this.playStart = t; }
  // car's lap started at t (its start, or the lap after the one it completed)
  lapStarted(car, t) {
    if (car === session.followed) return;
    if (!this.tapes.has(car) && this.tapes.size >= MAX_RIVALS) return;
    const tape = tapeStart(t);
    this.recent.into(tape, car, 1 / RIVAL_RATE);
    this.tapes.set(car, tape);
  }
  // another car completed a lap: kept when it is the session's fastest by another car
  lapDone(e) {
    if (e.car === session.followed) return;
    const tape = this.tapes.get(e.car);
    const bar = Math.min(this.best ? this.best.lap_time : Infinity, this.cut ? this.cut.lap_time : Infinity);
    if (tape && e.lap_time > 0 && e.lap_time < bar)
      this.cut = { car: e.car, name: String(e.name || `car ${e.car}`), t: e.t, lap_time: e.lap_time, tape };
  }

  // every state received (raw, not interpolated)
  onState(m) {
    this.recent.push(m);
    for (const [car, tape] of this.tapes) if (car !== session.followed) tapePush(tape, m.t, m.vehicles[car], 1 / RIVAL_RATE);
    const c = this.cut;
    if (!c) return;
    if (this.tapes.get(c.car) !== c.tape) tapePush(c.tape, m.t, m.vehicles[c.car], 1 / RIVAL_RATE);
    if (m.t < c.t) return;
    this.best = { car: c.car, name: c.name, lap_time: c.lap_time, samples: c.tape.samples };
    this.cut = null;
    if (this.vehicle) this.vehicle.dispose(this.scene);  // its label names the new lap's driver
    this.vehicle = null;
  }

  frame(s) {
    const b = this.best;
    drawLap(this, b, this.playStart === null ? null : s.t - this.playStart, () => {
      const layout = b && this.layouts[b.car];
      return layout ? buildGhostVehicle(this.scene, layout, 0xffb347, `${b.name} ${b.lap_time.toFixed(3)}`) : null;
    });
  }

  clear() {
    if (this.vehicle) this.vehicle.dispose(this.scene);
    this.vehicle = null;
    this.tapes.clear();
    this.recent.clear();
    this.cut = null; this.playStart = null; this.shown = null;
  }
}

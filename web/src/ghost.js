// The best-lap ghost (docs/front-end.md, Races): the own car's states of its
// best lap, as the server published them, kept per scenario (in memory and
// in localStorage) and drawn translucent beside the car on later laps, at
// the same time into the lap. A ghost passes through everything: it is
// drawn, never simulated.
import * as THREE from 'three';
import { app } from './app.js';
import { Vehicle } from './vehicle.js';

const MAX_SAMPLES = 60 * 60 * 10;  // 10 min at 60 Hz: a longer lap keeps no ghost
const STORE = 'groundsim.ghost.';

function slerpQ(a, b, u) {
  const qa = new THREE.Quaternion(a[1], a[2], a[3], a[0]), qb = new THREE.Quaternion(b[1], b[2], b[3], b[0]);
  qa.slerp(qb, u);
  return [qa.w, qa.x, qa.y, qa.z];
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
  }

  // the own car's lap started at t (simulated): record it, and race the ghost from it
  lapStarted(t) {
    this.rec = { start: t, samples: [] };
    this.playStart = t;
  }
  // the own car completed a lap at e.t: keep it when it is the best (once
  // the states up to e.t are in: events come before the frame that follows)
  lapDone(e) {
    if (e.best && this.rec) this.cut = { t: e.t, lap_time: e.lap_time, rec: this.rec };
  }

  // every state received (raw, not interpolated)
  onState(m) {
    const v = m.vehicles[app.followed];
    if (!v) return;
    const push = (r) => {
      if (r && r.samples.length < MAX_SAMPLES && m.t >= r.start - 0.1) r.samples.push([m.t - r.start, ...v.p, ...v.q]);
    };
    push(this.rec);
    if (!this.cut) return;
    if (this.cut.rec !== this.rec) push(this.cut.rec);
    if (m.t >= this.cut.t) {
      this.best = { lap_time: this.cut.lap_time, samples: this.cut.rec.samples };
      try { localStorage.setItem(STORE + this.key, JSON.stringify(this.best)); } catch { /* full: memory only */ }
      this.cut = null;
    }
  }

  // The ghost's pose tau seconds into its lap, interpolated between its states.
  pose(tau) {
    const s = this.best && this.best.samples;
    if (!s || s.length < 2 || tau < s[0][0] || tau > s[s.length - 1][0]) return null;
    let lo = 0, hi = s.length - 1;
    while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (s[mid][0] <= tau) lo = mid; else hi = mid; }
    const a = s[lo], b = s[hi], u = b[0] > a[0] ? (tau - a[0]) / (b[0] - a[0]) : 0;
    const p = [0, 1, 2].map((k) => a[1 + k] + u * (b[1 + k] - a[1 + k]));
    return { p, q: slerpQ(a.slice(4, 8), b.slice(4, 8), u) };
  }

  // per drawn state
  frame(s) {
    const pose = this.best && this.playStart !== null ? this.pose(s.t - this.playStart) : null;
    if (!pose) {
      if (this.vehicle) this.vehicle.root.visible = false;
      this.shown = null;
      return;
    }
    if (!this.vehicle && this.layout) this.vehicle = this.build(this.layout);
    if (!this.vehicle) return;
    this.vehicle.root.visible = true;
    this.vehicle.update({ p: pose.p, q: pose.q, w: [0, 0, 0], v: [0, 0, 0], speed: 0, spin: [], N: [] }, 0, 0, null, false);
    this.shown = { tau: s.t - this.playStart, p: pose.p };
  }

  build(layout) {
    const v = new Vehicle(this.scene, layout, 0x9fd8ff, '');
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

  clear() {
    if (this.vehicle) this.vehicle.dispose(this.scene);
    this.vehicle = null;
    this.rec = null; this.cut = null; this.playStart = null; this.shown = null;
  }
}

// Hits between bodies (contact states' `hits`: a pair from first touch
// until it parts) shown as they begin: a flash and sparks where they touch,
// and a line in the HUD naming the pair, its peak force and closing speed;
// a hard hit (a velocity change above collisions.hard_impact_dv for the
// lighter one) bigger, redder and in bold. The line is updated while the
// hit lasts and fades a few seconds after it ended.
import * as THREE from 'three';

const SPARKS = 28, LINE_S = 5, MAX_LINES = 4;
const key = (h) => `${h.a}|${h.b}|${h.begin.toFixed(4)}`;
const escape = (s) => String(s).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' }[c]));
const kN = (n) => (n >= 1000 ? `${(n / 1000).toFixed(1)} kN` : `${n.toFixed(0)} N`);

class Burst {
  constructor(scene, p, hard) {
    this.scene = scene;
    this.life = hard ? 0.9 : 0.5;
    this.age = 0;
    this.size = hard ? 0.9 : 0.45;
    this.flash = new THREE.Mesh(new THREE.SphereGeometry(1, 16, 12),
      new THREE.MeshBasicMaterial({ color: hard ? 0xff5a1f : 0xffe27a, transparent: true, opacity: 0.9,
        depthWrite: false, blending: THREE.AdditiveBlending }));
    this.flash.position.set(...p);
    this.flash.scale.setScalar(0.1);
    this.pos = new Float32Array(SPARKS * 3);
    this.vel = [];
    const speed = hard ? 7 : 4;
    for (let i = 0; i < SPARKS; ++i) {
      this.pos.set(p, 3 * i);
      const d = new THREE.Vector3().randomDirection();
      d.z = Math.abs(d.z) + 0.3;
      this.vel.push(d.normalize().multiplyScalar(speed * (0.4 + 0.6 * Math.random())));
    }
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(this.pos, 3));
    this.sparks = new THREE.Points(g, new THREE.PointsMaterial({ color: 0xffd36b, size: hard ? 0.12 : 0.08,
      transparent: true, depthWrite: false, blending: THREE.AdditiveBlending }));
    this.sparks.frustumCulled = false;
    scene.add(this.flash, this.sparks);
  }
  // The hit's point moved (a later contact state places it better): the
  // flash and the sparks follow.
  moveTo(p) {
    const d = new THREE.Vector3(...p).sub(this.flash.position);
    if (d.lengthSq() === 0) return;
    this.flash.position.add(d);
    for (let i = 0; i < SPARKS; ++i) {
      this.pos[3 * i] += d.x; this.pos[3 * i + 1] += d.y; this.pos[3 * i + 2] += d.z;
    }
  }
  // false once over (and removed)
  step(dt) {
    this.age += dt;
    const u = Math.min(1, this.age / this.life);
    this.flash.scale.setScalar(this.size * (0.2 + 0.8 * Math.sqrt(u)));
    this.flash.material.opacity = 0.9 * (1 - u);
    for (let i = 0; i < SPARKS; ++i) {
      const v = this.vel[i];
      v.z -= 9.81 * dt;
      this.pos[3 * i] += v.x * dt; this.pos[3 * i + 1] += v.y * dt; this.pos[3 * i + 2] += v.z * dt;
    }
    this.sparks.geometry.attributes.position.needsUpdate = true;
    this.sparks.material.opacity = 1 - u;
    if (u < 1) return true;
    this.dispose();
    return false;
  }
  dispose() {
    this.scene.remove(this.flash, this.sparks);
    this.flash.geometry.dispose(); this.flash.material.dispose();
    this.sparks.geometry.dispose(); this.sparks.material.dispose();
  }
}

export class HitEffects {
  // hud: the element holding the hit lines
  constructor(scene, hud) {
    this.scene = scene;
    this.hud = hud;
    this.reset();
  }
  reset() {
    for (const b of this.bursts || []) b.dispose();
    this.bursts = [];
    this.lines = new Map();  // key -> {a, b, peak, closing, hard, ongoing, age}
    this.shown = [];         // every hit shown: {a, b, hard, peak, closing, t, p} (tests read it)
    if (this.hud) this.hud.replaceChildren();
  }
  // m: a contact message of the session
  onContact(m) {
    const now = new Set();
    for (const h of m.hits || []) {
      const k = key(h);
      now.add(k);
      let line = this.lines.get(k);
      if (!line) {
        // its end may have come first, as an event (a page that reads slowly)
        for (const [ek, el] of this.lines)
          if (el.shown.event && el.a === h.a && el.b === h.b && el.shown.t >= h.begin - 1e-6) {
            this.lines.delete(ek);
            this.lines.set(k, line = el);
            break;
          }
      }
      if (!line) {
        const shown = { a: h.a, b: h.b, hard: h.hard, peak: h.peak, closing: h.closing, t: m.t, p: h.p };
        line = { a: h.a, b: h.b, hard: h.hard, peak: 0, closing: h.closing, age: 0, shown, burst: null };
        this.lines.set(k, line);
        if (this.bursts.length < 32) this.bursts.push(line.burst = new Burst(this.scene, h.p, h.hard));
        this.shown.push(shown);
        if (this.shown.length > 256) this.shown.shift();
        while (this.lines.size > MAX_LINES) this.lines.delete(this.lines.keys().next().value);
      } else if (h.hard && !line.hard) {
        // a hit turns hard during its course: flash again
        this.bursts.push(line.burst = new Burst(this.scene, h.p, true));
        line.hard = line.shown.hard = true;
      } else if (line.burst && line.burst.age < line.burst.life) {
        line.burst.moveTo(h.p);
      }
      line.shown.p = h.p;
      line.peak = Math.max(line.peak, h.peak);
      line.shown.peak = line.peak;
      line.ongoing = true;
      line.age = 0;
    }
    for (const [k, line] of this.lines) if (!now.has(k)) line.ongoing = false;
    this.render();
  }
  // An ended hit as the server's event ("hit: A and B at (x, y, z) m,
  // closing V m/s, ... peak force F N, ... (hard)"). Events are never
  // skipped, contact states may be (a browser that reads slowly gets the
  // newest): a hit this page never saw under way is shown now.
  onEndedHit(m) {
    const r = /^hit: (.+) and (.+) at \(([-0-9.e+]+), ([-0-9.e+]+), ([-0-9.e+]+)\) m, closing ([-0-9.e+]+) m\/s.*peak force ([-0-9.e+]+) N/
      .exec(m.reason || '');
    if (!r) return;
    const [a, b] = [r[1], r[2]], p = [r[3], r[4], r[5]].map(Number), closing = Number(r[6]), peak = Number(r[7]);
    const hard = m.reason.endsWith('(hard)');
    for (const line of this.lines.values()) if (line.a === a && line.b === b) return;  // seen under way
    const shown = { a, b, hard, peak, closing, t: m.t, p, event: true };
    this.lines.set(`${a}|${b}|event${m.t}`, { a, b, hard, peak, closing, age: 0, ongoing: false, shown, burst: null });
    while (this.lines.size > MAX_LINES) this.lines.delete(this.lines.keys().next().value);
    if (this.bursts.length < 32) this.bursts.push(new Burst(this.scene, p, hard));
    this.shown.push(shown);
    if (this.shown.length > 256) this.shown.shift();
    this.render();
  }
  frame(dt) {
    this.bursts = this.bursts.filter((b) => b.step(dt));
    let changed = false;
    for (const [k, line] of this.lines) {
      if (line.ongoing) continue;
      line.age += dt;
      if (line.age > LINE_S) { this.lines.delete(k); changed = true; }
    }
    if (changed) this.render();
  }
  render() {
    if (!this.hud) return;
    const rows = [...this.lines.values()].reverse().map((l) =>
      `<div class="hit${l.hard ? ' hard' : ''}${l.ongoing ? '' : ' over'}">${l.hard ? 'HARD HIT' : 'hit'}: ` +
      `${escape(l.a)} &ndash; ${escape(l.b)} &nbsp;${kN(l.peak)}, ${l.closing.toFixed(1)} m/s</div>`);
    this.hud.innerHTML = rows.join('');
  }
}

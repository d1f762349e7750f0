// Races (docs/front-end.md, Races): the server's race events ("race: {json}"
// reasons, docs/protocol.md) turned into what a racer sees: the countdown,
// the current lap's time (simulated time since the own car's lap started),
// last and best laps with the split at each gate against the best lap's,
// the leaderboard, the gates (posts, the next one lit with a tall beam) and
// wrong-way / off-track notices. The times shown are the server's: a lap's
// time is its lap event's; the running clock is the drawn state's t minus
// the lap's start as the server measured it.
import * as THREE from 'three';
import { session, addStateListener } from './session.js';
import { addEvent } from './hud.js';
import { Ghost, RivalGhost } from './ghost.js';

const fmt = (t) => {
  if (!(t > 0)) return '-';
  const m = Math.floor(t / 60), s = t - 60 * m;
  return m > 0 ? `${m}:${s.toFixed(3).padStart(6, '0')}` : s.toFixed(3);
};
const signed = (d) => `${d >= 0 ? '+' : '-'}${Math.abs(d).toFixed(3)}`;

function el(tag, css, parent) {
  const e = document.createElement(tag);
  if (css) e.style.cssText = css;
  if (parent) parent.appendChild(e);
  return e;
}

export class RaceView {
  // terrain: the ground drawn (the posts stand on it)
  constructor(scene, terrain) {
    this.scene = scene;
    this.terrain = terrain;
    this.group = new THREE.Group();
    scene.add(this.group);
    this.ghost = new Ghost(scene);       // the own best lap
    this.rival = new RivalGhost(scene);  // the session's fastest lap by another car
    addStateListener((m) => {
      if (!this.layout || m.session !== session.id) return;
      this.ghost.onState(m);
      this.rival.onState(m);
    });
    this.reset();
    // HUD: the panel top centre, the countdown and notices in the middle, the board at the right
    const panel = 'position:absolute;background:rgba(16,20,26,0.82);border-radius:6px;padding:6px 12px;' +
      'font-variant-numeric:tabular-nums;pointer-events:none;';
    this.dom = {
      panel: el('div', `${panel}top:10px;left:50%;transform:translateX(-50%);text-align:center;min-width:260px;`, document.body),
      big: el('div', 'position:absolute;top:32%;left:50%;transform:translate(-50%,-50%);font:700 96px system-ui;' +
        'color:#fff;text-shadow:0 0 12px #000;pointer-events:none;', document.body),
      notice: el('div', 'position:absolute;top:46%;left:50%;transform:translate(-50%,-50%);font:700 34px system-ui;' +
        'color:#ff5a3c;text-shadow:0 0 8px #000;pointer-events:none;', document.body),
      board: el('div', `${panel}top:120px;right:10px;font-size:13px;min-width:180px;`, document.body),
    };
    this.dom.panel.id = 'race-panel';
    this.dom.big.id = 'race-countdown';
    this.dom.notice.id = 'race-notice';
    this.dom.board.id = 'race-board';
    this.dom.lap = el('div', 'font-size:13px;color:#bbb', this.dom.panel);
    this.dom.clock = el('div', 'font-size:30px;font-weight:600', this.dom.panel);
    this.dom.clock.id = 'race-clock';
    this.dom.last = el('div', 'font-size:13px', this.dom.panel);
    this.dom.last.id = 'race-last';
    this.dom.split = el('div', 'font-size:15px;font-weight:600', this.dom.panel);
    this.dom.split.id = 'race-split';
    this.show(false);
  }

  reset() {
    this.layout = null;     // {laps, circuit, go, gates: [[lx, ly, rx, ry]], cars}
    this.standings = null;
    this.mine = { started: false, lapStart: 0, lap: 1, nextGate: 0, last: 0, best: 0, finished: false,
                  raceTime: 0, position: 0, wrongWay: false, offTrack: false, splits: [], bestSplits: [] };
    this.splitShown = null; // {text, until}
    this.events = [];       // race events received (tests read them)
    this.lapEvents = [];    // the own car's lap events as received: {lap, lap_time, t}
    this.shownLaps = [];    // the lap times the HUD showed, as text, one per lap event
    this.onLap = null;      // (event, mine) once per own lap
    this.onStart = null;    // (event) the own car's lap started (its first, or after a lap)
    for (const c of [...this.group.children]) { this.group.remove(c); c.geometry?.dispose(); c.dispose?.(); }
    this.posts = [];
    this.postMeshes = [];
    this.beam = null;
  }
  show(on) {
    for (const k of ['panel', 'board']) this.dom[k].style.display = on ? '' : 'none';
    if (!on) this.dom.big.textContent = this.dom.notice.textContent = '';
  }
  get active() { return !!this.layout; }

  // A bridge event; true when it was a race event (handled here).
  onEvent(m) {
    if (typeof m.reason !== 'string' || !m.reason.startsWith('race: ')) return false;
    let e;
    try { e = JSON.parse(m.reason.slice(6)); } catch { return true; }
    if (m.session !== session.id) return true;
    this.events.push(e);
    if (this.events.length > 2000) this.events.shift();
    const own = e.car === session.followed;
    const me = this.mine;
    if (!own) this.otherCar(e);
    switch (e.type) {
      case 'race': this.setLayout(e); this.events.push(e); break;
      case 'standings': this.standings = e; this.renderBoard(); break;
      case 'start':
        if (own) {
          Object.assign(me, { started: true, lapStart: e.t, lap: 1, nextGate: 1, splits: [] });
          this.ghost.lapStarted(e.t);
          this.rival.ownLapStarted(e.t);
          this.onStart?.(e);
        }
        break;
      case 'gate':
        if (own) {
          me.nextGate = e.gate + 1;
          me.splits.push(e.split);
          const best = me.bestSplits[me.splits.length - 1];
          this.splitShown = { text: best ? `split ${fmt(e.split)}  ${signed(e.split - best)}` : `split ${fmt(e.split)}`,
                              cls: best && e.split > best ? '#ff6b6b' : '#5bd778', until: e.t + 3 };
        }
        break;
      case 'lap':
        if (own) {
          me.last = e.lap_time;
          if (e.best) { me.best = e.lap_time; me.bestSplits = me.splits.slice(); }
          me.lap = e.lap + 1; me.lapStart = e.t; me.splits = []; me.nextGate = this.layout?.circuit === false ? 0 : 1;
          this.lapEvents.push({ lap: e.lap, lap_time: e.lap_time, t: e.t, best: e.best });
          this.splitShown = { text: `lap ${e.lap}  ${fmt(e.lap_time)}${e.best ? '  best' : ''}`, cls: e.best ? '#b784ff' : '#fff', until: e.t + 4 };
          this.renderLast();
          this.shownLaps.push(this.dom.last.dataset.lap);
          this.ghost.lapDone(e);
          addEvent(`lap ${e.lap}: ${fmt(e.lap_time)}${e.best ? ' (best)' : ''}`, 'i');
          this.onLap?.(e, me);
          if (e.lap < (this.layout?.laps || 1) && this.layout?.circuit !== false) {
            this.ghost.lapStarted(e.t);
            this.rival.ownLapStarted(e.t);
            this.onStart?.(e);
          }
        }
        break;
      case 'finish':
        if (own) {
          me.finished = true; me.raceTime = e.race_time; me.position = e.position;
          addEvent(`finished P${e.position} in ${fmt(e.race_time)}`, 'i');
        }
        break;
      case 'wrong_way': if (own) me.wrongWay = e.on; break;
      case 'off_track': if (own) me.offTrack = e.on; break;
      case 'respawn': if (own) { me.wrongWay = false; me.offTrack = false; } break;
      default: break;
    }
    return true;
  }

  // Another car's start and laps: its laps recorded for the rival ghost.
  otherCar(e) {
    if (typeof e.car !== 'number') return;
    if (e.type === 'start') this.rival.lapStarted(e.car, e.t);
    if (e.type === 'lap') {
      this.rival.lapDone(e);
      if (e.lap < (this.layout?.laps || 1) && this.layout?.circuit !== false) this.rival.lapStarted(e.car, e.t);
    }
  }

  // The race of the session joined (the joined layout's `race`, or the
  // server's "race" event at its start and after a reset); null: none.
  setLayout(race) {
    this.reset();
    this.ghost.clear();
    this.rival.clear();
    if (!race) return this.show(false);
    this.layout = race;
    this.build();
    this.show(true);
    // ghosts are kept per scenario: its name in the joined layout
    const { layout } = session;
    const name = layout && layout.name ? layout.name : `session ${session.id}`;
    const car = layout && layout.vehicles ? layout.vehicles[session.followed] : null;
    this.ghost.use(name, car);
    this.rival.use(session.id, layout && layout.vehicles);
  }

  // the gates as posts (one instanced mesh per colour: 2 draw calls for
  // any number of gates; each post an Object3D that frame() moves, copied
  // into its instance), the next one's beam
  build() {
    const gates = this.layout.gates || [];
    const postGeo = new THREE.CylinderGeometry(0.12, 0.12, 2.2, 8);
    postGeo.rotateX(Math.PI / 2);
    const mats = [new THREE.MeshStandardMaterial({ color: 0xffffff, emissive: 0x223344 }),
                  new THREE.MeshStandardMaterial({ color: 0x33d17a, emissive: 0x0d5a2a })];
    const counts = [2 * Math.max(0, gates.length - 1), gates.length ? 2 : 0];
    this.postMeshes = mats.map((m, k) => {
      const im = new THREE.InstancedMesh(postGeo, m, Math.max(1, counts[k]));
      im.count = counts[k];
      im.name = k ? 'start-posts' : 'gate-posts';
      im.frustumCulled = false;  // instances spread over the track
      this.group.add(im);
      return im;
    });
    const next = [0, 0];
    this.posts = gates.map((g, i) => [[g[0], g[1]], [g[2], g[3]]].map(([x, y]) => {
      const m = new THREE.Object3D();
      m.position.set(x, y, 1.1);
      m.userData.instance = [i === 0 ? 1 : 0, next[i === 0 ? 1 : 0]++];
      return m;
    }));
    const beamGeo = new THREE.CylinderGeometry(0.6, 0.6, 60, 12, 1, true);
    beamGeo.rotateX(Math.PI / 2);
    this.beam = new THREE.Mesh(beamGeo, new THREE.MeshBasicMaterial({ color: 0x33ff88, transparent: true, opacity: 0.25, depthWrite: false }));
    this.beam.name = 'next-gate';
    this.group.add(this.beam);
  }

  // per drawn state: the ghost, posts onto the ground (the car's height nearby), the next gate, the clock
  frame(s) {
    if (!this.layout || !s) return;
    this.ghost.frame(s);
    this.rival.frame(s);
    const v = s.vehicles[session.followed];
    const me = this.mine;
    const gates = this.layout.gates || [];
    const next = me.finished ? -1 : me.nextGate % Math.max(1, gates.length);
    // the posts stand on the drawn ground: a ray per post is costly (the
    // horizon's meshes), so two posts a frame, round robin, keep their heights
    const z = v ? v.p[2] - 0.5 : 0;
    const flat = this.posts.flat();
    for (let k = 0; k < Math.min(2, flat.length); ++k) {
      this.rr = ((this.rr || 0) + 1) % flat.length;
      const m = flat[this.rr];
      if (this.terrain) m.userData.ground = this.terrain.heightAt(m.position.x, m.position.y);
    }
    this.posts.forEach((pair, i) => pair.forEach((m) => {
      const h = m.userData.ground;
      m.position.z = (Number.isFinite(h) ? h : z) + 1.1;
      m.scale.setScalar(i === next ? 1.4 : 1);
      m.updateMatrix();
      const [k, j] = m.userData.instance;
      this.postMeshes[k].setMatrixAt(j, m.matrix);
    }));
    for (const im of this.postMeshes || []) im.instanceMatrix.needsUpdate = true;
    if (this.beam) {
      this.beam.visible = next >= 0 && !!gates[next];
      if (this.beam.visible) {
        const g = gates[next], pair = this.posts[next];
        this.beam.position.set((g[0] + g[2]) / 2, (g[1] + g[3]) / 2, pair[0].position.z - 1.1 + 30);
      }
    }
    // countdown: the server's go time against the drawn state's time
    const toGo = this.layout.go - s.t;
    this.dom.big.textContent = toGo > 0 ? String(Math.ceil(toGo)) : toGo > -1 ? 'GO' : '';
    this.dom.big.style.color = toGo > 0 ? '#ffd166' : '#5bd778';
    const laps = this.layout.laps;
    this.dom.lap.textContent = me.finished
      ? `finished: P${me.position}  ${fmt(me.raceTime)}`
      : `lap ${Math.min(me.lap, laps)} / ${laps}${this.layout.circuit === false ? ' (stage)' : ''}   gate ${next + 1} / ${gates.length}`;
    this.dom.clock.textContent = me.started && !me.finished ? fmt(Math.max(0, s.t - me.lapStart)) : me.finished ? fmt(me.last) : '0.000';
    this.renderLast();
    if (this.splitShown && s.t < this.splitShown.until) {
      this.dom.split.textContent = this.splitShown.text;
      this.dom.split.style.color = this.splitShown.cls;
    } else this.dom.split.textContent = '';
    this.dom.notice.textContent = me.wrongWay ? 'WRONG WAY' : me.offTrack ? 'OFF TRACK' : '';
  }
  renderLast() {
    const me = this.mine;
    this.dom.last.textContent = `last ${fmt(me.last)}   best ${fmt(me.best)}`;
    this.dom.last.dataset.lap = me.last > 0 ? me.last.toFixed(3) : '';
  }
  renderBoard() {
    const st = this.standings;
    if (!st) return;
    const rows = st.cars.map((c) => {
      const you = c.car === session.followed ? ' style="color:#ffd166"' : '';
      const what = c.finished ? fmt(c.race_time) : c.started ? `lap ${Math.min(c.laps_done + 1, st.laps)}` : 'grid';
      const player = session.players && session.players[c.car];
      const name = String(player ? `${player}` : c.name).replace(/[&<>]/g, (x) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;' })[x]);
      return `<tr${you} data-car="${c.car}"><td>P${c.position}</td><td>${name}</td><td>${what}</td><td>${fmt(c.best_lap)}</td></tr>`;
    }).join('');
    this.dom.board.innerHTML = `<div style="font-weight:600;margin-bottom:2px">leaderboard</div><table style="border-collapse:collapse">${rows}</table>`;
  }
  dispose() {
    this.reset();
    this.ghost.clear();
    this.rival.clear();
    this.show(false);
  }
}

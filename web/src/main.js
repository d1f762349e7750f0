// The page: lobby, scene, HUD, input, and the loop that draws at the
// display's rate (renderer.setAnimationLoop). Network (net.js), smoothing
// (interp.js), input (input.js), ground (ground.js), vehicles
// (vehicle.js), obstacles (objects.js) and hits (hits.js) are separate modules.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { Connection } from './net.js';
import { Playback } from './interp.js';
import { Input } from './input.js';
import { GroundMesh } from './ground.js';
import { Vehicle, defaultLayout } from './vehicle.js';
import { SceneObjects } from './objects.js';
import { HitEffects } from './hits.js';

const $ = (id) => document.getElementById(id);
const STATUS = { 1: 'running', 2: 'paused', 3: 'finished', 4: 'diverged', 5: 'stopped' };
const HEALTH = { 0: 'ok', 1: 'non-finite', 2: 'penetration', 3: 'speed', 4: 'energy' };
const COLORS = [0xd94f3d, 0x3d7dd9, 0x4fbf5a, 0xe0a030, 0xa05fd0, 0x40c0c0, 0xc0c040, 0xd070a0];
const SEND_PERIOD_MS = 50;
// ?render=0 runs everything but the drawing (the latency benchmark isolates
// the network path from a software renderer's frame time with it)
const DRAW = new URLSearchParams(location.search).get('render') !== '0';  // controls are re-sent so the server's command timeout never fires

// ---- three.js ----------------------------------------------------------------
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(Math.min(2, window.devicePixelRatio || 1));
renderer.setSize(window.innerWidth, window.innerHeight);
renderer.shadowMap.enabled = true;
$('view').appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x9fc4e0);
scene.fog = new THREE.Fog(0x9fc4e0, 30, 70);
scene.add(new THREE.HemisphereLight(0xdfefff, 0x4a5a3a, 1.4));
const sun = new THREE.DirectionalLight(0xffffff, 2.2);
sun.position.set(-12, -8, 20);
sun.castShadow = true;
sun.shadow.mapSize.set(1024, 1024);
Object.assign(sun.shadow.camera, { left: -15, right: 15, top: 15, bottom: -15, near: 1, far: 60 });
scene.add(sun, sun.target);
const camera = new THREE.PerspectiveCamera(55, window.innerWidth / window.innerHeight, 0.05, 500);
camera.up.set(0, 0, 1);
camera.position.set(-8, -6, 5);
const orbit = new OrbitControls(camera, renderer.domElement);
orbit.enabled = false;
window.addEventListener('resize', () => {
  camera.aspect = window.innerWidth / window.innerHeight;
  camera.updateProjectionMatrix();
  renderer.setSize(window.innerWidth, window.innerHeight);
});

// ---- session state ---------------------------------------------------------------
const ground = new GroundMesh(scene);
const hits = new HitEffects(scene, $('hud-hits'));
const playback = new Playback();
const input = new Input(window);
const wsUrl = `${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws`;
const net = new Connection(wsUrl);
const app = {
  session: null, role: null, vehicle: -1, layout: null, note: '',
  vehicles: [], events: [], lobby: null, configs: [], scenarios: [], cameraMode: 'chase',
  frames: 0, fps: 0, lastState: null, states: 0, groundGrids: 0, controlsSent: 0, errors: [],
  followed: 0, lastControls: null, stateListeners: [],
  car: null,  // the newest {"op":"car"} of the session: its road cars' gear, rpm, applied controls
  objects: null, objectMeshes: 0,  // the scenario's obstacles as drawn (objects.js)
  contacts: 0, hits, hitEvents: 0,  // contact states received, hits shown (hits.shown), "hit: " events
};
app.send = (m) => net.send(m);
window.groundsim = app;  // for tests and the latency benchmark
app.three = { scene, camera };

function clearScene() {
  for (const v of app.vehicles) v.dispose(scene);
  app.vehicles = [];
  if (app.objects) app.objects.dispose();
  app.objects = null;
  app.objectMeshes = 0;
  hits.reset();
  playback.reset();
  ground.center = null;
  if (ground.mesh) { scene.remove(ground.mesh); ground.mesh = null; }
}

function showLobby(show) {
  $('lobby').classList.toggle('hidden', !show);
  for (const id of ['hud', 'events', 'topbar', 'help']) $(id).classList.toggle('hidden', show);
}

function addEvent(text, cls) {
  app.events.push({ text, cls });
  if (app.events.length > 6) app.events.shift();
  $('events').innerHTML = app.events.map((e) => `<div class="${e.cls}">${e.text.replace(/</g, '&lt;')}</div>`).join('');
}

// ---- messages from the bridge -------------------------------------------------------
net.on('open', () => {
  const want = new URLSearchParams(location.search).get('session');
  if (want && !app.session) net.send({ op: 'join', session: want, role: 'spectate' });
  else if (app.session) net.send({ op: 'join', session: app.session, role: 'spectate' });
});
net.on('close', () => addEvent('connection to the bridge lost, reconnecting...', 'e'));
net.on('welcome', (m) => {
  app.configs = m.configs;
  // a bridge before the scenario list sent file names only
  app.scenarios = m.scenarios || m.configs.map((id) => ({ id, name: '', description: '', vehicles: 1, min_cars: 1, max_cars: 1 }));
  renderScenarios();
});
net.on('lobby', (m) => { app.lobby = m; renderLobby(); });
net.on('created', (m) => addEvent(`created session ${m.session}`, 'i'));
net.on('joined', (m) => {
  clearScene();
  app.session = m.session; app.role = m.role; app.vehicle = m.vehicle; app.layout = m.layout; app.note = m.note;
  app.followed = Math.max(0, m.vehicle);
  const q = new URLSearchParams(location.search);
  q.set('session', m.session);
  history.replaceState(null, '', `?${q}`);
  showLobby(false);
  $('hud-session').textContent = m.session;
  $('hud-role').textContent = m.role === 'drive' ? `driving vehicle ${m.vehicle}` : 'spectating';
  if (m.note) addEvent(m.note, 'w');
  app.objects = new SceneObjects(scene, m.layout && m.layout.objects);
  app.objectMeshes = app.objects.meshes.length;
});
net.on('left', () => { app.session = null; clearScene(); showLobby(true); });
net.on('ground', (m) => {
  if (m.session !== app.session) return;
  ground.show(m);
  app.groundGrids++;
});
net.on('state', (m) => {
  if (m.session !== app.session) return;
  const now = performance.now() / 1000;
  playback.push(m, now);
  app.lastState = m;
  app.states++;
  if (app.vehicles.length !== m.vehicles.length) buildVehicles(m);
  for (const fn of app.stateListeners) fn(m, performance.now());
});
net.on('car', (m) => { if (m.session === app.session) app.car = m; });
net.on('contact', (m) => {
  if (m.session !== app.session) return;
  app.contacts++;
  playback.pushContact(m);
  hits.onContact(m);
});
net.on('event', (m) => {
  const cls = m.severity >= 2 ? 'e' : m.severity === 1 ? 'w' : 'i';
  if (typeof m.reason === 'string' && m.reason.startsWith('hit: ')) {
    // an ended hit: the HUD named it while it lasted; one short line here
    app.hitEvents++;
    if (m.session === app.session) hits.onEndedHit(m);
    const pair = m.reason.split(' at (')[0], peak = m.reason.match(/peak force ([0-9.e+-]+) N/);
    const hard = m.reason.endsWith('(hard)') ? ' (hard)' : '';
    return addEvent(`t=${m.t.toFixed(2)} s  ${pair}${peak ? `, peak ${(parseFloat(peak[1]) / 1000).toFixed(1)} kN` : ''}${hard}`, cls);
  }
  addEvent(`t=${m.t.toFixed(2)} s  ${cls === 'e' ? 'error' : cls === 'w' ? 'warning' : 'info'} ${m.code}: ${m.reason}`, cls);
});
net.on('error', (m) => {
  app.errors.push(m);
  const text = `${m.request || 'message'} refused${m.field ? ' at ' + m.field : ''}: ${m.reason}`;
  if ($('lobby').classList.contains('hidden')) addEvent(text, 'e'); else $('lobby-error').textContent = text;
});
net.on('reply', (m) => addEvent(`${m.request}: ok`, 'i'));

function buildVehicles(state) {
  for (const v of app.vehicles) v.dispose(scene);
  const layouts = app.layout ? app.layout.vehicles : [];
  app.vehicles = state.vehicles.map((vs, i) => new Vehicle(scene, layouts[i] || defaultLayout(vs.name), COLORS[i % COLORS.length]));
  if (!app.layout && state.vehicles.length) {
    const p = state.vehicles[0].p;
    ground.flat(p[0], p[1], p[2] - 1);  // the report car's wheel radius
  }
}

// ---- lobby -----------------------------------------------------------------------
const carsText = (s) => (s.max_cars > s.min_cars ? `${s.min_cars}-${s.max_cars} cars` : `${s.min_cars} car${s.min_cars === 1 ? '' : 's'}`);
const scenarioById = (id) => app.scenarios.find((s) => s.id === id);

// The shipped scenarios: a row each (id, cars it hosts, description) and
// the same in the drop-down; a click on a row picks it.
function renderScenarios() {
  const sel = $('create-config'), body = $('lobby-scenarios'), keep = sel.value;
  sel.replaceChildren(...app.scenarios.map((s) => {
    const o = document.createElement('option');
    o.value = s.id;
    o.textContent = `${s.id} (${carsText(s)})`;
    return o;
  }));
  body.replaceChildren(...app.scenarios.map((s) => {
    const tr = document.createElement('tr');
    tr.dataset.config = s.id;
    for (const text of [s.id, carsText(s), s.description]) tr.appendChild(document.createElement('td')).textContent = text;
    tr.firstChild.className = 'id';
    tr.children[1].className = 'cars';
    tr.children[2].className = 'desc';
    if (s.limit) tr.children[1].title = s.limit;
    return tr;
  }));
  if (scenarioById(keep)) sel.value = keep;
  pickScenario(sel.value);
}
function pickScenario(id) {
  const s = scenarioById(id);
  if (!s) return;
  $('create-config').value = id;
  for (const tr of $('lobby-scenarios').children) tr.classList.toggle('picked', tr.dataset.config === id);
  const n = $('create-vehicles');
  n.min = s.min_cars;
  n.max = s.max_cars;
  const v = parseInt(n.value, 10) || 1;
  n.value = String(Math.max(s.min_cars, Math.min(s.max_cars, v)));
  $('create-about').textContent = `${carsText(s)}: ${s.description || '(no description)'}`;
}
$('create-config').addEventListener('change', () => {
  pickScenario($('create-config').value);
  const row = $('lobby-scenarios').querySelector('tr.picked');
  if (row) row.scrollIntoView({ block: 'nearest' });
});
$('lobby-scenarios').addEventListener('click', (e) => {
  const row = e.target.closest('tr');
  if (row) pickScenario(row.dataset.config);
});

function renderLobby() {
  const m = app.lobby;
  $('lobby-server').textContent = m.server
    ? `server ${m.server.id}: ${m.server.sessions} sessions, ${m.server.workers} workers, load ${(100 * m.server.load).toFixed(0)} %`
    : 'no server heartbeat on this bus (sessions below are states seen on the bus)';
  // rows are updated in place (a row rebuilt every heartbeat would eat clicks)
  const body = $('lobby-sessions'), ids = new Set(m.sessions.map((x) => x.id));
  for (const tr of [...body.children]) if (!ids.has(tr.dataset.session)) tr.remove();
  for (const x of m.sessions) {
    let tr = body.querySelector(`tr[data-session="${x.id}"]`);
    if (!tr) {
      tr = document.createElement('tr');
      tr.dataset.session = x.id;
      tr.innerHTML = '<td><code></code></td><td></td><td></td><td></td><td></td><td></td><td class="act"></td>';
      body.appendChild(tr);
    }
    const cells = tr.children;
    cells[0].firstChild.textContent = x.id;
    cells[1].textContent = x.name || '(unknown)';
    cells[2].textContent = x.mode;
    cells[3].textContent = STATUS[x.status] || x.status;
    cells[4].textContent = x.t.toFixed(1);
    cells[5].textContent = x.vehicles.length || '?';
    const acts = (x.drivable ? 'drive ' : '') + 'spectate';
    if (cells[6].dataset.acts !== acts) {
      cells[6].dataset.acts = acts;
      cells[6].innerHTML = acts.split(' ').map((a) => `<button data-act="${a}">${a}</button>`).join('');
    }
  }
}
$('lobby-sessions').addEventListener('click', (e) => {
  const act = e.target.dataset && e.target.dataset.act;
  const row = e.target.closest('tr');
  if (!act || !row) return;
  net.send({ op: 'join', session: row.dataset.session, role: act });
});
$('create-drive').addEventListener('click', () => {
  const s = scenarioById($('create-config').value);
  if (!s) return;
  const n = Math.max(s.min_cars, Math.min(s.max_cars, parseInt($('create-vehicles').value, 10) || 1));
  // vehicles 0: the scenario as it is; n: n copies of its car
  net.send({ op: 'create', config: s.id, vehicles: n === s.vehicles ? 0 : n, drive: true });
});
$('btn-lobby').addEventListener('click', () => { net.send({ op: 'leave' }); history.replaceState(null, '', '/'); });
$('btn-camera').addEventListener('click', () => toggleCamera());
$('btn-pause').addEventListener('click', () => togglePause());
$('btn-reset').addEventListener('click', () => net.send({ op: 'reset' }));

function toggleCamera() {
  app.cameraMode = app.cameraMode === 'chase' ? 'orbit' : 'chase';
  orbit.enabled = app.cameraMode === 'orbit';
  $('btn-camera').textContent = `camera: ${app.cameraMode}`;
}
function togglePause() {
  const s = playback.newest();
  net.send({ op: s && s.status === 2 ? 'resume' : 'pause' });
}

// ---- controls ----------------------------------------------------------------------
let lastSend = 0, lastInput = performance.now();
// Advances the input ramps by the time since the last call (whoever calls:
// the frame loop, the timer, a key event) and sends the controls when they
// changed or every SEND_PERIOD_MS.
function drive(v) {
  const t = performance.now();
  const dt = Math.min(0.1, (t - lastInput) / 1000);
  lastInput = t;
  for (const a of input.takeActions()) {
    if (a === 'camera') toggleCamera();
    else if (app.role === 'drive' && a === 'reset') net.send({ op: 'reset' });
    else if (app.role === 'drive' && a === 'pause') togglePause();
  }
  if (app.role !== 'drive') return;
  let forward = 0;
  if (v) {
    const q = new THREE.Quaternion(v.q[1], v.q[2], v.q[3], v.q[0]);
    const fwd = new THREE.Vector3(1, 0, 0).applyQuaternion(q);
    forward = fwd.x * v.v[0] + fwd.y * v.v[1] + fwd.z * v.v[2];
  }
  const c = input.update(dt, forward);
  const key = JSON.stringify(c), now = performance.now();
  if (key !== app.lastControls || now - lastSend > SEND_PERIOD_MS) {
    net.send({ op: 'controls', ...c, seq: app.controlsSent++ });
    app.lastControls = key;
    lastSend = now;
  }
}
// also while the tab's animation frames are throttled (hidden or headless)
const ownState = () => app.lastState && app.lastState.vehicles[app.vehicle];
setInterval(() => { if (app.role === 'drive' && performance.now() - lastSend > SEND_PERIOD_MS) drive(ownState()); }, SEND_PERIOD_MS);
// a key press goes out at once, not at the next frame (latency)
input.onChange = () => drive(ownState());

// ---- the frame loop ------------------------------------------------------------------
let lastFrame = performance.now(), fpsCount = 0, fpsStart = lastFrame, lastSimT = null;
const chaseTarget = new THREE.Vector3();
renderer.setAnimationLoop(() => {
  const now = performance.now();
  // the playback clock takes the whole wall time (a slow renderer must not
  // make it fall behind); camera smoothing takes at most 0.1 s a frame
  const wallDt = (now - lastFrame) / 1000, dt = Math.min(0.1, wallDt);
  lastFrame = now;
  const s = playback.frame(wallDt);
  const mine = s && s.vehicles[app.followed];
  drive(ownState());
  if (s) {
    const simDt = lastSimT === null ? 0 : Math.max(0, s.t - lastSimT);
    lastSimT = s.t;
    s.vehicles.forEach((v, i) => {
      const own = app.role === 'drive' && i === app.vehicle;
      const rc = app.car && app.car.session === s.session ? app.car.cars.find((c) => c.vehicle === i) : null;
      app.vehicles[i] && app.vehicles[i].update(v, simDt, own ? input.c.steer * 0.6 : null, rc || null);
    });
    if (app.objects) app.objects.update(s.objects);
    if (mine) {
      if (app.layout && ground.needsRefresh(mine.p[0], mine.p[1]) && !app.groundPending) {
        app.groundPending = true;
        setTimeout(() => { app.groundPending = false; }, 500);
        net.send({ op: 'ground', cx: mine.p[0], cy: mine.p[1] });
      }
      placeCamera(mine, dt);
      sun.position.set(mine.p[0] - 12, mine.p[1] - 8, mine.p[2] + 20);
      sun.target.position.set(mine.p[0], mine.p[1], mine.p[2]);
    }
    updateHud(s, mine);
  }
  hits.frame(wallDt);
  if (DRAW) renderer.render(scene, camera);
  app.frames++;
  fpsCount++;
  if (now - fpsStart > 1000) { app.fps = (1000 * fpsCount) / (now - fpsStart); fpsCount = 0; fpsStart = now; }
});

function placeCamera(v, dt) {
  const size = app.vehicles[app.followed] ? app.vehicles[app.followed].size : 3;
  chaseTarget.set(...v.p);
  if (app.cameraMode === 'orbit') {
    const d = chaseTarget.clone().sub(orbit.target);
    orbit.target.add(d);
    camera.position.add(d);
    orbit.update();
    return;
  }
  const q = new THREE.Quaternion(v.q[1], v.q[2], v.q[3], v.q[0]);
  const fwd = new THREE.Vector3(1, 0, 0).applyQuaternion(q);
  fwd.z = 0;
  if (fwd.lengthSq() < 1e-6) fwd.set(1, 0, 0);
  fwd.normalize();
  const want = chaseTarget.clone().addScaledVector(fwd, -2.6 * size).add(new THREE.Vector3(0, 0, 1.5 * size));
  camera.position.lerp(want, Math.min(1, 4 * dt));
  camera.lookAt(chaseTarget);
}

function updateHud(s, v) {
  if (!v) return;
  $('hud-speed').textContent = (Math.hypot(...v.v) * 3.6).toFixed(1);
  // a road car reports its engaged gear and engine rpm; other vehicles have
  // neither: the page's own gear and the wheels' mean spin stand in
  const rc = app.car && app.car.session === s.session ? app.car.cars.find((c) => c.vehicle === app.followed) : null;
  if (rc) {
    $('hud-gear').textContent = rc.gear > 0 ? String(rc.gear) : rc.gear < 0 ? 'R' : 'N';
    $('hud-rpm').textContent = rc.rpm.toFixed(0);
  } else {
    $('hud-gear').textContent = app.role === 'drive' ? (input.c.gear > 0 ? 'D' : input.c.gear < 0 ? 'R' : 'N') : '-';
    const spins = v.spin.length ? v.spin.reduce((a, x) => a + Math.abs(x), 0) / v.spin.length : 0;
    $('hud-rpm').textContent = (spins * 60 / (2 * Math.PI)).toFixed(0);
  }
  $('hud-time').textContent = `${s.t.toFixed(2)} s`;
  $('hud-rtf').textContent = playback.rate.toFixed(2);
  const st = $('status');
  st.textContent = STATUS[s.status] || s.status;
  st.className = s.status === 4 ? 'bad' : s.status !== 1 ? 'warn' : '';
  $('hud-health').textContent = HEALTH[s.health] || s.health;
  const car = app.vehicles[app.followed];
  $('hud-wheels').textContent = `${v.N.map((n) => n.toFixed(1)).join(' ')} N`;
  $('hud-travel').textContent = car ? `${car.wheels.map((w) => (1000 * w.lift).toFixed(3)).join(' ')} mm` : '-';
  $('hud-fps').textContent = `${app.fps.toFixed(0)} frames/s`;
  $('btn-pause').textContent = s.status === 2 ? 'resume' : 'pause';
}

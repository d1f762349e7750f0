/* global GROUNDSIM_FULL_LOCK */  // the full lock (rad), defined at bundle time from kFullLockRad (web/CMakeLists.txt)
// The page: wires the views together and runs the loop that draws at the
// display's rate (renderer.setAnimationLoop). Each concern is a module:
// app.js (shared state, window.groundsim), render.js (renderer, sky, sun,
// fog), terrain.js (ground to the horizon), track.js (a race's track as a
// ribbon), vehicle.js (cars), objects.js
// (obstacles), hits.js (hits), skids.js (tyre marks), camera.js (cameras),
// hud.js (HUD, events), lobby.js (lobby), replay.js (recordings on a
// timeline), net.js (WebSocket), interp.js (smoothing), input.js and
// drive.js (controls), predict.js (the own car ahead of the server's
// states: the physics core in WebAssembly), lag.js (round trip, lag notice).
import { app, $, COLORS } from './app.js';
import { World } from './render.js';
import { Terrain } from './terrain.js';
import { Vehicle, defaultLayout, sedanLayout } from './vehicle.js';
import { SceneObjects } from './objects.js';
import { HitEffects } from './hits.js';
import { SkidMarks } from './skids.js';
import { CameraRig } from './camera.js';
import { addEvent, clearEvents, updateHud } from './hud.js';
import { showLobby, renderScenarios, renderLobby, wireLobby, onPreview, playerName, shareLink, copyText } from './lobby.js';
import { Replay } from './replay.js';
import { Connection } from './net.js';
import { Playback } from './interp.js';
import { Input, RemapScreen } from './input.js';
import { Driver } from './drive.js';
import { probeHorizon } from './probe.js';
import { RaceView } from './race.js';
import { TrackRibbon } from './track.js';
import { Prediction } from './predict.js';
import { LagMeter } from './lag.js';

// ?render=0 runs everything but the drawing (the latency benchmark isolates
// the network path from a software renderer's frame time with it)
const DRAW = new URLSearchParams(location.search).get('render') !== '0';
// ?res=fixed keeps the full resolution (screenshots); else it adapts (below)
const ADAPT = new URLSearchParams(location.search).get('res') !== 'fixed';

// A replay's link: its recording is asked for now, before the renderer is
// made (a WebGL context takes a second in software), and drawn once the
// page is up (openReplay below takes it over).
const early = (() => {
  const q = new URLSearchParams(location.search), name = q.get('replay'), session = q.get('rsession');
  if (!name || !session) return null;
  const r = new Replay(name, session);
  return { r, opened: r.open(), scene: r.scene(), laps: r.laps() };
})();
if (early) early.opened.catch(() => {});  // reported by openReplay

const world = new World($('view'));
const { scene, camera } = world;
const terrain = new Terrain(scene);
const hits = new HitEffects(scene, $('hud-hits'));
const skids = new SkidMarks(scene);
const rig = new CameraRig(camera, world.renderer.domElement);
const playback = new Playback();
const input = new Input(window);
const remap = new RemapScreen(input);  // gamepad / wheel controls (key G)
const touch = matchMedia('(pointer: coarse)').matches || navigator.maxTouchPoints > 0 ? input.touchControls() : null;
const race = new RaceView(scene);  // races: HUD, gates, ghost (race.js, ghost.js)
const track = new TrackRibbon(scene);  // the race's track, drawn from its centre line (track.js)
const net = new Connection(`${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws`);
Object.assign(app, { race, track, hits, terrain, skids, three: { scene, camera, renderer: world.renderer, sky: world.sky, world } });
app.send = (m) => net.send(m);
const prediction = new Prediction();
const lag = new LagMeter(net);
net.on('*', () => lag.heard());
net.on('pong', (m) => lag.onPong(m));
app.debug = { probeHorizon: (opts) => probeHorizon(world, opts) };

function clearScene() {
  for (const v of app.vehicles) v.dispose(scene);
  app.vehicles = [];
  if (app.objects) app.objects.dispose();
  app.objects = null;
  app.objectMeshes = 0;
  hits.reset();
  skids.reset();
  race.dispose();
  track.clear();
  app.playerNames = [];
  playback.reset();
  prediction.stop('no session');
  terrain.clear();
  world.sky.visible = false;
}

// ---- messages from the bridge -------------------------------------------------------
net.on('open', () => {
  const q = new URLSearchParams(location.search);
  if (app.replay) return;
  if (q.get('replay') && q.get('rsession')) return openReplay(q.get('replay'), q.get('rsession'));
  const want = q.get('session');
  const who = playerName() ? { player: playerName() } : {};
  if (want && !app.session) net.send({ op: 'join', session: want, role: 'spectate', ...who });
  else if (app.session) net.send({ op: 'join', session: app.session, role: 'spectate', ...who });
});
net.on('close', () => addEvent('connection to the bridge lost, reconnecting...', 'e'));
net.on('welcome', (m) => {
  app.configs = m.configs;
  // a bridge before the scenario list sent file names only
  app.scenarios = m.scenarios || m.configs.map((id) => ({ id, name: '', description: '', vehicles: 1, min_cars: 1, max_cars: 1 }));
  renderScenarios();
});
net.on('lobby', (m) => { app.lobby = m; renderLobby(); namePlayers(); });
net.on('preview', (m) => onPreview(m));
net.on('created', (m) => addEvent(`created session ${m.session}`, 'i'));
net.on('joined', (m) => {
  closeReplay(false);
  clearScene();
  app.session = m.session; app.role = m.role; app.vehicle = m.vehicle; app.layout = m.layout; app.note = m.note;
  const q = new URLSearchParams(location.search);
  // a spectator may follow any car (?follow=k: a bot, another player)
  const follow = parseInt(q.get('follow'), 10), cars = ((m.layout && m.layout.vehicles) || []).length;
  app.followed = m.role !== 'drive' && follow >= 0 && follow < cars ? follow : Math.max(0, m.vehicle);
  q.set('session', m.session);
  history.replaceState(null, '', `?${q}`);
  showLobby(false);
  $('hud-session').textContent = m.session;
  $('hud-role').textContent = m.role === 'drive' ? `driving vehicle ${m.vehicle}` : 'spectating';
  if (m.note) addEvent(m.note, 'w');
  terrain.setLayout(m.layout);
  race.setLayout(m.layout && m.layout.race);
  track.set(m.layout && m.layout.track, m.layout && m.layout.race);
  world.sky.visible = true;
  app.objects = new SceneObjects(scene, m.layout && m.layout.objects);
  app.objectMeshes = app.objects.meshes.length;
  rig.set('chase');
  if (touch) touch.show(m.role === 'drive');
  if (m.role === 'drive') prediction.start(m.session, m.vehicle, m.scenario, m.scale);
  else prediction.stop('spectating');
});
net.on('left', () => { app.session = null; clearScene(); showLobby(true);
// a replay's link opens it at once: it reads the recording over HTTP and
// needs no WebSocket (the 'open' handler leaves it be)
{
  const q = new URLSearchParams(location.search);
  if (q.get('replay') && q.get('rsession')) openReplay(q.get('replay'), q.get('rsession'));
} });
net.on('ground', (m) => {
  if (m.session !== app.session) return;
  terrain.show(m);
  prediction.onGround(m);
  app.groundGrids++;
});
net.on('state', (m) => {
  if (m.session !== app.session || app.replay) return;
  playback.push(m, performance.now() / 1000);
  prediction.onState(m, performance.now());
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
  if (race.onEvent(m)) return;  // "race: {json}" (race.js)
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

// each car in its colour with its name (the own one marked) above it
function buildVehicles(state, layouts = app.layout ? app.layout.vehicles : []) {
  for (const v of app.vehicles) v.dispose(scene);
  const players = app.replay ? [] : app.playerNames || [];
  app.vehicles = state.vehicles.map((vs, i) => {
    const name = `${players[i] || vs.name}${app.role === 'drive' && i === app.vehicle && !app.replay ? ' (you)' : ''}`;
    const v = new Vehicle(scene, layouts[i] || defaultLayout(vs.name), COLORS[i % COLORS.length], name);
    v.setFigure(app.figure);
    return v;
  });
  if (!app.layout && !app.replay && state.vehicles.length) {
    const p = state.vehicles[0].p;
    terrain.flat(p[0], p[1], p[2] - 1);  // the report car's wheel radius
    world.sky.visible = true;
  }
}

// the players' names of the session shown (the lobby's "players", a name
// per car): above the cars, on the leaderboard
function namePlayers() {
  const x = app.session && app.lobby ? app.lobby.sessions.find((e) => e.id === app.session) : null;
  const players = (x && x.players) || [];
  app.playerNames = players;
  app.vehicles.forEach((v, i) => {
    const base = players[i] || (app.lastState && app.lastState.vehicles[i] ? app.lastState.vehicles[i].name : v.name);
    v.setName(`${base}${app.role === 'drive' && i === app.vehicle && !app.replay ? ' (you)' : ''}`);
  });
  race.renderBoard();
}

const named = (m) => (playerName() ? { ...m, player: playerName() } : m);
wireLobby({
  join: (session, role) => net.send(named({ op: 'join', session, role })),
  create: (config, vehicles, extra = {}) => net.send(named({ op: 'create', config, vehicles, drive: true, ...extra })),
  replay: (name, session) => openReplay(name, session),
  preview: (config) => net.send({ op: 'preview', config }),
});
$('btn-share').addEventListener('click', async () => {
  if (!app.session) return;
  const link = shareLink(app.session), ok = await copyText(link);
  app.shared = link;
  addEvent(`${ok ? 'copied' : 'share'}: ${link}`, 'i');
});
$('btn-lobby').addEventListener('click', () => { net.send({ op: 'leave' }); history.replaceState(null, '', '/'); });
$('btn-camera').addEventListener('click', () => toggleCamera());
$('btn-pause').addEventListener('click', () => togglePause());
$('btn-reset').addEventListener('click', () => net.send({ op: 'reset' }));
rig.onChange = (mode) => { app.cameraMode = mode; $('btn-camera').textContent = $('tl-camera').textContent = `camera: ${mode}`; };

function toggleCamera() { rig.cycle(app.replay ? ['chase', 'orbit', 'free'] : ['chase', 'orbit']); }
function togglePause() {
  const s = playback.newest();
  net.send({ op: s && s.status === 2 ? 'resume' : 'pause' });
}
function toggleFigure() {
  app.figure = !app.figure;
  for (const v of app.vehicles) v.setFigure(app.figure);
}
const driver = new Driver(input, net, (c) => prediction.setControls(c), (a) => {
  if (a === 'camera') toggleCamera();
  else if (a === 'figure') toggleFigure();
  else if (a === 'remap') remap.toggle();
  else if (app.role === 'drive' && !app.replay && a === 'reset') net.send({ op: 'reset' });
  else if (app.role === 'drive' && !app.replay && a === 'respawn' && race.active) net.send({ op: 'respawn' });
  else if (app.role === 'drive' && !app.replay && a === 'pause') togglePause();
});

// ---- replays ------------------------------------------------------------------------
async function openReplay(name, session) {
  if (app.session) net.send({ op: 'leave' });
  app.session = null; app.role = null; app.layout = null; app.vehicle = -1; app.car = null;
  clearScene();
  clearEvents();
  // the link's replay, asked for at load, or a new one
  const pre = early && early.r.name === name && early.r.session === session && !early.used ? early : null;
  if (pre) pre.used = true;
  const r = pre ? pre.r : new Replay(name, session);
  app.replay = r;
  app.followed = 0;
  showLobby(false);
  for (const id of ['hud', 'events']) $(id).classList.remove('hidden');
  for (const id of ['topbar', 'help']) $(id).classList.add('hidden');
  $('timeline').classList.remove('hidden');
  $('tl-title').textContent = `${name} / ${session}`;
  $('hud-session').textContent = session;
  $('hud-role').textContent = 'replay';
  const q = new URLSearchParams({ replay: name, rsession: session });
  history.replaceState(null, '', `?${q}`);
  rig.set('chase');
  // the scene and the laps are asked for beside the span and first window
  const sceneAsked = pre ? pre.scene : r.scene(), lapsAsked = pre ? pre.laps : r.laps();
  try {
    await (pre ? pre.opened : r.open());
  } catch (e) {
    addEvent(`replay ${name}: ${e.message || e}`, 'e');
    return;
  }
  if (app.replay !== r) return;
  const first = r.frame(0);
  if (!first) return addEvent(`replay ${name}: no states`, 'e');
  // the scene as the session had it (its scenario, attached to the file):
  // ground, track, objects and the cars' layouts; else, where the file holds
  // no scenario, road cars (four wheels, "sedan" in the name) are drawn as
  // sedans and others as the report's car, on flat ground below the first car
  const layout = await sceneAsked;
  if (app.replay !== r) return;
  if (layout) {
    app.replayLayout = layout;
    terrain.setLayout(layout);
    track.set(layout.track, layout.race);
    app.objects = new SceneObjects(scene, layout.objects);
    app.objectMeshes = app.objects.meshes.length;
    buildVehicles(first, layout.vehicles || []);
  } else {
    addEvent(`replay ${name}: ${r.sceneError}; drawn on flat ground`, 'w');
    const layouts = first.vehicles.map((v) => (v.spin.length === 4 && /sedan/i.test(v.name) ? sedanLayout(v.name) : defaultLayout(v.name)));
    buildVehicles(first, layouts);
    const v0 = first.vehicles[0], drop = layouts[0].road_car ? 0.55 : 1;
    terrain.flat(v0.p[0], v0.p[1], v0.p[2] - drop);
  }
  world.sky.visible = true;
  // laps (the race's events): a jump to each lap's start
  const laps = await lapsAsked;
  if (app.replay !== r) return;
  const lapSelect = $('tl-laps');
  lapSelect.replaceChildren(...[{ label: laps.length ? 'jump to lap' : 'no laps', t: null }, ...laps.map((l) => ({
    label: `car ${l.car + 1} lap ${l.lap}  ${l.lap_time.toFixed(3)} s${l.best ? ' (best)' : ''}`, t: l.start,
  }))].map((l) => {
    const o = document.createElement('option');
    o.value = l.t === null ? '' : String(l.t);
    o.textContent = l.label;
    return o;
  }));
  lapSelect.classList.toggle('hidden', !laps.length);
  $('tl-follow').replaceChildren(...first.vehicles.map((v, i) => {
    const o = document.createElement('option');
    o.value = String(i);
    o.textContent = v.name;
    return o;
  }));
  r.playing = true;
}
function closeReplay(toLobby = true) {
  if (!app.replay) return;
  app.replay = null;
  app.replayLayout = null;
  $('timeline').classList.add('hidden');
  if (toLobby) {
    clearScene();
    history.replaceState(null, '', '/');
    showLobby(true);
  }
}
$('tl-play').addEventListener('click', () => app.replay && app.replay.toggle());
$('tl-start').addEventListener('click', () => app.replay && app.replay.seek(app.replay.t0));
$('tl-back').addEventListener('click', () => app.replay && app.replay.jump(-10));
$('tl-fwd').addEventListener('click', () => app.replay && app.replay.jump(10));
$('tl-scrub').addEventListener('input', (e) => {
  const r = app.replay;
  if (r) r.seek(r.t0 + (r.t1 - r.t0) * (parseFloat(e.target.value) / 1000));
});
$('tl-speed').addEventListener('change', (e) => { if (app.replay) app.replay.speed = parseFloat(e.target.value); });
$('tl-follow').addEventListener('change', (e) => { app.followed = parseInt(e.target.value, 10) || 0; });
$('tl-laps').addEventListener('change', (e) => {
  const r = app.replay, t = parseFloat(e.target.value);
  if (r && Number.isFinite(t)) r.seek(t);
  e.target.value = '';
});
$('tl-camera').addEventListener('click', () => toggleCamera());
$('tl-close').addEventListener('click', () => closeReplay(true));
window.addEventListener('keydown', (e) => {
  const r = app.replay;
  if (!r || (e.target && ['INPUT', 'SELECT'].includes(e.target.tagName) && e.key !== ' ')) return;
  if (e.key === ' ') { r.toggle(); e.preventDefault(); }
  else if (e.key === 'ArrowLeft') r.jump(-5);
  else if (e.key === 'ArrowRight') r.jump(5);
});
function updateTimeline(r) {
  $('tl-play').textContent = r.playing ? 'pause' : 'play';
  $('tl-time').textContent = `${(r.t - r.t0).toFixed(2)} / ${(r.t1 - r.t0).toFixed(2)} s`;
  const scrub = $('tl-scrub');
  if (document.activeElement !== scrub) scrub.value = String(r.t1 > r.t0 ? Math.round(1000 * (r.t - r.t0) / (r.t1 - r.t0)) : 0);
}

// ---- the frame loop ------------------------------------------------------------------
let lastFrame = performance.now(), fpsCount = 0, fpsStart = lastFrame, lastSimT = null, frameSum = 0;

function drawState(s, wallDt) {
  const simDt = lastSimT === null ? 0 : Math.max(0, Math.min(0.5, Math.abs(s.t - lastSimT)));
  lastSimT = s.t;
  const car = (i) => (app.car && app.car.session === s.session ? app.car.cars.find((c) => c.vehicle === i) || null : null);
  s.vehicles.forEach((v, i) => {
    const vehicle = app.vehicles[i];
    if (!vehicle) return;
    const own = app.role === 'drive' && i === app.vehicle && !app.replay;
    const rc = car(i);
    // brake lights: the car state's applied brake, else the own controls, else (replay) the deceleration
    const braking = rc ? null : own ? input.c.brake > 0.05 : app.replay ? !!v.braking : null;
    vehicle.update(v, simDt, own ? input.c.steer * GROUNDSIM_FULL_LOCK : null, rc, braking);
    skids.update(i, vehicle, v, rc);
  });
  if (app.objects) app.objects.update(s.objects);
  if (!app.replay) race.frame(s);
  const mine = s.vehicles[app.followed];
  if (mine) {
    if (app.layout && !app.replay && terrain.needsRefresh(mine.p[0], mine.p[1]) && !app.groundPending) {
      app.groundPending = true;
      setTimeout(() => { app.groundPending = false; }, 500);
      net.send({ op: 'ground', cx: mine.p[0], cy: mine.p[1] });
    }
    // a replay's ground comes from the recording's scene (GET .../ground)
    if (app.replayLayout && app.replay && terrain.needsRefresh(mine.p[0], mine.p[1]) && !app.groundPending) {
      const r = app.replay;
      app.groundPending = true;
      r.ground(mine.p[0], mine.p[1]).then((g) => {
        app.groundPending = false;
        if (g && app.replay === r) { terrain.show(g); app.groundGrids++; }
      });
    }
    const followed = app.vehicles[app.followed];
    rig.place(mine, followed ? followed.size : 3, wallDt);
    world.follow(mine.p);
  }
  updateHud(s, mine, { gear: app.role === 'drive' && !app.replay ? input.c.gear : null, rate: app.replay ? app.replay.speed : playback.rate });
}

// Dynamic resolution: every pixel now shows ground or sky, and a slow
// renderer (software WebGL: SwiftShader draws a 1280 x 720 frame in about a
// second on a busy 2-core machine) draws fewer pixels rather than fewer
// frames; a fast one goes back up to the display's ratio.
function adaptResolution(fps) {
  const r = world.renderer.getPixelRatio(), max = Math.min(2, window.devicePixelRatio || 1);
  let next = r;
  if (fps < 24) next = Math.max(0.35, r * 0.75);
  else if (fps > 50) next = Math.min(max, r * 1.25);
  if (Math.abs(next - r) > 1e-3) {
    world.renderer.setPixelRatio(next);
    world.render();  // a resized canvas is blank until drawn: never leave it so
  }
  app.pixelRatio = next;
}

world.renderer.setAnimationLoop(() => {
  const now = performance.now();
  // the playback clock takes the whole wall time (a slow renderer must not
  // make it fall behind); camera smoothing takes at most 0.1 s a frame
  const wallDt = (now - lastFrame) / 1000;
  lastFrame = now;
  let s;
  if (app.replay) {
    s = app.replay.frame(wallDt);
    updateTimeline(app.replay);
    if (s && app.vehicles.length !== s.vehicles.length) s = null;  // layouts not built yet
  } else {
    s = playback.frame(wallDt);
    driver.drive(app.lastState && app.lastState.vehicles[app.vehicle]);
    // the own car from the local run, ahead by the round trip (predict.js);
    // the others stay on the playback clock
    const own = prediction.frame(wallDt, lag.rttS(), playback.rate, now);
    if (s && own && s.vehicles[app.vehicle]) {
      s.vehicles[app.vehicle] = { ...s.vehicles[app.vehicle], p: own.p, q: own.q, v: own.v, w: own.w, speed: Math.hypot(...own.v) };
    }
  }
  if (s) drawState(s, wallDt);
  else if (rig.mode === 'free') rig.place(null, 3, 0);
  for (const fn of app.frameListeners) fn(s, now);
  hits.frame(wallDt);
  const t0 = performance.now();
  if (DRAW) world.render();
  frameSum += performance.now() - t0;
  app.frames++;
  fpsCount++;
  if (now - fpsStart > 1000) {
    app.fps = (1000 * fpsCount) / (now - fpsStart);
    app.frameMs = frameSum / fpsCount;  // the render call's CPU time per frame
    fpsCount = 0; frameSum = 0; fpsStart = now;
    if (ADAPT && DRAW && (app.session || app.replay)) adaptResolution(app.fps);
  }
});
showLobby(true);

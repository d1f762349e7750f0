// The replay view: a recorded session (replay.js) drawn on a timeline
// (play, seek, jump, speed, the car followed, a jump to each lap), opened
// from the lobby or a replay's link. The replay open is the session's
// (session.js: replayOpened / replayClosed).
import { $ } from './app.js';
import { takeLinked } from './link.js';
import { Replay } from './replay.js';
import { defaultLayout, sedanLayout } from './vehicle.js';
import { session, replayOpened, replayScene, replayClosed, follow } from './session.js';
import { world, terrain, track, rig, buildCars, placeObjects } from './stage.js';
import { net, clearScene } from './live.js';
import { addEvent, clearEvents } from './hud.js';
import { showLobby } from './lobby.js';
import { toggleCamera } from './controls.js';

const option = (value, text) => {
  const o = document.createElement('option');
  o.value = value;
  o.textContent = text;
  return o;
};

export async function openReplay(name, rsession) {
  if (session.id) net.send({ op: 'leave' });
  clearScene();
  clearEvents();
  // the link's replay, asked for at load, or a new one
  const pre = takeLinked(name, rsession);
  const r = pre ? pre.r : new Replay(name, rsession);
  replayOpened(r);  // no live session meanwhile, the first car followed
  showLobby(false);
  for (const id of ['hud', 'events']) $(id).classList.remove('hidden');
  for (const id of ['topbar', 'help']) $(id).classList.add('hidden');
  $('timeline').classList.remove('hidden');
  $('tl-title').textContent = `${name} / ${rsession}`;
  $('hud-session').textContent = rsession;
  $('hud-role').textContent = 'replay';
  const q = new URLSearchParams({ replay: name, rsession: rsession });
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
  if (session.replay !== r) return;
  const first = r.frame(0);
  if (!first) return addEvent(`replay ${name}: no states`, 'e');
  // the scene as the session had it (its scenario, attached to the file):
  // ground, track, objects and the cars' layouts; else, where the file holds
  // no scenario, road cars (four wheels, "sedan" in the name) are drawn as
  // sedans and others as the report's car, on flat ground below the first car
  const layout = await sceneAsked;
  if (session.replay !== r) return;
  if (layout) {
    replayScene(layout);
    terrain.setLayout(layout);
    track.set(layout.track, layout.race);
    placeObjects(layout.objects);
    buildCars(first, layout.vehicles || []);
  } else {
    addEvent(`replay ${name}: ${r.sceneError}; drawn on flat ground`, 'w');
    const layouts = first.vehicles.map((v) => (v.spin.length === 4 && /sedan/i.test(v.name) ? sedanLayout(v.name) : defaultLayout(v.name)));
    buildCars(first, layouts);
    const v0 = first.vehicles[0], drop = layouts[0].road_car ? 0.55 : 1;
    terrain.flat(v0.p[0], v0.p[1], v0.p[2] - drop);
  }
  world.sky.visible = true;
  // laps (the race's events): a jump to each lap's start
  const laps = await lapsAsked;
  if (session.replay !== r) return;
  const lapSelect = $('tl-laps');
  lapSelect.replaceChildren(...[{ label: laps.length ? 'jump to lap' : 'no laps', t: null }, ...laps.map((l) => ({
    label: `car ${l.car + 1} lap ${l.lap}  ${l.lap_time.toFixed(3)} s${l.best ? ' (best)' : ''}`, t: l.start,
  }))].map((l) => option(l.t === null ? '' : String(l.t), l.label)));
  lapSelect.classList.toggle('hidden', !laps.length);
  $('tl-follow').replaceChildren(...first.vehicles.map((v, i) => option(String(i), v.name)));
  r.playing = true;
}

export function closeReplay(toLobby = true) {
  if (!session.replay) return;
  replayClosed();
  $('timeline').classList.add('hidden');
  if (toLobby) {
    clearScene();
    history.replaceState(null, '', '/');
    showLobby(true);
  }
}

// the timeline's controls and keys (space, arrows)
export function wireTimeline() {
  const replay = () => session.replay;
  $('tl-play').addEventListener('click', () => replay() && replay().toggle());
  $('tl-start').addEventListener('click', () => replay() && replay().seek(replay().t0));
  $('tl-back').addEventListener('click', () => replay() && replay().jump(-10));
  $('tl-fwd').addEventListener('click', () => replay() && replay().jump(10));
  $('tl-scrub').addEventListener('input', (e) => {
    const r = replay();
    if (r) r.seek(r.t0 + (r.t1 - r.t0) * (parseFloat(e.target.value) / 1000));
  });
  $('tl-speed').addEventListener('change', (e) => { if (replay()) replay().speed = parseFloat(e.target.value); });
  $('tl-follow').addEventListener('change', (e) => { follow(parseInt(e.target.value, 10) || 0); });
  $('tl-laps').addEventListener('change', (e) => {
    const r = replay(), t = parseFloat(e.target.value);
    if (r && Number.isFinite(t)) r.seek(t);
    e.target.value = '';
  });
  $('tl-camera').addEventListener('click', () => toggleCamera());
  $('tl-close').addEventListener('click', () => closeReplay(true));
  window.addEventListener('keydown', (e) => {
    const r = replay();
    if (!r || (e.target && ['INPUT', 'SELECT'].includes(e.target.tagName) && e.key !== ' ')) return;
    if (e.key === ' ') { r.toggle(); e.preventDefault(); }
    else if (e.key === 'ArrowLeft') r.jump(-5);
    else if (e.key === 'ArrowRight') r.jump(5);
  });
}

// per frame of a replay: the play button, the time, the scrubber
export function updateTimeline(r) {
  $('tl-play').textContent = r.playing ? 'pause' : 'play';
  $('tl-time').textContent = `${(r.t - r.t0).toFixed(2)} / ${(r.t1 - r.t0).toFixed(2)} s`;
  const scrub = $('tl-scrub');
  if (document.activeElement !== scrub) scrub.value = String(r.t1 > r.t0 ? Math.round(1000 * (r.t - r.t0) / (r.t1 - r.t0)) : 0);
}

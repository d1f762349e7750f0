/* global GROUNDSIM_FULL_LOCK */  // the full lock (rad), defined at bundle time from kFullLockRad (web/CMakeLists.txt)
// The frame loop, at the display's rate (renderer.setAnimationLoop): the
// state to draw (the replay's at its playhead, else the playback's with the
// own car from the prediction), the cars, obstacles, race, ground requests,
// camera and HUD placed for it, then the render. Owns the frame counts and
// rates tests read and the listeners called after each frame.
import { DRAW, ADAPT } from './link.js';
import { session } from './session.js';
import { world, skids, hits, race, rig, drawn } from './stage.js';
import { playback, prediction, lag } from './live.js';
import { input, driver } from './controls.js';
import { groundNear } from './ground.js';
import { updateHud } from './hud.js';
import { updateTimeline } from './timeline.js';

let frames = 0, fps = 0, frameMs = 0, pixelRatio = 1;
let listeners = [];  // fn(drawn state, now ms) after each frame's drawState (tests)
export const frameStats = {
  get frames() { return frames; },
  get fps() { return fps; },
  get frameMs() { return frameMs; },  // the render call's CPU time per frame
  get pixelRatio() { return pixelRatio; },
  get frameListeners() { return listeners; },
};
export function setFrameListeners(a) { listeners = a; }

let lastFrame = performance.now(), fpsCount = 0, fpsStart = lastFrame, lastSimT = null, frameSum = 0;

function drawState(s, wallDt) {
  const simDt = lastSimT === null ? 0 : Math.max(0, Math.min(0.5, Math.abs(s.t - lastSimT)));
  lastSimT = s.t;
  const cars = drawn.cars, replay = session.replay;
  s.vehicles.forEach((v, i) => {
    const vehicle = cars[i];
    if (!vehicle) return;
    const own = session.own(i);
    const rc = session.roadCar(s.session, i);
    // brake lights: the car state's applied brake, else the own controls, else (replay) the deceleration
    const braking = rc ? null : own ? input.c.brake > 0.05 : replay ? !!v.braking : null;
    vehicle.update(v, simDt, own ? input.c.steer * GROUNDSIM_FULL_LOCK : null, rc, braking);
    skids.update(i, vehicle, v, rc);
  });
  if (drawn.objects) drawn.objects.update(s.objects);
  if (!replay) race.frame(s);
  const mine = s.vehicles[session.followed];
  if (mine) {
    groundNear(mine);
    const followed = cars[session.followed];
    rig.place(mine, followed ? followed.size : 3, wallDt);
    world.follow(mine.p);
  }
  updateHud(s, mine, {
    gear: session.driving ? input.c.gear : null, rate: replay ? replay.speed : playback.rate,
    car: cars[session.followed], fps, frameMs,
  });
}

// Dynamic resolution: every pixel now shows ground or sky, and a slow
// renderer (software WebGL: SwiftShader draws a 1280 x 720 frame in about a
// second on a busy 2-core machine) draws fewer pixels rather than fewer
// frames; a fast one goes back up to the display's ratio.
function adaptResolution() {
  const r = world.renderer.getPixelRatio(), max = Math.min(2, window.devicePixelRatio || 1);
  let next = r;
  if (fps < 24) next = Math.max(0.35, r * 0.75);
  else if (fps > 50) next = Math.min(max, r * 1.25);
  if (Math.abs(next - r) > 1e-3) {
    world.renderer.setPixelRatio(next);
    world.render();  // a resized canvas is blank until drawn: never leave it so
  }
  pixelRatio = next;
}

function frame() {
  const now = performance.now();
  // the playback clock takes the whole wall time (a slow renderer must not
  // make it fall behind); camera smoothing takes at most 0.1 s a frame
  const wallDt = (now - lastFrame) / 1000;
  lastFrame = now;
  let s;
  const replay = session.replay;
  if (replay) {
    s = replay.frame(wallDt);
    updateTimeline(replay);
    if (s && drawn.cars.length !== s.vehicles.length) s = null;  // layouts not built yet
  } else {
    s = playback.frame(wallDt);
    const { lastState, vehicle } = session;
    driver.drive(lastState && lastState.vehicles[vehicle]);
    // the own car from the local run, ahead by the round trip (predict.js);
    // the others stay on the playback clock
    const own = prediction.frame(wallDt, lag.rttS(), playback.rate, now);
    if (s && own && s.vehicles[vehicle]) {
      s.vehicles[vehicle] = { ...s.vehicles[vehicle], p: own.p, q: own.q, v: own.v, w: own.w, speed: Math.hypot(...own.v) };
    }
  }
  if (s) drawState(s, wallDt);
  else if (rig.mode === 'free') rig.place(null, 3, 0);
  for (const fn of listeners) fn(s, now);
  hits.frame(wallDt);
  const t0 = performance.now();
  if (DRAW) world.render();
  frameSum += performance.now() - t0;
  frames++;
  fpsCount++;
  if (now - fpsStart > 1000) {
    fps = (1000 * fpsCount) / (now - fpsStart);
    frameMs = frameSum / fpsCount;  // the render call's CPU time per frame
    fpsCount = 0; frameSum = 0; fpsStart = now;
    if (ADAPT && DRAW && (session.id || session.replay)) adaptResolution();
  }
}

export function startLoop() { world.renderer.setAnimationLoop(frame); }

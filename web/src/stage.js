// The scene drawn, made once as the page loads: the renderer and its world
// (render.js: scene, camera, sky, sun, fog), the ground to the horizon
// (terrain.js), a race's track and HUD (track.js, race.js), hits, tyre
// marks, the cameras; and what this module owns and changes: the cars
// drawn (vehicle.js: one per car of the state, in its colour, with its
// player's name), the scenario's obstacles (objects.js) and figure 1 on or
// off. Others read them through `drawn`.
import { $, COLORS } from './app.js';
import { session, playersNamed } from './session.js';
import { World } from './render.js';
import { Terrain } from './terrain.js';
import { Vehicle, defaultLayout } from './vehicle.js';
import { SceneObjects } from './objects.js';
import { HitEffects } from './hits.js';
import { SkidMarks } from './skids.js';
import { CameraRig } from './camera.js';
import { RaceView } from './race.js';
import { TrackRibbon } from './track.js';

export const world = new World($('view'));
export const { scene, camera } = world;
export const terrain = new Terrain(scene);
export const hits = new HitEffects(scene, $('hud-hits'));
export const skids = new SkidMarks(scene);
export const rig = new CameraRig(camera, world.renderer.domElement);
export const race = new RaceView(scene, terrain);  // races: HUD, gates, ghost (race.js, ghost.js)
export const track = new TrackRibbon(scene);  // the race's track, drawn from its centre line (track.js)

let cars = [];          // Vehicle per car of the state drawn
let objects = null, objectMeshes = 0;  // the scenario's obstacles as drawn
let figure = false;     // the report's figure 1 (points and springs) drawn over the bodies (key F)

export const drawn = {
  get cars() { return cars; },
  get objects() { return objects; },
  get objectMeshes() { return objectMeshes; },
  get figure() { return figure; },
};

// nothing drawn: no cars, obstacles, marks, race, track, ground or sky
export function clear() {
  for (const v of cars) v.dispose(scene);
  cars = [];
  if (objects) objects.dispose();
  objects = null;
  objectMeshes = 0;
  hits.reset();
  skids.reset();
  race.dispose();
  track.clear();
  playersNamed([]);
  terrain.clear();
  world.sky.visible = false;
}

// the scenario's obstacles (a layout's `objects`)
export function placeObjects(list) {
  objects = new SceneObjects(scene, list);
  objectMeshes = objects.meshes.length;
}

// each car in its colour with its name (the own one marked) above it
export function buildCars(state, layouts = session.layout ? session.layout.vehicles : []) {
  for (const v of cars) v.dispose(scene);
  const players = session.replay ? [] : session.players || [];
  cars = state.vehicles.map((vs, i) => {
    const name = `${players[i] || vs.name}${session.own(i) ? ' (you)' : ''}`;
    const v = new Vehicle(scene, layouts[i] || defaultLayout(vs.name), COLORS[i % COLORS.length], name);
    v.setFigure(figure);
    return v;
  });
  if (!session.layout && !session.replay && state.vehicles.length) {
    const p = state.vehicles[0].p;
    terrain.flat(p[0], p[1], p[2] - 1);  // the report car's wheel radius
    world.sky.visible = true;
  }
}

// the players' names of the session shown (the lobby's "players", a name
// per car): above the cars, on the leaderboard
export function namePlayers(players) {
  playersNamed(players);
  const last = session.lastState;
  cars.forEach((v, i) => {
    const base = players[i] || (last && last.vehicles[i] ? last.vehicles[i].name : v.name);
    v.setName(`${base}${session.own(i) ? ' (you)' : ''}`);
  });
  race.renderBoard();
}

export function toggleFigure() {
  figure = !figure;
  for (const v of cars) v.setFigure(figure);
}

// The page's shared state: one object, `app`, that every module reads and
// writes, and the only global the page sets: window.groundsim = app, for the
// browser tests and the latency benchmark (docs/game.md lists the fields
// they read). Constants shared by several modules live here too.

export const $ = (id) => document.getElementById(id);
export const STATUS = { 1: 'running', 2: 'paused', 3: 'finished', 4: 'diverged', 5: 'stopped' };
export const HEALTH = { 0: 'ok', 1: 'non-finite', 2: 'penetration', 3: 'speed', 4: 'energy' };
// one colour per car, by its index in the session
export const COLORS = [0xc8372d, 0x2f6fd0, 0x3fa34d, 0xe0a030, 0x8e4fc4, 0x2fb0b0, 0xd8d8d8, 0x303438];

export const app = {
  session: null, role: null, vehicle: -1, layout: null, note: '',
  vehicles: [], events: [], lobby: null, configs: [], scenarios: [], cameraMode: 'chase',
  frames: 0, fps: 0, frameMs: 0, pixelRatio: 1, lastState: null, states: 0, groundGrids: 0, controlsSent: 0, errors: [],
  followed: 0, lastControls: null, stateListeners: [],
  frameListeners: [],  // fn(drawn state, now ms) after each frame's drawState (tests)
  prediction: null,    // the own car's prediction (predict.js): active, reason, lead, error, drawn ...
  net: null,           // round trip to the bridge (lag.js): rtt (median ms), rttLast, lagging
  car: null,  // the newest {"op":"car"} of the session: its road cars' gear, rpm, applied controls
  objects: null, objectMeshes: 0,  // the scenario's obstacles as drawn (objects.js)
  contacts: 0, hits: null, hitEvents: 0,  // contact states received, hits shown (hits.shown), "hit: " events
  figure: false,  // the report's figure 1 (points and springs) drawn over the bodies (key F)
  replay: null,   // the replay view (replay.js) while one is open
  terrain: null, three: null, skids: null,
  track: null,      // the race's track as drawn (track.js)
  playerNames: [],  // the session's players by car (the lobby's "players": a name, "" unnamed, null free)
  previews: {},     // the lobby cards' preview messages, by scenario id (preview.js)
  shared: null,     // the last session link the share button gave
  send: () => {},
};
window.groundsim = app;

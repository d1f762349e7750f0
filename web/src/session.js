// The session the page shows: a live one joined on the bridge (its id, the
// page's role and car in it, its layout, the join's note, the newest state
// and road-car message) or a recorded one on the timeline (the Replay and
// its scene), and the car the view follows in either. Its fields change
// here only, through the calls below (join.js on the bridge's join and
// leave, timeline.js for replays, live.js per message, stage.js for the
// players' names); every module reads
// them through `session`.

let id = null, role = null, vehicle = -1, layout = null, note = '';
let followed = 0;
let car = null;        // the newest {"op":"car"} of the session: its road cars' gear, rpm, applied controls
let lastState = null, states = 0;
let replay = null, replayLayout = null;  // the replay open (replay.js) and its recorded scene
let listeners = [];    // fn(state message, now ms) per state received
let carListeners = []; // fn(car message) per road-car message of the session
let players = [];      // the session's players by car (the lobby's "players": a name, "" unnamed, null free)

export const session = {
  get id() { return id; },
  get role() { return role; },
  get vehicle() { return vehicle; },
  get layout() { return layout; },
  get note() { return note; },
  get followed() { return followed; },
  get car() { return car; },
  get lastState() { return lastState; },
  get states() { return states; },
  get replay() { return replay; },
  get replayLayout() { return replayLayout; },
  get stateListeners() { return listeners; },
  get carListeners() { return carListeners; },
  get players() { return players; },
  // the page drives its car live (not spectating, no replay open)
  get driving() { return role === 'drive' && !replay; },
  // car i is the page's own, driven live
  own(i) { return role === 'drive' && i === vehicle && !replay; },
  // the road-car message's entry of car i for a state of session s, or null
  roadCar(s, i) { return car && car.session === s ? car.cars.find((c) => c.vehicle === i) || null : null; },
};

// the bridge's `joined`, following car `follow`
export function joined(m, follow) {
  id = m.session; role = m.role; vehicle = m.vehicle; layout = m.layout; note = m.note;
  followed = follow;
}
export function left() { id = null; }
export function follow(i) { followed = i; }
// a replay opened: no live session
export function replayOpened(r) {
  id = null; role = null; layout = null; vehicle = -1; car = null;
  replay = r;
  followed = 0;
}
export function replayScene(l) { replayLayout = l; }
export function replayClosed() { replay = null; replayLayout = null; }

export function playersNamed(list) { players = list; }
export function carReceived(m) {
  car = m;
  for (const fn of carListeners) fn(m);
}
export function stateReceived(m) {
  lastState = m;
  states++;
}
// the listeners of each state received (tests add theirs: window.groundsim.stateListeners)
export function addStateListener(fn) { listeners.push(fn); }
export function setStateListeners(a) { listeners = a; }
// the listeners of each road-car message (tests: window.groundsim.carListeners)
export function setCarListeners(a) { carListeners = a; }
export function notifyState(m) { for (const fn of listeners) fn(m, performance.now()); }

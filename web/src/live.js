// The live session's stream from the bridge: the WebSocket (net.js), the
// states smoothed for drawing (interp.js), the own car predicted ahead of
// them (predict.js), the round trip (lag.js), and the handlers of the
// messages that feed the session shown (state, car, contact, event, error:
// main.js hands them their ops). Owns the counts tests read: contact
// states received, ended hits reported, the bridge's refusals.
import { $ } from './app.js';
import { Connection } from './net.js';
import { Playback } from './interp.js';
import { Prediction } from './predict.js';
import { LagMeter } from './lag.js';
import { session, stateReceived, notifyState, carReceived } from './session.js';
import { drawn, hits, race, buildCars, clear } from './stage.js';
import { addEvent } from './hud.js';

export const playback = new Playback();
export const net = new Connection(`${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws`);
export const prediction = new Prediction();
export const lag = new LagMeter(net);

let contacts = 0, hitEvents = 0;
let errors = [];  // the bridge's {"op":"error"} refusals, as received
export const received = {
  get contacts() { return contacts; },
  get hitEvents() { return hitEvents; },
  get errors() { return errors; },
};
export function setErrors(a) { errors = a; }  // a test's fresh list (window.groundsim.errors = [])

// no session shown: the scene cleared, the stream and the prediction stopped
export function clearScene() {
  clear();
  playback.reset();
  prediction.stop('no session');
}

export function onState(m) {
  if (m.session !== session.id || session.replay) return;
  playback.push(m, performance.now() / 1000);
  prediction.onState(m, performance.now());
  stateReceived(m);
  if (drawn.cars.length !== m.vehicles.length) buildCars(m);
  notifyState(m);
}
export function onCar(m) { if (m.session === session.id) carReceived(m); }
export function onContact(m) {
  if (m.session !== session.id) return;
  contacts++;
  playback.pushContact(m);
  hits.onContact(m);
}
export function onEvent(m) {
  if (race.onEvent(m)) return;  // "race: {json}" (race.js)
  const cls = m.severity >= 2 ? 'e' : m.severity === 1 ? 'w' : 'i';
  if (typeof m.reason === 'string' && m.reason.startsWith('hit: ')) {
    // an ended hit: the HUD named it while it lasted; one short line here
    hitEvents++;
    if (m.session === session.id) hits.onEndedHit(m);
    const pair = m.reason.split(' at (')[0], peak = m.reason.match(/peak force ([0-9.e+-]+) N/);
    const hard = m.reason.endsWith('(hard)') ? ' (hard)' : '';
    return addEvent(`t=${m.t.toFixed(2)} s  ${pair}${peak ? `, peak ${(parseFloat(peak[1]) / 1000).toFixed(1)} kN` : ''}${hard}`, cls);
  }
  addEvent(`t=${m.t.toFixed(2)} s  ${cls === 'e' ? 'error' : cls === 'w' ? 'warning' : 'info'} ${m.code}: ${m.reason}`, cls);
}
export function onError(m) {
  errors.push(m);
  const text = `${m.request || 'message'} refused${m.field ? ' at ' + m.field : ''}: ${m.reason}`;
  if ($('lobby').classList.contains('hidden')) addEvent(text, 'e'); else $('lobby-error').textContent = text;
}

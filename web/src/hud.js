// The heads-up display while a session or a replay is shown: speed, gear
// and rpm, times, the session's status and health, the live error estimate
// (a session with a tolerance), wheel loads and travel, frame rate; and the
// event lines at the bottom left.
import { $, STATUS, HEALTH } from './app.js';
import { session } from './session.js';

let events = [];  // the event lines shown, oldest first: {text, cls}
export const eventLines = () => events;

export function addEvent(text, cls) {
  events.push({ text, cls });
  if (events.length > 6) events.shift();
  $('events').innerHTML = events.map((e) => `<div class="${e.cls}">${e.text.replace(/</g, '&lt;')}</div>`).join('');
}

export function clearEvents() {
  events = [];
  $('events').innerHTML = '';
}

// s: the state drawn; v: the followed vehicle in it; gear: the page's own
// gear (its input) when it drives a car that reports none; rate: real-time
// factor; car: the followed car as drawn (a Vehicle); fps, frameMs: the
// frame loop's rate and render time (loop.js)
export function updateHud(s, v, { gear = null, rate = null, car = null, fps = 0, frameMs = 0 } = {}) {
  if (!v) return;
  $('hud-speed').textContent = (Math.hypot(...v.v) * 3.6).toFixed(1);
  // a road car reports its engaged gear and engine rpm; other vehicles have
  // neither: the page's own gear and the wheels' mean spin stand in
  const rc = session.roadCar(s.session, session.followed);
  if (rc) {
    $('hud-gear').textContent = rc.gear > 0 ? String(rc.gear) : rc.gear < 0 ? 'R' : 'N';
    $('hud-rpm').textContent = rc.rpm.toFixed(0);
  } else {
    $('hud-gear').textContent = gear === null ? '-' : gear > 0 ? 'D' : gear < 0 ? 'R' : 'N';
    const spins = v.spin.length ? v.spin.reduce((a, x) => a + Math.abs(x), 0) / v.spin.length : 0;
    $('hud-rpm').textContent = (spins * 60 / (2 * Math.PI)).toFixed(0);
  }
  $('hud-time').textContent = `${s.t.toFixed(2)} s`;
  $('hud-rtf').textContent = rate === null ? '-' : rate.toFixed(2);
  const st = $('status');
  st.textContent = STATUS[s.status] || s.status;
  st.className = s.status === 4 ? 'bad' : s.status !== 1 ? 'warn' : '';
  $('hud-health').textContent = HEALTH[s.health] || s.health;
  // the live error estimate of a session run to a tolerance (docs/accuracy.md); -1 or absent: none
  const est = typeof s.error_estimate === 'number' && s.error_estimate >= 0 ? s.error_estimate : null;
  $('hud-error-row').classList.toggle('hidden', est === null);
  if (est !== null) $('hud-error').textContent = `~${(100 * est).toPrecision(2)}% (live estimate)`;
  $('hud-wheels').textContent = `${v.N.map((n) => n.toFixed(1)).join(' ')} N`;
  $('hud-travel').textContent = car ? `${car.wheels.map((w) => (1000 * w.lift).toFixed(3)).join(' ')} mm` : '-';
  $('hud-fps').textContent = `${fps.toFixed(0)} frames/s, ${frameMs.toFixed(1)} ms`;
  $('btn-pause').textContent = s.status === 2 ? 'resume' : 'pause';
}

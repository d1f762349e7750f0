// Joining: the lobby's join, create and replay choices sent to the bridge
// under the player's name, the session of the page's link joined again on
// each connection, and the bridge's answers: `joined` shows the session
// (its ground, race, track, obstacles, the own car predicted), `left`
// goes back to the lobby.
import { $ } from './app.js';
import { session, joined, left } from './session.js';
import { world, terrain, race, track, rig, placeObjects } from './stage.js';
import { net, prediction, clearScene } from './live.js';
import { addEvent } from './hud.js';
import { showLobby, wireLobby, playerName } from './lobby.js';
import { touch } from './controls.js';
import { openReplay, closeReplay } from './timeline.js';

// the replay the page's link names, if any
function linkedReplay() {
  const q = new URLSearchParams(location.search);
  return q.get('replay') && q.get('rsession') ? [q.get('replay'), q.get('rsession')] : null;
}

// the connection (again): the link's replay, or its session spectated
export function onOpen() {
  const q = new URLSearchParams(location.search);
  if (session.replay) return;
  const replay = linkedReplay();
  if (replay) return openReplay(...replay);
  const want = q.get('session');
  const who = playerName() ? { player: playerName() } : {};
  if (want && !session.id) net.send({ op: 'join', session: want, role: 'spectate', ...who });
  else if (session.id) net.send({ op: 'join', session: session.id, role: 'spectate', ...who });
}

export function onJoined(m) {
  closeReplay(false);
  clearScene();
  const q = new URLSearchParams(location.search);
  // a spectator may follow any car (?follow=k: a bot, another player)
  const want = parseInt(q.get('follow'), 10), cars = ((m.layout && m.layout.vehicles) || []).length;
  joined(m, m.role !== 'drive' && want >= 0 && want < cars ? want : Math.max(0, m.vehicle));
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
  placeObjects(m.layout && m.layout.objects);
  rig.set('chase');
  if (touch) touch.show(m.role === 'drive');
  if (m.role === 'drive') prediction.start(m.session, m.vehicle, m.scenario, m.scale);
  else prediction.stop('spectating');
}

export function onLeft() {
  left();
  clearScene();
  showLobby(true);
  // a replay's link opens it at once: it reads the recording over HTTP and
  // needs no WebSocket (onOpen leaves it be)
  const replay = linkedReplay();
  if (replay) openReplay(...replay);
}

// the lobby's choices, under the player's name
export function wireJoin() {
  const named = (m) => (playerName() ? { ...m, player: playerName() } : m);
  wireLobby({
    join: (id, role) => net.send(named({ op: 'join', session: id, role })),
    create: (config, vehicles, extra = {}) => net.send(named({ op: 'create', config, vehicles, drive: true, ...extra })),
    replay: (name, rsession) => openReplay(name, rsession),
    preview: (config) => net.send({ op: 'preview', config }),
  });
}

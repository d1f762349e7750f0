// The lobby: a card per shipped scenario (its picture, drawn by the page
// from the ground the bridge samples (preview.js), its description, the
// cars it hosts, and its sessions under way: free cars, who is in, join /
// spectate / copy link; "race" creates one and drives it), the player's
// name (kept in localStorage), sessions on the bus (drive or spectate), the
// scenarios as a table with the create row, and the recordings the bridge
// serves (replay). Rows and cards are updated in place: one rebuilt every
// heartbeat would eat clicks.
import { $, STATUS } from './app.js';
import { drawPreview } from './preview.js';

// what the bridge told of itself: its scenario files (`configs`) and
// scenarios (welcome), the newest lobby message, the cards' preview
// messages by scenario id, the recordings it serves
let configs = [], scenarios = [], last = null, recordings = undefined;
const previews = {};
export const lobby = {
  get configs() { return configs; },
  get scenarios() { return scenarios; },
  get last() { return last; },
  get previews() { return previews; },
  get recordings() { return recordings; },
};

const NAME_KEY = 'groundsim.player';
// the player's name as others see it ('' : none given)
export function playerName() {
  return ($('player-name') && $('player-name').value.trim()) || '';
}
// a session's link to share
export const shareLink = (id) => `${location.origin}/?session=${id}`;

// Copies text to the clipboard (the async API where the page may, else a
// selected field and execCommand); true when it went.
export async function copyText(text, field) {
  try {
    await navigator.clipboard.writeText(text);
    return true;
  } catch {
    if (!field) return false;
    field.value = text;
    field.select();
    try { return document.execCommand('copy'); } catch { return false; }
  }
}

const carsText = (s) => (s.max_cars > s.min_cars ? `${s.min_cars}-${s.max_cars} cars` : `${s.min_cars} car${s.min_cars === 1 ? '' : 's'}`);
const scenarioById = (id) => scenarios.find((s) => s.id === id);

export function showLobby(show) {
  $('lobby').classList.toggle('hidden', !show);
  for (const id of ['hud', 'events', 'topbar', 'help']) $(id).classList.toggle('hidden', show);
  if (show) refreshRecordings();
}

// {"op":"welcome"}: the scenarios the bridge offers
export function onWelcome(m) {
  configs = m.configs;
  // a bridge before the scenario list sent file names only
  scenarios = m.scenarios || m.configs.map((id) => ({ id, name: '', description: '', vehicles: 1, min_cars: 1, max_cars: 1 }));
  renderScenarios();
}

// {"op":"lobby"}: the sessions on the bus
export function onLobby(m) {
  last = m;
  renderLobby();
}
// the players by car of session id, as the newest lobby message has them ([] when unknown)
export function playersOf(id) {
  const x = id && last ? last.sessions.find((e) => e.id === id) : null;
  return (x && x.players) || [];
}

// The shipped scenarios: a row each (id, cars it hosts, description) and
// the same in the drop-down; a click on a row picks it.
function renderScenarios() {
  const sel = $('create-config'), body = $('lobby-scenarios'), keep = sel.value;
  sel.replaceChildren(...scenarios.map((s) => {
    const o = document.createElement('option');
    o.value = s.id;
    o.textContent = `${s.id} (${carsText(s)})`;
    return o;
  }));
  body.replaceChildren(...scenarios.map((s) => {
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
  renderCards();
}

// ---- cards ----------------------------------------------------------------------------
let handlers = null;
const previewAsked = new Set();
const defaultCars = (s) => Math.min(s.max_cars, Math.max(s.vehicles, s.min_cars, 2));
const esc = (t) => String(t).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' })[c]);

function renderCards() {
  const box = $('cards');
  box.replaceChildren(...scenarios.map((s) => {
    const card = document.createElement('div');
    card.className = 'card';
    card.dataset.config = s.id;
    card.innerHTML = `<canvas class="pic" width="240" height="120"></canvas>
      <div class="title"><b></b> <span class="cid"></span></div>
      <div class="desc"></div>
      <div class="cap"></div>
      <div class="live"></div>
      <div class="go"><span class="cars-label">cars</span> <input class="ncars" type="number" style="width:3em">
        <span class="bots-box hidden">bots <select class="nbots"></select> <select class="skill">
          <option value="0.6">easy</option><option value="0.8">medium</option><option value="1" selected>hard</option></select></span>
        <button data-act="race">race</button></div>`;
    card.querySelector('.title b').textContent = s.name || s.id;
    card.querySelector('.cid').textContent = s.id;
    card.querySelector('.desc').textContent = s.description || '(no description)';
    card.querySelector('.cap').textContent = carsText(s);
    const n = card.querySelector('.ncars');
    Object.assign(n, { min: s.min_cars, max: s.max_cars, value: String(defaultCars(s)) });
    n.disabled = s.max_cars === s.min_cars;
    if (s.race) {
      // a race: players and computer drivers (docs/drivers.md); the bots' cars come on top of the players'
      card.querySelector('.cars-label').textContent = 'players';
      card.querySelector('.bots-box').classList.remove('hidden');
      const players = Math.max(1, s.vehicles - (s.bots || 0));
      Object.assign(n, { min: 1, max: Math.max(1, s.max_cars - (s.bots || 0)), value: String(players) });
      n.disabled = false;
      const most = Math.max(0, Math.min(7, (s.grid || 8) - 1));
      const sel = card.querySelector('.nbots');
      for (let k = 0; k <= most; k += 1) sel.add(new Option(String(k), String(k), false, k === (s.bots || 0)));
    }
    if (previews[s.id]) drawPreview(card.querySelector('canvas'), previews[s.id]);
    return card;
  }));
  // pictures as the cards come into view (the bridge samples each scenario's ground once)
  const io = new IntersectionObserver((entries) => {
    for (const e of entries) {
      if (!e.isIntersecting) continue;
      const id = e.target.dataset.config;
      io.unobserve(e.target);
      if (!previewAsked.has(id) && handlers) { previewAsked.add(id); handlers.preview(id); }
    }
  }, { root: $('lobby') });
  for (const c of box.children) io.observe(c);
  renderLive();
}

// {"op":"preview"}: the card's picture
export function onPreview(m) {
  previews[m.config] = m;
  const card = $('cards').querySelector(`.card[data-config="${CSS.escape(m.config)}"]`);
  if (card && !m.error) card.dataset.drawn = String(drawPreview(card.querySelector('canvas'), m));
}

// a session's line on its scenario's card: id, free cars, who is in, buttons
function liveLine(x) {
  const players = x.players || [], names = players.filter((p) => p !== null).map((p) => p || 'anonymous');
  const free = players.length ? players.filter((p) => p === null).length : null;
  const watching = (x.spectators || []).length;
  const who = names.length ? `in: ${names.join(', ')}` : 'no driver';
  return { text: `${free === null ? '' : `${free} of ${players.length} cars free · `}${who}${watching ? ` · ${watching} watching` : ''}`,
    acts: `${x.drivable ? 'join ' : ''}spectate link`, names };
}

function renderLive() {
  const sessions = (last && last.sessions) || [];
  for (const card of $('cards').children) {
    const s = scenarioById(card.dataset.config);
    const mine = s ? sessions.filter((x) => x.source === 'server' && x.name && x.name === s.name && !(x.num_envs > 0)) : [];
    const box = card.querySelector('.live'), ids = new Set(mine.map((x) => x.id));
    for (const row of [...box.children]) if (!ids.has(row.dataset.session)) row.remove();
    for (const x of mine) {
      let row = box.querySelector(`div[data-session="${x.id}"]`);
      if (!row) {
        row = document.createElement('div');
        row.className = 'session';
        row.dataset.session = x.id;
        row.innerHTML = '<code></code> <span class="who"></span> <span class="acts"></span><input class="link" readonly>';
        box.appendChild(row);
      }
      const l = liveLine(x);
      row.querySelector('code').textContent = x.id;
      row.querySelector('.who').textContent = l.text;
      row.dataset.players = JSON.stringify(l.names);
      row.querySelector('.link').value = shareLink(x.id);
      const acts = row.querySelector('.acts');
      if (acts.dataset.acts !== l.acts) {
        acts.dataset.acts = l.acts;
        acts.innerHTML = l.acts.split(' ').map((a) => `<button data-act="${a}">${a === 'link' ? 'copy link' : esc(a)}</button>`).join('');
      }
    }
    card.classList.toggle('busy', mine.length > 0);
  }
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

function renderLobby() {
  const m = last;
  renderLive();
  $('lobby-server').textContent = m.server
    ? `server ${m.server.id}: ${m.server.sessions} sessions, ${m.server.workers} workers, load ${(100 * m.server.load).toFixed(0)} %`
    : 'no server heartbeat on this bus (sessions below are states seen on the bus)';
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
    const names = (x.players || []).filter((p) => p !== null).map((p) => p || 'anonymous');
    cells[5].title = names.length ? `in: ${names.join(', ')}` : '';
    const acts = (x.drivable ? 'drive ' : '') + 'spectate';
    if (cells[6].dataset.acts !== acts) {
      cells[6].dataset.acts = acts;
      cells[6].innerHTML = acts.split(' ').map((a) => `<button data-act="${a}">${a}</button>`).join('');
    }
  }
}

// GET /recordings: a row per recorded session, with a replay button; the
// section stays hidden when the bridge serves none.
export async function refreshRecordings() {
  let list = [];
  try {
    const r = await fetch('/recordings');
    if (r.ok) list = (await r.json()).recordings || [];
  } catch { /* no recordings served */ }
  recordings = list;
  $('replays').classList.toggle('hidden', list.length === 0);
  const rows = [];
  for (const f of list)
    for (const s of f.sessions || []) {
      const tr = document.createElement('tr');
      tr.dataset.recording = f.name;
      tr.dataset.session = s.id;
      tr.innerHTML = '<td></td><td><code></code></td><td></td><td></td><td class="act"><button data-act="replay">replay</button></td>';
      tr.children[0].textContent = f.name;
      tr.children[1].firstChild.textContent = s.id;
      tr.children[2].textContent = `${(s.t1 - s.t0).toFixed(1)} s`;
      tr.children[3].textContent = String(s.states);
      rows.push(tr);
    }
  $('lobby-replays').replaceChildren(...rows);
}

// handlers: {join(session, role), create(config, vehicles, extra), replay(name, session), preview(config)}
// (extra: a race's {bots, bot_skill})
export function wireLobby(h) {
  handlers = h;
  const name = $('player-name');
  try { name.value = localStorage.getItem(NAME_KEY) || ''; } catch { /* no storage */ }
  name.addEventListener('input', () => { try { localStorage.setItem(NAME_KEY, name.value.trim()); } catch { /* no storage */ } });
  $('cards').addEventListener('click', async (e) => {
    const act = e.target.dataset && e.target.dataset.act, card = e.target.closest('.card');
    if (!act || !card) return;
    const row = e.target.closest('.session');
    if (act === 'race') {
      const s = scenarioById(card.dataset.config);
      if (s.race) {
        // n players and the bots chosen: the bridge builds the grid (race.bots, withVehicles)
        const n = Math.max(1, parseInt(card.querySelector('.ncars').value, 10) || 1);
        const bots = parseInt(card.querySelector('.nbots').value, 10) || 0;
        const skill = parseFloat(card.querySelector('.skill').value) || 1;
        handlers.create(s.id, n, { bots, bot_skill: skill });
        return;
      }
      const n = Math.max(s.min_cars, Math.min(s.max_cars, parseInt(card.querySelector('.ncars').value, 10) || 1));
      handlers.create(s.id, n === s.vehicles ? 0 : n);
    } else if (act === 'join' && row) handlers.join(row.dataset.session, 'drive');
    else if (act === 'spectate' && row) handlers.join(row.dataset.session, 'spectate');
    else if (act === 'link' && row) {
      const field = row.querySelector('.link'), ok = await copyText(shareLink(row.dataset.session), field);
      field.classList.add('shown');
      e.target.textContent = ok ? 'copied' : 'copy the link';
    }
  });
  $('create-config').addEventListener('change', () => {
    pickScenario($('create-config').value);
    const row = $('lobby-scenarios').querySelector('tr.picked');
    if (row) row.scrollIntoView({ block: 'nearest' });
  });
  $('lobby-scenarios').addEventListener('click', (e) => {
    const row = e.target.closest('tr');
    if (row) pickScenario(row.dataset.config);
  });
  $('lobby-sessions').addEventListener('click', (e) => {
    const act = e.target.dataset && e.target.dataset.act;
    const row = e.target.closest('tr');
    if (act && row) handlers.join(row.dataset.session, act);
  });
  $('lobby-replays').addEventListener('click', (e) => {
    const row = e.target.closest('tr');
    if (e.target.dataset && e.target.dataset.act === 'replay' && row) handlers.replay(row.dataset.recording, row.dataset.session);
  });
  $('create-drive').addEventListener('click', () => {
    const s = scenarioById($('create-config').value);
    if (!s) return;
    const n = Math.max(s.min_cars, Math.min(s.max_cars, parseInt($('create-vehicles').value, 10) || 1));
    // vehicles 0: the scenario as it is; n: n copies of its car
    handlers.create(s.id, n === s.vehicles ? 0 : n);
  });
}

// The lobby: sessions on the bus (drive or spectate), the shipped
// scenarios to create a session from, and the recordings the bridge serves
// (replay). Rows are updated in place: a row rebuilt every heartbeat would
// eat clicks.
import { app, $, STATUS } from './app.js';

const carsText = (s) => (s.max_cars > s.min_cars ? `${s.min_cars}-${s.max_cars} cars` : `${s.min_cars} car${s.min_cars === 1 ? '' : 's'}`);
const scenarioById = (id) => app.scenarios.find((s) => s.id === id);

export function showLobby(show) {
  $('lobby').classList.toggle('hidden', !show);
  for (const id of ['hud', 'events', 'topbar', 'help']) $(id).classList.toggle('hidden', show);
  if (show) refreshRecordings();
}

// The shipped scenarios: a row each (id, cars it hosts, description) and
// the same in the drop-down; a click on a row picks it.
export function renderScenarios() {
  const sel = $('create-config'), body = $('lobby-scenarios'), keep = sel.value;
  sel.replaceChildren(...app.scenarios.map((s) => {
    const o = document.createElement('option');
    o.value = s.id;
    o.textContent = `${s.id} (${carsText(s)})`;
    return o;
  }));
  body.replaceChildren(...app.scenarios.map((s) => {
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

export function renderLobby() {
  const m = app.lobby;
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
  app.recordings = list;
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

// handlers: {join(session, role), create(config, vehicles), replay(name, session)}
export function wireLobby(handlers) {
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

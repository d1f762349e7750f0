// The lobby lists every shipped scenario, configs/**/*.json, by its path
// under configs/ ("plain.json", "tasks/speed.json"), each with its
// description (from its JSON) and the cars a session of it hosts; a click
// on a row picks it (drop-down and cars field follow). A scenario of a
// subfolder is created and driven by its id; a create asking for more cars
// than a scenario hosts, or naming a file that is not listed, is refused.
// The cards: one per shipped scenario with its description, capacity and a
// picture the page draws from the bridge's preview (the circuit's: its
// asphalt and grass, not one colour); the player's name is kept in
// localStorage across a reload; Ann races the circuit with 2 cars, Bob's
// card shows her in it with 1 of 2 cars free and he joins; both cards then
// list Ann and Bob with no car free, a spectator is counted; the copy-link
// button puts ORIGIN/?session=ID on the clipboard, and that link opened in
// a new page spectates the session.
import { readdirSync, readFileSync } from 'node:fs';
import { join } from 'node:path';
import * as h from './harness.mjs';

function shipped(dir, prefix = '') {
  const out = [];
  for (const e of readdirSync(join(dir, prefix), { withFileTypes: true })) {
    const id = prefix ? `${prefix}/${e.name}` : e.name;
    if (e.isDirectory()) out.push(...shipped(dir, id));
    else if (e.name.endsWith('.json')) out.push(id);
  }
  return out;
}

const { url } = await h.startServices();
await h.launch();
// the pages run without drawing the 3D view (?render=0: the lobby is DOM
// and 2D canvases; what is checked is the DOM and the pages' state)
const quiet = `${url}?render=0`;
const page = await h.newPage(quiet, { width: 1280, height: 900 });
const rows = await page.evaluate(() => [...document.querySelectorAll('#lobby-scenarios tr')].map((tr) => ({
  id: tr.dataset.config, cells: [...tr.children].map((td) => td.textContent), visible: tr.offsetParent !== null,
})));
const byId = new Map(rows.map((r) => [r.id, r]));
const files = shipped(h.CONFIGS);
console.log(`${rows.length} rows for ${files.length} files; e.g. ${JSON.stringify(rows.find((r) => r.id.includes('/')))}`);
for (const id of files) {
  const r = byId.get(id);
  if (!r) await h.fail(`${id} is not in the lobby`);
  const doc = JSON.parse(readFileSync(join(h.CONFIGS, id), 'utf8'));
  if (r.cells[0] !== id) await h.fail(`${id}'s row names ${r.cells[0]}`);
  if (!/^\d+(-\d+)? cars?$/.test(r.cells[1])) await h.fail(`${id}'s capacity reads "${r.cells[1]}"`);
  if (doc.description && r.cells[2] !== doc.description) await h.fail(`${id}'s description reads "${r.cells[2]}"`);
}
if (rows.length !== files.length) await h.fail(`${rows.length} rows for ${files.length} shipped scenarios`);
if (!rows.every((r) => r.visible)) await h.fail('a scenario row is not shown');
// the report's car on a plane: one per player, up to the bridge's 8
if (byId.get('plain.json').cells[1] !== '1-8 cars') await h.fail(`plain.json hosts "${byId.get('plain.json').cells[1]}"`);

// a click on a row picks it
const picked = await page.evaluate(() => {
  document.querySelector('#lobby-scenarios tr[data-config="tasks/speed.json"]').click();
  const n = document.getElementById('create-vehicles');
  return { value: document.getElementById('create-config').value, max: n.max, about: document.getElementById('create-about').textContent,
    marked: document.querySelector('#lobby-scenarios tr.picked').dataset.config };
});
console.log(`picked: ${JSON.stringify(picked)}`);
const speed = (await page.evaluate(() => window.groundsim.scenarios.find((s) => s.id === 'tasks/speed.json')));
if (picked.value !== 'tasks/speed.json' || picked.marked !== 'tasks/speed.json') await h.fail('a click did not pick the row');
if (picked.max !== String(speed.max_cars) || !picked.about.includes(speed.description)) await h.fail(`the picked scenario's cars and description: ${JSON.stringify(picked)}`);

// refused: a file that is not listed, a path out of configs/, more cars
// than the bridge offers, and (when one hosts fewer than 8) more than a
// scenario hosts
const errs = await page.evaluate(async () => {
  const g = window.groundsim;
  const few = g.scenarios.find((s) => s.max_cars < 8);
  g.errors = [];
  const bad = [{ op: 'create', config: 'tasks/nothing.json' }, { op: 'create', config: '../configs/plain.json' },
    { op: 'create', config: 'plain.json', vehicles: 9 }];
  if (few) bad.push({ op: 'create', config: few.id, vehicles: few.max_cars + 1 });
  for (const m of bad) g.send(m);
  const t0 = performance.now();
  while (g.errors.length < bad.length && performance.now() - t0 < 60000) await new Promise((r) => setTimeout(r, 50));
  return g.errors.map((e) => `${e.request} ${e.field}: ${e.reason}`);
});
console.log(`refused: ${JSON.stringify(errs)}`);
if (errs.length < 3 || !errs.every((e) => e.startsWith('create /config') || e.startsWith('create /vehicles')))
  await h.fail(`expected refused creates, got ${JSON.stringify(errs)}`);

// ---- cards, names, join, spectate, the link ------------------------------------------
const cards = await page.evaluate(() => [...document.querySelectorAll('#cards .card')].map((c) => ({
  id: c.dataset.config, desc: c.querySelector('.desc').textContent, cap: c.querySelector('.cap').textContent,
  race: !!c.querySelector('button[data-act="race"]') })));
if (cards.length !== files.length) await h.fail(`${cards.length} cards for ${files.length} shipped scenarios`);
for (const c of cards) {
  const doc = JSON.parse(readFileSync(join(h.CONFIGS, c.id), 'utf8'));
  if (doc.description && c.desc !== doc.description) await h.fail(`${c.id}'s card says "${c.desc}"`);
  if (c.cap !== byId.get(c.id).cells[1] || !c.race) await h.fail(`${c.id}'s card: ${JSON.stringify(c)}`);
}
// the circuit's picture: drawn once its card is in view, asphalt grey and grass green among its colours
await page.evaluate(() => document.querySelector('#cards .card[data-config="race/circuit.json"]').scrollIntoView());
const pic = await h.until('the circuit card\'s picture', () => page.evaluate(() => {
  const c = document.querySelector('#cards .card[data-config="race/circuit.json"]');
  if (c.dataset.drawn !== 'true') return null;
  const cv = c.querySelector('canvas'), d = cv.getContext('2d').getImageData(0, 0, cv.width, cv.height).data;
  let grey = 0, green = 0;
  const colours = new Set();
  for (let i = 0; i < d.length; i += 4) {
    const [r, g, b] = [d[i], d[i + 1], d[i + 2]];
    colours.add((r >> 3) << 10 | (g >> 3) << 5 | (b >> 3));
    if (Math.abs(r - g) < 12 && Math.abs(g - b) < 12 && r > 40 && r < 140) grey++;
    if (g > r + 15 && g > b + 15) green++;
  }
  return { grey: grey / (d.length / 4), green: green / (d.length / 4), colours: colours.size };
}), 60000, 200);
const took = await page.evaluate(() => Object.values(window.groundsim.previews).map((m) => `${m.config} ${m.ms} ms`));
console.log(`circuit card picture: ${(100 * pic.grey).toFixed(1)} % asphalt grey, ${(100 * pic.green).toFixed(1)} % green, ${pic.colours} colours; previews computed: ${took.join(', ')}`);
if (!(pic.grey > 0.03 && pic.green > 0.2 && pic.colours > 20)) await h.fail(`the circuit's picture: ${JSON.stringify(pic)}`);

// the name, kept across a reload
await page.fill('#player-name', 'Ann');
await page.goto(quiet);
await h.until('the page to reconnect', () => page.evaluate(() => window.groundsim && window.groundsim.configs.length > 0));
const kept = await page.evaluate(() => document.getElementById('player-name').value);
if (kept !== 'Ann') await h.fail(`the name after a reload: "${kept}"`);

const bob = await h.newPage(quiet, { width: 1280, height: 900 });
await bob.fill('#player-name', 'Bob');
const circuit = '#cards .card[data-config="race/circuit.json"]';
await page.fill(`${circuit} .ncars`, '2');
await page.click(`${circuit} button[data-act="race"]`);
await h.until('Ann driving', () => page.evaluate(() => window.groundsim.role === 'drive' && window.groundsim.states > 2), 60000);
const session = await page.evaluate(() => window.groundsim.session);
const line = (p, id) => p.evaluate(([sel, id]) => {
  const row = document.querySelector(`${sel} .session[data-session="${id}"]`);
  return row && { text: row.querySelector('.who').textContent, players: JSON.parse(row.dataset.players),
    acts: [...row.querySelectorAll('button')].map((b) => b.dataset.act), link: row.querySelector('.link').value };
}, [circuit, id]);
const seen = await h.until('Ann in the circuit card on Bob\'s page', async () => {
  const l = await line(bob, session);
  return l && l.players.includes('Ann') && l;
}, 30000, 100);
console.log(`Bob's card: ${session} "${seen.text}" ${JSON.stringify(seen.acts)}`);
if (!seen.text.startsWith('1 of 2 cars free') || JSON.stringify(seen.players) !== '["Ann"]' || !seen.acts.includes('join'))
  await h.fail(`Bob's card for ${session}: ${JSON.stringify(seen)}`);
await bob.click(`${circuit} .session[data-session="${session}"] button[data-act="join"]`);
await h.until('Bob driving', () => bob.evaluate((id) => window.groundsim.session === id && window.groundsim.role === 'drive', session), 60000);
const cid = await h.newPage(quiet, { width: 1280, height: 900 });
await cid.fill('#player-name', 'Cid');
await h.until('the session on Cid\'s card', () => line(cid, session), 30000, 100);
await cid.click(`${circuit} .session[data-session="${session}"] button[data-act="spectate"]`);
await h.until('Cid spectating', () => cid.evaluate((id) => window.groundsim.session === id && window.groundsim.role === 'spectate', session), 60000);
// a fourth browser, in the lobby (it may read the clipboard)
const lp = await h.newPage(quiet, { width: 1280, height: 900 });
await lp.context().grantPermissions(['clipboard-read', 'clipboard-write'], { origin: new URL(url).origin });
const full = await h.until('Ann and Bob in, one watching', async () => {
  const l = await line(lp, session);
  return l && JSON.stringify(l.players) === '["Ann","Bob"]' && l.text.includes('1 watching') && l;
}, 30000, 200);
console.log(`a fourth page's card: "${full.text}" ${JSON.stringify(full.acts)}`);
if (!full.text.startsWith('0 of 2 cars free') || full.acts.includes('join')) await h.fail(`the full session's card: ${JSON.stringify(full)}`);
// the names above the cars on Ann's page (the lobby names the session's players)
const labels = await h.until('the players\' names above the cars', () => page.evaluate(() => {
  const names = window.groundsim.vehicles.map((v) => v.name);
  return names.length === 2 && names[0] === 'Ann (you)' && names[1] === 'Bob' && names;
}), 30000, 100).catch(async () => h.fail(`names above Ann's cars: ${JSON.stringify(await page.evaluate(() => window.groundsim.vehicles.map((v) => v.name)))}`));

// the link: copied by the card's button, opened in a new page
await lp.click(`${circuit} .session[data-session="${session}"] button[data-act="link"]`);
const copied = await h.until('the copied link', () => lp.evaluate(async () => {
  try { return await navigator.clipboard.readText(); } catch (e) { return null; }
}), 60000, 100);
const want = `${new URL(url).origin}/?session=${session}`;
console.log(`copied: ${copied}`);
if (copied !== want) await h.fail(`copy link gave "${copied}", want ${want}`);
const friend = await h.newPage(copied, { width: 960, height: 540 });
await h.until('the link to open the session', () => friend.evaluate((id) => window.groundsim.session === id && window.groundsim.role === 'spectate' && window.groundsim.states > 2, session), 60000);
await page.evaluate(() => { window.groundsim.shared = null; document.getElementById('btn-share').click(); });
const shared = await h.until('the share button\'s link', () => page.evaluate(() => window.groundsim.shared), 60000, 50).catch(() => null);
if (shared !== want) await h.fail(`the in-game share button gave ${shared}`);
console.log(`names above Ann's cars: ${JSON.stringify(labels)}; the link opened spectating ${session}`);
for (const p of [bob, cid, friend, lp]) await p.context().close();
await page.click('#btn-lobby');
await h.until('the lobby', () => page.evaluate(() => !window.groundsim.session), 60000, 50);

// a scenario of a subfolder, by its id
await h.createAndDrive(page, 'tasks/speed.json');
const name = await page.evaluate(() => window.groundsim.lastState.vehicles.length);
await h.pass(`${rows.length} scenarios listed and as cards; Ann and Bob in one circuit session on every card, the link shared; tasks/speed.json driven (${name} car)`);

// The lobby lists every shipped scenario, configs/**/*.json, by its path
// under configs/ ("plain.json", "tasks/speed.json"), each with its
// description (from its JSON) and the cars a session of it hosts; a click
// on a row picks it (drop-down and cars field follow). A scenario of a
// subfolder is created and driven by its id; a create asking for more cars
// than a scenario hosts, or naming a file that is not listed, is refused.
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
const page = await h.newPage(url, { width: 1280, height: 900 });
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

// a scenario of a subfolder, by its id
await h.createAndDrive(page, 'tasks/speed.json');
const name = await page.evaluate(() => window.groundsim.lastState.vehicles.length);
await h.pass(`${rows.length} scenarios listed with descriptions and capacities; tasks/speed.json driven (${name} car)`);

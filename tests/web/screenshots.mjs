// The pictures of docs/img (not a test): the lobby's cards, the circuit
// with two players on its ribbon, their crash, and the rally stage, taken
// in headless Chromium at 1280 x 720 at full resolution (?res=fixed).
//
//   cmake --build build --target groundsim-server groundsim groundsim-web
//   GROUNDSIM_SERVER=build/server/lcm/groundsim-server GROUNDSIM_WEB=build/web/bridge/groundsim-web \
//   GROUNDSIM_CLI=build/client/groundsim GROUNDSIM_CONFIG_DIR=$PWD/configs \
//   GROUNDSIM_WEB_NODE_MODULES=$PWD/build/web/node_modules \
//     tests/integration/netns_run.sh node tests/web/screenshots.mjs docs/img
//
// Writes lobby.jpg, race-circuit.jpg, race-crash.jpg and race-rally.jpg.
import * as h from './harness.mjs';

const out = process.argv[2] || '.';
const shot = (p, name) => p.screenshot({ path: `${out}/${name}`, type: 'jpeg', quality: 82 });
const { url } = await h.startServices();
await h.launch();
const size = { width: 1280, height: 720 };
const ann = await h.newPage(`${url}?res=fixed`, size);
await ann.fill('#player-name', 'Ann');

const circuit = '#cards .card[data-config="race/circuit.json"]';

// Bob waits in the lobby (not drawing: one software renderer is enough)
const bob = await h.newPage(`${url}?render=0`, size);
await bob.fill('#player-name', 'Bob');
await ann.fill(`${circuit} .ncars`, '2');
await ann.click(`${circuit} button[data-act="race"]`);
await h.until('Ann driving', () => ann.evaluate(() => window.groundsim.role === 'drive' && window.groundsim.states > 2), 60000);
const session = await ann.evaluate(() => window.groundsim.session);
await h.until('the session on Bob\'s card', () => bob.evaluate(([sel, id]) => !!document.querySelector(`${sel} .session[data-session="${id}"] button[data-act="join"]`), [circuit, session]), 30000);
// the lobby picture from Bob's page (it does not draw 3D, the lobby is DOM
// and 2D canvases; a third page would wait for Ann's software renderer)
await bob.evaluate((sel) => document.querySelector(sel).scrollIntoView({ block: 'start' }), circuit);
await h.until('pictures and Ann\'s session', () => bob.evaluate(([sel, id]) => document.querySelector(`${sel}`).dataset.drawn === 'true' &&
  !!document.querySelector(`${sel} .session[data-session="${id}"]`), [circuit, session]), 60000, 200);
await bob.waitForTimeout(1500);
await shot(bob, 'lobby.jpg');
await bob.click(`${circuit} .session[data-session="${session}"] button[data-act="join"]`);
await h.until('Bob driving', () => bob.evaluate((id) => window.groundsim.session === id && window.groundsim.role === 'drive', session), 60000);
await h.until('Bob\'s name on Ann\'s page', () => ann.evaluate(() => window.groundsim.vehicles.some((v) => v.name === 'Bob')), 30000);
const x = (p, i) => p.evaluate((k) => window.groundsim.lastState.vehicles[k].p[0], i);
await ann.keyboard.down('w');
await bob.keyboard.down('w');
await h.until('past the start line', async () => (await x(ann, 0)) > 6, 60000, 50);
await ann.keyboard.up('w');
await bob.keyboard.up('w');
await shot(ann, 'race-circuit.jpg');
await ann.keyboard.down('w');
await bob.keyboard.down('w');
await h.until('past gate 1', async () => (await x(ann, 0)) > 44 && (await x(ann, 1)) > 44, 60000, 50);
await bob.keyboard.down('a');
await h.until('the crash', () => ann.evaluate(() => window.groundsim.hits.shown.some((s) => [s.a, s.b].sort().join() === 'sedan-1,sedan-2')), 30000, 20)
  .finally(async () => { await bob.keyboard.up('a'); });
await shot(ann, 'race-crash.jpg');
await ann.keyboard.up('w');
await bob.keyboard.up('w');
await bob.context().close();

// the rally stage, at speed
await ann.click('#btn-lobby');
await h.until('the lobby', () => ann.evaluate(() => !window.groundsim.session), 20000, 50);
await h.createAndDrive(ann, 'race/rally_stage.json');
await ann.keyboard.down('w');
await h.until('the end of the first asphalt', async () => (await x(ann, 0)) > 230, 180000, 100);
await ann.keyboard.up('w');
await shot(ann, 'race-rally.jpg');
await h.pass(`pictures in ${out}`);

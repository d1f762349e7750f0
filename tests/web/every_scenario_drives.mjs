// Every scenario the lobby offers creates and drives, as a player would:
// pick it, "create and drive", hold W. The bridge sends the files a
// scenario names (heightfields) with the create, so the hill scenarios work
// against a server started with no options (docs/protocol.md, Assets). Each
// session must publish states after the create, its ground grid must
// arrive and be built into the page's terrain (no "does not build here"),
// and W must move the throttle the page sends; the session is paused before
// the next one (2 cores) and must show it paused (or finished: a finished
// scenario cannot pause, nor does it step), else the test fails; the page
// goes back to the lobby. The page runs without drawing (?render=0): what
// is checked is its state; the drawing of grounds is web.PageDrawsGroundAndCar's.
import * as h from './harness.mjs';

// one page creates every shipped scenario in turn: more creates a minute than an
// anonymous player's (groundsim-web --browser-creates)
const { url } = await h.startServices({ bridgeArgs: ['--browser-creates', '0'] });
await h.launch();
const page = await h.newPage(`${url}?render=0`, { width: 1280, height: 900 });
const ids = await page.evaluate(() => [...document.querySelectorAll('#create-config option')].map((o) => o.value));
if (ids.length < 15) await h.fail(`the lobby offers ${ids.length} scenarios`);
const hills = ids.filter((id) => /hills|goal/.test(id));
if (hills.length < 3) await h.fail(`the heightfield scenarios are not all offered: ${hills}`);
const results = [];
for (const id of ids) {
  const before = await page.evaluate(() => window.groundsim.session);
  const grids = await page.evaluate(() => window.groundsim.groundGrids);
  await page.selectOption('#create-config', id);
  await page.fill('#create-vehicles', '1');
  await page.click('#create-drive');
  await h.until(`${id} to be created and driven`, () => page.evaluate((b) => window.groundsim.session !== b &&
    window.groundsim.role === 'drive' && window.groundsim.states > 2, before), 60000).catch(async () => {
    const err = await page.evaluate(() => document.getElementById('lobby-error')?.textContent || '');
    await h.fail(`${id}: not created and driven (${err})`);
  });
  const session = await page.evaluate(() => window.groundsim.session);
  const note = await page.evaluate(() => window.groundsim.note || '');
  if (note) await h.fail(`${id}: ${note}`);
  await h.until(`${id}: its ground to be drawn`, () => page.evaluate((g) => window.groundsim.groundGrids > g, grids),
    20000).catch(() => h.fail(`${id}: no ground grid arrived`));
  const n0 = await page.evaluate(() => window.groundsim.states);
  await page.keyboard.down('w');
  await h.until(`${id}: W to reach the controls sent`, () => page.evaluate(() => window.groundsim.lastControls &&
    JSON.parse(window.groundsim.lastControls).throttle > 0), 5000, 20);
  // states keep coming while W is held: waited for, not a fixed 300 ms (a
  // page busy drawing under software WebGL on a loaded machine reads its
  // socket late)
  await h.until(`${id}: states while driving`, () => page.evaluate((n) => window.groundsim.states > n, n0), 10000, 20)
    .catch(async () => h.fail(`${id}: no states while driving (${n0} -> ${await page.evaluate(() => window.groundsim.states)})`));
  await page.keyboard.up('w');
  const n1 = await page.evaluate(() => window.groundsim.states);
  results.push(`${id} ${session} +${n1 - n0}`);
  await page.click('#btn-pause');
  // paused, or finished (a finished scenario cannot pause: it no longer
  // steps either); anything else, or no answer, fails
  const status = await h.until(`${id} to pause`, () => page.evaluate(() => [2, 3].includes(window.groundsim.lastState?.status) &&
    window.groundsim.lastState.status), 60000, 20).catch(async () => h.fail(`${id}: not paused after pause: status ${await page.evaluate(() => window.groundsim.lastState?.status)}`));
  results[results.length - 1] += status === 2 ? ' paused' : ' finished';
  console.log(results[results.length - 1]);
  await page.click('#btn-lobby');  // back to the lobby for the next one
  await h.until('the lobby', () => page.evaluate(() => window.groundsim.session === null &&
    !document.getElementById('lobby').classList.contains('hidden')), 10000);
}
await h.pass(`${ids.length} scenarios created and driven from the lobby`);

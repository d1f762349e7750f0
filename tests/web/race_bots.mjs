// Racing bots from the lobby, as a new player would: the circuit's card,
// 1 player and 3 bots at "medium", "race". Checked on the page, against
// the server's race events as the bridge forwards them:
//  - the session has 4 cars, the player's and three named bots
//    (ada-bot, bruno-bot, carla-bot), each listed on the leaderboard;
//  - with the player driving off the grid (W held), every bot starts
//    (crosses the start line) and at least one passes gate 3 of 10, on
//    its own, through the players' controls path;
//  - no bot is ever off track meanwhile.
// The page runs without drawing (?render=0): what is checked is its state
// and DOM. Every wait is for a condition in the server's events.
import * as h from './harness.mjs';

const { url } = await h.startServices();
await h.launch();
const page = await h.newPage(`${url}?render=0`, { width: 1280, height: 800 });
await page.fill('#player-name', 'Ann');
const circuit = '#cards .card[data-config="race/circuit.json"]';
await h.until('the bots choice on the race card', () => page.evaluate((sel) => {
  const box = document.querySelector(`${sel} .bots-box`);
  return !!box && !box.classList.contains('hidden') && document.querySelector(`${sel} .nbots`).options.length >= 4;
}, circuit), 30000);
await page.fill(`${circuit} .ncars`, '1');
await page.selectOption(`${circuit} .nbots`, '3');
await page.selectOption(`${circuit} .skill`, '0.8');
await page.click(`${circuit} button[data-act="race"]`);
await h.until('Ann driving', () => page.evaluate(() => window.groundsim.role === 'drive' && window.groundsim.states > 2), 60000);
const names = await page.evaluate(() => window.groundsim.vehicles.map((v) => v.name));
console.log(`cars: ${names.join(', ')}`);
if (names.length !== 4) await h.fail(`expected 4 cars (1 player, 3 bots), got ${names.length}`);
for (const bot of ['ada-bot', 'bruno-bot', 'carla-bot'])
  if (!names.includes(bot)) await h.fail(`no car named ${bot}`);
await h.until('the race layout', () => page.evaluate(() => window.groundsim.race.active), 30000);
await page.keyboard.down('w');
const events = () => page.evaluate(() => window.groundsim.race.events.filter((e) => typeof e.name === 'string' && e.name.endsWith('-bot')));
await h.until('every bot started', async () => new Set((await events()).filter((e) => e.type === 'start').map((e) => e.name)).size === 3, 120000, 200);
await h.until('a bot past gate 3', async () => (await events()).some((e) => e.type === 'gate' && e.gate >= 3), 120000, 200);
await page.keyboard.up('w');
await h.until('the leaderboard with the bots', () => page.evaluate(() => ['ada-bot', 'bruno-bot', 'carla-bot'].every((n) => document.body.innerText.includes(n))), 30000);
const bots = await events();
const off = bots.filter((e) => e.type === 'off_track' && e.on);
if (off.length > 0) await h.fail(`bots off track: ${off.map((e) => `${e.name} at ${e.t.toFixed(1)} s`).join(', ')}`);
const gates = bots.filter((e) => e.type === 'gate');
console.log(`${bots.length} race events of bots; gates passed: ${gates.map((e) => `${e.name} ${e.gate}`).join(', ')}`);
await h.pass('three bots raced from the lobby');

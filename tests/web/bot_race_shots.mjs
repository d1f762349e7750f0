// The pictures and the video of a race with bots in docs/img (not a test):
// the circuit from its lobby card with 1 player and 3 trained bots
// (race/circuit_trained.json), the player driving off the grid; a picture
// of the lobby's card with its bots choice, one of the grid at go, one of
// the pack in the first corner, and a video of the first 20 simulated
// seconds, taken in headless Chromium (software WebGL: a few frames a
// second, so the video is slow; its frames are the page's own).
//
//   cmake --build build --target groundsim-server groundsim groundsim-web
//   GROUNDSIM_SERVER=build/server/lcm/groundsim-server GROUNDSIM_WEB=build/web/bridge/groundsim-web \
//   GROUNDSIM_CLI=build/client/groundsim GROUNDSIM_CONFIG_DIR=$PWD/configs \
//   GROUNDSIM_WEB_NODE_MODULES=$PWD/build/web/node_modules \
//     tests/integration/netns_run.sh node tests/web/bot_race_shots.mjs docs/img
//
// Writes race-bots-lobby.jpg, race-bots-grid.jpg, race-bots-corner.jpg and race-bots.webm.
import { renameSync, mkdtempSync, readdirSync } from 'node:fs';
import { tmpdir } from 'node:os';
import * as h from './harness.mjs';

const out = process.argv[2] || '.';
const shot = (p, name) => p.screenshot({ path: `${out}/${name}`, type: 'jpeg', quality: 82 });
const { url } = await h.startServices();
await h.launch();
const videoDir = mkdtempSync(`${tmpdir()}/groundsim-video-`);
const size = { width: 960, height: 540 };
const page = await h.newPage(`${url}?res=fixed`, size, { recordVideo: { dir: videoDir, size } });
await page.fill('#player-name', 'Ann');
const card = '#cards .card[data-config="race/circuit_trained.json"]';
await h.until('the card with its bots choice', () => page.evaluate((sel) => !!document.querySelector(`${sel} .nbots`) &&
  document.querySelector(`${sel} .nbots`).options.length > 3, card), 60000);
await page.evaluate((sel) => document.querySelector(sel).scrollIntoView({ block: 'start' }), card);
await h.until('its picture', () => page.evaluate((sel) => document.querySelector(sel).dataset.drawn === 'true', card), 60000, 200);
await page.selectOption(`${card} .nbots`, '3');
await shot(page, 'race-bots-lobby.jpg');
await page.click(`${card} button[data-act="race"]`);
await h.until('Ann driving', () => page.evaluate(() => window.groundsim.role === 'drive' && window.groundsim.states > 2), 60000);
const t = () => page.evaluate(() => window.groundsim.lastState.t);
await h.until('go', async () => (await t()) > 3.2, 120000, 50);
await shot(page, 'race-bots-grid.jpg');
await page.keyboard.down('w');
await h.until('the first corner', async () => (await t()) > 9.0, 180000, 50);
await shot(page, 'race-bots-corner.jpg');
await h.until('20 s', async () => (await t()) > 20.0, 240000, 100);
await page.keyboard.up('w');
const video = page.video();
await page.context().close();
renameSync(await video.path(), `${out}/race-bots.webm`);
await h.pass(`pictures and video in ${out} (${readdirSync(videoDir).length} left in ${videoDir})`);

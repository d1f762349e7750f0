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
import { mkdtempSync, rmSync } from 'node:fs';
import { spawnSync } from 'node:child_process';
import { tmpdir } from 'node:os';
import * as h from './harness.mjs';

const out = process.argv[2] || '.';
const shot = (p, name) => p.screenshot({ path: `${out}/${name}`, type: 'jpeg', quality: 82 });
const { url } = await h.startServices();
await h.launch();
const frames = mkdtempSync(`${tmpdir()}/groundsim-frames-`);
const size = { width: 960, height: 540 };
const page = await h.newPage(`${url}?res=fixed&render=0`, size);
await page.fill('#player-name', 'Ann');
const card = '#cards .card[data-config="race/circuit_trained.json"]';
await h.until('the card with its bots choice', () => page.evaluate((sel) => !!document.querySelector(`${sel} .nbots`) &&
  document.querySelector(`${sel} .nbots`).options.length > 3, card), 60000);
await page.evaluate((sel) => document.querySelector(sel).scrollIntoView({ block: 'start' }), card);
await h.until('its picture', () => page.evaluate((sel) => document.querySelector(sel).dataset.drawn === 'true', card), 60000, 200);
await page.selectOption(`${card} .nbots`, '3');
await shot(page, 'race-bots-lobby.jpg');
await page.click(`${card} button[data-act="race"]`);
await h.until('Ann on the grid', () => page.evaluate(() => window.groundsim.role === 'drive' && window.groundsim.states > 2), 60000);
const session = await page.evaluate(() => window.groundsim.session);
// the spectator's page draws: it follows ada-bot (car 1)
const view = await h.newPage(`${url}?res=fixed&session=${session}&follow=1`, size);
await h.until('spectating ada-bot', () => view.evaluate(() => window.groundsim.role === 'spectate' && window.groundsim.states > 2), 60000);
const t = () => view.evaluate(() => window.groundsim.lastState.t);
await h.until('go', async () => (await t()) > 3.2, 120000, 50);
await shot(view, 'race-bots-grid.jpg');
let n = 0, cornerShot = false;
// the session's clock paused between frames: the video has a frame every
// 0.1 s of simulated time whatever the software renderer's pace
const start = await t();
for (let k = 0; k < 200; ++k) {
  await h.pause(page);
  await h.until('a new frame drawn', () => view.evaluate((at) => window.groundsim.lastState.t >= at, start + 0.1 * k), 30000, 50);
  await view.waitForTimeout(300);  // the page draws the state it has
  await view.screenshot({ path: `${frames}/f${String(n++).padStart(4, '0')}.jpg`, type: 'jpeg', quality: 80 });
  if (!cornerShot && (await t()) > 9.0) {
    await shot(view, 'race-bots-corner.jpg');
    cornerShot = true;
  }
  await h.resume(page);
  await h.until('0.1 s on', async () => (await t()) >= start + 0.1 * (k + 1), 30000, 20);
}
const enc = spawnSync('ffmpeg', ['-y', '-loglevel', 'error', '-framerate', '10', '-i', `${frames}/f%04d.jpg`,
  '-c:v', 'libvpx-vp9', '-b:v', '600k', '-pix_fmt', 'yuv420p', `${out}/race-bots.webm`], { encoding: 'utf8' });
rmSync(frames, { recursive: true, force: true });
if (enc.status !== 0) await h.fail(`ffmpeg: ${enc.stderr}`);
await h.pass(`pictures and a video of ${n} frames in ${out}`);

// A session replayed with lcm-logplayer can be watched: a log recorded with
// lcm-logger while a session ran (from its create, so the log holds the
// server's scenario_t) is played back with no server running; the lobby
// lists the session from its states on the bus, and /?session=ID draws it
// with its actual ground (the bridge built the scene from the logged
// scenario) and its states moving.
import { spawn } from 'node:child_process';
import { existsSync, mkdtempSync } from 'node:fs';
import { tmpdir } from 'node:os';
import * as h from './harness.mjs';

if (!existsSync('/usr/bin/lcm-logger') || !existsSync('/usr/bin/lcm-logplayer')) h.skip('no lcm-logger/lcm-logplayer (liblcm-bin)');
const log = `${mkdtempSync(`${tmpdir()}/groundsim-replay-`)}/session.lcmlog`;
// the bridge starts only after the recording: what it draws comes from the log
const server = await h.startServer();
const logger = spawn('/usr/bin/lcm-logger', [`--lcm-url=${h.LCM_URL}`, '--quiet', log], { stdio: 'ignore' });
await new Promise((r) => setTimeout(r, 500));
const id = h.cli('create', `${h.CONFIGS}/cosine.json`, '--duration', '-1').trim().split('\n').pop().trim();
await new Promise((r) => setTimeout(r, 6000));
h.cli('stop', id);
logger.kill('SIGINT');
await new Promise((r) => setTimeout(r, 500));
// the server goes: only the replay is left on the bus
server.kill('SIGTERM');
await new Promise((r) => setTimeout(r, 1000));
const { url } = await h.startBridge();

await h.launch();
// both pages up before the replay starts: it plays once, in real time
const page = await h.newPage(url);
const spectator = await h.newPage(`${url}?session=${id}`);
// replay only the states and the scenario (not the recorded requests)
const player = spawn('/usr/bin/lcm-logplayer', [`--lcm-url=${h.LCM_URL}`, '-e', `GROUNDSIM_STATE_.*|GROUNDSIM_SCENARIO`, log], { stdio: 'ignore' });
await h.until('the replayed session in the lobby', () => page.evaluate((sid) => !!document.querySelector(`tr[data-session="${sid}"]`), id));
await h.until('replayed states', () => spectator.evaluate(() => window.groundsim.states > 5));
await h.until('its ground', () => spectator.evaluate(() => window.groundsim.groundGrids > 0));
const info = await spectator.evaluate(() => ({ ground: window.groundsim.layout && window.groundsim.layout.ground, t: window.groundsim.lastState.t }));
player.kill();
console.log(JSON.stringify(info));
if (info.ground !== 'cosine') await h.fail(`the replay is not drawn on its cosine ground: ${JSON.stringify(info)}`);
await h.pass(`replay of ${id} spectated at t=${info.t}`);

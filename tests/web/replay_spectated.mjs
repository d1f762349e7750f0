// A session replayed with lcm-logplayer can be watched: a log recorded with
// lcm-logger while a session ran (from its create, so the log holds the
// server's scenario_t) is played back with no server running; the lobby
// lists the session from its states on the bus, and /?session=ID draws it
// with its actual ground (the bridge built the scene from the logged
// scenario) and its states moving. Every step waits for its condition: the
// logger hearing the bus, 5 s of the session's simulated time recorded, the
// logger and the server gone; the replay (real time, once) is played again
// while the pages have not yet seen what they check (a loaded machine's
// pages may need longer than the recording lasts). The pages run without
// drawing (?render=0): what is checked is their state and DOM.
import { spawn } from 'node:child_process';
import { existsSync, mkdtempSync, statSync } from 'node:fs';
import { tmpdir } from 'node:os';
import * as h from './harness.mjs';

if (!existsSync('/usr/bin/lcm-logger') || !existsSync('/usr/bin/lcm-logplayer')) h.skip('no lcm-logger/lcm-logplayer (liblcm-bin)');
const log = `${mkdtempSync(`${tmpdir()}/groundsim-replay-`)}/session.lcmlog`;
// the bridge starts only after the recording: what it draws comes from the log
const server = await h.startServer();
const logger = spawn('/usr/bin/lcm-logger', [`--lcm-url=${h.LCM_URL}`, '--quiet', '--flush-interval', '1', log], { stdio: 'ignore' });
const exited = (p) => new Promise((r) => { if (p.exitCode !== null || p.signalCode !== null) r(); else p.once('exit', () => r()); });
// the logger hears the bus (the server's heartbeat is in the log) before the create
await h.until('the logger to record the server', () => existsSync(log) && statSync(log).size > 0, 60000, 50);
const id = h.cli('create', `${h.CONFIGS}/cosine.json`, '--duration', '-1').trim().split('\n').pop().trim();
await h.until(`5 s of session ${id} on the bus`, () => h.serverTime(id) >= 5.0, 120000, 200);
h.cli('stop', id);
logger.kill('SIGINT');
await exited(logger);
// the server goes: only the replay is left on the bus
server.kill('SIGTERM');
await exited(server);
const { url } = await h.startBridge();

await h.launch();
// both pages up before the replay starts: it plays once, in real time
const page = await h.newPage(`${url}?render=0`);
const spectator = await h.newPage(`${url}?render=0&session=${id}`);
// replay only the states and the scenario (not the recorded requests),
// again each time it ends until the test is done
let player = null, plays = 0;
const play = () => {
  player = spawn('/usr/bin/lcm-logplayer', [`--lcm-url=${h.LCM_URL}`, '-e', `GROUNDSIM_STATE_.*|GROUNDSIM_SCENARIO`, log], { stdio: 'ignore' });
  ++plays;
  player.once('exit', () => { if (player) play(); });
};
play();
await h.until('the replayed session in the lobby', () => page.evaluate((sid) => !!document.querySelector(`tr[data-session="${sid}"]`), id));
await h.until('replayed states', () => spectator.evaluate(() => window.groundsim.states > 5));
await h.until('its ground', () => spectator.evaluate(() => window.groundsim.groundGrids > 0));
const info = await spectator.evaluate(() => ({ ground: window.groundsim.layout && window.groundsim.layout.ground, t: window.groundsim.lastState.t }));
const last = player;
player = null;
last.kill();
console.log(`${JSON.stringify(info)} (the log played ${plays} time(s))`);
if (info.ground !== 'cosine') await h.fail(`the replay is not drawn on its cosine ground: ${JSON.stringify(info)}`);
await h.pass(`replay of ${id} spectated at t=${info.t}`);

// A session created with `groundsim create` (not through the bridge) appears
// in the lobby from the server's heartbeat, with its scenario's name, can be
// opened by its link /?session=ID as a spectator, and is drawn with its
// actual ground: the bridge fetched the scenario from the server (op 9), so
// the page got the car's layout and a ground grid. The lobby offers no
// "drive" for it: the bridge holds no token for it.
// The pages run without drawing (?render=0): the lobby is DOM and the
// layout and ground grid the page's state.
import * as h from './harness.mjs';
import { CONFIGS } from './harness.mjs';

const { url } = await h.startServices();
await h.launch();
const page = await h.newPage(`${url}?render=0`);
const id = h.cli('create', `${CONFIGS}/parabola.json`, '--duration', '-1').trim().split('\n').pop().trim();
console.log(`groundsim create: ${id}`);
const row = await h.until('the session in the lobby', () => page.evaluate((sid) => {
  const tr = document.querySelector(`tr[data-session="${sid}"]`);
  // first seen from its states on the bus, then named by the next heartbeat
  return tr && tr.textContent.includes('parabola') && { text: tr.textContent, drive: !!tr.querySelector('button[data-act="drive"]') };
}, id));
console.log(`lobby row: ${row.text.replace(/\s+/g, ' ')}`);
if (!row.text.includes('parabola')) await h.fail('the lobby row does not name the scenario');
if (row.drive) await h.fail('the lobby offers to drive a session whose token the bridge does not hold');

const spectator = await h.newPage(`${url}?render=0&session=${id}`);
await h.until('states of the session', () => spectator.evaluate(() => window.groundsim.states > 2));
await h.until('its ground', () => spectator.evaluate(() => window.groundsim.groundGrids > 0));
const info = await spectator.evaluate(() => ({ role: window.groundsim.role, ground: window.groundsim.layout && window.groundsim.layout.ground, note: window.groundsim.note }));
console.log(JSON.stringify(info));
if (info.role !== 'spectate' || info.ground !== 'parabola') await h.fail(`not spectating its parabola: ${JSON.stringify(info)}`);
await h.pass(`session ${id} listed and spectated`);

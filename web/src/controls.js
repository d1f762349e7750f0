// The player's controls: keys, gamepads and wheels (input.js, the remap
// screen on key G), touch on a touch screen, the controls sent (drive.js),
// the input's one-shot actions and the top bar's buttons. Owns the last
// session link the share button gave.
import { $ } from './app.js';
import { Input, RemapScreen } from './input.js';
import { Driver } from './drive.js';
import { session } from './session.js';
import { rig, race, toggleFigure } from './stage.js';
import { net, playback, prediction } from './live.js';
import { addEvent } from './hud.js';
import { shareLink, copyText } from './lobby.js';

export const input = new Input(window);
const remap = new RemapScreen(input);  // gamepad / wheel controls (key G)
export const touch = matchMedia('(pointer: coarse)').matches || navigator.maxTouchPoints > 0 ? input.touchControls() : null;

let shared = null;  // the last session link the share button gave
export const sharedLink = () => shared;
export function setShared(link) { shared = link; }

export function toggleCamera() { rig.cycle(session.replay ? ['chase', 'orbit', 'free'] : ['chase', 'orbit']); }
function togglePause() {
  const s = playback.newest();
  net.send({ op: s && s.status === 2 ? 'resume' : 'pause' });
}

export const driver = new Driver(input, net, (c) => prediction.setControls(c), (a) => {
  if (a === 'camera') toggleCamera();
  else if (a === 'figure') toggleFigure();
  else if (a === 'remap') remap.toggle();
  else if (session.driving && a === 'reset') net.send({ op: 'reset' });
  else if (session.driving && a === 'respawn' && race.active) net.send({ op: 'respawn' });
  else if (session.driving && a === 'pause') togglePause();
});

// the top bar: share, lobby, camera, pause, reset
export function wireTopbar() {
  $('btn-share').addEventListener('click', async () => {
    if (!session.id) return;
    const link = shareLink(session.id), ok = await copyText(link);
    shared = link;
    addEvent(`${ok ? 'copied' : 'share'}: ${link}`, 'i');
  });
  $('btn-lobby').addEventListener('click', () => { net.send({ op: 'leave' }); history.replaceState(null, '', '/'); });
  $('btn-camera').addEventListener('click', () => toggleCamera());
  $('btn-pause').addEventListener('click', () => togglePause());
  $('btn-reset').addEventListener('click', () => net.send({ op: 'reset' }));
  rig.onChange = (mode) => { $('btn-camera').textContent = $('tl-camera').textContent = `camera: ${mode}`; };
}

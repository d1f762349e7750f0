// The page: wires its modules together and starts. Each piece of state
// lives in the module that owns it and changes only there; others read it
// through what that module exports.
//   link.js      the link's URL parameters; a replay's link asked for at once
//   session.js   the session shown (live or replay), the car followed, the newest state
//   stage.js     the scene (render.js, terrain.js, track.js, race.js and ghost.js,
//                hits.js, skids.js, camera.js) and the cars (vehicle.js) and obstacles (objects.js)
//   live.js      the bridge (net.js), smoothing (interp.js), prediction (predict.js,
//                WebAssembly), the round trip (lag.js), the stream's messages
//   ground.js    the ground near the followed car, asked for and shown
//   controls.js  keys, gamepad, touch (input.js), controls sent (drive.js), the top bar
//   lobby.js     sessions, scenarios (preview.js), recordings
//   join.js      join, create, the bridge's joined and left
//   timeline.js  a replay (replay.js) on its timeline
//   hud.js       the heads-up display and event lines
//   loop.js      the frame loop
//   hooks.js     window.groundsim for the tests (probe.js)
import './link.js';  // first: a replay's link asks for its recording before the renderer is made
import { addEvent } from './hud.js';
import { net, lag, onState, onCar, onContact, onEvent, onError } from './live.js';
import { namePlayers } from './stage.js';
import { session } from './session.js';
import { onGround } from './ground.js';
import { wireTopbar } from './controls.js';
import { showLobby, onWelcome, onLobby, onPreview, playersOf } from './lobby.js';
import { onOpen, onJoined, onLeft, wireJoin } from './join.js';
import { wireTimeline } from './timeline.js';
import { startLoop } from './loop.js';
import { exposeHooks } from './hooks.js';

// the bridge's messages, each to the module that owns what it changes
net.on('*', () => lag.heard());
net.on('pong', (m) => lag.onPong(m));
net.on('open', onOpen);
net.on('close', () => addEvent('connection to the bridge lost, reconnecting...', 'e'));
net.on('welcome', onWelcome);
net.on('lobby', (m) => { onLobby(m); namePlayers(playersOf(session.id)); });
net.on('preview', onPreview);
net.on('created', (m) => addEvent(`created session ${m.session}`, 'i'));
net.on('joined', onJoined);
net.on('left', onLeft);
net.on('ground', onGround);
net.on('state', onState);
net.on('car', onCar);
net.on('contact', onContact);
net.on('event', onEvent);
net.on('error', onError);
net.on('reply', (m) => addEvent(`${m.request}: ok`, 'i'));

wireJoin();
wireTopbar();
wireTimeline();
exposeHooks();
startLoop();
showLobby(true);

// window.groundsim, the only global the page sets: what the browser tests
// and the latency benchmark read (docs/game.md lists them), each a getter
// onto the module that owns it; the few a test sets (stateListeners,
// carListeners, frameListeners, errors, shared, groundPending) go to their
// owner's setter. Tests may add fields of their own to it (testPath, bench, ...).
import { probeHorizon } from './probe.js';
import { session, setStateListeners, setCarListeners } from './session.js';
import { world, scene, camera, terrain, hits, skids, race, track, rig, drawn } from './stage.js';
import { net, prediction, lag, received, setErrors } from './live.js';
import { ground, setPending } from './ground.js';
import { driver, sharedLink, setShared } from './controls.js';
import { frameStats, setFrameListeners } from './loop.js';
import { lobby } from './lobby.js';
import { eventLines } from './hud.js';

export function exposeHooks() {
  window.groundsim = {
    // the session shown (session.js)
    get session() { return session.id; },
    get role() { return session.role; },
    get vehicle() { return session.vehicle; },
    get layout() { return session.layout; },
    get note() { return session.note; },
    get followed() { return session.followed; },
    get car() { return session.car; },
    get lastState() { return session.lastState; },
    get states() { return session.states; },
    get replay() { return session.replay; },
    get replayLayout() { return session.replayLayout; },
    get playerNames() { return session.players; },
    get stateListeners() { return session.stateListeners; },
    set stateListeners(a) { setStateListeners(a); },
    get carListeners() { return session.carListeners; },  // fn(car message) per {"op":"car"} of the session
    set carListeners(a) { setCarListeners(a); },
    // the lobby (lobby.js)
    get configs() { return lobby.configs; },
    get scenarios() { return lobby.scenarios; },
    get lobby() { return lobby.last; },
    get previews() { return lobby.previews; },
    get recordings() { return lobby.recordings; },
    // the scene drawn (stage.js)
    get vehicles() { return drawn.cars; },
    get objects() { return drawn.objects; },
    get objectMeshes() { return drawn.objectMeshes; },
    get figure() { return drawn.figure; },
    get cameraMode() { return rig.mode; },
    three: { scene, camera, renderer: world.renderer, sky: world.sky, world },
    terrain, hits, skids, race, track,
    // the stream (live.js, predict.js, lag.js, ground.js)
    get contacts() { return received.contacts; },
    get hitEvents() { return received.hitEvents; },
    get errors() { return received.errors; },
    set errors(a) { setErrors(a); },
    get prediction() { return prediction.info; },
    get net() { return lag.info; },
    get groundGrids() { return ground.grids; },
    get groundPending() { return ground.pending; },
    set groundPending(on) { setPending(on); },
    // controls sent (drive.js), the share button (controls.js), the HUD's event lines (hud.js)
    get controlsSent() { return driver.controlsSent; },
    get lastControls() { return driver.lastControls; },
    get shared() { return sharedLink(); },
    set shared(link) { setShared(link); },
    get events() { return eventLines(); },
    // frames (loop.js)
    get frames() { return frameStats.frames; },
    get fps() { return frameStats.fps; },
    get frameMs() { return frameStats.frameMs; },
    get pixelRatio() { return frameStats.pixelRatio; },
    get frameListeners() { return frameStats.frameListeners; },
    set frameListeners(a) { setFrameListeners(a); },
    send: (m) => net.send(m),
    debug: { probeHorizon: (opts) => probeHorizon(world, opts) },
  };
}

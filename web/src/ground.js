// The ground near the followed car: the bridge's `ground` grids of a live
// session, asked for again when the car nears the edge of the one shown,
// and a replay's from its recorded scene (GET .../ground). Owns whether a
// request is under way (a test holds the page's requests with it:
// window.groundsim.groundPending) and how many grids were shown.
import { session } from './session.js';
import { terrain } from './stage.js';
import { net, prediction } from './live.js';

let pending = false, grids = 0;
export const ground = {
  get pending() { return pending; },
  get grids() { return grids; },
};
export function setPending(on) { pending = on; }

// {"op":"ground"}: the grid round the car
export function onGround(m) {
  if (m.session !== session.id) return;
  terrain.show(m);
  prediction.onGround(m);
  grids++;
}

// per drawn frame: the followed car's state `mine`
export function groundNear(mine) {
  if (session.layout && !session.replay && terrain.needsRefresh(mine.p[0], mine.p[1]) && !pending) {
    pending = true;
    setTimeout(() => { pending = false; }, 500);
    net.send({ op: 'ground', cx: mine.p[0], cy: mine.p[1] });
  }
  // a replay's ground comes from the recording's scene (GET .../ground)
  if (session.replayLayout && session.replay && terrain.needsRefresh(mine.p[0], mine.p[1]) && !pending) {
    const r = session.replay;
    pending = true;
    r.ground(mine.p[0], mine.p[1]).then((g) => {
      pending = false;
      if (g && session.replay === r) { terrain.show(g); grids++; }
    });
  }
}

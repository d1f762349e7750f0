// What the page's link asks for as the page loads (URL parameters; the
// session and replay links are read again where they are followed:
// join.js, timeline.js). Imported first by main.js: a replay's link asks
// for its recording before the renderer is made (a WebGL context takes a
// second in software), and the replay view takes it over once the page is
// up (takeLinked).
import { Replay } from './replay.js';

const q = new URLSearchParams(location.search);
// ?render=0 runs everything but the drawing (the latency benchmark isolates
// the network path from a software renderer's frame time with it)
export const DRAW = q.get('render') !== '0';
// ?res=fixed keeps the full resolution (screenshots); else it adapts (loop.js)
export const ADAPT = q.get('res') !== 'fixed';

const linked = (() => {
  const name = q.get('replay'), session = q.get('rsession');
  if (!name || !session) return null;
  const r = new Replay(name, session);
  return { r, opened: r.open(), scene: r.scene(), laps: r.laps(), used: false };
})();
if (linked) linked.opened.catch(() => {});  // reported by openReplay

// the link's replay as asked for at load, once, when it is `name`/`session`; else null
export function takeLinked(name, session) {
  if (!linked || linked.r.name !== name || linked.r.session !== session || linked.used) return null;
  linked.used = true;
  return linked;
}

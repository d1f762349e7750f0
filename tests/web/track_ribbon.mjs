// The race track drawn as a ribbon (web/src/track.js) from the scenario's
// track, checked against the scenario's own centre line and the ground's
// heights as the bridge solves them for the terrain (ground grids, 0.5 m):
//  - race/circuit.json with 8 cars: every 5th vertex of the ribbon lies
//    within the track's half width of the centre line (race layout, as in
//    the JSON); at each centre line point the ribbon is there across the
//    width (hw - 0.1 m to each side) and not beyond it (hw + 0.5 m);
//    at every ground-grid node under the ribbon (grids asked for at the
//    start, a corner and the back straight) the ribbon is 0 to 6 cm above
//    the ground (it lies 3 cm up); one frame with 8 cars costs at most 150
//    draw calls and 500k triangles (renderer.info);
//  - race/rally_stage.json: the same on the valley road, where the ground
//    climbs (grids at x = 100, 600 and 1300 m, tens of metres apart in
//    height) - a ribbon drawn flat or at the wrong heights fails.
// GROUNDSIM_SCREENSHOT=dir writes circuit and rally pictures there.
import * as h from './harness.mjs';

const { url } = await h.startServices();
await h.launch();
const page = await h.newPage(url, { width: 1280, height: 720 });

// every ground grid the page receives, kept for the checks
async function keepGrids() {
  await page.evaluate(() => {
    const g = window.groundsim, t = g.terrain;
    if (t.testKeep) return;
    t.testKeep = true;
    g.testGrids = [];
    const show = t.show.bind(t);
    t.show = (m) => { g.testGrids.push(m); show(m); };
  });
}

// asks for the grid around (x, y) and compares the ribbon with its nodes
async function checkOnGround(x, y) {
  // the page asks for the grid round its car when its grid is elsewhere: not meanwhile
  // (the bridge keeps only the newest request waiting)
  await page.evaluate(([x, y]) => {
    const g = window.groundsim;
    g.groundPending = true;
    g.testGrids = [];
    g.send({ op: 'ground', cx: x, cy: y });
  }, [x, y]);
  return h.until(`the ground grid at (${x}, ${y})`, () => page.evaluate(([x, y]) => {
    const g = window.groundsim;
    const grid = g.testGrids.find((m) => Math.abs(m.x0 + m.step * (m.n - 1) / 2 - x) < 1 && Math.abs(m.y0 + m.step * (m.n - 1) / 2 - y) < 1);
    if (!grid) return null;
    let nodes = 0, under = 0, worst = 0, lo = Infinity, hi = -Infinity, zmin = Infinity, zmax = -Infinity;
    for (let i = 0; i < grid.n; ++i) for (let j = 0; j < grid.n; ++j) {
      const H = grid.z[i * grid.n + j];
      if (H === null) continue;
      const r = g.track.heightAt(grid.x0 + j * grid.step, grid.y0 + i * grid.step);
      if (r === null) continue;
      nodes++;
      const d = r - H;
      lo = Math.min(lo, d); hi = Math.max(hi, d);
      if (d < 0) under++;
      worst = Math.max(worst, Math.abs(d - 0.03));
      zmin = Math.min(zmin, H); zmax = Math.max(zmax, H);
    }
    g.groundPending = false;
    return { nodes, under, lo, hi, worst, zmin, zmax };
  }, [x, y]), 60000, 100);
}

// the ribbon against the race layout's centre line
function checkShape() {
  return page.evaluate(() => {
    const g = window.groundsim, race = g.layout.race, mesh = g.track.mesh;
    if (!mesh) return { missing: true };
    const line = race.centerline.slice();
    if (race.circuit) line.push(line[0]);
    const hw = race.half_width;
    const distToLine = (x, y) => {
      let best = Infinity;
      for (let k = 0; k + 1 < line.length; ++k) {
        const [ax, ay] = line[k], [bx, by] = line[k + 1];
        const ex = bx - ax, ey = by - ay, L2 = ex * ex + ey * ey;
        const u = L2 > 0 ? Math.max(0, Math.min(1, ((x - ax) * ex + (y - ay) * ey) / L2)) : 0;
        best = Math.min(best, Math.hypot(x - ax - u * ex, y - ay - u * ey));
      }
      return best;
    };
    const pos = mesh.geometry.attributes.position;
    let far = 0, checked = 0;
    for (let i = 0; i < pos.count; i += 5) { far = Math.max(far, distToLine(pos.getX(i), pos.getY(i))); checked++; }
    // across the width at each centre line point (normal: the bisector of its segments)
    let missing = [], beyond = [];
    const pts = race.circuit ? race.centerline.length : race.centerline.length;
    const step = Math.max(1, Math.floor(pts / 64));
    // a stage's centre line may be two points 2 km apart: walk it every 10 m
    const walk = [];
    for (let k = 0; k + 1 < line.length; ++k) {
      const [ax, ay] = line[k], [bx, by] = line[k + 1], L = Math.hypot(bx - ax, by - ay), m = race.circuit ? 1 : Math.max(1, Math.floor(L / 10));
      for (let q = 0; q < m; q += race.circuit ? 1 : 1) walk.push([ax + (bx - ax) * q / m, ay + (by - ay) * q / m, (bx - ax) / L, (by - ay) / L]);
    }
    walk.forEach(([x, y, tx, ty], k) => {
      if (k % step && race.circuit) return;
      // the bisector on a circuit's polyline corners
      let nx = -ty, ny = tx;
      if (race.circuit) {
        const [px, py] = line[(k + line.length - 2) % (line.length - 1)], [cx, cy] = line[k];
        const pl = Math.hypot(cx - px, cy - py), ptx = (cx - px) / pl, pty = (cy - py) / pl;
        const bx = tx + ptx, by = ty + pty, bl = Math.hypot(bx, by);
        nx = -by / bl; ny = bx / bl;
      }
      for (const side of [-1, 1]) {
        for (const o of [0, hw / 2, hw - 0.1]) if (g.track.heightAt(x + side * o * nx, y + side * o * ny) === null) missing.push([x, y, side * o]);
        const ox = x + side * (hw + 0.5) * nx, oy = y + side * (hw + 0.5) * ny;
        if (distToLine(ox, oy) > hw + 0.45 && g.track.heightAt(ox, oy) !== null) beyond.push([x, y, side]);
      }
    });
    return { vertices: pos.count, checked, far, hw, points: walk.length, missing: missing.slice(0, 5), nMissing: missing.length, beyond: beyond.slice(0, 5), nBeyond: beyond.length };
  });
}

async function checkTrack(name, places) {
  await h.until(`${name}: the ribbon`, () => page.evaluate(() => !!(window.groundsim.track.mesh && window.groundsim.terrain.grid)), 60000, 100);
  const shape = await checkShape();
  console.log(`${name}: ribbon of ${shape.vertices} vertices; farthest of ${shape.checked} from the centre line ${shape.far.toFixed(3)} m (half width ${shape.hw}); across the width at ${shape.points} points: ${shape.nMissing} holes, ${shape.nBeyond} beyond`);
  if (!(shape.far <= shape.hw + 0.01)) await h.fail(`${name}: a ribbon vertex ${shape.far} m from the centre line (half width ${shape.hw})`);
  if (shape.nMissing) await h.fail(`${name}: no ribbon at ${JSON.stringify(shape.missing)}`);
  if (shape.nBeyond) await h.fail(`${name}: ribbon beyond the half width at ${JSON.stringify(shape.beyond)}`);
  const heights = [];
  for (const [x, y] of places) {
    const r = await checkOnGround(x, y);
    console.log(`${name}: grid at (${x}, ${y}): ${r.nodes} nodes under the ribbon, ribbon - ground in [${r.lo.toFixed(4)}, ${r.hi.toFixed(4)}] m, ground ${r.zmin.toFixed(2)}..${r.zmax.toFixed(2)} m`);
    if (r.nodes < 200) await h.fail(`${name}: only ${r.nodes} grid nodes under the ribbon at (${x}, ${y})`);
    if (r.under) await h.fail(`${name}: the ribbon under the ground at ${r.under} nodes near (${x}, ${y}) (lowest ${r.lo} m)`);
    if (!(r.worst < 0.03)) await h.fail(`${name}: the ribbon ${r.lo}..${r.hi} m above the ground near (${x}, ${y}), want 0.03 +- 0.03`);
    heights.push((r.zmin + r.zmax) / 2);
  }
  return heights;
}

// ---- the circuit, 8 cars -----------------------------------------------------------
await h.createAndDrive(page, 'race/circuit.json', 8);
await keepGrids();
await checkTrack('circuit', [[-8, -30], [83, -19], [0, 30]]);
// a few frames with the chase camera back at the grid, then the budget of one frame
await page.evaluate(() => window.groundsim.send({ op: 'ground', cx: -8, cy: -27.5 }));
const f0 = await page.evaluate(() => window.groundsim.frames);
await h.until('frames drawn', () => page.evaluate((f) => window.groundsim.frames > f + 5, f0), 60000, 50);
const info = await page.evaluate(() => {
  const g = window.groundsim, r = g.three.renderer.info.render;
  return { calls: r.calls, triangles: r.triangles, cars: g.vehicles.length, ribbonTriangles: g.track.mesh.geometry.index.count / 3, frameMs: g.frameMs, fps: g.fps };
});
console.log(`circuit, ${info.cars} cars: ${info.calls} draw calls, ${info.triangles} triangles (ribbon ${info.ribbonTriangles}); render call ${info.frameMs.toFixed(1)} ms, ${info.fps.toFixed(1)} frames/s`);
if (info.cars !== 8) await h.fail(`${info.cars} cars drawn, want 8`);
if (info.calls > 150 || info.triangles > 500000) await h.fail(`frame too heavy: ${info.calls} draw calls, ${info.triangles} triangles`);
const shots = process.env.GROUNDSIM_SCREENSHOT;
if (shots) await page.screenshot({ path: `${shots}/ribbon-circuit.png` });

// ---- the rally stage ----------------------------------------------------------------
await page.click('#btn-lobby');
await h.until('the lobby', () => page.evaluate(() => !window.groundsim.session), 60000, 50);
await h.createAndDrive(page, 'race/rally_stage.json');
const z = await checkTrack('rally stage', [[100, 0], [600, 0], [1300, 0]]);
const climb = Math.max(...z) - Math.min(...z);
console.log(`rally stage: the ground under the ribbon spans ${climb.toFixed(1)} m between the three grids`);
if (!(climb > 5)) await h.fail(`the rally stage's grids differ by only ${climb} m in height: the check proves nothing`);
if (shots) await page.screenshot({ path: `${shots}/ribbon-rally.png` });
await h.pass(`circuit and rally stage ribbons on the centre line and the ground; ${info.calls} draw calls, ${info.triangles} triangles with 8 cars`);

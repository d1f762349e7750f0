// The page loads, creates a session from the lobby and draws its ground and
// car: the canvas is not blank (spread of pixel values, many colours), the
// ground mesh came from the bridge's grid sampled through the scenario
// layer, and the car's figure-1 points and springs are in the scene.
// Before the session, the same canvas is sky only: one colour.
// Each scenario named on the command line (cosine.json by default) in a
// page of its own, in one browser against one server and bridge.
// The canvas is judged once frames were drawn after the ground arrived,
// however long a software renderer on a loaded machine takes to draw them
// (a ceiling only ends a hung page), not after a fixed 1.5 s.
import * as h from './harness.mjs';

const configs = process.argv.slice(2).length ? process.argv.slice(2) : ['cosine.json'];
const { url } = await h.startServices();
await h.launch();
const drawn = [];
for (const config of configs) {
  const page = await h.newPage(url);
  // the page's first frames drawn (shaders compiled), then read
  await h.until('frames drawn in the lobby', () => page.evaluate(() => window.groundsim.frames >= 2), 120000);
  const before = await h.canvasStats(page);
  if (before.colours > 2) await h.fail(`${config}: the canvas before any session should be plain sky, got ${before.colours} colours`);

  await h.createAndDrive(page, config);
  await h.until('a ground grid', () => page.evaluate(() => window.groundsim.groundGrids > 0));
  const f0 = await page.evaluate(() => window.groundsim.frames);
  let after = null;
  await h.until(`${config}: the scene drawn (frames after the ground, a canvas that is not blank)`, async () => {
    if (!(await page.evaluate((f) => window.groundsim.frames > f + 2, f0))) return false;
    after = await h.canvasStats(page);
    return after.std >= 10 && after.colours >= 40;
  }, 120000, 200).catch(() => {});
  const frames = (await page.evaluate(() => window.groundsim.frames)) - f0;
  console.log(`${config}: canvas before: ${JSON.stringify(before)}, after ${frames} frames with the ground: ${JSON.stringify(after)}`);
  if (!after || after.std < 10 || after.colours < 40) await h.fail(`${config}: the scene looks blank: ${JSON.stringify(after)} after ${frames} frames`);
  const info = await page.evaluate(() => {
    const g = window.groundsim;
    return { layout: g.layout && g.layout.vehicles.length, points: g.layout && g.layout.vehicles[0].points.length,
             springs: g.layout && g.layout.vehicles[0].springs.length, frames: g.frames, ground: g.layout && g.layout.ground,
             webgl2: !!document.createElement('canvas').getContext('webgl2') };
  });
  console.log(JSON.stringify(info));
  if (!info.webgl2) await h.fail('no WebGL 2');
  if (info.layout !== 1 || info.points < 8 || info.springs < 8) await h.fail(`${config}: no car layout: ${JSON.stringify(info)}`);
  if (process.env.GROUNDSIM_SCREENSHOT) await page.screenshot({ path: process.env.GROUNDSIM_SCREENSHOT });
  drawn.push(`${config} ${JSON.stringify(after)}`);
  // one software renderer at a time
  await page.context().close();
}
await h.pass(`scene drawn: ${drawn.join('; ')}`);

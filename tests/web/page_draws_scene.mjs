// The page loads, creates a session from the lobby and draws its ground and
// car: the canvas is not blank (spread of pixel values, many colours), the
// ground mesh came from the bridge's grid sampled through the scenario
// layer, and the car's figure-1 points and springs are in the scene.
// Before the session, the same canvas is sky only: one colour.
import * as h from './harness.mjs';

const { url } = await h.startServices();
await h.launch();
const page = await h.newPage(url);
const before = await h.canvasStats(page);
if (before.colours > 2) await h.fail(`the canvas before any session should be plain sky, got ${before.colours} colours`);

await h.createAndDrive(page, process.argv[2] || 'cosine.json');
await h.until('a ground grid', () => page.evaluate(() => window.groundsim.groundGrids > 0));
await page.waitForTimeout(1500);
const after = await h.canvasStats(page);
console.log(`canvas before: ${JSON.stringify(before)}, after: ${JSON.stringify(after)}`);
if (after.std < 10 || after.colours < 40) await h.fail(`the scene looks blank: ${JSON.stringify(after)}`);
const info = await page.evaluate(() => {
  const g = window.groundsim;
  return { layout: g.layout && g.layout.vehicles.length, points: g.layout && g.layout.vehicles[0].points.length,
           springs: g.layout && g.layout.vehicles[0].springs.length, frames: g.frames, ground: g.layout && g.layout.ground,
           webgl2: !!document.createElement('canvas').getContext('webgl2') };
});
console.log(JSON.stringify(info));
if (!info.webgl2) await h.fail('no WebGL 2');
if (info.layout !== 1 || info.points < 8 || info.springs < 8) await h.fail(`no car layout: ${JSON.stringify(info)}`);
if (process.env.GROUNDSIM_SCREENSHOT) await page.screenshot({ path: process.env.GROUNDSIM_SCREENSHOT });
await h.pass(`scene drawn: ${JSON.stringify(after)}`);

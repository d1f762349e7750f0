// Pressing W drives the car and releasing it lets go: on the plane (mu 0.5)
// full throttle accelerates the car at up to mu g = 4.9 m/s^2, so 1.5 s of W
// adds metres per second, seen in the HUD and in the server's own states
// (groundsim watch, not through the bridge). After the release the throttle
// the page sends returns to 0 and the car only coasts: over the next second
// its speed gains less than a tenth of what a held key would add.
import * as h from './harness.mjs';

const { url } = await h.startServices();
await h.launch();
const page = await h.newPage(url);
const session = await h.createAndDrive(page, 'plain.json');
// the scenario starts rolling at ~1.1 m/s: handbrake to a stop first
await h.stopCars(page);
await page.waitForTimeout(300);
const v0 = await h.pageSpeed(page, 0), server0 = h.serverSpeeds(session)[0];
console.log(`at rest: page ${v0.toFixed(3)} m/s, server ${server0} m/s, HUD ${await h.hudSpeedKmh(page)} km/h`);

await page.keyboard.down('w');
await page.waitForTimeout(1500);
const vPressed = await h.pageSpeed(page, 0), hudPressed = await h.hudSpeedKmh(page);
const serverPressed = h.serverSpeeds(session)[0];
await page.keyboard.up('w');
console.log(`W held 1.5 s: page ${vPressed.toFixed(3)} m/s, server ${serverPressed} m/s, HUD ${hudPressed} km/h`);
if (!(vPressed > v0 + 1.0)) await h.fail(`holding W did not speed the car up: ${v0} -> ${vPressed} m/s`);
if (!(serverPressed > server0 + 1.0)) await h.fail(`the server's states show no speed-up: ${server0} -> ${serverPressed} m/s`);
if (!(hudPressed > 3.6)) await h.fail(`the HUD shows ${hudPressed} km/h after 1.5 s of W`);

await h.until('the throttle to return to 0', () => page.evaluate(() => window.groundsim.lastControls &&
  JSON.parse(window.groundsim.lastControls).throttle === 0), 2000, 20);
await page.waitForTimeout(300);
const vRel = await h.pageSpeed(page, 0);
await page.waitForTimeout(1000);
const vLater = await h.pageSpeed(page, 0);
const gainHeld = (vPressed - v0) / 1.5, gainAfter = vLater - vRel;
console.log(`after release: ${vRel.toFixed(3)} -> ${vLater.toFixed(3)} m/s in 1 s (held: +${gainHeld.toFixed(2)} m/s per s)`);
if (!(gainAfter < 0.1 * gainHeld)) await h.fail(`the car kept accelerating after W was released: +${gainAfter} m/s in 1 s`);
await h.pass(`W: +${(vPressed - v0).toFixed(2)} m/s in 1.5 s; released: ${gainAfter.toFixed(3)} m/s in 1 s`);

// Controls beyond the keyboard (web/src/input.js), in a phone-sized page with
// touch and a fake wheel (navigator.getGamepads replaced before the page
// loads). Touch: the controls show for a driver; a finger on GO sends full
// throttle and lifting it lets go; dragging the steering pad 20 px right
// steers right by 20 / (a quarter of the pad's width); a second finger works
// at once. Wheel: the remap screen (G) takes "throttle" from the axis the
// pedal moves (resting at 1.0, pressed -1.0, as wheels' pedals do), keeps it
// in localStorage, and half the pedal then sends throttle 0.5.
// Every step waits for what the page sends or shows (60 s ceilings for a
// hung page). The page runs without drawing (?render=0): what is checked
// is the controls it sends and its DOM.
import * as h from './harness.mjs';

const { url } = await h.startServices();
const browser = await h.launch();
const ctx = await browser.newContext({ viewport: { width: 390, height: 844 }, hasTouch: true, isMobile: true });
await ctx.addInitScript(() => {
  const buttons = Array.from({ length: 17 }, () => ({ pressed: false, touched: false, value: 0 }));
  window.fakePad = { id: 'Fake Wheel (pedals on axis 2)', index: 0, connected: true, mapping: '', timestamp: 0,
                     axes: [0, 0, 1, 0], buttons };
  navigator.getGamepads = () => [window.fakePad, null, null, null];
});
const page = await ctx.newPage();
page.on('pageerror', (e) => console.error(`[page] ${e.message}`));
await page.goto(`${url}?render=0`);
await h.until('the page to connect', () => page.evaluate(() => window.groundsim && window.groundsim.configs.length > 0));
await h.createAndDrive(page, 'plain.json');
const cdp = await ctx.newCDPSession(page);
const touch = (type, points) => cdp.send('Input.dispatchTouchEvent', { type, touchPoints: points });
const sent = () => page.evaluate(() => JSON.parse(window.groundsim.lastControls || '{}'));
const zones = await page.evaluate(() => {
  const el = document.getElementById('touch');
  if (!el || getComputedStyle(el).display === 'none') return null;
  const r = (k) => { const b = el.children[k].getBoundingClientRect(); return { x: b.left + b.width / 2, y: b.top + b.height / 2, w: b.width }; };
  return { pad: r(0), go: r(1), brake: r(2) };
});
if (!zones) await h.fail('no touch controls shown to a driver on a touch screen');

await touch('touchStart', [{ x: zones.go.x, y: zones.go.y, id: 1 }]);
await h.until('full throttle from GO', async () => (await sent()).throttle === 1, 60000, 20);
await touch('touchEnd', []);
await h.until('the throttle to return', async () => (await sent()).throttle === 0, 60000, 20);

await touch('touchStart', [{ x: zones.pad.x, y: zones.pad.y, id: 2 }]);
await touch('touchMove', [{ x: zones.pad.x + 20, y: zones.pad.y, id: 2 }]);
const want = -20 / Math.max(40, zones.pad.w / 4);
const steer = await h.until('steering from the pad', async () => {
  const c = await sent();
  return Math.abs(c.steer - want) < 1e-6 ? c.steer : null;
}, 60000, 20).catch(async () => (await sent()).steer);
console.log(`pad dragged 20 px of ${zones.pad.w.toFixed(0)}: steer ${steer} (want ${want.toFixed(4)})`);
if (!(Math.abs(steer - want) < 1e-6)) await h.fail(`steer ${steer}, want ${want}`);
await touch('touchStart', [{ x: zones.pad.x + 20, y: zones.pad.y, id: 2 }, { x: zones.go.x, y: zones.go.y, id: 3 }]);
const both = await h.until('steer and throttle at once', async () => {
  const c = await sent();
  return c.throttle === 1 && Math.abs(c.steer - want) < 1e-6 ? c : null;
}, 60000, 20).catch(() => null);
if (!both) await h.fail(`two fingers: ${JSON.stringify(await sent())}`);
await touch('touchEnd', []);

// the wheel: throttle remapped to the pedal's axis 2
await page.keyboard.press('g');
await h.until('the remap screen', () => page.evaluate(() => !document.getElementById('remap').classList.contains('hidden')), 60000, 20);
await page.click('#remap button[data-k="throttle"]');
// waiting for the pedal: the axes at rest are kept (was a fixed 200 ms)
await h.until('the remap screen waiting for the pedal', () => page.evaluate(() =>
  document.querySelector('#remap button[data-k="throttle"]').textContent === 'press...'), 60000, 20);
await page.evaluate(() => { window.fakePad.axes[2] = -1; });  // the pedal pressed
const kept = await h.until('the mapping', () => page.evaluate(() => {
  const m = JSON.parse(localStorage.getItem('groundsim.padmap') || 'null');
  return m && m.throttle && m.throttle.axis === 2 ? m.throttle : null;
}), 60000, 20).catch(() => null);
console.log(`kept: throttle ${JSON.stringify(kept)}`);
if (!kept || kept.rest !== 1 || kept.full !== -1) await h.fail(`throttle mapping ${JSON.stringify(kept)}`);
await page.evaluate(() => { window.fakePad.axes[2] = 0; });  // half way
const half = await h.until('half throttle from the pedal', async () => ((await sent()).throttle === 0.5 ? 0.5 : null), 60000, 20)
  .catch(async () => (await sent()).throttle);
if (half !== 0.5) await h.fail(`half the pedal sent throttle ${half}`);
await page.evaluate(() => { window.fakePad.axes[2] = 1; });
await h.until('the pedal released', async () => (await sent()).throttle === 0, 60000, 20);
await h.pass(`touch: GO 1, pad ${want.toFixed(3)}, both at once; wheel pedal on axis 2 remapped, half -> 0.5`);

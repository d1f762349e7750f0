// What a browser test pays to launch its own Chromium (docs/reliability.md,
// "One Chromium per browser test"): N times launch, a context and a blank
// page, close; the tests' own Chromium and flags (tests/web/harness.mjs).
//   GROUNDSIM_WEB_NODE_MODULES=build/web/node_modules node bench/web/chromium_launch.mjs [N=5]
import { existsSync } from 'node:fs';
import { createRequire } from 'node:module';
import { CHROMIUM, CHROMIUM_ARGS } from '../../tests/web/harness.mjs';

const runs = Number(process.argv[2] || 5);
const modules = process.env.GROUNDSIM_WEB_NODE_MODULES || 'build/web/node_modules';
if (!existsSync(CHROMIUM)) {
  console.log(`no Chromium at ${CHROMIUM}`);
  process.exit(77);
}
const { chromium } = createRequire(`${modules}/`)('playwright-core');
const ms = (a, b) => (b - a).toFixed(0);
for (let i = 0; i < runs; i++) {
  const t0 = performance.now();
  const browser = await chromium.launch({ executablePath: CHROMIUM, headless: true, args: CHROMIUM_ARGS });
  const t1 = performance.now();
  const page = await (await browser.newContext()).newPage();
  await page.goto('about:blank');
  const t2 = performance.now();
  await browser.close();
  const t3 = performance.now();
  console.log(`launch ${ms(t0, t1)} ms, context and page ${ms(t1, t2)} ms, close ${ms(t2, t3)} ms`);
}
process.exit(0);

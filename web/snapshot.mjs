// A picture of the web viewer in headless Chromium (Debian's), once the page says "ready":
//   node web/snapshot.mjs URL OUT.png [--width W --height H --timeout S]
// Serve web/ first (scripts/serve_web.sh). Prints the page's console and the seconds it took;
// exits 1 when the page reports an error or is not ready in time.
import { chromium } from 'playwright-core';

const args = process.argv.slice(2);
const option = (name, fallback) => {
  const at = args.indexOf(name);
  return at >= 0 ? Number(args[at + 1]) : fallback;
};
const [url, out] = args.filter((a, i) => !a.startsWith('--') && !args[i - 1]?.startsWith('--'));
if (!url || !out) {
  console.error('usage: node web/snapshot.mjs URL OUT.png [--width W --height H --timeout S]');
  process.exit(2);
}
const width = option('--width', 1024), height = option('--height', 768);
const start = Date.now();
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
  args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--no-sandbox'],
});
let status = 0;
try {
  const page = await browser.newPage({ viewport: { width, height } });
  page.on('console', (m) => console.log(`page: ${m.text()}`));
  page.on('pageerror', (e) => console.log(`page error: ${e.message}`));
  await page.goto(url);
  await page.waitForFunction(() => document.title === 'ready' || document.title.startsWith('error'),
                             null, { timeout: option('--timeout', 120) * 1000 });
  const title = await page.title();
  if (title !== 'ready') {
    console.log(title);
    status = 1;
  }
  await page.screenshot({ path: out });
  console.log(`${out}: ${title} after ${((Date.now() - start) / 1000).toFixed(1)} s`);
} catch (e) {
  console.log(`${url}: ${e.message}`);
  status = 1;
} finally {
  await browser.close();
}
process.exit(status);

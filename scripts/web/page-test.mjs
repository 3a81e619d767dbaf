// Opens a page written by `vbrain export --web` from its file in headless Chromium (Debian's
// /usr/bin/chromium, or $CHROMIUM) and uses it as a student would; prints what it saw as JSON:
// load and frame times, pixels that are not background, the name shown after a click on the
// brain, the organ tree's text, pixels after hiding the group "Cerebrum", and for a lesson the captions after Next and
// Previous; with STEP, at that step of a lesson the pixels that its cut faces change (drawn, then
// not). Usage: node page-test.mjs DIR [SCREENSHOT.png] [STEP]
import { chromium } from 'playwright-core';
import path from 'node:path';

const [dir, screenshot, step] = process.argv.slice(2);
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
    '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run'],
});
const out = { errors: [] };
try {
  const page = await browser.newPage({ viewport: { width: 1100, height: 720 } });
  // A software GPU on a busy 2-core machine can spend many seconds on one frame of the brain.
  page.setDefaultTimeout(240000);
  page.on('pageerror', (e) => out.errors.push(String(e)));
  page.on('dialog', (d) => { out.errors.push('a dialog opened: ' + d.message()); d.dismiss(); });
  page.on('requestfailed', (r) => out.errors.push('request failed: ' + r.url().slice(0, 120)));
  const started = Date.now();
  await page.goto('file://' + path.resolve(dir, 'index.html'));
  await page.waitForSelector('body[data-ready="1"]', { timeout: 120000 });
  out.load_ms = Date.now() - started;
  // Faded organs refine the still view over many frames; a software GPU under load can take
  // longer than an action's timeout for them, so each action waits for the view to settle.
  const settle = () => page.evaluate(() => window.vbrain.settled());
  // Pixels of the 3-D view that differ from the background.
  const pixels = () => page.evaluate(() => {
    window.vbrain.render();
    const c = document.querySelector('#view canvas');
    const copy = document.createElement('canvas');
    [copy.width, copy.height] = [c.width, c.height];
    const g = copy.getContext('2d');
    g.drawImage(c, 0, 0);
    const d = g.getImageData(0, 0, copy.width, copy.height).data;
    let n = 0;
    for (let i = 0; i < d.length; i += 4) {
      if (Math.abs(d[i] - 0x1e) + Math.abs(d[i + 1] - 0x21) + Math.abs(d[i + 2] - 0x28) > 24) n++;
    }
    return n;
  });
  out.frame_ms = await page.evaluate(() => {
    const gl = document.querySelector('#view canvas').getContext('webgl2');
    const pixel = new Uint8Array(4);
    const t = performance.now();
    for (let i = 0; i < 10; i++) {
      window.vbrain.render();
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
    }
    return (performance.now() - t) / 10;
  });
  out.pixels = await pixels();
  out.organs = await page.evaluate(() => window.vbrain.organs);
  out.title = await page.title();
  out.tree_text = await page.locator('#tree').textContent();
  await settle();
  const box = await page.locator('#view canvas').boundingBox();
  await page.mouse.click(box.x + box.width * 0.38, box.y + box.height * 0.45);
  out.clicked_name = await page.locator('#selected-name').textContent();
  out.clicked_info = await page.locator('#selected-info').textContent();
  await settle();
  if (screenshot) await page.screenshot({ path: screenshot });
  if (await page.locator('#lesson').isVisible()) {
    const caption = () => page.locator('#caption').textContent();
    out.captions = [await caption()];
    out.caption_markup = await page.evaluate(() => {
      const c = document.getElementById('caption');
      const count = (tag) => c.querySelectorAll(tag).length;
      return { p: count('p'), li: count('li'), strong: count('strong'), em: count('em') };
    });
    await settle();
    await page.getByRole('button', { name: 'Next >' }).click();
    out.captions.push(await caption());
    out.pixels_step_2 = await pixels();
    await settle();
    await page.getByRole('button', { name: '< Previous' }).click();
    out.captions.push(await caption());
  }
  if (step) {
    await page.evaluate((k) => window.vbrain.step(k), Number(step) - 1);
    await settle();
    if (screenshot) await page.screenshot({ path: screenshot.replace(/\.png$/, `-step${step}.png`) });
    out.cap_pixels = await page.evaluate(() => {
      const read = () => {
        window.vbrain.render();
        const c = document.querySelector('#view canvas');
        const copy = document.createElement('canvas');
        [copy.width, copy.height] = [c.width, c.height];
        copy.getContext('2d').drawImage(c, 0, 0);
        return copy.getContext('2d').getImageData(0, 0, copy.width, copy.height).data;
      };
      const drawn = read();
      window.vbrain.setCaps(false);
      const hollow = read();
      window.vbrain.setCaps(true);
      let n = 0;
      for (let i = 0; i < drawn.length; i += 4) {
        if (Math.abs(drawn[i] - hollow[i]) + Math.abs(drawn[i + 1] - hollow[i + 1]) + Math.abs(drawn[i + 2] - hollow[i + 2]) > 24) n++;
      }
      return n;
    });
  }
  const cerebrum = page.getByLabel('Show group Cerebrum', { exact: true });
  if (await cerebrum.count()) {
    await settle();
    await cerebrum.uncheck();
    out.pixels_without_cerebrum = await pixels();
  }
} finally {
  await browser.close();
}
console.log(JSON.stringify(out));

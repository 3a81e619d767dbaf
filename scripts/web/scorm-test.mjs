// A learning platform's side of a SCORM 1.2 package written by `vbrain export --scorm`, unpacked
// into DIR: headless Chromium (Debian's /usr/bin/chromium, or $CHROMIUM) opens the package's
// launch page inside a frame of a parent page that defines the SCORM 1.2 run-time API (window.API,
// as the standard specifies) and records every call. It takes the quiz as a student would,
// clicking the model for locate questions and the names for name questions, answering the
// first WRONG questions wrongly and the rest rightly; prints what it saw as JSON: the API calls
// in order, the score line, the missed structures, page errors. Both pages are served from one
// made-up origin so that the frame may reach its parent, as on a platform.
// Usage: node scorm-test.mjs DIR [WRONG] [SCREENSHOT.png]
import { chromium } from 'playwright-core';
import fs from 'node:fs';
import path from 'node:path';

const [dir, wrongArg, screenshot] = process.argv.slice(2);
const wrong = Number(wrongArg ?? 1);
const origin = 'http://platform.test';
const parent = `<!doctype html><html><head><title>Platform</title><script>
window.calls = [];
const record = (name) => (...args) => { window.calls.push([name, ...args.map(String)]); return name === 'LMSGetValue' ? '' : 'true'; };
window.API = {
  LMSInitialize: record('LMSInitialize'), LMSFinish: record('LMSFinish'), LMSGetValue: record('LMSGetValue'),
  LMSSetValue: record('LMSSetValue'), LMSCommit: record('LMSCommit'),
  LMSGetLastError: () => '0', LMSGetErrorString: () => 'No error', LMSGetDiagnostic: () => '',
};
</script></head><body style="margin:0"><iframe id="sco" src="/sco/index.html" style="width:1100px;height:720px;border:0"></iframe></body></html>`;

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
    '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run'],
});
const out = { errors: [], answers: [] };
try {
  const page = await browser.newPage({ viewport: { width: 1100, height: 720 } });
  // A software GPU on a busy 2-core machine can spend many seconds on one frame of the brain,
  // so each action also waits for the view to settle.
  page.setDefaultTimeout(240000);
  page.on('pageerror', (e) => out.errors.push(String(e)));
  page.on('dialog', (d) => { out.errors.push('a dialog opened: ' + d.message()); d.dismiss(); });
  await page.route(`${origin}/**`, (route) => {
    const url = new URL(route.request().url());
    if (url.pathname === '/') return route.fulfill({ contentType: 'text/html', body: parent });
    const file = path.join(dir, decodeURIComponent(url.pathname.replace(/^\/sco\//, '')));
    if (!url.pathname.startsWith('/sco/') || !fs.existsSync(file)) return route.fulfill({ status: 404, body: '' });
    const type = file.endsWith('.html') ? 'text/html' : 'application/octet-stream';
    return route.fulfill({ contentType: type, body: fs.readFileSync(file) });
  });
  page.on('requestfailed', (r) => out.errors.push('request failed: ' + r.url().slice(0, 120)));
  await page.goto(`${origin}/`);
  const frame = page.frameLocator('#sco');
  await frame.locator('body[data-ready="1"]').waitFor({ timeout: 120000 });
  const sco = page.frames().find((f) => f.url().endsWith('/sco/index.html'));
  out.start_label = await frame.locator('#quiz-start').textContent();
  await sco.evaluate(() => window.vbrain.settled());
  await frame.locator('#quiz-start').click();
  for (let k = 0; ; k++) {
    const q = await sco.evaluate(() => window.vbrain.question());
    if (!q) break;
    // The right answer, or for a wrong one the first other choice (that shows, to be clicked).
    const candidates = k >= wrong ? [q.organ] : q.choices.filter((c) => c.id !== q.organ.id);
    let pick = candidates[0];
    await sco.evaluate(() => window.vbrain.settled());
    if (q.kind === 'name') {
      await frame.getByRole('button', { name: pick.name, exact: true }).click();
    } else {
      let at = null;
      for (const c of candidates) {
        at = await sco.evaluate((id) => window.vbrain.pointOn(id), c.id);
        if (at) {
          pick = c;
          break;
        }
      }
      if (!at) {
        out.errors.push(`nothing of ${candidates.map((c) => c.id)} to click in question ${k + 1}`);
        break;
      }
      await frame.locator('#view canvas').click({ position: at });
    }
    out.answers.push({ kind: q.kind, organ: q.organ.id, clicked: pick.id,
      feedback: await frame.locator('#quiz-feedback').textContent() });
    await sco.evaluate(() => window.vbrain.settled());
    if (k === 0 && screenshot) await page.screenshot({ path: screenshot });
    await frame.locator('#quiz-next').click();
  }
  out.score_line = await frame.locator('#quiz-question').textContent();
  out.missed = await frame.locator('#quiz-review button').allTextContents();
  out.calls = await page.evaluate(() => window.calls);
} finally {
  await browser.close();
}
console.log(JSON.stringify(out));

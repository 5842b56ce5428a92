// The capture daemon's live page in Debian's chromium (headless, never a downloaded browser), driven by
// playwright-core. Run by tests/capture/live_page_e2e_test.cc, which starts the daemon (recording the
// simulated rig: the NDI emulator's replay and a fakenect Kinect1), reads this script's stdout and does
// what it asks for:
//   node live_page_test.js URL OUT_DIR
// prints "KILL_TRACKER" once the page has shown a recording with labels (the test then kills and
// restarts the emulator), and "RESULT <json>" at the end: the labels PNG the page showed (OUT_DIR/
// overlay.png), its frame and legend, the counters it saw. Any failed check exits non-zero with a line
// saying which.
'use strict';

const fs = require('fs');
const path = require('path');
const {chromium} = require('playwright-core');

const [url, outDir] = process.argv.slice(2);
const CHROMIUM = process.env.MOCAP_CHROMIUM || '/usr/bin/chromium';

function fail(message) {
  console.error(`live_page_test: ${message}`);
  process.exit(1);
}

async function waitFor(what, fn, timeoutMs) {
  const deadline = Date.now() + timeoutMs;
  for (;;) {
    const value = await fn();
    if (value) return value;
    if (Date.now() > deadline) fail(`timed out after ${timeoutMs} ms waiting for ${what}`);
    await new Promise((ok) => setTimeout(ok, 100));
  }
}

const text = (page, selector) => page.evaluate((s) => {
  const node = document.querySelector(s);
  return node ? node.textContent : null;
}, selector);

async function counter(page, stream, column) {
  const value = await text(page, `#streams tr[data-stream="${stream}"] .${column}`);
  return value === null || value === '–' ? -1 : Number(value);
}

// The counters of both streams rise between two updates of the page.
async function checkCountersRise(page) {
  await waitFor('the first frames and samples', async () =>
    (await counter(page, 'kinect1', 'received')) > 0 && (await counter(page, 'ndi', 'received')) > 0, 10000);
  const first = {cam: await counter(page, 'kinect1', 'received'), ndi: await counter(page, 'ndi', 'received')};
  await waitFor('the received counters to rise', async () =>
    (await counter(page, 'kinect1', 'received')) > first.cam && (await counter(page, 'ndi', 'received')) > first.ndi, 10000);
  return {first, then: {cam: await counter(page, 'kinect1', 'received'), ndi: await counter(page, 'ndi', 'received')}};
}

// A thumbnail whose labels show every instance with a pose; returns its labels PNG and what it shows.
async function waitForLabelledThumbnail(page, labelBodies) {
  return waitFor('a thumbnail with every object labelled', async () => {
    const shown = await page.evaluate(() => {
      const figure = document.querySelector('figure[data-camera="kinect1"][data-seq]');
      if (!figure) return null;
      const labels = figure.querySelector('img.labels');
      return {seq: Number(figure.dataset.seq), frame: Number(figure.dataset.frame), src: labels.src,
              loaded: labels.complete && labels.naturalWidth > 0, legend: JSON.parse(figure.dataset.legend || '[]')};
    });
    if (!shown || !shown.loaded || shown.legend.length === 0 || !shown.legend.every((i) => i.drawn)) return null;
    const png = labelBodies.get(shown.src);
    return png ? {...shown, png} : null;
  }, 15000);
}

async function main() {
  if (!url || !outDir) fail('usage: node live_page_test.js URL OUT_DIR');
  if (!fs.existsSync(CHROMIUM)) fail(`${CHROMIUM} not found: install Debian's chromium (scripts/install-deps.sh)`);
  const browser = await chromium.launch({executablePath: CHROMIUM, headless: true, args: ['--no-sandbox']});
  const page = await browser.newPage({viewport: {width: 390, height: 844}});  // a phone
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  const labelBodies = new Map();
  page.on('response', async (r) => {
    if (r.url().includes('/live/labels.png') && r.ok()) labelBodies.set(r.url(), await r.body().catch(() => null));
  });
  await page.goto(url);
  await waitFor('the state idle', async () => (await text(page, '#state')) === 'idle', 10000);
  const overflow = await page.evaluate(() => document.documentElement.scrollWidth - window.innerWidth);
  if (overflow > 0) fail(`the page is ${overflow} px wider than a 390 px phone screen`);

  await page.fill('#session-name', 'live');
  await page.click('#start');
  await waitFor('the state recording', async () => (await text(page, '#state')) === 'recording', 10000);
  const counters = await checkCountersRise(page);
  const visible = await waitFor('tracker bodies shown visible', async () => {
    const states = await page.$$eval('#bodies tbody tr .status', (cells) => cells.map((c) => c.textContent));
    return states.filter((s) => s === 'visible').length >= 5 ? states : null;
  }, 10000);
  const thumbnail = await waitForLabelledThumbnail(page, labelBodies);
  fs.writeFileSync(path.join(outDir, 'overlay.png'), thumbnail.png);
  await page.setViewportSize({width: 1100, height: 1000});
  await page.waitForTimeout(300);
  await page.screenshot({path: path.join(outDir, 'live_page.png'), fullPage: true});

  // The emulator's replay ends after the recording's 2.5 s: the bodies lose their poses.
  const hidden = await waitFor('the bodies shown without a pose once the replay ended', async () => {
    const states = await page.$$eval('#bodies tbody tr .status', (cells) => cells.map((c) => c.textContent));
    return states.length >= 5 && states.every((s) => s !== 'visible') ? states : null;
  }, 15000);
  console.log('KILL_TRACKER');
  const tracker = await waitFor('reconnect and gap events after the tracker restarted', async () => {
    const kinds = await page.$$eval('#events li', (items) => items.map((li) => li.dataset.kind));
    return kinds.includes('reconnect') && kinds.includes('gap') && kinds.includes('error') ? kinds : null;
  }, 30000);
  // The restarted emulator plays its replay again from the start.
  const visibleAgain = await waitFor('the bodies visible again', async () => {
    const states = await page.$$eval('#bodies tbody tr .status', (cells) => cells.map((c) => c.textContent));
    return states.filter((s) => s === 'visible').length >= 5 ? states : null;
  }, 15000);
  const dropped = await counter(page, 'kinect1', 'dropped');
  if (errors.length) fail(`script errors on the page: ${errors.join('; ')}`);
  await browser.close();
  const result = {frame: thumbnail.frame, seq: thumbnail.seq, legend: thumbnail.legend, counters, visible, hidden,
                  visible_again: visibleAgain, events: tracker, camera_dropped: dropped};
  console.log(`RESULT ${JSON.stringify(result)}`);
}

main().catch((e) => fail(e.stack || String(e)));

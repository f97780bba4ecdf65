// The browser test of web/ (ctest `browser`): the real oer-server on a free loopback port with a
// temporary data folder, Debian's chromium driven by playwright-core (no browser download), both
// started by harness.mjs.
//   node browser_test.mjs --server build/bin/oer-server --artifacts build/browser-artifacts
// Screenshots at desktop (1280x800) and phone (360x740) width go to the artifacts folder.
import { once } from 'node:events';
import { mkdirSync, readFileSync } from 'node:fs';
import { createServer } from 'node:http';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import assert from 'node:assert/strict';
import { RECORD_EVENTS, fullFrame, launchChromium, option, startServer } from './harness.mjs';

const here = dirname(fileURLToPath(import.meta.url));
const serverPath = option('--server');
const artifacts = option('--artifacts');
mkdirSync(artifacts, { recursive: true });

let passed = 0;
async function check(name, body) {
  const started = Date.now();
  await body();
  passed += 1;
  console.log(`ok ${passed} - ${name} (${Date.now() - started} ms)`);
}

// A second origin for the embedding pages, filled in once the server (told to allow this
// origin, http://127.0.0.1:port; http://localhost:port is another, which it does not allow)
// listens: / is web/embed-test.html; /bare.html a viewer the page gives no CSS size, with a
// poster; /unreachable.html the same, its `server` a loopback port where nothing listens.
async function startShop() {
  const template = readFileSync(join(here, '..', 'embed-test.html'), 'utf8');
  const bare = (origin, viewerServer) => `<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>A shop page with a bare viewer</title>
<script type="module" src="${origin}/web/oer-viewer.js"></script></head>
<body><main><h1>Dress form</h1><div style="width: 560px">
<oer-viewer server="${viewerServer}" poster="${origin}/v1/environments/default/preview.jpg"
            aria-label="The dress form; drag to turn it"></oer-viewer>
</div></main></body></html>`;
  let pages = null;
  const shop = createServer((request, response) => {
    const page = pages?.[new URL(request.url, 'http://shop').pathname];
    response.writeHead(page ? 200 : 503, { 'Content-Type': 'text/html; charset=utf-8' });
    response.end(page ?? 'the oer-server is not up yet');
  });
  shop.listen(0, '127.0.0.1');
  await once(shop, 'listening');
  // A loopback port nothing listens on: one just closed.
  const closed = createServer().listen(0, '127.0.0.1');
  await once(closed, 'listening');
  const deadPort = closed.address().port;
  closed.close();
  shop.serveFor = (serverPort) => {
    const origin = `http://127.0.0.1:${serverPort}`;
    pages = {
      '/': template.replaceAll('PORT', String(serverPort)),
      '/bare.html': bare(origin, origin),
      '/unreachable.html': bare(origin, `http://127.0.0.1:${deadPort}`),
    };
  };
  return shop;
}

// Records, from the page's start, when the element first shows visible feedback (its loading
// indicator; its poster) and when it shows its first frame, in performance.now() milliseconds,
// polled every animation frame: window.oerFeedback.
const RECORD_FEEDBACK = () => {
  window.oerFeedback = { indicatorAt: null, posterAt: null, posterSrc: null };
  const poll = () => {
    const viewer = document.querySelector('oer-viewer');
    const root = viewer?.shadowRoot;
    const feedback = window.oerFeedback;
    if (root && !viewer.hasAttribute('loaded')) {
      const now = performance.now();
      if (feedback.indicatorAt === null && root.querySelector('.loading')?.checkVisibility()) {
        feedback.indicatorAt = now;
      }
      const poster = root.querySelector('.poster');
      if (feedback.posterAt === null && poster?.complete && poster.naturalWidth > 0 &&
          poster.checkVisibility({ visibilityProperty: true })) {
        feedback.posterAt = now;
        feedback.posterSrc = poster.src;
        feedback.posterWidth = poster.naturalWidth;
      }
    }
    if (!viewer?.hasAttribute('loaded')) {
      requestAnimationFrame(poll);
    }
  };
  requestAnimationFrame(poll);
};

// What the element shows over the view before and besides its frame: the placeholder (poster
// and loading indicator) and the failure message, whether visible and what the message says.
async function overlays(page) {
  return page.evaluate(() => {
    const root = document.querySelector('oer-viewer').shadowRoot;
    const visible = (selector) => root.querySelector(selector).checkVisibility({ visibilityProperty: true });
    return {
      placeholder: visible('.placeholder'),
      indicator: visible('.loading'),
      poster: visible('.poster'),
      message: visible('.message'),
      messageText: root.querySelector('.message').textContent,
    };
  });
}

// The moderate, serious and critical violations axe-core finds on the page (WCAG 2.0 to 2.2 A
// and AA, and best practices), each as `id (impact): targets`.
const AXE_SOURCE = readFileSync(join(here, 'node_modules', 'axe-core', 'axe.min.js'), 'utf8');
// `selector`: only that part of the page.
async function axeViolations(page, selector = null) {
  await page.addScriptTag({ content: AXE_SOURCE });
  const results = await page.evaluate((part) => window.axe.run(part ?? document, {
    runOnly: { type: 'tag', values: ['wcag2a', 'wcag2aa', 'wcag21a', 'wcag21aa', 'wcag22aa', 'best-practice'] },
  }), selector);
  return {
    passes: results.passes.length,
    serious: results.violations
      .filter((violation) => ['moderate', 'serious', 'critical'].includes(violation.impact))
      .map((violation) => `${violation.id} (${violation.impact}): ` +
        violation.nodes.map((node) => node.target.join(' ')).join(', ')),
    minor: results.violations.filter((violation) => violation.impact === 'minor').map((violation) => violation.id),
  };
}

// The server's upload limit in this test: small enough to refuse a generated file before
// sending it, large enough for a Blender world.
const UPLOAD_LIMIT = 4 << 20;

// The shown image: natural size, the element's CSS size times devicePixelRatio, and pixel
// statistics (distinct colors in a 4-bit-per-channel histogram, luminance spread, a checksum).
async function shownImage(page) {
  return page.evaluate(() => {
    const viewer = document.querySelector('oer-viewer');
    const image = viewer.shadowRoot.querySelector('img');
    const rect = viewer.getBoundingClientRect();
    const canvas = document.createElement('canvas');
    canvas.width = image.naturalWidth;
    canvas.height = image.naturalHeight;
    const context = canvas.getContext('2d');
    context.drawImage(image, 0, 0);
    const { data } = context.getImageData(0, 0, canvas.width, canvas.height);
    const colors = new Set();
    let sum = 0;
    let sumSquares = 0;
    let checksum = 0;
    let redMinusGreen = 0;
    for (let i = 0; i < data.length; i += 4) {
      redMinusGreen += data[i] - data[i + 1];
      colors.add(((data[i] >> 4) << 8) | ((data[i + 1] >> 4) << 4) | (data[i + 2] >> 4));
      const luminance = 0.2126 * data[i] + 0.7152 * data[i + 1] + 0.0722 * data[i + 2];
      sum += luminance;
      sumSquares += luminance * luminance;
      checksum = (checksum * 31 + data[i] + 7 * data[i + 1] + 13 * data[i + 2]) >>> 0;
    }
    const count = data.length / 4;
    const mean = sum / count;
    return {
      naturalWidth: image.naturalWidth,
      naturalHeight: image.naturalHeight,
      expectedWidth: Math.min(4096, Math.round(rect.width * devicePixelRatio)),
      expectedHeight: Math.min(4096, Math.round(rect.height * devicePixelRatio)),
      colors: colors.size,
      mean,
      deviation: Math.sqrt(Math.max(0, sumSquares / count - mean * mean)),
      redOverGreen: redMinusGreen / count,
      checksum,
    };
  });
}

function assertRealFrame(image, what) {
  assert.equal(image.naturalWidth, image.expectedWidth, `${what}: width`);
  assert.equal(image.naturalHeight, image.expectedHeight, `${what}: height`);
  // A blank or flat frame has a handful; the neutral studio's product over its light floor
  // about 45 (the old dark studio's, over 50).
  assert.ok(image.colors >= 20, `${what}: ${image.colors} colors, a blank or flat frame`);
  assert.ok(image.deviation >= 10, `${what}: luminance deviation ${image.deviation}`);
  assert.ok(image.mean > 5 && image.mean < 250, `${what}: mean luminance ${image.mean}`);
}

// The chunks of a RIFF WebP file (Google's WebP container specification): each its FourCC and
// payload, padded to an even size.
function webpChunks(bytes) {
  assert.equal(bytes.toString('latin1', 0, 4), 'RIFF');
  assert.equal(bytes.toString('latin1', 8, 12), 'WEBP');
  assert.equal(bytes.readUInt32LE(4) + 8, bytes.length, 'the RIFF size is the file\'s');
  const chunks = [];
  for (let offset = 12; offset + 8 <= bytes.length;) {
    const size = bytes.readUInt32LE(offset + 4);
    chunks.push({ fourcc: bytes.toString('latin1', offset, offset + 4),
                  payload: bytes.subarray(offset + 8, offset + 8 + size) });
    offset += 8 + size + (size & 1);
  }
  return chunks;
}

// The entries a ZIP archive holds, from its end of central directory record (APPNOTE 4.3.16:
// signature 0x06054b50, the total entries at offset 10), found from the end (a comment may
// follow it).
function zipEntryCount(bytes) {
  assert.equal(bytes.readUInt32LE(0), 0x04034b50, 'a ZIP starts with a local file header');
  for (let offset = bytes.length - 22; offset >= 0; offset -= 1) {
    if (bytes.readUInt32LE(offset) === 0x06054b50) {
      return bytes.readUInt16LE(offset + 10);
    }
  }
  return assert.fail('no end of central directory record');
}

// What a link of the page answers, fetched in the page: its Content-Type, its sprite columns
// header, its bytes, and for an image its size.
async function fetchedInPage(page, href) {
  const answer = await page.evaluate(async (url) => {
    const response = await fetch(url);
    const blob = await response.blob();
    const image = blob.type.startsWith('image/') ? await createImageBitmap(blob) : null;
    return { status: response.status, type: blob.type,
             columns: response.headers.get('X-Oer-Sprite-Columns'),
             width: image?.width, height: image?.height,
             bytes: [...new Uint8Array(await blob.arrayBuffer())] };
  }, href);
  return { ...answer, bytes: Buffer.from(answer.bytes) };
}

// The job the page posts next (POST /v1/jobs), as the server answered it.
const postedJob = (page) => page.waitForResponse((response) =>
  new URL(response.url()).pathname === '/v1/jobs' && response.request().method() === 'POST')
  .then((response) => response.json());

let server = null;
let shop = null;
let browser = null;
const started = Date.now();
try {
  shop = await startShop();
  const shopUrl = `http://127.0.0.1:${shop.address().port}`;
  server = await startServer(serverPath, ['--cors-origins', shopUrl,
                                          '--max-upload-bytes', String(UPLOAD_LIMIT)]);
  shop.serveFor(new URL(server.url).port);

  browser = await launchChromium();

  const desktop = await browser.newContext({ viewport: { width: 1280, height: 800 } });
  await desktop.addInitScript(RECORD_EVENTS);
  await desktop.addInitScript(RECORD_FEEDBACK);
  // The browser's own complaints, for a failure's log.
  desktop.on('console', (message) => console.error(`browser console: ${message.text()}`));
  desktop.on('weberror', (error) => console.error(`browser error: ${error.error()}`));
  const page = await desktop.newPage();
  const renders = [];
  page.on('request', (request) => {
    if (request.url().includes('/v1/render')) {
      renders.push(request.url());
    }
  });

  let first;
  await check('the page at / shows a rendered frame of the element\'s size', async () => {
    await page.goto(`${server.url}/`);
    first = await fullFrame(page);
    assert.match(first.etag ?? '', /^"[0-9a-f]{64}"$/);
    assert.ok(first.serverTiming !== null, 'Server-Timing reaches the load event');
    assertRealFrame(await shownImage(page), 'first frame');
    // The first visible feedback, against the first frame (a cold server: its first scene).
    const { feedback, firstShown } = await page.evaluate(() =>
      ({ feedback: window.oerFeedback, firstShown: window.oerFrames[0].shownAt }));
    console.log(`  first visible feedback: loading indicator ${feedback.indicatorAt?.toFixed(0)} ms, ` +
                `poster ${feedback.posterAt?.toFixed(0) ?? 'not before the frame'} ms; ` +
                `first frame ${firstShown.toFixed(0)} ms, full frame ${first.shownAt.toFixed(0)} ms ` +
                '(since navigation)');
    assert.ok(feedback.indicatorAt !== null && feedback.indicatorAt < firstShown,
              `the loading indicator at ${feedback.indicatorAt} ms, the first frame at ${firstShown} ms`);
  });

  await check('before the first frame: a poster (a small frame of the view) and a loading indicator',
              async () => {
    // A fresh page whose full-size frames the test holds back 1 s (the poster, a small preview
    // with quality=50, passes at once): both must show meanwhile, and go with the first frame.
    const waiting = await desktop.newPage();
    const held = [];
    await waiting.route('**/v1/render?**', async (route) => {
      if (!route.request().url().includes('quality=')) {
        held.push(route.request().url());
        await new Promise((resolve) => setTimeout(resolve, 1000));
      }
      await route.continue().catch(() => {});
    });
    await waiting.goto(`${server.url}/?camera-orbit=10+20`);
    await waiting.waitForFunction(() => window.oerFeedback.posterAt !== null, null, { timeout: 10000 });
    const before = await overlays(waiting);
    const framesBefore = await waiting.evaluate(() => window.oerFrames.length);
    const busy = await waiting.locator('oer-viewer').getAttribute('aria-busy');
    await fullFrame(waiting);
    const after = await overlays(waiting);
    const { feedback, firstShown } = await waiting.evaluate(() =>
      ({ feedback: window.oerFeedback, firstShown: window.oerFrames[0].shownAt }));
    const cssWidth = await waiting.evaluate(() => document.querySelector('oer-viewer').clientWidth);
    await waiting.close();
    console.log(`  with the frame held back: indicator ${feedback.indicatorAt.toFixed(0)} ms, ` +
                `poster ${feedback.posterAt.toFixed(0)} ms (${feedback.posterWidth} px wide), ` +
                `first frame ${firstShown.toFixed(0)} ms`);
    assert.equal(framesBefore, 0, 'the poster came before any frame');
    assert.deepEqual({ placeholder: before.placeholder, indicator: before.indicator, poster: before.poster },
                     { placeholder: true, indicator: true, poster: true });
    assert.equal(busy, 'true', 'aria-busy until the first frame');
    assert.match(feedback.posterSrc, /^blob:/, 'the poster is the server\'s small frame');
    assert.ok(Math.abs(feedback.posterWidth - Math.round(cssWidth * 0.2)) <= 1,
              `a poster ${feedback.posterWidth} px wide for a ${cssWidth} px view`);
    assert.ok(feedback.posterAt < firstShown && feedback.indicatorAt < firstShown);
    assert.ok(held.length >= 1, 'the full frame was held back');
    assert.deepEqual({ placeholder: after.placeholder, message: after.message },
                     { placeholder: false, message: false });
  });

  await check('the element exposes the environment\'s lights and accepts lights="1,0,1"',
              async () => {
    const rig = await (await fetch(`${server.url}/v1/environments/default`)).json();
    const lights = await page.evaluate(() => document.querySelector('oer-viewer').lights);
    assert.equal(lights.length, rig.lights.length);
    assert.deepEqual(lights[0].direction, rig.lights[0].direction);
    const frames = await page.evaluate(() => window.oerFrames.length);
    await page.evaluate(() => document.querySelector('oer-viewer').setAttribute('lights', '1,0,1'));
    const dimmed = await fullFrame(page, frames);
    assert.match(dimmed.url, /[?&]lights=1%2C0%2C1(&|$)/);
    assert.notEqual(dimmed.etag, first.etag);
    const beforeRemoval = await page.evaluate(() => window.oerFrames.length);
    await page.evaluate(() => document.querySelector('oer-viewer').removeAttribute('lights'));
    assert.equal((await fullFrame(page, beforeRemoval)).etag, first.etag);
  });

  await check('a light\'s dimmer at 0.5 gives a frame between that light on and off', async () => {
    const rig = await (await fetch(`${server.url}/v1/environments/default`)).json();
    // The light with the largest share of the energy, whose dimming shows the most.
    const index = rig.lights.reduce((best, light, i) =>
      (light.luminance_share > rig.lights[best].luminance_share ? i : best), 0);
    const dimmer = page.locator('#light-switches input[type=range]').nth(index);
    const toggle = page.locator('#light-switches input[type=checkbox]').nth(index);
    assert.equal(await dimmer.getAttribute('aria-label'), `Light ${index + 1} weight`);
    const on = await shownImage(page);
    let frames = await page.evaluate(() => window.oerFrames.length);
    await dimmer.fill('0');
    await fullFrame(page, frames);
    const off = await shownImage(page);
    assert.equal(await toggle.isChecked(), false, 'a light dimmed to 0 is switched off');
    frames = await page.evaluate(() => window.oerFrames.length);
    const weightsEvent = page.evaluate(() => new Promise((resolve) => {
      document.querySelector('oer-viewer').addEventListener(
        'lights-change', ({ detail }) => resolve(detail.weights), { once: true });
    }));
    await dimmer.fill('0.5');
    const half = await fullFrame(page, frames);
    const expected = rig.lights.map((_, i) => (i === index ? 0.5 : 1)).join('%2C');
    assert.match(half.url, new RegExp(`[?&]lights=${expected}(&|$)`));
    assert.deepEqual(await weightsEvent, rig.lights.map((_, i) => (i === index ? 0.5 : 1)));
    const dimmed = await shownImage(page);
    console.log(`  mean luminance: on ${on.mean.toFixed(2)}, 0.5 ${dimmed.mean.toFixed(2)}, ` +
                `off ${off.mean.toFixed(2)}`);
    assert.ok(off.mean < dimmed.mean && dimmed.mean < on.mean,
              `0.5 gives ${dimmed.mean}, between off ${off.mean} and on ${on.mean}`);
    // The switch goes to 0 and back to the last weight above 0, not to 1.
    const viewer = page.locator('oer-viewer');
    await toggle.uncheck();
    assert.equal(await viewer.getAttribute('lights'), rig.lights.map((_, i) => (i === index ? 0 : 1)).join(','));
    await toggle.check();
    assert.equal(await viewer.getAttribute('lights'), rig.lights.map((_, i) => (i === index ? 0.5 : 1)).join(','));
    // The frames of the toggling may still arrive: wait for the one without lights.
    await page.locator('#all-on').click();
    const allOn = await page.waitForFunction(
      (count) => window.oerFrames.slice(count).find((frame) => frame.stage === 'full' &&
        !frame.url.includes('lights=')) ?? false,
      frames, { timeout: 30000 });
    assert.equal((await allOn.jsonValue()).etag, first.etag);
  });

  let afterDrag;
  await check('a drag sends previews, turns the camera and changes the image; release gives a full frame',
              async () => {
    const before = await shownImage(page);
    const box = await page.locator('oer-viewer').boundingBox();
    const frames = await page.evaluate(() => window.oerFrames.length);
    const x = box.x + box.width / 2;
    const y = box.y + box.height / 2;
    // The live status region's changes during the drag: none for the previews.
    await page.evaluate(() => {
      window.statusChanges = 0;
      window.statusObserver = new MutationObserver((records) => { window.statusChanges += records.length; });
      window.statusObserver.observe(document.getElementById('status'),
                                    { childList: true, characterData: true, subtree: true });
    });
    await page.mouse.move(x, y);
    await page.mouse.down();
    const firstDragRequest = renders.length;
    const dragStarted = Date.now();
    for (let step = 1; step <= 24; step += 1) {
      await page.mouse.move(x + step * 7.5, y + step * 2);
      await page.waitForTimeout(50);
    }
    const dragSeconds = (Date.now() - dragStarted) / 1000;
    const duringDrag = renders.slice(firstDragRequest);
    const dragStatus = await page.locator('#preview-rate').textContent();
    const statusChangesWhileDragging = await page.evaluate(() => window.statusChanges);
    await page.mouse.up();
    afterDrag = await fullFrame(page, frames);
    const statusChangesAfterRelease = await page.evaluate(() => {
      window.statusObserver.disconnect();
      return window.statusChanges;
    });
    const frameDetails = await page.evaluate((count) => window.oerFrames.slice(count), frames);
    assert.ok(duringDrag.length >= 1, 'requests while dragging');
    for (const url of duringDrag) {
      assert.match(url, /[?&]samples=1(&|$)/, `a preview: ${url}`);
      assert.match(url, /[?&]shadow_filter=hard(&|$)/, `a preview: ${url}`);
    }
    const previews = frameDetails.filter((frame) => frame.stage === 'preview');
    console.log(`  ${previews.length} previews shown in a ${dragSeconds.toFixed(2)} s drag ` +
                `(${(previews.length / dragSeconds).toFixed(1)}/s; ${duringDrag.length} requests), ` +
                `full frame ${afterDrag.milliseconds.toFixed(0)} ms after release`);
    assert.ok(previews.length >= 3, `${previews.length} previews shown while dragging`);
    // Frames per second beside the status while dragging, near the previews shown per second.
    const fps = Number(/^(\d+\.\d) fps$/.exec(dragStatus)?.[1]);
    assert.ok(fps > 0 && fps < 2 * previews.length / dragSeconds + 1, `preview rate "${dragStatus}"`);
    // The status (role=status, announced) is quiet through the previews and changes once settled.
    console.log(`  status changes: ${statusChangesWhileDragging} during the drag's ` +
                `${previews.length} previews, ${statusChangesAfterRelease} once settled`);
    assert.equal(statusChangesWhileDragging, 0, 'the status changed with the previews');
    assert.ok(statusChangesAfterRelease >= 1, 'the status shows the settled frame');
    assert.equal(await page.locator('#status').getAttribute('aria-live'), 'polite');
    assert.doesNotMatch(afterDrag.url, /samples=1/);
    const orbit = await page.evaluate(() => document.querySelector('oer-viewer').orbit);
    // 24 steps of 7.5 px right and 2 px down from the default orbit (30, 15), 0.4 degree a pixel.
    assert.ok(Math.abs(orbit.yaw - (30 - 180 * 0.4)) < 0.01, `yaw ${orbit.yaw}`);
    assert.ok(Math.abs(orbit.pitch - (15 + 48 * 0.4)) < 0.01, `pitch ${orbit.pitch}`);
    assert.notEqual(afterDrag.etag, first.etag);
    const after = await shownImage(page);
    assertRealFrame(after, 'frame after the drag');
    assert.notEqual(after.checksum, before.checksum, 'the image changed');
    assert.equal(after.naturalWidth, before.naturalWidth, 'full size again');
    // Over a floor the orbit stops at the horizon; without one it may go a little below.
    const lowest = await page.evaluate(() => {
      const viewer = document.querySelector('oer-viewer');
      const saved = viewer.getAttribute('camera-orbit');
      viewer.orbit = { yaw: 0, pitch: -8 };
      const overFloor = viewer.orbit.pitch;
      viewer.setAttribute('ground', 'off');
      viewer.orbit = { yaw: 0, pitch: -8 };
      const withoutFloor = viewer.orbit.pitch;
      viewer.removeAttribute('ground');
      viewer.setAttribute('camera-orbit', saved);
      return { overFloor, withoutFloor };
    });
    assert.deepEqual(lowest, { overFloor: 0, withoutFloor: -8 });
  });

  await check('the page\'s URL reproduces the same frame (same ETag) and its hotspots', async () => {
    // A hotspot placed in the page goes into its link (its name and its point of the surface),
    // and the link shows it again: the same name, the same point, at the same place in the view.
    const hotspotsShown = async (where) => (await where.waitForFunction(() => {
      const viewer = document.querySelector('oer-viewer');
      const hotspots = [...viewer.querySelectorAll(':scope > .hotspot')];
      if (hotspots.length === 0 || !hotspots.every((hotspot) => hotspot.hasAttribute('data-visible'))) {
        return false;
      }
      const view = viewer.getBoundingClientRect();
      return hotspots.map((hotspot) => {
        const rect = hotspot.getBoundingClientRect();
        return { slot: hotspot.slot, surface: hotspot.dataset.surface, text: hotspot.textContent,
                 x: rect.x + rect.width / 2 - view.x, y: rect.y + rect.height / 2 - view.y };
      });
    }, null, { timeout: 15000 })).jsonValue();
    await page.waitForFunction(() => location.search.includes('camera-orbit'));
    const box = await page.locator('oer-viewer').boundingBox();
    await page.locator('#place-hotspot').click();
    await page.mouse.click(box.x + box.width / 2, box.y + box.height / 2);
    const placed = await hotspotsShown(page);
    await page.locator('#place-hotspot').click();
    const saved = page.url();
    assert.deepEqual(new URL(saved).searchParams.getAll('hotspot'),
                     [`${placed[0].text} ${placed[0].surface}`], saved);
    const again = await desktop.newPage();
    await again.goto(saved);
    const frame = await fullFrame(again);
    assert.equal(frame.etag, afterDrag.etag, `${saved} gives the frame it was saved from`);
    const restored = await hotspotsShown(again);
    const identity = ({ slot, surface, text }) => ({ slot, surface, text });
    assert.deepEqual(restored.map(identity), placed.map(identity));
    console.log(`  hotspot ${placed[0].slot} at ${placed[0].x.toFixed(1)}, ${placed[0].y.toFixed(1)} ` +
                `placed, ${restored[0].x.toFixed(1)}, ${restored[0].y.toFixed(1)} from its link`);
    assert.ok(Math.abs(restored[0].x - placed[0].x) < 1 && Math.abs(restored[0].y - placed[0].y) < 1,
              `the link shows the hotspot at ${restored[0].x}, ${restored[0].y}, placed at ` +
              `${placed[0].x}, ${placed[0].y}`);
    await page.locator('#clear-hotspots').click();
    assert.doesNotMatch(page.url(), /[?&]hotspot=/);

    // Exposure, a background color, no ground and a turned environment, set with the controls.
    const frames = await page.evaluate(() => window.oerFrames.length);
    await page.locator('#exposure').fill('1.5');
    await page.locator('#background').selectOption('color');
    await page.locator('#background-color').fill('#336699');
    await page.locator('#ground').selectOption('off');
    await page.locator('#shadows').uncheck();
    await page.locator('#environment-yaw').fill('90');
    const handle = await page.waitForFunction(
      (count) => window.oerFrames.slice(count).find((shown) => !shown.preview &&
        !shown.preliminary && shown.url.includes('environment_yaw=90')) ?? false, frames,
      { timeout: 30000 });
    const dressed = await handle.jsonValue();
    for (const parameter of ['exposure=1.5', 'background=%23336699', 'ground=off', 'shadows=off',
                             'environment_yaw=90']) {
      assert.match(dressed.url, new RegExp(`[?&]${parameter}(&|$)`), dressed.url);
    }
    assert.notEqual(dressed.etag, afterDrag.etag);
    const dressedLink = page.url();
    for (const parameter of ['exposure=1.5', 'background=%23336699', 'ground=off', 'shadows=off',
                             'environment-yaw=90']) {
      assert.match(dressedLink, new RegExp(`[?&]${parameter}(&|$)`), dressedLink);
    }
    await again.goto(dressedLink);
    assert.equal((await fullFrame(again)).etag, dressed.etag, `${dressedLink} gives the same frame`);
    // The link sets the controls too.
    assert.equal(await again.locator('#exposure').inputValue(), '1.5');
    assert.equal(await again.locator('#background').inputValue(), 'color');
    assert.equal(await again.locator('#background-color').inputValue(), '#336699');
    assert.equal(await again.locator('#ground').inputValue(), 'off');
    assert.equal(await again.locator('#shadows').isChecked(), false);
    assert.equal(await again.locator('#environment-yaw').inputValue(), '90');
    await again.close();

    // A transparent background comes as PNG (JPEG has no alpha), and its link keeps it.
    const before = await page.evaluate(() => window.oerFrames.length);
    await page.locator('#background').selectOption('transparent');
    const clear = await fullFrame(page, before);
    assert.match(clear.url, /[?&]background=transparent(&|$)/);
    assert.match(clear.url, /[?&]format=png(&|$)/);
    assert.match(page.url(), /[?&]background=transparent(&|$)/);
    // The shadow-only floor at half strength over transparency: its frame and its link.
    const uncaught = await page.evaluate(() => window.oerFrames.length);
    await page.locator('#ground').selectOption('shadow');
    await page.locator('#shadow-intensity').fill('0.5');
    const caught = await (await page.waitForFunction(
      (count) => window.oerFrames.slice(count).find((shown) => !shown.preview &&
        !shown.preliminary && shown.url.includes('ground=shadow') &&
        shown.url.includes('shadow_intensity=0.5')) ?? false,
      uncaught, { timeout: 30000 })).jsonValue();
    assert.match(caught.url, /[?&]format=png(&|$)/);
    for (const parameter of ['ground=shadow', 'shadow-intensity=0.5']) {
      assert.match(page.url(), new RegExp(`[?&]${parameter}(&|$)`), page.url());
    }
    for (const name of ['exposure', 'background', 'ground', 'shadows', 'shadow-intensity',
                        'environment-yaw']) {
      await page.evaluate((attribute) => document.querySelector('oer-viewer').removeAttribute(attribute), name);
    }
    assert.equal(await page.locator('#background').inputValue(), 'env');
    assert.equal(await page.locator('#background-color').isHidden(), true);

  });

  await check('hotspots in a link that are mangled or hostile are left out, in plain words', async () => {
    const linked = await desktop.newPage();
    const dialogs = [];
    linked.on('dialog', (dialog) => {
      dialogs.push(dialog.message());
      dialog.dismiss();
    });
    const query = new URLSearchParams();
    query.append('hotspot', '<img/src=x/onerror=alert(1)> 0 0 0 1 0 0');
    query.append('hotspot', 'kept 0 0 0 0.2 0.3 0.5');
    query.append('hotspot', 'kept 0 0 1 0.2 0.3 0.5');
    query.append('hotspot', 'outside 0 0 0 2 -1 0');
    query.append('hotspot', 'short 0 0');
    await linked.goto(`${server.url}/?${query}`);
    // The page's script has run to its end once it says so.
    const message = linked.locator('#upload-status');
    await linked.waitForFunction(() => document.getElementById('upload-status').textContent !== '');
    assert.match(await message.textContent(),
                 /^This link's hotspots are not all shown: 4 of 5 left out \("<img\/src=x\/onerror=alert…" is not a hotspot name/);
    assert.equal(await message.getAttribute('class'), 'error');
    assert.deepEqual(await linked.evaluate(() =>
      [...document.querySelectorAll('oer-viewer > *')].map((child) => child.slot)), ['hotspot-kept']);
    assert.equal(await linked.locator('img[src="x"]').count(), 0, 'no markup from the link');
    assert.deepEqual(dialogs, []);
    // The link now holds what the page shows.
    assert.deepEqual(new URL(linked.url()).searchParams.getAll('hotspot'), ['kept 0 0 0 0.2 0.3 0.5']);
    await linked.close();
  });

  await check('the status line shows the server\'s time, then "cached" for the same frame again',
              async () => {
    // A fresh context each time: no browser cache, so the second request reaches the server.
    const link = `${server.url}/?camera-orbit=75+25`;
    const statuses = [];
    for (let visit = 0; visit < 2; visit += 1) {
      const context = await browser.newContext({ viewport: { width: 1280, height: 800 } });
      await context.addInitScript(RECORD_EVENTS);
      const visitor = await context.newPage();
      await visitor.goto(link);
      // The frame of the settled layout: the lights panel, once shown with its map, takes
      // height from the view.
      await visitor.locator('#light-switches input').first().waitFor();
      const handle = await visitor.waitForFunction(() => {
        const map = document.getElementById('light-map-image');
        if (!map.complete || map.naturalWidth === 0) {
          return false;
        }
        const rect = document.querySelector('oer-viewer').getBoundingClientRect();
        const frame = window.oerFrames.at(-1);
        return frame && !frame.preview && frame.height === Math.round(rect.height * devicePixelRatio)
          ? frame : false;
      }, null, { timeout: 30000 });
      const frame = await handle.jsonValue();
      const text = await visitor.locator('#status').textContent();
      assert.ok(text.includes(`${(frame.bytes / 1024).toFixed(0)} KiB`), `bytes in "${text}"`);
      statuses.push({ text, frame });
      await context.close();
    }
    const [miss, hit] = statuses;
    assert.equal(miss.frame.cache, 'miss');
    const serverMs = Number(/, server (\d+) ms$/.exec(miss.text)?.[1]);
    assert.ok(serverMs > 0, `server time in "${miss.text}"`);
    assert.equal(hit.frame.cache, 'hit');
    assert.equal(hit.frame.etag, miss.frame.etag, `${miss.frame.url} then ${hit.frame.url}`);
    assert.match(hit.text, /^\d+×\d+, \d+ KiB, \d+ ms, cached$/);
  });

  await check('keyboard alone switches a light off in the panel and orbits', async () => {
    const rig = await (await fetch(`${server.url}/v1/environments/default`)).json();
    assert.equal(await page.locator('#light-switches input[type=checkbox]').count(), rig.lights.length);
    const before = await shownImage(page);
    let frames = await page.evaluate(() => window.oerFrames.length);
    // Tab from the first light's dimmer to the second light's switch, then Space.
    await page.locator('#light-switches input[type=range]').nth(0).focus();
    await page.keyboard.press('Tab');
    assert.equal(await page.evaluate(() => document.activeElement.closest('label')?.textContent),
                 await page.locator('#light-switches label').nth(1).textContent());
    await page.keyboard.press('Space');
    const switched = await fullFrame(page, frames);
    const expected = rig.lights.map((_, index) => (index === 1 ? 0 : 1)).join('%2C');
    assert.match(switched.url, new RegExp(`[?&]lights=${expected}(&|$)`));
    assert.notEqual((await shownImage(page)).checksum, before.checksum, 'the image changed');
    assert.match(page.url(), new RegExp(`[?&]lights=${expected}(&|$)`));

    const yaw = (await page.evaluate(() => document.querySelector('oer-viewer').orbit)).yaw;
    frames = await page.evaluate(() => window.oerFrames.length);
    await page.locator('oer-viewer').focus();
    await page.keyboard.press('ArrowLeft');
    const turned = await fullFrame(page, frames);
    assert.notEqual(turned.etag, switched.etag);
    const orbit = await page.evaluate(() => document.querySelector('oer-viewer').orbit);
    assert.ok(Math.abs(orbit.yaw - (yaw + 5)) < 0.01, `yaw ${yaw} -> ${orbit.yaw}`);
    await page.locator('#all-on').click();
    assert.equal(await page.locator('oer-viewer').getAttribute('lights'), null);
  });

  await check('a color variant recolors the product, in the request and the link', async () => {
    const frames = await page.evaluate(() => window.oerFrames.length);
    const original = await shownImage(page);
    await page.locator('input[name=color][value="#b3262d"]').check();
    const red = await fullFrame(page, frames);
    // #b3262d in linear RGB (sRGB transfer function): 0.4508, 0.0194, 0.0262.
    assert.match(red.url, /[?&]base_color=0\.4508%2C0\.0194%2C0\.0262(&|$)/, red.url);
    assert.match(page.url(), /[?&]base-color=%23b3262d(&|$)/);
    const recolored = await shownImage(page);
    console.log(`  mean red minus green: original ${original.redOverGreen.toFixed(2)}, ` +
                `red variant ${recolored.redOverGreen.toFixed(2)}`);
    assert.ok(recolored.redOverGreen > original.redOverGreen + 5,
              `red - green ${original.redOverGreen} -> ${recolored.redOverGreen}`);
    const beforeOriginal = await page.evaluate(() => window.oerFrames.length);
    await page.locator('input[name=color][value=""]').check();
    const back = await fullFrame(page, beforeOriginal);
    assert.doesNotMatch(back.url, /base_color/);
    assert.equal(await page.locator('oer-viewer').getAttribute('base-color'), null);
  });

  await check('a color on one part recolors that material only, in the request and the link',
              async () => {
    const part = page.locator('#color-part');
    assert.equal(await page.locator('#color-part-group').isVisible(), true,
                 'the built-in product has two parts');
    await part.selectOption('dress form stand');
    const frames = await page.evaluate(() => window.oerFrames.length);
    await page.locator('input[name=color][value="#2b3a67"]').check();
    const navy = await fullFrame(page, frames);
    assert.match(navy.url, /[?&]base_color_material=dress\+form\+stand(&|$)/, navy.url);
    assert.match(page.url(), /[?&]base-color-material=dress\+form\+stand(&|$)/);
    const back = await page.evaluate(() => window.oerFrames.length);
    await page.locator('input[name=color][value=""]').check();
    assert.doesNotMatch((await fullFrame(page, back)).url, /base_color/);
    assert.equal(await page.locator('oer-viewer').getAttribute('base-color-material'), null);
    await part.selectOption('');
  });

  await check('a frame slower than half a second shows the waiting bar (aria-busy) until it comes',
    async () => {
      const viewer = page.locator('oer-viewer');
      const waitingShown = () => viewer.evaluate((element) => ({
        attribute: element.hasAttribute('waiting'),
        busy: element.getAttribute('aria-busy'),
        display: getComputedStyle(element.shadowRoot.querySelector('.waiting')).display,
      }));
      assert.deepEqual(await waitingShown(), { attribute: false, busy: null, display: 'none' });
      // The real server's frames, held back 1.5 s on their way to the page (one the element
      // aborted meanwhile, for the next, is gone: nothing to continue).
      const slow = async (route) => {
        await new Promise((resolve) => setTimeout(resolve, 1500));
        await route.continue().catch(() => {});
      };
      await page.route('**/v1/render?**', slow);
      const frames = await page.evaluate(() => window.oerFrames.length);
      const exposure = await viewer.getAttribute('exposure');
      const started = Date.now();
      await viewer.evaluate((element) => element.setAttribute('exposure', '0.25'));
      await page.waitForFunction(
        () => document.querySelector('oer-viewer').hasAttribute('waiting'), null,
        { timeout: 1400 });
      const shownAfter = Date.now() - started;
      assert.deepEqual(await waitingShown(), { attribute: true, busy: 'true', display: 'block' });
      assert.ok(shownAfter >= 450, `the bar came after ${shownAfter} ms, before half a second`);
      await page.unroute('**/v1/render?**', slow);
      await fullFrame(page, frames);
      await page.waitForFunction(
        () => !document.querySelector('oer-viewer').hasAttribute('waiting'));
      assert.deepEqual(await waitingShown(), { attribute: false, busy: null, display: 'none' });
      console.log(`  the waiting bar came ${shownAfter} ms after the frame was asked for`);
      // A frame as quick as a cached one (the one shown before) never shows it.
      const again = await page.evaluate(() => window.oerFrames.length);
      await viewer.evaluate((element, value) => {
        if (value === null) {
          element.removeAttribute('exposure');
        } else {
          element.setAttribute('exposure', value);
        }
      }, exposure);
      await fullFrame(page, again);
      assert.equal((await waitingShown()).attribute, false);
    });

  await check('the lights panel marks each light where the environment\'s preview is bright',
              async () => {
    const rig = await (await fetch(`${server.url}/v1/environments/default`)).json();
    await page.waitForFunction(() => document.getElementById('light-map-image').complete &&
      document.getElementById('light-map-image').naturalWidth > 0);
    const marks = await page.evaluate(() => {
      const image = document.getElementById('light-map-image');
      const canvas = document.createElement('canvas');
      canvas.width = image.naturalWidth;
      canvas.height = image.naturalHeight;
      const context = canvas.getContext('2d');
      context.drawImage(image, 0, 0);
      const { data } = context.getImageData(0, 0, canvas.width, canvas.height);
      const luminance = (x, y) => {
        const i = 4 * (y * canvas.width + x);
        return 0.2126 * data[i] + 0.7152 * data[i + 1] + 0.0722 * data[i + 2];
      };
      const all = [];
      for (let y = 0; y < canvas.height; y += 1) {
        for (let x = 0; x < canvas.width; x += 1) {
          all.push(luminance(x, y));
        }
      }
      all.sort((a, b) => a - b);
      const box = image.getBoundingClientRect();
      return {
        median: all[all.length >> 1],
        src: image.getAttribute('src'),
        markers: [...document.querySelectorAll('#light-map .marker')].map((marker) => {
          const rect = marker.getBoundingClientRect();
          // The marker's centre on the image, in the image's own pixels; the brightest pixel
          // within 2 % of the width around it (the light's region, not one pixel of it).
          const cx = Math.round((rect.x + rect.width / 2 - box.x) / box.width * canvas.width);
          const cy = Math.round((rect.y + rect.height / 2 - box.y) / box.height * canvas.height);
          const reach = Math.round(0.02 * canvas.width);
          let brightest = 0;
          for (let dy = -reach; dy <= reach; dy += 1) {
            for (let dx = -reach; dx <= reach; dx += 1) {
              const x = (cx + dx + canvas.width) % canvas.width;
              const y = Math.min(canvas.height - 1, Math.max(0, cy + dy));
              brightest = Math.max(brightest, luminance(x, y));
            }
          }
          return { text: marker.textContent, brightest };
        }),
      };
    });
    assert.equal(marks.src, '/v1/environments/default/preview.jpg');
    assert.equal(marks.markers.length, rig.lights.length);
    console.log(`  preview median luminance ${marks.median.toFixed(1)}; at the markers ` +
                marks.markers.map((marker) => marker.brightest.toFixed(0)).join(', '));
    marks.markers.forEach((marker, index) => {
      assert.equal(marker.text, String(index + 1));
      // Far brighter than the map's median, or clipped white where the map itself is bright
      // (the studio's grey room: median 139).
      assert.ok(marker.brightest > Math.min(2 * marks.median + 40, 250),
                `light ${index + 1}'s marker sits on luminance ${marker.brightest}, the map's median is ${marks.median}`);
    });
  });

  await check('the turntable turns the product through previews, and stopping it gives a full frame',
              async () => {
    const yaw = (await page.evaluate(() => document.querySelector('oer-viewer').orbit)).yaw;
    const frames = await page.evaluate(() => window.oerFrames.length);
    await page.locator('#turntable').check();
    await page.waitForFunction((count) =>
      window.oerFrames.slice(count).filter((frame) => frame.stage === 'preview').length >= 3, frames,
    { timeout: 30000 });
    await page.locator('#turntable').uncheck();
    const stopped = await fullFrame(page, frames);
    const shown = await page.evaluate((count) => window.oerFrames.slice(count), frames);
    const yaws = shown.filter((frame) => frame.stage === 'preview')
      .map((frame) => Number(new URL(frame.url, server.url).searchParams.get('yaw')));
    for (let i = 1; i < yaws.length; i += 1) {
      assert.ok(yaws[i] > yaws[i - 1], `the turntable's yaws increase: ${yaws.join(', ')}`);
    }
    assert.ok(yaws[0] > yaw, `from ${yaw} on: ${yaws.join(', ')}`);
    assert.doesNotMatch(stopped.url, /samples=1/);
    assert.equal(await page.locator('oer-viewer').getAttribute('auto-rotate'), null);
  });

  await check('Download PNG saves the view at full quality: a PNG of the view\'s size', async () => {
    const requestsBefore = renders.length;
    const [download] = await Promise.all([page.waitForEvent('download'),
                                          page.locator('#download').click()]);
    assert.equal(download.suggestedFilename(), 'oer-frame.png');
    const bytes = readFileSync(await download.path());
    // PNG signature, then the IHDR chunk: width and height, big-endian (PNG spec, 11.2.2).
    assert.deepEqual([...bytes.subarray(0, 8)], [0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]);
    assert.equal(bytes.toString('latin1', 12, 16), 'IHDR');
    const view = await shownImage(page);
    assert.equal(bytes.readUInt32BE(16), view.expectedWidth, 'PNG width');
    assert.equal(bytes.readUInt32BE(20), view.expectedHeight, 'PNG height');
    const request = renders.slice(requestsBefore).find((url) => url.includes('format=png'));
    assert.match(request ?? '', /[?&]samples=4(&|$)/, `the download's request: ${request}`);
    assert.doesNotMatch(request, /[?&]quality=/);
    console.log(`  downloaded ${bytes.length} bytes, ${bytes.readUInt32BE(16)}x${bytes.readUInt32BE(20)}`);
  });

  await check('Spin set: a turntable job of the view, its progress, then an animated WebP, a sprite ' +
              'sheet and a ZIP', async () => {
    // The view dressed beyond the defaults, which the job's request must carry: the element's
    // renderRequest() posted is the frame shown (the same ETag).
    const viewer = page.locator('oer-viewer');
    const frames = await page.evaluate(() => window.oerFrames.length);
    await viewer.evaluate((element) => {
      element.setAttribute('lights', '1,0.5,0');
      element.setAttribute('exposure', '0.5');
      element.setAttribute('ground', 'shadow');
    });
    const dressed = await (await page.waitForFunction((count) => window.oerFrames.slice(count)
      .find((frame) => !frame.preview && !frame.preliminary && frame.url.includes('ground=shadow') &&
        frame.url.includes('exposure=0.5') && frame.url.includes('lights=1%2C0.5%2C0')) ?? false,
    frames, { timeout: 30000 })).jsonValue();
    const posted = await page.evaluate(async () => {
      const response = await fetch('/v1/render', {
        method: 'POST', headers: { 'Content-Type': 'application/json' },
        body: JSON.stringify(document.querySelector('oer-viewer').renderRequest()),
      });
      return { status: response.status, etag: response.headers.get('ETag') };
    });
    assert.deepEqual(posted, { status: 200, etag: dressed.etag });

    // Views out of the field's range are refused in the page, with no job.
    const jobPosts = [];
    const onRequest = (request) => {
      if (request.url().endsWith('/v1/jobs')) {
        jobPosts.push(request.url());
      }
    };
    page.on('request', onRequest);
    await page.locator('#job-views').fill('500');
    await page.locator('#spin-set').click();
    assert.equal(await page.locator('#status').textContent(), 'Views: a whole number from 2 to 60.');
    page.off('request', onRequest);
    assert.deepEqual(jobPosts, []);

    // A small set: 6 views of 128x128. The status announces its start and its end only; the
    // progress goes to the bar and the text beside it.
    await page.locator('#job-views').fill('6');
    await page.locator('#job-size').selectOption('128');
    await page.evaluate(() => {
      window.jobTexts = { status: [], progress: [] };
      window.jobObserver = new MutationObserver((records) => {
        for (const record of records) {
          window.jobTexts[record.target.id === 'status' ? 'status' : 'progress']
            .push(record.target.textContent);
        }
      });
      for (const id of ['status', 'job-progress-text']) {
        window.jobObserver.observe(document.getElementById(id), { childList: true });
      }
    });
    const posting = postedJob(page);
    await page.locator('#spin-set').click();
    const { id } = await posting;
    const links = page.locator('#job-results a');
    await links.nth(2).waitFor({ timeout: 30000 });
    const texts = await page.evaluate(() => {
      window.jobObserver.disconnect();
      return window.jobTexts;
    });
    console.log(`  spin set progress: ${texts.progress.join(' | ')}`);
    assert.deepEqual(texts.status, ['Making the spin set: 6 views…',
                                    'Spin set ready: 6 views; save them with the links beside it.']);
    assert.equal(texts.progress.at(-1), '6/6 views, done');
    assert.equal(await page.locator('#job-progress').evaluate((bar) => bar.value), 1);
    assert.equal(await page.locator('#job-cancel').isHidden(), true);
    const job = await (await fetch(`${server.url}/v1/jobs/${id}`)).json();
    assert.deepEqual({ state: job.state, done: job.done, total: job.total },
                     { state: 'done', done: 6, total: 6 });

    const shown = await links.evaluateAll((anchors) => anchors.map((anchor) => {
      const box = anchor.getBoundingClientRect();
      return { text: anchor.textContent, href: anchor.href, download: anchor.download,
               width: box.width, height: box.height };
    }));
    assert.deepEqual(shown.map((link) => link.text), ['Animated WebP', 'Sprite sheet', 'ZIP (6 images)']);
    const file = `spin-set-${id.slice(0, 8)}`;
    assert.deepEqual(shown.map((link) => link.download),
                     [`${file}.webp`, `${file}-sprites.jpg`, `${file}.zip`]);
    for (const link of shown) {
      assert.ok(link.width >= 24 && link.height >= 24, `${link.text}: ${link.width}x${link.height}`);
    }
    const [webp, sheet, zip] = await Promise.all(shown.map((link) => fetchedInPage(page, link.href)));
    // An animated WebP: VP8X (its canvas 128x128, stored minus one), ANIM, one ANMF per view.
    const chunks = webpChunks(webp.bytes);
    assert.equal(webp.type, 'image/webp');
    assert.equal(chunks[0].fourcc, 'VP8X');
    assert.deepEqual([chunks[0].payload.readUIntLE(4, 3) + 1, chunks[0].payload.readUIntLE(7, 3) + 1],
                     [128, 128]);
    assert.ok(chunks.some((chunk) => chunk.fourcc === 'ANIM'), 'an ANIM chunk');
    assert.equal(chunks.filter((chunk) => chunk.fourcc === 'ANMF').length, 6, 'a frame per view');
    // The sheet: the views in rows of ceil(sqrt(6)) = 3, two rows, in the frames' format.
    assert.deepEqual({ type: sheet.type, columns: sheet.columns, width: sheet.width, height: sheet.height },
                     { type: 'image/jpeg', columns: '3', width: 3 * 128, height: 2 * 128 });
    assert.equal(zipEntryCount(zip.bytes), 6);
    console.log(`  WebP ${webp.bytes.length} bytes, sprite sheet ${sheet.bytes.length}, ZIP ${zip.bytes.length}`);

    // Its first view is the view itself (same yaw) at 128x128, byte for byte.
    const sameAsView = await page.evaluate(async ([jobId, frameName]) => {
      const render = { ...document.querySelector('oer-viewer').renderRequest(), width: 128, height: 128 };
      const [fromJob, fromView] = await Promise.all([
        fetch(`/v1/jobs/${jobId}/frames/${frameName}`),
        fetch('/v1/render', { method: 'POST', headers: { 'Content-Type': 'application/json' },
                              body: JSON.stringify(render) }),
      ]);
      const [a, b] = await Promise.all([fromJob, fromView].map(async (response) =>
        new Uint8Array(await response.arrayBuffer())));
      return { sizes: [a.length, b.length], same: a.length === b.length && a.every((value, i) => value === b[i]) };
    }, [id, job.frames[0].name]);
    assert.ok(sameAsView.same, `the job's first view and the view differ: ${sameAsView.sizes.join(' vs ')} bytes`);

    const found = await axeViolations(page, '#downloads');
    assert.deepEqual(found.serious, [], 'axe-core on the image sets');
    for (const name of ['lights', 'exposure', 'ground']) {
      await viewer.evaluate((element, attribute) => element.removeAttribute(attribute), name);
    }
  });

  await check('Cancel stops a spin set: the page says so and the server\'s job is cancelled', async () => {
    // A set far longer than the click that cancels it.
    await page.locator('#job-views').fill('60');
    await page.locator('#job-size').selectOption('1024');
    const posting = postedJob(page);
    await page.locator('#spin-set').click();
    const { id } = await posting;
    await page.locator('#job-cancel').click();
    const status = await (await page.waitForFunction(() => {
      const text = document.getElementById('status').textContent;
      return text.includes('cancelled') ? text : false;
    }, null, { timeout: 15000 })).jsonValue();
    const job = await (await fetch(`${server.url}/v1/jobs/${id}`)).json();
    console.log(`  "${status}"; the server's job: ${job.state}, ${job.done} of ${job.total} done`);
    assert.equal(job.state, 'cancelled');
    assert.ok(job.done < job.total, 'cancelled before its views were all made');
    const made = Number(/^Spin set cancelled after (\d+) of 60 views\.$/.exec(status)?.[1]);
    assert.ok(made <= job.done, `"${status}" against ${job.done} made`);
    assert.match(await page.locator('#job-progress-text').textContent(), /, cancelled$/);
    assert.equal(await page.locator('#job-cancel').isHidden(), true);
    assert.equal(await page.locator('#job-results a').count(), 0, 'nothing to save');
    // The keyboard's focus does not go with the Cancel button: to the button that started it.
    assert.equal(await page.evaluate(() => document.activeElement.id), 'spin-set');
    await page.locator('#job-views').fill('36');
    await page.locator('#job-size').selectOption('512');
  });

  await check('Tab reaches every control of the strip, each named and its focus outlined', async () => {
    // From the view, by keyboard, so that :focus-visible applies as it does for a keyboard user.
    await page.locator('oer-viewer').focus();
    await page.keyboard.press('Tab');
    const seen = [];
    for (let step = 0; step < 40; step += 1) {
      const focused = await page.evaluate(() => {
        const element = document.activeElement;
        if (!element?.closest('#controls')) {
          return null;
        }
        const name = element.getAttribute('aria-label') ||
          [...(element.labels ?? [])].map((label) => label.textContent.trim()).join(' ');
        return { id: element.id, name: name || element.textContent.trim(),
                 outline: getComputedStyle(element).outlineStyle };
      });
      if (!focused) {
        break;
      }
      seen.push(focused);
      await page.keyboard.press('Tab');
    }
    for (const control of seen) {
      assert.ok(control.name.length > 0, `a control without a name: ${JSON.stringify(control)}`);
      assert.equal(control.outline, 'solid', `focus of ${control.name} is not outlined`);
    }
    const names = seen.map((control) => control.name);
    for (const expected of ['Product', 'Environment', 'Upload…', 'Reset view', 'Background', 'Ground',
                            'Shadows', 'Turntable', 'Download PNG', 'Place hotspot', 'Views', 'Size',
                            'Spin set',
                            'Light 1 weight', 'All on',
                            'All off']) {
      assert.ok(names.includes(expected), `Tab never reaches ${expected}: ${names.join(' | ')}`);
    }
    assert.ok(names.some((name) => name.startsWith('Exposure')), names.join(' | '));
    assert.ok(names.some((name) => name.startsWith('Environment rotation')), names.join(' | '));
  });

  // Presets and uploads. The page's upload status, every text it showed since
  // watchUploadStatus(), and the end of an upload (its group no longer aria-busy).
  const uploadStatus = page.locator('#upload-status');
  // Each text also records the frame on screen when it appeared (window.uploadSeen).
  const watchUploadStatus = () => page.evaluate(() => {
    window.uploadObserver?.disconnect();
    window.uploadTexts = [];
    window.uploadSeen = [];
    window.uploadObserver = new MutationObserver((records) => {
      for (const record of records) {
        for (const node of record.addedNodes) {
          window.uploadTexts.push(node.data);
          window.uploadSeen.push({ text: node.data, shownUrl: window.oerFrames.at(-1)?.url ?? '' });
        }
      }
    });
    window.uploadObserver.observe(document.getElementById('upload-status'), { childList: true });
  });
  const uploadEnded = () => page.waitForFunction(
    () => !document.getElementById('upload-group').hasAttribute('aria-busy'), null, { timeout: 30000 });
  const postAsset = async (route, type, bytes) => {
    const response = await fetch(`${server.url}${route}`,
                                 { method: 'POST', headers: { 'Content-Type': type }, body: bytes });
    return { status: response.status, body: await response.json() };
  };
  const viewerAttribute = (name) => page.locator('oer-viewer').getAttribute(name);

  await check('a file the server rejects shows its problem+json detail verbatim; the view stays',
              async () => {
    const garbage = Buffer.from('not a Radiance file');
    // The server's own answer to the same bytes under the same name, which the page sends and
    // the problem names the file by.
    const answer = await postAsset('/v1/environments?filename=broken.hdr', 'image/vnd.radiance',
                                   garbage);
    assert.equal(answer.status, 422);
    assert.match(answer.body.detail, /^broken\.hdr: /);
    const environment = await viewerAttribute('environment');
    const frames = await page.evaluate(() => window.oerFrames.length);
    await page.locator('#upload-file').setInputFiles({ name: 'broken.hdr', mimeType: 'image/vnd.radiance',
                                                       buffer: garbage });
    await uploadEnded();
    assert.equal(await uploadStatus.textContent(), answer.body.detail);
    assert.equal(await uploadStatus.getAttribute('class'), 'error');
    assert.equal(await viewerAttribute('environment'), environment);
    assert.equal(await page.locator('#environment-picker').inputValue(), environment);
    assert.equal(await page.evaluate(() => window.oerFrames.length), frames, 'no new frame');

    // Refused in the page, without a request: a file of no known kind, one over the server's
    // limit (GET /v1/info's max_upload_bytes).
    const uploads = [];
    const onRequest = (request) => {
      if (request.method() === 'POST') {
        uploads.push(request.url());
      }
    };
    page.on('request', onRequest);
    await page.locator('#upload-file').setInputFiles({ name: 'notes.txt', mimeType: 'text/plain',
                                                       buffer: Buffer.from('hello') });
    assert.equal(await uploadStatus.textContent(),
                 'notes.txt: not a product (.glb, .gltf, .obj) or an environment (.hdr, .exr, .jpg, .png)');
    await page.locator('#upload-file').setInputFiles({ name: 'huge.exr', mimeType: 'image/x-exr',
                                                       buffer: Buffer.alloc(UPLOAD_LIMIT + 1) });
    await uploadEnded();
    assert.equal(await uploadStatus.textContent(),
                 'huge.exr is 4,194,305 bytes (4.0 MiB), over the server\'s upload limit of ' +
                 '4,194,304 bytes (4.0 MiB)');
    page.off('request', onRequest);
    assert.deepEqual(uploads, []);
    assert.equal(await viewerAttribute('environment'), environment);
  });

  let uploadedEnvironment;
  await check('a real HDR uploads with progress, then is picked and shown, its lights in the panel',
              async () => {
    const name = 'studio.exr';
    const bytes = readFileSync(`/usr/share/blender/datafiles/studiolights/world/${name}`);
    // Weights for the default studio's lights, which the new environment's must not inherit.
    await page.evaluate(() => document.querySelector('oer-viewer').setAttribute('lights', '1,0,1'));
    await watchUploadStatus();
    const frames = await page.evaluate(() => window.oerFrames.length);
    await page.locator('#upload-file').setInputFiles({ name, mimeType: 'image/x-exr', buffer: bytes });
    await uploadEnded();
    // The same bytes again: the server answers the stored rig, whose id the page must show.
    const { body: rig } = await postAsset('/v1/environments', 'image/x-exr', bytes);
    uploadedEnvironment = rig.id;
    const texts = await page.evaluate(() => window.uploadTexts);
    console.log(`  upload status: ${texts.join(' | ')}`);
    assert.equal(texts[0], `Uploading ${name}: 0 %`);
    assert.ok(texts.includes(`Uploading ${name}: 100 %`), texts.join(' | '));
    assert.ok(texts.includes('Preprocessing lights…'), texts.join(' | '));
    assert.equal(texts.at(-1), `${name}: ${rig.lights.length} lights`);
    // "Done" only with the new environment on screen, never over the previous one's frame.
    const done = await page.evaluate(() => window.uploadSeen.at(-1));
    assert.match(done.shownUrl, new RegExp(`[?&]environment=${rig.id}(&|$)`), JSON.stringify(done));
    // The link names the upload, for whoever opens it.
    assert.match(page.url(), new RegExp(`[?&]environment-name=${name}(&|$)`), page.url());
    assert.equal(await page.locator('#upload-progress').isHidden(), true, 'the progress is gone');
    assert.equal(await viewerAttribute('environment'), rig.id);
    assert.equal(await page.locator('#environment-picker').inputValue(), rig.id);
    assert.equal(await page.locator('#environment-picker option:checked').textContent(), name);
    const handle = await page.waitForFunction(
      (count) => window.oerFrames.slice(count).find((frame) => !frame.preview &&
        frame.url.includes(`environment=${document.querySelector('oer-viewer').environment}`)) ?? false,
      frames, { timeout: 30000 });
    assert.doesNotMatch((await handle.jsonValue()).url, /[?&]lights=/);
    assert.equal(await viewerAttribute('lights'), null);
    const switches = page.locator('#light-switches input[type=checkbox]');
    // The default studio has 3 lights, this one 4: the panel is the new environment's.
    assert.notEqual(rig.lights.length, 3);
    await page.waitForFunction((count) =>
      document.querySelectorAll('#light-switches input[type=checkbox]').length === count,
    rig.lights.length, { timeout: 30000 });
    assert.equal(await switches.count(), rig.lights.length);
  });

  let uploadedMesh;
  await check('a mesh file dropped on the page becomes the product', async () => {
    // A unit cube, 8 vertices and 12 triangles, counter-clockwise seen from outside.
    const cube = ['v 0 0 0', 'v 1 0 0', 'v 1 1 0', 'v 0 1 0', 'v 0 0 1', 'v 1 0 1', 'v 1 1 1', 'v 0 1 1',
                  'f 1 4 3', 'f 1 3 2', 'f 5 6 7', 'f 5 7 8', 'f 1 5 8', 'f 1 8 4',
                  'f 2 3 7', 'f 2 7 6', 'f 4 8 7', 'f 4 7 3', 'f 1 2 6', 'f 1 6 5', ''].join('\n');
    const frames = await page.evaluate(() => window.oerFrames.length);
    await watchUploadStatus();
    // The preparation is followed by its event stream, not polled.
    const preparationRequests = [];
    const onPreparationRequest = (request) => {
      if (request.url().includes('/preparation')) {
        preparationRequests.push(new URL(request.url()).pathname);
      }
    };
    page.on('request', onPreparationRequest);
    const dataTransfer = await page.evaluateHandle((text) => {
      const transfer = new DataTransfer();
      transfer.items.add(new File([text], 'cube.obj'));
      return transfer;
    }, cube);
    await page.dispatchEvent('body', 'dragenter', { dataTransfer });
    assert.equal(await page.locator('#drop-hint').isVisible(), true, 'the drop hint shows');
    await page.dispatchEvent('body', 'drop', { dataTransfer });
    assert.equal(await page.locator('#drop-hint').isVisible(), false, 'the drop hint is gone');
    await uploadEnded();
    const { body: mesh } = await postAsset('/v1/meshes', 'model/obj', Buffer.from(cube));
    uploadedMesh = mesh.id;
    // Refined at load for its per-vertex lighting: 16 segments along every side of
    // every face, 6 x 2 x 16^2 triangles.
    assert.equal(mesh.counts.triangles, 3072);
    assert.equal(await uploadStatus.textContent(), 'cube.obj: 3,072 triangles');
    // The transfer of its first frames, baked from the upload on, showed its progress.
    const texts = await page.evaluate(() => window.uploadTexts);
    console.log(`  upload status: ${texts.join(' | ')}`);
    assert.ok(texts.some((text) => /^Preparing cube\.obj's shadows and reflected light: \d+ %/
      .test(text)), texts.join(' | '));
    page.off('request', onPreparationRequest);
    assert.deepEqual(preparationRequests, [`/v1/meshes/${mesh.id}/preparation/events`]);
    assert.equal(await viewerAttribute('mesh'), mesh.id);
    assert.equal(await page.locator('#mesh-picker option:checked').textContent(), 'cube.obj');
    const done = await page.evaluate(() => window.uploadSeen.at(-1));
    assert.match(done.shownUrl, new RegExp(`[?&]mesh=${mesh.id}(&|$)`), JSON.stringify(done));
    const handle = await page.waitForFunction(
      ([count, id]) => window.oerFrames.slice(count).find((frame) => !frame.preview &&
        frame.url.includes(`mesh=${id}`)) ?? false, [frames, mesh.id], { timeout: 30000 });
    assert.match((await handle.jsonValue()).url, new RegExp(`[?&]environment=${uploadedEnvironment}(&|$)`));
  });

  await check('a product\'s own variants and cameras are offered; each is drawn', async () => {
    // One triangle in two materials' worth of variants (KHR_materials_variants), and a camera.
    const positions = Buffer.from(new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0]).buffer);
    const material = (name, color) => ({
      name, pbrMetallicRoughness: { baseColorFactor: [...color, 1], metallicFactor: 0 },
    });
    const gltf = {
      asset: { version: '2.0' },
      extensionsUsed: ['KHR_materials_variants'],
      extensions: { KHR_materials_variants: { variants: [{ name: 'Ruby' }, { name: 'Sky' }] } },
      buffers: [{ byteLength: 36, uri: `data:application/octet-stream;base64,${positions.toString('base64')}` }],
      bufferViews: [{ buffer: 0, byteLength: 36 }],
      accessors: [{ bufferView: 0, componentType: 5126, count: 3, type: 'VEC3',
                    min: [0, 0, 0], max: [1, 1, 0] }],
      materials: [material('Plain', [0.8, 0.8, 0.8]), material('Ruby', [0.6, 0.02, 0.05]),
                  material('Sky', [0.1, 0.3, 0.8])],
      meshes: [{ primitives: [{ attributes: { POSITION: 0 }, material: 0, extensions: {
        KHR_materials_variants: { mappings: [{ material: 1, variants: [0] },
                                             { material: 2, variants: [1] }] } } }] }],
      cameras: [{ type: 'perspective', name: 'Front', perspective: { yfov: 0.6, znear: 0.01 } }],
      nodes: [{ mesh: 0 }, { camera: 0, translation: [0.3, 0.3, 2] }],
      scenes: [{ nodes: [0, 1] }],
      scene: 0,
    };
    const { status, body: mesh } =
      await postAsset('/v1/meshes', 'model/gltf+json', Buffer.from(JSON.stringify(gltf)));
    assert.equal(status, 201, JSON.stringify(mesh));
    assert.deepEqual(mesh.variants.map((variant) => variant.name), ['Ruby', 'Sky']);
    const previous = await viewerAttribute('mesh');
    const allVariants = page.locator('#all-variants');
    assert.equal(await allVariants.isDisabled(), true, 'the cube has no variants');
    await page.evaluate((id) => document.querySelector('oer-viewer').setAttribute('mesh', id),
                        mesh.id);
    const choices = page.locator('#product-variants input[name=product-variant]');
    await page.waitForFunction(() => !document.getElementById('product-variants').hidden);
    assert.equal(await choices.count(), 3, 'as shipped, Ruby, Sky');
    // The swatch is the variant's base color, in sRGB: 0.6 linear is 0xcb.
    assert.equal(await page.locator('#product-variants .swatch').first()
      .evaluate((swatch) => getComputedStyle(swatch).backgroundColor), 'rgb(203, 39, 63)');
    const frames = await page.evaluate(() => window.oerFrames.length);
    await page.locator('#product-variants input[value="Sky"]').check();
    const sky = await fullFrame(page, frames);
    assert.match(sky.url, /[?&]variant=Sky(&|$)/, sky.url);
    assert.match(page.url(), /[?&]variant=Sky(&|$)/);
    // Its camera, as a view.
    assert.equal(await page.locator('#view-group').isVisible(), true);
    assert.deepEqual(await page.locator('#view-picker option').allTextContents(), ['Orbit', 'Front']);
    const viewed = await page.evaluate(() => window.oerFrames.length);
    await page.locator('#view-picker').selectOption('0');
    const front = await fullFrame(page, viewed);
    assert.match(front.url, /[?&]camera=asset%3A0(&|$)/, front.url);
    assert.doesNotMatch(front.url, /[?&]yaw=/);
    // All variants: this view (its camera) in each variant, a ZIP and each image.
    assert.equal(await allVariants.isEnabled(), true);
    await page.locator('#job-size').selectOption('128');
    const posting = postedJob(page);
    await allVariants.click();
    const { id } = await posting;
    const links = page.locator('#job-results a');
    await links.nth(2).waitFor({ timeout: 30000 });
    assert.equal(await page.locator('#status').textContent(),
                 'All variants ready: 2 variants; save them with the links beside it.');
    const made = await links.evaluateAll((anchors) => Promise.all(anchors.map(async (anchor) => {
      const image = anchor.querySelector('img');
      if (!image) {
        return { text: anchor.textContent, download: anchor.download };
      }
      await image.decode();
      const canvas = document.createElement('canvas');
      canvas.width = image.naturalWidth;
      canvas.height = image.naturalHeight;
      const context = canvas.getContext('2d');
      context.drawImage(image, 0, 0);
      const { data } = context.getImageData(0, 0, canvas.width, canvas.height);
      let redMinusBlue = 0;
      for (let i = 0; i < data.length; i += 4) {
        redMinusBlue += data[i] - data[i + 2];
      }
      return { text: anchor.textContent, download: anchor.download, width: image.naturalWidth,
               redMinusBlue: redMinusBlue / (data.length / 4) };
    })));
    const file = `variants-${id.slice(0, 8)}`;
    assert.deepEqual(made.map(({ text, download, width }) => ({ text, download, width })), [
      { text: 'ZIP (2 images)', download: `${file}.zip`, width: undefined },
      { text: 'Ruby', download: `${file}-01-Ruby.jpg`, width: 128 },
      { text: 'Sky', download: `${file}-02-Sky.jpg`, width: 128 },
    ]);
    const [, rubyImage, skyImage] = made;
    console.log(`  mean red minus blue: Ruby ${rubyImage.redMinusBlue.toFixed(2)}, ` +
                `Sky ${skyImage.redMinusBlue.toFixed(2)}`);
    assert.ok(rubyImage.redMinusBlue > skyImage.redMinusBlue + 5, 'Ruby is redder than Sky');
    const zip = await fetchedInPage(page, await links.first().getAttribute('href'));
    assert.equal(zipEntryCount(zip.bytes), 2);
    await page.locator('#job-size').selectOption('512');
    // Another product: its variant goes, and so do the swatches.
    await page.locator('#mesh-picker').selectOption(previous);
    await page.waitForFunction(() => document.getElementById('product-variants').hidden);
    assert.equal(await page.locator('oer-viewer').getAttribute('variant'), null);
    assert.equal(await allVariants.isDisabled(), true, 'no variants, no images of them');
  });

  await check('the pickers list the presets and the uploads, and choosing one changes the request',
              async () => {
    const presets = await (await fetch(`${server.url}/v1/presets`)).json();
    const optionTexts = (picker) => page.locator(`${picker} option`).allTextContents();
    assert.deepEqual(await optionTexts('#environment-picker'),
                     [...presets.environments.map((preset) => preset.name), 'studio.exr']);
    assert.deepEqual(await optionTexts('#mesh-picker'),
                     [...presets.meshes.map((preset) => preset.name), 'cube.obj']);
    let frames = await page.evaluate(() => window.oerFrames.length);
    await page.locator('#environment-picker').selectOption('default');
    let handle = await page.waitForFunction((count) => window.oerFrames.slice(count).find((frame) =>
      !frame.preview && frame.url.includes('environment=default')) ?? false, frames, { timeout: 30000 });
    assert.match((await handle.jsonValue()).url, new RegExp(`[?&]mesh=${uploadedMesh}(&|$)`));
    assert.match(page.url(), /[?&]environment=default(&|$)/);
    frames = await page.evaluate(() => window.oerFrames.length);
    await page.locator('#mesh-picker').selectOption('default');
    handle = await page.waitForFunction((count) => window.oerFrames.slice(count).find((frame) =>
      !frame.preview && frame.url.includes('mesh=default')) ?? false, frames, { timeout: 30000 });
    assert.match((await handle.jsonValue()).url, /[?&]environment=default(&|$)/);
    // A shared link to an upload this page never saw: the picker names it by the name the link
    // carries, else by its short id.
    const again = await desktop.newPage();
    await again.goto(`${server.url}/?environment=${uploadedEnvironment}&environment-name=studio.exr`);
    assert.equal(await again.locator('#environment-picker').inputValue(), uploadedEnvironment);
    assert.equal(await again.locator('#environment-picker option:checked').textContent(), 'studio.exr');
    await again.goto(`${server.url}/?environment=${uploadedEnvironment}`);
    assert.equal(await again.locator('#environment-picker option:checked').textContent(),
                 uploadedEnvironment.slice(0, 8));
    await again.close();
  });

  await check('an error event carries the server\'s problem+json type and detail verbatim', async () => {
    const missing = '0'.repeat(64);
    const problem = await (await fetch(`${server.url}/v1/render?environment=${missing}&mesh=default`)).json();
    const errors = await page.evaluate(() => window.oerErrors.length);
    await page.evaluate((id) => document.querySelector('oer-viewer').setAttribute('environment', id),
                        missing);
    const handle = await page.waitForFunction(
      (count) => window.oerErrors.slice(count).find((error) => error.url.includes('/v1/render')) ?? false,
      errors, { timeout: 30000 });
    const error = await handle.jsonValue();
    assert.equal(error.status, problem.status);
    assert.equal(error.type, '/v1/problems/unknown-id');
    assert.equal(error.type, problem.type);
    assert.equal(error.detail, problem.detail);
    // In plain words, over the view as well as in the page's status.
    assert.equal(error.code, 'not-found');
    assert.ok(error.message.startsWith('This product or environment is not available. ') &&
              error.message.includes(problem.detail), error.message);
    assert.equal(await page.locator('#status').textContent(), error.message);
    const shown = await overlays(page);
    assert.equal(shown.message, true, 'the message is visible in the view');
    assert.equal(shown.messageText, error.message.replace('. ', ''));
    assert.equal(await page.locator('oer-viewer').getAttribute('failed'), 'not-found');
    // A frame again takes the message away.
    const frames = await page.evaluate(() => window.oerFrames.length);
    await page.evaluate(() => document.querySelector('oer-viewer').setAttribute('environment', 'default'));
    await page.waitForFunction((count) => window.oerFrames.slice(count).some((frame) =>
      frame.url.includes('environment=default')), frames, { timeout: 30000 });
    assert.equal((await overlays(page)).message, false);
    assert.equal(await page.locator('oer-viewer').getAttribute('failed'), null);
  });

  await check('a hotspot behind the product is hidden and one in front is shown, for several orbits',
              async () => {
    await page.goto(`${server.url}/?camera-orbit=0+10`);
    await fullFrame(page);
    const viewer = page.locator('oer-viewer');
    const box = await viewer.boundingBox();
    // Sets the orbit; resolves with the first placement of the hotspots in a frame of that yaw.
    const placedAt = (yaw) => page.evaluate((orbitYaw) => new Promise((resolve) => {
      const element = document.querySelector('oer-viewer');
      const listener = ({ detail }) => {
        if (new URL(detail.url, location.href).searchParams.get('yaw') === String(orbitYaw)) {
          element.removeEventListener('hotspots-change', listener);
          resolve(detail.hotspots);
        }
      };
      element.addEventListener('hotspots-change', listener);
      element.setAttribute('camera-orbit', `${orbitYaw} 10`);
    }), yaw);
    // The page's place mode: a click on the product's front (yaw 0), then on its back (yaw 180).
    await page.locator('#place-hotspot').click();
    const click = async (count) => {
      await page.mouse.click(box.x + box.width / 2, box.y + box.height * 0.4);
      await page.waitForFunction((n) => document.querySelectorAll('oer-viewer > .hotspot').length === n,
                                 count, { timeout: 15000 });
    };
    await click(1);
    await placedAt(180);
    await click(2);
    await page.locator('#place-hotspot').click();
    const [front, back] = await page.evaluate(() =>
      [...document.querySelectorAll('oer-viewer > .hotspot')].map((hotspot) => hotspot.slot));
    // A third, between the two (inside the product, from their positions as the element's
    // pick() names them), its normal the front's: it faces the front's camera, so that only
    // the depth can hide it there.
    await page.evaluate(async () => {
      const element = document.querySelector('oer-viewer');
      const rect = element.getBoundingClientRect();
      const at = (yaw) => {
        element.setAttribute('camera-orbit', `${yaw} 10`);
        return element.pick(rect.left + rect.width / 2, rect.top + rect.height * 0.4);
      };
      const [a, b] = [await at(0), await at(180)];
      const inside = document.createElement('span');
      inside.slot = 'hotspot-inside';
      inside.className = 'hotspot-inside';
      inside.dataset.position = a.position.map((value, axis) => (value + b.position[axis]) / 2).join(' ');
      inside.dataset.normal = a.normal.join(' ');
      element.append(inside);
    });
    const slots = { [front]: 'front', [back]: 'back', 'hotspot-inside': 'inside' };
    for (const [yaw, shown] of [[0, 'front'], [25, 'front'], [-30, 'front'], [180, 'back'],
                                [150, 'back'], [-160, 'back']]) {
      const placed = await placedAt(yaw);
      const states = await page.evaluate(() => Object.fromEntries(
        [...document.querySelectorAll('oer-viewer > [slot^="hotspot-"]')].map((hotspot) => {
          const rect = hotspot.getBoundingClientRect();
          return [hotspot.slot, { visible: hotspot.hasAttribute('data-visible'),
                                  shown: rect.width > 0 && rect.height > 0,
                                  x: rect.x + rect.width / 2, y: rect.y + rect.height / 2 }];
        })));
      for (const [slot, name] of Object.entries(slots)) {
        const expected = name === shown;
        assert.equal(states[slot].visible, expected, `yaw ${yaw}: ${name} data-visible`);
        assert.equal(states[slot].shown, expected, `yaw ${yaw}: ${name} shown`);
        if (expected) {
          assert.ok(states[slot].x > box.x && states[slot].x < box.x + box.width &&
                    states[slot].y > box.y && states[slot].y < box.y + box.height,
                    `yaw ${yaw}: ${name} inside the view at ${states[slot].x}, ${states[slot].y}`);
        }
      }
      const inside = placed.find((hotspot) => hotspot.name === 'inside');
      if (yaw === 0) {
        assert.ok(inside.facing && inside.in_frame && !inside.visible,
                  `the inside point faces the camera and only the product hides it: ${JSON.stringify(inside)}`);
        const [x, y] = [states[front].x - box.x, states[front].y - box.y];
        assert.ok(Math.abs(x - box.width / 2) < 2 && Math.abs(y - box.height * 0.4) < 2,
                  `the front hotspot stays where it was placed: ${x}, ${y}`);
      }
    }
    await page.locator('#clear-hotspots').click();
    await page.evaluate(() => document.querySelector('.hotspot-inside').remove());
    assert.equal(await page.locator('oer-viewer > [slot^="hotspot-"]').count(), 0);
  });

  await check('desktop screenshot (1280x800)', async () => {
    await page.goto(`${server.url}/`);
    await fullFrame(page);
    // The lights come from their own request, which may end after a cached frame's.
    await page.locator('#light-switches input').first().waitFor();
    await page.screenshot({ path: join(artifacts, 'desktop-1280x800.png') });
  });

  await check('axe-core finds no violation of moderate or higher impact on the page', async () => {
    const found = await axeViolations(page);
    console.log(`  axe-core ${JSON.parse(readFileSync(join(here, 'node_modules', 'axe-core', 'package.json'), 'utf8')).version}: ` +
                `${found.passes} rules pass; minor: ${found.minor.join(', ') || 'none'}`);
    assert.deepEqual(found.serious, []);
    // The landmarks and the heading, and touch targets of 24x24 CSS px (WCAG 2.2, 2.5.8).
    assert.equal(await page.locator('main h1').count(), 1);
    const small = await page.evaluate(() => [...document.querySelectorAll(
      '#controls input[type=checkbox], #controls input[type=radio], #controls button, #controls select')]
      .filter((element) => element.checkVisibility())
      .map((element) => ({ name: element.id || element.value, box: element.getBoundingClientRect() }))
      .filter(({ box }) => box.width < 24 || box.height < 24)
      .map(({ name, box }) => `${name} ${box.width}x${box.height}`));
    assert.deepEqual(small, []);
  });

  await check('the lights panel fills when the lights come before the page\'s script', async () => {
    // index.js held back until the element (defined first) has its lights: the page must show
    // those, not wait for a lights-change that has already gone.
    const context = await browser.newContext({ viewport: { width: 800, height: 600 } });
    const late = await context.newPage();
    await context.route('**/web/index.js', async (route) => {
      await late.waitForFunction(() => document.querySelector('oer-viewer').lights?.length > 0,
                                 null, { timeout: 30000 });
      await route.continue();
    });
    await late.goto(`${server.url}/`);
    const rig = await (await fetch(`${server.url}/v1/environments/default`)).json();
    await late.waitForFunction((count) =>
      document.querySelectorAll('#light-switches input[type=checkbox]').length === count,
    rig.lights.length, { timeout: 30000 });
    await context.close();
  });

  await check('at phone width (360x740, touch) the page fits, shows a frame, and a pinch zooms', async () => {
    const phone = await browser.newContext({
      viewport: { width: 360, height: 740 }, deviceScaleFactor: 2, isMobile: true, hasTouch: true,
    });
    await phone.addInitScript(RECORD_EVENTS);
    const small = await phone.newPage();
    await small.goto(`${server.url}/`);
    await fullFrame(small);
    assertRealFrame(await shownImage(small), 'phone frame');
    await small.locator('#light-switches input').first().waitFor();
    const overflow = await small.evaluate(() => document.documentElement.scrollWidth - innerWidth);
    assert.ok(overflow <= 0, `the page is ${overflow} px wider than the phone`);
    await small.screenshot({ path: join(artifacts, 'phone-360x740.png') });

    // Two fingers spread from 80 to 160 px apart: the eye comes to half the automatic framing's
    // distance (named by the frame's X-Oer-Camera), and lifting them gives a full frame.
    const shownUrl = await small.evaluate(() => window.oerFrames.at(-1).url);
    const camera = (await fetch(new URL(shownUrl, server.url))).headers.get('X-Oer-Camera');
    const vector = (name) => new RegExp(`${name}=([^;]+)`).exec(camera)[1].split(',').map(Number);
    const framed = Math.hypot(...vector('eye').map((value, axis) => value - vector('target')[axis]));
    const box = await small.locator('oer-viewer').boundingBox();
    const [cx, cy] = [box.x + box.width / 2, box.y + box.height / 2];
    const touch = await phone.newCDPSession(small);
    const fingers = (half) => [{ x: cx - half, y: cy, id: 1 }, { x: cx + half, y: cy, id: 2 }];
    const frames = await small.evaluate(() => window.oerFrames.length);
    await touch.send('Input.dispatchTouchEvent', { type: 'touchStart', touchPoints: fingers(40) });
    for (let half = 45; half <= 80; half += 5) {
      await touch.send('Input.dispatchTouchEvent', { type: 'touchMove', touchPoints: fingers(half) });
      await small.waitForTimeout(30);
    }
    await touch.send('Input.dispatchTouchEvent', { type: 'touchEnd', touchPoints: [] });
    const pinched = await fullFrame(small, frames);
    const orbit = await small.evaluate(() => document.querySelector('oer-viewer').orbit);
    console.log(`  pinch: distance ${framed.toFixed(3)} -> ${orbit.distance}`);
    assert.ok(Math.abs(orbit.distance - framed / 2) < 0.01 * framed,
              `pinched to ${orbit.distance}, expected half of ${framed}`);
    assert.match(pinched.url, new RegExp(`[?&]distance=${orbit.distance}(&|$)`));
    await phone.close();
  });

  await check('a page on another origin embeds the element (CORS)', async () => {
    const context = await browser.newContext({ viewport: { width: 800, height: 600 } });
    await context.addInitScript(RECORD_EVENTS);
    const embedding = await context.newPage();
    await embedding.goto(`${shopUrl}/`);
    const frame = await fullFrame(embedding);
    assert.ok(frame.url.startsWith(server.url), frame.url);
    assert.match(frame.etag ?? '', /^"[0-9a-f]{64}"$/, 'ETag exposed to the other origin');
    // Access-Control-Expose-Headers (server/src/cors.cpp) lets the shop's page read these too.
    assert.match(frame.cache ?? '', /^(hit|miss)$/, 'X-Oer-Cache exposed to the other origin');
    if (frame.cache === 'miss') {
      assert.match(frame.serverTiming ?? '', /encode;dur=/, 'Server-Timing exposed to the other origin');
    }
    assertRealFrame(await shownImage(embedding), 'embedded frame');
    const found = await axeViolations(embedding);
    assert.deepEqual(found.serious, [], 'axe-core on the shop\'s page');
    await context.close();
  });

  await check('a viewer without a CSS size gets a 4:3 box, and its poster attribute until the frame',
              async () => {
    const context = await browser.newContext({ viewport: { width: 800, height: 600 } });
    await context.addInitScript(RECORD_EVENTS);
    await context.addInitScript(RECORD_FEEDBACK);
    const bare = await context.newPage();
    const posters = [];
    await bare.route('**/v1/render?**', async (route) => {
      if (route.request().url().includes('quality=')) {
        posters.push(route.request().url());
      } else {
        await new Promise((resolve) => setTimeout(resolve, 600));
      }
      await route.continue().catch(() => {});
    });
    await bare.goto(`${shopUrl}/bare.html`);
    await bare.waitForFunction(() => window.oerFeedback.posterAt !== null, null, { timeout: 10000 });
    const before = await overlays(bare);
    const frame = await fullFrame(bare);
    const { feedback } = await bare.evaluate(() => ({ feedback: window.oerFeedback }));
    const box = await bare.locator('oer-viewer').boundingBox();
    assert.deepEqual({ width: box.width, height: box.height }, { width: 560, height: 420 },
                     'the container\'s width at 4:3');
    assert.deepEqual({ width: frame.width, height: frame.height }, { width: 560, height: 420 });
    assert.equal(feedback.posterSrc, `${server.url}/v1/environments/default/preview.jpg`);
    assert.deepEqual(posters, [], 'no poster frame asked for when the page gives one');
    assert.deepEqual({ indicator: before.indicator, poster: before.poster }, { indicator: true, poster: true });
    assert.equal((await overlays(bare)).placeholder, false);
    await context.close();
  });

  // The element's failure: its error event (code and message) and the message over the view,
  // on a shop's page whose viewer never gets a frame.
  const failureOn = async (url) => {
    const context = await browser.newContext({ viewport: { width: 800, height: 600 } });
    await context.addInitScript(RECORD_EVENTS);
    const failing = await context.newPage();
    await failing.goto(url);
    const error = await (await failing.waitForFunction(
      () => window.oerErrors.find((reported) => reported.url.includes('/v1/render')) ?? false,
      null, { timeout: 15000 })).jsonValue();
    await failing.waitForFunction(() => document.querySelector('oer-viewer').hasAttribute('failed'));
    const shown = await overlays(failing);
    const box = await failing.locator('oer-viewer').boundingBox();
    const busy = await failing.locator('oer-viewer').getAttribute('aria-busy');
    await context.close();
    return { error, shown, box, busy };
  };

  await check('an unreachable server gives an error event and a plain message in the view', async () => {
    const { error, shown, box, busy } = await failureOn(`${shopUrl}/unreachable.html`);
    console.log(`  unreachable: "${error.message}"`);
    assert.equal(error.code, 'unreachable');
    assert.equal(error.status, 0);
    assert.match(error.message, /^The 3D view cannot load\. Its server \(127\.0\.0\.1:\d+\) does not answer/);
    assert.equal(shown.message, true);
    assert.equal(shown.messageText, error.message.replace('. ', ''));
    assert.equal(shown.indicator, false, 'no loading indicator once it failed');
    assert.equal(busy, null);
    assert.deepEqual({ width: box.width, height: box.height }, { width: 560, height: 420 });
  });

  await check('a page the server does not allow (CORS) gives an error event and a plain message',
              async () => {
    // http://localhost:port is another origin than the allowed http://127.0.0.1:port.
    const origin = `http://localhost:${shop.address().port}`;
    const { error, shown, box } = await failureOn(`${origin}/bare.html`);
    console.log(`  CORS refusal: "${error.message}"`);
    assert.equal(error.code, 'cors');
    assert.ok(error.message.includes(`does not allow pages of ${origin}`), error.message);
    assert.equal(shown.message, true);
    assert.equal(shown.messageText, error.message.replace('. ', ''));
    assert.deepEqual({ width: box.width, height: box.height }, { width: 560, height: 420 },
                     'the element is there, not absent');
  });

  console.log(`browser test: ${passed} checks passed in ${((Date.now() - started) / 1000).toFixed(1)} s; ` +
              `screenshots in ${artifacts}`);
} finally {
  await browser?.close();
  shop?.close();
  await server?.stop();
}

// The browser benchmark of the web client's speed targets (bench/README.md, web/README.md):
// the page at / in Debian's chromium against the real oer-server, the Stanford bunny under a Blender world,
// the viewer 800x600 CSS pixels at deviceScaleFactor 1. It prints figures, it asserts nothing:
//   node web/tests/browser_benchmark.mjs [--build build] [--world forest] [--repeat 5] [--seconds 3]
//                                        [--viewer changed/oer-viewer.js]
// (from the repository's root; --build: the build folder holding bin/oer-server; --world: a
// Blender world's name; --seconds: each gesture's length; --viewer: an oer-viewer.js served in
// place of the embedded one, to measure a change to the element without rebuilding).
// Per repetition, in a fresh browser context (no HTTP cache): (1) the first frame after page
// load, (2) previews per second during a ~60 Hz scripted drag, (3) the sharp frame after the
// pointer is released, (4) previews per second while adjust('environment-yaw', v) turns the
// environment at ~60 Hz. The server runs with no frame cache (--frame-cache-bytes 0), so that
// every repetition renders its frames; each repetition starts with one warm-up frame (the
// renderer's shadow-map cache stays on: a warm server's).
import { execFileSync } from 'node:child_process';
import { existsSync, readFileSync } from 'node:fs';
import { availableParallelism, loadavg } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

// playwright-core from package-lock.json, installed when missing as the browser test's runner
// does (run_browser_test.cmake), before the harness that needs it is loaded.
const here = dirname(fileURLToPath(import.meta.url));
if (!existsSync(join(here, 'node_modules', 'playwright-core'))) {
  console.error(`browser_benchmark.mjs: npm ci in ${here}`);
  execFileSync('npm', ['ci', '--no-audit', '--no-fund'], { cwd: here, stdio: 'inherit' });
}
const { RECORD_EVENTS, launchChromium, option, startServer } =
  await import('./harness.mjs');

const build = resolve(option('--build', 'build'));
const worldName = option('--world', 'forest');
const repetitions = Number(option('--repeat', '5'));
const gestureSeconds = Number(option('--seconds', '3'));
// A changed oer-viewer.js served in place of the embedded one, to measure a change to the
// element's scheduling or preview recipe before rebuilding the server.
const viewerPath = option('--viewer', '');
const GESTURE_HZ = 60;
const BUNNY = '/usr/share/glmark2/models/bunny.obj';
const WORLD = `/usr/share/blender/datafiles/studiolights/world/${worldName}.exr`;
const VIEWER = { width: 800, height: 600 };
// The web client's targets (docs/design.md section 8).
const TARGETS = {
  firstFrameMs: 1000,      // first frame after page load, server warm: at most
  dragPreviewsPerS: 20,    // previews shown per second while dragging: at least
  sharpFrameMs: 300,       // full frame shown after the pointer is released: at most
  turnPreviewsPerS: 10,    // previews shown per second while the environment turns: at least
};
// The passes of the server's Server-Timing (renderer/gl/src/frame_renderer.cpp; `total` is
// the render, `encode` the JPEG after it).
const PASSES = ['setup', 'shadow_pass', 'geometry_pass', 'shading_pass', 'readback', 'total',
                'encode'];

for (const [path, what] of [[join(build, 'bin', 'oer-server'), 'the server (build it first)'],
                            [BUNNY, 'the bunny (glmark2-data)'], [WORLD, `the world ${worldName}`],
                            ...(viewerPath ? [[viewerPath, 'the --viewer file']] : [])]) {
  if (!existsSync(path)) {
    throw new Error(`browser_benchmark.mjs: ${what} is missing at ${path}; ` +
                    'run scripts/setup-debian.sh --with-test-data and build oer-server');
  }
}
if (!(Number.isInteger(repetitions) && repetitions >= 1)) {
  throw new Error(`browser_benchmark.mjs: --repeat must be a whole number >= 1, not ${repetitions}`);
}

const median = (values) => {
  if (values.length === 0) {
    return NaN;
  }
  const sorted = [...values].sort((a, b) => a - b);
  const middle = sorted.length >> 1;
  return sorted.length % 2 ? sorted[middle] : (sorted[middle - 1] + sorted[middle]) / 2;
};
const fixed = (value, digits = 1) => (Number.isFinite(value) ? value.toFixed(digits) : '-');

// "total;dur=12.30, encode;dur=1.20" -> { total: 12.3, encode: 1.2 }
function serverPasses(header) {
  const passes = {};
  for (const entry of (header ?? '').split(',')) {
    const match = /^\s*([\w-]+)\s*;\s*dur=([\d.]+)/.exec(entry);
    if (match) {
      passes[match[1]] = Number(match[2]);
    }
  }
  return passes;
}

async function upload(url, path, type) {
  const started = performance.now();
  const response = await fetch(url, { method: 'POST', headers: { 'Content-Type': type },
                                      body: readFileSync(path) });
  const body = await response.json();
  if (!response.ok) {
    throw new Error(`POST ${url} of ${path}: ${response.status} ${body.detail ?? ''}`);
  }
  return { id: body.id, body, milliseconds: performance.now() - started };
}

// In the page, before its scripts: the viewer held at 800x600 CSS pixels whatever the control
// strip below it takes (the page lets it fill the window above the strip, whose height changes
// once the lights panel appears), set as the element is parsed so that its first frame is
// already of that size; the times of the pointer's moves while pressed and of its release;
// room for every frame's resource timing.
const BENCHMARK_PAGE = ({ width, height }) => {
  performance.setResourceTimingBufferSize(100000);
  new MutationObserver((_, observer) => {
    const viewer = document.querySelector('oer-viewer');
    if (viewer) {
      viewer.style.cssText += `;flex: none; width: ${width}px; height: ${height}px`;
      observer.disconnect();
    }
  }).observe(document, { childList: true, subtree: true });
  window.oerPointer = { moves: [], up: null };
  document.addEventListener('pointermove', (event) => {
    if (event.buttons & 1) {
      window.oerPointer.moves.push(performance.now());
    }
  }, true);
  document.addEventListener('pointerup', () => { window.oerPointer.up = performance.now(); }, true);
};

// Every frame shown so far, with the fetch's part of its time from the Resource Timing API
// (request start to last byte: server, queue and network) beside the element's `milliseconds`
// (request start to decoded image).
function framesWithFetchTimes(page) {
  return page.evaluate(() => window.oerFrames.map((frame) => {
    const name = new URL(frame.url, location.href).href;
    const entry = performance.getEntriesByName(name).findLast((timing) => timing.responseEnd > 0);
    return { ...frame, fetchMs: entry ? entry.responseEnd - entry.startTime : null };
  }));
}

// Waits for the viewer's full frame of its final size (the first, as its style holds it).
async function settledFrame(page) {
  await page.waitForFunction(({ width, height }) => {
    const frame = window.oerFrames.at(-1);
    return frame && !frame.preview && frame.width === width && frame.height === height;
  }, VIEWER, { timeout: 30000 });
}

async function oneRepetition(browser, pageUrl, serverCpuMs) {
  const context = await browser.newContext({ viewport: { width: VIEWER.width, height: 900 },
                                             deviceScaleFactor: 1 });
  await context.addInitScript(RECORD_EVENTS);
  await context.addInitScript(BENCHMARK_PAGE, VIEWER);
  context.on('weberror', (error) => console.error(`browser error: ${error.error()}`));
  if (viewerPath) {
    await context.route('**/web/oer-viewer.js', (route) => route.fulfill({
      contentType: 'text/javascript; charset=utf-8', body: readFileSync(viewerPath, 'utf8'),
    }));
  }
  const page = await context.newPage();
  try {
    const cpu = [serverCpuMs()];
    await page.goto(pageUrl);
    await settledFrame(page);
    cpu.push(serverCpuMs());
    const box = await page.locator('oer-viewer').boundingBox();
    if (Math.round(box.width) !== VIEWER.width || Math.round(box.height) !== VIEWER.height) {
      throw new Error(`the viewer is ${box.width}x${box.height}, not ${VIEWER.width}x${VIEWER.height}`);
    }

    // (2) and (3): a drag across the view at ~60 Hz, then the release.
    const beforeDrag = await page.evaluate(() => window.oerFrames.length);
    const steps = Math.round(gestureSeconds * GESTURE_HZ);
    const [left, right] = [box.x + 100, box.x + box.width - 100];
    const y = box.y + box.height / 2;
    await page.mouse.move(left, y);
    cpu.push(serverCpuMs());
    await page.mouse.down();
    const dragStart = performance.now();
    for (let step = 1; step <= steps; step += 1) {
      await page.mouse.move(left + (right - left) * step / steps, y + 20 * Math.sin(step / 15));
      const wait = dragStart + step * 1000 / GESTURE_HZ - performance.now();
      if (wait > 0) {
        await new Promise((done) => setTimeout(done, wait));
      }
    }
    cpu.push(serverCpuMs());
    await page.mouse.up();
    await page.waitForFunction((count) => window.oerPointer.up !== null &&
      window.oerFrames.slice(count).some((frame) => !frame.preview &&
                                                    frame.shownAt > window.oerPointer.up),
    beforeDrag, { timeout: 30000 });
    cpu.push(serverCpuMs());
    const pointer = await page.evaluate(() => window.oerPointer);

    // (4): the environment turned by adjust() at ~60 Hz, one degree a step (the page's rotation
    // slider), then left to rest.
    const beforeTurn = await page.evaluate(() => window.oerFrames.length);
    cpu.push(serverCpuMs());
    const turn = await page.evaluate(({ seconds, hz }) => new Promise((done) => {
      const viewer = document.querySelector('oer-viewer');
      const start = performance.now();
      let step = 0;
      const timer = setInterval(() => {
        step += 1;
        viewer.adjust('environment-yaw', ((step + 180) % 360) - 180);
        if (performance.now() - start >= seconds * 1000) {
          clearInterval(timer);
          done({ start, end: performance.now(), steps: step });
        }
      }, 1000 / hz);
    }), { seconds: gestureSeconds, hz: GESTURE_HZ });
    cpu.push(serverCpuMs());
    await page.waitForFunction(({ count, end }) => window.oerFrames.slice(count).some(
      (frame) => !frame.preview && frame.shownAt > end), { count: beforeTurn, end: turn.end },
    { timeout: 60000 });
    cpu.push(serverCpuMs());

    const frames = await framesWithFetchTimes(page);
    const firstMove = pointer.moves[0];
    const lastMove = pointer.moves.at(-1);
    const during = (from, to) => (frame) => frame.stage === 'preview' && frame.shownAt > from &&
                                            frame.shownAt <= to;
    const dragPreviews = frames.slice(beforeDrag).filter(during(firstMove, lastMove));
    const turnPreviews = frames.slice(beforeTurn).filter(during(turn.start, turn.end));
    // The element's rest: the sharp frame (full size, one sample), then the full-quality one.
    const sharp = frames.slice(beforeDrag).find((frame) => frame.stage === 'sharp' &&
                                                            frame.shownAt > pointer.up);
    const full = frames.slice(beforeDrag).find((frame) => frame.stage === 'full' &&
                                                           frame.shownAt > pointer.up);
    const turnRest = frames.slice(beforeTurn).find((frame) => !frame.preview &&
                                                               frame.shownAt > turn.end);
    // The server's CPU time in each case, per frame shown (aborted renders included).
    const [loadStart, loaded, dragStarted, dragEnded, sharpShown, turnStarted, turnEnded,
           turnRested] = cpu;
    return {
      first: { value: frames[0].shownAt, frames: [frames[0]], cpuMs: loaded - loadStart },
      drag: { value: dragPreviews.length / ((lastMove - firstMove) / 1000), frames: dragPreviews,
              cpuMs: (dragEnded - dragStarted) / dragPreviews.length,
              moves: pointer.moves.length },
      sharp: { value: sharp.shownAt - pointer.up, frames: [sharp], cpuMs: sharpShown - dragEnded },
      full: { value: full.shownAt - pointer.up, frames: [full], cpuMs: sharpShown - dragEnded },
      turn: { value: turnPreviews.length / ((turn.end - turn.start) / 1000), frames: turnPreviews,
              cpuMs: (turnEnded - turnStarted) / turnPreviews.length,
              steps: turn.steps },
      turnRest: { value: turnRest.shownAt - turn.end, frames: [turnRest],
                  cpuMs: turnRested - turnEnded },
    };
  } catch (error) {
    const state = await page.evaluate(() => JSON.stringify({ frames: window.oerFrames,
                                                            errors: window.oerErrors }))
      .catch(() => 'unavailable');
    throw new Error(`${error.message}\nthe page's frames and errors: ${state}`);
  } finally {
    await context.close();
  }
}

// The p50 of each server pass, of the server's time (total + encode), of the rest of the
// element's `milliseconds` (client), split into the fetch beyond the server's time (HTTP:
// queue, network, headers and body) and after the fetch (blob, decode, show).
function breakdown(frames) {
  const row = {};
  for (const pass of PASSES) {
    row[pass] = median(frames.map((frame) => serverPasses(frame.serverTiming)[pass])
      .filter((value) => value !== undefined));
  }
  const server = (frame) => {
    const passes = serverPasses(frame.serverTiming);
    return (passes.total ?? NaN) + (passes.encode ?? NaN);
  };
  row.client = median(frames.map((frame) => frame.milliseconds - server(frame))
    .filter(Number.isFinite));
  row.http = median(frames.filter((frame) => frame.fetchMs !== null)
    .map((frame) => frame.fetchMs - server(frame)).filter(Number.isFinite));
  row.decode = median(frames.filter((frame) => frame.fetchMs !== null)
    .map((frame) => frame.milliseconds - frame.fetchMs));
  row.frameMs = median(frames.map((frame) => frame.milliseconds));
  row.kib = median(frames.map((frame) => frame.bytes / 1024));
  row.size = frames.length ? `${frames[0].width}x${frames[0].height}` : '-';
  row.count = frames.length;
  return row;
}

// Idle time between previews: from one shown to the next one's request, which starts
// `milliseconds` before it is shown.
function previewGaps(frames) {
  const gaps = [];
  for (let i = 1; i < frames.length; i += 1) {
    gaps.push(frames[i].shownAt - frames[i].milliseconds - frames[i - 1].shownAt);
  }
  return gaps;
}

// The page's own first frame, rendered once before the page asks for it: the meshes and maps
// uploaded to GL, the shadow maps of the unturned environment's lights cached (the previous
// repetition's turn evicts them from the renderer's cache). Returns its Server-Timing.
async function warmServer(url, frameQuery) {
  const response = await fetch(`${url}/v1/render?${frameQuery}&width=${VIEWER.width}` +
                               `&height=${VIEWER.height}`);
  await response.arrayBuffer();
  if (!response.ok) {
    throw new Error(`the warm-up frame failed: ${response.status}`);
  }
  return response.headers.get('Server-Timing');
}

const server = await startServer(join(build, 'bin', 'oer-server'), ['--frame-cache-bytes', '0']);
// The server's CPU time so far (all its threads, /proc/PID/stat utime + stime, proc(5)): other
// processes' load stretches wall times, much less the CPU time a frame takes.
const ticksPerSecond = Number(execFileSync('getconf', ['CLK_TCK'], { encoding: 'utf8' }));
const serverCpuMs = () => {
  const fields = readFileSync(`/proc/${server.child.pid}/stat`, 'utf8').split(') ')[1].split(' ');
  return (Number(fields[11]) + Number(fields[12])) * 1000 / ticksPerSecond;
};
let browser = null;
try {
  const info = await (await fetch(`${server.url}/v1/info`)).json();
  const load = loadavg();
  console.log(`browser benchmark: ${availableParallelism()} CPUs (load average ${load.map((value) =>
    value.toFixed(2)).join(' ')}), renderer "${info.renderer.renderer}" (${info.renderer.version}), ` +
              `oer ${info.version}`);
  const mesh = await upload(`${server.url}/v1/meshes`, BUNNY, 'model/obj');
  const environment = await upload(`${server.url}/v1/environments`, WORLD, 'image/x-exr');
  console.log(`bunny uploaded in ${fixed(mesh.milliseconds, 0)} ms; ${worldName}.exr ` +
              `(${environment.body.source.width}x${environment.body.source.height}, ` +
              `${environment.body.lights.length} lights) preprocessed in ` +
              `${fixed(environment.milliseconds, 0)} ms`);
  const frameQuery = `environment=${environment.id}&mesh=${mesh.id}`;
  const warmUp = await warmServer(server.url, frameQuery);
  console.log(`warm-up frame ${VIEWER.width}x${VIEWER.height}: Server-Timing "${warmUp}"`);

  browser = await launchChromium();
  const pageUrl = `${server.url}/?mesh=${mesh.id}&environment=${environment.id}`;
  console.log(`${repetitions} repetitions of ${pageUrl}, viewer ${VIEWER.width}x${VIEWER.height} ` +
              `CSS px (its style; viewport ${VIEWER.width}x900), deviceScaleFactor 1, gestures ` +
              `${gestureSeconds} s at ${GESTURE_HZ} Hz, server frame cache off` +
              `${viewerPath ? `, oer-viewer.js from ${viewerPath}` : ''}\n`);
  const runs = [];
  for (let repetition = 1; repetition <= repetitions; repetition += 1) {
    if (repetition > 1) {
      await warmServer(server.url, frameQuery);
    }
    const run = await oneRepetition(browser, pageUrl, serverCpuMs);
    runs.push(run);
    console.log(`  run ${repetition}: first frame ${fixed(run.first.value, 0)} ms, drag ` +
                `${fixed(run.drag.value)} previews/s (${run.drag.frames.length} in ${run.drag.moves} ` +
                `moves), sharp ${fixed(run.sharp.value, 0)} ms, full ${fixed(run.full.value, 0)} ms, turn ${fixed(run.turn.value)} ` +
                `previews/s (${run.turn.frames.length} in ${run.turn.steps} steps), full frame ` +
                `${fixed(run.turnRest.value, 0)} ms after the turn`);
  }

  const cases = [
    ['first frame after page load', 'first', 'ms', `<= ${TARGETS.firstFrameMs} ms`,
     (value) => value <= TARGETS.firstFrameMs],
    ['previews while dragging', 'drag', '/s', `>= ${TARGETS.dragPreviewsPerS} /s`,
     (value) => value >= TARGETS.dragPreviewsPerS],
    ['sharp frame after release', 'sharp', 'ms', `<= ${TARGETS.sharpFrameMs} ms`,
     (value) => value <= TARGETS.sharpFrameMs],
    ['full-quality frame after release', 'full', 'ms', '(none)', null],
    ['previews while the env. turns', 'turn', '/s', `>= ${TARGETS.turnPreviewsPerS} /s`,
     (value) => value >= TARGETS.turnPreviewsPerS],
    ['full frame after the turn rests', 'turnRest', 'ms', '(none)', null],
  ];
  console.log(`\ntargets (median and range of ${repetitions} runs):`);
  console.log(`${'case'.padEnd(34)}${'median'.padStart(10)}  ${'range'.padEnd(16)}` +
              `${'target'.padEnd(13)}result`);
  for (const [name, key, unit, target, met] of cases) {
    const values = runs.map((run) => run[key].value);
    const value = median(values);
    const range = `${fixed(Math.min(...values))}..${fixed(Math.max(...values))}`;
    console.log(`${name.padEnd(34)}${`${fixed(value)} ${unit}`.padStart(10)}  ${range.padEnd(16)}` +
                `${target.padEnd(13)}${met ? (met(value) ? 'met' : 'NOT met') : ''}`);
  }

  console.log('\nwhere the time goes: p50 ms per frame (server passes from Server-Timing; client = ' +
              'the element\'s milliseconds - (total + encode), = http (fetch beyond the server) + ' +
              'decode (blob, decode, show); frame = the element\'s milliseconds; cpu = the server\'s ' +
              `CPU ms per frame shown, whose half bounds its wall time on ${availableParallelism()} ` +
              'idle CPUs from below):');
  const columns = ['setup', 'shadow', 'geometry', 'shading', 'readback', 'total', 'encode',
                   'client', 'http', 'decode', 'frame', 'KiB', 'cpu'];
  console.log(`${'case'.padEnd(34)}${'frames'.padStart(7)} ${'size'.padStart(8)}` +
              columns.map((column) => column.padStart(9)).join(''));
  for (const [name, key] of cases) {
    const row = breakdown(runs.flatMap((run) => run[key].frames));
    const values = [row.setup, row.shadow_pass, row.geometry_pass, row.shading_pass, row.readback,
                    row.total, row.encode, row.client, row.http, row.decode, row.frameMs, row.kib,
                    median(runs.map((run) => run[key].cpuMs))];
    console.log(`${name.padEnd(34)}${String(row.count).padStart(7)} ${row.size.padStart(8)}` +
                values.map((value) => fixed(value).padStart(9)).join(''));
  }
  const firstFrames = runs.map((run) => run.first.frames[0]);
  console.log(`first frame after page load: p50 ${fixed(median(firstFrames.map((frame) =>
    frame.shownAt - frame.milliseconds)))} ms from navigation to the element's request (the ` +
              'page, its scripts, layout), then the request to the image shown');
  for (const [name, key] of [['previews while dragging', 'drag'],
                             ['previews while the env. turns', 'turn']]) {
    const gaps = runs.flatMap((run) => previewGaps(run[key].frames));
    const intervals = runs.flatMap((run) => run[key].frames.slice(1).map(
      (frame, i) => frame.shownAt - run[key].frames[i].shownAt));
    console.log(`${name}: p50 ${fixed(median(intervals))} ms from one preview shown to the next, ` +
                `of which ${fixed(median(gaps))} ms idle (shown to the next request: the ` +
                'element\'s one-at-a-time scheduling)');
  }
  console.log(`load average at the end: ${loadavg().map((value) => value.toFixed(2)).join(' ')} ` +
              `(${availableParallelism()} CPUs; other processes' load stretches every figure)`);
} finally {
  await browser?.close();
  await server.stop();
}

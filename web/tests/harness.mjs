// What the browser test (browser_test.mjs) and the browser benchmark (browser_benchmark.mjs)
// share: the real oer-server on a free loopback port with a temporary data folder, Debian's
// chromium driven by playwright-core (no browser download), and the record of every frame the
// page's <oer-viewer> shows.
import { spawn } from 'node:child_process';
import { once } from 'node:events';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { basename, join } from 'node:path';
import { chromium } from 'playwright-core';

const CHROMIUM = '/usr/bin/chromium';
const CHROMIUM_ARGS = [
  '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
];

// The value after `name` on the command line; `fallback` when absent, an error when there is
// none.
export function option(name, fallback) {
  const index = process.argv.indexOf(name);
  if (index >= 0 && index + 1 < process.argv.length) {
    return process.argv[index + 1];
  }
  if (fallback === undefined) {
    throw new Error(`${basename(process.argv[1])}: ${name} is required`);
  }
  return fallback;
}

export function launchChromium() {
  return chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_ARGS });
}

// oer-server on a free port (--port 0) with a temporary data folder, its URL read from its
// banner, once /readyz answers. stop() ends it and removes the folder.
export async function startServer(serverPath, extraArgs = []) {
  const dataDir = mkdtempSync(join(tmpdir(), 'oer-browser-'));
  const child = spawn(serverPath, ['--host', '127.0.0.1', '--port', '0', '--data-dir', dataDir,
                                   ...extraArgs],
                      { stdio: ['ignore', 'pipe', 'pipe'] });
  const exited = once(child, 'exit');
  const stop = async () => {
    if (child.exitCode === null && child.signalCode === null) {
      child.kill('SIGTERM');
      await exited;
    }
    rmSync(dataDir, { recursive: true, force: true });
  };
  let output = '';
  child.stderr.on('data', (chunk) => { output += chunk; });
  try {
    const url = await new Promise((resolve, reject) => {
      child.stdout.on('data', (chunk) => {
        output += chunk;
        const match = /listening on (http:\/\/[\d.]+:\d+)/.exec(output);
        if (match) {
          resolve(match[1]);
        }
      });
      child.on('exit', (code) => reject(new Error(`oer-server exited (${code}):\n${output}`)));
    });
    for (let attempt = 0; attempt < 600; attempt += 1) {
      const response = await fetch(`${url}/readyz`).catch(() => null);
      if (response?.ok) {
        return { child, url, stop };
      }
      await new Promise((resolve) => setTimeout(resolve, 100));
    }
    throw new Error(`oer-server at ${url} never became ready:\n${output}`);
  } catch (error) {
    await stop();
    throw error;
  }
}

// Every 'load' and 'error' event of an <oer-viewer>, recorded from the page's start (the
// element's events do not bubble; a capturing listener on the document sees them all: not one
// on window, which a 'load' event never reaches, by the HTML standard's event path). Each
// frame's detail gains `shownAt`: performance.now() at its load event, milliseconds since the
// navigation started.
export const RECORD_EVENTS = () => {
  window.oerFrames = [];
  window.oerErrors = [];
  document.addEventListener('load', (event) => {
    if (event.target?.localName === 'oer-viewer') {
      window.oerFrames.push({ ...event.detail, shownAt: performance.now() });
    }
  }, true);
  document.addEventListener('error', (event) => {
    if (event.target?.localName === 'oer-viewer') {
      window.oerErrors.push({ ...event.detail, afterFrames: window.oerFrames.length });
    }
  }, true);
};

// Waits for a full frame (neither a preview nor a preliminary one, which the frame with its
// transfer follows) after the first `after` frames; returns its detail. An
// error event after those frames fails at once with the element's message, and a timeout says
// what the element showed and reported meanwhile, so that a failure in CI explains itself.
export async function fullFrame(page, after = 0) {
  let handle;
  try {
    handle = await page.waitForFunction((count) => {
      const error = window.oerErrors.find((reported) => reported.afterFrames >= count);
      return (error && { error }) ??
        window.oerFrames.slice(count).findLast((frame) => !frame.preview && !frame.preliminary) ??
        false;
    }, after, { timeout: 30000 });
  } catch (error) {
    const seen = await page.evaluate((count) => ({
      frames: window.oerFrames.slice(count).map(({ stage, url, cache, milliseconds }) =>
        ({ stage, url, cache, milliseconds })),
      errors: window.oerErrors,
    }), after).catch(() => 'unavailable: the page is gone');
    throw new Error(`no full frame after frame ${after}: ${error.message}\n` +
                    `the element showed and reported meanwhile: ${JSON.stringify(seen, null, 1)}`);
  }
  const result = await handle.jsonValue();
  if (result.error) {
    throw new Error(`the element reported an error instead of a full frame: ` +
                    `${JSON.stringify(result.error)}`);
  }
  return result;
}

'use strict';
// Debian's Chromium driven by playwright-core: headless, --no-sandbox (tests run as root in CI), WebGL
// through SwiftShader (three.js needs it; there is no GPU). Every page records its console errors and
// uncaught exceptions, and screenshots go to HRISIM_UI_ARTIFACTS (build/test/ui-artifacts by ctest).
// Every screenshot also checks the page with axe-core (lib/axe.js): a page worth a picture is a page
// worth checking, and the picture is there to look at when the check fails.
const fs = require('node:fs');
const path = require('node:path');
const { chromium } = require('playwright-core');
const { assertAccessible } = require('./axe');

const CHROMIUM = process.env.HRISIM_CHROMIUM || '/usr/bin/chromium';
const ARTIFACTS = process.env.HRISIM_UI_ARTIFACTS || path.resolve(__dirname, '../../../build/ui-artifacts');

async function launchBrowser() {
  return chromium.launch({
    executablePath: CHROMIUM,
    headless: true,
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-dev-shm-usage'],
  });
}

/**
 * A new page of `browser` at 1280×800 that collects console errors and page errors in `errors`;
 * `open(hash)` loads the UI at `#hash` from the server on `port`.
 */
async function newPage(browser, port) {
  const context = await browser.newContext({ viewport: { width: 1280, height: 800 } });
  const page = await context.newPage();
  const errors = [];
  page.on('console', (message) => {
    if (message.type() === 'error') errors.push(`console: ${message.text()}`);
  });
  page.on('pageerror', (error) => errors.push(`page: ${error.message}`));
  const base = `http://127.0.0.1:${port}/`;
  return {
    page,
    errors,
    base,
    async open(hash = '/') {
      await page.goto(`${base}#${hash}`);
    },
    async close() {
      await context.close();
    },
  };
}

/**
 * Saves a PNG of the whole page as ARTIFACTS/name.png, then fails on axe-core's serious and critical
 * violations on it; returns the PNG's path.
 */
async function screenshot(page, name) {
  fs.mkdirSync(ARTIFACTS, { recursive: true });
  const file = path.join(ARTIFACTS, `${name}.png`);
  await page.screenshot({ path: file, fullPage: true });
  await assertAccessible(page, `${name} (${page.url()})`);
  return file;
}

module.exports = { launchBrowser, newPage, screenshot, ARTIFACTS };

'use strict';
// The page shell: it loads from the server without console errors, the libraries come from the server
// itself (no other host is asked for anything), navigation is reachable by keyboard and each one puts
// the focus on the new page's heading, and an unknown address or a missing run is a page that says so.
const assert = require('node:assert/strict');
const { describe, it } = require('node:test');
const context = require('../lib/context');
const { newPage, screenshot } = require('../lib/browser');

describe('shell', () => {
  it('loads with the server version, only from the server, and without console errors', async () => {
    const tab = await newPage(context.browser, context.server.port);
    const hosts = new Set();
    tab.page.on('request', (request) => hosts.add(new URL(request.url()).host));
    try {
      await tab.open('/');
      await tab.page.waitForSelector('#server-status:has-text("hrisim")');
      // three.js and uPlot load from web/node_modules through the import map.
      const libraries = await tab.page.evaluate(async () => {
        const three = await import('three');
        const uplot = await import('uplot');
        return { three: three.REVISION, uplot: typeof uplot.default };
      });
      assert.match(libraries.three, /^\d+$/);
      assert.equal(libraries.uplot, 'function');
      assert.deepEqual([...hosts], [`127.0.0.1:${context.server.port}`], 'no CDN, no other host');
      await screenshot(tab.page, 'shell');
      assert.deepEqual(tab.errors, []);
    } finally {
      await tab.close();
    }
  });

  it('the main navigation is reachable with the keyboard, each navigation focuses the new heading, and an unknown page says so', async () => {
    const tab = await newPage(context.browser, context.server.port);
    const page = tab.page;
    const focused = () => page.evaluate(() => `${document.activeElement.tagName} ${document.activeElement.textContent}`);
    try {
      await tab.open('/no/such/page');
      await page.waitForSelector('[role=alert]');
      // A page of its own: the heading first, then the message, in words.
      assert.equal(await page.textContent('main > :first-child'), 'Page: not found');
      assert.equal(await page.getAttribute('main > :first-child', 'tabindex'), '-1');
      assert.match(await page.textContent('main > h1 + [role=alert]'), /^Error: No page at \/no\/such\/page$/);
      await screenshot(page, 'shell-no-page');
      await page.keyboard.press('Tab');  // the skip link: it moves the focus and leaves the address alone
      await page.keyboard.press('Enter');
      assert.equal(await focused(), 'H1 Page: not found');
      assert.equal(await page.evaluate(() => location.hash), '#/no/such/page');
      await page.focus('a.brand');
      await page.keyboard.press('Tab');
      assert.equal(await page.evaluate(() => document.activeElement.textContent), 'Scenarios');
      await page.keyboard.press('Tab');
      assert.equal(await page.evaluate(() => document.activeElement.textContent), 'Sessions');
      await page.keyboard.press('Tab');
      await page.keyboard.press('Enter');
      await page.waitForFunction(() => location.hash === '#/runs');
      await page.waitForFunction(() => document.activeElement.tagName === 'H1');
      assert.equal(await focused(), 'H1 Runs');
      await page.evaluate(() => { location.hash = '#/controllers'; });
      await page.waitForFunction(() => document.activeElement.textContent === 'Controllers' && document.activeElement.tagName === 'H1');
      await page.evaluate(() => { location.hash = '#/scenarios/elevator'; });
      await page.waitForFunction(() => document.activeElement.textContent === 'elevator' && document.activeElement.tagName === 'H1');
      assert.deepEqual(tab.errors, []);
    } finally {
      await tab.close();
    }
  });

  it('a run, an episode or a scenario that is not there is a page with a heading and the server\'s message', async () => {
    const tab = await newPage(context.browser, context.server.port);
    const page = tab.page;
    try {
      for (const [hash, heading, message] of [
        ['/runs/rmissing', 'Run rmissing: not found', "no run 'rmissing'"],
        ['/episodes/emissing', 'Episode emissing: not found', "no episode 'emissing'"],
        ['/scenarios/missing', 'Scenario missing: not found', "no scenario 'missing'"],
      ]) {
        await tab.open(hash);
        await page.waitForSelector('main [role=alert]');
        assert.equal(await page.textContent('main > :first-child'), heading);
        assert.equal(await page.textContent('main > h1 + [role=alert]'), `Error: ${message}`, 'the message, no raw details');
        assert.equal(await page.$('main pre'), null);
      }
      await screenshot(page, 'shell-missing-scenario');
      // Chromium logs every HTTP error response; the 404s are what this test asks for.
      assert.deepEqual(tab.errors.filter((e) => !/status of 404/.test(e)), []);
    } finally {
      await tab.close();
    }
  });
});

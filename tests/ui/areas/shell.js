'use strict';
// The page shell: it loads from the server without console errors, the libraries come from the server
// itself (no other host is asked for anything), navigation is reachable by keyboard, and an unknown
// address shows a message rather than a blank page.
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

  it('the main navigation is reachable with the keyboard, and an unknown page says so', async () => {
    const tab = await newPage(context.browser, context.server.port);
    try {
      await tab.open('/no/such/page');
      await tab.page.waitForSelector('[role=alert]');
      assert.match(await tab.page.textContent('[role=alert]'), /No page at \/no\/such\/page/);
      await tab.page.keyboard.press('Tab');  // the skip link
      await tab.page.keyboard.press('Tab');  // the brand
      await tab.page.keyboard.press('Tab');
      assert.equal(await tab.page.evaluate(() => document.activeElement.textContent), 'Scenarios');
      await tab.page.keyboard.press('Tab');
      await tab.page.keyboard.press('Enter');
      await tab.page.waitForFunction(() => location.hash === '#/runs');
    } finally {
      await tab.close();
    }
  });
});

'use strict';
// A server started with a token: the page asks for it, keeps it in the browser, and then everything
// works — the API with the bearer header, thumbnails and downloads fetched with it, and a session's
// WebSocket opened with a one-time ticket (a browser cannot put the header on the upgrade).
const assert = require('node:assert/strict');
const fs = require('node:fs');
const { describe, it, before, after } = require('node:test');
const context = require('../lib/context');
const { newPage, screenshot } = require('../lib/browser');
const { startServer } = require('../../contract/lib/server');

const TOKEN = 'ui-test-token-1234';

describe('token', () => {
  let server;
  before(async () => {
    server = await startServer(['--token', TOKEN]);
  });
  after(async () => {
    await server.stop();
  });

  it('asks for the token, then the catalogue, thumbnails and a live session work with it', async () => {
    const tab = await newPage(context.browser, server.port);
    const api = (path, init = {}) => fetch(`http://127.0.0.1:${server.port}${path}`, { ...init, headers: { authorization: `Bearer ${TOKEN}`, ...init.headers } });
    try {
      await tab.open('/');
      await tab.page.waitForSelector('#token-form');
      await screenshot(tab.page, 'token-asked');
      await tab.page.fill('#token-input', TOKEN);
      await tab.page.click('#token-form button[type=submit]');
      await tab.page.waitForSelector('img[alt="elevator from above at its start"]');
      // Thumbnails load lazily: scrolled through, every card's comes with the token.
      await tab.page.evaluate(() => window.scrollTo(0, document.body.scrollHeight));
      await tab.page.waitForFunction(() => [...document.querySelectorAll('main img')].every((image) => image.complete && image.naturalWidth > 0));
      assert.equal(await tab.page.$('#token-form'), null, 'no question once the token is kept');

      const session = await (await api('/api/v1/sessions', { method: 'POST', body: JSON.stringify({ scenario: 'elevator' }) })).json();
      await tab.open(`/sessions/${session.id}`);
      await tab.page.waitForFunction(async ([port, id, token]) => {
        const reply = await fetch(`http://127.0.0.1:${port}/api/v1/sessions/${id}`, { headers: { authorization: `Bearer ${token}` } });
        return (await reply.json()).connected_clients === 1;
      }, [server.port, session.id, TOKEN]);
      await tab.page.click('button:has-text("Step 1 tick")');
      await tab.page.waitForFunction(async ([port, id, token]) => {
        const reply = await fetch(`http://127.0.0.1:${port}/api/v1/sessions/${id}`, { headers: { authorization: `Bearer ${token}` } });
        return (await reply.json()).tick >= 1;
      }, [server.port, session.id, TOKEN]);
      await screenshot(tab.page, 'token-session');
      // Before the token was given, the API answered 401: the browser logs those; nothing else may fail.
      assert.deepEqual(tab.errors.filter((error) => !/status of 401/.test(error)), []);
    } finally {
      await tab.close();
    }
  });

  it('downloads a run\'s episodes as CSV with the token (a plain link could not send it)', async () => {
    const headers = { authorization: `Bearer ${TOKEN}`, 'content-type': 'application/json' };
    const created = await fetch(`http://127.0.0.1:${server.port}/api/v1/runs`, { method: 'POST', headers,
      body: JSON.stringify({ scenario: 'queue', seeds: [1], max_time: 2 }) });
    const run = (await created.json()).id;
    const tab = await newPage(context.browser, server.port);
    try {
      await tab.open('/');
      await tab.page.evaluate((token) => localStorage.setItem('hrisim.token', token), TOKEN);
      await tab.open(`/runs/${run}`);
      await tab.page.waitForSelector('.run-summary .badge:has-text("finished")');
      const [download] = await Promise.all([tab.page.waitForEvent('download'), tab.page.click('a:has-text("Episodes (CSV)")')]);
      assert.equal(download.suggestedFilename(), `${run}-episodes.csv`);
      const rows = fs.readFileSync(await download.path(), 'utf8').trim().split('\n');
      assert.match(rows[0], /^episode,seed,/);
      assert.equal(rows.length, 2);
      assert.deepEqual(tab.errors.filter((error) => !/status of 401/.test(error)), []);
    } finally {
      await tab.close();
    }
  });
});

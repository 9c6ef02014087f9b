'use strict';
// A server started with a token: the page asks for it, keeps it in the browser, and then everything
// works — the API with the bearer header, thumbnails fetched with it, and a session's WebSocket opened
// with a one-time ticket (a browser cannot put the header on the upgrade).
const assert = require('node:assert/strict');
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
});

'use strict';
// The Sessions page (#/sessions): it lists the live sessions and keeps them current while shown (and
// only then), resets one to a seed, restarts and ends one (after asking), says when there is none; and
// a session the server refuses for --max-sessions (8 in these tests) says so once, leading there.
const assert = require('node:assert/strict');
const { describe, it } = require('node:test');
const context = require('../lib/context');
const { newPage, screenshot } = require('../lib/browser');
const { call, createSession } = require('../lib/api');

/** A row's cells by their field, as text. */
function rowCells(page, id) {
  return page.$$eval(`tr[data-id="${id}"] td[data-field]`, (cells) => Object.fromEntries(cells.map((cell) => [cell.dataset.field, cell.textContent])));
}

describe('sessions', () => {
  it('lists a session made through the API and keeps it current; resets it to a seed, restarts and ends it', async () => {
    const id = await createSession({ scenario: 'elevator', seed: 3, unwatched_grace: 120 });
    await call('POST', `/api/v1/sessions/${id}/step`, { n: 30 });
    const tab = await newPage(context.browser, context.server.port);
    const page = tab.page;
    try {
      await tab.open('/sessions');
      await page.waitForSelector(`tr[data-id="${id}"]`);
      assert.equal(await page.getAttribute('nav a[data-nav=sessions]', 'aria-current'), 'page');
      const cells = await rowCells(page, id);
      assert.deepEqual({ ...cells, idle: undefined }, { scenario: 'elevator', seed: '3', mode: 'lockstep', status: 'running', tick: '30',
        time: '0.50 s', watchers: '0', idle: undefined, grace: '120 s' });
      assert.match(cells.idle, /^\d+ s$/);
      assert.equal(await page.getAttribute(`tr[data-id="${id}"] a:has-text("Open")`, 'href'), `#/sessions/${id}`);
      assert.equal(await page.inputValue(`tr[data-id="${id}"] .session-seed`), '3', 'the reset seed starts as the session\'s');

      // The page follows what others do to the session.
      await call('POST', `/api/v1/sessions/${id}/step`, { n: 12 });
      await page.waitForFunction((s) => document.querySelector(`tr[data-id="${s}"] td[data-field=tick]`).textContent === '42', id, { timeout: 8000 });

      // Reset to seed 5: tick 0, and the server agrees.
      await page.fill(`tr[data-id="${id}"] .session-seed`, '5');
      await page.click(`tr[data-id="${id}"] button:has-text("Reset")`);
      await page.waitForSelector(`.sessions-notice [role=status]:has-text("reset with seed 5")`);
      assert.deepEqual(await rowCells(page, id).then((c) => [c.seed, c.tick, c.time]), ['5', '0', '0.00 s']);
      const reset = (await call('GET', `/api/v1/sessions/${id}`)).body;
      assert.deepEqual([reset.seed, reset.tick], [5, 0]);
      await screenshot(page, 'sessions');

      // Restart: the same seed again, from tick 0.
      await call('POST', `/api/v1/sessions/${id}/step`, { n: 5 });
      await page.click(`tr[data-id="${id}"] button:has-text("Restart")`);
      await page.waitForSelector(`.sessions-notice [role=status]:has-text("reset with seed 5")`);
      const restarted = (await call('GET', `/api/v1/sessions/${id}`)).body;
      assert.deepEqual([restarted.seed, restarted.tick], [5, 0]);

      // End asks first: declined, the session stays; accepted, it goes, and the list says it is empty.
      page.once('dialog', (dialog) => dialog.dismiss());
      await page.click(`tr[data-id="${id}"] button:has-text("End")`);
      await page.waitForTimeout(300);
      assert.equal((await call('GET', `/api/v1/sessions/${id}`)).status, 200);
      page.once('dialog', (dialog) => dialog.accept());
      await page.click(`tr[data-id="${id}"] button:has-text("End")`);
      await page.waitForSelector(`tr[data-id="${id}"]`, { state: 'detached' });
      assert.equal((await call('GET', `/api/v1/sessions/${id}`)).status, 404);
      assert.deepEqual((await call('GET', '/api/v1/sessions')).body.items, []);
      assert.match(await page.textContent('.sessions-list'), /^No live sessions\. Start one from a scenario's page\.$/);

      // Left, the page asks no more.
      const asked = [];
      page.on('request', (request) => { if (request.url().endsWith('/api/v1/sessions')) asked.push(request.url()); });
      await page.evaluate(() => { location.hash = '#/runs'; });
      await page.waitForTimeout(3500);
      assert.deepEqual(asked, []);
      assert.deepEqual(tab.errors, []);
    } finally {
      await tab.close();
      await call('DELETE', `/api/v1/sessions/${id}`);
    }
  });

  it('a session refused for --max-sessions says so once, with the way to the Sessions page', async () => {
    const running = (await call('GET', '/api/v1/sessions')).body.items.filter((session) => session.status === 'running').length;
    const made = [];
    const tab = await newPage(context.browser, context.server.port);
    const page = tab.page;
    try {
      for (let i = running; i < 8; i++) made.push(await createSession({ scenario: 'queue', seed: i }));
      await tab.open('/scenarios/queue');
      await page.click('button:has-text("Start live session")');
      await page.waitForSelector('.sc-session-status [role=alert]');
      assert.equal(await page.textContent('.sc-session-status'), 'Not started: the server already runs its maximum of 8 sessions '
        + '(finished ones do not count). End one on the Sessions page, or try again in 10 s.');
      await screenshot(page, 'sessions-refused');
      await page.click('.sc-session-status a:has-text("Sessions page")');
      await page.waitForSelector(`tr[data-id="${made[0]}"]`);
      assert.equal(await page.locator('.sessions-table tbody tr').count(), 8);
      // Chromium logs the 503 the test asks for.
      assert.deepEqual(tab.errors.filter((error) => !/status of 503/.test(error)), []);
    } finally {
      await tab.close();
      for (const id of made) await call('DELETE', `/api/v1/sessions/${id}`);
    }
  });
});

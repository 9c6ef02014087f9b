'use strict';
// The controller × scenario comparison (#/controllers): runs made over the API with different
// controllers are one row each, with the numbers of their reports and 95 % intervals, under the command
// that reproduces them; a run the command would make otherwise is marked, and the scenario filter works.
const assert = require('node:assert/strict');
const { describe, it } = require('node:test');
const context = require('../lib/context');
const { newPage, screenshot } = require('../lib/browser');

const WAIT = { timeout: 20000 };

/** Starts runs over the API from the page and resolves to their reports once each has ended. */
async function runToTheEnd(page, requests) {
  return page.evaluate(async (bodies) => {
    const started = await Promise.all(bodies.map(async (body) => {
      const reply = await fetch('/api/v1/runs', { method: 'POST', headers: { 'content-type': 'application/json' }, body: JSON.stringify(body) });
      if (!reply.ok) throw new Error(`POST /api/v1/runs: ${reply.status} ${await reply.text()}`);
      return (await reply.json()).id;
    }));
    const reports = [];
    for (const id of started) {
      for (;;) {
        const report = await (await fetch(`/api/v1/runs/${id}`)).json();
        if (report.status !== 'queued' && report.status !== 'running') {
          reports.push(report);
          break;
        }
        await new Promise((resolve) => setTimeout(resolve, 200));
      }
    }
    return reports;
  }, requests);
}

/** The first number of a table cell's text ("0.398 m [0.321, 0.476]" → 0.398). */
function firstNumber(text) {
  return Number(/-?[\d,]*\.?\d+/.exec(text)[0].replace(/,/g, ''));
}

describe('controllers', () => {
  it('two runs with different controllers are two rows, with their numbers and the command that reproduces them', async () => {
    const tab = await newPage(context.browser, context.server.port);
    const page = tab.page;
    try {
      await tab.open('/controllers');
      const kitchen = { location: 'kitchen' };
      const [goal, social, queue] = await runToTheEnd(page, [
        { scenario: 'apartment', count: 2, controller: { type: 'goal', goal: kitchen } },
        { scenario: 'apartment', count: 2, controller: { type: 'social', goal: kitchen } },
        { scenario: 'queue', count: 1, max_time: 5 },
      ]);
      for (const report of [goal, social, queue]) assert.equal(report.status, 'finished', report.id);

      await tab.open('/controllers?scenario=apartment');
      await page.waitForSelector('table.controllers-table tbody tr[data-controller=social]', WAIT);
      const rows = await page.$$eval('table.controllers-table tbody tr', (trs) => trs.map((tr) => ({
        scenario: tr.dataset.scenario, controller: tr.dataset.controller, run: tr.dataset.run, cells: [...tr.cells].map((c) => c.textContent) })));
      assert.deepEqual(rows.map((r) => [r.scenario, r.controller, r.run]), [['apartment', 'goal', goal.id], ['apartment', 'social', social.id]],
        'one row per controller, the queue filtered out');
      for (const [row, report] of [[rows[0], goal], [rows[1], social]]) {
        assert.equal(row.cells[2], '2', 'episodes');
        const distance = report.aggregates.minimum_distance_to_people;
        assert.match(row.cells[7], /^[\d.]+ m \[[\d.-]+, [\d.-]+\]$/, 'mean and interval in metres');
        assert.ok(Math.abs(firstNumber(row.cells[7]) - distance.mean) <= 0.001 * Math.max(1, distance.mean), `${row.cells[7]} vs ${distance.mean}`);
        assert.ok(Math.abs(firstNumber(row.cells[3]) - report.aggregates.success.mean * 100) < 0.01, `success ${row.cells[3]}`);
      }
      assert.equal(await page.textContent('.reproduce pre.command'), 'scripts/compare-controllers --scenarios apartment --controllers goal,social --seeds 0-1');
      // The apartment's own robot drives to the living room: the script would not send "kitchen".
      assert.match(await page.textContent(`.reproduce .differences li[data-run="${goal.id}"]`),
        /controller \{.*"location":"kitchen".*\} where the script's run has \{"goal":\{"location":"living_room".*\}/);
      assert.equal(await page.inputValue('#controllers-scenario'), 'apartment');
      await screenshot(page, 'controllers');

      await page.selectOption('#controllers-scenario', '');
      await page.waitForSelector(`table.controllers-table tbody tr[data-run="${queue.id}"]`, WAIT);
      assert.match(await page.textContent(`tr[data-run="${queue.id}"]`), /scenario's own/);
      assert.match(await page.textContent('.reproduce pre.command'),
        /^scripts\/compare-controllers --scenarios apartment,queue --controllers scenario,goal,social --seeds 0-1$/);
      assert.match(await page.textContent('.reproduce .missing'), /apartment × scenario, queue × goal, queue × social/);
      assert.deepEqual(tab.errors, []);
    } finally {
      await tab.close();
    }
  });
});

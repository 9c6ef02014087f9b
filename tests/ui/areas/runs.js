'use strict';
// Runs, episode replays and comparisons: a run started from the form reaches its report (progress,
// then metrics with units and arrows; gates pending while it runs), every problem of the form shows
// beside its field at once, an episode replays (the scrubber moves the agents and the plots' cursor;
// each plot has a summary and its data as a table; the time to collision is clipped at 10 s),
// two runs compare with p-values and failed gates as chips, and the tables scroll in their panels on
// a narrow screen.
const assert = require('node:assert/strict');
const { describe, it } = require('node:test');
const context = require('../lib/context');
const { newPage, screenshot } = require('../lib/browser');

const WAIT = { timeout: 20000 };
// Shared by the tests below, in order: the run started from the form and one of its episodes.
const state = { runA: null, episode: null };

/** The page is no wider than the window: wide tables scroll in their own boxes. */
async function assertNoSidewaysScroll(page, what) {
  const { scrollWidth, innerWidth } = await page.evaluate(() => ({ scrollWidth: document.scrollingElement.scrollWidth, innerWidth }));
  assert.ok(scrollWidth <= innerWidth, `${what}: the page is ${scrollWidth} px wide in a ${innerWidth} px window`);
}

/** Starts a run through the form on #/runs?scenario=queue; resolves to its id once its page opened. */
async function startRunFromForm(tab, { seeds, gates }) {
  await tab.open('/runs?scenario=queue');
  const page = tab.page;
  await page.waitForSelector('#run-scenario option[value=queue]', { ...WAIT, state: 'attached' });
  assert.equal(await page.inputValue('#run-scenario'), 'queue');
  await page.selectOption('#run-seed-mode', 'list');
  await page.fill('#run-seeds', seeds);
  await page.fill('#run-max-time', '20');
  await page.fill('#run-gates', gates);
  await page.click('.run-form button[type=submit]');
}

describe('runs', () => {
  it('starts a run from the form; its page shows the progress, then the metrics with units and arrows', async () => {
    const tab = await newPage(context.browser, context.server.port);
    try {
      await startRunFromForm(tab, { seeds: '1,2', gates: 'collisions.max >= 0\nminimum_distance_to_people.min >= 0' });
      await tab.page.waitForFunction(() => /^#\/runs\/r[0-9a-f]{32}$/.test(location.hash), null, WAIT);
      state.runA = await tab.page.evaluate(() => location.hash.slice('#/runs/'.length));
      await tab.page.waitForSelector('progress#run-progress', WAIT);
      await tab.page.waitForSelector('.run-summary .badge:has-text("finished")', WAIT);
      assert.equal(await tab.page.getAttribute('progress#run-progress', 'value'), '2');
      await tab.page.waitForSelector('table.aggregates tr[data-metric=minimum_distance_to_people]', WAIT);
      const row = await tab.page.textContent('table.aggregates tr[data-metric=minimum_distance_to_people]');
      assert.match(row, /↑/, 'higher is better');
      assert.match(row, /\d m/, 'with its unit');
      assert.match(await tab.page.textContent('table.aggregates tr[data-metric=collisions]'), /↓/);
      assert.match(await tab.page.textContent('.verdict'), /passed/);
      await tab.page.waitForSelector('.dot-plot .uplot', WAIT);
      // Each dot plot reads as a summary, and its dots as a table of seeds.
      const distance = '.dot-plot[data-metric=minimum_distance_to_people]';
      assert.match(await tab.page.getAttribute(`${distance} .uplot`, 'aria-label'),
        /^minimum distance to people ↑ per episode, 2 episodes: from [\d.]+ m to [\d.]+ m, mean [\d.]+ m\.$/);
      await tab.page.click(`${distance} button:has-text("Show as table")`);
      assert.equal(await tab.page.getAttribute(`${distance} .plot-table-toggle`, 'aria-expanded'), 'true');
      assert.deepEqual(await tab.page.$$eval(`${distance} .plot-table tbody tr`, (rows) => rows.map((row) => row.cells[0].textContent)), ['1', '2']);
      await tab.page.waitForSelector('table.episodes a[href^="#/episodes/e"]', WAIT);
      state.episode = (await tab.page.getAttribute('table.episodes a[href^="#/episodes/e"]', 'href')).slice('#/episodes/'.length);
      assert.equal(await tab.page.getAttribute('a[href$="/junit"]', 'href'), `/api/v1/runs/${state.runA}/junit`);
      await screenshot(tab.page, 'runs-run-report');

      await tab.open('/runs');
      await tab.page.waitForSelector(`.runs-table a[href="#/runs/${state.runA}"]`, WAIT);
      assert.match(await tab.page.textContent('.runs-table tbody tr'), /2 \/ 2/);
      await screenshot(tab.page, 'runs-list');
      assert.deepEqual(tab.errors, []);
    } finally {
      await tab.close();
    }
  });

  it('a running run shows its progress, its gates pending, and can be cancelled', async () => {
    const tab = await newPage(context.browser, context.server.port);
    const page = tab.page;
    try {
      await tab.open('/runs');
      // The elevator's episodes take long enough (hundreds of ms each) to catch the run running.
      const run = await page.evaluate(async () => (await (await fetch('/api/v1/runs', { method: 'POST', headers: { 'content-type': 'application/json' },
        body: JSON.stringify({ scenario: 'elevator', count: 20, gates: ['collisions.max >= 0', 'success.mean > 2'] }) })).json()).id);
      await tab.open(`/runs/${run}`);
      await page.waitForSelector('.run-summary .badge:text-matches("queued|running")', WAIT);
      assert.match(await page.textContent('label[for=run-progress]'), /of 20 episodes done/);
      // Neither gate is settled while episodes remain, not even the one that cannot pass.
      assert.deepEqual(await page.$$eval('.verdict tr[data-gate] td:nth-child(3)', (cells) => cells.map((c) => c.textContent)), ['pending', 'pending']);
      assert.equal(await page.textContent('#verdict-title .badge'), 'pending');
      assert.equal(await page.$('.verdict .badge.bad'), null, 'nothing failed yet');
      assert.doesNotMatch(await page.textContent('.verdict table'), /no value/);
      await page.click('button:has-text("Cancel the run")');
      await page.waitForSelector('.run-summary .badge:has-text("cancelled")', WAIT);
      assert.equal(await page.isVisible('button:has-text("Cancel the run")'), false);
      await screenshot(page, 'runs-run-cancelled');
      assert.deepEqual(tab.errors, []);
    } finally {
      await tab.close();
    }
  });

  it('every problem of the form shows beside its field at once, and so does each of the server\'s', async () => {
    const tab = await newPage(context.browser, context.server.port);
    const page = tab.page;
    const posted = [];
    page.on('request', (request) => { if (request.method() === 'POST') posted.push(request.url()); });
    try {
      await startRunFromForm(tab, { seeds: '3-1', gates: 'collisions.max == 0\ncollisions.median < 1\nfast please' });
      await page.fill('#run-max-time', '-2');
      await page.click('.run-form button[type=submit]');
      await page.waitForSelector('#run-seeds-error:not([hidden])', WAIT);
      assert.match(await page.textContent('#run-seeds-error'), /backwards/);
      assert.match(await page.textContent('#run-max-time-error'), /above 0/);
      const gates = await page.textContent('#run-gates-error');
      assert.match(gates, /line 2: unknown statistic 'median'/);
      assert.match(gates, /line 3: "fast please" is not metric\.statistic OP number/);
      assert.doesNotMatch(gates, /line 1/);
      for (const field of ['#run-seeds', '#run-max-time', '#run-gates']) assert.equal(await page.getAttribute(field, 'aria-invalid'), 'true', field);
      assert.equal(await page.evaluate(() => document.activeElement.id), 'run-seeds', 'the first field in error takes the focus');
      assert.deepEqual(posted, [], 'nothing sent while the page sees problems');
      await screenshot(page, 'runs-form-errors');

      // What only the server knows (its metrics) comes back as a list of pointers, each beside its field.
      await page.fill('#run-seeds', '1-3');
      await page.fill('#run-max-time', '20');
      await page.fill('#run-gates', 'no_such_metric.max == 0\n\nnor_this.min > 1');
      await page.click('.run-form button[type=submit]');
      await page.waitForFunction(() => /line 3/.test(document.querySelector('#run-gates-error').textContent), null, WAIT);
      assert.match(await page.textContent('#run-gates-error'), /line 1: .*unknown metric 'no_such_metric'.*line 3: .*unknown metric 'nor_this'/);
      assert.equal(await page.isVisible('#run-seeds-error'), false, 'the seeds are fine now');
      assert.equal(posted.length, 1);
      // Chromium logs every HTTP error response; the refused run's 400 is the answer this test asks for.
      assert.deepEqual(tab.errors.filter((e) => !/Failed to load resource: .* 400 \(Bad Request\)/.test(e)), []);
    } finally {
      await tab.close();
    }
  });

  it('an episode replays: the scrubber moves the agents and the plots follow it; each plot reads as a summary and a table', async () => {
    assert.ok(state.episode, 'the first test stored an episode');
    const tab = await newPage(context.browser, context.server.port);
    try {
      await tab.open(`/episodes/${state.episode}`);
      const page = tab.page;
      await page.waitForSelector('svg.map g.map-agent[data-agent]', WAIT);
      await page.waitForSelector('.series-plot[data-series=distance_to_closest_person] .uplot', WAIT);
      const agents = () => page.$$eval('svg.map g.map-agent[data-agent] circle', (circles) => circles.map((c) => `${c.getAttribute('cx')},${c.getAttribute('cy')}`));
      const marker = () => page.$eval('.series-plot[data-series=distance_to_closest_person] .plot-marker', (m) => parseFloat(m.style.left));
      const before = await agents();
      const markerBefore = await marker();
      await page.focus('#replay-time');
      for (let i = 0; i < 20; i++) await page.keyboard.press('ArrowRight');
      assert.equal(await page.inputValue('#replay-time'), '20');
      assert.match(await page.textContent('.timeline .clock'), /^2 s of/);
      assert.notDeepEqual(await agents(), before, 'the agents moved');
      assert.ok(await marker() > markerBefore, 'the plot cursor moved right');
      // Hovering a plot moves the scrubber.
      const box = await page.$eval('.series-plot[data-series=robot_speed] .u-over', (o) => { const r = o.getBoundingClientRect(); return { x: r.x, y: r.y, w: r.width, h: r.height }; });
      await page.mouse.move(box.x + box.w * 0.75, box.y + box.h / 2);
      await page.waitForFunction(() => Number(document.querySelector('#replay-time').value) > 100, null, WAIT);
      assert.ok(await page.$$eval('.event-tick', (ticks) => ticks.length) > 0, 'events on the timeline');
      assert.match(await page.textContent('.reward-note'), /no benchmark task/);
      // A plot's text alternative: a summary as its name, every sample in a table on demand.
      const plot = '.series-plot[data-series=distance_to_closest_person]';
      const summary = await page.getAttribute(`${plot} .uplot`, 'aria-label');
      const samples = Number(/, (\d+) samples: from [\d.]+ m to [\d.]+ m, mean [\d.]+ m/.exec(summary)?.[1]);
      assert.ok(samples > 100, summary);
      assert.equal(await page.getAttribute(`${plot} .uplot`, 'role'), 'img');
      assert.equal(await page.isVisible(`${plot} .plot-table`), false);
      await page.click(`${plot} button:has-text("Show as table")`);
      assert.equal(await page.$$eval(`${plot} .plot-table tbody tr`, (rows) => rows.length), samples);
      assert.match(await page.textContent(`${plot} .plot-table tbody tr`), /^0[\d.]+$/, 'time 0 s and its distance');
      assert.match(await page.textContent('.episode-metrics tr[data-metric=minimum_distance_to_people]'), /\d m/);
      await screenshot(page, 'runs-episode');
      assert.deepEqual(tab.errors, []);
    } finally {
      await tab.close();
    }
  });

  it('two runs compare metric by metric, with p-values and failed gates, and the list leads there; tables scroll on a narrow screen', async () => {
    assert.ok(state.runA, 'the first test started a run');
    const tab = await newPage(context.browser, context.server.port);
    try {
      await startRunFromForm(tab, { seeds: '3-5', gates: 'success.mean > 1\ncollisions.max >= 0' });
      await tab.page.waitForFunction((a) => /^#\/runs\/r[0-9a-f]{32}$/.test(location.hash) && !location.hash.endsWith(a), state.runA, WAIT);
      const runB = await tab.page.evaluate(() => location.hash.slice('#/runs/'.length));
      await tab.page.waitForSelector('.run-summary .badge:has-text("finished")', WAIT);
      await tab.open('/runs');
      await tab.page.waitForSelector(`.runs-table a[href="#/runs/${runB}"]`, WAIT);
      await tab.page.check(`input[aria-label="Compare run ${state.runA}"]`);
      await tab.page.check(`input[aria-label="Compare run ${runB}"]`);
      await tab.page.click('button:has-text("Compare the two chosen")');
      await tab.page.waitForFunction((hash) => location.hash === hash, `#/compare/${state.runA}/${runB}`, WAIT);
      await tab.page.waitForSelector('table.comparison tbody tr[data-metric=success]', WAIT);
      const pValues = await tab.page.$$eval('table.comparison td.p-value', (cells) => cells.map((c) => c.textContent));
      assert.ok(pValues.some((p) => /^[<\d]/.test(p)), `some p-value: ${pValues.join(' ')}`);
      await tab.page.click('table.comparison button.sort');
      assert.equal(await tab.page.getAttribute('table.comparison th[aria-sort]', 'aria-sort'), 'ascending');
      // The queue's robot stands still under its own controller: its paths are points, attached but not "visible".
      await tab.page.waitForSelector('.compare-map svg.map polyline', { ...WAIT, state: 'attached' });
      // A's gates passed; B failed one, shown as a chip after its verdict.
      assert.equal(await tab.page.textContent('.side-a .verdict-facts'), 'passed');
      assert.doesNotMatch(await tab.page.textContent('.side-b .verdict-facts'), /object|,/);
      assert.deepEqual(await tab.page.$$eval('.side-b .verdict-facts code.chip', (chips) => chips.map((c) => c.textContent)), ['success.mean > 1']);
      await screenshot(tab.page, 'runs-compare');

      await tab.page.setViewportSize({ width: 800, height: 800 });
      await assertNoSidewaysScroll(tab.page, 'the comparison');
      assert.ok(await tab.page.$eval('.table-scroll:has(table.comparison)', (box) => box.scrollWidth > box.clientWidth), 'the metrics table scrolls in its box');
      await screenshot(tab.page, 'runs-compare-800px');
      await tab.open(`/runs/${runB}`);
      await tab.page.waitForSelector('table.episodes', WAIT);
      await assertNoSidewaysScroll(tab.page, 'the run report');
      await screenshot(tab.page, 'runs-run-report-800px');
      await tab.open('/runs');
      await tab.page.waitForSelector('table.runs-table', WAIT);
      await assertNoSidewaysScroll(tab.page, 'the runs list');
      await screenshot(tab.page, 'runs-list-800px');
      assert.deepEqual(tab.errors, []);
    } finally {
      await tab.close();
    }
  });

  it('a run with another controller goes to a chosen location, its time to collision clipped at 10 s; runs of two scenarios are drawn apart', async () => {
    assert.ok(state.runA, 'the first test started a run');
    const tab = await newPage(context.browser, context.server.port);
    const page = tab.page;
    try {
      await tab.open('/runs?scenario=apartment');
      await page.waitForSelector('#run-scenario option[value=apartment]', { ...WAIT, state: 'attached' });
      assert.equal(await page.isVisible('#run-goal'), false, 'no goal for the scenario\'s own controller');
      assert.deepEqual(await page.$$eval('#run-controller option', (options) => options.map((o) => o.value)),
        ['scenario', 'idle', 'goal', 'social', 'dwa', 'orca', 'social_force'], 'the reference controllers are offered');
      await page.selectOption('#run-controller', 'dwa');
      assert.equal(await page.isVisible('#run-goal'), true, 'a driving controller may have a goal');
      assert.equal(await page.inputValue('#run-goal'), '', 'none by default: the choreography\'s gotos');
      await page.selectOption('#run-controller', 'goal');
      await page.waitForSelector('#run-goal option[value=kitchen]', { ...WAIT, state: 'attached' });
      await page.selectOption('#run-goal', 'kitchen');
      await page.fill('#run-count', '2');
      await page.fill('#run-max-time', '20');
      await page.click('.run-form button[type=submit]');
      await page.waitForFunction((a) => /^#\/runs\/r[0-9a-f]{32}$/.test(location.hash) && !location.hash.endsWith(a), state.runA, WAIT);
      const runC = await page.evaluate(() => location.hash.slice('#/runs/'.length));
      await page.waitForSelector('.run-summary .badge:has-text("finished")', WAIT);
      assert.match(await page.textContent('.run-summary'), /goal → kitchen/);
      // The robot drives past people: times to collision of tens of seconds, drawn at the plot's top of 10 s.
      await page.click('table.episodes a[href^="#/episodes/e"]');
      const ttc = '.series-plot[data-series=time_to_collision]';
      await page.waitForSelector(`${ttc} .uplot`, WAIT);
      assert.equal(Number(await page.getAttribute(`${ttc} .uplot`, 'data-y-max')), 10.5);
      assert.match(await page.textContent(`${ttc} figcaption`), /Clipped at 10 s/);
      await page.click(`${ttc} button:has-text("Show as table")`);
      const longest = Math.max(...await page.$$eval(`${ttc} .plot-table tbody td:nth-child(2)`, (cells) => cells.map((c) => Number(c.textContent.replace(/,/g, ''))).filter(Number.isFinite)));
      assert.ok(longest > 10, `the table keeps the longest time, ${longest} s`);
      await screenshot(page, 'runs-episode-apartment');
      await tab.open(`/compare/${state.runA}/${runC}`);
      await page.waitForSelector('.compare-map .message.info', WAIT);
      assert.match(await page.textContent('.compare-map .message.info'), /different scenarios/);
      await page.waitForFunction(() => document.querySelectorAll('.compare-map svg.map').length === 2, null, WAIT);
      await page.waitForSelector('.compare-map svg.map polyline[stroke="#d1492f"]', WAIT);
      await screenshot(page, 'runs-compare-scenarios');
      assert.deepEqual(tab.errors, []);
    } finally {
      await tab.close();
    }
  });
});

'use strict';
// Runs, episode replays and comparisons: a run started from the form with a name, tags and notes
// reaches its report (progress, then metrics with units and arrows; gates pending while it runs), the
// report edits its labels in place, plots the metrics chosen in its address and saves its episodes,
// itself and its plots as files; every problem of the form shows beside its field at once; the list
// searches, filters by tag and by conditions, shows chosen metric columns, sorts and pages, all in the
// address; an episode replays from the moment its address names (the scrubber moves the agents and the
// plots' cursor; each plot has a summary and its data as a table; the time to collision is clipped at
// 10 s) and offers its trajectory and series as CSV; it is filmed as a video (the server's refusal
// beside the form, the progress, Cancel, then the video playing and its file); the runs chosen to
// compare stay chosen through a reload; three runs compare against a baseline with p-values, Holm's
// correction, distributions (saved as SVG and PNG) and failed gates as chips, and the tables scroll
// in their panels on a narrow screen; a run merged from shards says which shards it holds.
const assert = require('node:assert/strict');
const fs = require('node:fs');
const { describe, it } = require('node:test');
const context = require('../lib/context');
const { newPage, screenshot } = require('../lib/browser');
const { call } = require('../lib/api');

const WAIT = { timeout: 20000 };
// Shared by the tests below, in order: the run started from the form and one of its episodes.
const state = { runA: null, episode: null };

/** Starts a run through the API; resolves to its id once it has ended. */
async function runThroughApi(body) {
  const created = await call('POST', '/api/v1/runs', body);
  assert.equal(created.status, 201, JSON.stringify(created.body));
  for (let tries = 0; tries < 200; tries++) {
    if ((await call('GET', `/api/v1/runs/${created.body.id}`)).body.status === 'finished') return created.body.id;
    await new Promise((resolve) => setTimeout(resolve, 50));
  }
  throw new Error(`run ${created.body.id} did not finish`);
}

/** Clicks what `selector` names and resolves to the download it starts: {name, text}. */
async function download(page, selector) {
  const [started] = await Promise.all([page.waitForEvent('download', WAIT), page.click(selector)]);
  return { name: started.suggestedFilename(), bytes: fs.readFileSync(await started.path()) };
}

/** The address's query of the page, as an object. */
const addressQuery = (page) => page.evaluate(() => Object.fromEntries(new URLSearchParams(location.hash.split('?')[1] ?? '')));

/** The page is no wider than the window: wide tables scroll in their own boxes. */
async function assertNoSidewaysScroll(page, what) {
  const { scrollWidth, innerWidth } = await page.evaluate(() => ({ scrollWidth: document.scrollingElement.scrollWidth, innerWidth }));
  assert.ok(scrollWidth <= innerWidth, `${what}: the page is ${scrollWidth} px wide in a ${innerWidth} px window`);
}

/** Starts a run through the form on #/runs?scenario=queue. */
async function startRunFromForm(tab, { seeds, gates, name = '', tags = '', notes = '', maxTime = '20' }) {
  await tab.open('/runs?scenario=queue');
  const page = tab.page;
  await page.waitForSelector('#run-scenario option[value=queue]', { ...WAIT, state: 'attached' });
  assert.equal(await page.inputValue('#run-scenario'), 'queue');
  await page.selectOption('#run-seed-mode', 'list');
  await page.fill('#run-seeds', seeds);
  await page.fill('#run-max-time', maxTime);
  await page.fill('#run-gates', gates);
  await page.fill('#run-name', name);
  await page.fill('#run-tags', tags);
  await page.fill('#run-notes', notes);
  await page.click('.run-form button[type=submit]');
}

describe('runs', () => {
  it('starts a run from the form with a name, tags and notes; its page shows them, the progress, then the metrics with units and arrows', async () => {
    const tab = await newPage(context.browser, context.server.port);
    try {
      await startRunFromForm(tab, { seeds: '1,2', gates: 'collisions.max >= 0\nminimum_distance_to_people.min >= 0',
        name: 'queue baseline', tags: 'nightly, queue  smoke,nightly', notes: 'The first try.\nSecond line.' });
      await tab.page.waitForFunction(() => /^#\/runs\/r[0-9a-f]{32}$/.test(location.hash), null, WAIT);
      state.runA = await tab.page.evaluate(() => location.hash.slice('#/runs/'.length));
      await tab.page.waitForSelector('progress#run-progress', WAIT);
      assert.equal(await tab.page.textContent('h1'), `queue baseline (run ${state.runA.slice(0, 9)})`);
      assert.equal(await tab.page.textContent('.run-label-name'), 'queue baseline');
      assert.deepEqual(await tab.page.$$eval('.run-label-tags button.tag', (tags) => tags.map((t) => t.textContent)), ['nightly', 'queue', 'smoke']);
      assert.equal(await tab.page.textContent('.run-label-notes'), 'The first try.\nSecond line.');
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
      const listRow = `.runs-table tr:has(a[href="#/runs/${state.runA}"])`;
      assert.match(await tab.page.textContent(listRow), /2 \/ 2/);
      assert.equal(await tab.page.textContent(`${listRow} .run-name .name`), 'queue baseline');
      assert.deepEqual(await tab.page.$$eval(`${listRow} button.tag`, (tags) => tags.map((t) => t.textContent)), ['nightly', 'queue', 'smoke']);
      // The default metric columns, the success rate first.
      assert.deepEqual(await tab.page.$$eval('.runs-table th[data-column]', (cells) => cells.map((c) => c.dataset.column)),
        ['success.mean', 'collisions.max', 'time_to_goal.mean']);
      assert.equal(await tab.page.textContent(`${listRow} td[data-column="collisions.max"]`), '0');
      await screenshot(tab.page, 'runs-list');
      assert.deepEqual(tab.errors, []);
    } finally {
      await tab.close();
    }
  });

  it('a report edits its name, tags and notes in place, plots the metrics its address names, and saves itself and its plots as files', async () => {
    assert.ok(state.runA, 'the first test started a run');
    const tab = await newPage(context.browser, context.server.port);
    const page = tab.page;
    const patches = [];
    page.on('request', (request) => { if (request.method() === 'PATCH') patches.push(request.postDataJSON()); });
    try {
      await tab.open(`/runs/${state.runA}`);
      await page.click('button:has-text("Edit the name, tags and notes")', WAIT);
      assert.equal(await page.evaluate(() => document.activeElement.id), 'edit-name');
      assert.equal(await page.inputValue('#edit-tags'), 'nightly queue smoke');
      // What the page sees is shown before anything is sent.
      await page.fill('#edit-tags', `ok ${'x'.repeat(70)}`);
      await page.click('.labels-form button[type=submit]');
      assert.match(await page.textContent('#edit-tags-error'), /longer than 64 bytes/);
      assert.equal(await page.evaluate(() => document.activeElement.id), 'edit-tags');
      assert.deepEqual(patches, []);
      // What the server objects to goes beside the field its pointer names.
      await page.route('**/api/v1/runs/*', (route) => (route.request().method() !== 'PATCH' ? route.fallback() : route.fulfill({
        status: 400, contentType: 'application/json',
        body: JSON.stringify({ error: { code: 'bad_request', message: 'two problems', details: { errors: [
          { pointer: '/name', message: 'the server dislikes this name' }, { pointer: '/notes', message: 'and these notes' }] } } }) })));
      await page.fill('#edit-tags', 'ok');
      await page.click('.labels-form button[type=submit]');
      await page.waitForSelector('#edit-name-error:not([hidden])', WAIT);
      assert.equal(await page.textContent('#edit-name-error'), 'the server dislikes this name');
      assert.equal(await page.textContent('#edit-notes-error'), 'and these notes');
      assert.equal(await page.isVisible('#edit-tags-error'), false);
      await screenshot(page, 'runs-run-labels-errors');
      await page.unroute('**/api/v1/runs/*');
      await page.fill('#edit-name', 'renamed baseline');
      await page.fill('#edit-tags', 'nightly,alpha');
      await page.fill('#edit-notes', '');
      await page.click('.labels-form button[type=submit]');
      await page.waitForSelector('.run-label-name:has-text("renamed baseline")', WAIT);
      assert.deepEqual(patches.at(-1), { name: 'renamed baseline', tags: ['nightly', 'alpha'], notes: '' });
      assert.equal(await page.textContent('h1'), `renamed baseline (run ${state.runA.slice(0, 9)})`);
      const stored = (await call('GET', `/api/v1/runs/${state.runA}`)).body;
      assert.deepEqual([stored.name, stored.tags, stored.notes], ['renamed baseline', ['nightly', 'alpha'], '']);

      // The plotted metrics: chosen on the page, kept in the address, and a link brings them back.
      await page.click('#plot-metrics summary');
      await page.uncheck('#plot-metrics input[value=success]');
      await page.check('#plot-metrics input[value=episode_length]');
      await page.waitForSelector('.dot-plot[data-metric=episode_length] .uplot', WAIT);
      assert.equal((await addressQuery(page)).plots, 'collisions,minimum_distance_to_people,path_length,time_to_goal,episode_length');
      await tab.open(`/runs/${state.runA}?plots=episode_length,collisions`);
      await page.waitForSelector('.dot-plot[data-metric=episode_length] .uplot', WAIT);
      assert.deepEqual(await page.$$eval('.dot-plot', (plots) => plots.map((p) => p.dataset.metric)), ['episode_length', 'collisions']);

      // Files: the episodes as CSV from the server, the report as JSON, a plot as PNG and as SVG.
      assert.equal(await page.getAttribute('a:has-text("Episodes (CSV)")', 'href'), `/api/v1/runs/${state.runA}/episodes?format=csv`);
      const csv = await download(page, 'a:has-text("Episodes (CSV)")');
      assert.match(csv.bytes.toString(), /^episode,seed,/);
      assert.equal(csv.bytes.toString().trim().split('\n').length, 3, 'a header and two episodes');
      const json = await download(page, 'button:has-text("Report (JSON)")');
      assert.equal(json.name, `hrisim-${state.runA}.json`);
      assert.equal(JSON.parse(json.bytes.toString()).name, 'renamed baseline');
      const png = await download(page, 'button[aria-label="Save the plot of episode_length as PNG"]');
      assert.equal(png.name, `${state.runA}-episode_length.png`);
      assert.equal(png.bytes.subarray(1, 4).toString(), 'PNG');
      const svg = await download(page, 'button[aria-label="Save the plot of episode_length as SVG"]');
      const text = svg.bytes.toString();
      assert.match(text, /^<svg xmlns="http:\/\/www\.w3\.org\/2000\/svg"/);
      assert.match(text, />episode length</, 'its title');
      assert.equal(text.match(/<circle /g).length, 2, 'a dot per episode');
      assert.match(text, /stroke-dasharray/, 'the mean as a dashed line');
      await screenshot(page, 'runs-run-report-chosen-plots');
      // Chromium logs the faked 400.
      assert.deepEqual(tab.errors.filter((e) => !/Failed to load resource: .* 400 \(Bad Request\)/.test(e)), []);
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

  it('the list finds runs by text and tag, shows chosen metric columns, sorts by one and pages the sorted list, filters by conditions; all in the address', async () => {
    // Twelve short runs of one seed each, tagged to be found, with time limits that order their lengths.
    await Promise.all(Array.from({ length: 12 }, (_, i) => runThroughApi({ scenario: 'queue', seeds: [i], max_time: 0.5 + 0.25 * i,
      name: `paging ${i}`, tags: ['paging', i % 2 ? 'odd' : 'even'] })));
    const tab = await newPage(context.browser, context.server.port);
    const page = tab.page;
    const listed = [];
    page.on('request', (request) => { if (/\/api\/v1\/runs\?/.test(request.url())) listed.push(new URL(request.url()).searchParams); });
    const names = () => page.$$eval('.runs-table tbody .run-name .name', (cells) => cells.map((c) => c.textContent));
    const lengths = () => page.$$eval('.runs-table tbody td[data-column="episode_length.max"]', (cells) => cells.map((c) => Number(c.textContent.replace(/[^\d.]/g, ''))));
    const waitForRows = (count) => page.waitForFunction((n) => document.querySelectorAll('.runs-table tbody tr').length === n
      && !document.querySelector('.runs-list .loading'), count, WAIT);
    try {
      await tab.open('/runs?tag=paging&limit=10');
      await waitForRows(10);
      assert.equal(await page.inputValue('#filter-tag'), 'paging');
      assert.equal(await page.inputValue('#page-size'), '10');
      assert.ok((await names()).every((name) => /^paging \d+$/.test(name)));

      // A metric column, chosen on the page.
      await page.click('summary:has-text("Metric columns")');
      await page.selectOption('#column-metric', 'episode_length');
      await page.selectOption('#column-statistic', 'max');
      await page.click('button:has-text("Add the column")');
      await page.waitForSelector('.runs-table th[data-column="episode_length.max"]', WAIT);
      assert.equal((await addressQuery(page)).metrics, 'success.mean,collisions.max,time_to_goal.mean,episode_length.max');

      // Sorted by it: descending first (neither way is better), then ascending; aria-sort says which.
      const header = '.runs-table th[data-column="episode_length.max"]';
      await page.click(`${header} button`);
      await page.waitForFunction((h) => document.querySelector(h)?.getAttribute('aria-sort') === 'descending', header, WAIT);
      await page.click(`${header} button`);
      await page.waitForFunction((h) => document.querySelector(h)?.getAttribute('aria-sort') === 'ascending', header, WAIT);
      assert.equal(await page.evaluate((h) => document.activeElement === document.querySelector(`${h} button`), header), true, 'the focus stays on the heading');
      assert.equal(await page.getAttribute('.runs-table th:last-child', 'aria-sort'), 'none');
      await waitForRows(10);
      const first = await lengths();
      assert.deepEqual(first, [...first].sort((a, b) => a - b));
      assert.deepEqual(await addressQuery(page), { tag: 'paging', sort: 'episode_length.max', order: 'asc',
        metrics: 'success.mean,collisions.max,time_to_goal.mean,episode_length.max', limit: '10' });
      assert.match(await page.textContent('.sort-line'), /Sorted by episode_length\.max, lowest first/);

      // The next page of a sorted list: its cursor is an offset, in the address too.
      await page.click('button:has-text("Next page")');
      await waitForRows(2);
      assert.equal((await addressQuery(page)).cursor, '@10');
      const second = await lengths();
      assert.ok(second.every((length) => length >= first.at(-1)), `${second} after ${first}`);
      assert.equal(await page.isVisible('button:has-text("Previous page")'), true);
      await screenshot(page, 'runs-list-sorted-page-2');
      // Back: the first page again, as it was.
      await page.goBack();
      await waitForRows(10);
      assert.equal((await addressQuery(page)).cursor, undefined);
      assert.deepEqual(await lengths(), first);
      assert.equal(await page.getAttribute(header, 'aria-sort'), 'ascending');

      // Text in any case, then a tag clicked in a row.
      await page.fill('#filter-q', 'PAGING 1');
      await page.waitForFunction(() => new URLSearchParams(location.hash.split('?')[1]).get('q') === 'PAGING 1', null, WAIT);
      await waitForRows(3);
      assert.deepEqual((await names()).sort(), ['paging 1', 'paging 10', 'paging 11']);
      await page.click('.runs-table tbody button.tag:text-is("odd")');
      await page.waitForFunction(() => new URLSearchParams(location.hash.split('?')[1]).get('tag') === 'odd', null, WAIT);
      await waitForRows(2);
      assert.deepEqual((await names()).sort(), ['paging 1', 'paging 11']);
      assert.equal(await page.inputValue('#filter-tag'), 'odd');

      // Conditions: checked against the metrics before anything is asked, then applied.
      await page.click('summary:has-text("Conditions on metrics")');
      await page.fill('#where-1', 'nope.max == 1');
      await page.click('button:has-text("Add a condition")');
      await page.fill('#where-2', 'episode_length.median > 1');
      const asked = listed.length;
      await page.click('button:has-text("Apply the conditions")');
      assert.equal(await page.textContent('#where-1-error'), "unknown metric 'nope'");
      assert.match(await page.textContent('#where-2-error'), /unknown statistic 'median'/);
      assert.equal(await page.evaluate(() => document.activeElement.id), 'where-1');
      assert.equal(listed.length, asked, 'nothing asked while a condition is wrong');
      await screenshot(page, 'runs-list-conditions');
      await page.fill('#where-1', 'collisions.max == 0');
      await page.fill('#where-2', `episode_length.max > ${first[1]}`);
      await page.click('button:has-text("Apply the conditions")');
      await page.waitForFunction(() => new URLSearchParams(location.hash.split('?')[1]).has('where'), null, WAIT);
      await waitForRows(1);
      assert.deepEqual(await names(), ['paging 11']);
      assert.equal(listed.at(-1).get('where'), `collisions.max==0,episode_length.max>${first[1]}`);

      // A search with '+', '&' and '%' reaches the server as it was typed.
      await tab.open(`/runs?q=${encodeURIComponent('c++ & 100%')}`);
      await page.waitForSelector('.runs-list .message.info:has-text("No run matches.")', WAIT);
      assert.equal(await page.inputValue('#filter-q'), 'c++ & 100%');
      assert.equal(listed.at(-1).get('q'), 'c++ & 100%');

      // A link with a condition only the server can judge shows its answer.
      await tab.open('/runs?where=collisions.max==0,nope.max==1');
      await page.waitForSelector('.runs-list [role=alert]', WAIT);
      assert.match(await page.textContent('.runs-list [role=alert]'), /where: gate 'nope\.max==1': unknown metric 'nope'/);
      assert.equal(await page.inputValue('#where-2'), 'nope.max==1', 'the editor shows the conditions of the address');
      assert.deepEqual(tab.errors.filter((e) => !/Failed to load resource: .* 400 \(Bad Request\)/.test(e)), []);
    } finally {
      await tab.close();
    }
  });

  it('an episode replays from the moment its address names: the scrubber moves the agents and the plots follow it; each plot reads as a summary and a table', async () => {
    assert.ok(state.episode, 'the first test stored an episode');
    const tab = await newPage(context.browser, context.server.port);
    try {
      // A shared link opens the replay at its moment.
      await tab.open(`/episodes/${state.episode}?t=2`);
      const page = tab.page;
      await page.waitForSelector('svg.map g.map-agent[data-agent]', WAIT);
      await page.waitForSelector('.series-plot[data-series=distance_to_closest_person] .uplot', WAIT);
      assert.equal(await page.inputValue('#replay-time'), '20');
      assert.match(await page.textContent('.timeline .clock'), /^2 s of/);
      const entries = await page.evaluate(() => history.length);
      const agents = () => page.$$eval('svg.map g.map-agent[data-agent] circle', (circles) => circles.map((c) => `${c.getAttribute('cx')},${c.getAttribute('cy')}`));
      const marker = () => page.$eval('.series-plot[data-series=distance_to_closest_person] .plot-marker', (m) => parseFloat(m.style.left));
      const before = await agents();
      const markerBefore = await marker();
      await page.focus('#replay-time');
      for (let i = 0; i < 20; i++) await page.keyboard.press('ArrowRight');
      assert.equal(await page.inputValue('#replay-time'), '40');
      assert.match(await page.textContent('.timeline .clock'), /^4 s of/);
      assert.notDeepEqual(await agents(), before, 'the agents moved');
      assert.ok(await marker() > markerBefore, 'the plot cursor moved right');
      // Once the scrubber rests, the address has its moment (in place: no history entry per step).
      await page.waitForFunction(() => location.hash.endsWith('?t=4'), null, WAIT);
      assert.equal(await page.evaluate(() => history.length), entries);
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

      // The trajectory and each shown series as CSV.
      assert.equal(await page.getAttribute('a:has-text("Trajectory (CSV)")', 'href'), `/api/v1/episodes/${state.episode}/trajectory?format=csv`);
      const series = await download(page, 'a[aria-label="robot speed as CSV"]');
      assert.equal(series.name, `${state.episode}-robot_speed.csv`);
      assert.match(series.bytes.toString(), /^tick,time,robot_speed\n0,0,/);
      // The plotted series: chosen on the page, kept in the address with the moment.
      await page.click('#series-picker summary');
      await page.uncheck('#series-picker input[value=robot_speed]');
      await page.waitForFunction(() => !document.querySelector('.series-plot[data-series=robot_speed]'), null, WAIT);
      const shown = await page.$$eval('.series-plot', (plots) => plots.map((p) => p.dataset.series));
      await page.waitForFunction((names) => new URLSearchParams(location.hash.split('?')[1]).get('series') === names, shown.join(','), WAIT);
      await tab.open(`/episodes/${state.episode}?t=1.5&series=time_to_collision`);
      await page.waitForSelector('.series-plot[data-series=time_to_collision] .uplot', WAIT);
      assert.deepEqual(await page.$$eval('.series-plot', (plots) => plots.map((p) => p.dataset.series)), ['time_to_collision']);
      assert.match(await page.textContent('.timeline .clock'), /^1\.5 s of/);
      assert.equal(Number(await page.$eval('.series-plot .plot-marker', (m) => m.dataset.time)), 1.5);
      assert.deepEqual(tab.errors, []);
    } finally {
      await tab.close();
    }
  });

  it('an episode replays in 3D: a live session of it opens at the scrubber\'s moment, its slider over the whole episode, in the state the server replays', async () => {
    assert.ok(state.episode, 'the first test stored an episode');
    const tab = await newPage(context.browser, context.server.port);
    let session = null;
    try {
      await tab.open(`/episodes/${state.episode}?t=1.5`);
      const page = tab.page;
      await page.waitForSelector('#replay-time', WAIT);
      await page.click('button:has-text("Replay in 3D")');
      await page.waitForFunction(() => location.hash.startsWith('#/sessions/s'), null, WAIT);
      session = decodeURIComponent(await page.evaluate(() => location.hash.slice('#/sessions/'.length).split('?')[0]));
      const episode = (await call('GET', `/api/v1/episodes/${state.episode}`)).body;
      const dt = episode.sim_time / episode.ticks;
      const expected = Math.round(1.5 / dt);
      await page.waitForFunction((t) => Number(document.querySelector('.session-toolbar .clock')?.dataset.tick) === t, expected, WAIT);
      assert.equal(Number(await page.getAttribute('.seek-slider', 'max')), episode.ticks, 'the whole episode on the slider');
      const status = (await call('GET', `/api/v1/sessions/${session}`)).body;
      assert.equal(status.episode, state.episode);
      assert.equal(status.unwatched_grace, 30);
      assert.equal(status.tick, expected);
      // To its end: the replay reaches the stored episode's final state, bit for bit.
      await page.fill('.seek-tick', String(episode.ticks));
      await page.click('.seek button[type=submit]');
      await page.waitForFunction((t) => Number(document.querySelector('.session-toolbar .clock')?.dataset.tick) === t, episode.ticks, WAIT);
      assert.equal((await call('GET', `/api/v1/sessions/${session}`)).body.state_hash, episode.state_hash);
      await screenshot(page, 'episode-replay-3d');
      assert.deepEqual(tab.errors, []);
    } finally {
      if (session) await call('DELETE', `/api/v1/sessions/${session}`);
      await tab.close();
    }
  });

  it('an episode is filmed as a video: the server\'s refusal shows beside the form, the progress while it films, Cancel stops it, then the video plays and downloads', async () => {
    assert.ok(state.episode, 'the first test stored an episode');
    const tab = await newPage(context.browser, context.server.port);
    const page = tab.page;
    const videoRequests = [];
    page.on('request', (request) => {
      const { pathname } = new URL(request.url());
      if (/^\/api\/v1\/(videos\/|episodes\/[^/]+\/videos$)/.test(pathname)) videoRequests.push(`${request.method()} ${pathname}`);
    });
    // The server films this episode small in a fraction of a second: while `holding`, its status reads half way through.
    let holding = true;
    await page.route('**/api/v1/videos/*', async (route) => {
      if (!holding || route.request().method() !== 'GET') return route.fallback();
      const response = await route.fetch();
      const job = await response.json();
      const half = Math.round(job.progress.ticks / 2);
      return route.fulfill({ response, json: { ...job, status: 'filming', progress: { tick: half, ticks: job.progress.ticks, fraction: half / job.progress.ticks } } });
    });
    const held = [];
    try {
      const episode = (await call('GET', `/api/v1/episodes/${state.episode}`)).body;
      const cameras = (await call('GET', `/api/v1/episodes/${state.episode}/cameras`)).body.cameras;
      await tab.open(`/episodes/${state.episode}`);
      await page.click('.episode-facts button:has-text("Export video")', WAIT);
      assert.equal(await page.getAttribute('button[aria-controls=video-export]', 'aria-expanded'), 'true');
      await page.waitForSelector('#video-camera:not([disabled])', WAIT);
      assert.deepEqual(await page.$$eval('#video-camera option', (options) => options.map((o) => o.value)), cameras.map((c) => c.name));
      assert.equal(await page.inputValue('#video-camera'), 'overview');
      assert.equal(await page.inputValue('#video-fps'), '25');
      assert.equal(await page.getAttribute('#video-width', 'placeholder'), String(cameras.find((c) => c.name === 'overview').width));
      assert.deepEqual(await page.$eval('#video-width', (input) => [input.min, input.max]), ['16', '1920']);

      // A width the server refuses: its message beside the form, the field marked and focused.
      await page.fill('#video-width', '5');
      await page.click('.video-form button[type=submit]');
      await page.waitForSelector('#video-error [role=alert]', WAIT);
      assert.match(await page.textContent('#video-error'), /\/width: must be at least 16 \(got 5\)/);
      assert.equal(await page.getAttribute('#video-width', 'aria-invalid'), 'true');
      assert.equal(await page.evaluate(() => document.activeElement.id), 'video-width');
      assert.deepEqual(videoRequests, [`POST /api/v1/episodes/${state.episode}/videos`]);

      // Filming: the progress and its status, announced; Cancel stops the job and the server forgets it.
      await page.fill('#video-width', '160');
      await page.fill('#video-fps', '10');
      await page.selectOption('#video-format', 'mp4');
      await page.click('.video-form button[type=submit]');
      const half = Math.round(episode.ticks / 2);
      const filming = `Filming… 50 % (tick ${half.toLocaleString('en')} of ${episode.ticks.toLocaleString('en')})`;
      await page.waitForFunction((text) => document.querySelector('#video-status')?.textContent === text, filming, WAIT);
      assert.equal(await page.textContent('#video-error'), '', 'the last problem is gone');
      assert.equal(await page.getAttribute('#video-width', 'aria-invalid'), null);
      assert.equal(await page.isVisible('progress#video-progress'), true);
      assert.equal(await page.getAttribute('progress#video-progress', 'aria-label'), 'Filming progress');
      assert.equal(await page.$eval('progress#video-progress', (p) => p.value), 0.5);
      assert.equal(await page.getAttribute('#video-status', 'aria-live'), 'polite');
      assert.equal(await page.isDisabled('.video-form button[type=submit]'), true, 'one job at a time');
      await screenshot(page, 'runs-episode-video-filming');
      const cancelled = videoRequests.find((r) => r.startsWith('GET /api/v1/videos/')).slice('GET '.length);
      const posted = videoRequests.filter((r) => r.startsWith('POST'));
      assert.equal(posted.length, 2);
      await page.click('.video-running button:has-text("Cancel")');
      await page.waitForFunction(() => /^Cancelled/.test(document.querySelector('#video-status').textContent), null, WAIT);
      assert.ok(videoRequests.includes(`DELETE ${cancelled}`), videoRequests.join('\n'));
      assert.equal(await page.isVisible('progress#video-progress'), false);
      assert.equal((await call('GET', cancelled)).status, 404, 'the server forgot the job');

      // Again, to the end: the video plays in the page (its metadata loaded: 160 px wide), and downloads as an MP4.
      holding = false;
      await page.click('.video-form button[type=submit]');
      await page.waitForSelector('video.episode-video', WAIT);
      await page.waitForFunction(() => document.querySelector('video.episode-video').readyState >= 1, null, WAIT);
      const played = await page.$eval('video.episode-video', (video) => ({ width: video.videoWidth, duration: video.duration, error: video.error?.message ?? null }));
      assert.equal(played.width, 160);
      assert.ok(played.duration > 0, `duration ${played.duration}`);
      assert.equal(played.error, null);
      assert.match(await page.textContent('#video-status'), /^Filmed in [\d.]+ s\.$/);
      assert.match(await page.textContent('.video-file'), /MP4, H\.264, 160×120, [\d,]+ frames at 10 fps/);
      assert.equal(await page.$('.video-mismatch'), null, 'the replay matches the stored episode');
      const file = await download(page, 'a.video-download');
      assert.equal(file.name, `${state.episode}-overview.mp4`);
      assert.equal(file.bytes.subarray(4, 8).toString(), 'ftyp');
      assert.match(await page.textContent('a.video-download'), new RegExp(`\\(${Math.round(file.bytes.length / 1000)} kB\\)`));
      assert.doesNotMatch(await page.textContent('.video-result'), /null|undefined/);
      await screenshot(page, 'runs-episode-video');
      // The same options again find the same job; had its replay not ended where the stored episode did, a warning says so.
      await page.route('**/api/v1/episodes/*/videos', async (route) => {
        const response = await route.fetch();
        return route.fulfill({ response, json: { ...(await response.json()), matches_stored_episode: false } });
      });
      await page.click('.video-form button[type=submit]');
      await page.waitForSelector('.video-mismatch', WAIT);
      assert.match(await page.textContent('.video-mismatch'), /did not end in the stored episode's final state/);
      await page.unroute('**/api/v1/episodes/*/videos');

      // Leaving the page stops the polling; the job goes on on the server.
      holding = true;
      await page.fill('#video-fps', '5');
      await page.click('.video-form button[type=submit]');
      await page.waitForFunction(() => /^Filming/.test(document.querySelector('#video-status').textContent), null, WAIT);
      held.push(videoRequests.filter((r) => r.startsWith('GET /api/v1/videos/')).at(-1).slice('GET '.length));
      await page.click('.episode-facts a[href^="#/runs/"]');
      await page.waitForSelector('.run-summary', WAIT);
      const polls = videoRequests.length;
      // The page asks every 400 ms while it films.
      await new Promise((resolve) => setTimeout(resolve, 700));
      assert.equal(videoRequests.length, polls, 'no status asked after leaving the page');
      assert.equal((await call('GET', held[0])).status, 200);
      assert.deepEqual(tab.errors.filter((e) => !/Failed to load resource: .* 400 \(Bad Request\)/.test(e)), []);
    } finally {
      for (const path of held) await call('DELETE', path);
      await tab.close();
    }
  });

  it('a run merged from shards elsewhere, imported, shows its shards on its page, and which are missing', async () => {
    const { spawnSync } = require('node:child_process');
    const os = require('node:os');
    const path = require('node:path');
    const root = path.resolve(__dirname, '../../..');
    const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'hrisim-ui-shards-'));
    /** hrisim ARGS, which must exit with one of `statuses` (a merge missing shards fails its verdict: 1). */
    const hrisim = (args, statuses = [0]) => {
      const ran = spawnSync(path.resolve(process.env.HRISIM_BINARY), args, { env: { ...process.env, HRISIM_SCENARIOS: path.join(root, 'scenarios') } });
      assert.ok(statuses.includes(ran.status), `hrisim ${args.join(' ')}: exit ${ran.status}\n${ran.stderr}`);
    };
    const importDatabase = async (file) => {
      const response = await fetch(`http://127.0.0.1:${context.server.port}/api/v1/runs/import`,
        { method: 'POST', headers: { 'content-type': 'application/vnd.sqlite3' }, body: fs.readFileSync(file) });
      const text = await response.text();
      assert.equal(response.status, 200, text);
      return JSON.parse(text).runs[0].id;
    };
    const tab = await newPage(context.browser, context.server.port);
    try {
      const queue = path.join(root, 'scenarios/queue.json');
      for (const k of [1, 2, 3]) hrisim(['run', queue, '--seeds', '1-9', '--max-time', '2', '--name', 'ui shards', '--shard', `${k}/3`, '--db', path.join(dir, `shard-${k}.db`)]);
      hrisim(['merge', path.join(dir, 'shard-1.db'), path.join(dir, 'shard-3.db'), '--into', path.join(dir, 'partial.db')], [1]);
      const id = await importDatabase(path.join(dir, 'partial.db'));
      await tab.open(`/runs/${id}`);
      await tab.page.waitForSelector('.run-shards');
      assert.equal(await tab.page.textContent('.run-shards'), '2 of 3 merged (6 of 9 seeds); missing: 2');
      assert.match(await tab.page.textContent('main'), /2 of 3 shards are merged \(missing: 2\): 6 of 9 seeds/);
      await screenshot(tab.page, 'run-merged-shards');
      // The missing shard imported too: the run is whole.
      await importDatabase(path.join(dir, 'shard-2.db'));
      await tab.page.reload();
      await tab.page.waitForFunction(() => document.querySelector('.run-shards')?.textContent === '3 of 3 merged (9 of 9 seeds)');
      assert.deepEqual(tab.errors, []);
    } finally {
      await tab.close();
      fs.rmSync(dir, { recursive: true, force: true });
    }
  });

  it('three runs compare against a baseline: means, p-values with and without Holm\'s correction, distributions, failed gates; the view is in the address', async () => {
    assert.ok(state.runA, 'the first test started a run');
    const tab = await newPage(context.browser, context.server.port);
    const page = tab.page;
    try {
      const third = runThroughApi({ scenario: 'queue', seeds: [6, 7], max_time: 5, name: 'third' });
      await startRunFromForm(tab, { seeds: '3-5', gates: 'success.mean > 1\ncollisions.max >= 0', maxTime: '5' });
      await page.waitForFunction((a) => /^#\/runs\/r[0-9a-f]{32}$/.test(location.hash) && !location.hash.endsWith(a), state.runA, WAIT);
      const runB = await page.evaluate(() => location.hash.slice('#/runs/'.length));
      await page.waitForSelector('.run-summary .badge:has-text("finished")', WAIT);
      const runC = await third;
      await tab.open('/runs');
      await page.waitForSelector(`.runs-table a[href="#/runs/${runC}"]`, WAIT);
      // The chosen runs are in the address: a reload keeps them, in their order.
      for (const run of [state.runA, runB]) await page.check(`input[aria-label="Compare run ${run}"]`);
      await page.waitForFunction((ids) => new URLSearchParams(location.hash.split('?')[1]).get('compare') === ids, `${state.runA},${runB}`, WAIT);
      await page.reload();
      await page.waitForSelector(`.runs-table a[href="#/runs/${runC}"]`, WAIT);
      assert.deepEqual((await page.$$eval('.runs-table input[aria-label^="Compare run"]:checked', (boxes) => boxes.map((box) => box.getAttribute('aria-label')))).sort(),
        [state.runA, runB].map((run) => `Compare run ${run}`).sort());
      assert.match(await page.textContent('.compare-choice'), new RegExp(`Baseline ${state.runA.slice(0, 9)}, then ${runB.slice(0, 9)}\\.`));
      assert.equal(await page.isDisabled('button:has-text("Compare the chosen")'), false);
      await page.check(`input[aria-label="Compare run ${runC}"]`);
      assert.match(await page.textContent('.compare-choice'), new RegExp(`Baseline ${state.runA.slice(0, 9)}, then ${runB.slice(0, 9)}, ${runC.slice(0, 9)}`));
      await page.click('button:has-text("Compare the chosen")');
      await page.waitForFunction((hash) => location.hash === hash, `#/compare?runs=${state.runA},${runB},${runC}`, WAIT);
      await page.waitForSelector('table.comparison tbody tr[data-metric=success]', WAIT);
      // A mean per run, and for B and C: the difference, p, Holm's p and the change.
      const success = await page.$$eval('table.comparison tr[data-metric=success] td', (cells) => cells.map((c) => c.textContent));
      assert.equal(success.length, 2 + 1 + 2 * 5, success.join(' | '));
      assert.equal(await page.$$eval('table.comparison td.p-adjusted', (cells) => cells.length) > 0, true);
      const pValues = await page.$$eval('table.comparison td.p-value', (cells) => cells.map((c) => c.textContent));
      assert.ok(pValues.some((p) => /^[<\d]/.test(p)), `some p-value: ${pValues.join(' ')}`);
      assert.match(await page.textContent('.comparison-note'), /Holm-adjusted p < 0\.05 over the reply's \d+ tests/);
      await page.click('table.comparison button[aria-label^="p of C"]');
      assert.equal(await page.getAttribute('table.comparison th[aria-sort=ascending] button', 'aria-label'), 'p of C: sort by it (now ascending)');
      // A's gates passed; B failed one, shown as a chip after its verdict.
      assert.equal(await page.textContent(`table.compare-runs tr[data-run="${state.runA}"] .verdict-facts`), 'passed');
      assert.deepEqual(await page.$$eval(`table.compare-runs tr[data-run="${runB}"] .verdict-facts code.chip`, (chips) => chips.map((c) => c.textContent)), ['success.mean > 1']);
      assert.match(await page.textContent(`table.compare-runs tr[data-run="${runC}"]`), /third/);
      // The configurations side by side: the fields that differ, a value per run; the three ran the
      // queue's own controller, which the page says (their differences cannot be the controller's).
      assert.match(await page.textContent('#config-same-controller'), /same controller configuration/);
      assert.deepEqual(await page.$$eval('table.config-differences tr[data-pointer="/seeds"] td', (cells) => cells.length), 3);
      assert.equal(await page.$$eval('table.config-differences tr[data-pointer^="/effective_controller"]', (rows) => rows.length), 0);
      // Each chosen metric's distribution, a row per run, with a summary and a table.
      const distance = '.distribution-plot[data-metric=minimum_distance_to_people]';
      await page.waitForSelector(`${distance} svg`, WAIT);
      assert.equal(await page.$$eval(`${distance} svg .run-row`, (rows) => rows.length), 3);
      assert.equal(await page.$$eval(`${distance} svg circle.value`, (dots) => dots.length), 2 + 3 + 2, 'a dot per episode');
      assert.match(await page.getAttribute(`${distance} svg`, 'aria-label'), /^minimum distance to people ↑, per run: A r\w+ mean [\d.]+ m, median/);
      await page.click(`${distance} button:has-text("Show as table")`);
      assert.deepEqual(await page.$$eval(`${distance} .plot-table tbody tr`, (rows) => rows.map((r) => r.cells[1].textContent)), ['2', '3', '2']);
      // Each plot saves as SVG (standalone: the runs' dots, the page's font) and as PNG (twice the plot's size).
      const stem = `compare-${[state.runA, runB, runC].map((run) => run.slice(0, 9)).join('-')}`;
      const svgFile = await download(page, `${distance} button[aria-label="Save the plot of minimum_distance_to_people as SVG"]`);
      assert.equal(svgFile.name, `${stem}-minimum_distance_to_people.svg`);
      const parsed = await page.evaluate((text) => {
        const svg = new DOMParser().parseFromString(text, 'image/svg+xml');
        const root = svg.documentElement;
        return { root: root.localName, namespace: root.namespaceURI, errors: svg.getElementsByTagName('parsererror').length,
          dots: root.querySelectorAll('circle.value').length, font: /system-ui/.test(root.getAttribute('font-family')), title: root.querySelector('text').textContent };
      }, svgFile.bytes.toString());
      assert.deepEqual(parsed, { root: 'svg', namespace: 'http://www.w3.org/2000/svg', errors: 0, dots: 7, font: true, title: 'minimum distance to people ↑' });
      const successPlot = '.distribution-plot[data-metric=success]';
      const pngFile = await download(page, `${successPlot} button[aria-label="Save the plot of success as PNG"]`);
      assert.equal(pngFile.name, `${stem}-success.png`);
      assert.deepEqual([...pngFile.bytes.subarray(0, 8)], [0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a], 'the PNG signature');
      const size = await page.$eval(`${successPlot} svg`, (svg) => [Number(svg.getAttribute('width')), Number(svg.getAttribute('height'))]);
      assert.deepEqual([pngFile.bytes.readUInt32BE(16), pngFile.bytes.readUInt32BE(20)], size.map((n) => 2 * n), 'IHDR: twice the plot\'s size');
      // The robot's paths of the baseline and the run chosen (B first). The queue's robot stands still: points, attached but not "visible".
      await page.waitForSelector('.compare-map svg.map polyline[stroke="#d1492f"]', { ...WAIT, state: 'attached' });
      await screenshot(page, 'runs-compare');

      // Holm off, another metric plotted, C's paths: all in the address, and a link brings them back.
      await page.uncheck('#holm');
      await page.waitForFunction(() => /no correction/.test(document.querySelector('.comparison-note')?.textContent), null, WAIT);
      assert.equal(await page.$$eval('table.comparison td.p-adjusted', (cells) => cells.length), 0);
      await page.click('#plot-metrics summary');
      await page.check('#plot-metrics input[value=episode_length]');
      await page.waitForSelector('.distribution-plot[data-metric=episode_length] svg', WAIT);
      await page.selectOption('#paths-run', runC);
      await page.waitForSelector('.compare-map svg.map polyline[stroke="#2f8a4f"]', { ...WAIT, state: 'attached' });
      const view = await addressQuery(page);
      assert.deepEqual(view, { runs: `${state.runA},${runB},${runC}`, correction: 'none',
        plots: 'success,minimum_distance_to_people,time_to_goal,episode_length', paths: runC });
      await tab.open(`/compare?runs=${state.runA},${runB},${runC}&correction=none&plots=episode_length&paths=${runC}`);
      await page.waitForSelector('.distribution-plot[data-metric=episode_length] svg', WAIT);
      assert.equal(await page.isChecked('#holm'), false);
      assert.equal(await page.inputValue('#paths-run'), runC);
      assert.deepEqual(await page.$$eval('.distribution-plot', (plots) => plots.map((p) => p.dataset.metric)), ['episode_length']);

      // The former address of two runs opens the new one.
      await tab.open(`/compare/${state.runA}/${runB}`);
      await page.waitForFunction((hash) => location.hash === hash, `#/compare?runs=${state.runA},${runB}`, WAIT);
      await page.waitForSelector('.distribution-plot svg', WAIT);

      await page.setViewportSize({ width: 800, height: 800 });
      await assertNoSidewaysScroll(page, 'the comparison');
      assert.ok(await page.$eval('.table-scroll:has(table.comparison)', (box) => box.scrollWidth > box.clientWidth), 'the metrics table scrolls in its box');
      assert.ok(await page.$eval('.distribution-plot svg', (svg) => svg.getBoundingClientRect().width >= 700), 'a distribution plot is readable at 800 px');
      await screenshot(page, 'runs-compare-800px');
      await tab.open(`/runs/${runB}`);
      await page.waitForSelector('table.episodes', WAIT);
      await assertNoSidewaysScroll(page, 'the run report');
      await screenshot(page, 'runs-run-report-800px');
      await tab.open('/runs');
      await page.waitForSelector('table.runs-table', WAIT);
      await assertNoSidewaysScroll(page, 'the runs list');
      await screenshot(page, 'runs-list-800px');
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
      await page.waitForSelector('#run-goal option[value=kitchen]', { ...WAIT, state: 'attached' });
      assert.equal(await page.inputValue('#run-goal'), '', 'the scenario\'s own goal by default');
      assert.match(await page.$eval('#run-goal', (select) => select.selectedOptions[0].textContent), /the scenario's own: living_room, within 0.3 m/);
      await page.selectOption('#run-controller', 'goal');
      await page.waitForSelector('#run-goal option[value=kitchen]', { ...WAIT, state: 'attached' });
      await page.selectOption('#run-goal', 'kitchen');
      await page.fill('#run-count', '2');
      await page.fill('#run-max-time', '20');
      await page.click('.run-form button[type=submit]');
      await page.waitForFunction((a) => /^#\/runs\/r[0-9a-f]{32}$/.test(location.hash) && !location.hash.endsWith(a), state.runA, WAIT);
      const runC = await page.evaluate(() => location.hash.slice('#/runs/'.length));
      await page.waitForSelector('.run-summary .badge:has-text("finished")', WAIT);
      assert.match(await page.textContent('.run-summary .run-controller'), /^goal; goal location kitchen, radius 0\.3 m$/);
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

'use strict';
// The scenario catalogue and a scenario's page: a card per scenario with its thumbnail, searching and
// filtering, the elevator's map (labels that do not overlap, a true scale bar) and timeline, a benchmark
// task's settings in words, uploads whose errors appear at the lines they concern, the same content
// uploaded again, deleting uploads, and starting a live session from a scenario.
const assert = require('node:assert/strict');
const path = require('node:path');
const { describe, it } = require('node:test');
const context = require('../lib/context');
const { newPage, screenshot } = require('../lib/browser');

const BUNDLED = ['apartment', 'apartment_search', 'approach_human', 'approach_human_apartment', 'circle_crossing', 'conversation_group', 'corridor_navigation', 'corridor_passing', 'crossing_navigation', 'elevator', 'family_day',
  'follow_human', 'mirror_gesture', 'pair_walking', 'perpendicular_crossing', 'pick_and_place', 'queue', 'tea_break'];

// A small valid scenario, pretty-printed so that its errors have lines of their own.
function roomScenario(name, extraAction = null) {
  const actions = [{ agent: 'ana', goto: { location: 'door' } }];
  if (extraAction) actions.push(extraAction);
  return JSON.stringify({
    name,
    description: 'A small room for the UI tests.',
    time_limit: 30,
    world: {
      bounds: { min: [0, 0], max: [6, 4] },
      walls: [{ from: [0, 0], to: [6, 0] }, { from: [6, 0], to: [6, 4] }, { from: [6, 4], to: [0, 4] }, { from: [0, 4], to: [0, 0] }],
    },
    locations: { door: { x: 5, y: 2, theta: 0 } },
    humans: [{ id: 'ana', start: { x: 1, y: 2, theta: 0 } }],
    steps: [{ name: 'leave', actions }],
  }, null, 2);
}

const lineOf = (text, fragment) => text.split('\n').findIndex((line) => line.includes(fragment)) + 1;

/** Pairs of the map's labels whose boxes overlap, as "a/b". */
function overlappingLabels(page) {
  return page.$$eval('svg.map text.map-label', (texts) => {
    const boxes = texts.map((text) => ({ name: text.textContent, box: text.getBoundingClientRect() }));
    const pairs = [];
    boxes.forEach((a, i) => boxes.slice(i + 1).forEach((b) => {
      if (a.box.left < b.box.right && b.box.left < a.box.right && a.box.top < b.box.bottom && b.box.top < a.box.bottom) pairs.push(`${a.name}/${b.name}`);
    }));
    return pairs;
  });
}

async function serverGet(path) {
  const reply = await fetch(`http://127.0.0.1:${context.server.port}${path}`);
  return { status: reply.status, json: await reply.json() };
}

describe('scenarios', () => {
  it('the catalogue shows a card per scenario with its thumbnail, and searching and filters narrow it', async () => {
    const tab = await newPage(context.browser, context.server.port);
    try {
      await tab.open('/');
      await tab.page.waitForSelector('.sc-scenario-card');
      const ids = await tab.page.$$eval('.sc-scenario-card', (cards) => cards.map((card) => card.dataset.id));
      for (const id of BUNDLED) assert.ok(ids.includes(id), `a card for ${id}: ${ids.join(', ')}`);
      const bundled = await tab.page.$$eval('.sc-scenario-card', (cards) => cards.filter((card) => card.querySelector('.badge').textContent === 'bundled').length);
      assert.equal(bundled, BUNDLED.length);
      // Lazy thumbnails load once scrolled to; each is a real picture.
      for (const image of await tab.page.$$('.sc-scenario-card img')) await image.scrollIntoViewIfNeeded();
      await tab.page.waitForFunction(() => [...document.querySelectorAll('.sc-scenario-card img')].every((image) => image.complete && image.naturalWidth > 0),
        null, { timeout: 20000 });
      const elevator = await tab.page.textContent('.sc-scenario-card[data-id=elevator]');
      assert.match(elevator, /Humans\s*6/);
      assert.match(elevator, /robot \(hsr\)/);
      assert.match(elevator, /240 s/);
      await tab.page.evaluate(() => window.scrollTo(0, 0));
      await screenshot(tab.page, 'scenarios-catalogue');

      // Search by name, by keyboard; Tab goes on to the filters.
      await tab.page.focus('#scenario-search');
      await tab.page.keyboard.type('elev');
      assert.deepEqual(await tab.page.$$eval('.sc-scenario-card:not([hidden])', (cards) => cards.map((card) => card.dataset.id)), ['elevator']);
      assert.equal(await tab.page.textContent('.sc-scenario-count'), `1 of ${ids.length} scenarios`);
      await tab.page.keyboard.press('Tab');
      assert.equal(await tab.page.evaluate(() => document.activeElement.id), 'scenario-origin');
      await tab.page.fill('#scenario-search', '');
      await tab.page.selectOption('#scenario-robot', 'model');
      assert.deepEqual(await tab.page.$$eval('.sc-scenario-card:not([hidden])', (cards) => cards.map((card) => card.dataset.id)),
        ['apartment', 'apartment_search', 'approach_human', 'approach_human_apartment', 'circle_crossing', 'corridor_navigation', 'crossing_navigation', 'elevator', 'family_day', 'follow_human',
          'mirror_gesture', 'pick_and_place', 'tea_break']);
      await tab.page.selectOption('#scenario-robot', 'no');
      assert.deepEqual(await tab.page.$$eval('.sc-scenario-card:not([hidden])', (cards) => cards.map((card) => card.dataset.id)), ['perpendicular_crossing']);
      await tab.page.selectOption('#scenario-robot', '');
      await tab.page.fill('#scenario-min-humans', '5');
      await tab.page.fill('#scenario-max-humans', '5');
      assert.deepEqual(await tab.page.$$eval('.sc-scenario-card:not([hidden])', (cards) => cards.map((card) => card.dataset.id)), ['circle_crossing', 'queue']);
      await tab.page.fill('#scenario-min-humans', '7');
      await tab.page.fill('#scenario-max-humans', '');
      assert.equal(await tab.page.isVisible('text=No scenario matches these filters.'), true);
      // A card opens its scenario.
      await tab.page.fill('#scenario-min-humans', '');
      await tab.page.click('.sc-scenario-card[data-id=queue] .sc-card-link');
      await tab.page.waitForFunction(() => location.hash === '#/scenarios/queue');
      assert.deepEqual(tab.errors, []);
    } finally {
      await tab.close();
    }
  });

  it('the JSON pointer resolver finds the line of keys, array elements and escaped names; an unknown scenario says so', async () => {
    const tab = await newPage(context.browser, context.server.port);
    try {
      await tab.open('/');
      const lines = await tab.page.evaluate(async () => {
        const { jsonPointerLines } = await import('/pages/scenarios.js');
        const text = '{\n  "a": [\n    1,\n    {"b/c": "x\\"y",\n     "d~e": [[], {}]}\n  ],\n  "f": {\n  }\n';  // unterminated: tolerated
        return Object.fromEntries(jsonPointerLines(text));
      });
      assert.deepEqual(lines, { '': 1, '/a': 2, '/a/0': 3, '/a/1': 4, '/a/1/b~1c': 4, '/a/1/d~0e': 5, '/a/1/d~0e/0': 5, '/a/1/d~0e/1': 5, '/f': 7 });
      assert.deepEqual(tab.errors, []);
      // An unknown scenario says so in the page.
      await tab.open('/scenarios/no_such_scenario');
      await tab.page.waitForSelector('[role=alert]');
      assert.match(await tab.page.textContent('[role=alert]'), /no_such_scenario/);
    } finally {
      await tab.close();
    }
  });

  it('the elevator page shows its facts, its map with obstacles and a timeline row per agent', async () => {
    const tab = await newPage(context.browser, context.server.port);
    try {
      await tab.open('/scenarios/elevator');
      await tab.page.waitForSelector('svg.map polygon');
      assert.equal(await tab.page.textContent('h1'), 'elevator');
      assert.ok(await tab.page.$$eval('svg.map polygon', (polygons) => polygons.length) >= 12, 'walls and tables');
      assert.match(await tab.page.textContent('svg.map'), /button_floor1/);
      assert.match(await tab.page.textContent('.sc-facts'), /240 s/);
      const rows = await tab.page.$$eval('table.sc-timeline tbody tr', (trs) => trs.map((tr) => tr.dataset.agent));
      assert.deepEqual(rows, ['ada', 'ben', 'cleo', 'dev', 'eli', 'fay', 'robot']);
      const steps = await tab.page.$$eval('table.sc-timeline thead th', (ths) => ths.slice(1).map((th) => th.textContent));
      assert.deepEqual(steps, ['1. gather', '2. ride_up', '3. swap', '4. ride_down', '5. afterwards', '6. ride_back']);
      const eliSwap = await tab.page.textContent('tr[data-agent=eli] td:nth-of-type(3)');
      assert.match(eliSwap, /wait 4 s.*goto cabin/);
      assert.match(await tab.page.textContent('tr[data-agent=ada] td:nth-of-type(1)'), /routine call_up.*goto button_floor1/);
      assert.equal(await tab.page.getAttribute('a:has-text("Run in batch")', 'href'), '#/runs?scenario=elevator');
      // Queues and buttons of both floors sit close together: their labels make room for each other.
      assert.deepEqual(await overlappingLabels(tab.page), []);
      assert.match(await tab.page.textContent('svg.map'), /queue_floor1.*button_floor1|button_floor1.*queue_floor1/);
      // The scale bar's length in pixels per metre is the map's: as far apart as two locations are drawn.
      const world = (await serverGet('/api/v1/scenarios/elevator/world')).json;
      const [a, b] = ['centre_floor1', 'printer_floor1'].map((name) => world.locations.find((l) => l.name === name));
      const drawn = await tab.page.$$eval('svg.map circle', (circles, names) => names.map((name) => Number(circles.find((c) => c.querySelector('title')?.textContent === `location ${name}`).getAttribute('cx'))),
        [a.name, b.name]);
      const pixelsPerMetre = (drawn[1] - drawn[0]) / (b.x - a.x);
      const bar = await tab.page.$eval('svg.map g.map-scale', (g) => ({ metres: Number(g.dataset.metres), width: g.querySelector('.map-scale-bar').getBBox().width, text: g.textContent }));
      assert.equal(bar.text, `${bar.metres} m`);
      assert.ok(Math.abs(bar.width / bar.metres - pixelsPerMetre) < 0.01 * pixelsPerMetre, `bar ${bar.width} px for ${bar.metres} m; the map ${pixelsPerMetre} px/m`);
      await screenshot(tab.page, 'scenario-elevator');
      assert.deepEqual(tab.errors, []);
    } finally {
      await tab.close();
    }
  });

  it('a benchmark task reads as its name, what it asks and the settings the scenario gives', async () => {
    const tab = await newPage(context.browser, context.server.port);
    try {
      await tab.open('/scenarios/pick_and_place');
      await tab.page.waitForSelector('.sc-facts');
      const task = async () => tab.page.$eval('.sc-facts dt:text-is("Task") + dd', (dd) => dd.textContent);
      assert.doesNotMatch(await task(), /object Object/);
      assert.match(await task(), /^pick_and_place: pick up an object and put it on a target/);
      assert.deepEqual(await tab.page.$$eval('.task-settings li', (items) => items.map((item) => item.textContent)),
        ['object cup', 'penalised 16 (cuttingboard, cheese01, cheese02, …)', 'target (0, 0.68, 0.45) m']);
      // Its movable objects on the map, in the legend and listed, as the world gives them.
      const { objects } = (await serverGet('/api/v1/scenarios/pick_and_place/world')).json;
      assert.ok(objects.some((object) => object.name === 'cup'), 'the cup is among them');
      assert.deepEqual(await tab.page.$$eval('svg.map .map-object title', (titles) => titles.map((title) => title.textContent)),
        objects.map((object) => `object ${object.name} (${object.shape.kind})`));
      const cup = await tab.page.$eval('svg.map .map-object:has(title:text-is("object cup (cylinder)"))', (mark) => [Number(mark.getAttribute('cx')), Number(mark.getAttribute('cy'))]);
      const robot = await tab.page.$eval('svg.map .map-agent.robot circle', (mark) => [Number(mark.getAttribute('cx')), Number(mark.getAttribute('cy'))]);
      assert.ok(cup[0] > robot[0] + 10 && Math.abs(cup[1] - robot[1]) < 1, `the cup 0.68 m ahead of the robot: ${cup} and ${robot}`);
      assert.match(await tab.page.textContent('.sc-map-legend'), /movable object at its start/);
      assert.match(await tab.page.textContent('.sc-world-table:has(caption:text-is("Movable objects at their start")) tr:has-text("cuttingboard")'),
        /cuttingboard\s*box 0\.3 × 0\.2 × 0\.02 m\s*1\s*0\.22\s*0\.41\s*0\.5/);
      await screenshot(tab.page, 'scenario-pick-and-place');
      await tab.open('/scenarios/approach_human_apartment');
      await tab.page.waitForSelector('.task-settings');
      assert.match(await tab.page.textContent('.task-settings li[data-setting=spawn]'), /^spawn \[-4, -3\] to \[4, 3\] m$/);
      await tab.open('/scenarios/mirror_gesture');
      await tab.page.waitForSelector('.sc-facts');
      assert.match(await task(), /^mirror_gesture: point to the side .* \(every setting its default/);
      assert.deepEqual(tab.errors, []);
    } finally {
      await tab.close();
    }
  });

  it('an invalid upload shows each error at its line: JSON by pointer, IMHuS XML by line', async () => {
    const tab = await newPage(context.browser, context.server.port);
    try {
      await tab.open('/');
      await tab.page.click('.sc-upload-panel summary');
      const json = roomScenario('ui broken room', { agent: 'nobody', wait: { duration: 2 } });
      await tab.page.fill('#upload-text', json);
      await tab.page.click('button:has-text("Upload")');
      await tab.page.waitForSelector('.sc-source-note.error');
      const line = lineOf(json, '"agent": "nobody"');
      const note = await tab.page.$(`.sc-source-note.error[data-line="${line}"]`);
      assert.ok(note, `an error note at line ${line}`);
      assert.match(await note.textContent(), /Error at \/steps\/0\/actions\/1\/agent: unknown agent 'nobody'/);
      // The note sits right under its line.
      assert.equal(await note.evaluate((element) => element.previousElementSibling.dataset.line), String(line));
      assert.match(await tab.page.textContent('.sc-issue-list'), /\/steps\/0\/actions\/1\/agent/);
      await screenshot(tab.page, 'scenarios-upload-json-errors');

      // IMHuS XML from a file: a pose that does not exist, at line 5.
      const xml = ['<?xml version="1.0"?>', '<map_name name="elevator"/>', '<agents><human id="ann"/></agents>',
        '<poses><pose><pose id="start" x="4" y="-3" theta="0"/></pose></poses>',
        '<goals><scenarios><walk><initialisation><goto_action entityID="ann" poseID="start"/></initialisation>',
        '<go>', '<goto_action entityID="ann" poseID="nowhere"/>', '</go></walk></scenarios></goals>'].join('\n');
      await tab.page.setInputFiles('#upload-file', { name: 'broken.xml', mimeType: 'application/xml', buffer: Buffer.from(xml) });
      await tab.page.waitForFunction(() => document.querySelector('#upload-text').value.startsWith('<?xml'));
      await tab.page.click('button:has-text("Validate only")');
      await tab.page.waitForSelector('.sc-source-note.error[data-line="7"]');
      assert.match(await tab.page.textContent('.sc-source-note.error[data-line="7"]'), /Error: <goto_action>: unknown pose 'nowhere'/);
      await tab.page.click('.sc-issue-list button:has-text("line 7")');
      assert.equal(await tab.page.evaluate(() => document.activeElement.dataset.line), '7');
      await screenshot(tab.page, 'scenarios-upload-xml-errors');

      // Malformed XML, uploaded: the server's words and line, nothing of the parser's own.
      await tab.page.fill('#upload-text', ['<?xml version="1.0"?>', '<map_name name="elevator"/>', '<agents><human id="ann"/>', '</agentz>'].join('\n'));
      await tab.page.click('button:has-text("Upload")');
      await tab.page.waitForSelector('.sc-source-note.error[data-line="3"]');
      assert.equal(await tab.page.textContent('.sc-source-note.error[data-line="3"]'),
        'Error: malformed XML: <agents> opened at line 3 is never closed (</agentz> at line 4 comes first)');
      assert.match(await tab.page.textContent('.sc-upload-result [role=alert]'), /^Not stored: 1 error in the IMHuS XML scenario/);
      assert.deepEqual(tab.errors.filter((error) => !/status of 400/.test(error)), []);
    } finally {
      await tab.close();
    }
  });

  it('a valid upload opens as a new scenario and appears in the catalogue', async () => {
    const tab = await newPage(context.browser, context.server.port);
    try {
      await tab.open('/');
      await tab.page.click('.sc-upload-panel summary');
      await tab.page.fill('#upload-text', roomScenario('ui test room'));
      await tab.page.click('button:has-text("Validate only")');
      await tab.page.waitForSelector('text=/Valid JSON: “ui test room”/');
      await tab.page.click('button:has-text("Upload")');
      await tab.page.waitForFunction(() => /^#\/scenarios\/u[0-9a-f]{32}$/.test(location.hash));
      await tab.page.waitForSelector('table.sc-timeline');
      assert.match(await tab.page.textContent('[role=status]'), /Uploaded and stored as u[0-9a-f]{32}/);
      assert.equal(await tab.page.textContent('h1'), 'ui test room');
      const id = (await tab.page.evaluate(() => location.hash)).split('/')[2];
      await screenshot(tab.page, 'scenario-uploaded');
      await tab.open('/');
      await tab.page.fill('#scenario-search', 'ui test room');
      await tab.page.waitForSelector(`.sc-scenario-card[data-id="${id}"] img`);
      assert.match(await tab.page.textContent(`.sc-scenario-card[data-id="${id}"]`), /uploaded/);

      // An IMHuS file, imported: its steps and agents read as the native ones do.
      await tab.page.click('.sc-upload-panel summary');
      await tab.page.setInputFiles('#upload-file', path.join(__dirname, '../../fixtures/imhus/office.xml'));
      await tab.page.waitForFunction(() => document.querySelector('#upload-text').value.startsWith('<?xml'));
      await tab.page.selectOption('#upload-format', 'imhus');
      await tab.page.click('button:has-text("Upload")');
      await tab.page.waitForFunction((before) => /^#\/scenarios\/u/.test(location.hash) && location.hash !== before, `#/scenarios/${id}`);
      await tab.page.waitForSelector('table.sc-timeline');
      const agents = await tab.page.$$eval('table.sc-timeline tbody tr', (trs) => trs.map((tr) => tr.dataset.agent));
      assert.deepEqual(agents, ['ann', 'bo', 'cy', 'pepper']);
      await screenshot(tab.page, 'scenario-imported-imhus');
      assert.deepEqual(tab.errors, []);
    } finally {
      await tab.close();
    }
  });

  it('the same content uploaded again is the earlier upload; an upload is deleted from its card or its page, after asking', async () => {
    const api = (method, path, body) => fetch(`http://127.0.0.1:${context.server.port}${path}`, { method, body,
      headers: body ? { 'content-type': 'application/json' } : {} });
    const text = roomScenario('ui room to delete');
    const first = await (await api('POST', '/api/v1/scenarios', text)).json();
    const other = await (await api('POST', '/api/v1/scenarios', roomScenario('ui room deleted from its page'))).json();
    const { id } = first.summary;
    const tab = await newPage(context.browser, context.server.port);
    const page = tab.page;
    try {
      // Uploaded again from the page: no new upload, the earlier one opens and says so.
      await tab.open('/');
      await page.click('.sc-upload-panel summary');
      await page.fill('#upload-text', text);
      await page.click('button:has-text("Upload")');
      await page.waitForFunction((want) => location.hash === `#/scenarios/${want}`, id);
      await page.waitForSelector('table.sc-timeline, .sc-scenario-top');
      assert.equal(await page.textContent('main [role=status]'), `Already uploaded: this is ${id}, stored before with the same content; nothing new was stored.`);

      // From its card: declined, it stays; accepted, it leaves the catalogue, which says what that means.
      await tab.open('/');
      await page.waitForSelector(`.sc-scenario-card[data-id="${id}"]`);
      const uploaded = await page.$$eval('.sc-scenario-card', (cards) => cards.filter((card) => card.querySelector('.badge').textContent === 'uploaded').map((card) => card.dataset.id));
      assert.deepEqual(await page.$$eval('.sc-scenario-card:has(.sc-card-delete)', (cards) => cards.map((card) => card.dataset.id)), uploaded, 'only uploads can be deleted');
      page.once('dialog', (dialog) => dialog.dismiss());
      await page.click(`.sc-scenario-card[data-id="${id}"] .sc-card-delete`);
      await page.waitForTimeout(300);
      assert.equal((await api('GET', `/api/v1/scenarios/${id}`)).status, 200);
      await page.evaluate(() => window.scrollTo(0, 0));
      page.once('dialog', (dialog) => {
        assert.equal(dialog.message(), `Delete the uploaded scenario “ui room to delete” (${id})?`);
        dialog.accept();
      });
      await page.click(`.sc-scenario-card[data-id="${id}"] .sc-card-delete`);
      await page.waitForSelector(`.sc-scenario-card[data-id="${id}"]`, { state: 'detached' });
      const deleted = 'Deleted “ui room to delete”.';
      assert.equal(await page.textContent('.sc-notice [role=status]'), deleted);
      assert.match(await page.textContent('.sc-scenario-count'), new RegExp(`of ${uploaded.length + BUNDLED.length - 1} scenarios`));
      await screenshot(page, 'scenarios-upload-deleted');
      assert.equal((await api('GET', `/api/v1/scenarios/${id}`)).status, 404, 'no run ran it: gone');

      // From its own page, after a run ran it: only unlisted, and the catalogue says why.
      const run = await (await api('POST', '/api/v1/runs', JSON.stringify({ scenario: other.summary.id, seeds: [1], max_time: 1 }))).json();
      for (let tries = 0; (await (await api('GET', `/api/v1/runs/${run.id}`)).json()).status !== 'finished'; tries++) {
        assert.ok(tries < 400, `run ${run.id} did not finish`);
        await page.waitForTimeout(50);
      }
      await tab.open(`/scenarios/${other.summary.id}`);
      page.once('dialog', (dialog) => dialog.accept());
      await page.click('button:has-text("Delete this upload")');
      await page.waitForFunction(() => location.hash === '#/');
      await page.waitForSelector('.sc-scenario-card');
      assert.equal(await page.textContent('.sc-notice [role=status]'), '“ui room deleted from its page” is no longer listed. Runs used it, '
        + 'so it is kept for their reports and replays; uploading it again lists it again.');
      assert.equal((await api('GET', `/api/v1/scenarios/${other.summary.id}`)).status, 200, 'kept for the run');
      assert.equal(await page.$(`.sc-scenario-card[data-id="${other.summary.id}"]`), null);
      assert.deepEqual(tab.errors, []);
    } finally {
      await tab.close();
      for (const upload of [id, other.summary.id]) await api('DELETE', `/api/v1/scenarios/${upload}`);
    }
  });

  it('starting a live session from a scenario opens the session; a refused one says why next to the form', async () => {
    const tab = await newPage(context.browser, context.server.port);
    let session = null;
    try {
      await tab.open('/scenarios/elevator');
      await tab.page.waitForSelector('#session-controller');
      assert.equal(await tab.page.textContent('.sc-session-note'), 'It ends 30 s after its last tab closes; the Sessions page lists the live ones.');
      // A seed out of range is named beside the seed.
      await tab.page.fill('#session-seed', '-1');
      await tab.page.click('button:has-text("Start live session")');
      await tab.page.waitForSelector('#session-seed-error:not(:empty)');
      assert.equal(await tab.page.getAttribute('#session-seed', 'aria-invalid'), 'true');
      assert.deepEqual(tab.errors.filter((error) => !/status of 400/.test(error)), []);
      tab.errors.length = 0;
      await tab.page.fill('#session-seed', '7');
      await tab.page.selectOption('#session-controller', 'social');
      await tab.page.selectOption('#session-goal', 'centre_floor1');
      await tab.page.click('button:has-text("Start live session")');
      await tab.page.waitForFunction(() => /^#\/sessions\/s[0-9a-f]+$/.test(location.hash));
      session = (await tab.page.evaluate(() => location.hash)).split('/')[2];
      const status = await serverGet(`/api/v1/sessions/${session}`);
      assert.equal(status.status, 200);
      assert.equal(status.json.scenario, 'elevator');
      assert.equal(status.json.seed, 7);
      assert.deepEqual(status.json.controller, { type: 'social', goal: { location: 'centre_floor1' } });
      // A closed tab's session goes: the page asks for an unwatched grace, and says so by its button.
      assert.equal(status.json.unwatched_grace, 30);
    } finally {
      await tab.close();
      if (session) await fetch(`http://127.0.0.1:${context.server.port}/api/v1/sessions/${session}`, { method: 'DELETE' });
    }
  });
});

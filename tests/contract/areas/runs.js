'use strict';
// Runs: batches of headless episodes (start, list, report, cancel, episodes, JUnit), the stored
// episodes with their trajectories, the metric list, and a run a dying server leaves interrupted.
// Runs of the bundled queue scenario take a few milliseconds per episode; the elevator's 200 seeds
// keep the executor busy long enough to cancel them.
const assert = require('node:assert/strict');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { describe, it, before } = require('node:test');
const { api, Client } = require('../lib/client');
const { specAllows } = require('../lib/contract');
const { cupOnASideTable } = require('../lib/fixtures');
const { startServer } = require('../lib/server');

const FINAL = ['finished', 'failed', 'cancelled', 'interrupted'];
const RUN_LIMIT_MS = 60000;
const UNKNOWN_RUN = `r${'0'.repeat(32)}`;
const UNKNOWN_EPISODE = `e${'0'.repeat(32)}`;

const sleep = (ms) => new Promise((resolve) => { setTimeout(resolve, ms); });

/** Polls a run's report until its status is final (or `until` says so); resolves to the report. */
async function waitForRun(id, { client = api, until = (report) => FINAL.includes(report.status) } = {}) {
  const deadline = Date.now() + RUN_LIMIT_MS;
  for (;;) {
    const reply = await client.get(`/api/v1/runs/${id}`);
    assert.equal(reply.status, 200, reply.body);
    if (until(reply.json)) return reply.json;
    if (Date.now() > deadline) assert.fail(`run ${id} still ${reply.json.status} after ${RUN_LIMIT_MS} ms: ${JSON.stringify(reply.json.progress)}`);
    await sleep(50);
  }
}

/** Starts a run; resolves to the 201 reply. */
async function startRun(request, client = api) {
  const reply = await client.post('/api/v1/runs', request);
  assert.equal(reply.status, 201, reply.body);
  return reply;
}

describe('runs', () => {
  let metricKeys;
  // Seeds 0, 1 and 2 of the queue with a gate that passes and one that cannot.
  const gates = ['episode_length.count == 3', 'collisions.max < 0'];
  let created;
  let report;
  before(async () => {
    metricKeys = (await api.get('/api/v1/metrics')).json.items.map((metric) => metric.key);
    created = await startRun({ scenario: 'queue', count: 3, gates });
    report = await waitForRun(created.json.id);
  });

  it('GET /api/v1/metrics: every metric once, with unit, category and which way is better', async () => {
    const reply = await api.get('/api/v1/metrics');
    assert.equal(reply.status, 200);
    const keys = reply.json.items.map((metric) => metric.key);
    assert.equal(new Set(keys).size, keys.length, 'keys are unique');
    assert.equal(keys[0], 'success');
    for (const key of ['collisions', 'minimum_distance_to_people', 'path_length', 'requests_sent', 'episode_length']) {
      assert.ok(keys.includes(key), key);
    }
    const success = reply.json.items[0];
    assert.equal(success.unit, 'bool');
    assert.equal(success.better, 'higher');
  });

  it('POST /api/v1/runs: 201 with Location; the report lists the seeds in order', async () => {
    const { json } = created;
    assert.match(json.id, /^r[0-9a-f]{32}$/);
    assert.equal(created.headers.location, `/api/v1/runs/${json.id}`);
    assert.equal(json.scenario, 'queue');
    assert.equal(json.controller, 'scenario');
    assert.deepEqual(json.config.seeds, [0, 1, 2]);
    assert.deepEqual(json.config.gates, gates);
    assert.equal(json.progress.total, 3);
    assert.deepEqual(json.episodes.map((episode) => episode.seed), [0, 1, 2]);
    const version = (await api.get('/api/v1/version')).json;
    assert.equal(json.config.hrisim_version, version.version);
  });

  it('GET /api/v1/runs/{id}: a finished run stores every seed and aggregates every metric', async () => {
    assert.equal(report.status, 'finished');
    assert.ok(report.finished_at >= report.created_at);
    assert.deepEqual(report.progress, { total: 3, finished: 3, error: 0, running: 0, queued: 0, cancelled: 0, interrupted: 0 });
    assert.ok(report.episodes.every((episode) => episode.status === 'finished' && episode.termination === 'scenario_end'));
    assert.match(report.scenario_record, /^b[0-9a-f]{32}$/);
    assert.deepEqual(Object.keys(report.aggregates).sort(), [...metricKeys].sort());
    const length = report.aggregates.episode_length;
    assert.equal(length.count + length.nulls, 3);
    assert.ok(length.min <= length.mean && length.mean <= length.max);
    assert.ok(length.ci95_low <= length.mean && length.mean <= length.ci95_high);
    assert.ok(report.rates.success_rate >= 0 && report.rates.success_rate <= 1);
  });

  it('GET /api/v1/runs/{id}: the verdict fails with the failing gate as its reason', () => {
    const { verdict } = report;
    assert.equal(verdict.complete, true);
    assert.equal(verdict.passed, false);
    assert.deepEqual(verdict.gates.map((gate) => [gate.gate, gate.metric, gate.statistic, gate.op, gate.threshold, gate.actual, gate.passed]),
      [['episode_length.count == 3', 'episode_length', 'count', '==', 3, 3, true],
        ['collisions.max < 0', 'collisions', 'max', '<', 0, report.aggregates.collisions.max, false]]);
    assert.equal(verdict.reasons.length, 1);
    assert.match(verdict.reasons[0], /collisions\.max < 0/);
  });

  it('GET /api/v1/runs/{id}: passes with every gate passing; explicit seeds keep their order', async () => {
    const run = await startRun({ scenario: 'queue', seeds: [9, 5], gates: ['episode_length.count==2', ' success.max <= 1 '] });
    const done = await waitForRun(run.json.id);
    assert.deepEqual(done.episodes.map((episode) => episode.seed), [9, 5]);
    assert.deepEqual(done.verdict, {
      passed: true, complete: true, reasons: [],
      gates: [
        { gate: 'episode_length.count==2', metric: 'episode_length', statistic: 'count', op: '==', threshold: 2, actual: 2, passed: true },
        { gate: 'success.max <= 1', metric: 'success', statistic: 'max', op: '<=', threshold: 1, actual: done.aggregates.success.max, passed: true },
      ],
    });
  });

  it('POST /api/v1/runs: an uploaded scenario with another controller and a time limit', async () => {
    const uploaded = await api.post('/api/v1/scenarios', cupOnASideTable);
    assert.equal(uploaded.status, 201);
    const scenario = uploaded.json.summary.id;
    const run = await startRun({ scenario, count: 1, first_seed: 4, controller: { type: 'idle' }, max_time: 2 });
    assert.equal(run.json.controller, 'idle');
    assert.equal(run.json.scenario_record, scenario);
    assert.equal(run.json.config.scenario_sha256, uploaded.json.summary.sha256);
    const done = await waitForRun(run.json.id);
    assert.equal(done.status, 'finished');
    assert.equal(done.episodes[0].seed, 4);
    assert.equal(done.episodes[0].termination, 'timeout');
    assert.ok(Math.abs(done.episodes[0].sim_time - 2) < 0.05, String(done.episodes[0].sim_time));
    const listed = await api.get(`/api/v1/runs?scenario=${scenario}`);
    assert.deepEqual(listed.json.items.map((item) => item.id), [run.json.id]);
  });

  it('POST /api/v1/runs: requests make the robot ask at the given times', async () => {
    const plain = await waitForRun((await startRun({ scenario: 'queue', seeds: [0] })).json.id);
    const asking = await waitForRun((await startRun({ scenario: 'queue', seeds: [0], requests: [{ time: 1, task: 'help_robot' }] })).json.id);
    assert.deepEqual(asking.config.requests, [{ time: 1, task: 'help_robot' }]);
    assert.equal(asking.aggregates.requests_sent.mean, plain.aggregates.requests_sent.mean + 1);
  });

  it('POST /api/v1/runs: 404 for an unknown scenario', async () => {
    const reply = await api.post('/api/v1/runs', { scenario: 'atlantis', count: 1 });
    assert.equal(reply.status, 404);
    assert.equal(reply.json.error.code, 'not_found');
    assert.equal(reply.json.error.details.pointer, '/scenario');
  });

  it('POST /api/v1/runs: 400 naming the wrong field, storing nothing', async () => {
    const before = (await api.get('/api/v1/runs?limit=100')).json.items.length;
    const cases = [
      [{ count: 1 }, '/scenario'],
      [{ scenario: 'queue' }, '/seeds'],
      [{ scenario: 'queue', count: 1, seeds: [1] }, '/seeds'],
      [{ scenario: 'queue', seeds: [] }, '/seeds'],
      [{ scenario: 'queue', seeds: [1, 1] }, '/seeds'],
      [{ scenario: 'queue', seeds: [2, -1] }, '/seeds/1'],
      [{ scenario: 'queue', seeds: [0.5] }, '/seeds/0'],
      [{ scenario: 'queue', count: 0 }, '/count'],
      [{ scenario: 'queue', count: 100001 }, '/count'],
      [{ scenario: 'queue', count: 2, first_seed: 9007199254740991 }, '/first_seed', 'the sum is too big'],
      [{ scenario: 'queue', seeds: [1], first_seed: 3 }, '/first_seed'],
      [{ scenario: 'queue', count: 1, max_time: 0 }, '/max_time'],
      [{ scenario: 'queue', count: 1, colour: 'red' }, '/colour'],
      [{ scenario: 'queue', count: 1, gates: 'success.mean > 0' }, '/gates'],
      [{ scenario: 'queue', count: 1, controller: 'social' }, '/controller'],
      [{ scenario: 'queue', count: 1, controller: { type: 'warp' } }, '/controller/type'],
      [{ scenario: 'queue', count: 1, requests: [{ time: -1, task: 'help_robot' }] }, '/requests/0'],
      [{ scenario: 'queue', count: 1, requests: [{ time: 1, task: 'dance' }] }, '/requests/0', 'no such task'],
    ];
    // The spec refuses each request too, but for what only the server can know (the third item).
    for (const [body, pointer, allowedBySpec] of cases) {
      const reply = await api.post('/api/v1/runs', body);
      assert.equal(reply.status, 400, JSON.stringify(body));
      assert.equal(reply.json.error.code, 'bad_request');
      assert.equal(reply.json.error.details.pointer, pointer, JSON.stringify(body));
      assert.equal(specAllows('POST', '/api/v1/runs', body), Boolean(allowedBySpec), `the spec allows ${JSON.stringify(body)}`);
    }
    assert.equal((await api.request('POST', '/api/v1/runs', { body: '{"scenario": ' })).status, 400);
    assert.equal((await api.request('POST', '/api/v1/runs', { body: '["queue"]' })).status, 400);
    assert.equal((await api.get('/api/v1/runs?limit=100')).json.items.length, before);
  });

  it('POST /api/v1/runs: every wrong gate at once in details.errors', async () => {
    const reply = await api.post('/api/v1/runs', { scenario: 'queue', count: 1, gates: ['bogus.mean > 1', 'success.median > 1', 'success.mean >> 1', 'success.mean > 0', 'success.mean'] });
    assert.equal(reply.status, 400);
    assert.equal(reply.json.error.details.pointer, '/gates/0');
    assert.deepEqual(reply.json.error.details.errors.map((error) => error.pointer), ['/gates/0', '/gates/1', '/gates/2', '/gates/4']);
    assert.match(reply.json.error.details.errors[1].message, /median/);
  });

  it('POST /api/v1/runs: a body over the limit is 413 before it is sent', async () => {
    const reply = await api.request('POST', '/api/v1/runs', { headers: { 'content-length': String(5 * 1024 * 1024) } });
    assert.equal(reply.status, 413);
    assert.equal(reply.json.error.code, 'payload_too_large');
  });

  it('GET /api/v1/runs: newest first, pages follow next_cursor', async () => {
    const all = await api.get('/api/v1/runs?limit=100');
    assert.equal(all.status, 200);
    assert.equal(all.json.next_cursor, null);
    const ids = all.json.items.map((item) => item.id);
    assert.ok(ids.includes(report.id));
    const created = all.json.items.map((item) => item.created_at);
    assert.deepEqual(created, [...created].sort().reverse(), 'newest first');
    const first = await api.get('/api/v1/runs?limit=2');
    assert.deepEqual(first.json.items.map((item) => item.id), ids.slice(0, 2));
    assert.equal(first.json.next_cursor, ids[1]);
    const second = await api.get(`/api/v1/runs?limit=2&cursor=${first.json.next_cursor}`);
    assert.deepEqual(second.json.items.map((item) => item.id), ids.slice(2, 4));
  });

  it('GET /api/v1/runs: the summary agrees with the report', async () => {
    const listed = (await api.get('/api/v1/runs?limit=100')).json.items.find((item) => item.id === report.id);
    assert.deepEqual(listed, {
      id: report.id, scenario: 'queue', controller: 'scenario', status: 'finished', created_at: report.created_at,
      finished_at: report.finished_at, progress: report.progress, success_rate: report.rates.success_rate,
      verdict: { passed: false, complete: true },
    });
  });

  it('GET /api/v1/runs: by status and by scenario (its id or scenario_record)', async () => {
    const finished = await api.get('/api/v1/runs?status=finished&limit=100');
    assert.ok(finished.json.items.length > 0);
    assert.ok(finished.json.items.every((item) => item.status === 'finished'));
    assert.deepEqual((await api.get('/api/v1/runs?status=interrupted')).json.items, []);
    const byId = await api.get('/api/v1/runs?scenario=queue&limit=100');
    assert.ok(byId.json.items.every((item) => item.scenario === 'queue'));
    const byRecord = await api.get(`/api/v1/runs?scenario=${report.scenario_record}&limit=100`);
    assert.deepEqual(byRecord.json.items.map((item) => item.id), byId.json.items.map((item) => item.id));
    assert.deepEqual((await api.get('/api/v1/runs?scenario=atlantis')).json, { items: [], next_cursor: null });
  });

  it('GET /api/v1/runs: 400 for a bad limit, status or cursor', async () => {
    for (const [query, parameter] of [['limit=0', 'limit'], ['limit=101', 'limit'], ['limit=ten', 'limit'], ['status=done', 'status'], [`cursor=${UNKNOWN_RUN}`, 'cursor']]) {
      const reply = await api.get(`/api/v1/runs?${query}`);
      assert.equal(reply.status, 400, query);
      assert.equal(reply.json.error.details.parameter, parameter, query);
    }
  });

  it('GET /api/v1/runs/{id}: 404 for an unknown run', async () => {
    const reply = await api.get(`/api/v1/runs/${UNKNOWN_RUN}`);
    assert.equal(reply.status, 404);
    assert.equal(reply.json.error.code, 'not_found');
  });

  it('GET /api/v1/runs/{id}/episodes: each stored episode with every metric', async () => {
    const reply = await api.get(`/api/v1/runs/${report.id}/episodes`);
    assert.equal(reply.status, 200);
    const { items } = reply.json;
    assert.deepEqual(items.map((episode) => episode.id).sort(), report.episodes.map((episode) => episode.episode_id).sort());
    for (const episode of items) {
      assert.equal(episode.run_id, report.id);
      assert.equal(episode.scenario, report.scenario_record);
      assert.equal(episode.controller, 'scenario');
      assert.equal(episode.status, 'finished');
      assert.deepEqual(Object.keys(episode.metrics).sort(), [...metricKeys].sort());
      assert.equal(episode.metrics.episode_length, episode.ticks);
      const inReport = report.episodes.find((item) => item.episode_id === episode.id);
      assert.equal(inReport.seed, episode.seed);
      assert.equal(inReport.sim_time, episode.sim_time);
      assert.equal(inReport.success, episode.metrics.success);
    }
    assert.equal((await api.get(`/api/v1/runs/${UNKNOWN_RUN}/episodes`)).status, 404);
  });

  it('GET /api/v1/runs/{id}/junit: one testcase per gate, failures marked', async () => {
    const reply = await api.get(`/api/v1/runs/${report.id}/junit`);
    assert.equal(reply.status, 200);
    assert.match(reply.body, /^<\?xml version="1\.0" encoding="UTF-8"\?>/);
    assert.match(reply.body, /<testsuites tests="2" failures="1">/);
    assert.match(reply.body, new RegExp(`<testsuite name="hrisim run ${report.id}" tests="2" failures="1">`));
    assert.match(reply.body, /<testcase [^>]*name="collisions\.max &lt; 0">\s*<failure message="collisions\.max is [^"]+"\/>/);
    assert.match(reply.body, /<testcase [^>]*name="episode_length\.count == 3">\s*<\/testcase>/);
    assert.equal((await api.get(`/api/v1/runs/${UNKNOWN_RUN}/junit`)).status, 404);
  });

  it('GET /api/v1/episodes/{id}: metrics, the reason for each null one, and the events', async () => {
    const id = report.episodes[0].episode_id;
    const reply = await api.get(`/api/v1/episodes/${id}`);
    assert.equal(reply.status, 200);
    const episode = reply.json;
    assert.equal(episode.id, id);
    assert.equal(episode.seed, 0);
    for (const key of metricKeys) {
      assert.equal(episode.metrics[key] === null, key in episode.null_reasons, key);
    }
    // The queue's robot has no navigation goal.
    assert.equal(episode.metrics.time_to_goal, null);
    assert.ok(episode.null_reasons.time_to_goal.length > 0);
    assert.ok(episode.events.length > 0);
    const ticks = episode.events.map((event) => event.tick);
    assert.deepEqual(ticks, [...ticks].sort((a, b) => a - b), 'events in tick order');
    assert.ok(ticks.every((tick) => tick <= episode.ticks));
    assert.equal((await api.get(`/api/v1/episodes/${UNKNOWN_EPISODE}`)).status, 404);
  });

  it('GET /api/v1/episodes/{id}/trajectory: every agent at 10 Hz, as JSON and as CSV', async () => {
    const id = report.episodes[0].episode_id;
    const episode = (await api.get(`/api/v1/episodes/${id}`)).json;
    const json = await api.get(`/api/v1/episodes/${id}/trajectory`);
    assert.equal(json.status, 200);
    assert.equal(json.json.episode, id);
    assert.equal(json.json.rate, 10);
    const agents = Object.keys(json.json.agents);
    assert.ok(agents.includes('robot'), agents.join(', '));
    for (const samples of Object.values(json.json.agents)) {
      assert.equal(samples[0].tick, 0);
      const steps = samples.slice(1).map((sample, i) => sample.tick - samples[i].tick);
      assert.ok(steps.every((step) => step === steps[0]), 'evenly spaced');
      assert.ok(Math.abs(samples[1].time - samples[0].time - 0.1) < 0.02, 'at 10 Hz');
      assert.ok(samples.at(-1).tick <= episode.ticks);
    }
    const csv = await api.get(`/api/v1/episodes/${id}/trajectory?format=csv`);
    assert.equal(csv.status, 200);
    assert.equal(csv.headers['content-type'], 'text/csv; charset=utf-8');
    assert.equal(csv.headers['content-disposition'], `attachment; filename="${id}.csv"`);
    const lines = csv.body.trimEnd().split('\n');
    assert.equal(lines[0], 'agent,tick,time,x,y,theta');
    const rows = lines.slice(1).map((line) => line.split(','));
    const fromJson = Object.entries(json.json.agents).flatMap(([agent, samples]) => samples.map((s) => [agent, s.tick, s.time, s.x, s.y, s.theta]));
    assert.deepEqual(rows.map(([agent, ...numbers]) => [agent, ...numbers.map(Number)]), fromJson);
  });

  it('GET /api/v1/episodes/{id}/trajectory: 400 for an unknown format, 404 for an unknown episode', async () => {
    const id = report.episodes[0].episode_id;
    const wrong = await api.get(`/api/v1/episodes/${id}/trajectory?format=xml`);
    assert.equal(wrong.status, 400);
    assert.equal(wrong.json.error.details.parameter, 'format');
    assert.equal((await api.get(`/api/v1/episodes/${UNKNOWN_EPISODE}/trajectory`)).status, 404);
  });

  it('POST /api/v1/runs/{id}/cancel: 202; queued seeds never run, finished episodes stay', async () => {
    const run = await startRun({ scenario: 'elevator', count: 200 });
    assert.ok(['queued', 'running'].includes(run.json.status), run.json.status);
    const cancelled = await api.post(`/api/v1/runs/${run.json.id}/cancel`);
    assert.equal(cancelled.status, 202);
    assert.equal(cancelled.json.id, run.json.id);
    assert.equal(cancelled.json.progress.queued, 0, 'seeds that will never run are cancelled at once');
    assert.ok(cancelled.json.progress.cancelled > 0, JSON.stringify(cancelled.json.progress));
    assert.ok(cancelled.json.episodes.every((episode) => episode.status !== 'queued'));
    const done = await waitForRun(run.json.id);
    assert.equal(done.status, 'cancelled');
    assert.ok(done.finished_at);
    const { progress } = done;
    assert.ok(progress.finished < 200, JSON.stringify(progress));
    assert.equal(progress.finished + progress.cancelled, 200, JSON.stringify(progress));
    assert.ok(done.episodes.every((episode) => ['finished', 'cancelled'].includes(episode.status)));
    assert.equal(done.verdict.complete, false);
    assert.equal(done.verdict.passed, false);
    assert.ok(done.verdict.reasons.some((reason) => /cancelled/.test(reason)), done.verdict.reasons.join('; '));
    const stored = (await api.get(`/api/v1/runs/${run.json.id}/episodes`)).json.items;
    assert.equal(stored.length, progress.finished);
    const junit = (await api.get(`/api/v1/runs/${run.json.id}/junit`)).body;
    assert.match(junit, new RegExp(`<testsuites tests="${progress.cancelled}" failures="${progress.cancelled}">`));
    assert.match(junit, /<failure message="episode cancelled"\/>/);

    const again = await api.post(`/api/v1/runs/${run.json.id}/cancel`);
    assert.equal(again.status, 409);
    assert.equal(again.json.error.code, 'conflict');
    assert.equal(again.json.error.details.status, 'cancelled');
  });

  it('POST /api/v1/runs/{id}/cancel: 409 for a finished run, 404 for an unknown one', async () => {
    const finished = await api.post(`/api/v1/runs/${report.id}/cancel`);
    assert.equal(finished.status, 409);
    assert.equal(finished.json.error.details.status, 'finished');
    assert.equal((await api.post(`/api/v1/runs/${UNKNOWN_RUN}/cancel`)).status, 404);
  });
});

describe('a run the server dies under', () => {
  it('is marked interrupted when the next server starts; its stored episodes stay', async () => {
    const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'hrisim-contract-'));
    let first;
    let second;
    try {
      first = await startServer(['--run-jobs', '1'], { dir });
      const client = new Client(first.port);
      const run = (await startRun({ scenario: 'elevator', count: 200 }, client)).json;
      await waitForRun(run.id, { client, until: (report) => report.progress.finished >= 1 });
      await first.kill();
      first = undefined;

      second = await startServer([], { dir });
      client.connect(second.port);
      // Said on stderr before the port on stdout; the two pipes may be read in either order.
      const said = /1 run left unfinished by the last server marked interrupted/;
      for (let wait = 0; wait < 20 && !said.test(second.output()); wait++) await sleep(50);
      assert.match(second.output(), said);
      const report = (await client.get(`/api/v1/runs/${run.id}`)).json;
      assert.equal(report.status, 'interrupted');
      assert.ok(report.finished_at);
      const { progress } = report;
      assert.ok(progress.finished >= 1 && progress.finished < 200, JSON.stringify(progress));
      assert.equal(progress.finished + progress.interrupted, 200, JSON.stringify(progress));
      assert.ok(report.episodes.every((episode) => ['finished', 'interrupted'].includes(episode.status)));
      assert.equal(report.verdict.passed, false);
      assert.equal(report.verdict.complete, false);
      const stored = (await client.get(`/api/v1/runs/${run.id}/episodes`)).json.items;
      assert.equal(stored.length, progress.finished);
      assert.deepEqual((await client.get('/api/v1/runs?status=interrupted')).json.items.map((item) => item.id), [run.id]);
      const cancel = await client.post(`/api/v1/runs/${run.id}/cancel`);
      assert.equal(cancel.status, 409);
      assert.equal(cancel.json.error.details.status, 'interrupted');
    } finally {
      // A failed check must not leave a server behind (its pipes would keep the test process alive).
      if (first) await first.kill();
      if (second) await second.stop();
      fs.rmSync(dir, { recursive: true, force: true });
    }
  });
});

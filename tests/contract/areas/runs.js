'use strict';
// Runs: batches of headless episodes (start, list, report, cancel, episodes, JUnit, comparison of
// two runs), the stored episodes with their trajectories and per-step series, the metric list, and a
// run a dying server leaves interrupted.
// Runs of the bundled queue scenario take a few milliseconds per episode; the elevator's 200 seeds
// keep the executor busy long enough to cancel them.
const assert = require('node:assert/strict');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { describe, it, before } = require('node:test');
const { api, Client } = require('../lib/client');
const { openapi, specAllows } = require('../lib/contract');
const { cupOnASideTable } = require('../lib/fixtures');
const { startServer } = require('../lib/server');

const FINAL = ['finished', 'failed', 'cancelled', 'interrupted'];
const RUN_LIMIT_MS = 60000;
const UNKNOWN_RUN = `r${'0'.repeat(32)}`;
const UNKNOWN_EPISODE = `e${'0'.repeat(32)}`;

const sleep = (ms) => new Promise((resolve) => { setTimeout(resolve, ms); });

// Reference statistics for the comparison, computed apart from the server's (numerical integration
// of Student's t density rather than the incomplete beta function).

/** ln Γ(x) for x > 0 (Lanczos, g = 7). */
function logGamma(x) {
  const c = [0.99999999999980993, 676.5203681218851, -1259.1392167224028, 771.32342877765313, -176.61503916999185,
    12.507343278686905, -0.13857109526572012, 9.9843695780195716e-6, 1.5056327351493116e-7];
  if (x < 0.5) return Math.log(Math.PI / Math.sin(Math.PI * x)) - logGamma(1 - x);
  x -= 1;
  let sum = c[0];
  for (let i = 1; i < 9; i++) sum += c[i] / (x + i);
  const t = x + 7.5;
  return 0.5 * Math.log(2 * Math.PI) + (x + 0.5) * Math.log(t) - t + Math.log(sum);
}

/** ∫ f over [from, to] by Simpson's rule with `n` (even) intervals. */
function simpson(f, from, to, n = 4000) {
  const h = (to - from) / n;
  let sum = f(from) + f(to);
  for (let i = 1; i < n; i++) sum += (i % 2 ? 4 : 2) * f(from + i * h);
  return (sum * h) / 3;
}

/** P(|T| >= |t|) for Student's t with `df` >= 1 degrees of freedom. */
function twoSidedT(t, df) {
  const scale = Math.exp(logGamma((df + 1) / 2) - logGamma(df / 2)) / Math.sqrt(df * Math.PI);
  const density = (x) => scale * (1 + (x * x) / df) ** (-(df + 1) / 2);
  const a = Math.abs(t);
  if (a < 1) return 1 - 2 * simpson(density, 0, a);
  // The tail with x = a / s, s in (0, 1]: the integrand tends to a finite limit at s = 0 for df >= 1.
  return 2 * simpson((s) => (s === 0 ? 0 : (density(a / s) * a) / (s * s)), 0, 1);
}

const meanOf = (values) => values.reduce((sum, v) => sum + v, 0) / values.length;

/** Welch's two-sided p-value, or null with fewer than two values in a sample. */
function welch(a, b) {
  if (a.length < 2 || b.length < 2) return null;
  const variance = (values, mean) => values.reduce((sum, v) => sum + (v - mean) ** 2, 0) / (values.length - 1);
  const ma = meanOf(a), mb = meanOf(b);
  const va = variance(a, ma) / a.length, vb = variance(b, mb) / b.length;
  // Spread and difference within rounding of the values' size (1e-9 relative) count as none.
  const scale = Math.max(Math.abs(ma), Math.abs(mb), 1) * 1e-9;
  if (Math.sqrt(va + vb) <= scale) return Math.abs(ma - mb) <= scale ? 1 : 0;
  const df = (va + vb) ** 2 / (va ** 2 / (a.length - 1) + vb ** 2 / (b.length - 1));
  return twoSidedT((ma - mb) / Math.sqrt(va + vb), df);
}

/** Fisher's exact two-sided p-value for 0/1 samples, or null when either is empty. */
function fisher(a, b) {
  if (!a.length || !b.length) return null;
  const hitsA = a.filter((v) => v === 1).length, hits = hitsA + b.filter((v) => v === 1).length;
  const logChoose = (n, k) => logGamma(n + 1) - logGamma(k + 1) - logGamma(n - k + 1);
  const logP = (k) => logChoose(a.length, k) + logChoose(b.length, hits - k) - logChoose(a.length + b.length, hits);
  let p = 0;
  for (let k = Math.max(0, hits - b.length); k <= Math.min(a.length, hits); k++) {
    if (logP(k) <= logP(hitsA) + 1e-7) p += Math.exp(logP(k));
  }
  return Math.min(1, p);
}

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

  it('GET /api/v1/metrics: the per-step series, each with its unit, as GET /api/v1/episodes/{id}/series takes them', async () => {
    const { series } = (await api.get('/api/v1/metrics')).json;
    assert.deepEqual(series.map((item) => [item.name, item.unit]), [
      ['distance_to_closest_person', 'm'], ['proxemic_zone', 'zone'], ['time_to_collision', 's'], ['robot_speed', 'm/s'],
      ['social_force_on_robot', 'N/kg'], ['episode_reward', 'reward'],
    ]);
    assert.ok(series.every((item) => item.description.length > 0));
    const parameter = openapi.paths['/api/v1/episodes/{id}/series'].get.parameters.find((p) => p.name === 'name');
    assert.deepEqual(parameter.schema.enum, series.map((item) => item.name), "the spec's series names");
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
    assert.ok([200, 201].includes(uploaded.status), 'stored, or the same content stored by another test');
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

  it('DELETE /api/v1/scenarios/{id} of an upload a run ran only unlists it: the run still finds it; uploading it again lists it again', async () => {
    const uploaded = await api.post('/api/v1/scenarios', { ...cupOnASideTable, name: 'cup_ran_then_deleted' });
    assert.equal(uploaded.status, 201, uploaded.body);
    const scenario = uploaded.json.summary.id;
    const done = await waitForRun((await startRun({ scenario, count: 1, max_time: 0.5 })).json.id);
    assert.equal(done.status, 'finished');
    const unlisted = await api.delete(`/api/v1/scenarios/${scenario}`);
    assert.equal(unlisted.status, 200);
    assert.deepEqual(unlisted.json, { id: scenario, outcome: 'unlisted' });
    const listed = async () => (await api.get('/api/v1/scenarios?limit=200')).json.items.some((item) => item.id === scenario);
    assert.equal(await listed(), false, 'out of the list');
    assert.equal((await api.get(`/api/v1/scenarios/${scenario}/world`)).status, 200, 'the run\'s pages still find it');
    assert.equal((await api.get(`/api/v1/runs/${done.id}`)).status, 200);
    const again = await api.post('/api/v1/scenarios', { ...cupOnASideTable, name: 'cup_ran_then_deleted' });
    assert.equal(again.status, 200);
    assert.equal(again.json.summary.id, scenario);
    assert.equal(await listed(), true, 'listed again');
  });

  it('PATCH /api/v1/runs/{id} names, tags and notes a run; GET /api/v1/runs finds it by text and tag, sorts and filters by a metric, gives metric columns', async () => {
    const label = `labels${Date.now()}`;
    const started = await startRun({ scenario: 'queue', count: 2, name: 'first of two', tags: [label, 'queue'], notes: 'with the default controller' });
    assert.equal(started.json.name, 'first of two');
    assert.deepEqual(started.json.tags, [label, 'queue']);
    const first = await waitForRun(started.json.id);
    const second = await waitForRun((await startRun({ scenario: 'queue', count: 1, first_seed: 5, tags: [label] })).json.id);
    const patched = await api.patch(`/api/v1/runs/${second.id}`, { name: 'second', notes: 'one seed only' });
    assert.equal(patched.status, 200, patched.body);
    assert.equal(patched.json.name, 'second');
    assert.deepEqual(patched.json.tags, [label], 'tags not given stay');
    assert.equal(patched.json.notes, 'one seed only');
    const wrong = await api.patch(`/api/v1/runs/${second.id}`, { name: 7, tags: ['a b', 'x', 'x'] });
    assert.equal(wrong.status, 400);
    assert.deepEqual(wrong.json.error.details.errors.map((error) => error.pointer), ['/name', '/tags/0', '/tags/2']);
    assert.equal((await api.patch('/api/v1/runs/r0', { name: 'x' })).status, 404);

    const list = async (query) => {
      const reply = await api.get(`/api/v1/runs?tag=${label}&${query}`);
      assert.equal(reply.status, 200, `${query}: ${reply.body}`);
      return reply.json;
    };
    assert.deepEqual((await list('')).items.map((item) => item.id), [second.id, first.id], 'newest first');
    assert.deepEqual((await list('q=ONE%20SEED')).items.map((item) => item.id), [second.id], 'text in the notes, any case');
    const columns = await list('metrics=time_to_goal.mean,collisions.max');
    assert.deepEqual(Object.keys(columns.items[0].metrics).sort(), ['collisions.max', 'time_to_goal.mean']);
    assert.equal(columns.items[1].metrics['collisions.max'], first.aggregates.collisions.max);
    // Seeds 0 and 1 against seed 5: episodes of different lengths (ties would go newest first).
    const length = (run) => run.aggregates.episode_length.mean;
    assert.notEqual(length(first), length(second));
    const longestFirst = [first, second].sort((a, b) => length(b) - length(a)).map((run) => run.id);
    assert.deepEqual((await list('sort=episode_length.mean')).items.map((item) => item.id), longestFirst);
    assert.deepEqual((await list('sort=episode_length.mean&order=asc')).items.map((item) => item.id), [...longestFirst].reverse());
    const paged = await list('sort=episode_length.mean&limit=1');
    assert.equal(paged.next_cursor, '@1');
    assert.deepEqual((await list('sort=episode_length.mean&limit=1&cursor=@1')).items.map((item) => item.id), [longestFirst[1]]);
    const longest = Math.max(length(first), length(second));
    assert.deepEqual((await list(`where=episode_length.mean>=${longest}`)).items.map((item) => item.id), [longestFirst[0]]);
    for (const query of ['sort=nonsense.mean', 'sort=episode_length.median', 'order=up', 'where=episode_length.mean', 'metrics=x.y',
      'sort=episode_length.mean&cursor=r1']) {
      const refused = await api.get(`/api/v1/runs?${query}`);
      assert.equal(refused.status, 400, query);
    }
  });

  it('POST /api/v1/sessions with an episode replays it: the run\'s controller and time limit, stepped to the same final state hash', async () => {
    const run = await waitForRun((await startRun({ scenario: 'elevator', seeds: [3], controller: { type: 'goal', goal: { pose: { x: 1.0, y: -0.8, theta: 0 } } }, max_time: 2 })).json.id);
    const episode = (await api.get(`/api/v1/runs/${run.id}/episodes`)).json.items[0];
    assert.ok(episode.state_hash, 'the episode keeps its final state hash');
    const created = await api.post('/api/v1/sessions', { episode: episode.id });
    assert.equal(created.status, 201, created.body);
    const replay = created.json;
    assert.equal(replay.episode, episode.id);
    assert.equal(replay.seed, 3);
    assert.equal(replay.scenario, 'elevator');
    assert.deepEqual(replay.controller, run.config.controller);
    const end = await api.post(`/api/v1/sessions/${replay.id}/step`, { n: 100000 });
    assert.equal(end.json.status, 'finished');
    assert.equal(end.json.termination, 'timeout', 'the run\'s max_time');
    assert.equal(end.json.tick, episode.ticks);
    assert.equal(end.json.state_hash, episode.state_hash, 'bit for bit the episode it replays');
    await api.delete(`/api/v1/sessions/${replay.id}`);
    for (const [body, pointer] of [[{ episode: episode.id, seed: 4 }, '/seed'], [{ episode: episode.id, scenario: 'queue' }, '/episode'], [{ episode: 7 }, '/episode']]) {
      const refused = await api.post('/api/v1/sessions', body);
      assert.equal(refused.status, 400, JSON.stringify(body));
      assert.equal(refused.json.error.details.pointer, pointer);
    }
    const unknown = await api.post('/api/v1/sessions', { episode: 'e0' });
    assert.equal(unknown.status, 404);
    assert.equal(unknown.json.error.details.pointer, '/episode');
  });

  it('POST /api/v1/runs: requests make the robot ask at the given times', async () => {
    const plain = await waitForRun((await startRun({ scenario: 'queue', seeds: [0] })).json.id);
    const asking = await waitForRun((await startRun({ scenario: 'queue', seeds: [0], requests: [{ time: 1, routine: 'help_robot' }] })).json.id);
    assert.deepEqual(asking.config.requests, [{ time: 1, routine: 'help_robot' }]);
    assert.equal(asking.aggregates.requests_sent.mean, plain.aggregates.requests_sent.mean + 1);
    // "task", the routine's former name, is still accepted and stored under the new one.
    const former = await waitForRun((await startRun({ scenario: 'queue', seeds: [0], requests: [{ time: 1, task: 'help_robot' }] })).json.id);
    assert.deepEqual(former.config.requests, [{ time: 1, routine: 'help_robot' }]);
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
      [{ scenario: 'queue' }, ''],
      [{ scenario: 'queue', count: 1, seeds: [1] }, '/count'],
      [{ scenario: 'queue', seeds: [] }, '/seeds'],
      [{ scenario: 'queue', seeds: [1, 1] }, '/seeds/1'],
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
      [{ scenario: 'queue', count: 1, requests: [{ time: -1, task: 'help_robot' }] }, '/requests/0/time'],
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
    // Every field the spec refuses at once, each at its pointer, none of them reported twice; what only
    // the server knows (the unknown metric of /gates/0) comes once the body meets the spec.
    const many = await api.post('/api/v1/runs', { scenario: 'queue', count: 0, max_time: -1, gates: ['bogus.mean > 1', 7],
      requests: [{ time: -1, routine: 'help_robot' }], controller: { type: 'warp' } });
    assert.equal(many.status, 400);
    assert.deepEqual(many.json.error.details.errors.map((error) => error.pointer).sort(),
      ['/controller/type', '/count', '/gates/1', '/max_time', '/requests/0/time']);
    assert.equal((await api.request('POST', '/api/v1/runs', { body: '{"scenario": ' })).status, 400);
    assert.equal((await api.request('POST', '/api/v1/runs', { body: '["queue"]' })).status, 400);
    assert.equal((await api.get('/api/v1/runs?limit=100')).json.items.length, before);
  });

  it('POST /api/v1/runs: every wrong gate at once in details.errors', async () => {
    // The spec's grammar first (every gate that breaks it at once), then the metrics the server knows.
    const reply = await api.post('/api/v1/runs', { scenario: 'queue', count: 1, gates: ['bogus.mean > 1', 'success.median > 1', 'success.mean >> 1', 'success.mean > 0', 'success.mean'] });
    assert.equal(reply.status, 400);
    assert.equal(reply.json.error.details.pointer, '/gates/1');
    assert.deepEqual(reply.json.error.details.errors.map((error) => error.pointer), ['/gates/1', '/gates/2', '/gates/4']);
    assert.match(reply.json.error.details.errors[0].message, /must match the pattern/);
    const unknown = await api.post('/api/v1/runs', { scenario: 'queue', count: 1, gates: ['bogus.mean > 1', 'success.mean > 0', 'speed.max < 2'] });
    assert.equal(unknown.status, 400);
    assert.deepEqual(unknown.json.error.details.errors.map((error) => error.pointer), ['/gates/0', '/gates/2']);
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

  it('GET /api/v1/runs: the summary agrees with the report, with the reasons of its verdict', async () => {
    const listed = (await api.get('/api/v1/runs?limit=100')).json.items.find((item) => item.id === report.id);
    assert.deepEqual(listed, {
      id: report.id, name: '', tags: [], metrics: {}, scenario: 'queue', controller: 'scenario', status: 'finished', created_at: report.created_at,
      finished_at: report.finished_at, progress: report.progress, success_rate: report.rates.success_rate,
      verdict: { passed: false, complete: true, reasons: report.verdict.reasons },
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

  /** Each metric's non-null values over a run's finished episodes, by key, in stored order. */
  async function valuesOfRun(id) {
    const episodes = (await api.get(`/api/v1/runs/${id}/episodes`)).json.items.filter((episode) => episode.status === 'finished');
    return Object.fromEntries(metricKeys.map((key) => [key, episodes.map((e) => e.metrics[key]).filter((v) => v !== null)]));
  }

  /** Checks a comparison of runs `a` and `b` item by item against the stored episodes and reference tests. */
  async function checkComparison(comparison, a, b) {
    const definitions = (await api.get('/api/v1/metrics')).json.items;
    const [valuesA, valuesB] = [await valuesOfRun(a), await valuesOfRun(b)];
    assert.equal(comparison.a, a);
    assert.equal(comparison.b, b);
    assert.equal(comparison.significance_level, 0.05);
    assert.deepEqual(comparison.metrics.map((item) => item.key), metricKeys, 'every metric, in the order of GET /api/v1/metrics');
    for (const [i, item] of comparison.metrics.entries()) {
      const what = `${item.key}: ${JSON.stringify(item)}`;
      const definition = definitions[i];
      assert.equal(item.unit, definition.unit, what);
      assert.equal(item.better, definition.better, what);
      const [va, vb] = [valuesA[item.key], valuesB[item.key]];
      for (const [side, values] of [[item.a, va], [item.b, vb]]) {
        assert.equal(side.count, values.length, what);
        if (values.length) assert.ok(Math.abs(side.mean - meanOf(values)) <= 1e-9 * Math.max(1, Math.abs(side.mean)), what);
        else assert.equal(side.mean, null, what);
      }
      if (va.length && vb.length) assert.ok(Math.abs(item.difference - (item.b.mean - item.a.mean)) <= 1e-9 * Math.max(1, Math.abs(item.difference)), what);
      else assert.equal(item.difference, null, what);
      const binary = definition.unit === 'bool';
      assert.equal(item.test, binary ? 'fisher_exact' : 'welch_t', what);
      const expected = binary ? fisher(va, vb) : welch(va, vb);
      if (expected === null) assert.equal(item.p_value, null, what);
      else assert.ok(Math.abs(item.p_value - expected) < 1e-6, `${what}: p-value ${expected} expected`);
      assert.equal(item.significant, item.p_value !== null && item.p_value < comparison.significance_level, what);
      let change = 'no significant change';
      if (item.significant && item.better === 'none') change = 'different';
      else if (item.significant) change = (item.difference > 0) === (item.better === 'higher') ? 'better' : 'worse';
      assert.equal(item.change, change, what);
    }
  }

  it('GET /api/v1/runs/compare: Welch per continuous metric, Fisher per 0/1 metric, better or worse by direction', async () => {
    // The same seeds cut off at 5 s: shorter episodes, and no queue gets to its end.
    const short = await waitForRun((await startRun({ scenario: 'queue', seeds: [0, 1, 2], max_time: 5 })).json.id);
    assert.equal(short.status, 'finished');
    const reply = await api.get(`/api/v1/runs/compare?a=${report.id}&b=${short.id}`);
    assert.equal(reply.status, 200);
    await checkComparison(reply.json, report.id, short.id);
    const byKey = Object.fromEntries(reply.json.metrics.map((item) => [item.key, item]));
    assert.equal(byKey.episode_length.b.mean, 300, '5 s at 60 Hz');
    assert.ok(byKey.episode_length.difference < 0);
    assert.equal(byKey.episode_length.significant, true);
    assert.equal(byKey.episode_length.change, 'different', 'a metric with no better direction');
    assert.ok(reply.json.metrics.some((item) => ['better', 'worse'].includes(item.change)), 'some metric changed for better or worse');
    // Swapped, the difference changes sign and better becomes worse; the p-values stay.
    const swapped = (await api.get(`/api/v1/runs/compare?a=${short.id}&b=${report.id}`)).json;
    const opposite = { better: 'worse', worse: 'better', different: 'different', 'no significant change': 'no significant change' };
    for (const [i, item] of swapped.metrics.entries()) {
      const original = reply.json.metrics[i];
      assert.equal(item.p_value === null, original.p_value === null, item.key);
      if (item.p_value !== null) assert.ok(Math.abs(item.p_value - original.p_value) < 1e-12, item.key);
      if (item.difference !== null) assert.ok(item.difference === -original.difference, item.key);  // 0 and -0 alike
      assert.equal(item.change, opposite[original.change], item.key);
    }
  });

  it('GET /api/v1/runs/compare: a run against itself changes nothing; one episode is too few for Welch', async () => {
    const itself = (await api.get(`/api/v1/runs/compare?a=${report.id}&b=${report.id}`)).json;
    await checkComparison(itself, report.id, report.id);
    for (const item of itself.metrics) {
      assert.ok(item.difference === null || item.difference === 0, item.key);
      assert.ok(item.p_value === null || item.p_value === 1, `${item.key}: ${item.p_value}`);
      assert.equal(item.change, 'no significant change', item.key);
    }
    const single = await waitForRun((await startRun({ scenario: 'queue', seeds: [7] })).json.id);
    const reply = await api.get(`/api/v1/runs/compare?a=${single.id}&b=${report.id}`);
    await checkComparison(reply.json, single.id, report.id);
    for (const item of reply.json.metrics.filter((candidate) => candidate.test === 'welch_t')) {
      assert.equal(item.p_value, null, item.key);
      assert.equal(item.significant, false, item.key);
    }
    const success = reply.json.metrics.find((item) => item.key === 'success');
    assert.equal(success.test, 'fisher_exact');
    assert.equal(typeof success.p_value, 'number', 'Fisher needs one value a side');
  });

  it('GET /api/v1/runs/compare?runs=: three runs, each one\'s distribution and each against the baseline, Holm-adjusted over the reply', async () => {
    const short = await waitForRun((await startRun({ scenario: 'queue', seeds: [0, 1, 2], max_time: 5 })).json.id);
    const shorter = await waitForRun((await startRun({ scenario: 'queue', seeds: [3, 4, 5], max_time: 3 })).json.id);
    const ids = [report.id, short.id, shorter.id];
    const reply = await api.get(`/api/v1/runs/compare?runs=${ids.join(',')}`);
    assert.equal(reply.status, 200, reply.body);
    const holm = reply.json;
    assert.deepEqual(holm.runs, ids);
    assert.equal(holm.baseline, report.id);
    assert.equal(holm.correction, 'holm');
    const plain = (await api.get(`/api/v1/runs/compare?runs=${ids.join(',')}&correction=none`)).json;
    // Each later run against the baseline: the two-run form's test and p-value.
    for (const [r, other] of [[0, short], [1, shorter]]) {
      const pair = (await api.get(`/api/v1/runs/compare?a=${report.id}&b=${other.id}`)).json;
      for (const [m, item] of plain.metrics.entries()) {
        const comparison = item.comparisons[r];
        assert.equal(comparison.run, other.id);
        assert.equal(comparison.p_value, pair.metrics[m].p_value, item.key);
        assert.equal(comparison.p_adjusted, comparison.p_value, `${item.key}: no correction`);
        assert.equal(comparison.change, pair.metrics[m].change, item.key);
      }
    }
    // Holm by hand: sort the p-values of the whole reply, multiply the k-th smallest by m − k + 1, running maximum, cap 1.
    const tests = holm.metrics.flatMap((item) => item.comparisons).filter((comparison) => comparison.p_value !== null);
    assert.equal(holm.tests, tests.length);
    const order = [...tests].sort((x, y) => x.p_value - y.p_value);
    let running = 0;
    for (const [k, comparison] of order.entries()) {
      running = Math.max(running, Math.min(1, (order.length - k) * comparison.p_value));
      assert.ok(Math.abs(comparison.p_adjusted - running) < 1e-12, `${comparison.run}: ${comparison.p_adjusted} vs ${running}`);
      assert.equal(comparison.significant, comparison.p_adjusted < holm.significance_level);
    }
    // Distributions: the episodes' values with their five numbers.
    const length = holm.metrics.find((item) => item.key === 'episode_length');
    const shortest = length.runs[2];
    assert.deepEqual(shortest.values, [180, 180, 180], '3 s at 60 Hz');
    assert.deepEqual([shortest.min, shortest.q1, shortest.median, shortest.q3, shortest.max], [180, 180, 180, 180, 180]);
    const baseline = length.runs[0];
    const sorted = [...baseline.values].sort((x, y) => x - y);
    assert.equal(baseline.median, sorted[1]);
    assert.equal(baseline.q1, sorted[0] + 0.5 * (sorted[1] - sorted[0]), 'linear between the nearest two');
    for (const query of ['runs=' + report.id, `runs=${report.id},${report.id}`, `runs=${ids.join(',')}&correction=bonferroni`, `runs=${Array(11).fill(report.id).join(',')}`]) {
      const refused = await api.get(`/api/v1/runs/compare?${query}`);
      assert.equal(refused.status, 400, query);
      assert.equal(refused.json.error.details.parameter, query.includes('correction') ? 'correction' : 'runs', query);
    }
    assert.equal((await api.get(`/api/v1/runs/compare?runs=${report.id},${UNKNOWN_RUN}`)).status, 404);
  });

  it('GET /api/v1/runs/{id}/episodes?format=csv: one row per episode, a column per metric', async () => {
    const reply = await api.get(`/api/v1/runs/${report.id}/episodes?format=csv`);
    assert.equal(reply.status, 200);
    assert.match(reply.headers['content-type'], /^text\/csv/);
    assert.match(reply.headers['content-disposition'], new RegExp(`attachment; filename="${report.id}-episodes.csv"`));
    const [header, ...rows] = reply.body.trim().split('\n').map((line) => line.split(','));
    const metricKeys = (await api.get('/api/v1/metrics')).json.items.map((metric) => metric.key);
    assert.deepEqual(header, ['episode', 'seed', 'controller', 'status', 'termination', 'ticks', 'sim_time', ...metricKeys]);
    const episodes = (await api.get(`/api/v1/runs/${report.id}/episodes`)).json.items;
    assert.equal(rows.length, episodes.length);
    for (const [i, row] of rows.entries()) {
      assert.equal(row[0], episodes[i].id);
      assert.equal(Number(row[1]), episodes[i].seed);
      for (const [k, key] of metricKeys.entries()) {
        const value = episodes[i].metrics[key];
        if (value === null || value === undefined) assert.equal(row[7 + k], '', key);
        else assert.equal(Number(row[7 + k]), value, key);
      }
    }
    assert.equal((await api.get(`/api/v1/runs/${report.id}/episodes?format=xml`)).status, 400);
  });

  it('GET /api/v1/runs/compare: 400 naming the missing run, 404 for an unknown one', async () => {
    for (const [query, parameter] of [[`a=${report.id}`, 'b'], [`b=${report.id}`, 'a'], ['', 'a']]) {
      const reply = await api.get(`/api/v1/runs/compare${query && `?${query}`}`);
      assert.equal(reply.status, 400, query);
      assert.equal(reply.json.error.code, 'bad_request');
      assert.equal(reply.json.error.details.parameter, parameter, query);
    }
    for (const query of [`a=${UNKNOWN_RUN}&b=${report.id}`, `a=${report.id}&b=${UNKNOWN_RUN}`]) {
      const reply = await api.get(`/api/v1/runs/compare?${query}`);
      assert.equal(reply.status, 404, query);
      assert.equal(reply.json.error.code, 'not_found');
      assert.equal(reply.json.error.details.id, UNKNOWN_RUN);
    }
  });

  it('GET /api/v1/episodes/{id}/series: every series at 10 Hz, agreeing with the metrics', async () => {
    const id = report.episodes[0].episode_id;
    const episode = (await api.get(`/api/v1/episodes/${id}`)).json;
    const { series } = (await api.get('/api/v1/metrics')).json;
    const reply = await api.get(`/api/v1/episodes/${id}/series`);
    assert.equal(reply.status, 200);
    assert.equal(reply.json.episode, id);
    const { items } = reply.json;
    assert.deepEqual(items.map((item) => [item.name, item.unit]), series.map((s) => [s.name, s.unit]).sort(), 'every series, by name');
    const tickDt = episode.sim_time / episode.ticks;
    for (const item of items) {
      assert.equal(item.ticks.length, item.values.length, item.name);
      assert.equal(item.ticks[0], 0, item.name);
      assert.ok(item.ticks.slice(1).every((tick, i) => tick - item.ticks[i] === 6), `${item.name}: every 6 ticks at 60 Hz`);
      assert.ok(item.ticks.at(-1) <= episode.ticks && item.ticks.at(-1) > episode.ticks - 6, `${item.name}: to the last tick`);
      assert.ok(Math.abs(item.dt - 6 * tickDt) < 1e-12 && Math.abs(item.dt - 0.1) < 1e-9, `${item.name}: dt ${item.dt}`);
    }
    const named = Object.fromEntries(items.map((item) => [item.name, item.values]));
    // Hall's zones of the closest person's distance; no zone without a person.
    const zone = (d) => (d === null ? null : d < 0.45 ? 0 : d < 1.2 ? 1 : d < 3.6 ? 2 : 3);
    assert.deepEqual(named.proxemic_zone, named.distance_to_closest_person.map(zone));
    const present = (values) => values.filter((v) => v !== null);
    assert.ok(present(named.distance_to_closest_person).length > 0, 'the queue has people');
    assert.ok(Math.min(...present(named.distance_to_closest_person)) >= episode.metrics.minimum_distance_to_people - 1e-9, 'samples of the minimum');
    assert.ok(present(named.time_to_collision).every((t) => t >= 0));
    if (episode.metrics.min_time_to_collision !== null && present(named.time_to_collision).length) {
      assert.ok(Math.min(...present(named.time_to_collision)) >= episode.metrics.min_time_to_collision - 1e-9);
    }
    assert.ok([...named.robot_speed, ...named.social_force_on_robot].every((v) => v !== null && v >= 0));

    const one = await api.get(`/api/v1/episodes/${id}/series?name=time_to_collision&format=json`);
    assert.deepEqual(one.json, { episode: id, items: items.filter((item) => item.name === 'time_to_collision') });
  });

  it('GET /api/v1/episodes/{id}/series: one series as CSV, an empty cell for null', async () => {
    const id = report.episodes[0].episode_id;
    const episode = (await api.get(`/api/v1/episodes/${id}`)).json;
    const [json] = (await api.get(`/api/v1/episodes/${id}/series?name=time_to_collision`)).json.items;
    const csv = await api.get(`/api/v1/episodes/${id}/series?name=time_to_collision&format=csv`);
    assert.equal(csv.status, 200);
    assert.equal(csv.headers['content-type'], 'text/csv; charset=utf-8');
    const lines = csv.body.split('\n');
    assert.equal(lines.pop(), '', 'ends with a newline');
    assert.equal(lines[0], 'tick,time,time_to_collision');
    const rows = lines.slice(1).map((line) => line.split(','));
    assert.deepEqual(rows.map(([tick]) => Number(tick)), json.ticks);
    assert.deepEqual(rows.map(([, , value]) => (value === '' ? null : Number(value))), json.values);
    assert.ok(rows.some(([, , value]) => value === '') && rows.some(([, , value]) => value !== ''), 'the queue has both');
    const tickDt = episode.sim_time / episode.ticks;
    assert.ok(rows.every(([tick, time]) => Math.abs(Number(time) - Number(tick) * tickDt) < 1e-9));
  });

  it('GET /api/v1/episodes/{id}/series: 400 for an unknown name or format or CSV of everything, 404 for an unknown episode', async () => {
    const id = report.episodes[0].episode_id;
    for (const [query, parameter] of [['name=heart_rate', 'name'], ['format=csv', 'name'], ['format=xml', 'format'], ['name=robot_speed&format=xlsx', 'format']]) {
      const reply = await api.get(`/api/v1/episodes/${id}/series?${query}`);
      assert.equal(reply.status, 400, query);
      assert.equal(reply.json.error.code, 'bad_request', query);
      assert.equal(reply.json.error.details.parameter, parameter, query);
    }
    for (const query of ['', '?name=robot_speed&format=csv']) {
      const reply = await api.get(`/api/v1/episodes/${UNKNOWN_EPISODE}/series${query}`);
      assert.equal(reply.status, 404, query);
      assert.equal(reply.json.error.code, 'not_found', query);
    }
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
      const said = /1 run whose process ended marked interrupted/;
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

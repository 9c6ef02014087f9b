'use strict';
// Live sessions over REST: create, list, get, step, state, commands, sensors, poses, reset, delete,
// the session limit, and the errors of each.
const assert = require('node:assert/strict');
const { describe, it, before, after } = require('node:test');
const { api } = require('../lib/client');
const { cupOnASideTable } = require('../lib/fixtures');

const UNKNOWN_SESSION = `s${'0'.repeat(32)}`;

async function createSession(scenario, seed) {
  const reply = await api.post('/api/v1/sessions', seed === undefined ? { scenario } : { scenario, seed });
  assert.equal(reply.status, 201, reply.body);
  return reply.json;
}

describe('sessions', () => {
  // The bundled elevator scenario: humans ada, ben, ...; an HSR with the id "robot".
  let session;
  before(async () => {
    session = await createSession('elevator', 7);
  });
  after(async () => {
    await api.delete(`/api/v1/sessions/${session.id}`);
  });
  const at = (suffix = '') => `/api/v1/sessions/${session.id}${suffix}`;

  it('POST /api/v1/sessions: 201 at tick 0 with Location', async () => {
    const reply = await api.post('/api/v1/sessions', { scenario: 'pair_walking', seed: 3 });
    assert.equal(reply.status, 201);
    assert.match(reply.json.id, /^s[0-9a-f]{32}$/);
    assert.equal(reply.headers.location, `/api/v1/sessions/${reply.json.id}`);
    assert.equal(reply.json.tick, 0);
    assert.equal(reply.json.seed, 3);
    assert.equal(reply.json.status, 'running');
    assert.equal(reply.json.step.index, 0);
    assert.equal((await api.delete(reply.headers.location)).status, 204);
    const largest = await api.post('/api/v1/sessions', { scenario: 'pair_walking', seed: Number.MAX_SAFE_INTEGER });
    assert.equal(largest.status, 201);
    assert.equal(largest.json.seed, Number.MAX_SAFE_INTEGER);
    await api.delete(largest.headers.location);
  });

  it('POST /api/v1/sessions: 404 for an unknown scenario, 400 naming a bad field', async () => {
    const unknown = await api.post('/api/v1/sessions', { scenario: 'atlantis' });
    assert.equal(unknown.status, 404);
    assert.equal(unknown.json.error.details.pointer, '/scenario');
    const cases = [[{ scenario: 'elevator', seed: -1 }, '/seed'], [{ scenario: 'elevator', seed: 1.5 }, '/seed'],
      [{ scenario: 'elevator', colour: 'red' }, '/colour'], [{}, '/scenario']];
    for (const [body, pointer] of cases) {
      const reply = await api.post('/api/v1/sessions', body);
      assert.equal(reply.status, 400, JSON.stringify(body));
      assert.equal(reply.json.error.details.pointer, pointer, JSON.stringify(body));
    }
    assert.equal((await api.request('POST', '/api/v1/sessions', { body: '{"scenario": ' })).status, 400);
    assert.equal((await api.request('POST', '/api/v1/sessions', { body: '["elevator"]' })).status, 400);
  });

  it('GET /api/v1/sessions lists the live sessions', async () => {
    const reply = await api.get('/api/v1/sessions');
    assert.equal(reply.status, 200);
    assert.ok(reply.json.items.some((item) => item.id === session.id));
  });

  it('GET /api/v1/sessions/{id}: the status; 404 for an unknown id', async () => {
    const reply = await api.get(at());
    assert.equal(reply.status, 200);
    assert.equal(reply.json.scenario, 'elevator');
    assert.equal(reply.json.seed, 7);
    assert.equal((await api.get(`/api/v1/sessions/${UNKNOWN_SESSION}`)).status, 404);
  });

  it('POST /api/v1/sessions/{id}/step: n steps with their events; 1 without a body', async () => {
    const reply = await api.post(at('/step'), { n: 30 });
    assert.equal(reply.status, 200);
    assert.equal(reply.json.tick, 30);
    assert.equal(reply.json.terminated, false);
    assert.equal(reply.json.truncated, false);
    const one = await api.request('POST', at('/step'));
    assert.equal(one.status, 200);
    assert.equal(one.json.tick, 31);
  });

  it('POST /api/v1/sessions/{id}/step stops at the scenario\'s end: finished, terminated or truncated', async () => {
    const short = await createSession('pair_walking', 1);
    const reply = await api.post(`/api/v1/sessions/${short.id}/step`, { n: 100000 });
    await api.delete(`/api/v1/sessions/${short.id}`);
    assert.equal(reply.status, 200);
    assert.ok(reply.json.tick < 100000);
    assert.equal(reply.json.status, 'finished');
    assert.equal(reply.json.step, null);
    assert.equal(reply.json.terminated, reply.json.termination === 'scenario_end');
    assert.equal(reply.json.truncated, reply.json.termination === 'timeout');
    assert.ok(reply.json.terminated !== reply.json.truncated);
  });

  it('POST /api/v1/sessions/{id}/step: 400 for n out of range, 404 for an unknown session', async () => {
    for (const n of [0, 100001, 'ten']) {
      const reply = await api.post(at('/step'), { n });
      assert.equal(reply.status, 400, String(n));
      assert.equal(reply.json.error.details.pointer, '/n');
    }
    assert.equal((await api.post(`/api/v1/sessions/${UNKNOWN_SESSION}/step`, { n: 1 })).status, 404);
  });

  it('equal scenario, seed and steps give equal state hashes', async () => {
    const [a, b] = [await createSession('corridor_passing', 42), await createSession('corridor_passing', 42)];
    const hashes = [];
    for (const id of [a.id, b.id]) {
      hashes.push((await api.post(`/api/v1/sessions/${id}/step`, { n: 50 })).json.state_hash);
      await api.delete(`/api/v1/sessions/${id}`);
    }
    assert.match(hashes[0], /^[0-9a-f]{16}$/);
    assert.equal(hashes[0], hashes[1]);
  });

  it('GET /api/v1/sessions/{id}/state: agents, requests, events since a tick', async () => {
    const reply = await api.get(at('/state?events_since=0'));
    assert.equal(reply.status, 200);
    const kinds = Object.fromEntries(reply.json.agents.map((agent) => [agent.id, agent.kind]));
    assert.equal(kinds.ada, 'human');
    assert.equal(kinds.robot, 'robot');
    assert.equal((await api.get(at('/state?events_since=-1'))).status, 400);
    assert.equal((await api.get(`/api/v1/sessions/${UNKNOWN_SESSION}/state`)).status, 404);
  });

  it('POST /api/v1/sessions/{id}/commands gives a whole list', async () => {
    const reply = await api.post(at('/commands'), {
      commands: [{ human: 'ada', command: 'wait 1' }, { robot: 'robot', velocity: { linear: 0.1, angular: 0 } },
        { robot: 'robot', joints: { group: 'arm', positions: [0.1, 0, 0, 0, 0, 0] } }, { robot: 'robot', gripper: 'close' }],
    });
    assert.equal(reply.status, 200);
    assert.equal(reply.json.applied, 4);
    const state = await api.get(at(`/state?events_since=${reply.json.tick}`));
    assert.ok(state.json.events.some((event) => event.kind === 'command' && event.data.text === 'wait 1'), 'event "command"');
  });

  // "The status after the steps, with the events they produced": each event in exactly one step reply,
  // those of the session's start and of commands in the next one.
  it('POST /step: consecutive replies share no event and together hold every event', async () => {
    const own = await createSession('elevator', 2);
    const ownAt = (suffix) => `/api/v1/sessions/${own.id}${suffix}`;
    const first = await api.post(ownAt('/step'), { n: 1 });
    await api.post(ownAt('/commands'), { commands: [{ human: 'ada', command: 'wait 1' }] });
    const second = await api.post(ownAt('/step'), { n: 10 });
    const third = await api.post(ownAt('/step'), { n: 10 });
    const all = (await api.get(ownAt('/state?events_since=0'))).json.events;
    await api.delete(ownAt(''));
    assert.ok(first.json.events.some((event) => event.tick === 0), "the start's events come with the first step");
    assert.ok(second.json.events.some((event) => event.kind === 'command'), "the command's event comes with the next step");
    const seen = new Set(first.json.events.map((event) => JSON.stringify(event)));
    assert.deepEqual(second.json.events.filter((event) => seen.has(JSON.stringify(event))), []);
    assert.deepEqual([...first.json.events, ...second.json.events, ...third.json.events], all);
  });

  it('POST /api/v1/sessions/{id}/commands: 400 names the wrong command, none is given', async () => {
    const reply = await api.post(at('/commands'), { commands: [{ human: 'ada', command: 'walk 1 1' }, { robot: 'robot', gripper: 'squeeze' }] });
    assert.equal(reply.status, 400);
    assert.equal(reply.json.error.details.pointer, '/commands/1/gripper');
    const state = await api.get(at('/state?events_since=0'));
    assert.ok(!state.json.events.some((event) => event.kind === 'command' && event.data.text === 'walk 1 1'), 'ada got no command');
    assert.equal((await api.post(at('/commands'), { orders: [] })).status, 400);
    assert.equal((await api.post(`/api/v1/sessions/${UNKNOWN_SESSION}/commands`, { commands: [] })).status, 404);
  });

  it('GET /api/v1/sessions/{id}/robots/{robot}/sensors: lasers with REP 117 ranges; 404 for a non-robot', async () => {
    const reply = await api.get(at('/robots/robot/sensors'));
    assert.equal(reply.status, 200);
    assert.equal(reply.json.robot, 'robot');
    assert.ok(reply.json.lasers.length > 0);
    assert.ok(reply.json.lasers.every((laser) => laser.ranges.length > 0));
    assert.ok(reply.json.joints.some((joint) => joint.name === 'arm_lift_joint'));
    assert.equal((await api.get(at('/robots/ada/sensors'))).status, 404);
    assert.equal((await api.get(at('/robots/nobody/sensors'))).status, 404);
  });

  it('GET /api/v1/sessions/{id}/poses and PUT /poses/{name} move an agent', async () => {
    const poses = await api.get(at('/poses'));
    assert.equal(poses.status, 200);
    const ada = poses.json.agents.find((agent) => agent.id === 'ada');
    const placed = await api.put(at('/poses/ada'), { x: ada.x, y: ada.y, yaw: 1.0 });
    assert.equal(placed.status, 200);
    assert.equal(placed.json.agents.find((agent) => agent.id === 'ada').yaw, 1.0);
  });

  it('PUT /api/v1/sessions/{id}/poses/{name}: 400 for a tilted agent or a missing y, 404 for an unknown name', async () => {
    const tilted = await api.put(at('/poses/ada'), { x: 1, y: 1, z: 0.5 });
    assert.equal(tilted.status, 400);
    assert.equal(tilted.json.error.details.pointer, '/z');
    assert.equal((await api.put(at('/poses/ada'), { x: 1 })).status, 400);
    assert.equal((await api.put(at('/poses/nobody'), { x: 1, y: 1 })).status, 404);
  });

  it('POST /api/v1/sessions/{id}/reset starts again at tick 0 with a new seed', async () => {
    const reply = await api.post(at('/reset'), { seed: 9 });
    assert.equal(reply.status, 200);
    assert.equal(reply.json.tick, 0);
    assert.equal(reply.json.seed, 9);
    assert.equal((await api.post(at('/reset'), { seed: 'nine' })).status, 400);
    assert.equal((await api.post(`/api/v1/sessions/${UNKNOWN_SESSION}/reset`, {})).status, 404);
  });

  it('POST /api/v1/sessions beyond --max-sessions is 503 with Retry-After', async () => {
    const created = [];
    let refused;
    while (!refused && created.length < 20) {
      const reply = await api.post('/api/v1/sessions', { scenario: 'pair_walking' });
      if (reply.status === 201) created.push(reply.json.id);
      else refused = reply;
    }
    for (const id of created) await api.delete(`/api/v1/sessions/${id}`);
    assert.ok(refused, 'no 503 after 20 sessions');
    assert.equal(refused.status, 503);
    assert.equal(refused.headers['retry-after'], '10');
    assert.equal(refused.json.error.code, 'unavailable');
  });

  it('DELETE /api/v1/sessions/{id}: 204, then 404', async () => {
    const doomed = await createSession('queue');
    assert.equal((await api.delete(`/api/v1/sessions/${doomed.id}`)).status, 204);
    assert.equal((await api.delete(`/api/v1/sessions/${doomed.id}`)).status, 404);
    assert.equal((await api.get(`/api/v1/sessions/${doomed.id}`)).status, 404);
  });
});

describe('a session with a cup in the HSR\'s open hand', () => {
  let scenario;
  before(async () => {
    const uploaded = await api.post('/api/v1/scenarios', cupOnASideTable);
    assert.equal(uploaded.status, 201);
    scenario = uploaded.json.summary.id;
  });

  it('GET /robots/{robot}/sensors: the fingers touch the cup at the first tick', async () => {
    const cup = await createSession(scenario);
    await api.post(`/api/v1/sessions/${cup.id}/step`, { n: 1 });
    const { contacts } = (await api.get(`/api/v1/sessions/${cup.id}/robots/hsr/sensors`)).json;
    assert.deepEqual(contacts, [{ with: 'cup', part: 'cup' }]);
    await api.delete(`/api/v1/sessions/${cup.id}`);
  });

  it('PUT /poses/{name} places the cup at rest; 409 once the gripper holds it', async () => {
    const cup = await createSession(scenario);
    const cupAt = (suffix) => `/api/v1/sessions/${cup.id}${suffix}`;
    const { pose } = cupOnASideTable.objects[0];
    const placed = await api.put(cupAt('/poses/cup'), pose);
    assert.equal(placed.status, 200);
    assert.equal(placed.json.objects.find((object) => object.name === 'cup').z, pose.z);
    await api.post(cupAt('/step'), { n: 30 });
    await api.post(cupAt('/commands'), { commands: [{ robot: 'hsr', gripper: 'close' }] });
    const stepped = await api.post(cupAt('/step'), { n: 120 });
    assert.ok(stepped.json.events.some((event) => event.kind === 'grasp'), 'the HSR grasps the cup');
    assert.equal((await api.get(cupAt('/robots/hsr/sensors'))).json.gripper_closed, true);
    const refused = await api.put(cupAt('/poses/cup'), { x: 5, y: 5, z: 0.05 });
    assert.equal(refused.status, 409);
    assert.equal(refused.json.error.code, 'conflict');
    await api.delete(cupAt(''));
  });
});

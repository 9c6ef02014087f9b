'use strict';
// Scenarios: the paged list, one scenario, its thumbnail, validate, upload (JSON and XML) and bad input.
const assert = require('node:assert/strict');
const crypto = require('node:crypto');
const { describe, it } = require('node:test');
const { api } = require('../lib/client');
const { cupOnASideTable, fixture } = require('../lib/fixtures');
const { decodePng } = require('../lib/images');

const BUNDLED = ['apartment', 'apartment_search', 'approach_human', 'approach_human_apartment', 'circle_crossing', 'conversation_group', 'corridor_navigation', 'corridor_passing', 'crossing_navigation', 'elevator', 'family_day',
  'follow_human', 'mirror_gesture', 'pair_walking', 'perpendicular_crossing', 'pick_and_place', 'queue', 'tea_break'];

// The overview's background: RGB 0.82, 0.86, 0.9 (× 255, rounded), opaque.
const BACKGROUND = [209, 219, 230, 255];

/** A thumbnail: 200, an RGBA PNG that caches may keep an hour, decoded. */
async function thumbnail(id, query = '') {
  const reply = await api.get(`/api/v1/scenarios/${id}/thumbnail${query}`);
  assert.equal(reply.status, 200, `${id}${query}: ${reply.body.slice(0, 300)}`);
  assert.equal(reply.headers['content-type'], 'image/png');
  assert.equal(reply.headers['cache-control'], 'max-age=3600');
  const image = decodePng(reply.bytes);
  assert.deepEqual([image.bitDepth, image.colourType], [8, 6], 'an 8-bit RGBA PNG');
  return image;
}

/** The RGBA of pixel (x, y), y from the top row. */
const pixel = (image, x, y) => [...image.samples.subarray(4 * (y * image.width + x), 4 * (y * image.width + x) + 4)];

/** Where two images of one size differ: the bounding box of the differing pixels, or undefined. */
function differences(a, b) {
  let box;
  for (let i = 0; i < a.width * a.height; i++) {
    if (a.samples.subarray(4 * i, 4 * i + 4).every((value, k) => value === b.samples[4 * i + k])) continue;
    const [x, y] = [i % a.width, Math.floor(i / a.width)];
    box = box ? { left: Math.min(box.left, x), right: Math.max(box.right, x), top: Math.min(box.top, y), bottom: Math.max(box.bottom, y) } : { left: x, right: x, top: y, bottom: y };
  }
  return box;
}

/** The cup scenario with a human placed outside the map and a step naming an unknown agent. */
function brokenScenario() {
  const broken = structuredClone(cupOnASideTable);
  broken.humans = [{ id: 'ana', start: { x: 50, y: 50 } }];
  broken.steps[0].actions[0].agent = 'nobody';
  return broken;
}

describe('scenarios', () => {
  it('GET /api/v1/scenarios lists the bundled scenarios in id order on one page', async () => {
    const reply = await api.get('/api/v1/scenarios?limit=200');
    assert.equal(reply.status, 200);
    const bundled = reply.json.items.filter((item) => item.origin === 'bundled').map((item) => item.id);
    assert.deepEqual(bundled, BUNDLED);
    assert.equal(reply.json.next_cursor, null);
  });

  it('GET /api/v1/scenarios pages follow next_cursor', async () => {
    const first = await api.get('/api/v1/scenarios?limit=2');
    assert.equal(first.status, 200);
    assert.equal(first.json.items.length, 2);
    assert.equal(first.json.next_cursor, first.json.items[1].id);
    const second = await api.get(`/api/v1/scenarios?limit=2&cursor=${first.json.next_cursor}`);
    assert.equal(second.status, 200);
    assert.ok(second.json.items[0].id > first.json.next_cursor);
  });

  it('GET /api/v1/scenarios with a limit out of range or not a number is 400', async () => {
    for (const limit of ['0', '201', 'ten']) {
      const reply = await api.get(`/api/v1/scenarios?limit=${limit}`);
      assert.equal(reply.status, 400, limit);
      assert.equal(reply.json.error.code, 'bad_request');
    }
  });

  it('GET /api/v1/scenarios/{id}: the native document; 404 for an unknown id', async () => {
    const elevator = await api.get('/api/v1/scenarios/elevator');
    assert.equal(elevator.status, 200);
    assert.ok(Array.isArray(elevator.json.humans));
    const unknown = await api.get('/api/v1/scenarios/u0000');
    assert.equal(unknown.status, 404);
    assert.equal(unknown.json.error.code, 'not_found');
  });

  it('GET /api/v1/scenarios/{id}/thumbnail: 320 × 240 by default, the overview of a fresh seed-0 session, one per scenario', async () => {
    const elevator = await thumbnail('elevator');
    assert.deepEqual([elevator.width, elevator.height], [320, 240]);
    assert.notDeepEqual(pixel(elevator, 160, 120), BACKGROUND, 'the map covers the centre');
    assert.deepEqual(pixel(elevator, 0, 0), BACKGROUND, 'a corner is in the margin around the map');
    const apartment = await thumbnail('apartment');
    assert.ok(differences(elevator, apartment), 'two scenarios, two thumbnails');
    // The scenario at its start, as the overview draws it.
    const session = (await api.post('/api/v1/sessions', { scenario: 'elevator', seed: 0 })).json;
    try {
      const frame = await api.get(`/api/v1/sessions/${session.id}/frames/overview?width=320&height=240`);
      assert.deepEqual(decodePng(frame.bytes).samples, elevator.samples, 'GET .../frames/overview of a fresh session');
    } finally {
      await api.delete(`/api/v1/sessions/${session.id}`);
    }
  });

  it('GET /api/v1/scenarios/{id}/world: the elevator as a map view draws it; 404 for an unknown id', async () => {
    const reply = await api.get('/api/v1/scenarios/elevator/world');
    assert.equal(reply.status, 200);
    const world = reply.json;
    const document = (await api.get('/api/v1/scenarios/elevator')).json;
    assert.equal(world.id, 'elevator');
    assert.equal(world.name, document.name);
    // Every agent of the document, in order: humans then robots, each at its start.
    const agents = [...document.humans.map((h) => [h.id, 'human']), ...document.robots.map((r) => [r.id, 'robot'])];
    assert.deepEqual(world.agents.map((a) => [a.id, a.kind]), agents);
    const robot = world.agents.find((a) => a.kind === 'robot');
    assert.equal(robot.model, 'hsr');
    assert.equal(robot.type, null);
    assert.deepEqual([robot.start.x, robot.start.y], [document.robots[0].start.x, document.robots[0].start.y]);
    assert.deepEqual(world.locations.map((l) => l.name).sort(), Object.keys(document.locations).sort());
    assert.ok(world.doors.length >= 2 && world.elevators.length === 1, 'the elevator and its doors');
    assert.ok(world.walls.length > 0, 'the map from an image as wall segments');
    // Everything lies within the bounds.
    const [[x0, y0], [x1, y1]] = [world.bounds.min, world.bounds.max];
    for (const agent of world.agents) assert.ok(agent.start.x >= x0 && agent.start.x <= x1 && agent.start.y >= y0 && agent.start.y <= y1, agent.id);
    const apartment = (await api.get('/api/v1/scenarios/apartment/world')).json;
    const chair = apartment.obstacles.find((o) => o.name === 'chair_1');
    assert.equal(chair.mesh, 'chair');
    assert.equal(chair.polygon.length, 4);
    assert.ok(apartment.obstacles.some((o) => o.name.startsWith('wall ') && o.mesh === null), 'walls come as obstacles too');
    assert.deepEqual(world.objects, [], 'the elevator has no movable objects');
    // pick_and_place's objects, each as its document gives it.
    const kitchen = (await api.get('/api/v1/scenarios/pick_and_place/world')).json;
    const objects = (await api.get('/api/v1/scenarios/pick_and_place')).json.objects;
    assert.deepEqual(kitchen.objects.map((o) => o.name), objects.map((o) => o.name));
    for (const [object, given] of kitchen.objects.map((o, i) => [o, objects[i]])) {
      assert.equal(object.shape.kind, given.shape.kind, object.name);
      assert.equal(object.mass, given.mass, object.name);
      assert.deepEqual([object.pose.x, object.pose.y, object.pose.z], [given.pose.x, given.pose.y, given.pose.z ?? object.pose.z], object.name);
    }
    const unknown = await api.get('/api/v1/scenarios/no_such_scenario/world');
    assert.equal(unknown.status, 404);
    assert.equal(unknown.json.error.details.id, 'no_such_scenario');
  });

  it('GET .../thumbnail: width and height from 16 to 1024; one given alone keeps 4:3', async () => {
    for (const [query, size] of [['?width=100&height=100', [100, 100]], ['?width=1024&height=16', [1024, 16]], ['?width=16&height=1024', [16, 1024]],
      ['?width=64', [64, 48]], ['?height=48', [64, 48]], ['?width=16', [16, 16]], ['?height=1024', [1024, 1024]]]) {
      const image = await thumbnail('queue', query);
      assert.deepEqual([image.width, image.height], size, query);
    }
  });

  it('GET .../thumbnail of an uploaded scenario: the map from above, x to the right and y up', async () => {
    // The cup scenario (an 11 m square map), and the same with a crate near its top right corner.
    const withCrate = structuredClone(cupOnASideTable);
    withCrate.world.obstacles.push({ name: 'crate', box: { x: 8.5, y: 8, length: 1, width: 1 }, height: 0.5 });
    const upload = async (scenario) => {
      const reply = await api.post('/api/v1/scenarios', scenario);
      assert.equal(reply.status, 201);
      return reply.json.summary.id;
    };
    const plain = await thumbnail(await upload(cupOnASideTable));
    const crated = await thumbnail(await upload(withCrate));
    assert.deepEqual([plain.width, plain.height], [320, 240]);
    assert.notDeepEqual(pixel(plain, 160, 120), BACKGROUND, 'the floor at the centre');
    const crate = differences(plain, crated);
    assert.ok(crate, 'the crate is seen');
    assert.ok(crate.left > 160 && crate.bottom < 120, `the crate is in the top right quarter: ${JSON.stringify(crate)}`);
  });

  it('GET .../thumbnail: 404 naming an unknown scenario, 400 naming a bad width or height', async () => {
    const unknown = await api.get('/api/v1/scenarios/u0000/thumbnail');
    assert.equal(unknown.status, 404);
    assert.equal(unknown.json.error.code, 'not_found');
    assert.equal(unknown.json.error.details.id, 'u0000');
    for (const [query, parameter] of [['width=15', 'width'], ['width=1025', 'width'], ['width=64.5', 'width'], ['width=wide', 'width'],
      ['height=0', 'height'], ['height=2048', 'height']]) {
      const reply = await api.get(`/api/v1/scenarios/elevator/thumbnail?${query}`);
      assert.equal(reply.status, 400, query);
      assert.equal(reply.json.error.code, 'bad_request', query);
      assert.equal(reply.json.error.details.parameter, parameter, query);
    }
  });

  it('POST /api/v1/scenarios/validate: a valid scenario, with its summary', async () => {
    const reply = await api.post('/api/v1/scenarios/validate', cupOnASideTable);
    assert.equal(reply.status, 200);
    assert.deepEqual(reply.json.errors, []);
    assert.equal(reply.json.valid, true);
    assert.equal(reply.json.format, 'json');
    assert.deepEqual(reply.json.summary.robots, [{ id: 'hsr', model: 'hsr' }]);
  });

  it('POST /api/v1/scenarios/validate: every error with its JSON pointer', async () => {
    const reply = await api.post('/api/v1/scenarios/validate', brokenScenario());
    assert.equal(reply.status, 200);
    assert.equal(reply.json.valid, false);
    const pointers = reply.json.errors.map((error) => error.pointer);
    assert.ok(pointers.includes('/humans/0/start'), pointers.join(', '));
    assert.ok(pointers.includes('/steps/0/actions/0/agent'), pointers.join(', '));
  });

  it('POST /api/v1/scenarios/validate: IMHuS XML by ?format=, with XML errors by line', async () => {
    const reply = await api.request('POST', '/api/v1/scenarios/validate?format=imhus', { body: fixture('imhus/duo.xml'), contentType: 'application/xml' });
    assert.equal(reply.status, 200);
    assert.equal(reply.json.format, 'imhus_xml');
    assert.equal(reply.json.valid, true, JSON.stringify(reply.json.errors));
    const broken = await api.request('POST', '/api/v1/scenarios/validate?format=imhus', { body: '<agents>\n<human id="a"/>\n</oops>', contentType: 'application/xml' });
    assert.equal(broken.status, 200);
    assert.equal(broken.json.valid, false);
    assert.ok(broken.json.errors.some((error) => Number.isInteger(error.line)), JSON.stringify(broken.json.errors));
  });

  it('POST /api/v1/scenarios/validate with an unknown ?format= is 400', async () => {
    const reply = await api.post('/api/v1/scenarios/validate?format=yaml', cupOnASideTable);
    assert.equal(reply.status, 400);
    assert.equal(reply.json.error.details.parameter, 'format');
  });

  it('POST /api/v1/scenarios stores a valid scenario: 201, Location, SHA-256 of the source', async () => {
    const source = JSON.stringify({ ...cupOnASideTable, name: 'cup_stored' });
    const reply = await api.request('POST', '/api/v1/scenarios', { body: source, contentType: 'application/json' });
    assert.equal(reply.status, 201);
    const { summary } = reply.json;
    assert.match(summary.id, /^u[0-9a-f]{32}$/);
    assert.equal(summary.origin, 'uploaded');
    assert.equal(summary.sha256, crypto.createHash('sha256').update(source).digest('hex'));
    assert.equal(reply.headers.location, `/api/v1/scenarios/${summary.id}`);
    const stored = await api.get(reply.headers.location);
    assert.equal(stored.status, 200);
    assert.equal(stored.json.name, 'cup_stored');
  });

  it('POST /api/v1/scenarios with content uploaded before is 200 with that upload; DELETE …/scenarios/{id} deletes an upload no run ran', async () => {
    const scenario = { ...cupOnASideTable, name: 'cup_to_delete' };
    const first = await api.post('/api/v1/scenarios', scenario);
    assert.equal(first.status, 201, first.body);
    assert.equal(first.json.existed, false);
    const again = await api.post('/api/v1/scenarios', scenario);
    assert.equal(again.status, 200, again.body);
    assert.equal(again.json.existed, true);
    assert.equal(again.json.summary.id, first.json.summary.id);
    assert.equal(again.headers.location, first.headers.location);
    const id = first.json.summary.id;
    const deleted = await api.delete(`/api/v1/scenarios/${id}`);
    assert.equal(deleted.status, 200);
    assert.deepEqual(deleted.json, { id, outcome: 'deleted' });
    assert.equal((await api.get(`/api/v1/scenarios/${id}`)).status, 404);
    const listed = await api.get('/api/v1/scenarios?limit=200');
    assert.ok(!listed.json.items.some((item) => item.id === id));
    assert.equal((await api.delete(`/api/v1/scenarios/${id}`)).status, 404);
    const bundled = await api.delete('/api/v1/scenarios/elevator');
    assert.equal(bundled.status, 409);
    assert.match(bundled.json.error.message, /bundled/);
    const anew = await api.post('/api/v1/scenarios', scenario);
    assert.equal(anew.status, 201, 'deleted: stored anew');
    assert.notEqual(anew.json.summary.id, id);
    assert.equal((await api.delete(`/api/v1/scenarios/${anew.json.summary.id}`)).json.outcome, 'deleted');
  });

  it('POST /api/v1/scenarios takes Pedsim XML by its content', async () => {
    const reply = await api.request('POST', '/api/v1/scenarios', { body: fixture('pedsim/hall.xml'), contentType: 'application/xml' });
    assert.equal(reply.status, 201);
    assert.equal(reply.json.summary.format, 'pedsim_xml');
  });

  it('POST /api/v1/scenarios refuses an invalid scenario with every error, storing nothing', async () => {
    const before = await api.get('/api/v1/scenarios?limit=200');
    const reply = await api.post('/api/v1/scenarios', brokenScenario());
    assert.equal(reply.status, 400);
    assert.equal(reply.json.error.details.format, 'json');
    assert.ok(reply.json.error.details.errors.length >= 2);
    const after = await api.get('/api/v1/scenarios?limit=200');
    assert.equal(after.json.items.length, before.json.items.length);
  });

  it('POST /api/v1/scenarios: a body over the limit is 413 before it is sent', async () => {
    const reply = await api.request('POST', '/api/v1/scenarios', { headers: { 'content-length': String(5 * 1024 * 1024) } });
    assert.equal(reply.status, 413);
    assert.equal(reply.json.error.code, 'payload_too_large');
  });

  it('POST /api/v1/scenarios refuses malformed and too deeply nested JSON with 400', async () => {
    const malformed = await api.request('POST', '/api/v1/scenarios', { body: '{"name": "x",\n oops}' });
    assert.equal(malformed.status, 400);
    const deep = await api.request('POST', '/api/v1/scenarios', { body: `${'['.repeat(65)}${']'.repeat(65)}` });
    assert.equal(deep.status, 400);
    assert.equal(deep.json.error.details.limit, 64);
  });
});

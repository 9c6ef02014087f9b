'use strict';
// A session's WebSocket (api/asyncapi.yaml): each message answered once, in order; wrong messages get
// an error and the socket stays open; binary laser and camera frames; state frames pushed to subscribers,
// each followed by a camera frame when the subscription has a camera; realtime sessions; an unknown session, a missing token or ticket and a foreign Origin are refused
// before the upgrade.
const assert = require('node:assert/strict');
const { describe, it, before, after } = require('node:test');
const { decodeSceneFrame } = require('../lib/scene_frame');
const { api, Client } = require('../lib/client');
const { LAYOUT, layoutInSpec, decodeLaserFrame } = require('../lib/laser_frame');
const cameraFrame = require('../lib/camera_frame');
const { decodeNpy } = require('../lib/images');
const { startServer } = require('../lib/server');
const { asyncapi } = require('../lib/contract');

const sleep = (ms) => new Promise((resolve) => { setTimeout(resolve, ms); });

/** A JSON range as the number it stands for. */
const rangeValue = (range) => (range === 'inf' ? Infinity : range === '-inf' ? -Infinity : range);

describe('session WebSocket', () => {
  let session;
  let socket;
  before(async () => {
    const created = await api.post('/api/v1/sessions', { scenario: 'elevator', seed: 1 });
    assert.equal(created.status, 201);
    session = created.json;
    socket = await api.openSocket(session.id);
  });
  after(async () => {
    socket.close();
    await api.delete(`/api/v1/sessions/${session.id}`);
  });

  it('step advances n steps and answers with the status and events', async () => {
    const reply = await socket.send({ type: 'step', n: 5 });
    assert.equal(reply.type, 'step');
    assert.equal(reply.tick, 5);
    assert.equal(reply.terminated, false);
    assert.equal(reply.observation.length, 48);
    assert.equal(reply.reward, 0);
    assert.deepEqual(reply.info, { tick: 5, time: reply.time });
    assert.equal((await socket.send({ type: 'step' })).tick, 6);
  });

  it('step with an action gives it to the robot; a wrong action is an error naming it', async () => {
    const own = (await api.post('/api/v1/sessions', { scenario: 'elevator', seed: 4 })).json;
    const ownSocket = await api.openSocket(own.id);
    const start = await ownSocket.send({ type: 'step', action: [0, 0] });
    const moved = await ownSocket.send({ type: 'step', n: 60, action: [1.0, 0] });
    const wrong = await ownSocket.send({ type: 'step', action: [1, 'x'] });
    const short = await ownSocket.send({ type: 'step', action: [1] });
    ownSocket.close();
    await api.delete(`/api/v1/sessions/${own.id}`);
    assert.ok(Math.hypot(moved.observation[0] - start.observation[0], moved.observation[1] - start.observation[1]) > 0.05, 'it drove');
    assert.equal(wrong.type, 'error');
    assert.equal(wrong.error.details.pointer, '/action/1');
    assert.equal(short.error.details.pointer, '/action');
  });

  it('step_many steps several sessions, each by its action, answered once in the order asked; a bad list is an error naming its place', async () => {
    const others = [];
    for (const seed of [5, 6]) others.push((await api.post('/api/v1/sessions', { scenario: 'elevator', seed })).json);
    const reply = await socket.send({ type: 'step_many', sessions: others.map((other) => other.id), actions: [[0.5, 0], null], n: 3 });
    const wrong = await socket.send({ type: 'step_many', sessions: [others[0].id, others[0].id] });
    for (const other of others) await api.delete(`/api/v1/sessions/${other.id}`);
    assert.equal(reply.type, 'step_many');
    assert.deepEqual(reply.results.map((result) => result.id), others.map((other) => other.id));
    assert.deepEqual(reply.results.map((result) => result.tick), [3, 3]);
    assert.equal(wrong.type, 'error');
    assert.equal(wrong.error.details.pointer, '/sessions/1');
  });

  it('commands gives a list; a wrong one is an error naming it', async () => {
    const reply = await socket.send({ type: 'commands', commands: [{ human: 'ada', command: 'wait 1' }] });
    assert.equal(reply.type, 'commands');
    assert.equal(reply.applied, 1);
    const wrong = await socket.send({ type: 'commands', commands: [{ human: 'nobody', command: 'wait 1' }] });
    assert.equal(wrong.type, 'error');
    assert.equal(wrong.error.details.pointer, '/commands/0/human');
  });

  it('snapshot keeps this point; restore goes back to it, bit for bit; an unknown one is an error naming it', async () => {
    const snapshot = await socket.send({ type: 'snapshot' });
    assert.equal(snapshot.type, 'snapshot');
    const stepped = await socket.send({ type: 'step', n: 12 });
    const restored = await socket.send({ type: 'restore', snapshot: snapshot.snapshot });
    assert.equal(restored.type, 'restore');
    assert.equal(restored.tick, snapshot.tick);
    assert.equal(restored.state_hash, snapshot.state_hash);
    assert.equal((await socket.send({ type: 'step', n: 12 })).state_hash, stepped.state_hash);
    const wrong = await socket.send({ type: 'restore', snapshot: 'snap-0' });
    assert.equal(wrong.type, 'error');
    assert.equal(wrong.error.details.pointer, '/snapshot');
    // Back to the snapshot's tick for the tests that follow.
    assert.equal((await socket.send({ type: 'restore', snapshot: snapshot.snapshot })).tick, snapshot.tick);
  });

  it('seek goes back to a tick bit for bit and forth by ticks; a tick out of range is an error at /tick', async () => {
    const start = await socket.send({ type: 'state', events_since: 0 });
    const stepped = await socket.send({ type: 'step', n: 8 });
    const back = await socket.send({ type: 'seek', tick: start.tick });
    assert.equal(back.type, 'seek');
    assert.equal(back.state_hash, start.state_hash);
    const forth = await socket.send({ type: 'seek', tick: stepped.tick });
    assert.equal(forth.state_hash, stepped.state_hash);
    const wrong = await socket.send({ type: 'seek', tick: -3 });
    assert.equal(wrong.type, 'error');
    assert.equal(wrong.error.details.pointer, '/tick');
    // Back to where it was for the tests that follow.
    assert.equal((await socket.send({ type: 'seek', tick: start.tick })).tick, start.tick);
  });

  it('scene answers with a binary scene frame, the same bytes as GET …/scene', async () => {
    const frame = await socket.send({ type: 'scene' });
    assert.ok(Buffer.isBuffer(frame));
    const rest = await api.get(`/api/v1/sessions/${session.id}/scene`);
    assert.ok(frame.equals(rest.bytes), 'the same frame over both');
    assert.ok(decodeSceneFrame(frame).parts.length > 0);
    const all = await socket.send({ type: 'scene', all: true });
    assert.ok(decodeSceneFrame(all).parts.length > decodeSceneFrame(frame).parts.length);
    const wrong = await socket.send({ type: 'scene', all: 1 });
    assert.equal(wrong.type, 'error');
    assert.equal(wrong.error.details.pointer, '/all');
  });

  it('state answers with agents and the events since a tick', async () => {
    const reply = await socket.send({ type: 'state', events_since: 0 });
    assert.equal(reply.type, 'state');
    assert.equal(reply.tick, 6);
    assert.ok(reply.agents.some((agent) => agent.id === 'robot'));
  });

  it('sensors answers with a robot\'s readings; an unknown robot is an error', async () => {
    const reply = await socket.send({ type: 'sensors', robot: 'robot' });
    assert.equal(reply.type, 'sensors');
    assert.ok(reply.lasers.length > 0);
    const unknown = await socket.send({ type: 'sensors', robot: 'nobody' });
    assert.equal(unknown.type, 'error');
    assert.equal(unknown.error.code, 'not_found');
  });

  it('step replies hold each event once, those of the start and of commands included', async () => {
    const own = await api.post('/api/v1/sessions', { scenario: 'elevator', seed: 2 });
    const ownSocket = await api.openSocket(own.json.id);
    const first = await ownSocket.send({ type: 'step' });
    await ownSocket.send({ type: 'commands', commands: [{ human: 'ada', command: 'wait 1' }] });
    const second = await ownSocket.send({ type: 'step', n: 10 });
    const third = await ownSocket.send({ type: 'step', n: 10 });
    const all = (await ownSocket.send({ type: 'state', events_since: 0 })).events;
    ownSocket.close();
    await api.delete(`/api/v1/sessions/${own.json.id}`);
    assert.ok(first.events.some((event) => event.tick === 0), "the start's events come with the first step");
    assert.ok(second.events.some((event) => event.kind === 'command'), "the command's event comes with the next step");
    assert.deepEqual([...first.events, ...second.events, ...third.events], all);
  });

  it('laser answers a binary frame: the spec\'s layout, the same scan as the sensors message', async () => {
    assert.deepEqual(layoutInSpec(), LAYOUT, 'the decoder reads the layout api/asyncapi.yaml gives');
    await socket.send({ type: 'step' });
    const sensors = await socket.send({ type: 'sensors', robot: 'robot' });
    const frames = [decodeLaserFrame(await socket.send({ type: 'laser', robot: 'robot' }))];
    for (const laser of sensors.lasers) frames.push(decodeLaserFrame(await socket.send({ type: 'laser', robot: 'robot', sensor: laser.sensor })));
    const [first, ...named] = frames;
    assert.deepEqual(first, named[0], 'without a sensor: the first laser');
    const { dt } = (await api.get(`/api/v1/sessions/${session.id}`)).json;
    sensors.lasers.forEach((laser, i) => {
      const frame = named[i];
      assert.equal(frame.tick, laser.tick);
      assert.ok(laser.tick >= 0);
      assert.equal(frame.time, laser.tick * dt);
      for (const [field, value] of [['x', laser.pose.x], ['y', laser.pose.y], ['theta', laser.pose.theta], ['angle_min', laser.angle_min],
        ['angle_increment', laser.angle_increment], ['range_min', laser.range_min], ['range_max', laser.range_max]]) {
        assert.equal(frame[field], Math.fround(value), `${laser.sensor}: ${field} as float32`);
      }
      assert.equal(frame.count, laser.ranges.length);
      assert.deepEqual(frame.ranges, laser.ranges.map((range) => Math.fround(rangeValue(range))), `${laser.sensor}: ranges as float32, infinities too`);
      assert.ok(frame.ranges.every((range) => range === Infinity || range === -Infinity || (range >= frame.range_min && range <= frame.range_max)),
        'REP 117: a range is within [range_min, range_max] or infinite');
    });
  });

  it('laser: an unknown robot, one without a model, an unknown sensor or a wrong field is an error', async () => {
    const cases = [[{ robot: 'nobody' }, 'not_found', '/robot'], [{ robot: 'ada' }, 'not_found', '/robot'],
      [{ robot: 'robot', sensor: 'nose' }, 'not_found', '/sensor'], [{ robot: 'robot', sensor: 5 }, 'bad_request', '/sensor'],
      [{}, 'bad_request', '/robot'], [{ robot: 'robot', colour: 'red' }, 'bad_request', '/colour']];
    for (const [fields, code, pointer] of cases) {
      const reply = await socket.send({ type: 'laser', ...fields });
      assert.equal(reply.type, 'error', JSON.stringify(fields));
      assert.equal(reply.error.code, code, JSON.stringify(fields));
      assert.equal(reply.error.details.pointer, pointer, JSON.stringify(fields));
    }
  });

  it('camera answers a binary frame: the spec\'s layout, the head camera\'s images at 256 × 256, with ids when asked', async () => {
    assert.deepEqual(cameraFrame.layoutInSpec(), cameraFrame.LAYOUT, 'the decoder reads the layout api/asyncapi.yaml gives');
    const { cameras, segmentation } = (await api.get(`/api/v1/sessions/${session.id}/cameras`)).json;
    const head = cameras.find((camera) => camera.name === 'robot.head_rgbd');
    const { tick, dt } = (await api.get(`/api/v1/sessions/${session.id}`)).json;
    const size = 256;
    const plain = cameraFrame.decodeCameraFrame(await socket.send({ type: 'camera', camera: 'robot.head_rgbd', width: size, height: size }));
    const withIds = cameraFrame.decodeCameraFrame(await socket.send({ type: 'camera', camera: 'robot.head_rgbd', width: size, height: size, ids: true }));
    // The pinhole keeps its horizontal field of view at the new size, with square pixels.
    const focal = (size / 2) / Math.tan(Math.atan(head.width / 2 / head.fx));
    for (const [frame, parts] of [[plain, 3], [withIds, 7]]) {
      assert.equal(frame.parts, parts);
      assert.equal(frame.camera, 'robot.head_rgbd');
      assert.deepEqual([frame.width, frame.height], [size, size]);
      assert.equal(frame.tick, tick);
      assert.equal(frame.time, tick * dt);
      assert.ok(Math.abs(frame.fx - focal) < 1e-3 && frame.fy === frame.fx, `fx ${frame.fx}, fy ${frame.fy}: ${focal}`);
      assert.deepEqual([frame.cx, frame.cy], [size / 2, size / 2]);
      assert.deepEqual([frame.near, frame.far], [Math.fround(head.near), Math.fround(head.far)]);
    }
    assert.equal(plain.ids, undefined);
    assert.deepEqual(withIds.colour, plain.colour, 'the same colour image');
    assert.deepEqual(withIds.depth, plain.depth, 'the same depth image');
    // The images are GET .../frames' npy images of the same camera and size.
    const npy = async (image) => decodeNpy((await api.get(`/api/v1/sessions/${session.id}/frames/robot.head_rgbd?format=npy&image=${image}&width=${size}&height=${size}`)).bytes).values;
    assert.deepEqual(plain.colour, await npy('colour'), 'colour as GET .../frames');
    assert.deepEqual(plain.depth, await npy('depth'), 'depth as GET .../frames');
    assert.deepEqual(withIds.ids, await npy('segmentation'), 'ids as GET .../frames');
    const known = new Set(segmentation.map((label) => label.id));
    assert.ok(withIds.ids.every((id) => id === 0 || known.has(id)), 'every id is in the legend');
  });

  it('camera: an unknown camera, a size out of range, ids that are no boolean or a wrong field is an error', async () => {
    const cases = [[{ camera: 'ceiling' }, 'not_found'], [{}, 'bad_request', '/camera'], [{ camera: 5 }, 'bad_request', '/camera'],
      [{ camera: 'overview', width: 15 }, 'bad_request', '/width'], [{ camera: 'overview', width: 2049 }, 'bad_request', '/width'],
      [{ camera: 'overview', width: 64.5 }, 'bad_request', '/width'], [{ camera: 'overview', height: '64' }, 'bad_request', '/height'],
      [{ camera: 'overview', ids: 1 }, 'bad_request', '/ids'], [{ camera: 'overview', colour: 'red' }, 'bad_request', '/colour']];
    for (const [fields, code, pointer] of cases) {
      const reply = await socket.send({ type: 'camera', ...fields });
      assert.equal(reply.type, 'error', JSON.stringify(fields));
      assert.equal(reply.error.code, code, JSON.stringify(fields));
      if (pointer) assert.equal(reply.error.details.pointer, pointer, JSON.stringify(fields));
    }
    const unknown = await socket.send({ type: 'camera', camera: 'ceiling' });
    assert.equal(unknown.error.details.camera, 'ceiling');
    assert.match(unknown.error.message, /overview, follow, robot\.head_rgbd/, 'the message lists the cameras there are');
  });

  it('subscribe: a state frame when the session changed, with the events since the last one', async () => {
    const own = (await api.post('/api/v1/sessions', { scenario: 'elevator', seed: 3 })).json;
    const ownSocket = await api.openSocket(own.id);
    try {
      assert.deepEqual(await ownSocket.send({ type: 'subscribe', rate: 50 }), { type: 'subscribed', rate: 50, camera: null });
      const first = await ownSocket.nextFrame();
      assert.equal(first.type, 'state_frame');
      assert.equal(first.tick, 0);
      assert.equal(first.dropped_frames, 0);
      assert.equal(first.connected_clients, 1);
      assert.equal(await ownSocket.nextFrame(100), undefined, 'nothing changed: no frame');
      const stepped = await ownSocket.send({ type: 'step', n: 5 });
      const second = await ownSocket.nextFrame();
      assert.equal(second.tick, 5);
      assert.equal(second.state_hash, stepped.state_hash);
      await ownSocket.send({ type: 'commands', commands: [{ human: 'ada', command: 'wait 1' }] });
      const third = await ownSocket.nextFrame();
      assert.equal(third.tick, 5, 'a command changed the session, not its tick');
      assert.ok(third.events.some((event) => event.kind === 'command'), 'the command\'s event');
      const all = (await ownSocket.send({ type: 'state', events_since: 0 })).events;
      assert.deepEqual([...first.events, ...second.events, ...third.events], all, 'each event in one frame');
      assert.deepEqual(third.agents, (await ownSocket.send({ type: 'state' })).agents);
      assert.deepEqual(await ownSocket.send({ type: 'subscribe', rate: 0 }), { type: 'subscribed', rate: 0, camera: null });
      await sleep(60);  // the frame timer set at rate 50 runs out once more (see the todo test below)
      await ownSocket.send({ type: 'step' });
      assert.equal(await ownSocket.nextFrame(100), undefined, 'rate 0: no more frames');
    } finally {
      ownSocket.close();
      await api.delete(`/api/v1/sessions/${own.id}`);
    }
  });

  it('subscribe: a rate out of 0–60 or a wrong field is an error', async () => {
    for (const [message, pointer] of [[{ rate: -1 }, '/rate'], [{ rate: 61 }, '/rate'], [{ rate: 'fast' }, '/rate'], [{}, '/rate'],
      [{ rate: 1, colour: 'red' }, '/colour']]) {
      const reply = await socket.send({ type: 'subscribe', ...message });
      assert.equal(reply.type, 'error', JSON.stringify(message));
      assert.equal(reply.error.code, 'bad_request');
      assert.equal(reply.error.details.pointer, pointer, JSON.stringify(message));
    }
    assert.equal((await socket.send({ type: 'subscribe', rate: 60 })).rate, 60);
    assert.equal((await socket.send({ type: 'subscribe', rate: 0 })).rate, 0);
  });

  /** The next pushed frame, which must be a state frame. */
  const nextStateFrame = async (from) => {
    const frame = await from.nextFrame();
    assert.ok(frame && !Buffer.isBuffer(frame), `a state frame, not ${Buffer.isBuffer(frame) ? 'a binary frame' : frame}`);
    assert.equal(frame.type, 'state_frame');
    return frame;
  };
  /** The next pushed frame, which must be a camera frame, decoded. */
  const nextCameraFrame = async (from) => {
    const frame = await from.nextFrame();
    assert.ok(Buffer.isBuffer(frame), `a binary camera frame, not ${JSON.stringify(frame)?.slice(0, 100)}`);
    return cameraFrame.decodeCameraFrame(frame);
  };

  it('subscribe with a camera: each state frame is followed by that camera\'s frame of the same tick, as the camera message draws it', async () => {
    const own = (await api.post('/api/v1/sessions', { scenario: 'elevator', seed: 5 })).json;
    const ownSocket = await api.openSocket(own.id);
    try {
      const head = { name: 'robot.head_rgbd', width: 64, height: 48, ids: false };
      assert.deepEqual(await ownSocket.send({ type: 'subscribe', rate: 60, camera: head }), { type: 'subscribed', rate: 60, camera: head });
      const check = (frame, tick, [name, width, height, parts]) => {
        assert.deepEqual([frame.tick, frame.time, frame.camera, frame.width, frame.height, frame.parts], [tick, tick * own.dt, name, width, height, parts]);
      };
      assert.equal((await nextStateFrame(ownSocket)).tick, 0, 'the session as it is now');
      check(await nextCameraFrame(ownSocket), 0, ['robot.head_rgbd', 64, 48, 3]);
      // Stepped over the socket and over REST: a state frame and its camera frame each time.
      await ownSocket.send({ type: 'step', n: 5 });
      assert.equal((await nextStateFrame(ownSocket)).tick, 5);
      const pushed = await nextCameraFrame(ownSocket);
      check(pushed, 5, ['robot.head_rgbd', 64, 48, 3]);
      assert.equal(await ownSocket.nextFrame(50), undefined, 'nothing changed: nothing pushed');
      const asked = cameraFrame.decodeCameraFrame(await ownSocket.send({ type: 'camera', camera: 'robot.head_rgbd', width: 64, height: 48 }));
      assert.deepEqual(pushed, asked, 'the camera message\'s frame of the same moment');
      assert.equal((await api.post(`/api/v1/sessions/${own.id}/step`, { n: 2 })).status, 200);
      assert.equal((await nextStateFrame(ownSocket)).tick, 7);
      check(await nextCameraFrame(ownSocket), 7, ['robot.head_rgbd', 64, 48, 3]);

      // A new subscription replaces the camera: a width alone keeps the overview's 4:3, with ids.
      const overview = { name: 'overview', width: 64, ids: true };
      assert.deepEqual((await ownSocket.send({ type: 'subscribe', rate: 60, camera: overview })).camera, { ...overview, height: 0 }, '0: not asked for');
      await ownSocket.send({ type: 'step' });
      assert.equal((await nextStateFrame(ownSocket)).tick, 8);
      const withIds = await nextCameraFrame(ownSocket);
      check(withIds, 8, ['overview', 64, 48, 7]);
      assert.ok(withIds.ids.some((id) => id !== 0), 'the overview sees the map');
      // ...and a subscription without one stops the camera frames, not the state frames.
      assert.deepEqual(await ownSocket.send({ type: 'subscribe', rate: 60, camera: null }), { type: 'subscribed', rate: 60, camera: null });
      await ownSocket.send({ type: 'step' });
      assert.equal((await nextStateFrame(ownSocket)).tick, 9);
      assert.equal(await ownSocket.nextFrame(100), undefined, 'no camera frame');
      await ownSocket.send({ type: 'subscribe', rate: 60, camera: { name: 'follow', height: 32 } });
      assert.deepEqual((await ownSocket.send({ type: 'subscribe', rate: 60 })).camera, null, 'no camera: none');
    } finally {
      ownSocket.close();
      await api.delete(`/api/v1/sessions/${own.id}`);
    }
  });

  it('subscribe with a camera on a realtime session: each state frame, then its camera frame', async () => {
    const realtime = (await api.post('/api/v1/sessions', { scenario: 'elevator', mode: 'realtime' })).json;
    const realtimeSocket = await api.openSocket(realtime.id);
    try {
      await realtimeSocket.send({ type: 'subscribe', rate: 30, camera: { name: 'robot.head_rgbd', width: 32, height: 24, ids: true } });
      const ticks = [];
      for (let pair = 0; pair < 3; pair++) {
        const state = await nextStateFrame(realtimeSocket);
        const camera = await nextCameraFrame(realtimeSocket);
        assert.deepEqual([camera.tick, camera.camera, camera.width, camera.height, camera.parts], [state.tick, 'robot.head_rgbd', 32, 24, 7]);
        assert.equal(camera.time, state.time);
        ticks.push(state.tick);
      }
      assert.ok(ticks.every((tick, i) => i === 0 || tick > ticks[i - 1]), `ticks advance on their own: ${ticks}`);
      assert.equal((await realtimeSocket.send({ type: 'subscribe', rate: 0, camera: { name: 'overview' } })).rate, 0);
    } finally {
      realtimeSocket.close();
      await api.delete(`/api/v1/sessions/${realtime.id}`);
    }
  });

  it('subscribe: a wrong camera is an error naming it, and subscribes nothing', async () => {
    const other = await api.openSocket(session.id);
    try {
      const cases = [[{ name: 'ceiling' }, 'not_found'], ['robot.head_rgbd', 'bad_request', '/camera'], [{}, 'bad_request', '/camera/name'],
        [{ name: 5 }, 'bad_request', '/camera/name'], [[], 'bad_request', '/camera'],
        [{ name: 'overview', width: 15 }, 'bad_request', '/camera/width'], [{ name: 'overview', width: 2049 }, 'bad_request', '/camera/width'],
        [{ name: 'overview', width: 64.5 }, 'bad_request', '/camera/width'], [{ name: 'overview', height: '48' }, 'bad_request', '/camera/height'],
        [{ name: 'overview', ids: 1 }, 'bad_request', '/camera/ids'], [{ name: 'overview', colour: 'red' }, 'bad_request', '/camera/colour']];
      for (const [camera, code, pointer] of cases) {
        const reply = await other.send({ type: 'subscribe', rate: 60, camera });
        assert.equal(reply.type, 'error', JSON.stringify(camera));
        assert.equal(reply.error.code, code, JSON.stringify(camera));
        if (pointer) assert.equal(reply.error.details.pointer, pointer, JSON.stringify(camera));
      }
      const unknown = await other.send({ type: 'subscribe', rate: 60, camera: { name: 'ceiling' } });
      assert.equal(unknown.error.details.camera, 'ceiling');
      assert.match(unknown.error.message, /overview, follow, robot\.head_rgbd/, 'the message lists the cameras there are');
      await other.send({ type: 'step' });
      assert.equal(await other.nextFrame(100), undefined, 'nothing subscribed');
    } finally {
      await other.closeAndWait();
    }
  });

  it('a realtime session moves by itself: frames at most at the rate, step is a conflict', async () => {
    const realtime = (await api.post('/api/v1/sessions', { scenario: 'elevator', mode: 'realtime', realtime_factor: 2 })).json;
    const realtimeSocket = await api.openSocket(realtime.id);
    try {
      const refused = await realtimeSocket.send({ type: 'step' });
      assert.equal(refused.type, 'error');
      assert.equal(refused.error.code, 'conflict');
      await realtimeSocket.send({ type: 'subscribe', rate: 20 });
      const started = Date.now();
      const frames = [];
      while (frames.length < 4) frames.push(await realtimeSocket.nextFrame());
      const seconds = (Date.now() - started) / 1000;
      const ticks = frames.map((frame) => frame.tick);
      assert.ok(ticks.every((tick, i) => i === 0 || tick > ticks[i - 1]), `ticks advance on their own: ${ticks}`);
      assert.ok(frames.length <= 20 * seconds + 2, `${frames.length} frames in ${seconds} s at 20 a second`);
      assert.ok(frames.every((frame) => frame.mode === 'realtime' && frame.dropped_frames === 0));
    } finally {
      realtimeSocket.close();
      await api.delete(`/api/v1/sessions/${realtime.id}`);
    }
  });

  it('subscribe: a reset is a change too, and the new run\'s events come in frames', {
    todo: 'server: frames are pushed when the tick or the number of events changed, so a reset stepped back to the same tick with as many events pushes nothing (and one with more events skips the first ones)',
  }, async () => {
    const own = (await api.post('/api/v1/sessions', { scenario: 'elevator', seed: 1 })).json;
    const ownSocket = await api.openSocket(own.id);
    try {
      await ownSocket.send({ type: 'subscribe', rate: 2 });
      await ownSocket.nextFrame();
      await ownSocket.send({ type: 'step', n: 300 });
      await ownSocket.nextFrame();
      // Within the half second before the next frame: another seed, back to the same tick.
      await api.post(`/api/v1/sessions/${own.id}/reset`, { seed: 2 });
      const stepped = await ownSocket.send({ type: 'step', n: 300 });
      const all = (await ownSocket.send({ type: 'state', events_since: 0 })).events;
      const frames = [];
      for (let frame = await ownSocket.nextFrame(1500); frame; frame = await ownSocket.nextFrame(700)) frames.push(frame);
      assert.equal(frames.at(-1)?.state_hash, stepped.state_hash, 'a frame shows the new state');
      assert.deepEqual(frames.flatMap((frame) => frame.events), all, 'the new run\'s events');
    } finally {
      ownSocket.close();
      await api.delete(`/api/v1/sessions/${own.id}`);
    }
  });

  it('subscribe with rate 0 stops the frames at once', {
    todo: 'server: a push timer already set when rate 0 arrives still sends one frame (up to 1/rate s after the subscribed reply)',
  }, async () => {
    const realtime = (await api.post('/api/v1/sessions', { scenario: 'elevator', mode: 'realtime' })).json;
    const realtimeSocket = await api.openSocket(realtime.id);
    try {
      await realtimeSocket.send({ type: 'subscribe', rate: 4 });
      await realtimeSocket.nextFrame();
      await realtimeSocket.send({ type: 'subscribe', rate: 0 });
      realtimeSocket.dropFrames();
      assert.equal(await realtimeSocket.nextFrame(400), undefined, 'a frame after the subscribed reply for rate 0');
    } finally {
      realtimeSocket.close();
      await api.delete(`/api/v1/sessions/${realtime.id}`);
    }
  });

  it('wrong messages get errors and the socket stays open', async () => {
    const wrong = [['not json', undefined], [{ type: 'jump' }, '/type'], [{ type: 'step', n: 0 }, '/n'], [{ type: 'step', action: 'fast' }, '/action'],
      [{ type: 'state', events_since: -1 }, '/events_since'], [{ type: 'step', legs: 2 }, '/legs']];
    for (const [message, pointer] of wrong) {
      const reply = await socket.send(message);
      assert.equal(reply.type, 'error', JSON.stringify(message));
      assert.equal(reply.error.code, 'bad_request');
      if (pointer) assert.equal(reply.error.details.pointer, pointer, JSON.stringify(message));
    }
    // An unknown type's error names every type the spec has the client send.
    const unknownType = await socket.send({ type: 'jump' });
    // "#/channels/session/messages/NAME", which refers to "#/components/messages/MESSAGE"
    const messageOf = (ref) => asyncapi.components.messages[asyncapi.channels.session.messages[ref.split('/').pop()].$ref.split('/').pop()];
    const types = Object.values(asyncapi.operations).filter((operation) => operation.action === 'receive')
      .map((operation) => messageOf(operation.messages[0].$ref).payload.properties.type.const);
    for (const type of types) {
      assert.match(unknownType.error.message, new RegExp(`\\b${type}\\b`), `an unknown type's error lists '${type}'`);
    }
    assert.ok(socket.isOpen);
    assert.equal((await socket.send({ type: 'step' })).type, 'step');
  });

  it('messages sent together are answered once each, in order', async () => {
    const replies = await Promise.all([socket.send({ type: 'step', n: 2 }), socket.send({ type: 'state' }), socket.send({ type: 'step' })]);
    assert.deepEqual(replies.map((reply) => reply.type), ['step', 'state', 'step']);
    assert.equal(replies[1].tick, replies[0].tick);
    assert.equal(replies[2].tick, replies[0].tick + 1);
  });

  it('a session deleted under an open socket answers not_found, or the server closes the socket normally', async () => {
    const doomed = await api.post('/api/v1/sessions', { scenario: 'queue' });
    const doomedSocket = await api.openSocket(doomed.json.id);
    await api.delete(`/api/v1/sessions/${doomed.json.id}`);
    // The server checks about once a second whether what a socket serves is gone, and then closes it
    // with 1000; a message that arrives first is answered.
    try {
      const reply = await doomedSocket.send({ type: 'step' });
      assert.equal(reply.type, 'error');
      assert.equal(reply.error.code, 'not_found');
    } catch (error) {
      assert.match(error.message, /the socket closed \(1000\)/);
    }
    doomedSocket.close();
  });

  const overLimit = `"${'x'.repeat(1024 * 1024)}"`;

  it('a message over 1 MiB closes the socket', async () => {
    const other = await api.openSocket(session.id);
    await assert.rejects(other.send(overLimit), /the socket closed/);
  });

  it('a message over 1 MiB closes the socket with code 1009, every time', {
    todo: 'server: Boost 1.74 Beast\'s teardown stops draining after 2 KiB and resets the connection, so the peer often sees 1006',
  }, async () => {
    for (let attempt = 0; attempt < 5; attempt++) {
      const other = await api.openSocket(session.id);
      await assert.rejects(other.send(overLimit), /closed \(1009\)/);
    }
  });

  it('an unknown session is refused with 404 before the upgrade', async () => {
    await assert.rejects(api.openSocket(`s${'0'.repeat(32)}`), (error) => error.refused?.status === 404);
  });

  it('without a token on the server: any Origin but its own is refused with 403; a ticket is not needed', async () => {
    await assert.rejects(api.openSocket(session.id, { origin: 'https://evil.example' }),
      (error) => error.refused?.status === 403 && error.refused.json.error.code === 'forbidden');
    const own = await api.openSocket(session.id, { origin: `http://127.0.0.1:${api.port}` });
    own.close();
    const { ticket } = (await api.post(`/api/v1/sessions/${session.id}/ws-ticket`)).json;
    for (const attempt of [1, 2]) {
      const withTicket = await api.openSocket(session.id, { ticket });
      assert.equal((await withTicket.send({ type: 'state' })).type, 'state', `attempt ${attempt}`);
      withTicket.close();
    }
  });
});

describe('session WebSocket: tickets and origins', () => {
  const token = 'contract-test-token-0123456789';
  const allowed = 'https://lab.example:8443';
  let server;
  let withToken;
  let withoutToken;
  let session;
  before(async () => {
    server = await startServer(['--token', token, '--allowed-origins', `${allowed},http://other.example`]);
    withToken = new Client(server.port, { token });
    withoutToken = new Client(server.port);
    session = (await withToken.post('/api/v1/sessions', { scenario: 'elevator' })).json;
  });
  after(async () => {
    await server.stop();
  });

  const ticketFor = async (id) => {
    const reply = await withToken.post(`/api/v1/sessions/${id}/ws-ticket`);
    assert.equal(reply.status, 201, reply.body);
    return reply.json;
  };
  const refusal = (status, code) => (error) => {
    assert.equal(error.refused?.status, status, error.message);
    assert.equal(error.refused.json.error.code, code);
    return true;
  };

  it('a ticket opens the session\'s WebSocket once without the token', async () => {
    const { ticket, url } = await ticketFor(session.id);
    assert.ok(url.endsWith(`?ticket=${ticket}`));
    const socket = await withoutToken.openSocket(session.id, { ticket });
    assert.equal((await socket.send({ type: 'step' })).type, 'step');
    socket.close();
    await assert.rejects(withoutToken.openSocket(session.id, { ticket }), refusal(401, 'unauthorized'), 'used once already');
  });

  it('a ticket for another session, or none that was issued, is 401', async () => {
    const other = (await withToken.post('/api/v1/sessions', { scenario: 'queue' })).json;
    const { ticket } = await ticketFor(other.id);
    await assert.rejects(withoutToken.openSocket(session.id, { ticket }), refusal(401, 'unauthorized'));
    await assert.rejects(withoutToken.openSocket(other.id, { ticket }), refusal(401, 'unauthorized'), 'tried once, it is gone');
    await assert.rejects(withoutToken.openSocket(session.id, { ticket: `t${'0'.repeat(32)}` }), refusal(401, 'unauthorized'));
    await withToken.delete(`/api/v1/sessions/${other.id}`);
  });

  it('POST /ws-ticket needs the token; 404 for an unknown session', async () => {
    const refused = await withoutToken.post(`/api/v1/sessions/${session.id}/ws-ticket`);
    assert.equal(refused.status, 401);
    const unknown = await withToken.post(`/api/v1/sessions/s${'0'.repeat(32)}/ws-ticket`);
    assert.equal(unknown.status, 404);
  });

  it('a browser Origin that is not the server\'s own nor allowed is refused with 403', async () => {
    await assert.rejects(withToken.openSocket(session.id, { origin: 'https://evil.example' }), refusal(403, 'forbidden'));
    await assert.rejects(withToken.openSocket(session.id, { origin: 'https://lab.example' }), refusal(403, 'forbidden'), 'the port is part of it');
    const { ticket } = await ticketFor(session.id);
    await assert.rejects(withoutToken.openSocket(session.id, { ticket, origin: 'https://evil.example' }), refusal(403, 'forbidden'));
    for (const origin of [allowed, 'http://other.example', `http://127.0.0.1:${server.port}`]) {
      const socket = await withToken.openSocket(session.id, { origin });
      assert.equal((await socket.send({ type: 'state' })).type, 'state', origin);
      socket.close();
    }
  });
});

'use strict';
// A session as a Foxglove WebSocket server (docs/foxglove.md), tested with Foxglove's own client
// (@foxglove/ws-protocol, which offers foxglove.websocket.v1) and every message checked against
// Foxglove's JSON Schemas (@foxglove/schemas): every channel subscribed and decoded, a velocity
// published that moves the robot, the step and reset services; a raw client offering only
// foxglove.sdk.v1 is served, one offering another subprotocol refused; wrong messages get an error
// status and the socket stays open.
const assert = require('node:assert/strict');
const { describe, it, before, after } = require('node:test');
const WebSocket = require('ws');
const Ajv = require('ajv');
const { FoxgloveClient } = require('@foxglove/ws-protocol');
const foxgloveSchemas = require('@foxglove/schemas/jsonschema');
const { api } = require('../lib/client');

const LIMIT_MS = 15000;
const encoder = new TextEncoder();
const decoder = new TextDecoder();
const ajv = new Ajv({ strict: false, allErrors: true });

/** Resolves with the first value `take` returns (not undefined) for an event of `client`, or rejects after LIMIT_MS. */
function waitFor(client, event, take = (value) => value) {
  return new Promise((resolve, reject) => {
    const timer = setTimeout(() => { client.off(event, listener); reject(new Error(`no ${event} within ${LIMIT_MS} ms`)); }, LIMIT_MS);
    function listener(value) {
      const taken = take(value);
      if (taken === undefined) return;
      clearTimeout(timer);
      client.off(event, listener);
      resolve(taken);
    }
    client.on(event, listener);
  });
}

/** Foxglove's client on a session, with its server info, channels and services once they came. */
async function connect(sessionId) {
  const ws = new WebSocket(`ws://127.0.0.1:${api.port}/api/v1/sessions/${sessionId}/foxglove`, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
  const client = new FoxgloveClient({ ws });
  const [serverInfo, channels, services] = await Promise.all([waitFor(client, 'serverInfo'), waitFor(client, 'advertise'), waitFor(client, 'advertiseServices')]);
  return { ws, client, serverInfo, channels, services };
}

/** Calls a service with a JSON request and resolves with its JSON response (or rejects with its failure). */
let nextCall = 1;
function call(client, service, request) {
  const callId = nextCall++;
  const response = new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`no answer from ${service.name} within ${LIMIT_MS} ms`)), LIMIT_MS);
    const done = (listener) => { clearTimeout(timer); client.off('serviceCallResponse', answered); client.off('serviceCallFailure', failed); return listener; };
    function answered(message) { if (message.callId === callId) { done(); resolve(JSON.parse(decoder.decode(message.data))); } }
    function failed(message) { if (message.callId === callId) { done(); reject(new Error(message.message)); } }
    client.on('serviceCallResponse', answered);
    client.on('serviceCallFailure', failed);
  });
  client.sendServiceCallRequest({ serviceId: service.id, callId, encoding: 'json', data: encoder.encode(JSON.stringify(request)) });
  return response;
}

/** The next message on `channel` (subscribing to it, then `prod` to make one happen), decoded from JSON. */
async function nextOn(client, channel, prod = async () => {}) {
  const subscription = client.subscribe(channel.id);
  const next = waitFor(client, 'message', (m) => (m.subscriptionId === subscription ? m : undefined));
  await prod();
  const message = await next.catch((error) => { throw new Error(`${channel.topic}: ${error.message}`); });
  client.unsubscribe(subscription);
  return { ...message, json: JSON.parse(decoder.decode(message.data)) };
}

/** Foxglove's schema of a well-known message, or the one the server advertised for its own. */
function schemaOf(channel) {
  return channel.schemaName.startsWith('foxglove.') ? foxgloveSchemas[channel.schemaName.slice('foxglove.'.length)] : JSON.parse(channel.schema);
}

/** Where the transforms put a robot's base, or undefined. */
const basePosition = (transforms) => transforms.find((t) => t.parent_frame_id === 'map' && t.child_frame_id.endsWith('/base_link'))?.translation;

describe('Foxglove WebSocket', () => {
  let session;
  let foxglove;
  before(async () => {
    session = (await api.post('/api/v1/sessions', { scenario: 'elevator', seed: 1 })).json;
    foxglove = await connect(session.id);
  });
  after(async () => {
    foxglove.client.close();
    await api.delete(`/api/v1/sessions/${session.id}`);
  });

  it('greets with its capabilities, channels in JSON with JSON Schemas, and the step, reset and seek services', () => {
    assert.equal(foxglove.ws.protocol, 'foxglove.websocket.v1');
    assert.deepEqual([...foxglove.serverInfo.capabilities].sort(), ['clientPublish', 'services', 'time']);
    assert.deepEqual(foxglove.serverInfo.supportedEncodings, ['json']);
    assert.equal(foxglove.serverInfo.metadata.session, session.id);
    const topics = foxglove.channels.map((c) => c.topic);
    for (const topic of ['/scene', '/tf', '/robot/base_scan', '/robot/people', '/camera/overview', '/camera/robot.head_rgbd', '/camera/robot.head_rgbd/depth', '/events', '/metrics']) {
      assert.ok(topics.includes(topic), `${topic} in ${topics}`);
    }
    for (const channel of foxglove.channels) {
      assert.equal(channel.encoding, 'json');
      assert.equal(channel.schemaEncoding, 'jsonschema');
      assert.equal(JSON.parse(channel.schema).title, channel.schemaName);
    }
    assert.deepEqual(foxglove.services.map((s) => s.name), ['/hrisim/step', '/hrisim/reset', '/hrisim/seek']);
  });

  it('every channel decodes, and each message is what Foxglove\'s JSON Schema of its type allows', async () => {
    const { client, channels, services } = foxglove;
    await call(client, services[0], { n: 30 });
    for (const channel of channels) {
      // Events come as they happen: a command to a person is one.
      const command = async () => {
        assert.equal((await api.post(`/api/v1/sessions/${session.id}/commands`, { commands: [{ human: 'ada', command: 'wait 1' }] })).status, 200);
        await call(client, services[0], { n: 1 });
      };
      const message = await nextOn(client, channel, channel.topic === '/events' ? command : undefined);
      const validate = ajv.compile(schemaOf(channel));
      assert.ok(validate(message.json), `${channel.topic} (${channel.schemaName}): ${ajv.errorsText(validate.errors)}`);
      assert.ok(message.timestamp > 0n, `${channel.topic}: a simulated timestamp`);
      if (channel.schemaName === 'foxglove.CompressedImage') {
        const jpeg = Buffer.from(message.json.data, 'base64');
        assert.deepEqual([...jpeg.subarray(0, 2)], [0xff, 0xd8], `${channel.topic}: a JPEG`);
      }
      if (channel.schemaName === 'foxglove.RawImage') {
        const depth = Buffer.from(message.json.data, 'base64');
        assert.equal(message.json.encoding, '32FC1');
        assert.equal(depth.length, message.json.height * message.json.step, `${channel.topic}: a float a pixel`);
        assert.ok(Array.from({ length: depth.length / 4 }, (_, i) => depth.readFloatLE(4 * i)).some((metres) => metres > 0.1), `${channel.topic}: something in view`);
      }
      if (channel.topic === '/scene') assert.ok(message.json.entities.length > 0);
      if (channel.topic === '/tf') assert.ok(basePosition(message.json.transforms), 'map → robot/base_link');
      if (channel.topic === '/robot/base_scan') assert.ok(message.json.ranges.some((range) => range > 0), 'the laser sees walls');
    }
  });

  it('the time follows the simulation', async () => {
    const { client, services } = foxglove;
    const before = await call(client, services[0], { n: 1 });
    const time = waitFor(client, 'time', (t) => (Number(t.timestamp) / 1e9 > before.time ? t : undefined));
    await call(client, services[0], { n: 60 });
    const after = await time;
    assert.ok(Number(after.timestamp) / 1e9 > before.time, `${Number(after.timestamp) / 1e9} > ${before.time}`);
  });

  it('a Twist published on /cmd_vel drives the robot; reset brings it back to tick 0', async () => {
    const { client, channels, services } = foxglove;
    const tf = channels.find((c) => c.topic === '/tf');
    const start = basePosition((await nextOn(client, tf)).json.transforms);
    const velocity = client.advertise({ topic: '/cmd_vel', encoding: 'json', schemaName: 'geometry_msgs/msg/Twist' });
    client.sendMessage(velocity, encoder.encode(JSON.stringify({ linear: { x: 0.5, y: 0, z: 0 }, angular: { x: 0, y: 0, z: 0 } })));
    const stepped = await call(client, services[0], { n: 90 });
    const moved = basePosition((await nextOn(client, tf)).json.transforms);
    assert.ok(Math.hypot(moved.x - start.x, moved.y - start.y) > 0.2, `the robot moved from ${JSON.stringify(start)} to ${JSON.stringify(moved)}`);
    assert.ok(stepped.tick > 90);
    const reset = await call(client, services[1], {});
    assert.equal(reset.tick, 0);
    const seek = await call(client, services[2], { tick: 0 });
    assert.equal(seek.tick, 0);
    await assert.rejects(call(client, services[2], {}), /tick/);
  });

  it('wrong messages get an error status, and the socket goes on', async () => {
    const { ws, client, channels } = foxglove;
    const statuses = [];
    const listen = (status) => statuses.push(status);
    client.on('status', listen);
    const nextStatus = () => waitFor(client, 'status', (s) => s);
    const wrong = async (send) => { const status = nextStatus(); send(); return status; };
    const badJson = await wrong(() => ws.send('{"op": "subscribe", '));
    const unknownOp = await wrong(() => ws.send(JSON.stringify({ op: 'fly' })));
    const unadvertised = await wrong(() => client.sendMessage(4242, encoder.encode('{}')));
    const protobuf = await wrong(() => client.advertise({ topic: '/cmd_vel', encoding: 'protobuf', schemaName: 'foxglove.Twist' }));
    const nowhere = await wrong(() => client.advertise({ topic: '/fly', encoding: 'json', schemaName: 'geometry_msgs/msg/Twist' }));
    const velocity = client.advertise({ topic: '/cmd_vel', encoding: 'json', schemaName: 'geometry_msgs/msg/Twist' });
    const notTwist = await wrong(() => client.sendMessage(velocity, encoder.encode(JSON.stringify({ linear: 1 }))));
    const noChannel = await wrong(() => ws.send(JSON.stringify({ op: 'subscribe', subscriptions: [{ id: 900, channelId: 9999 }] })));
    const shortBinary = await wrong(() => ws.send(new Uint8Array([2, 1])));
    client.off('status', listen);
    for (const [status, says] of [[badJson, /JSON object/], [unknownOp, /op 'fly'/], [unadvertised, /channel 4242/], [protobuf, /protobuf/],
      [nowhere, /\/fly/], [notTwist, /linear\.x/], [noChannel, /no channel 9999/], [shortBinary, /too short/]]) {
      assert.equal(status.level, 2, status.message);
      assert.match(status.message, says);
    }
    // Still served.
    assert.ok((await nextOn(client, channels.find((c) => c.topic === '/tf'))).json.transforms.length > 0);
  });

  it('a client offering only foxglove.sdk.v1 is served; one offering only another subprotocol is refused with 400', async () => {
    const url = `ws://127.0.0.1:${api.port}/api/v1/sessions/${session.id}/foxglove`;
    const sdk = new WebSocket(url, ['foxglove.sdk.v1']);
    const first = await new Promise((resolve, reject) => { sdk.once('message', (data) => resolve(JSON.parse(data))); sdk.once('error', reject); });
    assert.equal(sdk.protocol, 'foxglove.sdk.v1');
    assert.equal(first.op, 'serverInfo');
    sdk.close();
    const other = new WebSocket(url, ['foxglove.sdk.v2']);
    const status = await new Promise((resolve, reject) => {
      other.on('unexpected-response', (request, response) => { resolve(response.statusCode); request.destroy(); });
      other.on('open', () => reject(new Error('opened')));
    });
    assert.equal(status, 400);
  });
});

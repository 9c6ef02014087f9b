'use strict';
// A session as a rosbridge v2 server (docs/rosbridge.md), tested with the rosbridge client ROS users
// have, roslib 2.1.0 (roslibjs, an ES module, on node's `ws`): rosapi's introspection, /scan, /odom,
// /tf and /clock subscribed in JSON and CBOR, a Twist published on /cmd_vel that moves the robot in
// /odom, the reset, step and seek services. Every topic subscribed as cbor-raw decodes with
// @foxglove/rosmsg2-serialization against the definitions hrisim gives (/rosapi/topics_and_raw_types),
// and those definitions are ROS 2 Jazzy's (@foxglove/rosmsg-msgs-common). Wrong messages from a raw
// WebSocket get an error status, and the socket goes on.
const assert = require('node:assert/strict');
const { describe, it, before, after } = require('node:test');
const WebSocket = require('ws');
const { parse: parseDefinition } = require('@foxglove/rosmsg');
const { MessageReader } = require('@foxglove/rosmsg2-serialization');
const { ros2jazzy } = require('@foxglove/rosmsg-msgs-common');
const { api } = require('../lib/client');

const LIMIT_MS = 15000;

/** Rejects after LIMIT_MS unless `promise` settles first, naming what was awaited. */
function within(promise, what) {
  let timer;
  const timeout = new Promise((resolve, reject) => { timer = setTimeout(() => reject(new Error(`no ${what} within ${LIMIT_MS} ms`)), LIMIT_MS); });
  return Promise.race([promise, timeout]).finally(() => clearTimeout(timer));
}

describe('rosbridge WebSocket', () => {
  let roslib;
  let ros;
  let session;
  const url = () => `ws://127.0.0.1:${api.port}/api/v1/sessions/${session.id}/rosbridge`;

  /** Calls a service with roslib; resolves with its values, rejects with its failure. */
  function call(name, request = {}) {
    const service = new roslib.Service({ ros, name, serviceType: '' });
    return within(new Promise((resolve, reject) => service.callService(request, resolve, (error) => reject(new Error(error)))), `answer from ${name}`);
  }

  /** The first message on `topic` for which `take` returns something (default: the first), subscribing and unsubscribing with roslib. */
  async function nextOn(name, messageType, { compression, take = (m) => m, prod = async () => {} } = {}) {
    const topic = new roslib.Topic({ ros, name, messageType, compression });
    const message = new Promise((resolve) => {
      topic.subscribe((m) => {
        const taken = take(m);
        if (taken !== undefined) resolve(taken);
      });
    });
    await prod();
    try {
      return await within(message, `message on ${name}`);
    } finally {
      topic.unsubscribe();
    }
  }

  before(async () => {
    roslib = await import('roslib');
    session = (await api.post('/api/v1/sessions', { scenario: 'elevator', seed: 1 })).json;
    ros = new roslib.Ros({});
    await within(ros.connect(url()), 'connection');
  });
  after(async () => {
    ros.close();
    await api.delete(`/api/v1/sessions/${session.id}`);
  });

  it('rosapi names the topics with their ROS 2 types, the node, the services and the ROS version', async () => {
    const { topics, types } = await within(new Promise((resolve, reject) => ros.getTopics(resolve, reject)), 'topics');
    const typeOf = Object.fromEntries(topics.map((topic, i) => [topic, types[i]]));
    assert.deepEqual({ scan: typeOf['/scan'], odom: typeOf['/odom'], tf: typeOf['/tf'], tfStatic: typeOf['/tf_static'], clock: typeOf['/clock'],
      rosout: typeOf['/rosout'], markers: typeOf['/people_markers'], people: typeOf['/people'], cmdVel: typeOf['/cmd_vel'], camera: typeOf['/camera/overview/compressed'] },
    { scan: 'sensor_msgs/msg/LaserScan', odom: 'nav_msgs/msg/Odometry', tf: 'tf2_msgs/msg/TFMessage', tfStatic: 'tf2_msgs/msg/TFMessage',
      clock: 'rosgraph_msgs/msg/Clock', rosout: 'rcl_interfaces/msg/Log', markers: 'visualization_msgs/msg/MarkerArray', people: 'people_msgs/msg/People', cmdVel: 'geometry_msgs/msg/Twist',
      camera: 'sensor_msgs/msg/CompressedImage' });
    assert.deepEqual(await call('/rosapi/get_ros_version'), { version: 2, distro: 'jazzy' });
    assert.deepEqual((await call('/rosapi/nodes')).nodes, ['/hrisim']);
    const details = await call('/rosapi/node_details', { node: '/hrisim' });
    assert.ok(details.publishing.includes('/scan') && details.subscribing.includes('/cmd_vel') && details.services.includes('/hrisim/reset'));
    assert.equal((await call('/rosapi/service_type', { service: '/hrisim/reset' })).type, 'std_srvs/srv/Trigger');
    assert.equal((await call('rosapi/topic_type', ['/odom'])).type, 'nav_msgs/msg/Odometry', 'a name without its slash, args as a list');
    const services = await within(new Promise((resolve, reject) => ros.getServices(resolve, reject)), 'services');
    assert.ok(services.includes('/rosapi/topics_and_raw_types') && services.includes('/hrisim/step'));
  });

  it('/scan, /odom, /tf and /clock come in ROS 2 shapes, stamped with simulated time', async () => {
    await call('/hrisim/step', { n: 30 });
    const scan = await nextOn('/scan', 'sensor_msgs/msg/LaserScan');
    assert.equal(scan.header.frame_id, 'robot/base_scan');
    assert.ok(scan.ranges.some((range) => typeof range === 'number' && range > 0), 'the laser sees walls');
    assert.ok(scan.angle_max > scan.angle_min && scan.range_max > scan.range_min);
    const odom = await nextOn('/odom', 'nav_msgs/msg/Odometry');
    assert.equal(odom.header.frame_id, 'robot/odom');
    assert.equal(odom.child_frame_id, 'robot/base_link');
    assert.equal(odom.pose.covariance.length, 36);
    const tf = await nextOn('/tf', 'tf2_msgs/msg/TFMessage');
    assert.ok(tf.transforms.some((t) => t.header.frame_id === 'map' && t.child_frame_id === 'robot/base_link'), 'map → robot/base_link');
    const tfStatic = await nextOn('/tf_static', 'tf2_msgs/TFMessage');
    assert.ok(tfStatic.transforms.some((t) => t.child_frame_id === 'robot/base_scan'), 'robot/base_link → robot/base_scan');
    const clock = await nextOn('/clock', 'rosgraph_msgs/Clock');
    const time = await call('/rosapi/get_time');
    assert.deepEqual(clock.clock, time.time, 'the clock and rosapi agree while the session stands');
    assert.ok(clock.clock.sec * 1e9 + clock.clock.nanosec > 0);
  });

  it('a Twist published on /cmd_vel drives the robot, seen in /odom; reset brings it back to tick 0', async () => {
    const start = (await nextOn('/odom', 'nav_msgs/msg/Odometry')).pose.pose.position;
    const velocity = new roslib.Topic({ ros, name: '/cmd_vel', messageType: 'geometry_msgs/msg/Twist' });
    velocity.publish({ linear: { x: 0.15, y: 0, z: 0 }, angular: { x: 0, y: 0, z: 0 } });
    const stepped = await call('/hrisim/step', { n: 90 });
    assert.ok(stepped.success && stepped.tick > 90, JSON.stringify(stepped));
    const odometry = await nextOn('/odom', 'nav_msgs/msg/Odometry');
    assert.ok(Math.abs(odometry.twist.twist.linear.x - 0.15) < 0.03, `the wheels measure the speed asked: ${odometry.twist.twist.linear.x}`);
    const moved = odometry.pose.pose.position;
    assert.ok(Math.hypot(moved.x - start.x, moved.y - start.y) > 0.1, `the robot moved from ${JSON.stringify(start)} to ${JSON.stringify(moved)}`);
    velocity.unadvertise();
    const reset = await call('/hrisim/reset');
    assert.equal(reset.success, true);
    assert.deepEqual((await call('/rosapi/get_time')).time, { sec: 0, nanosec: 0 });
    assert.equal((await call('/hrisim/seek', { tick: 0 })).tick, 0);
    await assert.rejects(call('/hrisim/seek', {}), /tick must be an integer/);
  });

  it('CBOR carries the same messages as JSON', async () => {
    await call('/hrisim/step', { n: 5 });
    const json = await nextOn('/tf', 'tf2_msgs/msg/TFMessage');
    const cbor = await nextOn('/tf', 'tf2_msgs/msg/TFMessage', { compression: 'cbor' });
    assert.deepEqual(cbor, json);
  });

  it('every topic as cbor-raw decodes with rosmsg2-serialization, by hrisim\'s definitions and by ROS 2 Jazzy\'s', async () => {
    const { topics, types, typedefs_full_text: texts } = await call('/rosapi/topics_and_raw_types');
    await call('/hrisim/step', { n: 30 });
    const decodedTopics = [];
    for (const [i, topic] of topics.entries()) {
      if (topic.endsWith('cmd_vel')) continue;  // taken, not published
      const ours = parseDefinition(texts[i], { ros2: true });
      // people_msgs is the people stack's, not in ROS 2 itself: decoded by hrisim's definition alone.
      const jazzy = ros2jazzy[types[i].replace('/msg/', '/')] ?? (types[i].startsWith('people_msgs/') ? undefined : assert.fail(`${types[i]} is not ROS 2 Jazzy's`));
      const fields = (definition) => definition.definitions.filter((f) => !f.isConstant).map((f) => [f.type, f.name, f.isArray ?? false, f.arrayLength]);
      if (jazzy) assert.deepEqual(fields(ours[0]), fields(jazzy), `${topic}: ${types[i]} is ROS 2 Jazzy's`);
      // Events come as they happen: a command to a person is one.
      const prod = topic === '/rosout' ? async () => {
        assert.equal((await api.post(`/api/v1/sessions/${session.id}/commands`, { commands: [{ human: 'ada', command: 'wait 1' }] })).status, 200);
        await call('/hrisim/step', { n: 1 });
      } : undefined;
      // As Lichtblick's rosbridge player subscribes: cbor-raw, no type named.
      const raw = await nextOn(topic, undefined, { compression: 'cbor-raw', prod });
      assert.ok(raw.bytes instanceof Uint8Array, `${topic}: bytes`);
      assert.deepEqual([...raw.bytes.subarray(0, 4)], [0, 1, 0, 0], `${topic}: little-endian CDR`);
      assert.ok(Number.isInteger(raw.secs) && Number.isInteger(raw.nsecs));
      const decoded = [ours, jazzy ? [jazzy, ...Object.values(ros2jazzy)] : ours].map((definitions) => {
        const reader = new MessageReader(definitions);
        const message = reader.readMessage(raw.bytes);
        assert.equal(reader.lastReadHadTrailingBytes(), false, `${topic}: every byte read`);
        return message;
      });
      assert.deepEqual(decoded[0], decoded[1], topic);
      if (topic === '/scan') assert.ok(decoded[0].ranges.some((range) => range > 0));
      if (topic === '/people') assert.ok(decoded[0].people.every((person) => person.name && person.tagnames[0] === 'face_visible'));
      if (topic === '/rosout') assert.match(decoded[0].msg, /command|wait/);
      decodedTopics.push(topic);
      if (topic.startsWith('/camera/')) assert.deepEqual([...decoded[0].data.subarray(0, 2)], [0xff, 0xd8], `${topic}: a JPEG`);
    }
    for (const topic of ['/clock', '/tf', '/tf_static', '/people_markers', '/people', '/robot/people', '/rosout', '/scan', '/robot/base_scan', '/odom', '/robot/odom', '/camera/overview/compressed',
      '/camera/robot/head_rgbd/compressed']) {
      assert.ok(decodedTopics.includes(topic), `${topic} in ${decodedTopics}`);
    }
  });

  it('wrong messages get an error status, and the socket goes on', async () => {
    const raw = new WebSocket(url());
    await within(new Promise((resolve, reject) => { raw.once('open', resolve); raw.once('error', reject); }), 'open');
    const replies = [];
    raw.on('message', (data, binary) => replies.push(binary ? data : JSON.parse(data)));
    const answer = async (send) => {
      const count = replies.length;
      raw.send(send);
      await within(new Promise((resolve) => { const poll = setInterval(() => { if (replies.length > count) { clearInterval(poll); resolve(); } }, 5); }), 'status');
      return replies[count];
    };
    const cases = [
      ['{"op": "subscribe", ', /JSON object/],
      [{ op: 'fly' }, /op 'fly'/],
      [{ op: 'subscribe', topic: '/nowhere', id: 'a' }, /no topic \/nowhere/],
      [{ op: 'subscribe', topic: '/scan', type: 'nav_msgs/msg/Odometry' }, /sensor_msgs\/msg\/LaserScan, not "nav_msgs\/msg\/Odometry"/],
      [{ op: 'subscribe', topic: '/scan', throttle_rate: -1 }, /throttle_rate/],
      [{ op: 'advertise', topic: '/cmd_vel', type: 'std_msgs/msg/String' }, /geometry_msgs\/msg\/Twist, not/],
      [{ op: 'publish', topic: '/scan', msg: {} }, /takes nothing here; publish a Twist on \/cmd_vel/],
      [{ op: 'publish', topic: '/cmd_vel', msg: { linear: 1 } }, /linear must be an object/],
      [{ op: 'publish', topic: '/cmd_vel', msg: { linear: { x: 'fast' } } }, /linear\.x must be a number/],
      [{ op: 'publish', topic: '/cmd_vel', msg: { speed: 1 } }, /speed is not a field of geometry_msgs\/msg\/Twist/],
      [new Uint8Array([1, 2, 3]), /binary messages/],
    ];
    for (const [message, says] of cases) {
      const status = await answer(typeof message === 'string' || message instanceof Uint8Array ? message : JSON.stringify(message));
      assert.equal(status.op, 'status', JSON.stringify(status));
      assert.equal(status.level, 'error', status.msg);
      assert.match(status.msg, says);
    }
    assert.equal((await answer(JSON.stringify({ op: 'subscribe', topic: '/nowhere', id: 'a' }))).id, 'a', 'a status carries the op\'s id');
    const failed = await answer(JSON.stringify({ op: 'call_service', service: '/fly', id: 'c' }));
    assert.deepEqual([failed.op, failed.result, failed.id], ['service_response', false, 'c']);
    const unsupported = await answer(JSON.stringify({ op: 'subscribe', topic: '/clock', compression: 'png' }));
    assert.equal(unsupported.level, 'warning');
    // Still served: the clock it subscribed to comes.
    await within(new Promise((resolve) => { const poll = setInterval(() => { if (replies.some((r) => r.op === 'publish' && r.topic === '/clock')) { clearInterval(poll); resolve(); } }, 5); }), '/clock');
    raw.close();
  });
});

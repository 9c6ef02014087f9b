'use strict';
// Sessions of the benchmark task scenarios (docs/benchmark.md): their spaces, steps of the task's
// frame skip with its reward terms in info, the task's ending, and mirror_gesture's camera
// observation fetched over the WebSocket. Every reply is checked against the specs by the client.
const assert = require('node:assert/strict');
const { describe, it } = require('node:test');
const { api } = require('../lib/client');
const { decodeCameraFrame } = require('../lib/camera_frame');

async function createSession(scenario, seed) {
  const reply = await api.post('/api/v1/sessions', { scenario, seed });
  assert.equal(reply.status, 201, reply.body);
  return reply.json;
}

describe('benchmark tasks', () => {
  it('approach_human: 11 observed values, 10 ticks a step, the distance gained as reward, done within 0.3 m', async () => {
    const session = await createSession('approach_human', 3);
    const at = (suffix) => `/api/v1/sessions/${session.id}${suffix}`;
    try {
      const observation = (await api.get(at('/observation_space'))).json;
      assert.deepEqual(observation.shape, [11]);
      const action = (await api.get(at('/action_space'))).json;
      assert.deepEqual(action.shape, [2]);
      const start = (await api.post(at('/reset'), { seed: 3 })).json;
      assert.equal(start.observation.length, 11);
      const step = (await api.post(at('/step'), { action: [0, 0] })).json;
      assert.equal(step.tick, 10, 'one step is the frame skip: 10 ticks');
      assert.equal(step.reward, step.info.distance_reward + step.info.collision_human + step.info.collision_obstacle);
      assert.ok(Math.abs(step.info.distance_reward - (start.observation[10] - step.observation[10])) < 1e-12);
      assert.deepEqual(step.info.touched, []);
      // Put the robot 0.2 m from her: the next step ends the episode.
      const [hx, hy] = [step.observation[6], step.observation[7]];
      const d = Math.hypot(hx, hy);
      const place = { x: hx * (1 - 0.2 / d), y: hy * (1 - 0.2 / d), yaw: 0 };  // the robot stands at the origin facing +x
      assert.equal((await api.put(at('/poses/robot'), place)).status, 200);
      const done = (await api.post(at('/step'), { action: [0, 0] })).json;
      assert.equal(done.terminated, true);
      assert.equal(done.truncated, false);
      const after = (await api.post(at('/step'), { action: [0.2, 0] })).json;
      assert.equal(after.tick, done.tick, 'a terminated episode runs no more ticks');
      assert.equal(after.reward, 0);
    } finally {
      await api.delete(at(''));
    }
  });

  it('pick_and_place: 8 action values, a gripper step of 8 ticks and an arm step of 120; a wrong action names the value', async () => {
    const session = await createSession('pick_and_place', 0);
    const at = (suffix) => `/api/v1/sessions/${session.id}${suffix}`;
    try {
      assert.deepEqual((await api.get(at('/action_space'))).json.shape, [8]);
      assert.deepEqual((await api.get(at('/observation_space'))).json.shape, [18]);
      const gripper = (await api.post(at('/step'), { action: [1, -1, 0, 0, 0, 0, 0, 0] })).json;
      assert.equal(gripper.tick, 8);
      const arm = (await api.post(at('/step'), { action: [-1, 0, 0.3, -1.5708, 0, 0, 0, 0] })).json;
      assert.equal(arm.tick, 128);
      for (const key of ['gripper_object', 'object_target', 'lifting', 'collision_obstacle']) assert.equal(typeof arm.info[key], 'number', key);
      const wrong = await api.post(at('/step'), { action: [1, 1] });
      assert.equal(wrong.status, 400);
      assert.equal(wrong.json.error.details.pointer, '/action');
    } finally {
      await api.delete(at(''));
    }
  });

  it('mirror_gesture: a float32 image space naming its camera; the observation is that camera\'s frame', async () => {
    const session = await createSession('mirror_gesture', 1);
    const at = (suffix) => `/api/v1/sessions/${session.id}${suffix}`;
    const socket = await api.openSocket(session.id);
    try {
      const space = (await api.get(at('/observation_space'))).json;
      assert.deepEqual(space, {
        name: 'Box', shape: [256, 256, 5], dtype: 'float32', low: [0], high: [255],
        camera: { name: 'robot.head_rgbd', width: 256, height: 256 },
      });
      const step = await socket.send({ type: 'step', action: [0, 0, 0, 0, 0, 0] });
      assert.equal(step.observation, null, 'the image is not in the JSON');
      assert.equal(step.tick, 10);
      assert.ok(['left', 'right'].includes(step.info.human_points));
      const frame = decodeCameraFrame(await socket.send({ type: 'camera', camera: space.camera.name, width: 256, height: 256 }));
      assert.equal(frame.tick, 10);
      assert.deepEqual([frame.width, frame.height], [256, 256]);
    } finally {
      socket.close();
      await api.delete(at(''));
    }
  });
});

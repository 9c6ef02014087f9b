'use strict';
// Videos of stored episodes: the cameras to film with, a job from queued to done with its progress,
// the file whole and in a range, the same job asked again, cancelling, and refused requests that
// the spec refuses too. Every reply is checked against the specs by the client.
const assert = require('node:assert/strict');
const { describe, it, before } = require('node:test');
const { api } = require('../lib/client');
const { specAllows } = require('../lib/contract');

const LIMIT_MS = 60000;
const sleep = (ms) => new Promise((resolve) => { setTimeout(resolve, ms); });

/** Polls a video job until it has left the queue and the camera; its last status. */
async function waitForVideo(id) {
  const deadline = Date.now() + LIMIT_MS;
  for (;;) {
    const reply = await api.get(`/api/v1/videos/${id}`);
    assert.equal(reply.status, 200, reply.body);
    if (!['queued', 'filming'].includes(reply.json.status)) return reply.json;
    if (Date.now() > deadline) assert.fail(`video ${id} still ${reply.json.status} after ${LIMIT_MS} ms`);
    await sleep(50);
  }
}

describe('videos of episodes', () => {
  let episode;
  before(async () => {
    const run = await api.post('/api/v1/runs', { scenario: 'queue', seeds: [4], max_time: 3 });
    assert.equal(run.status, 201, run.body);
    for (let report = run.json; ; report = (await api.get(`/api/v1/runs/${run.json.id}`)).json) {
      if (report.status === 'finished') {
        episode = report.episodes[0].episode_id;
        break;
      }
      assert.ok(['queued', 'running'].includes(report.status), JSON.stringify(report.status));
      await sleep(50);
    }
  });

  it('GET /api/v1/episodes/{id}/cameras: the scenario\'s cameras at the first tick', async () => {
    const reply = await api.get(`/api/v1/episodes/${episode}/cameras`);
    assert.equal(reply.status, 200);
    assert.equal(reply.json.episode, episode);
    assert.deepEqual(reply.json.cameras.slice(0, 2).map((camera) => camera.name), ['overview', 'follow']);
  });

  it('POST /api/v1/episodes/{id}/videos: a job films the episode, then GET …/file serves it whole and in ranges', async () => {
    const request = { camera: 'overview', fps: 10, width: 96, format: 'webm' };
    const created = await api.post(`/api/v1/episodes/${episode}/videos`, request);
    assert.equal(created.status, 202, created.body);
    assert.equal(created.headers.location, `/api/v1/videos/${created.json.id}`);
    assert.equal(created.json.width, 96);
    const done = await waitForVideo(created.json.id);
    assert.equal(done.status, 'done', JSON.stringify(done));
    assert.equal(done.codec, 'vp8');
    assert.equal(done.matches_stored_episode, true);
    // 3 s at 60 Hz, a frame every 6 ticks from tick 0.
    assert.equal(done.frames, 31);
    const again = await api.post(`/api/v1/episodes/${episode}/videos`, request);
    assert.equal(again.status, 200);
    assert.equal(again.json.id, created.json.id);

    const whole = await api.get(done.file);
    assert.equal(whole.status, 200);
    assert.equal(whole.headers['content-type'], 'video/webm');
    assert.equal(whole.bytes.length, done.bytes);
    assert.deepEqual([...whole.bytes.subarray(0, 4)], [0x1a, 0x45, 0xdf, 0xa3], 'a Matroska (WebM) container');
    const part = await api.get(done.file, { headers: { range: 'bytes=10-19' } });
    assert.equal(part.status, 206);
    assert.equal(part.headers['content-range'], `bytes 10-19/${done.bytes}`);
    assert.deepEqual(part.bytes, whole.bytes.subarray(10, 20));
    assert.equal((await api.get(done.file, { headers: { range: `bytes=${done.bytes}-` } })).status, 416);
  });

  it('DELETE /api/v1/videos/{id}: cancels a job and forgets it', async () => {
    const created = await api.post(`/api/v1/episodes/${episode}/videos`, { fps: 60, width: 640 });
    assert.equal(created.status, 202, created.body);
    const early = await api.get(`/api/v1/videos/${created.json.id}/file`);
    assert.equal(early.status, 409, 'not done yet');
    assert.ok(['queued', 'filming'].includes(early.json.error.details.status));
    assert.equal((await api.delete(`/api/v1/videos/${created.json.id}`)).status, 204);
    assert.equal((await api.get(`/api/v1/videos/${created.json.id}`)).status, 404);
    assert.equal((await api.delete(`/api/v1/videos/${created.json.id}`)).status, 404);
  });

  it('POST /api/v1/episodes/{id}/videos: what the spec refuses the server refuses, naming the field', async () => {
    for (const [body, pointer] of [[{ fps: 0 }, '/fps'], [{ width: 4096 }, '/width'], [{ format: 'gif' }, '/format'], [{ speed: 2 }, '/speed']]) {
      assert.equal(specAllows('POST', `/api/v1/episodes/${episode}/videos`, body), false, JSON.stringify(body));
      const reply = await api.post(`/api/v1/episodes/${episode}/videos`, body);
      assert.equal(reply.status, 400, JSON.stringify(body));
      assert.equal(reply.json.error.details.pointer, pointer);
    }
    const camera = await api.post(`/api/v1/episodes/${episode}/videos`, { camera: 'ceiling' });
    assert.equal(camera.status, 400);
    assert.equal(camera.json.error.details.pointer, '/camera');
    assert.equal((await api.post(`/api/v1/episodes/e${'0'.repeat(32)}/videos`, {})).status, 404);
  });
});

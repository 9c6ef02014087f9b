'use strict';
// A session's WebSocket (api/asyncapi.yaml): each message answered once, in order; wrong messages get
// an error and the socket stays open; an unknown session is refused before the upgrade.
const assert = require('node:assert/strict');
const { describe, it, before, after } = require('node:test');
const { api } = require('../lib/client');

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
    assert.equal((await socket.send({ type: 'step' })).tick, 6);
  });

  it('commands gives a list; a wrong one is an error naming it', async () => {
    const reply = await socket.send({ type: 'commands', commands: [{ human: 'ada', command: 'wait 1' }] });
    assert.equal(reply.type, 'commands');
    assert.equal(reply.applied, 1);
    const wrong = await socket.send({ type: 'commands', commands: [{ human: 'nobody', command: 'wait 1' }] });
    assert.equal(wrong.type, 'error');
    assert.equal(wrong.error.details.pointer, '/commands/0/human');
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

  it('wrong messages get errors and the socket stays open', async () => {
    const wrong = [['not json', undefined], [{ type: 'jump' }, '/type'], [{ type: 'step', n: 0 }, '/n'],
      [{ type: 'state', events_since: -1 }, '/events_since'], [{ type: 'step', legs: 2 }, '/legs']];
    for (const [message, pointer] of wrong) {
      const reply = await socket.send(message);
      assert.equal(reply.type, 'error', JSON.stringify(message));
      assert.equal(reply.error.code, 'bad_request');
      if (pointer) assert.equal(reply.error.details.pointer, pointer, JSON.stringify(message));
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

  it('a session deleted under an open socket answers not_found', async () => {
    const doomed = await api.post('/api/v1/sessions', { scenario: 'queue' });
    const doomedSocket = await api.openSocket(doomed.json.id);
    await api.delete(`/api/v1/sessions/${doomed.json.id}`);
    const reply = await doomedSocket.send({ type: 'step' });
    assert.equal(reply.type, 'error');
    assert.equal(reply.error.code, 'not_found');
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
});

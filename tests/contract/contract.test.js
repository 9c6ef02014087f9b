'use strict';
// Contract tests: the real hrisim server against api/openapi.yaml and api/asyncapi.yaml.
//   cd tests/contract && npm ci && HRISIM_BINARY=../../build/test/server/app/hrisim node --test
// One server serves every area file; each file under areas/ tests one part of the API. A new area is
// one more require() below; the last test fails while any operation of either spec has not been seen
// to succeed, so a route added to a spec without a test fails the suite.
const assert = require('node:assert/strict');
const { describe, before, after, it } = require('node:test');
const { startServer } = require('./lib/server');
const { api } = require('./lib/client');
const { specProblems, unexercisedOperations } = require('./lib/contract');

// The suite takes seconds; a hang fails it well within ctest's TIMEOUT, naming the test that hung (as
// cancelled), instead of being killed without a word.
const SUITE_LIMIT_MS = 240000;
// Once the tests are done, nothing may keep the process alive (a socket, a timer, a server's pipes).
const LINGER_LIMIT_MS = 10000;

describe('hrisim contract', { timeout: SUITE_LIMIT_MS }, () => {
  let server;
  before(async () => {
    server = await startServer(['--max-sessions', '6']);
    api.connect(server.port);
  });
  after(async () => {
    try {
      await server.stop();
    } finally {
      setTimeout(() => {
        process.stderr.write(`still running ${LINGER_LIMIT_MS} ms after the tests: ${process.getActiveResourcesInfo().join(', ')}\n`);
        process.exit(1);
      }, LINGER_LIMIT_MS).unref();
    }
  });

  it('both specs say what they mean and compile in strict mode', () => {
    assert.deepEqual(specProblems(), []);
  });

  require('./areas/server');
  require('./areas/scenarios');
  require('./areas/sessions');
  require('./areas/session_socket');
  require('./areas/foxglove');
  require('./areas/rosbridge');
  require('./areas/runs');
  require('./areas/tasks');
  require('./areas/videos');
  require('./areas/imports');

  it('exercised every operation of both specs', () => {
    assert.deepEqual(unexercisedOperations(), [], 'operations no test has seen succeed');
  });
});

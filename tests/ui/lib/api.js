'use strict';
// The areas' own calls to the server under test, beside the browser: set up what a page shows, and
// check what it did.
const assert = require('node:assert/strict');
const context = require('./context');

/** One request to the server; resolves to { status, body } (the body parsed, or null when empty). */
async function call(method, path, body) {
  const response = await fetch(`http://127.0.0.1:${context.server.port}${path}`, {
    method,
    headers: body ? { 'content-type': 'application/json' } : {},
    body: body ? JSON.stringify(body) : undefined,
  });
  const text = await response.text();
  return { status: response.status, body: text ? JSON.parse(text) : null };
}

/** Creates a session (POST /api/v1/sessions with `body`); resolves to its id. */
async function createSession(body) {
  const created = await call('POST', '/api/v1/sessions', body);
  assert.equal(created.status, 201, JSON.stringify(created.body));
  return created.body.id;
}

module.exports = { call, createSession };

'use strict';
// The server itself: health, version, the spec it serves, built-in robots, static files, unknown
// paths and methods, and a server started with a bearer token.
const assert = require('node:assert/strict');
const fs = require('node:fs');
const path = require('node:path');
const zlib = require('node:zlib');
const YAML = require('yaml');
const { describe, it, before, after } = require('node:test');
const { api, Client } = require('../lib/client');
const { httpOperations, repoRoot } = require('../lib/contract');
const { startServer } = require('../lib/server');

describe('server', () => {
  it('GET /healthz: the server and its database answer', async () => {
    const reply = await api.get('/healthz');
    assert.equal(reply.status, 200);
    assert.deepEqual(reply.json, { status: 'ok', database: 'ok' });
  });

  it('GET /api/v1/version names hrisim and its libraries', async () => {
    const reply = await api.get('/api/v1/version');
    assert.equal(reply.status, 200);
    assert.equal(reply.json.name, 'hrisim');
    assert.ok(reply.json.libraries.sqlite);
  });

  it('GET /api/v1/openapi.yaml serves api/openapi.yaml', async () => {
    const reply = await api.get('/api/v1/openapi.yaml');
    assert.equal(reply.status, 200);
    const onDisk = YAML.parse(fs.readFileSync(path.join(repoRoot, 'api/openapi.yaml'), 'utf8'));
    assert.deepEqual(YAML.parse(reply.body), onDisk, 'the binary embeds another api/openapi.yaml: rebuild it');
  });

  it('GET /api/v1/openapi.json serves the same description as JSON', async () => {
    const reply = await api.get('/api/v1/openapi.json');
    assert.equal(reply.status, 200);
    assert.match(reply.json.openapi, /^3\.1\./);
    const served = YAML.parse((await api.get('/api/v1/openapi.yaml')).body);
    assert.deepEqual(reply.json, served, 'the JSON is the YAML the server serves');
    const onDisk = YAML.parse(fs.readFileSync(path.join(repoRoot, 'api/openapi.yaml'), 'utf8'));
    assert.deepEqual(reply.json, onDisk, 'the binary embeds another api/openapi.yaml: rebuild it');
  });

  it('GET /api/v1/robots lists the built-in robots', async () => {
    const reply = await api.get('/api/v1/robots');
    assert.equal(reply.status, 200);
    assert.deepEqual(reply.json.items.map((robot) => robot.name).sort(), ['artos', 'hsr', 'roman']);
  });

  it('GET /api/v1/robots/{name}: one robot; 404 names the known ones', async () => {
    const hsr = await api.get('/api/v1/robots/hsr');
    assert.equal(hsr.status, 200);
    assert.equal(hsr.json.summary.name, 'hsr');
    const unknown = await api.get('/api/v1/robots/r2d2');
    assert.equal(unknown.status, 404);
    assert.equal(unknown.json.error.code, 'not_found');
    assert.match(unknown.json.error.message, /hsr/);
  });

  it('GET /{path}: a UI file; 404 for a missing one, 400 for ".."', async () => {
    const page = await api.get('/index.html');
    assert.equal(page.status, 200);
    assert.match(page.headers['content-type'], /^text\/html/);
    assert.equal((await api.get('/missing.html')).status, 404);
    assert.equal((await api.get('/..')).status, 400);
  });

  it('GET /{path}: the UI\'s libraries at the versions web/package.json pins, kept a year; text gzipped; a conditional GET is 304', async () => {
    const page = (await api.get('/index.html')).body;
    const pinned = JSON.parse(fs.readFileSync(path.join(repoRoot, 'web', 'package.json'), 'utf8')).dependencies;
    const libraries = [...page.matchAll(/"(\/lib\/([a-z0-9-]+)@([0-9.]+)\/[^"]*)"/g)];
    assert.deepEqual([...new Set(libraries.map((match) => match[2]))].sort(), Object.keys(pinned).sort(), 'every library the page uses, and only those');
    for (const [, url, name, version] of libraries) {
      assert.equal(version, pinned[name], `${url}: the version web/package.json pins`);
      if (url.endsWith('/')) continue;  // an import map prefix
      const reply = await api.get(url, { headers: { 'accept-encoding': 'gzip' } });
      assert.equal(reply.status, 200, url);
      assert.equal(reply.headers['cache-control'], 'public, max-age=31536000, immutable', url);
    }
    const script = await api.get('/app.js', { headers: { 'accept-encoding': 'gzip' } });
    assert.equal(script.headers['content-encoding'], 'gzip');
    assert.equal(zlib.gunzipSync(script.bytes).toString('utf8'), fs.readFileSync(path.join(repoRoot, 'web', 'app.js'), 'utf8'));
    assert.equal(script.headers['cache-control'], 'no-cache');
    const again = await api.get('/app.js', { headers: { 'accept-encoding': 'gzip', 'if-none-match': script.headers.etag } });
    assert.equal(again.status, 304);
    assert.equal(again.bytes.length, 0);
  });

  it('an unknown API path is a JSON 404', async () => {
    const reply = await api.get('/api/v1/nothing-here');
    assert.equal(reply.status, 404);
    assert.equal(reply.json.error.code, 'not_found');
  });

  it('a method a path does not have is a JSON 405 with Allow', async () => {
    const reply = await api.request('PATCH', '/api/v1/robots');
    assert.equal(reply.status, 405);
    assert.equal(reply.json.error.code, 'method_not_allowed');
    assert.equal(reply.headers.allow, 'GET');
  });
});

describe('server with a token', () => {
  const token = 'contract-test-token-0123456789';
  let server;
  let withToken;
  let withoutToken;
  before(async () => {
    server = await startServer(['--token', token]);
    withToken = new Client(server.port, { token });
    withoutToken = new Client(server.port);
  });
  after(async () => {
    await server.stop();
  });

  it('every operation that names bearer security answers 401 without the token', async () => {
    for (const operation of httpOperations.filter((candidate) => candidate.needsToken)) {
      const target = operation.template.replace(/\{[^}]+\}/g, 'x');
      const reply = await withoutToken.request(operation.method, target);
      assert.equal(reply.status, 401, operation.key);
      assert.equal(reply.json.error.code, 'unauthorized', operation.key);
      assert.equal(reply.headers['www-authenticate'], 'Bearer realm="hrisim"', operation.key);
    }
  });

  it('a wrong token is 401, the right one passes', async () => {
    const wrong = await withToken.get('/api/v1/scenarios', { token: 'not-the-token-at-all' });
    assert.equal(wrong.status, 401);
    assert.equal((await withToken.get('/api/v1/scenarios')).status, 200);
  });

  it('operations without bearer security need no token', async () => {
    const open = httpOperations.filter((candidate) => !candidate.needsToken);
    assert.ok(open.length > 0);
    for (const operation of open) {
      const target = operation.template === '/{path}' ? '/index.html' : operation.template;
      assert.equal((await withoutToken.request(operation.method, target)).status, 200, operation.key);
    }
  });

  it('a session WebSocket without the token is refused with 401 before the upgrade', async () => {
    const created = await withToken.post('/api/v1/sessions', { scenario: 'pair_walking' });
    assert.equal(created.status, 201);
    await assert.rejects(withoutToken.openSocket(created.json.id), (error) => error.refused?.status === 401);
    const socket = await withToken.openSocket(created.json.id);
    socket.close();
  });
});

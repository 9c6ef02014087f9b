'use strict';
// Importing runs: a database made by hrisim on another machine (two shards merged) goes into the
// server's, its run listed with its report; importing it again adds nothing; a body that is not a
// database, and a shard of another scenario content under the same run, are refused. Every reply is
// checked against the specs by the client.
const assert = require('node:assert/strict');
const { execFileSync } = require('node:child_process');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { describe, it, before, after } = require('node:test');
const { api } = require('../lib/client');
const { repoRoot } = require('../lib/contract');

/** hrisim run|merge … with the bundled scenarios; its stdout as JSON. */
function hrisim(args) {
  const env = { ...process.env, HRISIM_SCENARIOS: path.join(repoRoot, 'scenarios') };
  try {
    return JSON.parse(execFileSync(path.resolve(process.env.HRISIM_BINARY), args, { env, stdio: ['ignore', 'pipe', 'ignore'] }).toString());
  } catch (error) {
    if (error.stdout?.length) return JSON.parse(error.stdout.toString());  // exit 1: a failed verdict, still a report
    throw error;
  }
}

const post = (bytes) => api.request('POST', '/api/v1/runs/import', { body: bytes, contentType: 'application/vnd.sqlite3' });

describe('importing runs', () => {
  let dir;
  let merged;
  before(() => {
    dir = fs.mkdtempSync(path.join(os.tmpdir(), 'hrisim-import-'));
    const queue = path.join(repoRoot, 'scenarios/queue.json');
    for (const k of [1, 2]) hrisim(['run', queue, '--seeds', '1-6', '--max-time', '2', '--name', 'imported', '--shard', `${k}/2`, '--db', path.join(dir, `shard-${k}.db`)]);
    merged = hrisim(['merge', path.join(dir, 'shard-1.db'), path.join(dir, 'shard-2.db'), '--into', path.join(dir, 'results.db')]);
    // The same run from an edited copy of the scenario: another content under the same name.
    const edited = { ...JSON.parse(fs.readFileSync(queue, 'utf8')), description: 'edited' };
    fs.writeFileSync(path.join(dir, 'queue.json'), JSON.stringify(edited));
    hrisim(['run', path.join(dir, 'queue.json'), '--seeds', '1-6', '--max-time', '2', '--name', 'imported', '--shard', '2/2', '--db', path.join(dir, 'edited.db')]);
  });
  after(() => fs.rmSync(dir, { recursive: true, force: true }));

  it('POST /api/v1/runs/import: a merged database\'s run appears with its report; again, nothing is added', async () => {
    const bytes = fs.readFileSync(path.join(dir, 'results.db'));
    const imported = await post(bytes);
    assert.equal(imported.status, 200, imported.body);
    assert.deepEqual(imported.json.runs, [{ id: merged.id, source_id: merged.id, added: 6, present: 0 }]);
    const report = (await api.get(`/api/v1/runs/${merged.id}`)).json;
    assert.equal(report.name, 'imported');
    assert.deepEqual(report.aggregates, merged.aggregates);
    assert.deepEqual(report.verdict, merged.verdict);
    assert.ok((await api.get('/api/v1/runs?q=imported')).json.items.some((run) => run.id === merged.id));
    const again = await post(bytes);
    assert.deepEqual(again.json.runs, [{ id: merged.id, source_id: merged.id, added: 0, present: 6 }]);
  });

  it('POST /api/v1/runs/import: refuses what is not a database, and a shard of another scenario content (409, nothing kept)', async () => {
    const text = await post(Buffer.from('not a database'));
    assert.equal(text.status, 400);
    assert.match(text.json.error.message, /not an SQLite database/);
    const conflicting = await post(fs.readFileSync(path.join(dir, 'edited.db')));
    assert.equal(conflicting.status, 409, conflicting.body);
    // The importer learns that the server's run differs, not what it holds.
    assert.match(conflicting.json.error.message, /its scenario's content \(sha256\) is [0-9a-f]{64} in the uploaded database, another in this server's$/);
    assert.equal((await api.get(`/api/v1/runs/${merged.id}`)).json.episodes.length, 6);
  });
});

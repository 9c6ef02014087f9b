'use strict';
// deploy/: the Kubernetes manifests validated offline against Kubernetes' own schemas (the
// kubernetes-models package: types, required fields, enums; like the API server, the schemas allow
// unknown field names, so the fields the recipe relies on are checked by name below), and their shell
// commands run with the real hrisim (paths mapped onto this machine, fewer seeds): the four shards'
// pods, then the merge, give a complete run. The Slurm scripts are checked by bash -n here; running
// them on a real cluster is tests/slurm's.
//   cd tests/deploy && npm ci && HRISIM_BINARY=../../build/test/server/app/hrisim node --test
const assert = require('node:assert/strict');
const { execFileSync, spawnSync } = require('node:child_process');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { describe, it } = require('node:test');
const YAML = require('yaml');
const { Job } = require('kubernetes-models/batch/v1/Job');
const { PersistentVolumeClaim } = require('kubernetes-models/v1/PersistentVolumeClaim');

const SOURCE = path.resolve(__dirname, '../..');
const KUBERNETES = path.join(SOURCE, 'deploy/kubernetes');
const MODELS = { 'batch/v1 Job': Job, 'v1 PersistentVolumeClaim': PersistentVolumeClaim };

/** Every document of every manifest, by kind and name. */
function manifests() {
  const found = {};
  for (const file of fs.readdirSync(KUBERNETES).filter((name) => name.endsWith('.yaml'))) {
    for (const document of YAML.parseAllDocuments(fs.readFileSync(path.join(KUBERNETES, file), 'utf8'))) {
      assert.deepEqual(document.errors, [], `${file}: YAML errors`);
      const object = document.toJS();
      found[`${object.kind}/${object.metadata.name}`] = { file, object };
    }
  }
  return found;
}

describe('deploy/kubernetes', () => {
  const all = manifests();
  const shards = all['Job/hrisim-shards']?.object;
  const merge = all['Job/hrisim-merge']?.object;
  const volume = all['PersistentVolumeClaim/hrisim-results']?.object;

  it('holds the shards\' Indexed Job, the merge Job and the results volume, each valid by Kubernetes\' schema', () => {
    assert.ok(shards && merge && volume, `found ${Object.keys(all).join(', ')}`);
    for (const [name, { file, object }] of Object.entries(all)) {
      const Model = MODELS[`${object.apiVersion} ${object.kind}`];
      assert.ok(Model, `${file}: ${name} is a ${object.apiVersion} ${object.kind}, which this test does not know`);
      assert.doesNotThrow(() => new Model(object).validate(), `${file}: ${name}`);
    }
  });

  it('the schema check catches a wrong field', () => {
    const broken = structuredClone(shards);
    broken.spec.completions = 'four';
    assert.throws(() => new Job(broken).validate(), /completions must be integer/);
  });

  it('the shards are one Indexed Job whose completions, parallelism and --shard auto/N agree, on the shared volume', () => {
    const container = shards.spec.template.spec.containers[0];
    const command = container.args.join(' ');
    assert.equal(shards.spec.completionMode, 'Indexed');
    const count = Number(command.match(/--shard auto\/(\d+)/)?.[1]);
    assert.equal(shards.spec.completions, count, 'completions = the N of --shard auto/N');
    assert.equal(shards.spec.parallelism, count);
    assert.equal(shards.spec.template.spec.restartPolicy, 'Never');
    for (const job of [shards, merge]) {
      const pod = job.spec.template.spec;
      assert.equal(pod.volumes[0].persistentVolumeClaim.claimName, volume.metadata.name);
      assert.equal(pod.containers[0].volumeMounts[0].mountPath, '/results');
      assert.equal(pod.containers[0].image, container.image, 'the same image for shards and merge');
    }
    assert.ok(volume.spec.accessModes.includes('ReadWriteMany'), 'every pod writes the volume at once');
    assert.match(command, /--db \/results\/shard-\$\(\(JOB_COMPLETION_INDEX \+ 1\)\)\.db/);
    assert.match(merge.spec.template.spec.containers[0].args.join(' '), /hrisim merge \/results\/shard-\*\.db --into \/results\/results\.db/);
  });

  it('the pods\' commands, run here with the real hrisim, give a complete merged run', () => {
    const binary = process.env.HRISIM_BINARY;
    assert.ok(binary, 'HRISIM_BINARY names the hrisim to run');
    const results = fs.mkdtempSync(path.join(os.tmpdir(), 'hrisim-deploy-'));
    const bin = fs.mkdtempSync(path.join(os.tmpdir(), 'hrisim-bin-'));
    try {
      fs.symlinkSync(path.resolve(binary), path.join(bin, 'hrisim'));
      // The image's paths mapped onto this machine; 40 seeds and 2 s episodes instead of the recipe's 1,000.
      const onThisMachine = (text) => text.replaceAll('/opt/hrisim/scenarios', path.join(SOURCE, 'scenarios')).replaceAll('/results', results)
        .replace('--seeds 1-1000', '--seeds 1-40 --max-time 2');
      const env = { ...process.env, PATH: `${bin}:${process.env.PATH}` };
      const shardCommand = onThisMachine(shards.spec.template.spec.containers[0].args.join(' '));
      for (let index = 0; index < shards.spec.completions; index++) {
        const pod = spawnSync('/bin/sh', ['-c', shardCommand], { env: { ...env, JOB_COMPLETION_INDEX: String(index) }, encoding: 'utf8' });
        assert.equal(pod.status, 0, `pod ${index}: ${pod.stderr}`);
        assert.equal(JSON.parse(fs.readFileSync(path.join(results, `shard-${index + 1}.json`), 'utf8')).config.sharding.index, index + 1);
      }
      const merged = spawnSync('/bin/sh', ['-c', onThisMachine(merge.spec.template.spec.containers[0].args.join(' '))], { env, encoding: 'utf8' });
      assert.equal(merged.status, 0, merged.stderr);
      const report = JSON.parse(fs.readFileSync(path.join(results, 'report.json'), 'utf8'));
      assert.deepEqual(report.config.sharding.merged, [1, 2, 3, 4]);
      assert.equal(report.episodes.length, 40);
      assert.equal(report.verdict.complete, true);
      assert.ok(fs.readFileSync(path.join(results, 'report.xml'), 'utf8').includes('<testsuites tests="1"'));
    } finally {
      fs.rmSync(results, { recursive: true, force: true });
      fs.rmSync(bin, { recursive: true, force: true });
    }
  });
});

describe('deploy/slurm', () => {
  it('its scripts are valid bash', () => {
    for (const file of ['shard.sbatch', 'merge.sbatch', 'submit.sh']) {
      execFileSync('bash', ['-n', path.join(SOURCE, 'deploy/slurm', file)]);
    }
  });
});

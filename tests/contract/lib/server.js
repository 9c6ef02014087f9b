'use strict';
// Starts the real `hrisim serve` (HRISIM_BINARY) on a free loopback port with a temporary database, as
// tests/api/test_server.cpp does.
const { spawn } = require('node:child_process');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { repoRoot } = require('./contract');

const START_LIMIT_MS = 20000;
const STOP_LIMIT_MS = 20000;

/**
 * Starts a server with `extraArgs` after the defaults; resolves once it prints the port it listens on.
 * Its database is in a new temporary folder, removed when it stops, or in `dir` (kept) when given, so
 * that a second server can open what a first one left.
 */
async function startServer(extraArgs = [], { dir: keptDir } = {}) {
  const binary = process.env.HRISIM_BINARY;
  if (!binary) throw new Error('set HRISIM_BINARY to the hrisim binary, e.g. build/test/server/app/hrisim');
  const dir = keptDir ?? fs.mkdtempSync(path.join(os.tmpdir(), 'hrisim-contract-'));
  // The caller's HRISIM_* variables (a token, another port) must not change the server under test.
  const env = Object.fromEntries(Object.entries(process.env).filter(([name]) => !name.startsWith('HRISIM_')));
  env.HRISIM_SCENARIOS = path.join(repoRoot, 'scenarios');
  const args = ['serve', '--host', '127.0.0.1', '--port', '0', '--db', path.join(dir, 'hrisim.db'), '--log-requests', '0', ...extraArgs];
  const child = spawn(path.resolve(binary), args, { cwd: repoRoot, env, stdio: ['ignore', 'pipe', 'pipe'] });
  // Never outlive the test process, even when it ends early (a failed hook, an uncaught error).
  const killOnExit = () => child.kill('SIGKILL');
  process.on('exit', killOnExit);
  let output = '';
  const exited = new Promise((resolve) => child.on('exit', (code, signal) => resolve(code ?? `signal ${signal}`)));
  const started = new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`hrisim serve did not start within ${START_LIMIT_MS} ms:\n${output}`)), START_LIMIT_MS);
    const collect = (chunk) => {
      output += chunk;
      // The whole port: a chunk may end in the middle of it.
      const listening = /listening on http:\/\/[^:\s]+:(\d+)\D/.exec(output);
      if (listening) {
        clearTimeout(timer);
        resolve(Number(listening[1]));
      }
    };
    child.stdout.setEncoding('utf8').on('data', collect);
    child.stderr.setEncoding('utf8').on('data', collect);
    child.on('error', (error) => reject(error));
    exited.then((status) => reject(new Error(`hrisim serve exited at start (${status}):\n${output}`)));
  });
  let port;
  try {
    port = await started;
  } catch (error) {
    // A server that did not start in time must not stay: its pipes would keep the tests from ending.
    child.kill('SIGKILL');
    let timer;
    await Promise.race([exited, new Promise((resolve) => { timer = setTimeout(resolve, STOP_LIMIT_MS); })]);  // no exit when spawn failed
    clearTimeout(timer);
    process.off('exit', killOnExit);
    if (!keptDir) fs.rmSync(dir, { recursive: true, force: true });
    throw error;
  }

  return {
    port,
    output: () => output,
    /** SIGTERM, then the exit status (SIGKILL and an error after STOP_LIMIT_MS). */
    async stop() {
      child.kill('SIGTERM');
      let timer;
      const status = await Promise.race([exited, new Promise((resolve) => { timer = setTimeout(() => resolve('timeout'), STOP_LIMIT_MS); })]);
      clearTimeout(timer);
      process.off('exit', killOnExit);
      if (status === 'timeout') child.kill('SIGKILL');
      if (!keptDir) fs.rmSync(dir, { recursive: true, force: true });
      if (status !== 0) throw new Error(`hrisim serve did not stop cleanly (${status}):\n${output}`);
    },
    /** SIGKILL, as a crash: the server gets no chance to tidy up. Resolves once it is gone. */
    async kill() {
      child.kill('SIGKILL');
      await exited;
      process.off('exit', killOnExit);
      if (!keptDir) fs.rmSync(dir, { recursive: true, force: true });
    },
  };
}

module.exports = { startServer };

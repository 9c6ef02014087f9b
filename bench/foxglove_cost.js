'use strict';
// What the Foxglove stream costs a session (issue 43, item 5): a realtime elevator session at 1× on a
// server this script starts, its CPU time measured from /proc with no client, then with a Foxglove
// client (a raw WebSocket offering foxglove.sdk.v1) subscribed to the scene, the transforms, the
// lasers and one camera at 320 × 240, all at 30 Hz, reading everything. The cost is the difference
// in CPU seconds per wall-clock second: the share of one core, which is the session's whole real-time
// budget (a second of simulation due every second). Rounds alternate without and with the client.
//   usage: node bench/foxglove_cost.js [build dir=build/release] [seconds per measure=10] [rounds=3]
// Needs tests/contract's npm packages (scripts/npm-deps tests/contract) for `ws`.
const { spawn } = require('node:child_process');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const repo = path.resolve(__dirname, '..');
const WebSocket = require(path.join(repo, 'tests/contract/node_modules/ws'));

const [buildDir = 'build/release', seconds = '10', rounds = '3'] = process.argv.slice(2);
const CLOCK_TICKS = 100;  // getconf CLK_TCK on Linux
const sleep = (ms) => new Promise((resolve) => { setTimeout(resolve, ms); });
const median = (values) => [...values].sort((a, b) => a - b)[Math.floor(values.length / 2)];

/** The server's user and system CPU time so far, s. */
function cpuSeconds(pid) {
  const fields = fs.readFileSync(`/proc/${pid}/stat`, 'utf8').split(') ')[1].split(' ');
  return (Number(fields[11]) + Number(fields[12])) / CLOCK_TICKS;
}

async function startServer() {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'hrisim-foxglove-bench-'));
  const child = spawn(path.join(repo, buildDir, 'server/app/hrisim'),
    ['serve', '--port', '0', '--db', path.join(dir, 'bench.db'), '--log-requests', '0'], { cwd: repo, stdio: ['ignore', 'pipe', 'inherit'] });
  const port = await new Promise((resolve) => {
    let output = '';
    child.stdout.on('data', (chunk) => {
      output += chunk;
      const found = output.match(/listening on http:\/\/[^:]+:(\d+)/);
      if (found) resolve(Number(found[1]));
    });
  });
  return { child, port };
}

async function post(port, target, body) {
  const response = await fetch(`http://127.0.0.1:${port}${target}`, { method: 'POST', headers: { 'content-type': 'application/json' }, body: JSON.stringify(body) });
  return response.json();
}

/** A Foxglove client subscribed to the scene, transforms, lasers and the robot's head camera; counts what it reads. */
function openStream(port, session) {
  const url = `ws://127.0.0.1:${port}/api/v1/sessions/${session}/foxglove?rate=30&image_rate=30&image_width=320&image_height=240`;
  const ws = new WebSocket(url, ['foxglove.sdk.v1']);
  const counts = { messages: {}, bytes: 0 };
  const topics = new Map();
  ws.on('message', (data, binary) => {
    counts.bytes += data.length;
    if (!binary) {
      const message = JSON.parse(data);
      if (message.op !== 'advertise') return;
      const wanted = message.channels.filter((c) => ['/scene', '/tf', '/camera/robot.head_rgbd'].includes(c.topic) || c.schemaName === 'foxglove.LaserScan');
      wanted.forEach((c) => topics.set(c.id, c.topic));
      ws.send(JSON.stringify({ op: 'subscribe', subscriptions: wanted.map((c) => ({ id: c.id, channelId: c.id })) }));
      return;
    }
    if (data[0] !== 1) return;
    const topic = topics.get(data.readUInt32LE(1));
    counts.messages[topic] = (counts.messages[topic] ?? 0) + 1;
  });
  return { ws, counts };
}

/** CPU seconds per wall-clock second of the server over `seconds`. */
async function measure(pid) {
  const cpu = cpuSeconds(pid), start = process.hrtime.bigint();
  await sleep(Number(seconds) * 1000);
  return (cpuSeconds(pid) - cpu) / (Number(process.hrtime.bigint() - start) / 1e9);
}

async function main() {
  const { child, port } = await startServer();
  try {
    const session = await post(port, '/api/v1/sessions', { scenario: 'elevator', seed: 1, mode: 'realtime' });
    await sleep(2000);
    const without = [], withStream = [], rates = [];
    for (let round = 0; round < Number(rounds); round++) {
      without.push(await measure(child.pid));
      const stream = openStream(port, session.id);
      await sleep(2000);  // subscribed, the fixed scene sent
      const before = { ...stream.counts.messages };
      withStream.push(await measure(child.pid));
      rates.push(Object.fromEntries(Object.entries(stream.counts.messages).map(([topic, n]) => [topic, (n - (before[topic] ?? 0)) / Number(seconds)])));
      stream.ws.close();
      await sleep(1000);
      console.log(`round ${round + 1}: without ${without[round].toFixed(3)}, with ${withStream[round].toFixed(3)} CPU s/s; messages/s ${JSON.stringify(rates[round], (k, v) => (typeof v === 'number' ? Number(v.toFixed(1)) : v))}`);
    }
    const costs = withStream.map((w, i) => w - without[i]);
    console.log(`median: without ${median(without).toFixed(3)}, with ${median(withStream).toFixed(3)} CPU s/s; the stream costs ${(100 * median(costs)).toFixed(1)} % of the session's real-time budget (one core)`);
  } finally {
    child.kill('SIGTERM');
  }
}

main().catch((error) => { console.error(error); process.exit(1); });

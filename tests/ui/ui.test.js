'use strict';
// The browser UI in a real browser: Debian's Chromium against the real server (a temporary database,
// the bundled scenarios, web/ as the UI).
//   cd tests/ui && npm ci && HRISIM_BINARY=../../build/test/server/app/hrisim node --test
// One server and one browser serve every area file under areas/; each tests one part of the UI and
// leaves a screenshot of each page it visits in HRISIM_UI_ARTIFACTS. HRISIM_UI_AREAS=session,runs
// runs only those areas (ctest runs the areas as shards side by side).
const fs = require('node:fs');
const path = require('node:path');
const { describe, before, after } = require('node:test');
const { startServer } = require('../contract/lib/server');
const { launchBrowser } = require('./lib/browser');
const context = require('./lib/context');

const SUITE_LIMIT_MS = 300000;
const LINGER_LIMIT_MS = 10000;

describe('hrisim UI', { timeout: SUITE_LIMIT_MS }, () => {
  before(async () => {
    context.server = await startServer(['--max-sessions', '8']);
    context.browser = await launchBrowser();
  });
  after(async () => {
    try {
      if (context.browser) await context.browser.close();
      if (context.server) await context.server.stop();
    } finally {
      setTimeout(() => {
        process.stderr.write(`still running ${LINGER_LIMIT_MS} ms after the tests: ${process.getActiveResourcesInfo().join(', ')}\n`);
        process.exit(1);
      }, LINGER_LIMIT_MS).unref();
    }
  });

  // Every area file, or those HRISIM_UI_AREAS names, in name order (as the whole suite runs them).
  const areas = fs.readdirSync(path.join(__dirname, 'areas')).filter((name) => name.endsWith('.js')).sort();
  const wanted = process.env.HRISIM_UI_AREAS ? process.env.HRISIM_UI_AREAS.split(',').sort() : areas.map((name) => name.slice(0, -3));
  for (const area of wanted) {
    if (!areas.includes(`${area}.js`)) throw new Error(`no UI test area ${area} (areas: ${areas.join(', ')})`);
    require(path.join(__dirname, 'areas', `${area}.js`));
  }
});

'use strict';
// What ui.test.js starts for every area: `server` (from ../contract/lib/server.js: `port`, `stop`) and
// `browser` (playwright's). Areas read them inside their tests, after ui.test.js's before() ran.
module.exports = { server: null, browser: null };

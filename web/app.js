// The browser UI: a hash router over the pages in pages/. Each page module exports
// `render(root, params, query)`, which fills `root` and may return a function that cleans up (closes
// sockets, stops timers) when the user leaves the page.
import { api, ApiError, savedToken, saveToken } from './lib/api.js';
import { h, showError, errorPage } from './lib/ui.js';

const routes = [
  { pattern: /^\/?$/, page: 'scenarios', nav: 'scenarios' },
  { pattern: /^\/scenarios\/([^/]+)$/, page: 'scenario', nav: 'scenarios', keys: ['id'] },
  { pattern: /^\/sessions$/, page: 'sessions', nav: 'sessions' },
  { pattern: /^\/sessions\/([^/]+)$/, page: 'session', nav: 'sessions', keys: ['id'] },
  { pattern: /^\/runs$/, page: 'runs', nav: 'runs' },
  { pattern: /^\/runs\/([^/]+)$/, page: 'run', nav: 'runs', keys: ['id'] },
  { pattern: /^\/episodes\/([^/]+)$/, page: 'episode', nav: 'runs', keys: ['id'] },
  { pattern: /^\/compare$/, page: 'compare', nav: 'runs' },
  { pattern: /^\/compare\/([^/]+)\/([^/]+)$/, page: 'compare', nav: 'runs', keys: ['a', 'b'] },
  { pattern: /^\/controllers$/, page: 'controllers', nav: 'controllers' },
];

let cleanup = null;
let navigation = 0;
const HOME = { href: '#/', text: 'Back to the scenarios' };

/**
 * After a navigation, keyboard and screen reader users start at the new page's heading, unless they
 * already went on into the page while it loaded.
 */
function focusHeading(root) {
  if (root.contains(document.activeElement) && document.activeElement !== root) return;
  root.querySelector('h1')?.focus();
}

async function show({ navigated = true } = {}) {
  const current = ++navigation;
  if (cleanup) {
    try { cleanup(); } catch (error) { console.warn('cleaning up the last page failed', error); }
    cleanup = null;
  }
  // Only the path is decoded here: URLSearchParams decodes the query's values once ('&', '+' or '%' in a search stay theirs).
  const [encodedPath, queryText = ''] = (location.hash.slice(1) || '/').split('?');
  const path = decodeURIComponent(encodedPath);
  const query = new URLSearchParams(queryText);
  const root = document.getElementById('main');
  root.replaceChildren();
  const route = routes.find((r) => r.pattern.test(path));
  for (const link of document.querySelectorAll('[data-nav]')) {
    if (route && link.dataset.nav === route.nav) link.setAttribute('aria-current', 'page');
    else link.removeAttribute('aria-current');
  }
  if (!route) {
    errorPage(root, 'Page', new ApiError(404, { error: { code: 'not_found', message: `No page at ${path}` } }), HOME);
    if (navigated) focusHeading(root);
    return;
  }
  const match = route.pattern.exec(path);
  const params = Object.fromEntries((route.keys ?? []).map((key, i) => [key, match[i + 1]]));
  try {
    const module = await import(`./pages/${route.page}.js`);
    if (current !== navigation) return;  // the user moved on meanwhile
    const done = await module.render(root, params, query);
    if (current !== navigation) {
      if (typeof done === 'function') done();
      return;
    }
    cleanup = typeof done === 'function' ? done : null;
  } catch (error) {
    if (current !== navigation) return;
    if (root.querySelector('h1')) showError(root, error);
    else errorPage(root, 'Page', error, HOME);
  }
  if (navigated && current === navigation) focusHeading(root);
}

async function showServer() {
  const status = document.getElementById('server-status');
  try {
    const version = await api.get('/api/v1/version');
    status.textContent = `hrisim ${version.version}`;
    status.title = `commit ${version.git_commit}`;
  } catch (error) {
    status.textContent = `server: ${error.message}`;
    status.classList.add('error');
  }
}

/** A server started with --token answers 401 until the page has the token: ask for it, once. */
function askForToken() {
  if (document.getElementById('token-form')) return;
  const input = h('input', { type: 'password', id: 'token-input', autocomplete: 'off', required: true });
  const form = h('form', { id: 'token-form', class: 'message info token-form',
    onsubmit: (event) => {
      event.preventDefault();
      saveToken(input.value.trim());
      location.reload();
    } },
    h('p', {}, savedToken()
      ? 'The server refused the saved token. Give the one it was started with (--token or HRISIM_TOKEN).'
      : 'This server was started with a token (--token or HRISIM_TOKEN): give it to use the API from this browser. It is kept in this browser only.'),
    h('div', { class: 'fields' }, h('label', { for: 'token-input' }, 'Token', input), h('button', { type: 'submit' }, 'Use this token'),
      savedToken() ? h('button', { type: 'button', class: 'secondary', onclick: () => { saveToken(''); location.reload(); } }, 'Forget the saved token') : null));
  document.querySelector('header.top').after(form);
  input.focus();
}

// The skip link would change the hash (and so the page): it moves the focus instead.
document.querySelector('a.skip').addEventListener('click', (event) => {
  event.preventDefault();
  (document.querySelector('#main h1') ?? document.getElementById('main')).focus();
});
window.addEventListener('hrisim-unauthorized', askForToken);
window.addEventListener('hashchange', () => show());
show({ navigated: false });
showServer();

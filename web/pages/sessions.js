// #/sessions: the server's live sessions (this browser's token's, with tokens), refreshed every few
// seconds while the page is shown: what each runs, how far it is, who watches it and what ends it by
// itself; open one, reset it to a seed, restart it or end it.
import { api } from '../lib/api.js';
import { h, loading, showError, scrollBox, formatNumber, pageTitle } from '../lib/ui.js';
import { UNWATCHED_GRACE_S } from './scenario.js';

const REFRESH_MS = 3000;

/** Wall-clock seconds in words: "12 s", "4 min 5 s", "2 h 10 min". */
function wallTime(seconds) {
  const s = Math.floor(seconds);
  if (s < 60) return `${s} s`;
  if (s < 3600) return `${Math.floor(s / 60)} min ${s % 60} s`;
  return `${Math.floor(s / 3600)} h ${Math.floor((s % 3600) / 60)} min`;
}

const sessionPath = (id) => `/api/v1/sessions/${encodeURIComponent(id)}`;

/**
 * One session's row, updated in place by each refresh (so a seed being typed stays): `act(what, call)`
 * runs an action of its buttons and reports it.
 */
function sessionRow(session, act) {
  const cell = (name, numeric) => h('td', { class: numeric ? 'number' : null, 'data-field': name });
  const cells = {
    scenario: cell('scenario'), seed: cell('seed', true), mode: cell('mode'), status: cell('status'), tick: cell('tick', true),
    time: cell('time', true), watchers: cell('watchers', true), idle: cell('idle', true), grace: cell('grace', true),
  };
  const seedField = h('input', { type: 'number', min: 0, step: 1, required: true, inputmode: 'numeric', class: 'session-seed', value: session.seed,
    'aria-label': `Seed to reset session ${session.id} to` });
  let shownSeed = session.seed;
  const button = (text, options, onclick) => h('button', { type: options.submit ? 'submit' : 'button', class: `secondary ${options.class ?? ''}`, onclick }, text);
  // One action of a row at a time; its buttons stay enabled, so that the focus stays on the one pressed.
  let busy = false;
  const run = async (what, call) => {
    if (busy) return;
    busy = true;
    try {
      await act(what, call);
    } finally {
      busy = false;
    }
  };
  const reset = (seed) => run(`Session ${session.id} reset with seed ${seed}`, () => api.post(`${sessionPath(session.id)}/reset`, { seed }));
  const resetForm = h('form', { class: 'session-reset', onsubmit: (event) => {
    event.preventDefault();
    reset(Number(seedField.value));
  } }, seedField, button('Reset', { submit: true }));
  const restart = button('Restart', {}, () => reset(shownSeed));
  const end = button('End', { class: 'danger' }, () => {
    if (!confirm(`End session ${session.id} (${session.scenario}, seed ${shownSeed})? It cannot be resumed.`)) return;
    run(`Session ${session.id} ended`, () => api.delete(sessionPath(session.id)));
  });
  const row = h('tr', { 'data-id': session.id },
    h('th', { scope: 'row' }, h('code', { title: session.id }, `${session.id.slice(0, 9)}…`)),
    Object.values(cells),
    h('td', {}, h('div', { class: 'session-actions' }, h('a', { class: 'button secondary', href: `#/sessions/${encodeURIComponent(session.id)}` }, 'Open'),
      resetForm, restart, end)));

  function update(next) {
    cells.scenario.replaceChildren(h('a', { href: `#/scenarios/${encodeURIComponent(next.scenario)}` }, next.scenario));
    cells.seed.textContent = String(next.seed);
    cells.mode.textContent = next.mode === 'realtime' ? `realtime ${formatNumber(next.realtime_factor)}×` : next.mode;
    const finished = next.status === 'finished';
    cells.status.replaceChildren(h('span', { class: `badge ${finished ? 'good' : ''}` }, next.status),
      ...(finished ? [h('span', { class: 'muted session-termination' }, (next.termination ?? '').replace('_', ' '))] : []));
    cells.tick.textContent = formatNumber(next.tick);
    cells.time.textContent = `${next.time.toFixed(2)} s`;
    cells.watchers.textContent = String(next.connected_clients);
    cells.idle.textContent = wallTime(next.unused_for);
    cells.grace.textContent = next.unwatched_grace === null ? '—' : `${next.unwatched_grace} s`;
    // A new seed (a reset) shows in the field, unless the user is typing one.
    if (next.seed !== shownSeed && document.activeElement !== seedField) seedField.value = next.seed;
    shownSeed = next.seed;
  }
  update(session);
  return { row, update };
}

export async function render(root) {
  pageTitle(root, 'Sessions', 'The live sessions on this server. Open one to watch and drive it; reset, restart or end it here.');
  const notice = h('div', { class: 'sessions-notice', 'aria-live': 'polite' });
  const listArea = h('div', { class: 'sessions-list' });
  root.append(notice, listArea,
    h('p', { class: 'muted sessions-note' }, 'A session ends by itself after the server\'s idle timeout without use, or, with an unwatched grace, '
      + `that long after its last viewer left (sessions started in this browser have ${UNWATCHED_GRACE_S} s); while someone watches it, never.`));

  const rows = new Map();
  const tbody = h('tbody');
  const table = scrollBox(h('table', { class: 'sessions-table' },
    h('thead', {}, h('tr', {}, [['Session'], ['Scenario'], ['Seed', true], ['Mode'], ['Status'], ['Tick', true], ['Time', true],
      ['Watchers', true], ['Idle for', true], ['Unwatched grace', true], ['Actions']]
      .map(([title, numeric]) => h('th', { scope: 'col', class: numeric ? 'number' : null }, title)))),
    tbody), 'Live sessions');
  const empty = h('p', { class: 'message info' }, 'No live sessions. Start one from a ', h('a', { href: '#/' }, 'scenario'), "'s page.");

  let timer = null;
  let stopped = false;

  /** Runs an action of a row (`call()`), refreshes the list, then says what the action did or why not. */
  async function act(what, call) {
    notice.replaceChildren();
    let failure = null;
    try {
      await call();
    } catch (error) {
      failure = error;
    }
    await load();
    if (failure) showError(notice, failure);
    else notice.append(h('p', { class: 'message info', role: 'status' }, `${what}.`));
  }

  async function load() {
    let reply;
    try {
      reply = await api.get('/api/v1/sessions');
    } catch (error) {
      if (stopped) return;
      listArea.replaceChildren();
      showError(listArea, error);
      schedule();
      return;
    }
    if (stopped) return;
    const live = new Set(reply.items.map((session) => session.id));
    for (const [id, entry] of rows) {
      if (!live.has(id)) {
        entry.row.remove();
        rows.delete(id);
      }
    }
    for (const session of reply.items) {
      const entry = rows.get(session.id);
      if (entry) {
        entry.update(session);
      } else {
        const added = sessionRow(session, act);
        rows.set(session.id, added);
        tbody.append(added.row);
      }
    }
    const shown = rows.size ? table : empty;
    if (listArea.firstChild !== shown || listArea.childNodes.length !== 1) listArea.replaceChildren(shown);
    schedule();
  }

  // Loads may overlap (a refresh and an action's): one timer stays.
  function schedule() {
    clearTimeout(timer);
    timer = setTimeout(load, REFRESH_MS);
  }

  loading(listArea, 'Loading the sessions');
  await load();
  return () => {
    stopped = true;
    clearTimeout(timer);
  };
}

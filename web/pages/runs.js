// #/runs: a form that starts a run (runs/form.js), and the runs — found by text and tag, filtered by
// status, scenario and conditions on their metrics, with metric columns to sort by, paged. The whole
// view is in the address (#/runs?q=dwa&sort=success.mean&order=asc&metrics=…&where=…), so a link
// reopens it and back and forward walk through it. Two to ten chosen runs compare on #/compare; the
// choice is in the address too (&compare=A,B: a reload or a link keeps it, ticking a box adds no
// history entry).
import { api } from '../lib/api.js';
import { h, loading, showError, scrollBox, pageTitle } from '../lib/ui.js';
import { loadMetrics, withUnit, statusBadge, verdictBadge, isRunning } from '../lib/plots.js';
import { showInAddress, listOf } from '../lib/hashquery.js';
import { allScenarios, startForm } from '../runs/form.js';
import { tagChips } from '../runs/fields.js';
import { whereEditor } from '../runs/where.js';
import { columnsPicker } from '../runs/columns.js';

const STATUSES = ['queued', 'running', 'finished', 'failed', 'cancelled', 'interrupted'];
const PAGE_SIZES = [10, 20, 50, 100];
const PAGE_SIZE = 20;
const DEFAULT_COLUMNS = ['success.mean', 'collisions.max', 'time_to_goal.mean'];
const MAX_COMPARED = 10;
const SEARCH_DELAY_MS = 300;

/** The list's view as the address gives it. */
function readView(query) {
  return {
    q: query.get('q') ?? '', tag: query.get('tag') ?? '', status: query.get('status') ?? '', scenario: query.get('scenario') ?? '',
    sort: query.get('sort') ?? '', order: query.get('order') === 'asc' ? 'asc' : 'desc',
    columns: listOf(query, 'metrics', DEFAULT_COLUMNS), where: listOf(query, 'where'), cursor: query.get('cursor') ?? '',
    limit: PAGE_SIZES.includes(Number(query.get('limit'))) ? Number(query.get('limit')) : PAGE_SIZE,
    chosen: [...new Set(listOf(query, 'compare'))].slice(0, MAX_COMPARED),
  };
}

/** The view as the address's query: only what differs from the defaults. */
function addressValues(view) {
  return {
    q: view.q || null, tag: view.tag || null, status: view.status || null, scenario: view.scenario || null,
    sort: view.sort || null, order: view.sort && view.order === 'asc' ? 'asc' : null,
    metrics: view.columns.join(',') === DEFAULT_COLUMNS.join(',') ? null : view.columns,
    where: view.where.length ? view.where : null, limit: view.limit === PAGE_SIZE ? null : view.limit, cursor: view.cursor || null,
    compare: view.chosen.length ? view.chosen : null,
  };
}

/** GET /api/v1/runs for the view. */
function listPath(view) {
  const search = new URLSearchParams({ limit: String(view.limit) });
  for (const key of ['q', 'tag', 'status', 'scenario', 'cursor']) if (view[key]) search.set(key, view[key]);
  if (view.sort) {
    search.set('sort', view.sort);
    search.set('order', view.order);
  }
  if (view.where.length) search.set('where', view.where.join(','));
  if (view.columns.length) search.set('metrics', view.columns.join(','));
  return `/api/v1/runs?${search}`;
}

/** A column's value with its metric's unit (counts of episodes have none). */
function columnValue(value, column, metrics) {
  const [key, statistic] = column.split('.');
  const unit = statistic === 'count' || statistic === 'nulls' ? 'count' : metrics.byKey.get(key)?.unit;
  return withUnit(value, unit);
}

/** How a sorted list reads: "lowest first" for ascending. */
const orderWords = (order) => (order === 'asc' ? 'lowest first' : 'highest first');

function runRow(run, view, metrics, { chosen, onChoose, onTag }) {
  const done = run.progress.finished + run.progress.error;
  const gatesCell = h('span', { class: 'failing-gates' }, run.verdict.complete && !run.verdict.passed ? run.verdict.reasons.join('; ') : '');
  const box = h('input', { type: 'checkbox', checked: chosen.includes(run.id), 'aria-label': `Compare run ${run.id}`, 'data-focus': `compare-${run.id}`, onchange: (e) => onChoose(run.id, e.target) });
  return h('tr', {},
    h('td', {}, box),
    // The accessible name starts with the visible text (voice control users say what they see).
    h('td', {}, h('a', { href: `#/runs/${run.id}`, class: 'run-id', title: run.id, 'aria-label': `${run.id.slice(0, 9)}: run ${run.id}` }, run.id.slice(0, 9))),
    h('td', { class: 'run-name' }, run.name ? h('span', { class: 'name' }, run.name) : null, ' ', tagChips(run.tags, onTag)),
    h('td', {}, statusBadge(run.status)),
    h('td', {}, run.scenario),
    h('td', {}, run.controller),
    h('td', { class: 'number' }, `${done} / ${run.progress.total}`),
    view.columns.map((column) => h('td', { class: 'number', 'data-column': column }, columnValue(run.metrics?.[column] ?? null, column, metrics))),
    h('td', {}, verdictBadge(run.verdict, run.status), ' ', gatesCell),
    h('td', {}, h('time', { datetime: run.created_at }, new Date(run.created_at).toLocaleString('en-GB'))));
}

/**
 * A sortable column's heading: a button that sorts by it (or flips the order when it already does),
 * and aria-sort saying how the list is sorted now.
 */
function sortHeading(text, sorted, order, onSort, attributes = {}) {
  const arrow = !sorted ? '⇅' : order === 'asc' ? '▲' : '▼';
  return h('th', { scope: 'col', 'aria-sort': sorted ? (order === 'asc' ? 'ascending' : 'descending') : 'none', ...attributes },
    h('button', { type: 'button', class: 'link sort', 'data-focus': `sort-${text}`, onclick: onSort }, text, h('span', { 'aria-hidden': 'true' }, ` ${arrow}`)));
}

function runsTable(items, view, metrics, handlers) {
  const plain = (text, className = null) => h('th', { scope: 'col', class: className }, text);
  // A column sorts its best runs first, then the other way; a descriptive metric's highest first.
  const firstOrder = (column) => (metrics.byKey.get(column.split('.')[0])?.better === 'lower' ? 'asc' : 'desc');
  return h('table', { class: 'runs-table' },
    h('thead', {}, h('tr', {},
      plain('Compare'), plain('Run'), plain('Name and tags'), plain('Status'), plain('Scenario'), plain('Controller'), plain('Episodes done', 'number'),
      view.columns.map((column) => sortHeading(column, view.sort === column, view.order,
        () => handlers.onSort(column, view.sort === column ? (view.order === 'asc' ? 'desc' : 'asc') : firstOrder(column)),
        { class: 'number', 'data-column': column })),
      plain('Verdict'),
      sortHeading('Created', !view.sort, 'desc', () => handlers.onSort('', 'desc')))),
    h('tbody', {}, items.map((run) => runRow(run, view, metrics, handlers))));
}

export async function render(root, params, query) {
  pageTitle(root, 'Runs', 'Batches of headless episodes: their progress, metrics and gate verdicts.');
  const wait = loading(root, 'Loading scenarios and metrics');
  let scenarios = [];
  let metrics;
  try {
    [scenarios, metrics] = await Promise.all([allScenarios(), loadMetrics()]);
  } catch (error) {
    showError(root, error);
    return null;
  } finally {
    wait.remove();
  }
  root.append(startForm(scenarios, query.get('scenario')));

  const view = readView(query);
  let typedSincePush = false;
  let searchTimer = null;
  /** A change of the view: into the address (typing replaces its own last entry), then the list again, from its first page. */
  const apply = (changes, { typing = false } = {}) => {
    Object.assign(view, { cursor: '' }, changes);
    showInAddress('/runs', addressValues(view), { replace: typing && typedSincePush });
    typedSincePush = typing;
    load();
  };

  const search = h('input', { id: 'filter-q', type: 'search', value: view.q, size: 22, placeholder: 'name, notes, tag, scenario…',
    oninput: () => {
      clearTimeout(searchTimer);
      searchTimer = setTimeout(() => apply({ q: search.value.trim() }, { typing: true }), SEARCH_DELAY_MS);
    } });
  const tagFilter = h('input', { id: 'filter-tag', type: 'text', value: view.tag, size: 12, spellcheck: 'false',
    onchange: () => apply({ tag: tagFilter.value.trim() }) });
  const statusFilter = h('select', { id: 'filter-status', onchange: () => apply({ status: statusFilter.value }) },
    h('option', { value: '' }, 'any'), STATUSES.map((s) => h('option', { value: s, selected: s === view.status }, s)));
  const pageSize = h('select', { id: 'page-size', onchange: () => apply({ limit: Number(pageSize.value) }) },
    PAGE_SIZES.map((n) => h('option', { value: n, selected: n === view.limit }, n)));
  const scenarioFilter = h('select', { id: 'filter-scenario', onchange: () => apply({ scenario: scenarioFilter.value }) },
    h('option', { value: '' }, 'any'), scenarios.map((s) => h('option', { value: s.id, selected: s.id === view.scenario }, s.id)));
  const onTag = (tag) => {
    tagFilter.value = tag;
    apply({ tag });
  };

  const compareButton = h('button', { type: 'button', class: 'secondary', disabled: true }, 'Compare the chosen');
  const compareHint = h('span', { class: 'muted small', 'aria-live': 'polite' });
  // The runs chosen to compare, in the order chosen (the first is the baseline); view.chosen itself.
  const chosen = view.chosen;
  const showChosen = (note = null) => {
    compareButton.disabled = chosen.length < 2;
    const [baseline, ...others] = chosen.map((id) => id.slice(0, 9));
    const order = baseline ? `Baseline ${baseline}${others.length ? `, then ${others.join(', ')}` : ''}.` : '';
    compareHint.textContent = note ?? (others.length ? order : `${order} Choose 2 to ${MAX_COMPARED} runs: the first chosen is the baseline.`.trim());
  };
  const onChoose = (id, box) => {
    const at = chosen.indexOf(id);
    if (box.checked && at < 0 && chosen.length >= MAX_COMPARED) {
      box.checked = false;
      showChosen(`At most ${MAX_COMPARED} runs compare at once.`);
      return;
    }
    if (box.checked && at < 0) chosen.push(id);
    if (!box.checked && at >= 0) chosen.splice(at, 1);
    showInAddress('/runs', addressValues(view), { replace: true });
    showChosen();
  };
  showChosen();
  compareButton.addEventListener('click', () => { location.hash = `#/compare?runs=${chosen.join(',')}`; });

  const conditionsTitle = () => `Conditions on metrics${view.where.length ? ` (${view.where.length})` : ''}`;
  const conditionsSummary = h('summary', {}, conditionsTitle());
  const sortLine = h('p', { class: 'sort-line', 'aria-live': 'polite' });
  const firstButton = h('button', { type: 'button', class: 'secondary' }, 'First page');
  const previousButton = h('button', { type: 'button', class: 'secondary' }, 'Previous page');
  const nextButton = h('button', { type: 'button', class: 'secondary' }, 'Next page');
  const listArea = h('div', { class: 'runs-list' });
  root.append(
    h('h2', { id: 'runs-title' }, 'Runs'),
    h('div', { class: 'row filters' },
      h('div', { class: 'field' }, h('label', { for: 'filter-q' }, 'Search'), search),
      h('div', { class: 'field' }, h('label', { for: 'filter-tag' }, 'Tag'), tagFilter),
      h('div', { class: 'field' }, h('label', { for: 'filter-status' }, 'Status'), statusFilter),
      h('div', { class: 'field' }, h('label', { for: 'filter-scenario' }, 'Scenario'), scenarioFilter),
      h('div', { class: 'compare-choice' }, compareButton, compareHint)),
    h('div', { class: 'list-tools' },
      h('details', { class: 'panel tool', open: view.where.length > 0 },
        conditionsSummary,
        whereEditor(view.where, metrics.byKey, (where) => {
          apply({ where });
          conditionsSummary.textContent = conditionsTitle();
        })),
      h('details', { class: 'panel tool' },
        h('summary', {}, 'Metric columns'),
        columnsPicker(view.columns, metrics, (columns) => apply({ columns })))),
    sortLine,
    listArea,
    h('div', { class: 'row paging' }, firstButton, previousButton, nextButton,
      h('div', { class: 'field' }, h('label', { for: 'page-size' }, 'Runs per page'), pageSize)));

  const handlers = { chosen, onChoose, onTag, onSort: (sort, order) => apply({ sort, order }) };
  let timer = null;
  let generation = 0;
  const load = async ({ quiet = false } = {}) => {
    clearTimeout(timer);
    const current = ++generation;
    sortLine.replaceChildren(...(view.sort ? [`Sorted by ${view.sort}, ${orderWords(view.order)}; runs without a value last. `,
      h('button', { type: 'button', class: 'link', onclick: () => apply({ sort: '', order: 'desc' }) }, 'Newest first')] : ['Newest first.']));
    const wait = quiet ? null : loading(listArea, 'Loading runs');
    let reply;
    try {
      reply = await api.get(listPath(view));
    } catch (error) {
      if (current !== generation) return;
      listArea.replaceChildren();
      showError(listArea, error);
      return;
    }
    if (current !== generation) return;
    wait?.remove();
    // A sorted list's cursor is @offset: its previous page is known too.
    const offset = /^@(\d+)$/.exec(view.cursor)?.[1];
    firstButton.disabled = !view.cursor;
    previousButton.hidden = offset === undefined;
    previousButton.onclick = () => apply({ cursor: Number(offset) > view.limit ? `@${Number(offset) - view.limit}` : '' });
    nextButton.disabled = !reply.next_cursor;
    nextButton.onclick = () => apply({ cursor: reply.next_cursor });
    if (!reply.items.length) {
      const filtered = view.q || view.tag || view.status || view.scenario || view.where.length;
      listArea.replaceChildren(h('p', { class: 'message info' }, view.cursor ? 'No more runs.' : filtered ? 'No run matches.' : 'No runs yet: start one above.'));
      return;
    }
    // A new table (a refresh, another order) keeps the keyboard focus on the same control.
    const focused = listArea.contains(document.activeElement) ? document.activeElement.dataset.focus : null;
    listArea.replaceChildren(scrollBox(runsTable(reply.items, view, metrics, handlers), 'Runs'));
    if (focused) listArea.querySelector(`[data-focus="${CSS.escape(focused)}"]`)?.focus();
    // Keep the progress of unfinished runs current.
    if (reply.items.some((run) => isRunning(run.status))) timer = setTimeout(() => load({ quiet: true }), 2000);
  };
  firstButton.addEventListener('click', () => apply({ cursor: '' }));
  await load();
  return () => { clearTimeout(timer); clearTimeout(searchTimer); generation++; };
}

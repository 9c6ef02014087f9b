// #/controllers[?scenario=NAME,…]: the controller × scenario comparison. The latest ended run of each
// pair (scenario name, controller type), its metrics with 95 % intervals, as the table of
// scripts/compare-controllers, and the command that makes it again: the script runs each controller
// as the scenario's own robot controller with only the type changed, so a run made otherwise is marked.
import { api } from '../lib/api.js';
import { h, loading, showError, scrollBox, formatNumber, pageTitle } from '../lib/ui.js';

const PAGE_SIZE = 100;
const ENDED = new Set(['finished', 'failed']);  // cancelled and interrupted runs are partial
const CONTROLLER_ORDER = ['scenario', 'idle', 'goal', 'social', 'dwa', 'orca', 'social_force', 'teleop'];
const NORMAL_975 = 1.959963984540054;

/** Wilson's score interval of a share of n, as the server gives it for 0/1 metrics. */
function wilson(share, n) {
  const z2 = NORMAL_975 ** 2;
  const centre = (share + z2 / (2 * n)) / (1 + z2 / n);
  const half = NORMAL_975 / (1 + z2 / n) * Math.sqrt(share * (1 - share) / n + z2 / (4 * n * n));
  return [Math.max(0, centre - half), Math.min(1, centre + half)];
}

// Each column's {count, mean, low, high} from a run's report, shown times `scale` in `unit`.
const COLUMNS = [
  { title: 'Success', unit: '%', scale: 100, of: (r) => stats(r.aggregates.success) },
  { title: 'Episodes with a collision', unit: '%', scale: 100, of: collisionRate },
  { title: 'Collisions per episode', unit: '', scale: 1, of: (r) => stats(r.aggregates.collisions) },
  { title: 'Time to goal', unit: 's', scale: 1, of: (r) => stats(r.aggregates.time_to_goal) },
  { title: 'Min. distance to people', unit: 'm', scale: 1, of: (r) => stats(r.aggregates.minimum_distance_to_people) },
  { title: 'Intimate-space intrusions', unit: '% of steps', scale: 1, of: (r) => stats(r.aggregates.intimate_space_intrusions) },
];

/** The report gives the collision rate without an interval: Wilson's, over the episodes with a count. */
function collisionRate(report) {
  const share = report.rates.collision_rate;
  if (share === null) return stats(null);
  const count = report.aggregates.collisions.count;
  const [low, high] = wilson(share, count);
  return { count, mean: share, low, high };
}

function stats(aggregate) {
  return aggregate && aggregate.count ? { count: aggregate.count, mean: aggregate.mean, low: aggregate.ci95_low, high: aggregate.ci95_high }
    : { count: 0, mean: null, low: null, high: null };
}

function cell(column, value, finished) {
  if (!value.count) return h('td', { class: 'number' }, '—');
  const number = (x) => formatNumber(x * column.scale);
  return h('td', { class: 'number' },
    `${number(value.mean)}${column.unit ? ` ${column.unit}` : ''}`,
    value.low === null ? null : h('span', { class: 'ci' }, ` [${number(value.low)}, ${number(value.high)}]`),
    value.count < finished ? h('span', { class: 'muted small' }, ` (n ${value.count})`) : null);
}

/** Every run the server lists, newest first. */
async function allRuns() {
  const runs = [];
  let cursor = null;
  do {
    const reply = await api.get(`/api/v1/runs?limit=${PAGE_SIZE}${cursor ? `&cursor=${encodeURIComponent(cursor)}` : ''}`);
    runs.push(...reply.items);
    cursor = reply.items.length ? reply.next_cursor : null;
  } while (cursor);
  return runs;
}

/**
 * Scenario documents by id, each asked for once. A run's scenario id is the name of a bundled scenario,
 * but a stored record's id for one `hrisim run --db` ran: only the document has the name. A scenario
 * that cannot be read (an upload deleted since) is null, and its runs go by their id.
 */
function documents() {
  const cache = new Map();
  return (id) => {
    if (!cache.has(id)) cache.set(id, api.get(`/api/v1/scenarios/${encodeURIComponent(id)}`).catch(() => null));
    return cache.get(id);
  };
}

function byControllerOrder(a, b) {
  const rank = (c) => (CONTROLLER_ORDER.includes(c) ? CONTROLLER_ORDER.indexOf(c) : CONTROLLER_ORDER.length);
  return rank(a) - rank(b) || a.localeCompare(b);
}

/** A JSON text with sorted keys, to compare two controllers whatever their keys' order. */
function canonical(value) {
  if (Array.isArray(value)) return `[${value.map(canonical).join(',')}]`;
  if (value && typeof value === 'object') return `{${Object.keys(value).sort().map((k) => `${JSON.stringify(k)}:${canonical(value[k])}`).join(',')}}`;
  return JSON.stringify(value);
}

/** "1-20" for consecutive seeds, else "1,3,7": what `hrisim run --seeds` (and so the script) takes. */
function seedsArgument(seeds) {
  const consecutive = seeds.length > 1 && seeds.every((s, i) => i === 0 || s === seeds[i - 1] + 1);
  return consecutive ? `${seeds[0]}-${seeds[seeds.length - 1]}` : seeds.join(',');
}

/**
 * The controller the script's run of a type gives the robot: the scenario's own with only the type
 * changed, less what that type does not take (as the server makes it).
 */
function scriptController(own, type) {
  const controller = { ...own, type };
  if (type === 'idle' || type === 'teleop') delete controller.goal;
  if (type !== 'search') {
    delete controller.person;
    delete controller.strategy;
  }
  return controller;
}

/** How a run differs from what the script would run for its pair with `seeds`; empty when it does not. */
function differences(row, seeds) {
  const config = row.report.config;
  const own = row.recordDocument?.robots?.[0]?.controller ?? {};
  const expected = row.controller === 'scenario' ? null : scriptController(own, row.controller);
  // What the robot had (runs stored before effective controllers had the controller asked for, whole).
  const had = config.controller === null ? null : config.effective_controller ?? config.controller;
  const found = [];
  if (canonical(had) !== canonical(expected)) {
    found.push(`controller ${JSON.stringify(had)} where the script's run has ${expected ? JSON.stringify(expected) : "the scenario's own"}`);
  }
  if (config.max_time !== null) found.push(`a time limit of ${formatNumber(config.max_time)} s`);
  if (config.requests.length) found.push('scripted requests');
  if (config.baseline_without_robot) found.push('a baseline without the robot');
  if (seedsArgument(config.seeds) !== seeds) found.push(`seeds ${seedsArgument(config.seeds)}`);
  return found;
}

function comparisonTable(rows) {
  return h('table', { class: 'controllers-table' },
    h('thead', {}, h('tr', {},
      h('th', { scope: 'col' }, 'Scenario'), h('th', { scope: 'col' }, 'Controller'), h('th', { scope: 'col', class: 'number' }, 'Episodes'),
      COLUMNS.map((c) => h('th', { scope: 'col', class: 'number' }, c.title, h('span', { class: 'muted small' }, ' [95 % CI]'))),
      h('th', { scope: 'col' }, 'Run'))),
    h('tbody', {}, rows.map((row) => {
      const { progress } = row.report;
      const goal = row.report.config.controller?.goal;
      return h('tr', { 'data-scenario': row.scenario, 'data-controller': row.controller, 'data-run': row.report.id },
        h('th', { scope: 'row' }, row.scenario),
        h('td', {}, row.controller === 'scenario' ? "scenario's own" : row.controller,
          goal?.location ? h('span', { class: 'muted small' }, ` → ${goal.location}`) : null),
        h('td', { class: 'number' }, String(progress.finished), progress.error ? h('span', { class: 'muted small' }, ` (+${progress.error} in error)`) : null),
        COLUMNS.map((c) => cell(c, c.of(row.report), progress.finished)),
        h('td', { class: 'run' }, h('a', { href: `#/runs/${row.report.id}`, class: 'run-id', title: row.report.id }, row.report.id.slice(0, 9)),
          row.differences.length ? h('sup', { title: row.differences.join('; ') }, ' †') : null));
    })));
}

/** The seeds most rows share, as --seeds; a row with others is marked like any other difference. */
function commonSeeds(rows) {
  const counts = new Map();
  for (const row of rows) {
    const seeds = seedsArgument(row.report.config.seeds);
    counts.set(seeds, (counts.get(seeds) ?? 0) + 1);
  }
  return [...counts].sort((a, b) => b[1] - a[1])[0][0];
}

function reproduction(rows, scenarios, controllers, seeds) {
  const command = `scripts/compare-controllers --scenarios ${scenarios.join(',')} --controllers ${controllers.join(',')} --seeds ${seeds}`;
  const have = new Set(rows.map((r) => `${r.scenario}\u0000${r.controller}`));
  const missing = scenarios.flatMap((s) => controllers.filter((c) => !have.has(`${s}\u0000${c}`)).map((c) => `${s} × ${c}`));
  const marked = rows.filter((r) => r.differences.length);
  return h('section', { class: 'panel reproduce', 'aria-labelledby': 'reproduce-title' },
    h('h2', { id: 'reproduce-title' }, 'Reproduce it with one command'),
    h('pre', { class: 'command' }, h('code', {}, command)),
    h('p', { class: 'muted small' }, 'From the checkout: it runs every pair into var/controllers.db (', h('code', {}, '--db'),
      ' to choose) and prints this table in Markdown; a scenario name stands for scenarios/NAME.json, give the path of a scenario of your own. ',
      'Each controller is the scenario\'s own robot controller with only its type changed; ', h('code', {}, 'scenario'), ' is the scenario\'s own.'),
    missing.length ? h('p', { class: 'missing small' }, `No ended run yet, the command runs them too: ${missing.join(', ')}.`) : null,
    marked.length ? h('div', { class: 'differences small' }, h('p', {}, '† Made otherwise than the command makes it:'),
      h('ul', {}, marked.map((r) => h('li', { 'data-run': r.report.id }, `${r.scenario} × ${r.controller}: ${r.differences.join('; ')}`)))) : null);
}

export async function render(root, params, query) {
  pageTitle(root, 'Controllers', 'Each controller on each scenario: the latest ended run of every pair, with 95 % confidence intervals.');
  const wait = loading(root, 'Loading runs');
  const chosen = (query.get('scenario') ?? '').split(',').filter(Boolean);
  let rows;
  try {
    const runs = (await allRuns()).filter((run) => ENDED.has(run.status));
    const documentOf = documents();
    const names = new Map(await Promise.all([...new Set(runs.map((r) => r.scenario))]
      .map(async (id) => [id, (await documentOf(id))?.name ?? id])));
    // Newest first: the first run of a pair is its latest.
    const latest = new Map();
    for (const run of runs) {
      const key = `${names.get(run.scenario)}\u0000${run.controller}`;
      if (!latest.has(key)) latest.set(key, run);
    }
    rows = await Promise.all([...latest.values()].map(async (run) => {
      const report = await api.get(`/api/v1/runs/${encodeURIComponent(run.id)}`);
      return { scenario: names.get(run.scenario), controller: run.controller, report, recordDocument: await documentOf(report.scenario_record) };
    }));
  } catch (error) {
    showError(root, error);
    return;
  } finally {
    wait.remove();
  }
  const allScenarios = [...new Set(rows.map((r) => r.scenario))].sort();
  const filter = h('select', { id: 'controllers-scenario',
    onchange: (event) => { location.hash = event.target.value ? `#/controllers?scenario=${encodeURIComponent(event.target.value)}` : '#/controllers'; } },
  h('option', { value: '' }, 'every scenario'),
  allScenarios.map((s) => h('option', { value: s, selected: chosen.length === 1 && chosen[0] === s }, s)));
  root.append(h('div', { class: 'row filters' }, h('div', { class: 'field' }, h('label', { for: 'controllers-scenario' }, 'Scenario'), filter)));

  const shown = rows.filter((r) => !chosen.length || chosen.includes(r.scenario))
    .sort((a, b) => a.scenario.localeCompare(b.scenario) || byControllerOrder(a.controller, b.controller));
  if (!shown.length) {
    root.append(h('p', { class: 'message info' }, chosen.length ? `No ended run of ${chosen.join(', ')}.`
      : 'No ended runs yet: start some on the Runs page, or run scripts/compare-controllers with this server\'s database.'));
    return;
  }
  const scenarios = [...new Set(shown.map((r) => r.scenario))];
  const controllers = [...new Set(shown.map((r) => r.controller))].sort(byControllerOrder);
  const seeds = commonSeeds(shown);
  for (const row of shown) row.differences = differences(row, seeds);
  root.append(scrollBox(comparisonTable(shown), 'Controllers on scenarios'), reproduction(shown, scenarios, controllers, seeds));
}

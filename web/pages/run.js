// #/runs/ID: one run's report — its name, tags and notes (edited in place), progress (polled every
// second while it runs), verdict, every metric's aggregates with units and which way is better,
// per-episode values of the chosen metrics as dot plots (#/runs/ID?plots=success,collisions), the
// episodes with links to their replays, and the report as files: episodes CSV, JSON, JUnit XML.
import { api } from '../lib/api.js';
import { h, loading, showError, errorPage, scrollBox, formatNumber, pageTitle } from '../lib/ui.js';
import { CATEGORY_NAMES, loadMetrics, withUnit, unitLabel, betterArrow, statusBadge, verdictBadge, isRunning } from '../lib/plots.js';
import { downloadLink, saveButton } from '../lib/download.js';
import { showInAddress, listOf } from '../lib/hashquery.js';
import { labelsPanel } from '../runs/labels.js';
import { episodePlots } from '../runs/episode-plots.js';
import { controllerText } from '../runs/config.js';

// Shown per episode and plotted (unless the address chooses others), in this order, when the metrics list has them.
const KEY_METRICS = ['success', 'collisions', 'minimum_distance_to_people', 'path_length', 'time_to_goal'];

/** Seeds as ranges: 1-5, 8, 10-12. */
function seedRanges(seeds) {
  const parts = [];
  for (let i = 0; i < seeds.length;) {
    let j = i;
    while (j + 1 < seeds.length && seeds[j + 1] === seeds[j] + 1) j++;
    parts.push(j > i ? `${seeds[i]}-${seeds[j]}` : String(seeds[i]));
    i = j + 1;
  }
  return parts.join(', ');
}

const running = (report) => isRunning(report.status);

/**
 * A run split over machines (docs/scale-out.md): one shard's part of it, or the shards merged so far
 * and those missing.
 */
function shardingText(config) {
  const { count, index, merged, of_seeds: all } = config.sharding;
  if (!merged) return `shard ${index} of ${count}: ${config.seeds.length} of the run's ${all.length} seeds`;
  const missing = [];
  for (let shard = 1; shard <= count; shard++) if (!merged.includes(shard)) missing.push(shard);
  return `${merged.length} of ${count} merged (${config.seeds.length} of ${all.length} seeds)`
    + (missing.length ? `; missing: ${missing.slice(0, 10).join(', ')}${missing.length > 10 ? ', …' : ''}` : '');
}

function summaryPanel(report) {
  const p = report.progress;
  const done = p.finished + p.error;
  const config = report.config;
  return h('div', { class: 'panel run-summary' },
    h('div', { class: 'row' },
      h('div', {}, h('span', { class: 'muted' }, 'Status '), statusBadge(report.status)),
      h('div', { class: 'progress-wrap' },
        h('label', { for: 'run-progress' }, `${done} of ${p.total} episodes done`
          + (p.running ? `, ${p.running} running` : '') + (p.queued ? `, ${p.queued} queued` : '')
          + (p.error ? `, ${p.error} in error` : '') + (p.cancelled ? `, ${p.cancelled} cancelled` : '') + (p.interrupted ? `, ${p.interrupted} interrupted` : '')),
        h('progress', { id: 'run-progress', max: p.total, value: done }, `${done} / ${p.total}`))),
    h('dl', { class: 'facts' },
      h('dt', {}, 'Scenario'), h('dd', {}, h('a', { href: `#/scenarios/${encodeURIComponent(report.scenario)}` }, report.scenario),
        h('span', { class: 'muted' }, ` (snapshot ${report.scenario_record})`)),
      h('dt', {}, 'Controller'), h('dd', { class: 'run-controller' }, controllerText(config)),
      h('dt', {}, 'Seeds'), h('dd', {}, `${seedRanges(config.seeds)} (${config.seeds.length})`),
      h('dt', {}, 'Time limit'), h('dd', {}, config.max_time === null ? "the scenario's" : `${formatNumber(config.max_time)} s`),
      config.sharding ? [h('dt', {}, 'Shards'), h('dd', { class: 'run-shards' }, shardingText(config))] : null,
      h('dt', {}, 'Success rate'), h('dd', {}, report.rates.success_rate === null ? '—' : `${formatNumber(report.rates.success_rate * 100, 2)} %`),
      h('dt', {}, 'Collision rate'), h('dd', {}, report.rates.collision_rate === null ? '—' : `${formatNumber(report.rates.collision_rate * 100, 2)} %`),
      h('dt', {}, 'Created'), h('dd', {}, new Date(report.created_at).toLocaleString('en-GB')),
      h('dt', {}, 'Finished'), h('dd', {}, report.finished_at ? new Date(report.finished_at).toLocaleString('en-GB') : '—'),
      h('dt', {}, 'hrisim'), h('dd', {}, `${config.hrisim_version} (${config.git_commit.slice(0, 12)})`)));
}

/**
 * A gate's row. While the run goes on a gate is pending, whatever its statistic says so far: the
 * episodes still to come may change it.
 */
function gateRow(gate, pending) {
  const actual = gate.actual === null ? (pending ? '—' : 'no value') : `${formatNumber(gate.actual)}${pending ? ' so far' : ''}`;
  const result = pending ? h('span', { class: 'badge' }, 'pending')
    : h('span', { class: `badge ${gate.passed ? 'good' : 'bad'}` }, gate.passed ? 'passed' : 'failed');
  return h('tr', { 'data-gate': gate.gate }, h('td', {}, h('code', {}, gate.gate)), h('td', { class: 'number' }, actual), h('td', {}, result));
}

function verdictPanel(report) {
  const v = report.verdict;
  return h('section', { class: 'panel verdict', 'aria-labelledby': 'verdict-title' },
    h('h2', { id: 'verdict-title' }, 'Verdict ', verdictBadge(v, report.status)),
    v.gates.length ? scrollBox(h('table', { class: 'gates' },
      h('thead', {}, h('tr', {}, h('th', { scope: 'col' }, 'Gate'), h('th', { scope: 'col', class: 'number' }, 'Actual'), h('th', { scope: 'col' }, 'Result'))),
      h('tbody', {}, v.gates.map((g) => gateRow(g, running(report))))), 'Gates')
      : h('p', { class: 'muted' }, 'No gates: the verdict needs only every episode to finish.'),
    v.reasons.length ? h('ul', { class: 'reasons' }, v.reasons.map((r) => h('li', {}, r))) : null);
}

function aggregatesTable(report, metrics) {
  const rows = [];
  let category = null;
  for (const metric of metrics.items) {
    const a = report.aggregates[metric.key];
    if (!a) continue;
    if (metric.category !== category) {
      category = metric.category;
      rows.push(h('tr', { class: 'category' }, h('th', { colspan: 9, scope: 'rowgroup' }, CATEGORY_NAMES[category] ?? category)));
    }
    rows.push(h('tr', { 'data-metric': metric.key },
      h('th', { scope: 'row', title: `${metric.description} (${metric.convention})` }, metric.key),
      h('td', { class: 'arrow' }, betterArrow(metric.better)),
      h('td', {}, unitLabel(metric.unit)),
      h('td', { class: 'number' }, withUnit(a.mean, metric.unit)),
      h('td', { class: 'number ci' }, a.ci95_low === null ? '—' : `${formatNumber(a.ci95_low)} … ${formatNumber(a.ci95_high)}`),
      h('td', { class: 'number' }, withUnit(a.min, metric.unit)),
      h('td', { class: 'number' }, withUnit(a.max, metric.unit)),
      h('td', { class: 'number' }, a.std === null ? '—' : formatNumber(a.std)),
      h('td', { class: 'number' }, `${a.count} / ${a.nulls}`)));
  }
  return h('table', { class: 'aggregates' },
    h('caption', { class: 'muted' }, 'Over the finished episodes: the mean and its 95 % confidence interval (Wilson\'s for 0/1 metrics, Student\'s t otherwise), in the unit of each row. ↑ higher is better, ↓ lower is better.'),
    h('thead', {}, h('tr', {}, ['Metric', 'Better', 'Unit', 'Mean', '95 % CI', 'Min', 'Max', 'Std', 'Count / nulls']
      .map((t, i) => h('th', { scope: 'col', class: i >= 3 ? 'number' : null }, t)))),
    h('tbody', {}, rows));
}

function episodesTable(report, episodes, keys, metrics) {
  const byId = new Map(episodes.map((e) => [e.id, e]));
  return h('table', { class: 'episodes' },
    h('thead', {}, h('tr', {},
      h('th', { scope: 'col', class: 'number' }, 'Seed'), h('th', { scope: 'col' }, 'Status'), h('th', { scope: 'col' }, 'Termination'),
      h('th', { scope: 'col', class: 'number' }, 'Simulated time'),
      keys.map((k) => h('th', { scope: 'col', class: 'number' }, k.replaceAll('_', ' '), ' ', betterArrow(metrics.byKey.get(k).better))),
      h('th', { scope: 'col' }, 'Replay'))),
    h('tbody', {}, report.episodes.map((seed) => {
      const episode = seed.episode_id ? byId.get(seed.episode_id) : null;
      return h('tr', {},
        h('td', { class: 'number' }, seed.seed),
        h('td', {}, statusBadge(seed.status)),
        h('td', {}, seed.termination ?? '—'),
        h('td', { class: 'number' }, seed.sim_time === undefined ? '—' : `${formatNumber(seed.sim_time)} s`),
        keys.map((k) => h('td', { class: 'number' }, episode ? withUnit(episode.metrics[k], metrics.byKey.get(k).unit, { bool: 'word' }) : '—')),
        h('td', {}, seed.episode_id ? h('a', { href: `#/episodes/${seed.episode_id}`, 'aria-label': `Replay seed ${seed.seed}` }, 'replay') : '—'));
    })));
}

/** The page's heading: the run's name, else its short id. */
const heading = (report) => (report.name ? `${report.name} (run ${report.id.slice(0, 9)})` : `Run ${report.id.slice(0, 9)}`);

export async function render(root, params, query) {
  const id = params.id;
  const path = `/api/v1/runs/${encodeURIComponent(id)}`;
  pageTitle(root, `Run ${id.slice(0, 9)}`, id);
  const wait = loading(root, 'Loading the run');
  let report, metrics;
  try {
    [report, metrics] = await Promise.all([api.get(path), loadMetrics()]);
  } catch (error) {
    errorPage(root, `Run ${id}`, error, { href: '#/runs', text: 'All runs' });
    return null;
  }
  wait.remove();
  const keys = KEY_METRICS.filter((k) => metrics.byKey.has(k));
  const title = root.querySelector('h1');
  const retitle = () => {
    title.textContent = heading(report);
    document.title = `${heading(report)} · hrisim`;
  };
  retitle();

  const cancelButton = h('button', { type: 'button', class: 'secondary danger' }, 'Cancel the run');
  const actionMessage = h('div', { 'aria-live': 'polite' });
  const actions = h('div', { class: 'row run-actions' },
    cancelButton,
    downloadLink(`${path}/episodes?format=csv`, `${id}-episodes.csv`, 'Episodes (CSV)'),
    saveButton('Report (JSON)', () => ({ blob: new Blob([`${JSON.stringify(report, null, 2)}\n`], { type: 'application/json' }), filename: `hrisim-${id}.json` })),
    downloadLink(`${path}/junit`, `hrisim-${id}.xml`, 'JUnit report (XML)'),
    h('a', { class: 'button secondary', href: `#/runs?scenario=${encodeURIComponent(report.scenario)}` }, 'Start another run of this scenario'),
    actionMessage);
  const summary = h('div');
  const verdict = h('div');
  // The plotted metrics' choice is the address's, and goes back into it.
  const plots = episodePlots({ runId: id, metrics, chosen: listOf(query, 'plots', keys).filter((k) => metrics.byKey.has(k)),
    onChoose: (chosen) => showInAddress(`/runs/${id}`, { plots: chosen.join(',') === keys.join(',') ? null : chosen }) });
  const aggregates = h('section', { 'aria-labelledby': 'aggregates-title' });
  const episodesArea = h('section', { 'aria-labelledby': 'episodes-title' });
  root.append(actions, labelsPanel(report, (edited) => { report = edited; retitle(); }),
    h('div', { class: 'run-top' }, summary, verdict), plots.element, aggregates, episodesArea);

  let shownStored = -1;
  let shownStatus = null;

  const showDetails = async () => {
    const stored = report.progress.finished + report.progress.error;
    if (stored === shownStored && report.status === shownStatus) return;
    shownStored = stored;
    shownStatus = report.status;
    aggregates.replaceChildren(h('h2', { id: 'aggregates-title' }, 'Metrics'), scrollBox(aggregatesTable(report, metrics), 'Metrics'));
    let episodes = [];
    try {
      episodes = (await api.get(`${path}/episodes`)).items;
    } catch (error) {
      episodesArea.replaceChildren(h('h2', { id: 'episodes-title' }, 'Episodes'));
      showError(episodesArea, error);
      return;
    }
    episodesArea.replaceChildren(h('h2', { id: 'episodes-title' }, 'Episodes'), scrollBox(episodesTable(report, episodes, keys, metrics), 'Episodes'));
    plots.show(report, episodes);
  };

  const show = () => {
    summary.replaceChildren(summaryPanel(report));
    verdict.replaceChildren(verdictPanel(report));
    cancelButton.hidden = !running(report);
    return showDetails();
  };

  let timer = null;
  let left = false;
  const poll = async () => {
    try {
      report = await api.get(path);
      if (left) return;
      await show();
    } catch (error) {
      if (left) return;
      actionMessage.replaceChildren(h('span', { class: 'message error', role: 'alert' }, `Updating failed: ${error.message}`));
    }
    if (!left && running(report)) timer = setTimeout(poll, 1000);
  };

  cancelButton.addEventListener('click', async () => {
    cancelButton.disabled = true;
    try {
      report = await api.post(`${path}/cancel`);
      actionMessage.replaceChildren(h('span', { class: 'muted' }, 'Cancelling: running episodes stop at their next step.'));
      await show();
    } catch (error) {
      actionMessage.replaceChildren(h('span', { class: 'message error', role: 'alert' }, `Cancelling failed: ${error.message}`));
    } finally {
      cancelButton.disabled = false;
    }
  });

  await show();
  if (running(report)) timer = setTimeout(poll, 1000);
  return () => {
    left = true;
    clearTimeout(timer);
    plots.destroy();
  };
}

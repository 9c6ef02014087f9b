// #/compare?runs=A,B,C: two to ten runs metric by metric against the first (the baseline) — every
// run's mean, and for each other run the difference, the test's p-value, Holm's adjusted p-value and
// whether it is significantly better or worse — with each run's verdict, failed gates and effective
// controller, the fields in which the runs' configurations differ, the chosen
// metrics' distributions run by run (each saved as PNG or SVG on demand), and the robot's paths of
// the baseline and one chosen run. The address keeps the view: &correction=none (plain p-values),
// &plots=success,… and &paths=RUN.
// The former #/compare/A/B opens #/compare?runs=A,B.
import { api } from '../lib/api.js';
import { h, loading, showError, errorPage, scrollBox, formatNumber, pageTitle } from '../lib/ui.js';
import { withUnit, unitLabel, betterArrow, statusBadge, verdictBadge, isRunning, loadMetrics, metricTitle } from '../lib/plots.js';
import { showInAddress, listOf } from '../lib/hashquery.js';
import { tagChips } from '../runs/fields.js';
import { checkPicker, metricGroups } from '../runs/picker.js';
import { distributionPlot } from '../runs/distribution.js';
import { exportButtons, svgElementText, svgElementPng } from '../lib/plotexport.js';
import { pathsSection } from '../runs/paths.js';
import { controllerText, configDiffSection } from '../runs/config.js';

// One colour per run, the baseline's first; dark enough for thin lines and dots on white.
const COLOURS = ['#2f6fd1', '#d1492f', '#2f8a4f', '#7d4fb8', '#b7791f', '#0f7f86', '#c2418f', '#5d6575', '#8a5a12', '#1d2330'];
const LETTERS = 'ABCDEFGHIJ';
const DEFAULT_PLOTS = ['success', 'minimum_distance_to_people', 'time_to_goal'];
const CHANGE_TONE = { better: 'good', worse: 'bad', different: 'warn', 'no significant change': '' };

const pValue = (p) => (p === null ? '—' : p < 1e-4 ? '< 0.0001' : formatNumber(p));

/** The gates a run failed, as chips after its verdict (none while it runs: its gates are pending). */
function failedGates(report) {
  const failed = isRunning(report.status) ? [] : report.verdict.gates.filter((g) => !g.passed);
  if (!failed.length) return null;
  return [' failed gate', failed.length === 1 ? '' : 's', ': ', failed.map((g) => h('code', { class: 'chip bad' }, g.gate))];
}

function runsTable(runs) {
  return h('table', { class: 'compare-runs' },
    h('thead', {}, h('tr', {}, ['Run', 'Name and tags', 'Scenario', 'Controller', 'Episodes', 'Success rate', 'Verdict']
      .map((t, i) => h('th', { scope: 'col', class: i === 4 || i === 5 ? 'number' : null }, t)))),
    h('tbody', {}, runs.map(({ report, label, colour }, i) => {
      const p = report.progress;
      const config = report.config;
      return h('tr', { 'data-run': report.id },
        h('th', { scope: 'row' }, h('span', { class: 'swatch', style: `background:${colour}` }), ` ${label} `,
          h('a', { href: `#/runs/${report.id}`, class: 'run-id', title: report.id }, report.id.slice(0, 9)), ' ', statusBadge(report.status),
          i === 0 ? h('span', { class: 'muted small' }, ' baseline') : null),
        h('td', {}, report.name ? h('span', { class: 'name' }, report.name, ' ') : null, tagChips(report.tags)),
        h('td', {}, report.scenario),
        h('td', { class: 'run-controller' }, controllerText(config)),
        h('td', { class: 'number' }, `${p.finished}${p.error ? ` (+${p.error} in error)` : ''} / ${p.total}`),
        h('td', { class: 'number' }, report.rates.success_rate === null ? '—' : `${formatNumber(report.rates.success_rate * 100, 2)} %`),
        h('td', { class: 'verdict-facts' }, verdictBadge(report.verdict, report.status), failedGates(report)));
    })));
}

/**
 * The metrics table: a row per metric, the baseline's mean, then for each other run its mean, the
 * difference, p, Holm's p (when corrected) and the change. Sorting by a run's p-value is the table's own.
 */
function comparisonTable(comparison, runs) {
  const holm = comparison.correction === 'holm';
  const others = runs.slice(1);
  let sortedBy = null;
  let order = 'none';
  const body = h('tbody');
  const sortButtons = new Map();
  const header = (text, attributes = {}) => h('th', { scope: 'col', ...attributes }, text);
  const pHeader = (run, index) => {
    const button = h('button', { type: 'button', class: 'link sort', onclick: () => {
      order = sortedBy === index && order === 'ascending' ? 'descending' : sortedBy === index && order === 'descending' ? 'none' : 'ascending';
      sortedBy = order === 'none' ? null : index;
      fill();
    } }, 'p');
    const th = header(button, { class: 'number' });
    sortButtons.set(index, { button, th, run });
    return th;
  };
  const rows = comparison.metrics.map((m) => ({ m, row: h('tr', { 'data-metric': m.key },
    h('th', { scope: 'row' }, m.key),
    h('td', { class: 'arrow' }, betterArrow(m.better)),
    h('td', {}, unitLabel(m.unit)),
    h('td', { class: 'number' }, withUnit(m.runs[0].mean, m.unit), h('span', { class: 'muted small' }, ` (n ${m.runs[0].count})`)),
    m.comparisons.map((c, k) => {
      const label = others[k].label;
      return [
        h('td', { class: 'number group-start' }, withUnit(m.runs[k + 1].mean, m.unit), h('span', { class: 'muted small' }, ` (n ${m.runs[k + 1].count})`)),
        h('td', { class: 'number' }, c.difference === null ? '—' : `${c.difference > 0 ? '+' : ''}${withUnit(c.difference, m.unit)}`),
        h('td', { class: 'number p-value', title: c.test === 'welch_t' ? "Welch's t-test" : "Fisher's exact test" }, pValue(c.p_value)),
        holm ? h('td', { class: 'number p-adjusted' }, pValue(c.p_adjusted)) : null,
        h('td', { class: 'change' }, c.significant ? h('span', { class: `badge ${CHANGE_TONE[c.change]}` }, c.change === 'different' ? `${label} different` : `${label} ${c.change}`)
          : h('span', { class: 'muted small' }, c.p_value === null ? 'not testable' : 'no significant change')),
      ];
    })) }));
  const fill = () => {
    const p = (r) => r.m.comparisons[sortedBy].p_value;
    const sorted = sortedBy === null ? rows : [...rows].sort((x, y) => {
      if (p(x) === null || p(y) === null) return (p(x) === null) - (p(y) === null);
      return order === 'ascending' ? p(x) - p(y) : p(y) - p(x);
    });
    body.replaceChildren(...sorted.map((r) => r.row));
    for (const [index, { button, th, run }] of sortButtons) {
      const state = sortedBy === index ? order : 'none';
      th.setAttribute('aria-sort', state);
      button.textContent = `p ${state === 'ascending' ? '▲' : state === 'descending' ? '▼' : '⇅'}`;
      button.setAttribute('aria-label', `p of ${run.label}: sort by it (now ${state === 'none' ? 'not sorted by it' : state})`);
    }
  };
  const table = h('table', { class: 'comparison' },
    h('thead', {},
      h('tr', {},
        header('Metric', { rowspan: 2 }), header('Better', { rowspan: 2 }), header('Unit', { rowspan: 2 }),
        h('th', { scope: 'colgroup', class: 'group-start' }, h('span', { class: 'swatch', style: `background:${runs[0].colour}` }), ` ${runs[0].label} (baseline)`),
        others.map((run) => h('th', { scope: 'colgroup', colspan: holm ? 5 : 4, class: 'group-start' },
          h('span', { class: 'swatch', style: `background:${run.colour}` }), ` ${run.label} ${run.report.id.slice(0, 9)}`))),
      h('tr', {},
        header('mean', { class: 'number group-start' }),
        others.map((run, k) => [header('mean', { class: 'number group-start' }), header(`${run.label} − ${runs[0].label}`, { class: 'number' }), pHeader(run, k),
          holm ? header('p (Holm)', { class: 'number' }) : null, header('change')]))),
    body);
  fill();
  const significant = comparison.metrics.filter((m) => m.comparisons.some((c) => c.significant));
  return h('div', {},
    h('p', { class: 'muted comparison-note' }, `${significant.length} of ${comparison.metrics.length} metrics differ significantly from the baseline in at least one run `
      + (holm ? `(Holm-adjusted p < ${comparison.significance_level} over the reply's ${comparison.tests} tests). `
        : `(p < ${comparison.significance_level}, no correction: with ${comparison.tests} tests, some look significant by chance). `)
      + 'Better or worse is by each metric\'s direction.'),
    scrollBox(table, 'Metrics of the runs'));
}

export async function render(root, params, query) {
  if (params.a) {
    // The former address of a comparison of two runs: the same view at the new one, in its place in the history.
    location.replace(`#/compare?runs=${params.a},${params.b}`);
    return null;
  }
  const ids = listOf(query, 'runs');
  pageTitle(root, `Compare ${ids.length} runs`, ids.length ? `Baseline ${ids[0]}` : null);
  const wait = loading(root, 'Comparing the runs');
  const view = { correction: query.get('correction') === 'none' ? 'none' : 'holm', plots: listOf(query, 'plots', DEFAULT_PLOTS), paths: query.get('paths') ?? ids[1] };
  const comparisonPath = () => `/api/v1/runs/compare?${new URLSearchParams({ runs: ids.join(','), correction: view.correction })}`;
  let comparison, reports, metrics;
  try {
    [comparison, metrics, ...reports] = await Promise.all([api.get(comparisonPath()), loadMetrics(), ...ids.map((id) => api.get(`/api/v1/runs/${encodeURIComponent(id)}`))]);
  } catch (error) {
    errorPage(root, 'Comparison', error, { href: '#/runs', text: 'All runs: choose 2 to 10 to compare' });
    return null;
  }
  wait.remove();
  const runs = reports.map((report, i) => ({ report, label: LETTERS[i], colour: COLOURS[i] }));
  view.plots = view.plots.filter((key) => metrics.byKey.has(key));
  const address = () => showInAddress('/compare', { runs: ids, correction: view.correction === 'none' ? 'none' : null,
    plots: view.plots.join(',') === DEFAULT_PLOTS.join(',') ? null : view.plots, paths: view.paths === ids[1] ? null : view.paths });

  const holm = h('input', { type: 'checkbox', id: 'holm', checked: view.correction === 'holm' });
  const metricsArea = h('div', { class: 'comparison-area' });
  const plotsArea = h('div', { class: 'distributions' });
  root.append(
    h('p', {}, h('a', { href: '#/runs' }, 'All runs'), ' · ', h('a', { href: `#/compare?runs=${[...ids.slice(1), ids[0]].join(',')}` }, `${runs[1].label} as the baseline`)),
    h('section', { 'aria-labelledby': 'runs-title' }, h('h2', { id: 'runs-title' }, 'Runs'), scrollBox(runsTable(runs), 'Runs compared')),
    configDiffSection(runs),
    h('section', { 'aria-labelledby': 'metrics-title' }, h('h2', { id: 'metrics-title' }, 'Metrics'),
      h('label', { class: 'check', for: 'holm' }, holm, "Holm's correction for testing many metrics and runs at once"),
      metricsArea),
    h('section', { 'aria-labelledby': 'distributions-title' }, h('h2', { id: 'distributions-title' }, 'Distributions'),
      checkPicker({ id: 'plot-metrics', legend: 'Metrics plotted', groups: metricGroups(metrics), chosen: view.plots,
        onChange: (keys) => { view.plots = keys; address(); drawPlots(); } }),
      h('p', { class: 'muted small' }, 'Each run\'s episodes as dots; the box spans the first to the third quartile, the thick line is the median, the whiskers reach the minimum and maximum, the diamond is the mean.'),
      plotsArea));

  const showMetrics = () => metricsArea.replaceChildren(comparisonTable(comparison, runs));
  // A saved plot's file name: the runs' short ids, the baseline's first.
  const fileStem = ids.map((id) => id.slice(0, 9)).join('-');
  const drawPlots = () => {
    plotsArea.replaceChildren();
    const width = Math.min(plotsArea.clientWidth || 720, 760);
    for (const key of view.plots) {
      const m = comparison.metrics.find((item) => item.key === key);
      if (!m) continue;
      const figure = h('figure', { class: 'distribution-plot', 'data-metric': key });
      plotsArea.append(figure);
      const plot = distributionPlot(figure, { title: metricTitle(key, m.better), unit: m.unit === 'bool' ? '' : unitLabel(m.unit), bool: m.unit === 'bool',
        width, runs: m.runs.map((distribution, i) => ({ ...distribution, label: `${runs[i].label} ${runs[i].report.id.slice(0, 9)}`, colour: runs[i].colour })) });
      figure.append(exportButtons(key, `compare-${fileStem}-${key}`, { png: () => svgElementPng(plot), svg: () => svgElementText(plot) }));
    }
    if (!view.plots.length) plotsArea.append(h('p', { class: 'muted' }, 'No metric chosen: choose some above.'));
  };
  holm.addEventListener('change', async () => {
    view.correction = holm.checked ? 'holm' : 'none';
    address();
    const wait = loading(metricsArea, 'Comparing again');
    try {
      comparison = await api.get(comparisonPath());
      showMetrics();
    } catch (error) {
      wait.remove();
      showError(metricsArea, error);
    }
  });
  showMetrics();
  drawPlots();

  root.append(pathsSection(runs, view.paths, (run) => { view.paths = run; address(); }));
  return null;
}

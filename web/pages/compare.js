// #/compare/A/B: two runs metric by metric (both means, the difference, the test's p-value, better or
// worse for B), their summaries side by side, and the robot's paths of a few episodes of each on a map.
import { api } from '../lib/api.js';
import { h, loading, showError, errorPage, scrollBox, formatNumber, pageTitle } from '../lib/ui.js';
import { MapView } from '../lib/map2d.js';
import { withUnit, unitLabel, betterArrow, statusBadge, verdictBadge, isRunning } from '../lib/plots.js';

const EPISODES_DRAWN = 5;
const COLOURS = { a: '#2f6fd1', b: '#d1492f' };
const CHANGE_TONE = { better: 'good', worse: 'bad', different: 'warn', 'no significant change': '' };

function runSummary(report, which) {
  const p = report.progress;
  const config = report.config;
  return h('section', { class: `panel run-side side-${which}`, 'aria-label': `Run ${which.toUpperCase()}` },
    h('h2', {}, h('span', { class: 'swatch', style: `background:${COLOURS[which]}` }), ` ${which.toUpperCase()}: `,
      h('a', { href: `#/runs/${report.id}`, title: report.id }, report.id.slice(0, 9)), ' ', statusBadge(report.status)),
    h('dl', { class: 'facts' },
      h('dt', {}, 'Scenario'), h('dd', {}, `${report.scenario} (snapshot ${report.scenario_record})`),
      h('dt', {}, 'Controller'), h('dd', {}, config.controller ? `${config.controller.type}${config.controller.goal?.location ? ` → ${config.controller.goal.location}` : ''}` : "the scenario's own"),
      h('dt', {}, 'Episodes'), h('dd', {}, `${p.finished} finished${p.error ? `, ${p.error} in error` : ''} of ${p.total}`),
      h('dt', {}, 'Seeds'), h('dd', {}, config.seeds.length > 12 ? `${config.seeds.slice(0, 12).join(', ')}, … (${config.seeds.length})` : config.seeds.join(', ')),
      h('dt', {}, 'Time limit'), h('dd', {}, config.max_time === null ? "the scenario's" : `${formatNumber(config.max_time)} s`),
      h('dt', {}, 'Success rate'), h('dd', {}, report.rates.success_rate === null ? '—' : `${formatNumber(report.rates.success_rate * 100, 2)} %`),
      h('dt', {}, 'Collision rate'), h('dd', {}, report.rates.collision_rate === null ? '—' : `${formatNumber(report.rates.collision_rate * 100, 2)} %`),
      h('dt', {}, 'Verdict'), h('dd', { class: 'verdict-facts' }, verdictBadge(report.verdict, report.status), failedGates(report))));
}

/** The gates a run failed, as chips after its verdict (none while it runs: its gates are pending). */
function failedGates(report) {
  const failed = isRunning(report.status) ? [] : report.verdict.gates.filter((g) => !g.passed);
  if (!failed.length) return null;
  return [' failed gate', failed.length === 1 ? '' : 's', ': ', failed.map((g) => h('code', { class: 'chip bad' }, g.gate))];
}

function comparisonTable(comparison) {
  // Sorting: the metrics list's order, then by p-value ascending / descending (no p-value last).
  let order = 'none';
  const body = h('tbody');
  const sortButton = h('button', { type: 'button', class: 'link sort' }, 'p-value');
  const pHeader = h('th', { scope: 'col', class: 'number', 'aria-sort': 'none' }, sortButton);
  const rows = comparison.metrics.map((m) => ({ m, row: h('tr', { 'data-metric': m.key, class: m.significant ? `significant ${CHANGE_TONE[m.change]}` : null },
    h('th', { scope: 'row' }, m.key),
    h('td', { class: 'arrow' }, betterArrow(m.better)),
    h('td', {}, unitLabel(m.unit)),
    h('td', { class: 'number' }, withUnit(m.a.mean, m.unit), h('span', { class: 'muted small' }, ` (n ${m.a.count})`)),
    h('td', { class: 'number' }, withUnit(m.b.mean, m.unit), h('span', { class: 'muted small' }, ` (n ${m.b.count})`)),
    h('td', { class: 'number' }, m.difference === null ? '—' : `${m.difference > 0 ? '+' : ''}${withUnit(m.difference, m.unit)}`),
    h('td', { class: 'muted small' }, m.test === 'welch_t' ? "Welch's t" : "Fisher's exact"),
    h('td', { class: 'number p-value' }, m.p_value === null ? '—' : m.p_value < 1e-4 ? '< 0.0001' : formatNumber(m.p_value)),
    h('td', {}, m.significant ? h('span', { class: `badge ${CHANGE_TONE[m.change]}` }, m.change === 'different' ? 'different' : `B ${m.change}`)
      : h('span', { class: 'muted small' }, m.p_value === null ? 'not testable' : 'no significant change'))) }));
  const fill = () => {
    const sorted = order === 'none' ? rows : [...rows].sort((x, y) => {
      const px = x.m.p_value, py = y.m.p_value;
      if (px === null || py === null) return (px === null) - (py === null);
      return order === 'ascending' ? px - py : py - px;
    });
    body.replaceChildren(...sorted.map((r) => r.row));
    pHeader.setAttribute('aria-sort', order);
    sortButton.textContent = `p-value ${order === 'ascending' ? '▲' : order === 'descending' ? '▼' : '⇅'}`;
    sortButton.setAttribute('aria-label', `Sort by p-value (now ${order === 'none' ? 'in the metrics order' : order})`);
  };
  sortButton.addEventListener('click', () => {
    order = order === 'ascending' ? 'descending' : order === 'descending' ? 'none' : 'ascending';
    fill();
  });
  fill();
  const significant = comparison.metrics.filter((m) => m.significant);
  return h('div', {},
    h('p', { class: 'muted' }, `${significant.length} of ${comparison.metrics.length} metrics differ significantly (p < ${comparison.significance_level}); `
      + 'better or worse says how B compares with A by each metric\'s direction. No correction for testing many metrics at once.'),
    scrollBox(h('table', { class: 'comparison' },
      h('thead', {}, h('tr', {},
        h('th', { scope: 'col' }, 'Metric'), h('th', { scope: 'col' }, 'Better'), h('th', { scope: 'col' }, 'Unit'),
        h('th', { scope: 'col', class: 'number' }, 'A mean'), h('th', { scope: 'col', class: 'number' }, 'B mean'),
        h('th', { scope: 'col', class: 'number' }, 'B − A'), h('th', { scope: 'col' }, 'Test'), pHeader, h('th', { scope: 'col' }, 'Change'))),
      body), 'Metrics of A and B'));
}

/** The first robot's path in the first few stored episodes of a run: [{seed, points}]. */
async function robotPaths(report, robotId) {
  const stored = report.episodes.filter((e) => e.episode_id).slice(0, EPISODES_DRAWN);
  const trajectories = await Promise.all(stored.map((e) => api.get(`/api/v1/episodes/${e.episode_id}/trajectory?format=json`)));
  return trajectories.map((t, i) => ({ seed: stored[i].seed, points: (t.agents[robotId] ?? []).map((s) => [s.x, s.y]) }))
    .filter((p) => p.points.length);
}

async function drawPaths(container, entries) {
  // entries: [{which, report, world}], drawn on the first entry's world.
  const world = entries[0].world;
  const robot = world.agents.find((a) => a.kind === 'robot');
  if (!robot) {
    container.append(h('p', { class: 'message info' }, 'The scenario has no robot: there is no robot path to draw.'));
    return;
  }
  const view = new MapView(container, world, { width: entries.length > 1 ? 760 : 580, maxHeight: entries.length > 1 ? 520 : 420, starts: false });
  const legend = h('p', { class: 'legend small' });
  for (const { which, report } of entries) {
    const paths = await robotPaths(report, robot.id);
    for (const { seed, points } of paths) {
      view.path(points, { colour: COLOURS[which], width: 2, dash: which === 'b' ? '6 3' : null, label: `run ${which.toUpperCase()}, seed ${seed}` })
        .setAttribute('opacity', 0.75);
    }
    legend.append(h('span', { class: 'swatch', style: `background:${COLOURS[which]}` }),
      ` run ${which.toUpperCase()} (${paths.length} episode${paths.length === 1 ? '' : 's'}${which === 'b' ? ', dashed' : ''}) `);
  }
  view.agent(robot.start.x, robot.start.y, robot.start.theta, 'robot', robot.radius, `${robot.id} at the start`);
  container.append(legend);
}

export async function render(root, params) {
  const { a, b } = params;
  pageTitle(root, 'Compare runs', `A ${a} (baseline) vs B ${b}`);
  const wait = loading(root, 'Comparing the runs');
  let comparison, reportA, reportB;
  try {
    [comparison, reportA, reportB] = await Promise.all([
      api.get(`/api/v1/runs/compare?a=${encodeURIComponent(a)}&b=${encodeURIComponent(b)}`),
      api.get(`/api/v1/runs/${encodeURIComponent(a)}`),
      api.get(`/api/v1/runs/${encodeURIComponent(b)}`),
    ]);
  } catch (error) {
    errorPage(root, `Comparison of ${a} and ${b}`, error, { href: '#/runs', text: 'All runs' });
    return null;
  }
  wait.remove();
  root.append(h('p', {}, h('a', { href: `#/compare/${b}/${a}` }, 'Swap A and B'), ' · ', h('a', { href: '#/runs' }, 'all runs')));
  root.append(h('div', { class: 'compare-sides' }, runSummary(reportA, 'a'), runSummary(reportB, 'b')));
  const mapSection = h('section', { class: 'panel compare-map', 'aria-labelledby': 'paths-title' },
    h('h2', { id: 'paths-title' }, `The robot's paths (first ${EPISODES_DRAWN} episodes of each run)`));
  root.append(h('section', { 'aria-labelledby': 'metrics-title' }, h('h2', { id: 'metrics-title' }, 'Metrics'), comparisonTable(comparison)), mapSection);

  const mapWait = loading(mapSection, 'Loading the trajectories');
  try {
    if (reportA.scenario_record === reportB.scenario_record) {
      const world = await api.get(`/api/v1/scenarios/${encodeURIComponent(reportA.scenario_record)}/world`);
      const box = h('div', { class: 'map-box' });
      mapSection.append(box);
      await drawPaths(box, [{ which: 'a', report: reportA, world }, { which: 'b', report: reportB, world }]);
    } else {
      mapSection.append(h('p', { class: 'message info' }, reportA.scenario === reportB.scenario
        ? `Both runs are of ${reportA.scenario}, but the scenario changed between them (snapshots ${reportA.scenario_record} and ${reportB.scenario_record}): each is drawn on its own map.`
        : `The runs are of different scenarios (${reportA.scenario} and ${reportB.scenario}): each is drawn on its own map.`));
      const [worldA, worldB] = await Promise.all([reportA, reportB].map((r) => api.get(`/api/v1/scenarios/${encodeURIComponent(r.scenario_record)}/world`)));
      const boxA = h('div', { class: 'map-box' }, h('h3', {}, `A: ${reportA.scenario}`));
      const boxB = h('div', { class: 'map-box' }, h('h3', {}, `B: ${reportB.scenario}`));
      mapSection.append(h('div', { class: 'compare-sides' }, boxA, boxB));
      await drawPaths(boxA, [{ which: 'a', report: reportA, world: worldA }]);
      await drawPaths(boxB, [{ which: 'b', report: reportB, world: worldB }]);
    }
  } catch (error) {
    const box = h('div');
    mapSection.append(box);
    showError(box, error);
  } finally {
    mapWait.remove();
  }
  return null;
}

// A run report's per-episode values: one dot plot per chosen metric (seeds along x, in the run's order),
// each saved as PNG or SVG on demand. The page keeps the choice in its address.
import { h } from '../lib/ui.js';
import { unitLabel, dotPlot, metricTitle } from '../lib/plots.js';
import { plotPng, plotSvg, exportButtons } from '../lib/plotexport.js';
import { checkPicker, metricGroups } from './picker.js';

const PLOT_COLOURS = ['#2f8a4f', '#c0392b', '#2f6fd1', '#7d4fb8', '#b7791f'];

/**
 * The section, its plots of `chosen` metrics drawn by show(report, episodes) (again after each choice);
 * `onChoose(keys)` hears the choice. destroy() frees the plots.
 */
export function episodePlots({ runId, metrics, chosen, onChoose }) {
  let plotted = chosen;
  let last = null;
  let uplots = [];
  const grid = h('div', { class: 'dot-plots' });
  const picker = checkPicker({ id: 'plot-metrics', legend: 'Metrics plotted', groups: metricGroups(metrics), chosen,
    onChange: (keys) => {
      plotted = keys;
      onChoose(keys);
      if (last) show(last.report, last.episodes);
    } });
  const element = h('section', { 'aria-labelledby': 'plots-title' }, h('h2', { id: 'plots-title' }, 'Per-episode values'), picker, grid);
  const destroy = () => { for (const u of uplots) u.destroy(); uplots = []; };

  /** Plots `report`'s finished `episodes` (those listed by GET …/episodes). */
  const show = (report, episodes) => {
    last = { report, episodes };
    destroy();
    grid.replaceChildren();
    const finished = episodes.filter((e) => e.status === 'finished');
    if (!finished.length || !plotted.length) {
      grid.append(h('p', { class: 'muted' }, finished.length ? 'No metric chosen: choose some above.' : 'No finished episode yet.'));
      return;
    }
    // The seeds' order of the report, so a plot's x axis reads like the episodes table.
    const order = new Map(report.config.seeds.map((s, i) => [s, i]));
    finished.sort((a, b) => order.get(a.seed) - order.get(b.seed));
    plotted.forEach((key, i) => {
      const metric = metrics.byKey.get(key);
      const points = finished.map((e) => ({ seed: e.seed, value: e.metrics[key] ?? null }));
      const cell = h('figure', { class: 'dot-plot', 'data-metric': key });
      grid.append(cell);
      if (points.every((p) => p.value === null)) {
        cell.append(h('figcaption', {}, `${key.replaceAll('_', ' ')}: no value in any episode`));
        return;
      }
      const title = metricTitle(key, metric.better);
      const u = dotPlot(cell, { points, title, unit: unitLabel(metric.unit), bool: metric.unit === 'bool', colour: PLOT_COLOURS[i % PLOT_COLOURS.length] });
      uplots.push(u);
      cell.append(exportButtons(key, `${runId}-${key}`, { png: () => plotPng(u, title), svg: () => plotSvg(u, title) }));
    });
  };
  return { element, show, destroy };
}

// One metric's distribution in each of several runs, drawn as SVG: a row per run with its episodes'
// values as dots (spread up and down a little, so that equal values stay visible), a box from the
// first to the third quartile with the median, whiskers to the minimum and maximum, and the mean as a
// diamond. Its text alternative is a summary and the numbers as a table (lib/plots.js); the compare
// page saves it as SVG or PNG (lib/plotexport.js svgElementText, svgElementPng).
import { formatNumber } from '../lib/ui.js';
import { textAlternative } from '../lib/plots.js';

const SVG = 'http://www.w3.org/2000/svg';
const ROW = 34;
const LEFT = 120;
const RIGHT = 16;
const TOP = 26;
const AXIS = 34;

function svg(tag, attributes = {}, text = null) {
  const element = document.createElementNS(SVG, tag);
  for (const [name, value] of Object.entries(attributes)) element.setAttribute(name, String(value));
  if (text !== null) element.textContent = text;
  return element;
}

/**
 * About `count` round ticks from `low` to `high` (steps of 1, 2 or 5 times a power of ten), each as
 * {value, text} with as many decimals as the step needs.
 */
function ticks(low, high, count = 5) {
  const rough = (high - low) / count;
  const magnitude = 10 ** Math.floor(Math.log10(rough));
  const step = [1, 2, 5, 10].map((m) => m * magnitude).find((s) => s >= rough);
  const decimals = Math.max(0, -Math.floor(Math.log10(step) + 1e-9));
  const result = [];
  for (let k = Math.ceil(low / step - 1e-9); k * step <= high + step * 1e-9; k++) {
    result.push({ value: k * step, text: (k * step).toLocaleString('en', { maximumFractionDigits: decimals }) });
  }
  return result;
}

/** The x range over every run's values, a little wider; a single value gets room around it. */
function domain(runs, bool) {
  if (bool) return [-0.08, 1.08];
  const present = runs.filter((r) => r.count > 0);
  let low = Math.min(...present.map((r) => r.min));
  let high = Math.max(...present.map((r) => r.max));
  if (high - low < 1e-12) {
    const room = Math.abs(low) > 1e-12 ? Math.abs(low) * 0.1 : 1;
    low -= room;
    high += room;
  }
  const pad = (high - low) * 0.05;
  return [low - pad, high + pad];
}

/**
 * Draws the plot in `container` (a figure). `runs` is [{label, colour, count, mean, min, q1, median,
 * q3, max, values}] as GET /api/v1/runs/compare gives each run's distribution, with a label and colour.
 */
export function distributionPlot(container, { title, unit, bool, runs, width = 720 }) {
  const plotWidth = Math.max(320, Math.min(width, 760));
  const height = TOP + runs.length * ROW + AXIS;
  const root = svg('svg', { class: 'distribution', width: plotWidth, height, viewBox: `0 0 ${plotWidth} ${height}`, xmlns: SVG });
  root.append(svg('rect', { width: plotWidth, height, fill: '#fff' }),
    svg('text', { x: plotWidth / 2, y: 16, 'text-anchor': 'middle', 'font-weight': 600, 'font-size': 13 }, title));
  const withValues = runs.filter((r) => r.count > 0);
  const [low, high] = withValues.length ? domain(withValues, bool) : [0, 1];
  const x = (value) => LEFT + ((value - low) / (high - low)) * (plotWidth - LEFT - RIGHT);
  const bottom = TOP + runs.length * ROW;

  const axis = svg('g', { class: 'axis', 'font-size': 11 });
  const marks = bool ? [{ value: 0, text: 'no (0)' }, { value: 1, text: 'yes (1)' }] : ticks(low, high);
  for (const { value, text } of marks) {
    axis.append(svg('line', { x1: x(value), x2: x(value), y1: TOP, y2: bottom, stroke: '#e3e6eb' }),
      svg('text', { x: x(value), y: bottom + 14, 'text-anchor': 'middle' }, text));
  }
  if (unit && !bool) axis.append(svg('text', { x: LEFT + (plotWidth - LEFT - RIGHT) / 2, y: bottom + 29, 'text-anchor': 'middle' }, unit));
  root.append(axis);

  runs.forEach((run, i) => {
    const middle = TOP + i * ROW + ROW / 2;
    const row = svg('g', { class: 'run-row', 'data-run': run.run ?? run.label });
    row.append(svg('text', { x: LEFT - 8, y: middle + 4, 'text-anchor': 'end', 'font-size': 12 }, run.label));
    if (!run.count) {
      row.append(svg('text', { x: LEFT + 4, y: middle + 4, 'font-size': 11, fill: '#5d6575' }, 'no value'));
      root.append(row);
      return;
    }
    const box = { stroke: run.colour, 'stroke-width': 1.5, fill: 'none' };
    row.append(svg('line', { ...box, x1: x(run.min), x2: x(run.q1), y1: middle, y2: middle }),
      svg('line', { ...box, x1: x(run.q3), x2: x(run.max), y1: middle, y2: middle }),
      svg('line', { ...box, x1: x(run.min), x2: x(run.min), y1: middle - 6, y2: middle + 6 }),
      svg('line', { ...box, x1: x(run.max), x2: x(run.max), y1: middle - 6, y2: middle + 6 }),
      svg('rect', { ...box, x: x(run.q1), y: middle - 10, width: Math.max(x(run.q3) - x(run.q1), 1), height: 20, 'fill-opacity': 0.08, fill: run.colour }),
      svg('line', { ...box, 'stroke-width': 2.5, x1: x(run.median), x2: x(run.median), y1: middle - 10, y2: middle + 10 }));
    // Dots spread by the golden ratio's sequence (the first in the middle): the same picture every time, equal values apart.
    run.values.forEach((value, k) => {
      const offset = ((((k * 0.618034) + 0.5) % 1) - 0.5) * (ROW - 10);
      row.append(svg('circle', { class: 'value', cx: x(value), cy: middle + offset, r: 3.2, fill: run.colour, 'fill-opacity': 0.7 }));
    });
    const m = x(run.mean);
    row.append(svg('path', { class: 'mean', d: `M${m} ${middle - 6}L${m + 6} ${middle}L${m} ${middle + 6}L${m - 6} ${middle}Z`, fill: '#fff', stroke: '#1d2330', 'stroke-width': 1.5 }));
    root.append(row);
  });
  container.append(root);

  const show = (value) => (bool ? formatNumber(value) : `${formatNumber(value)}${unit ? ` ${unit}` : ''}`);
  textAlternative(root, container, {
    title,
    summary: `${title}, per run: ${runs.map((r) => (r.count ? `${r.label} mean ${show(r.mean)}, median ${show(r.median)}, from ${show(r.min)} to ${show(r.max)} (${r.count} episodes)`
      : `${r.label} no value`)).join('; ')}.`,
    headings: ['run', 'episodes', 'mean', 'min', 'first quartile', 'median', 'third quartile', 'max'],
    rows: () => runs.map((r) => [r.label, String(r.count), ...[r.mean, r.min, r.q1, r.median, r.q3, r.max].map((v) => formatNumber(v))]),
  });
  return root;
}

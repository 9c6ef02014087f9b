// uPlot helpers for runs and episodes: time series synchronised with a replay scrubber (a marker
// line that follows the replay, hovering that moves the replay) and per-episode dot plots, each with
// a text alternative (a summary as its accessible name, its data as a table on demand); and the
// metric formatting (units, "better" arrows, status badges) the runs pages share with their plots.
import uPlot from 'uplot';
import { api } from './api.js';
import { h, formatNumber, scrollBox } from './ui.js';

let metricsRequest = null;

/** GET /api/v1/metrics once per page load: {items, series, byKey}. */
export function loadMetrics() {
  metricsRequest ??= api.get('/api/v1/metrics').then((reply) => ({ ...reply, byKey: new Map(reply.items.map((m) => [m.key, m])) }))
    .catch((error) => { metricsRequest = null; throw error; });
  return metricsRequest;
}

/** The metrics' categories (GET /api/v1/metrics `category`) in words. */
export const CATEGORY_NAMES = {
  task_and_path: 'Task and path', proximity: 'Proximity', contact: 'Contact', social_forces: 'Social forces',
  interaction: 'Interaction', task_rewards: 'Task rewards',
};

/** A metric's value with its unit: "0.42 m", "12 %", "3" (count), "yes"/"no" (bool, one episode). */
export function withUnit(value, unit, { bool = 'number' } = {}) {
  if (value === null || value === undefined) return '—';
  if (unit === 'bool' && bool === 'word') return value >= 0.5 ? 'yes' : 'no';
  const number = formatNumber(value);
  if (unit === 'count' || unit === 'bool' || unit === 'ratio' || unit === 'reward') return number;
  return unit === '%' ? `${number} %` : `${number} ${unit}`;
}

/** How a unit reads in a table's unit column. */
export function unitLabel(unit) {
  return { bool: '0/1', ratio: 'ratio', count: 'count', reward: 'reward' }[unit] ?? unit;
}

/** ↑ / ↓ / – for a metric's better direction, with its meaning for screen readers and tooltips. */
export function betterArrow(better) {
  const text = { higher: ['↑', 'higher is better'], lower: ['↓', 'lower is better'], none: ['–', 'descriptive: neither way is better'] }[better]
    ?? ['', ''];
  return h('span', { class: `better ${better}`, title: text[1], 'aria-label': text[1] }, text[0]);
}

/** A metric's key as a plot's title, with ↑ or ↓ when one way is better: "minimum distance to people ↑". */
export function metricTitle(key, better) {
  return `${key.replaceAll('_', ' ')}${better === 'higher' ? ' ↑' : better === 'lower' ? ' ↓' : ''}`;
}

const STATUS_TONE = { finished: 'good', failed: 'bad', error: 'bad', cancelled: 'warn', interrupted: 'warn', running: '', queued: '' };

/** A run's or episode's status as a badge. */
export function statusBadge(status) {
  return h('span', { class: `badge status ${STATUS_TONE[status] ?? ''}` }, status);
}

/** A run still has episodes to run: its verdict and gates are not settled yet. */
export const isRunning = (status) => status === 'queued' || status === 'running';

/** A run's verdict as a badge: passed, pending (still running), failed, or incomplete (cancelled, interrupted). */
export function verdictBadge(verdict, status) {
  if (verdict.passed) return h('span', { class: 'badge good' }, 'passed');
  if (isRunning(status)) return h('span', { class: 'badge' }, 'pending');
  return verdict.complete ? h('span', { class: 'badge bad' }, 'failed') : h('span', { class: 'badge warn' }, 'incomplete');
}

/** Hall's proxemic zones (m), as the proxemic_zone series and the intrusion metrics count them. */
export const PROXEMIC_BANDS = [
  { name: 'intimate', from: 0, to: 0.45, colour: 'rgba(192, 57, 43, 0.16)' },
  { name: 'personal', from: 0.45, to: 1.2, colour: 'rgba(183, 121, 31, 0.14)' },
  { name: 'social', from: 1.2, to: 3.6, colour: 'rgba(47, 111, 209, 0.09)' },
];

/** A uPlot draw hook shading horizontal bands [{from, to, colour}] (in y values) under the series. */
function bandsHook(bands) {
  return (u) => {
    const { ctx, bbox } = u;
    ctx.save();
    for (const band of bands) {
      const top = u.valToPos(band.to, 'y', true);
      const bottom = u.valToPos(band.from, 'y', true);
      const y0 = Math.max(Math.min(top, bottom), bbox.top);
      const y1 = Math.min(Math.max(top, bottom), bbox.top + bbox.height);
      if (y1 <= y0) continue;
      ctx.fillStyle = band.colour;
      ctx.fillRect(bbox.left, y0, bbox.width, y1 - y0);
    }
    ctx.restore();
  };
}

/** A y range from 0 (or below) that stays readable when every value is the same. */
function valueRange(min, max) {
  if (min === null || max === null) return [0, 1];
  const low = Math.min(0, min);
  const high = max - low < 1e-12 ? low + 1 : max;
  return uPlot.rangeNum(low, high, 0.1, true);
}

const axisValues = (u, splits) => splits.map((v) => formatNumber(v, 2));

/** "from 0.1 to 3.2 m, mean 1.4 m" over the values that are not null; "no value" when none is. */
function valueSummary(values, unit) {
  const present = values.filter((v) => v !== null && v !== undefined);
  if (!present.length) return 'no value';
  const mean = present.reduce((a, b) => a + b, 0) / present.length;
  const withIt = (v) => `${formatNumber(v)}${unit ? ` ${unit}` : ''}`;
  const missing = values.length - present.length;
  return `from ${withIt(Math.min(...present))} to ${withIt(Math.max(...present))}, mean ${withIt(mean)}${missing ? `, ${missing} without a value` : ''}`;
}

/**
 * A plot's text alternative: `summary` as the accessible name of the plot's `element`, and after it in
 * `container` a button that shows the plotted data as a table (`headings`, `rows` of cells; built on first use).
 */
export function textAlternative(element, container, { title, summary, headings, rows }) {
  element.setAttribute('role', 'img');
  element.setAttribute('aria-label', summary);
  const box = h('div', { class: 'plot-table', hidden: true });
  const toggle = h('button', { type: 'button', class: 'link plot-table-toggle', 'aria-expanded': 'false' }, 'Show as table');
  toggle.addEventListener('click', () => {
    const open = box.hidden;
    if (open && !box.firstChild) {
      box.append(scrollBox(h('table', { class: 'compact' }, h('caption', {}, title),
        h('thead', {}, h('tr', {}, headings.map((heading) => h('th', { scope: 'col', class: 'number' }, heading)))),
        h('tbody', {}, rows().map((cells) => h('tr', {}, cells.map((cell) => h('td', { class: 'number' }, cell)))))), `${title} as a table`));
    }
    box.hidden = !open;
    toggle.setAttribute('aria-expanded', String(open));
    toggle.textContent = open ? 'Hide the table' : 'Show as table';
  });
  container.append(toggle, box);
}

function plotWidth(container, fallback = 520) {
  return Math.max(240, Math.floor(container.clientWidth || fallback));
}

/**
 * A time-series plot of `values` over `times` (s) in `container`. Options: title, unit, colour,
 * bands (shaded y ranges), clipAbove (the y axis ends there: larger values are drawn at that
 * height, the legend and the table keep them as they are), syncKey (plots sharing it share their
 * cursor), onHover(time) (the user hovers a sample). Returns {plot, setMarker(time), destroy()}:
 * setMarker moves the vertical line that shows the replay's time.
 */
export function timePlot(container, { times, values, title, unit, colour = '#2f6fd1', bands = null, clipAbove = null, syncKey = null, onHover = null, height = 150 }) {
  const yRange = clipAbove !== null ? () => [0, clipAbove * 1.05]
    : bands ? (u, min, max) => [0, Math.max(max ?? 0, bands[bands.length - 1].to) * 1.05]
      : (u, min, max) => valueRange(min, max);
  // The replay's time as a DOM line over the plot: cheap to move many times a second, no redraw.
  // Its place needs the scales, which uPlot sets up after the constructor returns: placed when ready.
  const marker = document.createElement('div');
  marker.className = 'plot-marker';
  let markerTime = null;
  const place = (u) => {
    if (markerTime === null) return;
    const left = u.valToPos(markerTime, 'x');
    if (!Number.isFinite(left)) return;
    marker.style.left = `${left}px`;
    marker.dataset.time = String(markerTime);
    // The legend reads the value at the replay's time too (samples are evenly spaced from 0).
    const xs = u.data[0];
    const step = xs.length > 1 ? xs[1] - xs[0] : 1;
    u.setLegend({ idx: Math.max(0, Math.min(xs.length - 1, Math.round((markerTime - xs[0]) / step))) }, false);
  };
  const plot = new uPlot({
    width: plotWidth(container),
    height,
    title,
    scales: { x: { time: false }, y: { range: yRange } },
    legend: { show: true },
    cursor: { y: false, sync: syncKey ? { key: syncKey } : undefined, drag: { x: false, y: false }, points: { size: 6 } },
    series: [
      { label: 'time', value: (u, v) => (v === null ? '—' : `${formatNumber(v, 2)} s`) },
      { label: title, stroke: colour, width: 1.5, spanGaps: false,
        value: (u, v, series, i) => (i === null || values[i] === null ? '—' : `${formatNumber(values[i])} ${unit}`) },
    ],
    axes: [
      { label: 'time (s)', labelSize: 18, size: 32 },
      { label: unit, labelSize: 18, size: 52, values: axisValues },
    ],
    hooks: {
      ready: [(u) => { u.over.append(marker); place(u); }],
      drawClear: bands ? [bandsHook(bands)] : [],
      setCursor: onHover ? [(u) => { if (u.cursor.idx !== null && u.cursor.idx !== undefined) onHover(u.data[0][u.cursor.idx]); }] : [],
      // The y axis's extent, for a look from outside the canvas (tests).
      setScale: [(u, key) => { if (key === 'y') u.root.dataset.yMax = String(u.scales.y.max); }],
    },
  }, [times, clipAbove === null ? values : values.map((v) => (v === null ? null : Math.min(v, clipAbove)))], container);
  const end = times.length ? times[times.length - 1] : 0;
  textAlternative(plot.root, container, {
    title: `${title} over time`,
    summary: `${title} over ${formatNumber(end, 2)} s, ${times.length} samples: ${valueSummary(values, unit)}`
      + `${clipAbove !== null ? `; the plot shows 0 to ${formatNumber(clipAbove)} ${unit}, more drawn at ${formatNumber(clipAbove)} ${unit}` : ''}.`,
    headings: ['time (s)', `${title} (${unit})`],
    rows: () => times.map((time, i) => [formatNumber(time, 2), values[i] === null ? '—' : formatNumber(values[i])]),
  });
  return {
    plot,
    setMarker(time) { markerTime = time; place(plot); },
    destroy() { plot.destroy(); },
  };
}

/** A series drawn as dots, without a line between them (lib/plotexport.js draws it so too). */
export const POINTS_ONLY = () => null;

/**
 * Per-episode values of one metric as dots (x: episodes in run order, labelled by seed) with a dashed
 * line at their mean. `points` is [{seed, value}] (null values are left out by the caller or shown as
 * gaps). Returns the uPlot instance (destroy it on leave).
 */
export function dotPlot(container, { points, title, unit, bool = false, colour = '#2f6fd1', height = 170 }) {
  const xs = points.map((_, i) => i + 1);
  const ys = points.map((p) => p.value);
  const present = ys.filter((v) => v !== null && v !== undefined);
  const mean = present.length ? present.reduce((a, b) => a + b, 0) / present.length : null;
  const seeds = points.map((p) => p.seed);
  const plot = new uPlot({
    width: plotWidth(container, 300),
    height,
    title,
    scales: {
      x: { time: false, range: () => [0.5, xs.length + 0.5] },
      y: { range: bool ? () => [-0.15, 1.15] : (u, min, max) => valueRange(min, max) },
    },
    legend: { show: false },
    cursor: { drag: { x: false, y: false }, points: { size: 9 } },
    series: [
      { label: 'episode' },
      { label: title, stroke: colour, fill: colour, paths: POINTS_ONLY, points: { show: true, size: 8, fill: colour } },
      { label: 'mean', stroke: '#5d6575', dash: [5, 4], width: 1, points: { show: false } },
    ],
    axes: [
      {
        label: 'seed', labelSize: 18, size: 32,
        ...(xs.length <= 12 ? { splits: () => xs } : {}),
        values: (u, splits) => splits.map((x) => (Number.isInteger(x) && seeds[x - 1] !== undefined ? String(seeds[x - 1]) : '')),
      },
      bool ? { label: unit, labelSize: 18, size: 52, splits: () => [0, 1], values: (u, splits) => splits.map((v) => (v ? 'yes' : 'no')) }
        : { label: unit, labelSize: 18, size: 52, values: axisValues },
    ],
  }, [xs, ys, xs.map(() => mean)], container);
  const valueText = (v) => (v === null || v === undefined ? '—' : bool ? (v >= 0.5 ? 'yes' : 'no') : formatNumber(v));
  textAlternative(plot.root, container, {
    title: `${title} per episode`,
    summary: `${title} per episode, ${points.length} episode${points.length === 1 ? '' : 's'}: ${valueSummary(ys, bool ? '' : unit)}.`,
    headings: ['seed', bool ? title : `${title} (${unit})`],
    rows: () => points.map((p) => [String(p.seed), valueText(p.value)]),
  });
  return plot;
}

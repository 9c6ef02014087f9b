// A plot as a file, for papers and slides. A uPlot plot: a PNG of its canvas (axes, dots, lines) under
// its title, and an SVG drawn from the same scales, ticks and data (uPlot keeps the ticks it drew in
// its axes' _splits and _values: not a documented field, but the only record of what the canvas
// shows). A plot the page draws as SVG (runs/distribution.js): that SVG as a file, and as a PNG drawn
// from it. exportButtons() offers either as the PNG and SVG buttons under a plot.
import { POINTS_ONLY } from './plots.js';
import { h } from './ui.js';
import { saveButton } from './download.js';

const TITLE_HEIGHT = 28;
const FONT = 'system-ui, -apple-system, "Segoe UI", Roboto, sans-serif';
const TEXT = '#1d2330';
const GRID = '#d9dde4';

/** The plot `u` as a PNG blob: its canvas on white, `title` above it. */
export function plotPng(u, title) {
  const source = u.ctx.canvas;
  const ratio = source.width / u.width;
  const canvas = document.createElement('canvas');
  canvas.width = source.width;
  canvas.height = source.height + Math.round(TITLE_HEIGHT * ratio);
  const context = canvas.getContext('2d');
  context.fillStyle = '#fff';
  context.fillRect(0, 0, canvas.width, canvas.height);
  context.fillStyle = TEXT;
  context.font = `600 ${14 * ratio}px ${FONT}`;
  context.textAlign = 'center';
  context.textBaseline = 'middle';
  context.fillText(title, canvas.width / 2, (TITLE_HEIGHT * ratio) / 2);
  context.drawImage(source, 0, Math.round(TITLE_HEIGHT * ratio));
  return new Promise((resolve) => canvas.toBlob(resolve, 'image/png'));
}

const escape = (text) => String(text).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' })[c]);
const round = (value) => Math.round(value * 10) / 10;

/** The plot `u` as an SVG document (text): title, grid, ticks and axis labels, each series as dots or a line. */
export function plotSvg(u, title) {
  const ratio = u.ctx.canvas.width / u.width;
  const left = u.bbox.left / ratio;
  const top = u.bbox.top / ratio + TITLE_HEIGHT;
  const width = u.bbox.width / ratio;
  const height = u.bbox.height / ratio;
  const x = (value) => round(left + u.valToPos(value, 'x'));
  const y = (value) => round(top + u.valToPos(value, 'y'));
  const parts = [
    `<rect width="100%" height="100%" fill="#fff"/>`,
    `<text x="${round(u.width / 2)}" y="18" text-anchor="middle" font-weight="600" font-size="14">${escape(title)}</text>`,
  ];
  const [xAxis, yAxis] = u.axes;
  (yAxis._splits ?? []).forEach((split, i) => {
    parts.push(`<line x1="${round(left)}" x2="${round(left + width)}" y1="${y(split)}" y2="${y(split)}" stroke="${GRID}"/>`,
      `<text x="${round(left - 6)}" y="${y(split) + 4}" text-anchor="end">${escape(yAxis._values?.[i] ?? split)}</text>`);
  });
  (xAxis._splits ?? []).forEach((split, i) => {
    parts.push(`<text x="${x(split)}" y="${round(top + height + 16)}" text-anchor="middle">${escape(xAxis._values?.[i] ?? split)}</text>`);
  });
  parts.push(`<rect x="${round(left)}" y="${round(top)}" width="${round(width)}" height="${round(height)}" fill="none" stroke="${GRID}"/>`);
  if (xAxis.label) parts.push(`<text x="${round(left + width / 2)}" y="${round(top + height + 34)}" text-anchor="middle">${escape(xAxis.label)}</text>`);
  if (yAxis.label) {
    parts.push(`<text transform="translate(14 ${round(top + height / 2)}) rotate(-90)" text-anchor="middle">${escape(yAxis.label)}</text>`);
  }
  u.series.slice(1).forEach((series, index) => {
    if (!series.show) return;
    const i = index + 1;
    const colour = series.stroke(u, i) ?? TEXT;
    const points = u.data[0].map((xValue, k) => [xValue, u.data[i][k]]);
    if (series.paths === POINTS_ONLY) {
      for (const [xValue, yValue] of points) {
        if (yValue !== null && yValue !== undefined) parts.push(`<circle cx="${x(xValue)}" cy="${y(yValue)}" r="4" fill="${colour}"/>`);
      }
      return;
    }
    // A line, broken where a value is missing.
    const dash = series.dash ? ` stroke-dasharray="${series.dash.join(' ')}"` : '';
    let run = [];
    const flush = () => {
      if (run.length > 1) parts.push(`<polyline points="${run.join(' ')}" fill="none" stroke="${colour}" stroke-width="${series.width}"${dash}/>`);
      run = [];
    };
    for (const [xValue, yValue] of points) {
      if (yValue === null || yValue === undefined) flush();
      else run.push(`${x(xValue)},${y(yValue)}`);
    }
    flush();
  });
  const svgHeight = round(u.height + TITLE_HEIGHT);
  return `<svg xmlns="http://www.w3.org/2000/svg" width="${u.width}" height="${svgHeight}" viewBox="0 0 ${u.width} ${svgHeight}" `
    + `font-family='${FONT}' font-size="11" fill="${TEXT}">\n${parts.join('\n')}\n</svg>\n`;
}

/**
 * The buttons under a plot of metric `key` that save it as `name`.png and `name`.svg: `png()` gives
 * the PNG blob (or a promise of it), `svg()` the SVG document's text.
 */
export function exportButtons(key, name, { png, svg }) {
  return h('div', { class: 'plot-exports' },
    saveButton('PNG', async () => ({ blob: await png(), filename: `${name}.png` }), { 'aria-label': `Save the plot of ${key} as PNG` }),
    saveButton('SVG', () => ({ blob: new Blob([svg()], { type: 'image/svg+xml' }), filename: `${name}.svg` }),
      { 'aria-label': `Save the plot of ${key} as SVG` }));
}

/**
 * An <svg> of the page as an SVG document (text) that looks the same on its own: the page's styles
 * (its font) written into it, the page's own attributes (class, role, its accessible name) left out.
 */
export function svgElementText(element) {
  const copy = element.cloneNode(true);
  for (const name of ['class', 'role', 'aria-label', 'style']) copy.removeAttribute(name);
  copy.setAttribute('font-family', FONT);
  copy.setAttribute('fill', TEXT);
  return `${new XMLSerializer().serializeToString(copy)}\n`;
}

/** An <svg> of the page as a PNG blob, drawn from svgElementText() at the screen's pixel ratio (at least 2). */
export async function svgElementPng(element) {
  const width = Number(element.getAttribute('width'));
  const height = Number(element.getAttribute('height'));
  const ratio = Math.max(2, window.devicePixelRatio || 1);
  const url = URL.createObjectURL(new Blob([svgElementText(element)], { type: 'image/svg+xml' }));
  try {
    const image = new Image(width, height);
    image.src = url;
    await image.decode();
    const canvas = document.createElement('canvas');
    canvas.width = Math.round(width * ratio);
    canvas.height = Math.round(height * ratio);
    const context = canvas.getContext('2d');
    context.fillStyle = '#fff';
    context.fillRect(0, 0, canvas.width, canvas.height);
    context.drawImage(image, 0, 0, canvas.width, canvas.height);
    return await new Promise((resolve) => canvas.toBlob(resolve, 'image/png'));
  } finally {
    URL.revokeObjectURL(url);
  }
}

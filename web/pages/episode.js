// #/episodes/ID: a stored episode replayed — the map with every agent's path and the agents at the
// scrubber's time, events on the timeline, the chosen per-step series' plots whose cursor follows the
// scrubber (and hovering a plot moves it), the episode's metrics with units, and its trajectory and
// series as CSV; the server films it as a video on demand (runs/video.js). The address keeps the
// replay's moment and the series: #/episodes/ID?t=12.3&series=….
import { api } from '../lib/api.js';
import { h, loading, showError, errorPage, formatNumber, pageTitle } from '../lib/ui.js';
import { MapView, palette } from '../lib/map2d.js';
import { CATEGORY_NAMES, loadMetrics, withUnit, betterArrow, statusBadge, timePlot, PROXEMIC_BANDS } from '../lib/plots.js';
import { downloadLink } from '../lib/download.js';
import { showInAddress, listOf } from '../lib/hashquery.js';
import { checkPicker } from '../runs/picker.js';
import { videoExport } from '../runs/video.js';

const SPEEDS = [0.25, 0.5, 1, 2, 4, 10];
// Series plotted first, in this order; proxemic_zone is what the distance plot's bands show.
const SERIES_ORDER = ['distance_to_closest_person', 'robot_speed', 'time_to_collision', 'social_force_on_robot'];
const SERIES_SHOWN_AS_BANDS = 'proxemic_zone';
const SERIES_COLOURS = { distance_to_closest_person: '#2f6fd1', robot_speed: '#e07b18', time_to_collision: '#c0392b', social_force_on_robot: '#7d4fb8' };
// Where a series' y axis ends: a time to collision runs to days when nobody is on a collision course,
// and only its first seconds matter (longer ones are drawn at this height).
const SERIES_CLIPPED_ABOVE = { time_to_collision: 10 };
// The replay's time goes into the address once the scrubber rests (every frame would flood the history).
const ADDRESS_DELAY_MS = 300;

function eventTone(kind) {
  if (/contact|collision|error/.test(kind)) return 'bad';
  if (/request|answer|accept|drop/.test(kind)) return 'request';
  if (/goal|finished|completed/.test(kind)) return 'good';
  return 'plain';
}

function eventText(event) {
  const data = Object.entries(event.data ?? {}).map(([k, v]) => `${k} ${typeof v === 'number' ? formatNumber(v) : JSON.stringify(v)}`).join(', ');
  return `${event.kind} · ${event.subject}${data ? ` (${data})` : ''}`;
}

/** The index of the sample of `times` (ascending) closest to `time`. */
function nearest(times, time) {
  let lo = 0, hi = times.length - 1;
  while (lo < hi) {
    const mid = (lo + hi) >> 1;
    if (times[mid] < time) lo = mid + 1; else hi = mid;
  }
  return lo > 0 && time - times[lo - 1] < times[lo] - time ? lo - 1 : lo;
}

function metricsTables(episode, metrics) {
  const groups = new Map();
  for (const metric of metrics.items) {
    if (!(metric.key in episode.metrics)) continue;
    if (!groups.has(metric.category)) groups.set(metric.category, []);
    groups.get(metric.category).push(metric);
  }
  if (!groups.size) return h('p', { class: 'muted' }, 'No metrics: the episode ended in error.');
  return h('div', { class: 'episode-metrics' }, [...groups].map(([category, list]) => h('table', { class: 'compact' },
    h('caption', {}, CATEGORY_NAMES[category] ?? category),
    h('tbody', {}, list.map((metric) => {
      const value = episode.metrics[metric.key];
      const reason = episode.null_reasons?.[metric.key];
      return h('tr', { 'data-metric': metric.key },
        h('th', { scope: 'row', title: metric.description }, metric.key.replaceAll('_', ' '),
          value === null && reason ? h('span', { class: 'reason' }, reason) : null),
        h('td', { class: 'arrow' }, betterArrow(metric.better)),
        h('td', { class: 'number' }, value === null ? '—' : withUnit(value, metric.unit, { bool: 'word' })));
    })))));
}

export async function render(root, params, query) {
  const id = params.id;
  pageTitle(root, `Episode ${id.slice(0, 9)}`, id);
  const wait = loading(root, 'Loading the episode');
  let episode, trajectory, metrics;
  try {
    [episode, trajectory, metrics] = await Promise.all([
      api.get(`/api/v1/episodes/${encodeURIComponent(id)}`),
      api.get(`/api/v1/episodes/${encodeURIComponent(id)}/trajectory?format=json`),
      loadMetrics(),
    ]);
  } catch (error) {
    errorPage(root, `Episode ${id}`, error, { href: '#/runs', text: 'All runs' });
    return null;
  }
  wait.textContent = 'Loading the map and series…';

  const seriesNames = metrics.series.map((s) => s.name).filter((n) => n !== SERIES_SHOWN_AS_BANDS)
    .sort((a, b) => (SERIES_ORDER.indexOf(a) + 1 || 99) - (SERIES_ORDER.indexOf(b) + 1 || 99));
  const [worldResult, ...seriesResults] = await Promise.allSettled([
    api.get(`/api/v1/scenarios/${encodeURIComponent(episode.scenario)}/world`),
    ...seriesNames.map((name) => api.get(`/api/v1/episodes/${encodeURIComponent(id)}/series?name=${encodeURIComponent(name)}&format=json`)),
  ]);
  wait.remove();

  const video = videoExport(id);
  root.append(h('div', { class: 'episode-facts' },
    episode.run_id ? h('a', { href: `#/runs/${episode.run_id}` }, `← run ${episode.run_id.slice(0, 9)}`) : null,
    h('span', {}, `seed ${episode.seed}`), statusBadge(episode.status),
    h('span', {}, `ended by ${episode.termination.replaceAll('_', ' ')}`),
    h('span', {}, `${formatNumber(episode.sim_time)} s simulated (${episode.ticks.toLocaleString('en')} steps)`),
    h('span', {}, `controller ${episode.controller}`),
    h('span', { class: 'muted' }, `scenario ${episode.scenario}`),
    downloadLink(`/api/v1/episodes/${encodeURIComponent(id)}/trajectory?format=csv`, `${id}.csv`, 'Trajectory (CSV)'),
    h('button', { type: 'button', class: 'secondary', onclick: replayIn3d }, 'Replay in 3D'),
    video.toggle));
  const replayError = h('p', { class: 'message error', role: 'alert', hidden: true });
  root.append(replayError, video.panel);

  /** The episode again as a live session (the server replays it bit for bit), opened at the scrubber's moment. */
  async function replayIn3d(event) {
    event.target.disabled = true;
    try {
      const session = await api.post('/api/v1/sessions', { episode: id, unwatched_grace: 30 });
      const dt = episode.ticks > 0 ? episode.sim_time / episode.ticks : 0;
      const tick = dt > 0 ? Math.round((times[Number(scrubber.value)] ?? 0) / dt) : 0;
      location.hash = `#/sessions/${encodeURIComponent(session.id)}?tick=${tick}`;
    } catch (error) {
      event.target.disabled = false;
      replayError.hidden = false;
      replayError.textContent = `Could not open the replay: ${error.message}`;
    }
  }

  const agentIds = Object.keys(trajectory.agents);
  const longest = agentIds.reduce((best, a) => (trajectory.agents[a].length > (trajectory.agents[best]?.length ?? 0) ? a : best), agentIds[0]);
  const times = longest ? trajectory.agents[longest].map((s) => s.time) : [];

  // Map with faint full paths; the agents at the scrubber's time are redrawn in their own layer.
  const mapPanel = h('section', { class: 'panel replay', 'aria-labelledby': 'replay-title' }, h('h2', { id: 'replay-title' }, 'Replay'));
  const plotsPanel = h('section', { class: 'panel series', 'aria-labelledby': 'series-title' }, h('h2', { id: 'series-title' }, 'Series'));
  root.append(h('div', { class: 'episode-layout' }, mapPanel, plotsPanel));

  let view = null;
  let kinds = new Map();
  if (worldResult.status === 'fulfilled') {
    const world = worldResult.value;
    kinds = new Map(world.agents.map((a) => [a.id, a]));
    const mapBox = h('div', { class: 'map-box' });
    mapPanel.append(mapBox);
    view = new MapView(mapBox, world, { width: 600, maxHeight: 460, starts: false });
    for (const agent of agentIds) {
      const kind = kinds.get(agent)?.kind ?? 'human';
      const line = view.path(trajectory.agents[agent].map((s) => [s.x, s.y]),
        { colour: kind === 'robot' ? palette.robot : palette.human, width: kind === 'robot' ? 2 : 1.5, label: `${agent}'s path` });
      line.setAttribute('opacity', kind === 'robot' ? 0.55 : 0.3);
    }
    mapPanel.append(h('p', { class: 'legend muted small' },
      h('span', { class: 'swatch', style: `background:${palette.robot}` }), ' robot ',
      h('span', { class: 'swatch', style: `background:${palette.human}` }), ' people — faint lines: whole paths; discs: at the replay time.'));
  } else {
    const box = h('div');
    mapPanel.append(box);
    showError(box, new Error(`The scenario's map (${episode.scenario}) could not be loaded: ${worldResult.reason.message}`));
  }

  const drawAgents = (index) => {
    if (!view) return;
    view.layers.marks.replaceChildren();
    for (const agent of agentIds) {
      const samples = trajectory.agents[agent];
      const sample = samples[Math.min(index, samples.length - 1)];
      if (!sample) continue;
      const info = kinds.get(agent);
      const group = view.agent(sample.x, sample.y, sample.theta, info?.kind ?? 'human', info?.radius ?? 0.3, agent);
      group.dataset.agent = agent;
    }
  };

  // The timeline: play/pause, the scrubber with the events as ticks along its track, speed.
  const duration = times.length ? times[times.length - 1] : 0;
  const scrubber = h('input', { type: 'range', id: 'replay-time', min: 0, max: Math.max(times.length - 1, 0), step: 1, value: 0,
    'aria-label': 'Replay time', disabled: times.length < 2 });
  const playButton = h('button', { type: 'button', class: 'play', 'aria-label': 'Play', disabled: times.length < 2 }, '▶');
  const speed = h('select', { id: 'replay-speed' }, SPEEDS.map((s) => h('option', { value: s, selected: s === 1 }, `${s}×`)));
  const clock = h('output', { for: 'replay-time', class: 'clock', 'aria-live': 'off' });
  const ticks = h('div', { class: 'event-ticks', 'aria-hidden': 'true' });
  for (const event of episode.events) {
    const fraction = duration > 0 ? Math.min(event.time / duration, 1) : 0;
    ticks.append(h('span', { class: `event-tick ${eventTone(event.kind)}`, title: `${formatNumber(event.time)} s: ${eventText(event)}`,
      style: `left: calc(8px + (100% - 16px) * ${fraction})`, onclick: () => setIndex(nearest(times, event.time)) }));
  }
  mapPanel.append(h('div', { class: 'timeline' },
    h('div', { class: 'scrubber' }, scrubber, ticks),
    h('div', { class: 'controls' }, playButton, clock, h('label', { class: 'speed' }, 'Speed', speed),
      h('span', { class: 'muted small' }, 'Focus the slider: ← → step 0.1 s, Page Up/Down jump, Home/End.'))));
  if (!times.length) mapPanel.append(h('p', { class: 'message info' }, 'This episode stored no trajectory.'));

  // Plots of the chosen series, one each, sharing one cursor; the choice is the address's.
  let shownSeries = listOf(query, 'series', seriesNames).filter((name) => seriesNames.includes(name));
  let plots = [];
  const syncKey = `episode-${id}`;
  const plotsArea = h('div', { class: 'series-plots' });
  plotsPanel.append(checkPicker({ id: 'series-picker', legend: 'Series plotted',
    groups: [{ name: '', items: seriesNames.map((name) => ({ key: name, label: name.replaceAll('_', ' '), title: metrics.series.find((s) => s.name === name)?.description })) }],
    chosen: shownSeries,
    onChange: (names) => {
      shownSeries = names;
      showInAddress(`/episodes/${id}`, addressValues());
      drawSeries();
      setIndex(index);
    } }), plotsArea);
  const drawSeries = () => {
    for (const p of plots) p.destroy();
    plots = [];
    plotsArea.replaceChildren();
    for (const name of shownSeries) drawOneSeries(name, seriesResults[seriesNames.indexOf(name)]);
    if (!shownSeries.length) plotsArea.append(h('p', { class: 'muted' }, 'No series chosen.'));
  };
  const drawOneSeries = (name, result) => {
    const definition = metrics.series.find((s) => s.name === name);
    const figure = h('figure', { class: 'series-plot', 'data-series': name },
      h('figcaption', { class: 'muted small' }, definition?.description ?? ''));
    plotsArea.append(figure);
    if (result.status === 'rejected') {
      showError(figure, new Error(`${name}: ${result.reason.message}`));
      return;
    }
    const series = result.value.items[0];
    if (!series || !series.values.some((v) => v !== null)) {
      figure.prepend(h('p', { class: 'muted' }, `${name.replaceAll('_', ' ')}: no value in this episode`));
      return;
    }
    const csv = downloadLink(`/api/v1/episodes/${encodeURIComponent(id)}/series?name=${encodeURIComponent(name)}&format=csv`,
      `${id}-${name}.csv`, 'CSV', { class: 'button secondary series-csv', 'aria-label': `${name.replaceAll('_', ' ')} as CSV` });
    const seriesTimes = series.values.map((_, k) => k * series.dt);
    const bands = name === 'distance_to_closest_person' ? PROXEMIC_BANDS : null;
    const clipAbove = SERIES_CLIPPED_ABOVE[name] ?? null;
    plots.push(timePlot(figure, {
      times: seriesTimes, values: series.values, title: name.replaceAll('_', ' '), unit: series.unit,
      colour: SERIES_COLOURS[name] ?? '#2f6fd1', bands, clipAbove, syncKey,
      onHover: (time) => setIndex(nearest(times, time), 'plot'),
    }));
    if (clipAbove !== null) {
      figure.querySelector('figcaption').append(`. Clipped at ${formatNumber(clipAbove)} ${series.unit}: longer times are drawn at `
        + `${formatNumber(clipAbove)} ${series.unit}, the legend and the table give every value.`);
    }
    if (bands) {
      figure.append(h('p', { class: 'legend muted small' }, 'Shaded: Hall\'s zones — ',
        PROXEMIC_BANDS.flatMap((b) => [h('span', { class: 'swatch', style: `background:${b.colour.replace(/[\d.]+\)$/, '0.5)')}` }), ` ${b.name} < ${b.to} m `])));
    }
    figure.append(csv);
  };
  // Rewards come from a benchmark task: its episode_reward series is plotted above.
  const reward = episode.metrics.episode_reward;
  if (reward === null || reward === undefined) {
    plotsPanel.append(h('p', { class: 'message info reward-note' }, 'No reward: this scenario has no benchmark task.'));
  }

  const events = h('section', { 'aria-labelledby': 'events-title' }, h('h2', { id: 'events-title' }, `Events (${episode.events.length})`),
    episode.events.length ? h('ol', { class: 'events' }, episode.events.map((event) => h('li', { class: eventTone(event.kind) },
      h('button', { type: 'button', class: 'link', onclick: () => { setIndex(nearest(times, event.time)); scrubber.focus(); },
        'aria-label': `Go to ${formatNumber(event.time)} s` }, `${formatNumber(event.time)} s`),
      ' ', eventText(event))))
      : h('p', { class: 'muted' }, 'No events.'));
  const steps = episode.step_durations?.length ? h('section', { 'aria-labelledby': 'steps-title' }, h('h2', { id: 'steps-title' }, 'Choreography steps'),
    h('table', { class: 'compact steps' }, h('tbody', {}, episode.step_durations.map((s) => h('tr', {}, h('th', { scope: 'row' }, s.step),
      h('td', { class: 'number' }, `${formatNumber(s.duration)} s`)))))) : null;
  root.append(h('div', { class: 'episode-lower' }, events, steps),
    h('section', { 'aria-labelledby': 'metrics-title' }, h('h2', { id: 'metrics-title' }, 'Metrics'), metricsTables(episode, metrics)));

  let index = 0;
  let addressTimer = null;
  // The time to a tenth of a second, as the samples are at 10 Hz; the series when not all of them.
  function addressValues() {
    return { t: index > 0 ? String(Math.round(times[index] * 10) / 10) : null, series: shownSeries.length === seriesNames.length ? null : shownSeries };
  }
  function setIndex(next, source = 'code') {
    index = Math.max(0, Math.min(next, times.length - 1));
    clearTimeout(addressTimer);
    addressTimer = setTimeout(() => showInAddress(`/episodes/${id}`, addressValues(), { replace: true }), ADDRESS_DELAY_MS);
    if (source !== 'slider') scrubber.value = String(index);
    const time = times[index] ?? 0;
    const text = `${formatNumber(time, 2)} s of ${formatNumber(duration, 2)} s`;
    clock.value = text;
    scrubber.setAttribute('aria-valuetext', text);
    drawAgents(index);
    for (const p of plots) p.setMarker(time);
  }
  scrubber.addEventListener('input', () => setIndex(Number(scrubber.value), 'slider'));

  // Playback advances by wall time × speed, so it plays at the chosen speed whatever the frame rate.
  let frame = null;
  let last = null;
  let playTime = 0;
  const stop = () => {
    if (frame !== null) cancelAnimationFrame(frame);
    frame = null;
    playButton.textContent = '▶';
    playButton.setAttribute('aria-label', 'Play');
  };
  const tick = (now) => {
    playTime += ((now - (last ?? now)) / 1000) * Number(speed.value);
    last = now;
    setIndex(nearest(times, playTime));
    if (playTime >= duration) { stop(); return; }
    frame = requestAnimationFrame(tick);
  };
  playButton.addEventListener('click', () => {
    if (frame !== null) { stop(); return; }
    if (index >= times.length - 1) setIndex(0);
    playTime = times[index];
    last = null;
    playButton.textContent = '❚❚';
    playButton.setAttribute('aria-label', 'Pause');
    frame = requestAnimationFrame(tick);
  });
  // Hovering a plot while playing would fight the playback: the user's hand wins.
  scrubber.addEventListener('pointerdown', stop);
  scrubber.addEventListener('keydown', stop);

  drawSeries();
  setIndex(nearest(times, Number(query.get('t')) || 0));
  return () => {
    stop();
    clearTimeout(addressTimer);
    video.destroy();
    for (const p of plots) p.destroy();
  };
}

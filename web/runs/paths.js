// The comparison's map: the robot's paths in the first few episodes of the baseline and of one chosen
// run, overlaid on one map when both ran the same scenario snapshot, else each on its own.
import { api } from '../lib/api.js';
import { h, loading, showError } from '../lib/ui.js';
import { MapView } from '../lib/map2d.js';

const EPISODES_DRAWN = 5;

/** The first robot's path in the first few stored episodes of a run: [{seed, points}]. */
async function robotPaths(report, robotId) {
  const stored = report.episodes.filter((e) => e.episode_id).slice(0, EPISODES_DRAWN);
  const trajectories = await Promise.all(stored.map((e) => api.get(`/api/v1/episodes/${e.episode_id}/trajectory?format=json`)));
  return trajectories.map((t, i) => ({ seed: stored[i].seed, points: (t.agents[robotId] ?? []).map((s) => [s.x, s.y]) }))
    .filter((p) => p.points.length);
}

/** Draws `entries` ([{run: {report, label, colour}, dashed}]) on `world`'s map in `container`. */
async function drawPaths(container, world, entries) {
  const robot = world.agents.find((a) => a.kind === 'robot');
  if (!robot) {
    container.append(h('p', { class: 'message info' }, 'The scenario has no robot: there is no robot path to draw.'));
    return;
  }
  const view = new MapView(container, world, { width: entries.length > 1 ? 760 : 580, maxHeight: entries.length > 1 ? 520 : 420, starts: false });
  const legend = h('p', { class: 'legend small' });
  for (const { run, dashed } of entries) {
    const paths = await robotPaths(run.report, robot.id);
    for (const { seed, points } of paths) {
      view.path(points, { colour: run.colour, width: 2, dash: dashed ? '6 3' : null, label: `run ${run.label}, seed ${seed}` })
        .setAttribute('opacity', 0.75);
    }
    legend.append(h('span', { class: 'swatch', style: `background:${run.colour}` }),
      ` run ${run.label} (${paths.length} episode${paths.length === 1 ? '' : 's'}${dashed ? ', dashed' : ''}) `);
  }
  view.agent(robot.start.x, robot.start.y, robot.start.theta, 'robot', robot.radius, `${robot.id} at the start`);
  container.append(legend);
}

const world = (report) => api.get(`/api/v1/scenarios/${encodeURIComponent(report.scenario_record)}/world`);

/**
 * The section for `runs` ([{report, label, colour}], the baseline first) with the baseline and the run
 * whose id is `chosenId` drawn; `onChoose(id)` hears another choice (the section redraws itself).
 */
export function pathsSection(runs, chosenId, onChoose) {
  const [baseline, ...others] = runs;
  const select = h('select', { id: 'paths-run' }, others.map((run) => h('option', { value: run.report.id, selected: run.report.id === chosenId },
    `${run.label} ${run.report.id.slice(0, 9)}${run.report.name ? `: ${run.report.name}` : ''}`)));
  const area = h('div');
  const section = h('section', { class: 'panel compare-map', 'aria-labelledby': 'paths-title' },
    h('h2', { id: 'paths-title' }, `The robot's paths (first ${EPISODES_DRAWN} episodes of each run)`),
    others.length > 1 ? h('div', { class: 'field' }, h('label', { for: 'paths-run' }, `Drawn with the baseline ${baseline.label}`), select) : null,
    area);

  let drawing = 0;
  const draw = async () => {
    const current = ++drawing;
    const other = others.find((run) => run.report.id === select.value) ?? others[0];
    area.replaceChildren();
    const wait = loading(area, 'Loading the trajectories');
    try {
      if (baseline.report.scenario_record === other.report.scenario_record) {
        const box = h('div', { class: 'map-box' });
        const map = await world(baseline.report);
        if (current !== drawing) return;
        area.append(box);
        await drawPaths(box, map, [{ run: baseline, dashed: false }, { run: other, dashed: true }]);
      } else {
        const [a, b] = [baseline.report, other.report];
        const maps = await Promise.all([world(a), world(b)]);
        if (current !== drawing) return;
        area.append(h('p', { class: 'message info' }, a.scenario === b.scenario
          ? `Both runs are of ${a.scenario}, but the scenario changed between them (snapshots ${a.scenario_record} and ${b.scenario_record}): each is drawn on its own map.`
          : `The runs are of different scenarios (${a.scenario} and ${b.scenario}): each is drawn on its own map.`));
        const boxes = [baseline, other].map((run) => h('div', { class: 'map-box' }, h('h3', {}, `${run.label}: ${run.report.scenario}`)));
        area.append(h('div', { class: 'compare-sides' }, boxes));
        await drawPaths(boxes[0], maps[0], [{ run: baseline, dashed: false }]);
        await drawPaths(boxes[1], maps[1], [{ run: other, dashed: true }]);
      }
    } catch (error) {
      if (current === drawing) showError(area, error);
    } finally {
      wait.remove();
    }
  };
  select.addEventListener('change', () => {
    onChoose(select.value);
    draw();
  });
  draw();
  return section;
}

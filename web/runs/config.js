// What a run ran with, for the report and the comparison: the robot's controller as it was in effect
// (the scenario's own, or the scenario's with the run's changes over it), and the differences between
// runs' configurations, field by field.
import { h, formatNumber } from '../lib/ui.js';

/** A goal as a reader says it: "location kitchen" or "pose (17.5, 1.5)", with its radius when given. */
function goalText(goal) {
  const where = goal.location !== undefined ? `location ${goal.location}`
    : goal.pose ? `pose (${formatNumber(goal.pose.x)}, ${formatNumber(goal.pose.y)}${goal.pose.theta !== undefined ? `, θ ${formatNumber(goal.pose.theta)}` : ''})` : 'none';
  return goal.radius !== undefined ? `${where}, radius ${formatNumber(goal.radius)} m` : where;
}

/**
 * The controller the run's robot had: its type, goal and search parameters, and whether it is the
 * scenario's own. Runs stored before the effective controller was kept say only what was asked.
 */
export function controllerText(config) {
  const effective = config.effective_controller ?? config.controller;
  if (!effective) return config.controller === null ? "the scenario's own (the robot has none)" : '—';
  const parts = [effective.type ?? 'idle'];
  if (effective.goal) parts.push(`goal ${goalText(effective.goal)}`);
  else if (!['idle', 'teleop'].includes(effective.type)) parts.push('no goal');
  if (effective.person) parts.push(`person ${effective.person}`);
  if (effective.strategy) parts.push(`strategy ${effective.strategy}`);
  return `${parts.join('; ')}${config.controller ? '' : " (the scenario's own)"}`;
}

/** Every leaf of a JSON value by its JSON pointer (arrays of numbers and strings stay whole). */
function leaves(value, pointer = '', out = new Map()) {
  const whole = Array.isArray(value) && value.every((v) => v === null || typeof v !== 'object');
  if (value !== null && typeof value === 'object' && !whole && Object.keys(value).length) {
    for (const [key, child] of Object.entries(value)) leaves(child, `${pointer}/${String(key).replace(/~/g, '~0').replace(/\//g, '~1')}`, out);
  } else {
    out.set(pointer, value);
  }
  return out;
}

// Fields of a run's configuration that say where or when it ran, not what: not differences of setup.
const PROVENANCE = ['/git_commit', '/sharding'];

/** The configuration fields (JSON pointers) in which the runs differ, each with every run's value. */
export function configDifferences(configs) {
  const flat = configs.map((config) => leaves(config));
  const pointers = [...new Set(flat.flatMap((f) => [...f.keys()]))].sort();
  return pointers
    .filter((pointer) => !PROVENANCE.some((p) => pointer === p || pointer.startsWith(`${p}/`)))
    .filter((pointer) => new Set(flat.map((f) => JSON.stringify(f.has(pointer) ? f.get(pointer) : undefined))).size > 1)
    .map((pointer) => ({ pointer, values: flat.map((f) => f.get(pointer)) }));
}

const shown = (value) => (value === undefined ? '(absent)' : JSON.stringify(value));

/**
 * The section that says how the compared runs' setups differ: a row per differing field, a column per
 * run; and a warning when their controllers and scenarios are the same, so that a difference in their
 * metrics cannot come from the controller.
 */
export function configDiffSection(runs) {
  const configs = runs.map((r) => r.report.config);
  const differences = configDifferences(configs);
  const controllers = new Set(configs.map((c) => JSON.stringify(c.effective_controller ?? c.controller ?? null)));
  const scenarios = new Set(configs.map((c) => c.scenario_sha256));
  const same = controllers.size === 1 && scenarios.size === 1;
  return h('section', { 'aria-labelledby': 'config-title', class: 'config-diff' },
    h('h2', { id: 'config-title' }, 'Configurations'),
    same ? h('p', { class: 'message warn', role: 'note', id: 'config-same-controller' },
      'These runs ran the same scenario content with the same controller configuration: differences between them come from their seeds, '
      + 'time limits or requests, not from the controller.') : null,
    differences.length
      ? h('table', { class: 'config-differences' },
        h('thead', {}, h('tr', {}, h('th', { scope: 'col' }, 'Field'), runs.map((r) => h('th', { scope: 'col' }, `${r.label} ${r.report.id.slice(0, 9)}`)))),
        h('tbody', {}, differences.map((d) => h('tr', { 'data-pointer': d.pointer },
          h('th', { scope: 'row' }, h('code', {}, d.pointer)),
          d.values.map((v) => h('td', {}, h('code', {}, shown(v))))))))
      : h('p', { class: 'muted', id: 'config-no-differences' }, 'The runs\' configurations are the same in every field (their commits aside).'));
}

// The HSR benchmark's tasks (docs/benchmark.md) in words: what each asks of the robot, what one action
// is, and a scenario's task section (its name and the settings it gives) as one line.
import { h, formatNumber } from './ui.js';

const TASKS = {
  approach_human: { aim: 'drive up to a person', actions: 'a forward speed and a yaw rate' },
  approach_human_apartment: { aim: 'drive up to a person in a furnished apartment', actions: 'a forward speed and a yaw rate' },
  follow_human: { aim: 'follow a person who walks away', actions: 'a forward speed and a yaw rate' },
  pick_and_place: { aim: 'pick up an object and put it on a target', actions: 'a mode, a gripper command and 6 arm joint targets' },
  mirror_gesture: { aim: 'point to the side a person points to, as her mirror image', actions: '6 arm joint targets' },
};

/** What one action of the task is made of, in words; null for a task this page does not know. */
export function taskActions(name) {
  return TASKS[name]?.actions ?? null;
}

const LISTED = 3;

/** A setting's value in a few words: points as (x, y, z) m, boxes as from … to, long lists shortened. */
function settingText(value) {
  if (Array.isArray(value)) {
    const words = value.map(settingText);
    return value.length > LISTED ? `${value.length} (${words.slice(0, LISTED).join(', ')}, …)` : words.join(', ');
  }
  if (value && typeof value === 'object') {
    if ('x' in value && 'y' in value) return `(${['x', 'y', 'z'].filter((axis) => axis in value).map((axis) => formatNumber(value[axis])).join(', ')}) m`;
    if ('min' in value && 'max' in value) return `[${value.min.map((v) => formatNumber(v)).join(', ')}] to [${value.max.map((v) => formatNumber(v)).join(', ')}] m`;
    return Object.entries(value).map(([key, inner]) => `${key.replaceAll('_', ' ')} ${settingText(inner)}`).join(', ');
  }
  return typeof value === 'number' ? formatNumber(value) : String(value);
}

/** A scenario's `task` section: its name, what it asks, and each setting it gives (the rest are defaults). */
export function taskSummary(task) {
  const settings = Object.entries(task).filter(([key]) => key !== 'name');
  const aim = TASKS[task.name]?.aim;
  return [h('code', {}, task.name), aim ? `: ${aim}` : '',
    settings.length
      ? h('ul', { class: 'task-settings' }, settings.map(([key, value]) => h('li', { 'data-setting': key, title: Array.isArray(value) ? value.join(', ') : null },
        `${key.replaceAll('_', ' ')} ${settingText(value)}`)))
      : h('span', { class: 'muted' }, ' (every setting its default: docs/benchmark.md)')];
}

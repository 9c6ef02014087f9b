// A choice of several things to show (metrics to plot, series to draw) as checkboxes in groups, folded
// under a summary that says how many are chosen. The page keeps the choice in its address.
import { h } from '../lib/ui.js';
import { CATEGORY_NAMES } from '../lib/plots.js';

/**
 * `groups` [{name, items: [{key, label, title}]}] with `chosen` keys checked; `onChange(keys)` gets
 * the chosen keys after each change, in the order chosen (a new one last). `id` names the picker.
 */
export function checkPicker({ id, legend, groups, chosen, onChange }) {
  const picked = [...chosen];
  const summary = h('summary', {});
  const showCount = () => { summary.textContent = `${legend} (${picked.length} chosen)`; };
  const box = (item) => h('label', { class: 'check', title: item.title ?? null },
    h('input', { type: 'checkbox', value: item.key, checked: picked.includes(item.key),
      onchange: (event) => {
        if (event.target.checked) picked.push(item.key); else picked.splice(picked.indexOf(item.key), 1);
        showCount();
        onChange([...picked]);
      } }),
    item.label);
  showCount();
  return h('details', { class: `picker ${id}`, id },
    summary,
    groups.map((group) => h('fieldset', {},
      h('legend', { class: group.name ? null : 'visually-hidden' }, group.name || legend),
      group.items.map(box))));
}

/** The metrics of loadMetrics() as a picker's groups: one per category, in the list's order. */
export function metricGroups(metrics) {
  const groups = new Map();
  for (const metric of metrics.items) {
    if (!groups.has(metric.category)) groups.set(metric.category, { name: CATEGORY_NAMES[metric.category] ?? metric.category, items: [] });
    groups.get(metric.category).items.push({ key: metric.key, label: metric.key.replaceAll('_', ' '), title: metric.description });
  }
  return [...groups.values()];
}

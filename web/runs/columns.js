// The runs list's metric columns: which statistics of which metrics each run shows (the API's
// `metrics`), added from a choice of metric and statistic, removed one by one.
import { h } from '../lib/ui.js';
import { CATEGORY_NAMES } from '../lib/plots.js';
import { STATISTICS } from './gates.js';

const MAX_COLUMNS = 10;

/** The picker for `columns` (['success.mean', …]); `onChange(columns)` after each addition or removal. */
export function columnsPicker(columns, metrics, onChange) {
  const chosen = [...columns];
  const chips = h('ul', { class: 'column-chips', 'aria-label': 'Metric columns shown' });
  const metricSelect = h('select', { id: 'column-metric' });
  const groups = new Map();
  for (const metric of metrics.items) {
    if (!groups.has(metric.category)) groups.set(metric.category, h('optgroup', { label: CATEGORY_NAMES[metric.category] ?? metric.category }));
    groups.get(metric.category).append(h('option', { value: metric.key }, metric.key));
  }
  metricSelect.append(...groups.values());
  const statisticSelect = h('select', { id: 'column-statistic' }, STATISTICS.map((s) => h('option', { value: s }, s)));
  const add = h('button', { type: 'submit', class: 'secondary' }, 'Add the column');
  const note = h('span', { class: 'muted small', 'aria-live': 'polite' });

  const show = () => {
    chips.replaceChildren(...chosen.map((column) => h('li', {}, h('code', { class: 'chip' }, column,
      h('button', { type: 'button', class: 'link remove', 'aria-label': `Remove the column ${column}`,
        onclick: () => { chosen.splice(chosen.indexOf(column), 1); show(); onChange([...chosen]); } }, '×')))));
    if (!chosen.length) chips.append(h('li', { class: 'muted small' }, 'none'));
    add.disabled = chosen.length >= MAX_COLUMNS;
    note.textContent = chosen.length >= MAX_COLUMNS ? `At most ${MAX_COLUMNS} columns.` : '';
  };
  show();
  const form = h('form', { class: 'columns-picker', novalidate: true },
    chips,
    h('div', { class: 'row' },
      h('label', { for: 'column-metric' }, 'Metric', metricSelect),
      h('label', { for: 'column-statistic' }, 'Statistic', statisticSelect),
      add, note));
  form.addEventListener('submit', (event) => {
    event.preventDefault();
    const column = `${metricSelect.value}.${statisticSelect.value}`;
    if (chosen.includes(column)) {
      note.textContent = `${column} is shown already.`;
      return;
    }
    chosen.push(column);
    show();
    onChange([...chosen]);
  });
  return form;
}

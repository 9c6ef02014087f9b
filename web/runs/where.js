// The runs list's conditions on metrics (the API's `where`): one gate per line of the editor, such as
// collisions.max == 0, each checked against GET /api/v1/metrics before the list asks the server, its
// problem shown beside it. The server keeps the ended runs that meet every condition.
import { h } from '../lib/ui.js';
import { STATISTICS, gateProblem } from './gates.js';
import { field, setError } from './fields.js';

/**
 * The editor, filled with `conditions`; `onApply(conditions)` gets the conditions given (without
 * spaces; [] for none) once every one reads as a gate over a known metric (`metrics`: byKey).
 */
export function whereEditor(conditions, metrics, onApply) {
  const list = h('div', { class: 'where-rows' });
  let serial = 0;
  const rows = [];
  const renumber = () => rows.forEach((row, i) => { row.label.textContent = `Condition ${i + 1}`; });
  const addRow = (text = '') => {
    const input = h('input', { id: `where-${++serial}`, type: 'text', value: text, size: 30, spellcheck: 'false', autocomplete: 'off',
      placeholder: 'success.mean >= 0.9' });
    const row = field('Condition', input);
    row.label = row.wrapper.querySelector('label');
    const remove = h('button', { type: 'button', class: 'secondary remove', 'aria-label': 'Remove this condition',
      onclick: () => {
        rows.splice(rows.indexOf(row), 1);
        row.wrapper.remove();
        if (!rows.length) addRow();
        renumber();
      } }, '×');
    input.after(remove);
    rows.push(row);
    list.append(row.wrapper);
    renumber();
    return row;
  };
  for (const condition of conditions.length ? conditions : ['']) addRow(condition);

  const form = h('form', { class: 'where-editor', novalidate: true, 'aria-describedby': 'where-help' },
    h('p', { id: 'where-help', class: 'muted small' }, `Keep the ended runs whose aggregates meet every condition, each written as a gate: `
      + `metric.statistic OP number (statistics ${STATISTICS.join(', ')}; OP ==, !=, <, <=, >, >=).`),
    list,
    h('div', { class: 'row' },
      h('button', { type: 'button', class: 'secondary', onclick: () => addRow().control.focus() }, 'Add a condition'),
      h('button', { type: 'submit' }, 'Apply the conditions'),
      h('button', { type: 'button', class: 'secondary', onclick: () => {
        for (const row of rows.splice(0)) row.wrapper.remove();
        addRow();
        onApply([]);
      } }, 'Clear')));
  form.addEventListener('submit', (event) => {
    event.preventDefault();
    let problems = 0;
    for (const row of rows) {
      const text = row.control.value.trim();
      const problem = text ? gateProblem(text, metrics) : null;
      setError(row, problem);
      if (problem) problems++;
    }
    if (problems) {
      form.querySelector('[aria-invalid=true]').focus();
      return;
    }
    onApply(rows.map((row) => row.control.value.replace(/\s+/g, '')).filter(Boolean));
  });
  return form;
}

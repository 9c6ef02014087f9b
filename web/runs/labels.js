// A run's name, tags and notes on its report: shown as they are, and edited in place (PATCH
// /api/v1/runs/{id}) with every problem beside its field, the page's and the server's.
import { api } from '../lib/api.js';
import { h, showError } from '../lib/ui.js';
import { labelFields, listedProblems, tagChips } from './fields.js';

/** The panel for `report`; `onSaved(report)` gets the report the server answers with after an edit. */
export function labelsPanel(report, onSaved) {
  const panel = h('section', { class: 'panel run-labels', 'aria-labelledby': 'labels-title' });
  const title = () => h('h2', { id: 'labels-title' }, 'Name, tags and notes');
  const none = () => h('span', { class: 'muted' }, 'none');

  const show = () => {
    const editButton = h('button', { type: 'button', class: 'secondary', onclick: edit }, 'Edit the name, tags and notes');
    panel.replaceChildren(title(),
      h('dl', { class: 'facts' },
        h('dt', {}, 'Name'), h('dd', { class: 'run-label-name' }, report.name || none()),
        h('dt', {}, 'Tags'), h('dd', { class: 'run-label-tags' }, tagChips(report.tags) ?? none()),
        h('dt', {}, 'Notes'), h('dd', { class: 'run-label-notes notes' }, report.notes || none())),
      editButton);
    return editButton;
  };

  const edit = () => {
    const labels = labelFields('edit', report);
    const formError = h('div');
    const save = h('button', { type: 'submit' }, 'Save');
    const form = h('form', { class: 'labels-form', novalidate: true, 'aria-labelledby': 'labels-title' },
      title(),
      h('div', { class: 'fields' }, Object.values(labels.fields).map((f) => f.wrapper)),
      h('div', { class: 'row' }, save, h('button', { type: 'button', class: 'secondary', onclick: () => show().focus() }, 'Cancel')),
      formError);
    form.addEventListener('submit', async (event) => {
      event.preventDefault();
      formError.replaceChildren();
      const { body, problems } = labels.read();
      if (!problems) {
        save.disabled = true;
        try {
          report = await api.patch(`/api/v1/runs/${encodeURIComponent(report.id)}`, body);
          onSaved(report);
          show().focus();
          return;
        } catch (error) {
          const listed = listedProblems(error).filter((problem) => !labels.showProblem(problem.pointer ?? '', problem.message));
          if (listed.length || !listedProblems(error).length) showError(formError, error);
        } finally {
          save.disabled = false;
        }
      }
      form.querySelector('[aria-invalid=true]')?.focus();
    });
    panel.replaceChildren(form);
    labels.fields.name.control.focus();
  };

  show();
  return panel;
}

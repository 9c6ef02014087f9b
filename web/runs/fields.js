// Form fields of the runs pages with an error line under each, which the page fills with its own
// checks and with the API's objections (each JSON pointer beside its field); and a run's labels (name,
// tags, notes) as fields, shared by the form that starts a run and the report that edits them.
import { h } from '../lib/ui.js';

/** A labelled field with an error line under it. */
export function field(labelText, control, hint = null) {
  const error = h('span', { class: 'field-error', id: `${control.id}-error`, role: 'alert', hidden: true });
  control.setAttribute('aria-describedby', `${control.id}-error${hint ? ` ${control.id}-hint` : ''}`);
  const wrapper = h('div', { class: 'field' },
    h('label', { for: control.id }, labelText),
    control,
    hint ? h('span', { class: 'hint muted', id: `${control.id}-hint` }, hint) : null,
    error);
  return { wrapper, control, error };
}

/** Shows `message` under the field (null: clears it), and marks the control invalid. */
export function setError(f, message) {
  f.error.replaceChildren();
  f.error.hidden = !message;
  if (message) f.control.setAttribute('aria-invalid', 'true');
  else f.control.removeAttribute('aria-invalid');
  if (message) f.error.append(h('span', {}, message));
}

/** Adds `message` under the field, after any already there. */
export function appendError(f, message) {
  if (f.error.hidden) return setError(f, message);
  f.error.append(h('br'), h('span', {}, message));
  return null;
}

/** The API's objections of a 400 as [{pointer, message}] (one problem without a list: itself). */
export function listedProblems(error) {
  if (error.details?.errors) return error.details.errors;
  return error.details?.pointer ? [{ pointer: error.details.pointer, message: error.message }] : [];
}

// The server's limits on a run's labels (POST and PATCH /api/v1/runs).
const NAME_BYTES = 200;
const NOTES_BYTES = 20000;
const MAX_TAGS = 32;
const TAG_BYTES = 64;
const bytes = (text) => new TextEncoder().encode(text).length;

/** "baseline, dwa  night" → ['baseline', 'dwa', 'night']: words between commas and spaces, each once. */
export function parseTags(text) {
  return [...new Set(text.split(/[\s,]+/).filter(Boolean))];
}

/**
 * A run's name, tags and notes as three fields (ids `${prefix}-name`, …) filled with `run`'s; `read()`
 * gives {body, problems} (problems: how many the page found, each shown beside its field) and
 * `showProblem(pointer, message)` puts one of the API's beside its field (false when none is its).
 */
export function labelFields(prefix, run = { name: '', tags: [], notes: '' }) {
  const name = field('Name', h('input', { id: `${prefix}-name`, name: 'name', type: 'text', value: run.name, size: 28, autocomplete: 'off' }), 'optional');
  const tags = field('Tags', h('input', { id: `${prefix}-tags`, name: 'tags', type: 'text', value: run.tags.join(' '), size: 22, autocomplete: 'off',
    spellcheck: 'false' }), 'words, separated by spaces or commas');
  const notes = field('Notes', h('textarea', { id: `${prefix}-notes`, name: 'notes', rows: 3, cols: 40 }, run.notes), 'optional');
  const fields = { name, tags, notes };
  const read = () => {
    for (const f of Object.values(fields)) setError(f, null);
    let problems = 0;
    const problem = (f, message) => { appendError(f, message); problems++; };
    const body = { name: name.control.value.trim(), tags: parseTags(tags.control.value), notes: notes.control.value };
    if (bytes(body.name) > NAME_BYTES) problem(name, `a name is at most ${NAME_BYTES} bytes (this one is ${bytes(body.name)})`);
    if (body.tags.length > MAX_TAGS) problem(tags, `at most ${MAX_TAGS} tags (these are ${body.tags.length})`);
    for (const tag of body.tags.filter((t) => bytes(t) > TAG_BYTES)) problem(tags, `the tag "${tag.slice(0, 20)}…" is longer than ${TAG_BYTES} bytes`);
    if (bytes(body.notes) > NOTES_BYTES) problem(notes, `notes are at most ${NOTES_BYTES.toLocaleString('en')} bytes (these are ${bytes(body.notes).toLocaleString('en')})`);
    return { body, problems };
  };
  const showProblem = (pointer, message) => {
    const key = Object.keys(fields).find((k) => pointer === `/${k}` || pointer.startsWith(`/${k}/`));
    if (!key) return false;
    appendError(fields[key], message);
    return true;
  };
  return { fields, read, showProblem };
}

/** A run's tags as small buttons that show the runs with that tag (the runs list's filter). */
export function tagChips(tags, onTag = (tag) => { location.hash = `#/runs?tag=${encodeURIComponent(tag)}`; }) {
  if (!tags.length) return null;
  return h('span', { class: 'tags' }, tags.map((tag) => h('button', { type: 'button', class: 'chip tag', title: `Show the runs tagged ${tag}`,
    onclick: () => onTag(tag) }, tag)));
}

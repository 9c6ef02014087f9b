// The scenario catalogue (#/): every scenario the server holds as a card with its thumbnail, searched
// and filtered in the page, uploads deleted from their cards, and an upload form that shows the
// server's errors at their lines.
import { api, authorisedUrl } from '../lib/api.js';
import { h, loading, showError, formatNumber, pageTitle } from '../lib/ui.js';
import { recentUploads, recentDeletions, deleteUpload, deletedText } from './scenario.js';

/** Every scenario summary, following `next_cursor` through the pages. */
async function allScenarios() {
  const items = [];
  let cursor = null;
  do {
    const page = await api.get(`/api/v1/scenarios?limit=200${cursor ? `&cursor=${encodeURIComponent(cursor)}` : ''}`);
    items.push(...page.items);
    cursor = page.next_cursor;
  } while (cursor);
  return items;
}

const FORMATS = { json: 'JSON', imhus_xml: 'IMHuS XML', pedsim_xml: 'Pedsim XML', hunav_yaml: 'HuNavSim YAML' };

function robotsText(robots) {
  if (!robots.length) return 'no robot';
  return robots.map((robot) => `${robot.id} (${robot.model ?? 'disc'})`).join(', ');
}

/** A scenario's card; an upload's has a Delete button, which calls `onDelete(scenario)`. */
function card(scenario, onDelete) {
  const link = `#/scenarios/${encodeURIComponent(scenario.id)}`;
  const image = h('img', { alt: `${scenario.name} from above at its start`, width: 320, height: 240, loading: 'lazy', decoding: 'async' });
  // A scenario whose picture cannot be drawn (an upload this server no longer compiles) says so in place.
  const missing = () => image.replaceWith(h('div', { class: 'sc-thumb-missing' }, 'No picture'));
  image.addEventListener('error', missing, { once: true });
  authorisedUrl(`/api/v1/scenarios/${encodeURIComponent(scenario.id)}/thumbnail`).then((source) => { image.src = source; }, missing);
  const facts = [
    ['Humans', formatNumber(scenario.humans)],
    ['Robots', robotsText(scenario.robots)],
    ['Task', scenario.task ?? '—'],
    ['Duration', `${formatNumber(scenario.duration)} s`],
    ['Steps', formatNumber(scenario.steps)],
  ];
  return h('article', { class: 'sc-scenario-card panel', 'data-id': scenario.id },
    h('div', { class: 'sc-thumb' }, image),
    h('h2', {}, h('a', { href: link, class: 'sc-card-link' }, scenario.name)),
    scenario.id !== scenario.name ? h('p', { class: 'sc-card-id muted' }, scenario.id) : null,
    h('p', { class: 'sc-card-description', title: scenario.description }, scenario.description || 'No description.'),
    h('dl', { class: 'sc-card-facts' }, facts.flatMap(([term, value]) => [h('dt', {}, term), h('dd', {}, value)])),
    h('p', { class: 'sc-card-badges' },
      h('span', { class: `badge ${scenario.origin === 'uploaded' ? 'warn' : 'good'}` }, scenario.origin),
      ' ', h('span', { class: 'badge' }, FORMATS[scenario.format] ?? scenario.format),
      scenario.origin === 'uploaded' ? h('button', { type: 'button', class: 'secondary danger sc-card-delete', 'aria-label': `Delete ${scenario.name}`,
        onclick: () => onDelete(scenario) }, 'Delete') : null));
}

// ---------------------------------------------------------------------------------------------------
// JSON pointers → lines of the uploaded text

function escapePointer(key) {
  return String(key).replaceAll('~', '~0').replaceAll('/', '~1');
}

/**
 * The line (1-based) of every value in a JSON text, by its JSON pointer: a member's line is that of its
 * key, an array element's that of its first character. Tolerant: on a syntax error it keeps what it read
 * up to there.
 */
export function jsonPointerLines(text) {
  const lines = new Map([['', 1]]);
  let i = 0, line = 1;
  const blank = () => {
    while (i < text.length) {
      const c = text[i];
      if (c === '\n') line++;
      else if (c !== ' ' && c !== '\t' && c !== '\r' && c !== '\uFEFF') return;
      i++;
    }
  };
  const string = () => {
    let out = '';
    i++;  // the opening quote
    while (i < text.length && text[i] !== '"') {
      if (text[i] === '\n') line++;
      if (text[i] === '\\' && i + 1 < text.length) {
        const e = text[++i];
        if (e === 'u') { out += String.fromCharCode(parseInt(text.slice(i + 1, i + 5), 16) || 0); i += 4; }
        else out += { n: '\n', t: '\t', r: '\r', b: '\b', f: '\f' }[e] ?? e;
      } else {
        out += text[i];
      }
      i++;
    }
    i++;  // the closing quote
    return out;
  };
  const value = (path, depth) => {
    blank();
    if (!lines.has(path)) lines.set(path, line);
    if (depth > 512) throw new Error('too deep');
    const c = text[i];
    if (c === '{') {
      i++;
      for (;;) {
        blank();
        if (i >= text.length) return;
        if (text[i] === '}') { i++; return; }
        if (text[i] === ',') { i++; continue; }
        if (text[i] !== '"') throw new Error('key expected');
        const keyLine = line;
        const child = `${path}/${escapePointer(string())}`;
        lines.set(child, keyLine);
        blank();
        if (text[i] === ':') i++;
        value(child, depth + 1);
      }
    } else if (c === '[') {
      i++;
      let index = 0;
      for (;;) {
        blank();
        if (i >= text.length) return;
        if (text[i] === ']') { i++; return; }
        if (text[i] === ',') { i++; continue; }
        value(`${path}/${index++}`, depth + 1);
      }
    } else if (c === '"') {
      string();
    } else {
      const start = i;
      while (i < text.length && !/[\s,\]}]/.test(text[i])) i++;
      if (i === start) throw new Error('value expected');
    }
  };
  try { value('', 0); } catch { /* keep the lines read so far */ }
  return lines;
}

/** Where an issue of the server lies in the uploaded text: {line, exact} or null when it cannot be placed. */
function locate(issue, pointerLines) {
  if (Number.isInteger(issue.line)) return { line: issue.line, exact: true };
  // A JSON syntax error has an empty pointer and names its line in the message.
  const syntax = /at line (\d+)/.exec(issue.message ?? '');
  if (syntax && !issue.pointer) return { line: Number(syntax[1]), exact: true };
  if (!pointerLines || issue.pointer === undefined) return null;
  let pointer = issue.pointer;
  // A missing member (a required key) is placed at the nearest enclosing value that exists.
  while (!pointerLines.has(pointer)) pointer = pointer.slice(0, Math.max(pointer.lastIndexOf('/'), 0));
  return { line: pointerLines.get(pointer), exact: pointer === issue.pointer };
}

/**
 * The uploaded text with numbered lines, each error and warning shown under the line it concerns, and a
 * list of them all whose entries scroll to their place.
 */
function sourceReport(text, isJson, errors, warnings) {
  const pointerLines = isJson ? jsonPointerLines(text) : null;
  const textLines = text.split(/\r?\n/);
  const issues = [...errors.map((issue) => ({ ...issue, kind: 'error' })), ...warnings.map((issue) => ({ ...issue, kind: 'warning' }))]
    .map((issue) => {
      const place = isJson || Number.isInteger(issue.line) ? locate(issue, pointerLines) : null;
      return { ...issue, place: place && place.line <= textLines.length ? place : null };
    });
  const byLine = new Map();
  for (const issue of issues) {
    if (!issue.place) continue;
    if (!byLine.has(issue.place.line)) byLine.set(issue.place.line, []);
    byLine.get(issue.place.line).push(issue);
  }
  const view = h('div', { class: 'sc-source-view', tabindex: 0, role: 'region', 'aria-label': 'Uploaded source with its errors at their lines' });
  const notes = [];
  textLines.forEach((content, index) => {
    const number = index + 1;
    const here = byLine.get(number) ?? [];
    const kind = here.some((issue) => issue.kind === 'error') ? 'error' : here.length ? 'warning' : '';
    view.append(h('div', { class: `sc-source-line ${kind}`, 'data-line': number },
      h('span', { class: 'sc-source-number', 'aria-hidden': 'true' }, number), h('code', {}, content || ' ')));
    for (const issue of here) {
      const note = h('div', { class: `sc-source-note ${issue.kind}`, 'data-line': number, tabindex: -1 },
        h('strong', {}, issue.kind === 'error' ? 'Error' : 'Warning'), issue.pointer ? ` at ${issue.pointer}` : '',
        issue.place.exact ? '' : ' (missing here or near here)', ': ', issue.message);
      notes.push([issue, note]);
      view.append(note);
    }
  });
  const list = h('ol', { class: 'sc-issue-list' }, issues.map((issue) => {
    const entry = notes.find(([candidate]) => candidate === issue);
    const where = issue.place
      ? h('button', { type: 'button', class: 'secondary sc-issue-jump', 'aria-label': `Show line ${issue.place.line}`,
        onclick: () => { entry[1].scrollIntoView({ block: 'center' }); entry[1].focus(); } }, `line ${issue.place.line}`)
      : h('span', { class: 'muted' }, Number.isInteger(issue.line) ? `line ${issue.line}, past the end` : isJson ? 'not in the text' : 'in the imported JSON');
    return h('li', {},
      h('span', { class: `badge ${issue.kind === 'error' ? 'bad' : 'warn'}` }, issue.kind), ' ',
      issue.pointer ? [h('code', {}, issue.pointer), ' '] : null, where, ' ', h('span', {}, issue.message));
  }));
  return h('div', { class: 'sc-source-report' }, list, view);
}

/** Scrolls a source report's view (not the page) to its first note, once the report is in the page. */
function revealFirstNote(report) {
  const view = report.querySelector('.sc-source-view');
  const note = view.querySelector('.sc-source-note');
  if (note) view.scrollTop = Math.max(0, note.offsetTop - view.offsetTop - view.clientHeight / 3);
}

// ---------------------------------------------------------------------------------------------------
// Upload

function uploadForm() {
  let fileText = null;  // the chosen file byte for byte, until the text box is edited
  const file = h('input', { type: 'file', accept: '.json,.xml,.yaml,.yml,application/json,application/xml,text/xml,application/yaml', id: 'upload-file' });
  const textBox = h('textarea', { id: 'upload-text', rows: 8, spellcheck: 'false', placeholder: '{ "name": …, "world": …, "humans": … }, <IMHuS/Pedsim XML> or a HuNavSim agents YAML' });
  const format = h('select', { id: 'upload-format' },
    h('option', { value: '' }, 'auto'), h('option', { value: 'json' }, 'json'), h('option', { value: 'imhus' }, 'imhus (IMHuS XML)'),
    h('option', { value: 'pedsim' }, 'pedsim (Pedsim XML)'), h('option', { value: 'hunav' }, 'hunav (HuNavSim YAML)'));
  const upload = h('button', { type: 'submit' }, 'Upload');
  const validate = h('button', { type: 'button', class: 'secondary' }, 'Validate only');
  const result = h('div', { class: 'sc-upload-result', 'aria-live': 'polite' });

  file.addEventListener('change', async () => {
    const chosen = file.files[0];
    if (!chosen) return;
    fileText = await chosen.text();
    textBox.value = fileText;
  });
  textBox.addEventListener('input', () => { fileText = null; });

  const source = () => fileText ?? textBox.value;
  const isJsonText = (text) => format.value === 'json' || (!format.value && /^[{[]/.test(text.trimStart()));
  // What the server reads the text as when no format is chosen: XML by '<', JSON by '{' or '[', else YAML.
  const contentType = (text) => {
    if (isJsonText(text)) return 'application/json';
    if (format.value === 'hunav' || (!format.value && !text.trimStart().startsWith('<'))) return 'application/yaml';
    return 'application/xml';
  };

  async function send(path) {
    const text = source();
    result.replaceChildren();
    if (!text.trim()) {
      result.append(h('p', { class: 'message error', role: 'alert' }, 'Choose a file or paste a scenario first.'));
      return null;
    }
    const json = isJsonText(text);
    const query = format.value ? `?format=${format.value}` : '';
    upload.disabled = validate.disabled = true;
    const wait = loading(result, path.endsWith('validate') ? 'Validating' : 'Uploading');
    try {
      return { text, json, reply: await api.post(path + query, text, { 'content-type': contentType(text) }) };
    } catch (error) {
      const errors = error.details?.errors;
      if (error.status === 400 && Array.isArray(errors)) {
        const report = sourceReport(text, (error.details.format ?? (json ? 'json' : 'xml')) === 'json', errors, []);
        result.append(h('p', { class: 'message error', role: 'alert' },
          `Not stored: ${errors.length} error${errors.length === 1 ? '' : 's'} in the ${FORMATS[error.details.format] ?? 'uploaded'} scenario, shown at their lines below.`),
        report);
        revealFirstNote(report);
      } else {
        showError(result, error);
      }
      return null;
    } finally {
      wait.remove();
      upload.disabled = validate.disabled = false;
    }
  }

  const form = h('form', { class: 'sc-upload-form', 'aria-label': 'Upload a scenario', onsubmit: async (event) => {
    event.preventDefault();
    const sent = await send('/api/v1/scenarios');
    if (!sent) return;
    const { summary, warnings, existed } = sent.reply;
    recentUploads.set(summary.id, { warnings, existed });
    result.append(h('p', { class: 'message info', role: 'status' },
      existed ? `Already uploaded as ${summary.id} (“${summary.name}”); opening it…` : `Stored “${summary.name}” as ${summary.id}; opening it…`));
    location.hash = `#/scenarios/${encodeURIComponent(summary.id)}`;
  } },
  h('div', { class: 'fields' },
    h('label', { for: 'upload-file' }, 'Scenario file (.json, .xml, .yaml)', file),
    h('label', { for: 'upload-format' }, 'Format', format)),
  h('label', { for: 'upload-text', class: 'sc-upload-text-label' }, 'or paste its text', textBox),
  h('div', { class: 'row sc-upload-actions' }, upload, validate),
  result);

  validate.addEventListener('click', async () => {
    const sent = await send('/api/v1/scenarios/validate');
    if (!sent) return;
    const verdict = sent.reply;
    const json = sent.json && verdict.format === 'json';
    const summary = verdict.summary;
    result.append(h('p', { class: `message ${verdict.valid ? 'info' : 'error'}`, role: verdict.valid ? 'status' : 'alert' },
      verdict.valid
        ? `Valid ${FORMATS[verdict.format] ?? verdict.format}: “${summary.name}”, ${summary.humans} human${summary.humans === 1 ? '' : 's'}, ${robotsText(summary.robots)}, ${summary.steps} steps, ${formatNumber(summary.duration)} s. Not stored.`
        : `Not valid: ${verdict.errors.length} error${verdict.errors.length === 1 ? '' : 's'}, shown at their lines below.`));
    if (verdict.errors.length || verdict.warnings.length) {
      const report = sourceReport(sent.text, json, verdict.errors, verdict.warnings);
      result.append(report);
      revealFirstNote(report);
    }
  });
  return form;
}

// ---------------------------------------------------------------------------------------------------
// The page

export async function render(root) {
  pageTitle(root, 'Scenarios', 'Choreographed situations of people around robots. Open one to see its map and steps, start a live session or run it in batch.');
  const uploadPanel = h('details', { class: 'panel sc-upload-panel' },
    h('summary', {}, 'Upload a scenario (native JSON, IMHuS XML or Pedsim XML)'), uploadForm());
  const notice = h('div', { class: 'sc-notice', 'aria-live': 'polite' });
  root.append(uploadPanel, notice);
  for (const [id, { name, outcome }] of recentDeletions) {
    recentDeletions.delete(id);
    notice.append(h('p', { class: 'message info', role: 'status' }, deletedText(name, outcome)));
  }
  const wait = loading(root, 'Loading scenarios');
  let scenarios;
  try {
    scenarios = await allScenarios();
  } catch (error) {
    wait.remove();
    showError(root, error);
    return;
  }
  wait.remove();

  const search = h('input', { type: 'search', id: 'scenario-search', placeholder: 'name, description or id' });
  const origin = h('select', { id: 'scenario-origin' },
    h('option', { value: '' }, 'all'), h('option', { value: 'bundled' }, 'bundled'), h('option', { value: 'uploaded' }, 'uploaded'));
  const robot = h('select', { id: 'scenario-robot' },
    h('option', { value: '' }, 'any'), h('option', { value: 'yes' }, 'with a robot'), h('option', { value: 'model' }, 'with a robot model'),
    h('option', { value: 'no' }, 'without a robot'));
  const minHumans = h('input', { type: 'number', id: 'scenario-min-humans', min: 0, step: 1, inputmode: 'numeric' });
  const maxHumans = h('input', { type: 'number', id: 'scenario-max-humans', min: 0, step: 1, inputmode: 'numeric' });
  const count = h('p', { class: 'sc-scenario-count muted', role: 'status', 'aria-live': 'polite' });
  const empty = h('p', { class: 'message info', hidden: true }, 'No scenario matches these filters.');
  const cards = scenarios.map((scenario) => ({ scenario, element: card(scenario, remove) }));
  const grid = h('div', { class: 'sc-scenario-grid' }, cards.map((entry) => entry.element));

  const filter = () => {
    const words = search.value.toLowerCase().split(/\s+/).filter(Boolean);
    const low = minHumans.value === '' ? -Infinity : Number(minHumans.value);
    const high = maxHumans.value === '' ? Infinity : Number(maxHumans.value);
    let shown = 0;
    for (const { scenario, element } of cards) {
      const haystack = `${scenario.name} ${scenario.description} ${scenario.id}`.toLowerCase();
      const visible = words.every((word) => haystack.includes(word))
        && (!origin.value || scenario.origin === origin.value)
        && (!robot.value || (robot.value === 'yes' ? scenario.robots.length > 0
          : robot.value === 'model' ? scenario.robots.some((r) => r.model) : scenario.robots.length === 0))
        && scenario.humans >= low && scenario.humans <= high;
      element.hidden = !visible;
      if (visible) shown++;
    }
    count.textContent = `${shown} of ${cards.length} scenarios`;
    empty.hidden = shown > 0;
  };
  for (const control of [search, origin, robot, minHumans, maxHumans]) control.addEventListener('input', filter);

  async function remove(scenario) {
    notice.replaceChildren();
    let outcome;
    try {
      outcome = await deleteUpload(scenario);
      if (!outcome) return;
    } catch (error) {
      showError(notice, error);
      return;
    }
    const at = cards.findIndex((entry) => entry.scenario === scenario);
    cards[at].element.remove();
    cards.splice(at, 1);
    filter();
    notice.append(h('p', { class: 'message info', role: 'status' }, deletedText(scenario.name, outcome)));
  }

  root.append(
    h('form', { class: 'sc-scenario-filters panel', role: 'search', 'aria-label': 'Filter scenarios', onsubmit: (event) => event.preventDefault() },
      h('div', { class: 'fields' },
        h('label', { for: 'scenario-search', class: 'sc-grow' }, 'Search', search),
        h('label', { for: 'scenario-origin' }, 'Origin', origin),
        h('label', { for: 'scenario-robot' }, 'Robot', robot),
        h('label', { for: 'scenario-min-humans' }, 'Humans, at least', minHumans),
        h('label', { for: 'scenario-max-humans' }, 'Humans, at most', maxHumans)),
      count),
    empty, grid);
  filter();
}

// #/runs: the runs newest first (filters, paging, two chosen for a comparison) and a form that starts
// a run, with the API's objections shown next to the field each JSON pointer names.
import { api } from '../lib/api.js';
import { h, loading, showError, scrollBox, formatNumber, pageTitle } from '../lib/ui.js';
import { statusBadge, verdictBadge } from '../lib/plots.js';

const STATUSES = ['queued', 'running', 'finished', 'failed', 'cancelled', 'interrupted'];
const PAGE_SIZE = 20;
const CONTROLLERS = [
  ['scenario', "the scenario's own"],
  ['idle', 'idle (stands still)'],
  ['goal', 'goal (A* path, pure pursuit, blind to people)'],
  ['social', 'social (yields to people)'],
  ['dwa', 'dwa (Dynamic Window Approach)'],
  ['orca', 'orca (ORCA, the robot avoids alone)'],
  ['social_force', 'social_force (HuNavSim\'s social force)'],
];
/** The controllers that drive: to a goal when given one, else along the choreography's goto actions. */
const DRIVING = ['goal', 'social', 'dwa', 'orca', 'social_force'];

/** Every scenario the server holds (paging through the list). */
async function allScenarios() {
  const scenarios = [];
  let cursor = null;
  do {
    const reply = await api.get(`/api/v1/scenarios?limit=100${cursor ? `&cursor=${encodeURIComponent(cursor)}` : ''}`);
    scenarios.push(...reply.items);
    cursor = reply.items.length ? reply.next_cursor : null;
  } while (cursor);
  return scenarios;
}

const STATISTICS = ['count', 'nulls', 'mean', 'std', 'min', 'max', 'ci95_low', 'ci95_high'];
const GATE = /^([A-Za-z0-9_]+)\.([A-Za-z0-9_]+)\s*(==|!=|<=|>=|<|>)\s*(-?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)$/;
const MAX_SEED = 9007199254740990;

/** What is wrong with one gate's text (null: nothing the page can tell; the server knows the metrics). */
function gateProblem(text) {
  const gate = GATE.exec(text);
  if (!gate) return `"${text}" is not metric.statistic OP number, e.g. collisions.max == 0`;
  if (!STATISTICS.includes(gate[2])) return `unknown statistic '${gate[2]}' (${STATISTICS.join(', ')})`;
  return null;
}

/** An integer field's problem: empty, not a number, not whole or out of [low, high]; null when fine. */
function integerProblem(input, name, low, high, { optional = false } = {}) {
  if (input.validity.badInput) return `${name} must be a number`;
  if (input.value.trim() === '') return optional ? null : `give ${name}`;
  const value = Number(input.value);
  if (!Number.isInteger(value) || value < low || value > high) return `${name} must be a whole number from ${low.toLocaleString('en')} to ${high.toLocaleString('en')}`;
  return null;
}

/** "1,2,5", "1-20" or a mix ("1-3, 7") → seeds; throws with a message for anything else. */
function parseSeeds(text) {
  const seeds = [];
  for (const part of text.split(',').map((p) => p.trim()).filter(Boolean)) {
    const range = /^(\d+)\s*-\s*(\d+)$/.exec(part);
    if (range) {
      const [from, to] = [Number(range[1]), Number(range[2])];
      if (to < from) throw new Error(`the range ${part} runs backwards`);
      if (to - from >= 100000) throw new Error(`the range ${part} has more than 100,000 seeds`);
      for (let seed = from; seed <= to; seed++) seeds.push(seed);
    } else if (/^\d+$/.test(part)) {
      seeds.push(Number(part));
    } else {
      throw new Error(`"${part}" is neither a seed nor a range like 1-20`);
    }
  }
  if (!seeds.length) throw new Error('give at least one seed, e.g. 1,2,5 or 1-20');
  return seeds;
}

/** A labelled field with an error line under it that the form fills from the API's pointers. */
function field(labelText, control, hint = null) {
  const error = h('span', { class: 'field-error', id: `${control.id}-error`, role: 'alert', hidden: true });
  control.setAttribute('aria-describedby', `${control.id}-error${hint ? ` ${control.id}-hint` : ''}`);
  const wrapper = h('div', { class: 'field' },
    h('label', { for: control.id }, labelText),
    control,
    hint ? h('span', { class: 'hint muted', id: `${control.id}-hint` }, hint) : null,
    error);
  return { wrapper, control, error };
}

function startForm(scenarios, preselected) {
  const scenarioSelect = h('select', { id: 'run-scenario', name: 'scenario', required: true },
    scenarios.map((s) => h('option', { value: s.id, selected: s.id === preselected }, `${s.name} (${s.id})`)));
  const seedMode = h('select', { id: 'run-seed-mode', name: 'seed-mode' },
    h('option', { value: 'count' }, 'a count from a first seed'), h('option', { value: 'list' }, 'a list or range'));
  const count = h('input', { id: 'run-count', name: 'count', type: 'number', min: 1, max: 100000, value: 5, required: true });
  const firstSeed = h('input', { id: 'run-first-seed', name: 'first_seed', type: 'number', min: 0, value: 0 });
  const seedList = h('input', { id: 'run-seeds', name: 'seeds', type: 'text', placeholder: '1,2,5 or 1-20', size: 14 });
  const controller = h('select', { id: 'run-controller', name: 'controller' }, CONTROLLERS.map(([value, text]) => h('option', { value }, text)));
  const goal = h('select', { id: 'run-goal', name: 'goal' });
  const maxTime = h('input', { id: 'run-max-time', name: 'max_time', type: 'number', min: 0.1, step: 'any', placeholder: 'scenario’s', size: 8 });
  const gates = h('textarea', { id: 'run-gates', name: 'gates', rows: 3, cols: 34, spellcheck: 'false',
    placeholder: 'collisions.max == 0\nsuccess.mean >= 0.9' });
  const fields = {
    scenario: field('Scenario', scenarioSelect),
    seedMode: field('Seeds as', seedMode),
    count: field('Count', count),
    first_seed: field('First seed', firstSeed),
    seeds: field('Seeds', seedList, 'e.g. 1,2,5 or 1-20'),
    controller: field('Robot controller', controller),
    goal: field('Goal location', goal),
    max_time: field('Time limit (s)', maxTime, 'optional'),
    gates: field('Gates, one per line', gates, 'metric.statistic OP number'),
  };
  const formError = h('div', { class: 'form-error' });
  const submit = h('button', { type: 'submit' }, 'Start the run');
  const controllerNote = h('p', { class: 'muted small', id: 'run-controller-note' });
  const form = h('form', { class: 'panel run-form', 'aria-labelledby': 'start-run-title', novalidate: true },
    h('h2', { id: 'start-run-title' }, 'Start a run'),
    h('div', { class: 'fields' }, fields.scenario.wrapper, fields.seedMode.wrapper, fields.count.wrapper, fields.first_seed.wrapper,
      fields.seeds.wrapper, fields.controller.wrapper, fields.goal.wrapper, fields.max_time.wrapper, fields.gates.wrapper),
    controllerNote,
    h('div', { class: 'row' }, submit, h('span', { class: 'muted small' },
      `Gates: statistic ${STATISTICS.join(', ')}; OP ==, !=, <, <=, >, >=.`)),
    formError);

  const showSeedMode = () => {
    const list = seedMode.value === 'list';
    fields.count.wrapper.hidden = list;
    fields.first_seed.wrapper.hidden = list;
    fields.seeds.wrapper.hidden = !list;
  };
  seedMode.addEventListener('change', showSeedMode);
  showSeedMode();

  // Goal locations come from the scenario's world; another controller needs a robot with a model.
  let worldRequest = 0;
  const showController = () => { fields.goal.wrapper.hidden = !DRIVING.includes(controller.value); };
  const loadScenario = async () => {
    const scenario = scenarios.find((s) => s.id === scenarioSelect.value);
    const robot = scenario?.robots?.[0];
    controllerNote.textContent = !robot ? 'This scenario has no robot: only its own controller applies.'
      : !robot.model ? `The robot "${robot.id}" has no model: the server accepts another controller only for a robot with one.` : '';
    const request = ++worldRequest;
    goal.replaceChildren(h('option', { value: '' }, 'loading locations…'));
    try {
      const world = await api.get(`/api/v1/scenarios/${encodeURIComponent(scenarioSelect.value)}/world`);
      if (request !== worldRequest) return;
      goal.replaceChildren(h('option', { value: '' }, "none (the choreography's goto actions)"),
        ...world.locations.map((l) => h('option', { value: l.name }, l.name)));
      setError(fields.goal, null);
    } catch (error) {
      if (request !== worldRequest) return;
      goal.replaceChildren(h('option', { value: '' }, 'no locations'));
      setError(fields.goal, `locations unavailable: ${error.message}`);
    }
  };
  controller.addEventListener('change', showController);
  scenarioSelect.addEventListener('change', loadScenario);
  showController();
  if (scenarios.length) loadScenario();

  // Gates' indexes in the request → their line in the text box, for /gates/N pointers.
  let gateLines = [];
  const clearErrors = () => {
    for (const f of Object.values(fields)) setError(f, null);
    formError.replaceChildren();
  };
  const errorAt = (pointer, message) => {
    const gate = /^\/gates\/(\d+)/.exec(pointer);
    if (gate) return appendError(fields.gates, `line ${gateLines[Number(gate[1])] ?? Number(gate[1]) + 1}: ${message}`);
    if (/^\/controller\/goal/.test(pointer) && !fields.goal.wrapper.hidden) return appendError(fields.goal, message);
    const key = ['scenario', 'seeds', 'count', 'first_seed', 'controller', 'max_time', 'gates'].find((k) => pointer === `/${k}` || pointer.startsWith(`/${k}/`));
    if (key && !fields[key].wrapper.hidden) return appendError(fields[key], message);
    formError.append(h('div', { class: 'message error', role: 'alert' }, pointer ? `${pointer}: ${message}` : message));
    return null;
  };

  /** The request the form asks for, and every problem the page can see in it, each beside its field. */
  const readForm = () => {
    const body = { scenario: scenarioSelect.value };
    let problems = 0;
    const problem = (f, message) => { if (message) { appendError(f, message); problems++; } };
    if (!scenarioSelect.value) problem(fields.scenario, 'choose a scenario');
    if (seedMode.value === 'list') {
      try { body.seeds = parseSeeds(seedList.value); } catch (error) { problem(fields.seeds, error.message); }
    } else {
      problem(fields.count, integerProblem(count, 'the count', 1, 100000));
      problem(fields.first_seed, integerProblem(firstSeed, 'the first seed', 0, MAX_SEED, { optional: true }));
      body.count = Number(count.value);
      if (firstSeed.value !== '') body.first_seed = Number(firstSeed.value);
    }
    if (controller.value !== 'scenario') {
      body.controller = { type: controller.value };
      if (DRIVING.includes(controller.value) && goal.value) body.controller.goal = { location: goal.value };
    }
    if (maxTime.validity.badInput || (maxTime.value.trim() !== '' && !(Number(maxTime.value) > 0))) {
      problem(fields.max_time, 'the time limit must be a number of seconds above 0 (or empty: the scenario\'s)');
    }
    if (maxTime.value.trim() !== '') body.max_time = Number(maxTime.value);
    gateLines = [];
    body.gates = [];
    gates.value.split('\n').forEach((line, i) => {
      if (!line.trim()) return;
      const gateError = gateProblem(line.trim());
      if (gateError) problem(fields.gates, `line ${i + 1}: ${gateError}`);
      body.gates.push(line.trim());
      gateLines.push(i + 1);
    });
    return { body, problems };
  };

  form.addEventListener('submit', async (event) => {
    event.preventDefault();
    clearErrors();
    const { body, problems } = readForm();
    if (problems) {
      form.querySelector('[aria-invalid=true]')?.focus();
      return;
    }
    submit.disabled = true;
    submit.textContent = 'Starting…';
    try {
      const run = await api.post('/api/v1/runs', body);
      location.hash = `#/runs/${run.id}`;
    } catch (error) {
      const listed = error.details?.errors ?? (error.details?.pointer ? [{ pointer: error.details.pointer, message: error.message }] : []);
      if (listed.length) for (const problem of listed) errorAt(problem.pointer ?? '', problem.message);
      else errorAt('', error.message);
      form.querySelector('[aria-invalid=true]')?.focus();
    } finally {
      submit.disabled = false;
      submit.textContent = 'Start the run';
    }
  });
  return form;
}

function setError(f, message) {
  f.error.replaceChildren();
  f.error.hidden = !message;
  if (message) f.control.setAttribute('aria-invalid', 'true');
  else f.control.removeAttribute('aria-invalid');
  if (message) f.error.append(h('span', {}, message));
}

function appendError(f, message) {
  if (f.error.hidden) return setError(f, message);
  f.error.append(h('br'), h('span', {}, message));
  return null;
}

function runRow(run, chosen, onChoose) {
  const done = run.progress.finished + run.progress.error;
  const verdict = verdictBadge(run.verdict, run.status);
  const gatesCell = h('span', { class: 'failing-gates' }, run.verdict.complete && !run.verdict.passed ? run.verdict.reasons.join('; ') : '');
  const box = h('input', { type: 'checkbox', checked: chosen.includes(run.id), 'aria-label': `Compare run ${run.id}`, onchange: (e) => onChoose(run.id, e.target.checked) });
  return {
    row: h('tr', {},
      h('td', {}, box),
      // The accessible name starts with the visible text (voice control users say what they see).
      h('td', {}, h('a', { href: `#/runs/${run.id}`, class: 'run-id', title: run.id, 'aria-label': `${run.id.slice(0, 9)}: run ${run.id}` }, run.id.slice(0, 9))),
      h('td', {}, statusBadge(run.status)),
      h('td', {}, run.scenario),
      h('td', {}, run.controller),
      h('td', { class: 'number' }, `${done} / ${run.progress.total}`),
      h('td', { class: 'number' }, run.success_rate === null ? '—' : `${formatNumber(run.success_rate * 100, 2)} %`),
      h('td', {}, verdict, ' ', gatesCell),
      h('td', {}, h('time', { datetime: run.created_at }, new Date(run.created_at).toLocaleString('en-GB')))),
    gatesCell,
  };
}

export async function render(root, params, query) {
  pageTitle(root, 'Runs', 'Batches of headless episodes: their progress, metrics and gate verdicts.');
  const wait = loading(root, 'Loading scenarios');
  let scenarios = [];
  try {
    scenarios = await allScenarios();
  } catch (error) {
    showError(root, error);
  } finally {
    wait.remove();
  }
  root.append(startForm(scenarios, query.get('scenario')));

  const statusFilter = h('select', { id: 'filter-status' }, h('option', { value: '' }, 'any'), STATUSES.map((s) => h('option', { value: s }, s)));
  const scenarioFilter = h('select', { id: 'filter-scenario' }, h('option', { value: '' }, 'any'), scenarios.map((s) => h('option', { value: s.id }, s.id)));
  const compareButton = h('button', { type: 'button', class: 'secondary', disabled: true }, 'Compare the two chosen');
  const compareHint = h('span', { class: 'muted small', 'aria-live': 'polite' }, 'Choose two runs: the first is the baseline (A).');
  const firstButton = h('button', { type: 'button', class: 'secondary', disabled: true }, 'First page');
  const nextButton = h('button', { type: 'button', class: 'secondary', disabled: true }, 'Next page');
  const listArea = h('div', { class: 'runs-list' });
  root.append(
    h('h2', {}, 'Runs, newest first'),
    h('div', { class: 'row filters' },
      h('div', { class: 'field' }, h('label', { for: 'filter-status' }, 'Status'), statusFilter),
      h('div', { class: 'field' }, h('label', { for: 'filter-scenario' }, 'Scenario'), scenarioFilter),
      h('div', { class: 'compare-choice' }, compareButton, compareHint)),
    listArea,
    h('div', { class: 'row paging' }, firstButton, nextButton));

  const chosen = [];
  const onChoose = (id, on) => {
    const at = chosen.indexOf(id);
    if (on && at < 0) chosen.push(id);
    if (!on && at >= 0) chosen.splice(at, 1);
    compareButton.disabled = chosen.length !== 2;
    compareHint.textContent = chosen.length === 2 ? `A ${chosen[0].slice(0, 9)} vs B ${chosen[1].slice(0, 9)}`
      : chosen.length > 2 ? 'Choose only two runs.' : 'Choose two runs: the first is the baseline (A).';
  };
  compareButton.addEventListener('click', () => { location.hash = `#/compare/${chosen[0]}/${chosen[1]}`; });

  let cursor = null;
  let timer = null;
  let generation = 0;
  const load = async ({ quiet = false } = {}) => {
    clearTimeout(timer);
    const current = ++generation;
    const search = new URLSearchParams({ limit: String(PAGE_SIZE) });
    if (statusFilter.value) search.set('status', statusFilter.value);
    if (scenarioFilter.value) search.set('scenario', scenarioFilter.value);
    if (cursor) search.set('cursor', cursor);
    const wait = quiet ? null : loading(listArea, 'Loading runs');
    let reply;
    try {
      reply = await api.get(`/api/v1/runs?${search}`);
    } catch (error) {
      wait?.remove();
      listArea.replaceChildren();
      showError(listArea, error);
      return;
    }
    if (current !== generation) return;
    wait?.remove();
    firstButton.disabled = !cursor;
    nextButton.disabled = !reply.next_cursor;
    nextButton.onclick = () => { cursor = reply.next_cursor; load(); };
    if (!reply.items.length) {
      listArea.replaceChildren(h('p', { class: 'message info' }, cursor ? 'No more runs.' : 'No runs yet: start one above.'));
      return;
    }
    const rows = reply.items.map((run) => ({ run, ...runRow(run, chosen, onChoose) }));
    // A refresh replaces the table: keep the keyboard focus on the same control.
    const focused = listArea.contains(document.activeElement) ? document.activeElement.getAttribute('aria-label') : null;
    listArea.replaceChildren(scrollBox(h('table', { class: 'runs-table' },
      h('thead', {}, h('tr', {}, ['Compare', 'Run', 'Status', 'Scenario', 'Controller', 'Episodes done', 'Success', 'Verdict', 'Created']
        .map((title, i) => h('th', { scope: 'col', class: i === 5 || i === 6 ? 'number' : null }, title)))),
      h('tbody', {}, rows.map((r) => r.row))), 'Runs'));
    if (focused) listArea.querySelector(`[aria-label="${CSS.escape(focused)}"]`)?.focus();
    // Keep the progress of unfinished runs current.
    if (reply.items.some((run) => run.status === 'queued' || run.status === 'running')) timer = setTimeout(() => load({ quiet: true }), 2000);
  };
  firstButton.addEventListener('click', () => { cursor = null; load(); });
  statusFilter.addEventListener('change', () => { cursor = null; load(); });
  scenarioFilter.addEventListener('change', () => { cursor = null; load(); });
  await load();
  return () => { clearTimeout(timer); generation++; };
}

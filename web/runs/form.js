// The form that starts a run on #/runs: scenario, seeds, controller and goal, time limit, gates, and the
// run's name, tags and notes. Every problem the page can see is shown beside its field at once before
// anything is sent, and so is each of the API's objections (by JSON pointer).
import { api } from '../lib/api.js';
import { h } from '../lib/ui.js';
import { STATISTICS, gateProblem } from './gates.js';
import { field, setError, appendError, listedProblems, labelFields } from './fields.js';

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


/** A scenario robot's goal as the form offers it. */
function ownGoalText(goal) {
  const where = goal.location !== undefined ? goal.location : goal.pose ? `pose (${goal.pose.x}, ${goal.pose.y})` : 'as written';
  return goal.radius !== undefined ? `${where}, within ${goal.radius} m` : where;
}

/** Every scenario the server holds (paging through the list). */
export async function allScenarios() {
  const scenarios = [];
  let cursor = null;
  do {
    const reply = await api.get(`/api/v1/scenarios?limit=100${cursor ? `&cursor=${encodeURIComponent(cursor)}` : ''}`);
    scenarios.push(...reply.items);
    cursor = reply.items.length ? reply.next_cursor : null;
  } while (cursor);
  return scenarios;
}

const MAX_SEED = 9007199254740990;

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

/** The form that starts a run of one of `scenarios` (`preselected` chosen); a started run's report opens. */
export function startForm(scenarios, preselected) {
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
  const labels = labelFields('run');
  const formError = h('div', { class: 'form-error' });
  const submit = h('button', { type: 'submit' }, 'Start the run');
  const controllerNote = h('p', { class: 'muted small', id: 'run-controller-note' });
  const form = h('form', { class: 'panel run-form', 'aria-labelledby': 'start-run-title', novalidate: true },
    h('h2', { id: 'start-run-title' }, 'Start a run'),
    h('div', { class: 'fields' }, fields.scenario.wrapper, fields.seedMode.wrapper, fields.count.wrapper, fields.first_seed.wrapper,
      fields.seeds.wrapper, fields.controller.wrapper, fields.goal.wrapper, fields.max_time.wrapper, fields.gates.wrapper),
    h('div', { class: 'fields' }, Object.values(labels.fields).map((f) => f.wrapper)),
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
      const id = encodeURIComponent(scenarioSelect.value);
      const [world, document] = await Promise.all([api.get(`/api/v1/scenarios/${id}/world`), api.get(`/api/v1/scenarios/${id}`)]);
      if (request !== worldRequest) return;
      // The scenario's own goal is the default: the server keeps it when only the type changes.
      const own = document.robots?.[0]?.controller?.goal;
      goal.replaceChildren(
        // The two choices that are not locations say what they are in data-kind (a location may have any name).
        own ? h('option', { value: '', 'data-kind': 'own' }, `the scenario's own: ${ownGoalText(own)}`) : null,
        h('option', { value: '', 'data-kind': 'none' }, "none (the choreography's goto actions)"),
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
    if (labels.showProblem(pointer, message)) return null;
    formError.append(h('div', { class: 'message error', role: 'alert' }, pointer ? `${pointer}: ${message}` : message));
    return null;
  };

  /** The request the form asks for, and every problem the page can see in it, each beside its field. */
  const readForm = () => {
    const labelled = labels.read();
    const body = { scenario: scenarioSelect.value, ...labelled.body };
    let problems = labelled.problems;
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
      // Only what changes is sent: the server keeps the rest of the scenario's controller.
      body.controller = { type: controller.value };
      const kind = goal.selectedOptions[0]?.dataset.kind ?? 'location';
      if (DRIVING.includes(controller.value) && kind === 'none') body.controller.goal = null;
      else if (DRIVING.includes(controller.value) && kind === 'location' && goal.value) body.controller.goal = { location: goal.value };
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
      const listed = listedProblems(error);
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

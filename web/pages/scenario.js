// One scenario (#/scenarios/ID): its facts, its map with what is on it, its choreography as a timeline
// (one row per agent, one column per step), starting a live session or a batch run of it, and deleting
// an upload.
import { api } from '../lib/api.js';
import { h, loading, errorPage, showError, formatNumber, pageTitle } from '../lib/ui.js';
import { MapView, palette } from '../lib/map2d.js';
import { taskSummary } from '../lib/tasks.js';
import { routinesOf, routineOf } from '../lib/routines.js';

/** Scenarios uploaded from the catalogue in this page's life, with their warnings and whether they existed, shown once on arrival. */
export const recentUploads = new Map();
/** Uploads deleted from their own page, id → {name, outcome}, said once by the catalogue. */
export const recentDeletions = new Map();
/** A session started here ends this long (s) after its last tab closed (or after its start, if no tab opens it). */
export const UNWATCHED_GRACE_S = 30;

const number = (value, unit) => `${formatNumber(value)} ${unit}`;
// To the centimetre: imported files carry rounding noise (7.96e-4 m) nobody means.
const centimetres = (value) => formatNumber(Math.round(value * 100) / 100 + 0);
const point = (x, y) => `(${centimetres(x)}, ${centimetres(y)}) m`;

/** The kind of an action: its one key besides who acts. */
function actionKind(action) {
  return Object.keys(action).find((key) => key !== 'agent' && key !== 'group') ?? 'unknown';
}

/** An action in a few words: "goto kitchen", "wait 2 s", "motion wave". */
function actionText(action) {
  const kind = actionKind(action);
  const a = action[kind];
  switch (kind) {
    case 'goto':
      if (a.location) return `goto ${a.location}${a.offset ? ` + ${point(a.offset.x ?? 0, a.offset.y ?? 0)}` : ''}`;
      if (a.social_space) return `goto ${a.social_space} (social space)`;
      if (a.pose) return `goto ${point(a.pose.x, a.pose.y)}${a.radius ? ` ± ${number(a.radius, 'm')}` : ''}`;
      break;
    case 'wait':
      if (a.duration !== undefined) return `wait ${number(a.duration, 's')}`;
      return `wait until ${a.topic} = “${a.message}”`;
    case 'look_at':
      if (a.angle !== undefined) return `look at ${number(a.angle, 'rad')}`;
      return `look at ${a.agent ?? a.location}`;
    case 'turn':
      return a.by !== undefined ? `turn by ${number(a.by, 'rad')}` : `turn to ${number(a.to, 'rad')}`;
    case 'publish':
      return `publish “${a.message}” on ${a.topic}`;
    case 'routine':
    case 'task':  // the former name
      return `routine ${a}`;
    case 'form_group':
      return `form group ${a.group} (${(a.members ?? []).join(', ')})`;
    case 'dismantle_group':
      return `dismantle group ${a}`;
    case 'harass':
      return `harass ${a.robot} for ${number(a.duration, 's')}${a.distance ? ` at ${number(a.distance, 'm')}` : ''}`;
    case 'stop_and_look':
      return `stop and look at ${a.robot} for ${number(a.duration, 's')}${a.distance ? ` within ${number(a.distance, 'm')}` : ''}`;
    case 'request':
      return `request ${routineOf(a)}`;
    case 'motion':
      return `motion ${a.name}${a.duration !== undefined ? ` ${number(a.duration, 's')}` : ''}`;
    default:
      break;
  }
  return `${kind} ${JSON.stringify(a)}`;
}

function actionItem(action, routines) {
  const kind = actionKind(action);
  const item = h('li', { class: `sc-action sc-action-${kind}` }, actionText(action));
  // A routine is spelled out under its name, so a row reads as the agent's whole part.
  const routine = routines[routineOf(action)];
  if ((kind === 'routine' || kind === 'task') && Array.isArray(routine)) {
    item.append(h('ol', { class: 'sc-routine-actions' }, routine.map((inner) => h('li', { class: `sc-action sc-action-${actionKind(inner)}` }, actionText(inner)))));
  }
  return item;
}

/** The choreography as a table: a row per agent (and group), a column per step, the actions in order in each cell. */
function timeline(doc, world) {
  const steps = doc.steps ?? [];
  const routines = routinesOf(doc);
  const rows = world.agents.map((agent) => ({ key: `agent:${agent.id}`, label: agent.id, kind: agent.kind }));
  const known = new Set(rows.map((row) => row.key));
  const addRow = (key, label, kind) => {
    if (!known.has(key)) { known.add(key); rows.push({ key, label, kind }); }
  };
  for (const name of Object.keys(doc.groups ?? {})) addRow(`group:${name}`, name, 'group');
  for (const step of steps) {
    for (const action of step.actions ?? []) {
      if (action.group) addRow(`group:${action.group}`, action.group, 'group');
      else if (action.agent) addRow(`agent:${action.agent}`, action.agent, 'unknown');
    }
  }
  const members = (name) => doc.groups?.[name]?.members
    ?? steps.flatMap((step) => step.actions ?? []).find((action) => action.form_group?.group === name)?.form_group.members ?? [];
  if (!steps.length) return h('p', { class: 'muted' }, 'No steps: the humans stand where they start.');
  const table = h('table', { class: 'sc-timeline', 'aria-describedby': 'sc-timeline-note' },
    h('thead', {}, h('tr', {}, h('th', { scope: 'col', class: 'sc-timeline-agent' }, 'Agent'),
      steps.map((step, index) => h('th', { scope: 'col' }, h('span', { class: 'sc-step-number' }, `${index + 1}.`), ' ', step.name)))),
    h('tbody', {}, rows.map((row) => h('tr', { class: `sc-row-${row.kind}`, 'data-agent': row.label },
      h('th', { scope: 'row', class: 'sc-timeline-agent' },
        h('span', { class: `sc-agent-dot ${row.kind}`, 'aria-hidden': 'true' }), row.label,
        h('span', { class: 'muted sc-agent-kind' }, row.kind === 'group' ? ` group of ${members(row.label).join(', ') || '?'}` : row.kind === 'unknown' ? ' not in the scenario' : ` ${row.kind}`)),
      steps.map((step) => {
        const mine = (step.actions ?? []).filter((action) => (row.kind === 'group' ? action.group === row.label && !action.agent : action.agent === row.label));
        return h('td', { class: mine.length ? '' : 'idle' }, mine.length ? h('ol', { class: 'sc-actions' }, mine.map((action) => actionItem(action, routines))) : '');
      })))));
  return [h('p', { class: 'muted sc-timeline-note', id: 'sc-timeline-note' },
    'Steps run in order, left to right; in a step every agent starts at once and runs its own actions top to bottom.'),
  h('div', { class: 'sc-timeline-scroll', tabindex: 0, role: 'region', 'aria-label': 'Choreography timeline' }, table)];
}

function routinesSection(doc) {
  const parts = [];
  const routines = Object.entries(routinesOf(doc));
  if (routines.length) {
    parts.push(h('h3', {}, 'Routines'), h('table', { class: 'sc-routines' },
      h('thead', {}, h('tr', {}, h('th', { scope: 'col' }, 'Routine'), h('th', { scope: 'col' }, 'Actions, in order'))),
      h('tbody', {}, routines.map(([name, actions]) => h('tr', {}, h('th', { scope: 'row' }, name),
        h('td', {}, h('ol', { class: 'sc-actions inline' }, actions.map((action) => h('li', { class: `sc-action sc-action-${actionKind(action)}` }, actionText(action))))))))));
  }
  if ((doc.async ?? []).length) {
    parts.push(h('p', {}, h('strong', {}, 'Answers to robot requests: '),
      'the closest idle human within 3 m of the robot performs ', doc.async.map(routineOf).join(', '), '.'));
  }
  if ((doc.requests ?? []).length) {
    parts.push(h('p', {}, h('strong', {}, 'Scripted robot requests: '),
      doc.requests.map((request) => `${routineOf(request)} at ${number(request.time, 's')}${request.robot ? ` by ${request.robot}` : ''}`).join('; '), '.'));
  }
  return parts;
}

function legend(world) {
  const swatch = (colour, shape) => h('span', { class: `sc-swatch ${shape}`, style: `--swatch: ${colour}`, 'aria-hidden': 'true' });
  const entries = [
    [palette.wall, 'box', 'wall'], [palette.obstacle, 'box', 'obstacle'], [palette.door, 'bar', 'door'],
    [palette.location, 'ring', 'location'], [palette.space, 'dashed', 'social space (dots: slots)'],
    [palette.human, 'disc', 'human at its start'], [palette.robot, 'disc', 'robot at its start'],
    ...(world.objects.length ? [[palette.object, 'box', 'movable object at its start']] : []),
  ];
  return h('ul', { class: 'sc-map-legend', 'aria-label': 'Map legend' }, entries.map(([colour, shape, text]) => h('li', {}, swatch(colour, shape), text)));
}

/** A movable object's shape in words: "box 0.3 × 0.2 × 0.02 m", "cylinder, radius 0.035 m, 0.1 m long". */
function shapeText(shape) {
  if (shape.kind === 'box') return `box ${shape.size.map((size) => formatNumber(size)).join(' × ')} m`;
  const radius = `radius ${formatNumber(shape.radius)} m`;
  return shape.kind === 'sphere' ? `sphere, ${radius}` : `${shape.kind}, ${radius}, ${formatNumber(shape.length)} m long`;
}

/**
 * Asks whether to delete the upload `summary` ({id, name}), then does: 'deleted', 'unlisted' (runs ran
 * it), or null when the user said no (the API's error is thrown).
 */
export async function deleteUpload({ id, name }) {
  if (!confirm(`Delete the uploaded scenario “${name}” (${id})?`)) return null;
  return (await api.delete(`/api/v1/scenarios/${encodeURIComponent(id)}`)).outcome;
}

/** What a deletion did: an upload runs ran is only out of the list (docs/api.md, Uploading a scenario). */
export const deletedText = (name, outcome) => (outcome === 'unlisted'
  ? `“${name}” is no longer listed. Runs used it, so it is kept for their reports and replays; uploading it again lists it again.`
  : `Deleted “${name}”.`);

function table(caption, headings, rows) {
  if (!rows.length) return null;
  return h('table', { class: 'sc-world-table' }, h('caption', {}, caption),
    h('thead', {}, h('tr', {}, headings.map(([text, numeric]) => h('th', { scope: 'col', class: numeric ? 'number' : '' }, text)))),
    h('tbody', {}, rows.map((cells) => h('tr', {}, cells.map((cell, index) => h(index === 0 ? 'th' : 'td', { scope: index === 0 ? 'row' : undefined,
      class: headings[index][1] ? 'number' : '' }, cell))))));
}

function worldLists(world) {
  const furniture = world.obstacles.filter((obstacle) => !obstacle.name.startsWith('wall '));
  const walls = world.obstacles.length - furniture.length;
  const elevatorOf = (door) => world.elevators.find((elevator) => elevator.doors.includes(door))?.name ?? '—';
  const f = (value) => formatNumber(value);
  return h('div', { class: 'sc-world-lists', tabindex: 0, role: 'region', 'aria-label': 'What is on the map' },
    table('Agents at their start', [['Agent'], ['Kind'], ['x, m', true], ['y, m', true], ['θ, rad', true], ['Radius, m', true]],
      world.agents.map((agent) => [agent.id, agent.kind === 'robot' ? `robot (${agent.model ?? 'disc'})` : `human${agent.type ? ` (${agent.type})` : ''}`,
        f(agent.start.x), f(agent.start.y), f(agent.start.theta), f(agent.radius)])),
    table('Movable objects at their start', [['Name'], ['Shape'], ['x, m', true], ['y, m', true], ['z, m', true], ['Mass, kg', true]],
      world.objects.map((object) => [object.name, shapeText(object.shape), f(object.pose.x), f(object.pose.y), f(object.pose.z), f(object.mass)])),
    table('Locations', [['Name'], ['x, m', true], ['y, m', true], ['θ, rad', true], ['Radius, m', true]],
      world.locations.map((location) => [location.name, f(location.x), f(location.y), f(location.theta), f(location.radius)])),
    table('Social spaces', [['Name'], ['Centre x, m', true], ['Centre y, m', true], ['Slots', true]],
      world.social_spaces.map((space) => [space.name, f(space.centre.x), f(space.centre.y), f(space.slots.length)])),
    table('Doors', [['Name'], ['From'], ['To'], ['Elevator'], ['At start']],
      world.doors.map((door) => [door.name, point(...door.from), point(...door.to), elevatorOf(door.name), door.initially_open ? 'open' : 'closed'])),
    table(`Obstacles${walls ? ` (and ${walls} wall${walls === 1 ? '' : 's'})` : ''}`, [['Name'], ['Height, m', true], ['Mesh']],
      furniture.map((obstacle) => [obstacle.name, f(obstacle.height), obstacle.mesh ?? '—'])),
    world.obstacles.length === 0 && world.walls.length ? h('p', { class: 'muted' }, `${world.walls.length} wall segments from the map image.`) : null);
}

function facts(id, doc, world) {
  const humans = world.agents.filter((agent) => agent.kind === 'human');
  const robots = world.agents.filter((agent) => agent.kind === 'robot');
  const [x0, y0] = world.bounds.min, [x1, y1] = world.bounds.max;
  const entries = [
    ['Id', h('code', {}, id)],
    ['Humans', humans.length ? `${humans.length}: ${humans.map((agent) => agent.id).join(', ')}` : '0'],
    ['Robots', robots.length ? robots.map((agent) => `${agent.id} (${agent.model ?? 'disc, no model'})`).join(', ') : 'none'],
    ['Task', doc.task ? taskSummary(doc.task) : '—'],
    ['Duration (time limit)', number(world.time_limit, 's')],
    ['Steps', formatNumber((doc.steps ?? []).length)],
    ['Time step', `${number(world.dt, 's')} (${formatNumber(1 / world.dt)} Hz)`],
    ['Map', `${formatNumber(x1 - x0)} × ${formatNumber(y1 - y0)} m`],
  ];
  return h('dl', { class: 'sc-facts' }, entries.flatMap(([term, value]) => [h('dt', {}, term), h('dd', {}, value)]));
}

/** The form that starts a live session, with the first robot's controller when it has a model. */
function sessionForm(id, doc, world) {
  const robot = world.agents.find((agent) => agent.kind === 'robot');
  const seed = h('input', { type: 'number', id: 'session-seed', min: 0, step: 1, value: 0, required: true, inputmode: 'numeric' });
  const seedError = h('span', { class: 'sc-field-error', id: 'session-seed-error', role: 'alert' });
  seed.setAttribute('aria-describedby', seedError.id);
  const fields = [h('label', { for: 'session-seed' }, 'Seed', seed, seedError)];
  let controller = null, goal = null, controllerError = null;
  if (robot && robot.model) {
    const own = doc.robots?.find((entry) => entry.id === robot.id)?.controller?.type ?? 'idle';
    controller = h('select', { id: 'session-controller' },
      h('option', { value: '' }, `scenario's own (${own})`), h('option', { value: 'idle' }, 'idle'),
      h('option', { value: 'goal' }, 'goal (A*, blind to people)'), h('option', { value: 'social' }, 'social (yields to people)'),
      h('option', { value: 'dwa' }, 'dwa (Dynamic Window Approach)'), h('option', { value: 'orca' }, 'orca (avoids alone)'),
      h('option', { value: 'social_force' }, "social_force (HuNavSim's)"), h('option', { value: 'teleop' }, 'teleop'));
    goal = h('select', { id: 'session-goal', disabled: true }, h('option', { value: '' }, "none (the choreography's goto actions)"),
      world.locations.map((location) => h('option', { value: location.name }, location.name)));
    controllerError = h('span', { class: 'sc-field-error', id: 'session-controller-error', role: 'alert' });
    controller.setAttribute('aria-describedby', controllerError.id);
    goal.setAttribute('aria-describedby', controllerError.id);
    // Every controller but idle and teleop drives: to a goal when given one, else along the choreography's gotos.
    const drives = () => !['', 'idle', 'teleop'].includes(controller.value);
    controller.addEventListener('input', () => { goal.disabled = !drives(); });
    fields.push(h('label', { for: 'session-controller' }, `Controller of ${robot.id} (${robot.model})`, controller),
      h('label', { for: 'session-goal' }, 'Goal location', goal), controllerError);
    // A robot without a drive (ROMAN) can only stand idle.
    api.get(`/api/v1/robots/${encodeURIComponent(robot.model)}`).then((described) => {
      if (described.summary?.drive !== null) return;
      for (const option of controller.options) if (option.value && option.value !== 'idle') option.disabled = true;
    }).catch(() => { /* the server names a controller it refuses when the session is asked for */ });
  }
  const start = h('button', { type: 'submit' }, 'Start live session');
  const status = h('div', { class: 'sc-session-status', 'aria-live': 'polite' });
  const note = !robot ? 'No robot in this scenario: the session runs the humans only.'
    : !robot.model ? `${robot.id} has no model (a disc moved by the choreography), so its controller cannot be replaced.` : null;

  const form = h('form', { class: 'sc-session-form', 'aria-label': 'Start a live session', novalidate: true, onsubmit: async (event) => {
    event.preventDefault();
    for (const element of [seedError, controllerError]) if (element) element.textContent = '';
    for (const element of [seed, controller, goal]) element?.removeAttribute('aria-invalid');
    status.replaceChildren();
    const body = { scenario: id, unwatched_grace: UNWATCHED_GRACE_S };
    if (seed.value.trim() !== '') body.seed = Number(seed.value);
    if (controller && controller.value) {
      body.controller = { type: controller.value };
      if (!goal.disabled && goal.value) body.controller.goal = { location: goal.value };
    }
    start.disabled = true;
    const wait = loading(status, 'Starting the session');
    try {
      const session = await api.post('/api/v1/sessions', body);
      location.hash = `#/sessions/${encodeURIComponent(session.id)}`;
    } catch (error) {
      // Each problem beside the field it names; the rest as a message under the form.
      const problems = error.details?.errors ?? (error.details?.pointer !== undefined ? [{ pointer: error.details.pointer, message: error.message }] : []);
      const placed = problems.filter((problem) => {
        if (problem.pointer === '/seed') { seedError.textContent = problem.message; seed.setAttribute('aria-invalid', 'true'); return true; }
        if (controllerError && problem.pointer?.startsWith('/controller')) {
          controllerError.textContent += `${controllerError.textContent ? ' ' : ''}${problem.pointer}: ${problem.message}`;
          (problem.pointer.startsWith('/controller/goal') ? goal : controller).setAttribute('aria-invalid', 'true');
          return true;
        }
        return false;
      });
      if (error.details?.max_sessions !== undefined) {
        // The server's message names its API; in the browser the way out is the Sessions page.
        status.append(h('p', { class: 'message error', role: 'alert' }, h('strong', {}, 'Not started: '),
          `the server already runs its maximum of ${error.details.max_sessions} sessions (finished ones do not count). End one on the `,
          h('a', { href: '#/sessions' }, 'Sessions page'), `, or try again in ${error.details.retry_after ?? 10} s.`));
      } else if (!problems.length || placed.length < problems.length) {
        status.append(h('p', { class: 'message error', role: 'alert' }, h('strong', {}, `Not started (HTTP ${error.status ?? '?'}): `), error.message));
      }
    } finally {
      wait.remove();
      start.disabled = false;
    }
  } }, h('div', { class: 'fields' }, fields), note ? h('p', { class: 'muted' }, note) : null, h('div', { class: 'row' }, start),
  h('p', { class: 'muted sc-session-note' }, `It ends ${UNWATCHED_GRACE_S} s after its last tab closes; the `, h('a', { href: '#/sessions' }, 'Sessions page'), ' lists the live ones.'),
  status);
  return form;
}

export async function render(root, params) {
  const id = params.id;
  const path = `/api/v1/scenarios/${encodeURIComponent(id)}`;
  const wait = loading(root, 'Loading the scenario');
  let doc, world;
  try {
    [doc, world] = await Promise.all([api.get(path), api.get(`${path}/world`)]);
  } catch (error) {
    errorPage(root, `Scenario ${id}`, error, { href: '#/', text: '← All scenarios' });
    return;
  }
  wait.remove();
  const uploaded = /^u[0-9a-f]{32}$/.test(id);
  root.append(h('p', { class: 'sc-breadcrumb' }, h('a', { href: '#/' }, '← All scenarios')));
  pageTitle(root, doc.name ?? id);
  const deleteButton = uploaded ? h('button', { type: 'button', class: 'secondary danger', onclick: async () => {
    deleteButton.disabled = true;
    try {
      const outcome = await deleteUpload({ id, name: doc.name ?? id });
      if (!outcome) return;
      recentDeletions.set(id, { name: doc.name ?? id, outcome });
      location.hash = '#/';
    } catch (error) {
      showError(deleteArea, error);
    } finally {
      deleteButton.disabled = false;
    }
  } }, 'Delete this upload') : null;
  const deleteArea = h('div', { 'aria-live': 'polite' });
  root.append(h('div', { class: 'sc-scenario-head' },
    h('p', { class: 'subtitle' }, h('span', { class: `badge ${uploaded ? 'warn' : 'good'}` }, uploaded ? 'uploaded' : 'bundled'), ' ', h('code', {}, id)),
    deleteButton), deleteArea);

  const recent = recentUploads.get(id);
  if (recent) {
    recentUploads.delete(id);
    root.append(h('div', { class: 'message info', role: 'status' },
      recent.existed ? `Already uploaded: this is ${id}, stored before with the same content; nothing new was stored.` : `Uploaded and stored as ${id}.`,
      recent.warnings?.length ? h('ul', {}, recent.warnings.map((warning) => h('li', {}, h('code', {}, warning.pointer ?? `line ${warning.line}`), ' ', warning.message))) : null));
  }
  if (doc.description) root.append(h('p', { class: 'sc-scenario-description' }, doc.description));

  root.append(h('div', { class: 'sc-scenario-top' },
    h('section', { class: 'panel', 'aria-labelledby': 'facts-heading' }, h('h2', { id: 'facts-heading' }, 'Summary'), facts(id, doc, world),
      h('p', {}, h('a', { href: path, download: `${id}.json` }, 'Native JSON document'))),
    h('section', { class: 'panel', 'aria-labelledby': 'actions-heading' }, h('h2', { id: 'actions-heading' }, 'Start'),
      sessionForm(id, doc, world),
      h('p', { class: 'sc-batch-link' }, h('a', { class: 'button secondary', href: `#/runs?scenario=${encodeURIComponent(id)}` }, 'Run in batch'),
        h('span', { class: 'muted' }, ' headless episodes over many seeds, with metrics and gates')))));

  const mapBox = h('div', { class: 'sc-map-box' });
  root.append(h('section', { 'aria-labelledby': 'map-heading' }, h('h2', { id: 'map-heading' }, 'Map'),
    h('div', { class: 'sc-map-layout' }, h('div', { class: 'panel sc-map-panel' }, mapBox, legend(world)), h('div', { class: 'panel' }, worldLists(world)))));
  const map = new MapView(mapBox, world, { width: 640, maxHeight: 640 });
  for (const agent of world.agents) {
    map.text(agent.start.x, agent.start.y + agent.radius + 0.15, agent.id, agent.kind === 'robot' ? palette.robotText : palette.human);
  }

  root.append(h('section', { 'aria-labelledby': 'timeline-heading' }, h('h2', { id: 'timeline-heading' }, 'Choreography'),
    timeline(doc, world), routinesSection(doc)));
}

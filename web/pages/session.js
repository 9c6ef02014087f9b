// #/sessions/ID: a live lockstep session. The page steps it itself over the session's WebSocket at the
// chosen speed (one step message in flight at most), draws the agents in 3D with the robot's laser
// and proxemic rings, shows a camera's frames, the choreography's progress and the events as they
// happen, and lets the user drive the robot, command a human or make a robot request.
import { api, ApiError, sessionSocketUrl } from '../lib/api.js';
import { h, loading, showError, formatNumber, pageTitle } from '../lib/ui.js';
import { SceneView, PROXEMIC_DISTANCES } from '../lib/scene.js';
import { palette } from '../lib/map2d.js';

/** Playback speeds, simulated seconds per wall-clock second. */
const SPEEDS = [0.25, 0.5, 1, 2, 4];
const CAMERA_SIZE = { width: 320, height: 240 };
/** A few camera frames a second: each is drawn off-screen on the server's worker pool. */
const CAMERA_INTERVAL_MS = 250;
const SENSORS_INTERVAL_MS = 200;
/** How often the play loop looks at the clock while no step is in flight. */
const LOOP_INTERVAL_MS = 30;
/** A realtime session steps itself; the page only looks at it this often, ms. */
const WATCH_INTERVAL_MS = 100;
/** Simulated time the page may owe after a slow reply (wall s × speed); more is dropped, not caught up. */
const MAX_BACKLOG_S = 0.5;
/** Trails: the last seconds of each agent's positions, a point every few centimetres. */
const TRAIL_SECONDS = 10;
const TRAIL_SPACING_M = 0.05;
const MAX_EVENTS = 200;
/** The "actual speed" readout averages over this window, ms. */
const SPEED_WINDOW_MS = 2000;
const HRCF_HEADER_BYTES = 96;

/**
 * The session's WebSocket as request → answer: answers come one per message, in order, so each one
 * settles the oldest waiting promise. Error answers reject with an ApiError.
 */
class Lockstep {
  constructor(url, onClose) {
    this.pending = [];
    this.closing = false;
    this.socket = new WebSocket(url);
    this.socket.binaryType = 'arraybuffer';
    this.opened = new Promise((resolve, reject) => {
      this.socket.addEventListener('open', () => resolve(), { once: true });
      this.socket.addEventListener('error', () => reject(new Error('could not open the session\'s WebSocket')), { once: true });
    });
    this.socket.addEventListener('message', (event) => {
      const waiting = this.pending.shift();
      if (!waiting) return;
      if (typeof event.data !== 'string') {
        waiting.resolve(event.data);
        return;
      }
      const message = JSON.parse(event.data);
      if (message.type === 'error') waiting.reject(new ApiError(0, message));
      else waiting.resolve(message);
    });
    this.socket.addEventListener('close', (event) => {
      for (const waiting of this.pending.splice(0)) waiting.reject(new Error('the connection closed'));
      if (!this.closing) onClose(event);
    });
  }

  get open() {
    return this.socket.readyState === WebSocket.OPEN;
  }

  send(message) {
    if (!this.open) return Promise.reject(new Error('not connected to the session'));
    return new Promise((resolve, reject) => {
      this.pending.push({ resolve, reject });
      this.socket.send(JSON.stringify(message));
    });
  }

  close() {
    this.closing = true;
    this.socket.close();
  }
}

/** An API error as one line, with the JSON pointer it names. */
function errorText(error) {
  const pointer = error.details?.pointer;
  const where = pointer && !error.message.includes(pointer) ? ` (${pointer})` : '';
  return `${error.message}${where}`;
}

function shortData(data) {
  return Object.entries(data ?? {}).map(([key, value]) => {
    const text = typeof value === 'number' ? formatNumber(value) : typeof value === 'object' ? JSON.stringify(value) : String(value);
    return `${key} ${text}`;
  }).join(', ');
}

function eventTone(kind) {
  if (/collision|contact_start|unreachable|dropped/.test(kind)) return 'bad';
  if (/request/.test(kind)) return 'warn';
  if (/reached|accepted|finished/.test(kind)) return 'good';
  return '';
}

function message(target, tone, text) {
  target.className = `message ${tone}`;
  target.textContent = text;
  target.hidden = false;
}

export async function render(root, { id }) {
  const wait = loading(root, 'Loading the session');
  let status, world, scenario, cameras, actionSpace;
  try {
    status = await api.get(`/api/v1/sessions/${encodeURIComponent(id)}`);
    [world, scenario, cameras, actionSpace] = await Promise.all([
      api.get(`/api/v1/scenarios/${encodeURIComponent(status.scenario)}/world`),
      api.get(`/api/v1/scenarios/${encodeURIComponent(status.scenario)}`),
      api.get(`/api/v1/sessions/${encodeURIComponent(id)}/cameras`),
      // 409 for a robot without a drive: then it cannot be driven by keys.
      api.get(`/api/v1/sessions/${encodeURIComponent(id)}/action_space`).catch((error) => {
        if (error instanceof ApiError && error.status === 409) return null;
        throw error;
      }),
    ]);
  } catch (error) {
    wait.remove();
    pageTitle(root, 'Session', id);
    showError(root, error);
    root.append(h('p', {}, h('a', { href: '#/' }, 'Back to the scenarios')));
    return undefined;
  }
  wait.remove();

  const humans = world.agents.filter((agent) => agent.kind === 'human');
  const robot = world.agents.find((agent) => agent.kind === 'robot') ?? null;  // the robot under test
  const radii = Object.fromEntries(world.agents.map((agent) => [agent.id, agent.radius]));
  const steps = scenario.steps ?? [];
  const answered = new Set((scenario.async ?? []).map((entry) => entry.task));
  // Tasks a human answers first: the others are dropped at once.
  const tasks = Object.keys(scenario.tasks ?? {}).sort((a, b) => Number(answered.has(b)) - Number(answered.has(a)));
  const canDrive = Boolean(robot && robot.model && actionSpace && actionSpace.shape?.[0] === 2);
  const dt = status.dt;
  const realtime = status.mode === 'realtime';
  // A benchmark task's step is its frame skip in ticks (docs/benchmark.md); otherwise one tick.
  const stepTicks = () => status.task?.step_ticks ?? 1;

  // ---- Page state ----
  let socket = null;
  let scene = null;
  let disposed = false;
  let playing = false;
  let speed = 1;
  let debt = 0;
  let lastClock = 0;
  let timer = 0;
  let inFlight = null;
  let queuedSteps = 0;
  let stepsWaiting = false;
  let cameraName = (cameras.cameras.find((c) => c.kind === 'camera' || c.kind === 'rgbd_camera')
    ?? cameras.cameras.find((c) => c.name === 'follow') ?? cameras.cameras[0])?.name ?? null;
  let lastCamera = -Infinity;
  let lastSensors = -Infinity;
  let layers = { laser: Boolean(robot?.model), rings: Boolean(robot), trails: true, plans: true };
  const trails = new Map();
  const speedSamples = [];
  let teleopOn = status.controller?.type === 'teleop';
  const pressed = new Set();
  let sentVelocity = { linear: 0, angular: 0 };
  let pendingRequest = null;
  let eventsFrom = 0;  // realtime: events come with the state, from this tick on
  const laserKeys = new Set();
  // Filled by the panels' builders: what the key handlers and event tracking update.
  const teleopUi = { show() {}, error() {}, clearError() {}, maxLinear: 0, maxAngular: 0 };
  const requestUi = { result: null };

  // ---- Layout ----
  pageTitle(root, `Session ${id}`);
  const scenarioLink = h('a', { href: `#/scenarios/${encodeURIComponent(status.scenario)}` }, scenario.name ?? status.scenario);
  const controllerText = status.controller ? status.controller.type : 'the scenario\'s own';
  const endButton = h('button', { type: 'button', class: 'secondary danger', onclick: endSession }, 'End session');
  const endMessage = h('p', { class: 'message error', role: 'alert', hidden: true });
  root.append(h('div', { class: 'session-head' },
    h('p', { class: 'subtitle' }, 'Scenario ', scenarioLink, ` · seed ${status.seed} · ${status.mode} · controller: ${controllerText} · dt ${formatNumber(dt)} s`),
    endButton));
  root.append(endMessage);
  const connection = h('div', { class: 'message error', role: 'alert', hidden: true });
  root.append(connection);

  // Toolbar: playback, view, time and choreography.
  const playButton = h('button', { type: 'button', class: 'play', onclick: () => (playing ? pause() : play()), 'aria-pressed': 'false' }, 'Play');
  const stepButton = h('button', { type: 'button', class: 'secondary', onclick: singleStep },
    status.task ? `Step 1 step (${stepTicks()} ticks)` : `Step 1 tick (${formatNumber(dt, 2)} s)`);
  const speedSelect = h('select', { onchange: () => { speed = Number(speedSelect.value); } },
    SPEEDS.map((value) => h('option', { value, selected: value === speed }, `${value}× real time`)));
  const actualSpeed = h('span', { class: 'muted actual-speed' });
  const viewButtons = ['top', 'perspective'].map((view) => h('button', {
    type: 'button', class: 'secondary', 'data-view': view, 'aria-pressed': String(view === 'top'),
    onclick: () => setView(view),
  }, view === 'top' ? 'Top' : 'Perspective'));
  const clock = h('span', { class: 'clock', 'aria-live': 'off' });
  const runState = h('span', { class: 'badge' });
  const stepText = h('span', { class: 'step-name' });
  const stepBar = h('progress', { max: Math.max(steps.length, 1), value: 0, 'aria-label': 'Choreography progress' });
  const playError = h('p', { class: 'message error', role: 'alert', hidden: true });
  const playback = realtime
    ? h('div', { class: 'toolbar-group' }, h('span', {}, `Realtime: the server steps it at ${formatNumber(status.realtime_factor)}× real time.`))
    : h('div', { class: 'toolbar-group', role: 'group', 'aria-label': 'Playback' }, playButton, stepButton,
      h('label', { class: 'inline' }, 'Speed', speedSelect), actualSpeed);
  root.append(h('div', { class: 'panel session-toolbar' },
    playback,
    h('div', { class: 'toolbar-group', role: 'group', 'aria-label': 'View' }, h('span', { class: 'muted' }, 'View'), viewButtons),
    h('div', { class: 'toolbar-group status-group' }, clock, runState),
    h('div', { class: 'toolbar-group choreography' }, h('span', { class: 'muted' }, 'Choreography'), stepBar, stepText)));
  root.append(playError);

  // The scene and, beside it, a camera and teleop.
  const sceneBox = h('div', {
    class: 'scene-box', tabindex: '0', role: 'application',
    'aria-label': `3D view of ${world.name}. Drag to move the view, scroll to zoom${canDrive ? '; with teleop on, arrow keys or W A S D drive the robot' : ''}.`,
    onkeydown: keyDown, onkeyup: keyUp, onblur: releaseKeys,
  });
  const layerToggles = [
    ['trails', 'Trails (last 10 s)', true],
    ['plans', 'Planned paths (dashed)', true],
    ['laser', 'Laser scan', Boolean(robot?.model)],
    ['rings', `Proxemic rings (${Object.entries(PROXEMIC_DISTANCES).map(([name, r]) => `${name} ${r} m`).join(', ')})`, Boolean(robot)],
  ].filter(([, , available]) => available).map(([key, text]) => h('label', { class: 'check' },
    h('input', { type: 'checkbox', checked: layers[key], onchange: (event) => setLayer(key, event.target.checked) }), text));
  const legend = h('div', { class: 'scene-legend' },
    h('span', { class: 'ss-swatch human' }, 'human (pale: idle)'), h('span', { class: 'ss-swatch robot' }, 'robot'),
    h('span', { class: 'ss-swatch location' }, 'location'), h('span', { class: 'ss-swatch space' }, 'social space'),
    robot?.model ? h('span', { class: 'ss-swatch laser' }, 'laser') : null, layerToggles);

  const cameraSelect = h('select', { onchange: () => { cameraName = cameraSelect.value; lastCamera = -Infinity; refresh(); } },
    cameras.cameras.map((c) => h('option', { value: c.name, selected: c.name === cameraName }, `${c.name} (${c.kind})`)));
  const cameraCanvas = h('canvas', { class: 'camera-frame', width: CAMERA_SIZE.width, height: CAMERA_SIZE.height, role: 'img', 'aria-label': 'Camera frame' });
  const cameraCaption = h('p', { class: 'muted camera-caption' }, 'Waiting for the first frame…');
  const cameraError = h('p', { class: 'message error', role: 'alert', hidden: true });
  const cameraPanel = h('section', { class: 'panel camera-panel', 'aria-label': 'Camera' },
    h('h2', {}, 'Camera'), h('label', {}, 'Camera', cameraSelect), cameraCanvas, cameraCaption, cameraError);

  const teleopPanel = robot ? buildTeleop() : null;
  const taskUi = status.task ? buildTask() : null;
  root.append(h('div', { class: 'session-main' },
    h('section', { class: 'panel scene-panel', 'aria-label': 'Scene' }, sceneBox, legend),
    h('div', { class: 'session-side' }, cameraPanel, taskUi?.panel, teleopPanel)));

  // Below: events, agents, commands.
  const eventList = h('ol', { class: 'event-list', 'aria-label': 'Events, newest first' });
  const noEvents = h('p', { class: 'muted' }, 'No events yet: they appear as the session steps.');
  const agentRows = new Map();
  const agentTable = h('table', { class: 'agent-table' },
    h('thead', {}, h('tr', {}, h('th', {}, 'Agent'), h('th', { class: 'number' }, 'x (m)'), h('th', { class: 'number' }, 'y (m)'),
      h('th', { class: 'number' }, 'θ (rad)'), h('th', { class: 'number' }, 'speed (m/s)'), h('th', {}, 'Actions left'))),
    h('tbody', {}, world.agents.map((agent) => {
      const cells = { x: h('td', { class: 'number' }), y: h('td', { class: 'number' }), theta: h('td', { class: 'number' }),
        speed: h('td', { class: 'number' }), busy: h('td', {}) };
      const row = h('tr', { 'data-agent': agent.id, 'data-kind': agent.kind },
        h('th', { scope: 'row' }, h('span', { class: `ss-dot ${agent.kind}` }), agent.id), cells.x, cells.y, cells.theta, cells.speed, cells.busy);
      agentRows.set(agent.id, { row, cells });
      return row;
    })));
  const openRequests = h('p', { class: 'muted open-requests' });
  root.append(h('div', { class: 'session-lower' },
    h('section', { class: 'panel events-panel', 'aria-label': 'Events' }, h('h2', {}, 'Events'), noEvents, eventList),
    h('section', { class: 'panel agents-panel', 'aria-label': 'Agents' }, h('h2', {}, 'Agents'), agentTable, openRequests),
    h('div', { class: 'session-commands' }, humans.length ? buildHumanCommand() : null, robot && tasks.length ? buildRequest() : null)));

  // ---- Scene ----
  scene = new SceneView(sceneBox, world, { height: 480 });

  showStatus(status);

  // ---- Socket ----
  socket = new Lockstep(await sessionSocketUrl(id), (event) => {
    pause();
    setDisabled(true);
    message(connection, 'error', `The connection to the session closed (code ${event.code}${event.reason ? `: ${event.reason}` : ''}). `
      + 'The session may have ended; reload the page to try again.');
  });
  const connecting = loading(sceneBox.parentElement, 'Connecting to the session');
  try {
    await socket.opened;
  } catch (error) {
    connecting.remove();
    if (!disposed) message(connection, 'error', `${error.message}.`);
    return cleanup;
  }
  connecting.remove();
  if (realtime) watch();
  else refresh();
  return cleanup;

  // ---- Functions (hoisted) ----

  function cleanup() {
    disposed = true;
    playing = false;
    clearTimeout(timer);
    if (socket) socket.close();
    if (scene) scene.dispose();
  }

  function setDisabled(disabled) {
    for (const control of root.querySelectorAll('.session-toolbar button, .session-toolbar select, .session-commands button, .teleop button')) {
      control.disabled = disabled;
    }
  }

  function setView(view) {
    for (const button of viewButtons) button.setAttribute('aria-pressed', String(button.dataset.view === view));
    scene.setView(view);
  }

  function setLayer(key, on) {
    layers = { ...layers, [key]: on };
    if ((key === 'trails' || key === 'plans') && !on) scene.setPaths({});
    if (key === 'laser' && !on) for (const laser of laserKeys) scene.setLaser(laser, null);
    if (key === 'rings' && !on) scene.setProxemicRings(0, 0, null);
    lastSensors = -Infinity;
    refresh();
  }

  // ---- Playback ----

  function play() {
    if (status.status === 'finished' || !socket) return;
    playing = true;
    debt = 0;
    lastClock = performance.now();
    speedSamples.length = 0;
    playButton.textContent = 'Pause';
    playButton.setAttribute('aria-pressed', 'true');
    stepButton.disabled = true;
    clearTimeout(timer);
    loop();
  }

  function pause() {
    const wasPlaying = playing;
    playing = false;
    clearTimeout(timer);
    playButton.textContent = 'Play';
    playButton.setAttribute('aria-pressed', 'false');
    stepButton.disabled = status.status === 'finished';
    actualSpeed.textContent = '';
    if (wasPlaying) {
      // The camera and laser are throttled while playing: bring them up to the tick it stopped at.
      lastCamera = -Infinity;
      lastSensors = -Infinity;
      (inFlight ?? Promise.resolve()).then(refresh);
    }
  }

  /** Steps as many ticks as the wall clock × speed owes, one step message at a time. */
  function loop() {
    timer = 0;
    if (!playing || disposed) return;
    const now = performance.now();
    debt = Math.min(debt + ((now - lastClock) / 1000) * speed, MAX_BACKLOG_S * speed);
    lastClock = now;
    const n = Math.floor(debt / (dt * stepTicks()) + 1e-6);
    if (n >= 1 && !inFlight) {
      debt -= n * dt * stepTicks();
      cycle(n).finally(() => {
        if (playing && !disposed) timer = setTimeout(loop, LOOP_INTERVAL_MS);
      });
    } else {
      timer = setTimeout(loop, LOOP_INTERVAL_MS);
    }
  }

  /** A realtime session: its state, laser and camera, over and over. */
  function watch() {
    timer = 0;
    if (disposed) return;
    (inFlight ?? cycle(0)).finally(() => {
      if (!disposed) timer = setTimeout(watch, WATCH_INTERVAL_MS);
    });
  }

  /** One tick per click; clicks while a reply is awaited are added up and sent together after it. */
  function singleStep() {
    if (status.status === 'finished' || playing) return;
    queuedSteps += 1;
    sendSteps();
  }

  function sendSteps() {
    if (inFlight) {
      if (!stepsWaiting) {
        stepsWaiting = true;
        inFlight.then(() => {
          stepsWaiting = false;
          sendSteps();
        });
      }
      return;
    }
    if (!queuedSteps || playing || disposed) return;
    lastCamera = -Infinity;
    lastSensors = -Infinity;
    const n = queuedSteps;
    queuedSteps = 0;
    cycle(n).then(sendSteps);
  }

  /** A new state, laser and camera frame without stepping (after a change of camera or layer). */
  function refresh() {
    if (!inFlight && !playing && !disposed && socket.open) cycle(0);
  }

  /**
   * One round: n steps (0: none), then the state, and the laser and camera when they are due — sent
   * together (the answers come in order), applied as each answer arrives.
   */
  function cycle(n) {
    const now = performance.now();
    const work = [];
    playError.hidden = true;
    if (n > 0) {
      work.push(socket.send({ type: 'step', n }).then((reply) => {
        showStatus(reply);
        addEvents(reply.events);
        if (taskUi) taskUi.show(reply);
      }, (error) => {
        pause();
        message(playError, 'error', `Stepping failed: ${errorText(error)}`);
      }));
    }
    // In lockstep every event comes with a step reply, once; the state need not repeat them.
    const since = realtime ? eventsFrom : Number.MAX_SAFE_INTEGER;
    work.push(socket.send({ type: 'state', events_since: since }).then(showState, () => {}));
    if (robot?.model && layers.laser && now - lastSensors >= SENSORS_INTERVAL_MS) {
      lastSensors = now;
      work.push(socket.send({ type: 'sensors', robot: robot.id }).then(showSensors, () => {}));
    }
    if (cameraName && now - lastCamera >= CAMERA_INTERVAL_MS) {
      lastCamera = now;
      work.push(socket.send({ type: 'camera', camera: cameraName, ...CAMERA_SIZE }).then(showFrame, (error) => {
        message(cameraError, 'error', `No frame from ${cameraName}: ${errorText(error)}`);
      }));
    }
    inFlight = Promise.all(work).finally(() => { inFlight = null; });
    return inFlight;
  }

  // ---- Showing what the server says ----

  function showStatus(next) {
    status = { ...status, ...next };
    clock.textContent = `t = ${status.time.toFixed(2)} s · tick ${status.tick}`;
    clock.dataset.tick = String(status.tick);
    const finished = status.status === 'finished';
    runState.textContent = finished ? `finished: ${(status.termination ?? '').replace('_', ' ')}` : 'running';
    runState.className = `badge ${finished ? 'good' : ''}`;
    if (status.step) {
      stepBar.value = status.step.index;
      stepText.textContent = `step ${status.step.index + 1} of ${steps.length}: ${status.step.name}`;
    } else {
      stepBar.value = steps.length;
      stepText.textContent = steps.length ? `all ${steps.length} steps done` : 'no steps';
    }
    if (finished) {
      pause();
      playButton.disabled = true;
      stepButton.disabled = true;
    }
    if (playing) {
      const now = performance.now();
      speedSamples.push([now, status.time]);
      while (speedSamples.length > 2 && now - speedSamples[0][0] > SPEED_WINDOW_MS) speedSamples.shift();
      const [t0, s0] = speedSamples[0];
      if (now - t0 > 500) actualSpeed.textContent = `actual ${((status.time - s0) / ((now - t0) / 1000)).toFixed(2)}×`;
    }
  }

  function showState(state) {
    showStatus(state);
    if (realtime) {
      addEvents(state.events.slice(-MAX_EVENTS));
      eventsFrom = state.tick + 1;
    }
    const agents = state.agents.filter((agent) => agent.active).map((agent) => ({ ...agent, radius: radii[agent.id] }));
    scene.update(agents);
    for (const agent of state.agents) {
      const entry = agentRows.get(agent.id);
      if (!entry) continue;
      entry.row.hidden = !agent.active;
      entry.row.dataset.x = String(agent.x);
      entry.row.dataset.y = String(agent.y);
      entry.cells.x.textContent = agent.x.toFixed(2);
      entry.cells.y.textContent = agent.y.toFixed(2);
      entry.cells.theta.textContent = agent.theta.toFixed(2);
      entry.cells.speed.textContent = Math.hypot(agent.vx, agent.vy).toFixed(2);
      entry.cells.busy.textContent = agent.busy ? 'yes' : 'no';
    }
    const robotNow = robot && state.agents.find((agent) => agent.id === robot.id);
    if (robotNow && layers.rings) scene.setProxemicRings(robotNow.x, robotNow.y);
    updateTrails(state);
    openRequests.textContent = state.requests.length
      ? `Open requests: ${state.requests.map((r) => `${r.robot} → ${r.task}`).join(', ')}` : '';
  }

  function updateTrails(state) {
    for (const agent of state.agents) {
      let trail = trails.get(agent.id);
      if (!trail) trails.set(agent.id, (trail = []));
      const last = trail[trail.length - 1];
      if (last && status.time < last.t) trail.length = 0;  // the session was reset
      if (!last || Math.hypot(agent.x - last.x, agent.y - last.y) >= TRAIL_SPACING_M) trail.push({ x: agent.x, y: agent.y, t: status.time });
      while (trail.length && status.time - trail[0].t > TRAIL_SECONDS) trail.shift();
    }
    const paths = {};
    state.agents.forEach((agent, index) => {
      // One colour per agent for its trail behind and its planned path ahead.
      const colour = palette.path[index % palette.path.length];
      const trail = trails.get(agent.id);
      if (layers.trails && trail) paths[`trail ${agent.id}`] = { points: [...trail.map((p) => [p.x, p.y]), [agent.x, agent.y]], colour };
      if (layers.plans && agent.path.length > 1) paths[`plan ${agent.id}`] = { points: agent.path, colour, dashed: true };
    });
    scene.setPaths(paths);
  }

  function showSensors(sensors) {
    if (!layers.laser) return;
    for (const laser of sensors.lasers) {
      if (laser.tick < 0) continue;
      const key = `${sensors.robot}/${laser.sensor}`;
      laserKeys.add(key);
      scene.setLaser(key, { ...laser.pose, angle_min: laser.angle_min,
        angle_increment: laser.angle_increment, ranges: laser.ranges, height: laser.height });
    }
  }

  function showFrame(buffer) {
    const view = new DataView(buffer);
    const width = view.getUint32(24, true);
    const height = view.getUint32(28, true);
    const tick = Number(view.getBigInt64(8, true));
    const name = new TextDecoder().decode(new Uint8Array(buffer, 60, 36)).replace(/\0.*$/s, '');
    if (cameraCanvas.width !== width || cameraCanvas.height !== height) Object.assign(cameraCanvas, { width, height });
    const pixels = new Uint8ClampedArray(buffer, HRCF_HEADER_BYTES, width * height * 4);
    cameraCanvas.getContext('2d').putImageData(new ImageData(pixels, width, height), 0, 0);
    cameraCanvas.dataset.tick = String(tick);
    cameraCanvas.setAttribute('aria-label', `Frame of camera ${name} at tick ${tick}`);
    cameraCaption.textContent = `${name} · tick ${tick} · ${width} × ${height} px`;
    cameraError.hidden = true;
  }

  function addEvents(events) {
    if (!events?.length) return;
    noEvents.hidden = true;
    const items = [];
    for (const event of events) {
      if (event.kind === 'door_state') scene.setDoorState(event.subject, event.data.state);
      trackRequest(event);
      items.push(h('li', { 'data-kind': event.kind },
        h('span', { class: 'event-time' }, `${event.time.toFixed(2)} s`),
        h('span', { class: `badge ${eventTone(event.kind)}` }, event.kind),
        h('span', { class: 'event-subject' }, event.subject),
        h('span', { class: 'event-data muted' }, shortData(event.data))));
    }
    eventList.prepend(...items.reverse());
    while (eventList.children.length > MAX_EVENTS) eventList.lastElementChild.remove();
  }

  // ---- Teleop ----

  /** A benchmark task: the last step's reward and its terms, the episode's return so far, its end. */
  function buildTask() {
    let episodeReturn = 0;
    let episodeTicks = status.tick;
    const reward = h('dd', { class: 'number', 'data-field': 'reward' }, '—');
    const total = h('dd', { class: 'number', 'data-field': 'return' }, '0');
    const ending = h('dd', { 'data-field': 'ending' }, status.task.terminated ? 'terminated' : 'running');
    const terms = h('dl', { class: 'facts task-terms', 'aria-label': 'The last step\'s reward terms' });
    const panel = h('section', { class: 'panel task-panel', 'aria-label': 'Task' },
      h('h2', {}, `Task: ${status.task.name}`),
      h('p', { class: 'muted' }, `One step is ${stepTicks()} ticks; the rewards are seed 003's (`, h('code', {}, 'docs/benchmark.md'), ').'),
      h('dl', { class: 'facts' }, h('dt', {}, 'Last reward'), reward, h('dt', {}, 'Return so far'), total, h('dt', {}, 'Episode'), ending),
      terms);
    return {
      panel,
      show(reply) {
        if (reply.tick < episodeTicks) episodeReturn = 0;  // a reset started a new episode
        episodeTicks = reply.tick;
        episodeReturn += reply.reward;
        reward.textContent = formatNumber(reply.reward, 3);
        total.textContent = formatNumber(episodeReturn, 3);
        ending.textContent = reply.terminated ? 'terminated' : reply.truncated ? 'truncated (episode length)' : 'running';
        terms.replaceChildren(...Object.entries(reply.info ?? {}).filter(([key]) => key !== 'tick' && key !== 'time')
          .flatMap(([key, value]) => [h('dt', {}, key.replaceAll('_', ' ')),
            h('dd', { class: typeof value === 'number' ? 'number' : '' }, typeof value === 'number' ? formatNumber(value, 3)
              : Array.isArray(value) ? (value.join(', ') || 'none') : String(value))]));
      },
    };
  }

  function buildTeleop() {
    const [maxLinear, maxAngular] = canDrive ? actionSpace.high.map(Number) : [0, 0];
    const keys = Object.fromEntries(['forward', 'back', 'left', 'right'].map((direction) => [direction,
      h('kbd', { 'data-direction': direction }, { forward: '↑ W', back: '↓ S', left: '← A', right: '→ D' }[direction])]));
    const toggle = h('button', { type: 'button', class: 'secondary', 'aria-pressed': String(teleopOn), onclick: () => {
      teleopOn = !teleopOn;
      toggle.setAttribute('aria-pressed', String(teleopOn));
      toggle.textContent = teleopOn ? 'Release control' : 'Take control';
      if (!teleopOn) releaseKeys();
      else sceneBox.focus();
    } }, teleopOn ? 'Release control' : 'Take control');
    const teleopError = h('p', { class: 'message error', role: 'alert', hidden: true });
    const velocity = h('p', { class: 'teleop-velocity', 'aria-live': 'polite' }, 'v 0.00 m/s · ω 0.00 rad/s');
    Object.assign(teleopUi, {
      maxLinear,
      maxAngular,
      show() {
        for (const [direction, key] of Object.entries(keys)) key.classList.toggle('pressed', pressed.has(direction));
        velocity.textContent = `v ${sentVelocity.linear.toFixed(2)} m/s · ω ${sentVelocity.angular.toFixed(2)} rad/s`;
      },
      error(error) { message(teleopError, 'error', `Drive command refused: ${errorText(error)}`); },
      clearError() { teleopError.hidden = true; },
    });
    if (!canDrive) {
      return h('section', { class: 'panel teleop', 'aria-label': 'Drive the robot' }, h('h2', {}, `Drive ${robot.id}`),
        h('p', { class: 'muted' }, robot.model ? `The ${robot.model} has no drive to steer.` : 'Only a robot with a model can be driven.'));
    }
    return h('section', { class: 'panel teleop', 'aria-label': 'Drive the robot' },
      h('h2', {}, `Drive ${robot.id}`),
      h('p', { class: 'muted' }, status.controller?.type === 'teleop'
        ? 'Teleop controller: focus the 3D view and hold the keys.'
        : 'Take control, then focus the 3D view and hold the keys; the robot keeps to any path it is following.'),
      h('div', { class: 'row teleop-row' }, toggle,
        h('div', { class: 'keys', role: 'group', 'aria-label': 'Driving keys' }, h('span'), keys.forward, h('span'), keys.left, keys.back, keys.right)),
      velocity,
      h('p', { class: 'muted session-note' }, `Top speed ${formatNumber(maxLinear)} m/s, turn ${formatNumber(maxAngular)} rad/s. Keys up: stop. The session moves only while it plays or steps.`),
      teleopError);
  }

  function direction(event) {
    return { ArrowUp: 'forward', KeyW: 'forward', ArrowDown: 'back', KeyS: 'back', ArrowLeft: 'left', KeyA: 'left',
      ArrowRight: 'right', KeyD: 'right' }[event.code] ?? null;
  }

  function keyDown(event) {
    const which = direction(event);
    if (!which || !teleopOn || !canDrive || event.altKey || event.ctrlKey || event.metaKey) return;
    event.preventDefault();  // no scrolling while driving
    if (pressed.has(which)) return;  // key repeat
    pressed.add(which);
    sendVelocity();
  }

  function keyUp(event) {
    const which = direction(event);
    if (!which || !pressed.has(which)) return;
    event.preventDefault();
    pressed.delete(which);
    sendVelocity();
  }

  function releaseKeys() {
    if (!pressed.size) return;
    pressed.clear();
    sendVelocity();
  }

  function sendVelocity() {
    const linear = ((pressed.has('forward') ? 1 : 0) - (pressed.has('back') ? 1 : 0)) * teleopUi.maxLinear;
    const angular = ((pressed.has('left') ? 1 : 0) - (pressed.has('right') ? 1 : 0)) * teleopUi.maxAngular;
    sentVelocity = { linear, angular };
    teleopUi.show();
    socket.send({ type: 'commands', commands: [{ robot: robot.id, velocity: { linear, angular } }] })
      .then(() => teleopUi.clearError(), (error) => teleopUi.error(error));
  }

  // ---- Human commands and robot requests ----

  function buildHumanCommand() {
    const who = h('select', { name: 'human' }, humans.map((human) => h('option', { value: human.id }, human.id)));
    const text = h('input', { name: 'command', type: 'text', placeholder: 'walk 2 3', required: true, autocomplete: 'off', spellcheck: 'false' });
    const result = h('p', { class: 'message', role: 'status', hidden: true });
    const form = h('form', { class: 'human-command', onsubmit: async (event) => {
      event.preventDefault();
      const command = text.value.trim();
      if (!command) return;
      try {
        const reply = await socket.send({ type: 'commands', commands: [{ human: who.value, command }] });
        message(result, 'info', `${who.value}: “${command}” given at tick ${reply.tick}; it runs as the session steps.`);
        result.setAttribute('role', 'status');
      } catch (error) {
        message(result, 'error', errorText(error));
        result.setAttribute('role', 'alert');
      }
    } },
    h('div', { class: 'fields' }, h('label', {}, 'Human', who), h('label', { class: 'grow' }, 'Command', text), h('button', { type: 'submit' }, 'Send')),
    result);
    return h('section', { class: 'panel', 'aria-label': 'Command a human' }, h('h2', {}, 'Command a human'), form,
      h('p', { class: 'muted session-note' }, 'walk X Y (m) · wait S (s) · turn_to RAD · look_at NAME · motion NAME [S]. The command goes first, then the choreography resumes.'));
  }

  function buildRequest() {
    const task = h('select', { name: 'task' }, tasks.map((name) => h('option', { value: name },
      answered.has(name) ? `${name} (a human answers)` : name)));
    const result = h('p', { class: 'message', role: 'status', hidden: true });
    requestUi.result = result;
    const form = h('form', { class: 'robot-request', onsubmit: async (event) => {
      event.preventDefault();
      try {
        const reply = await socket.send({ type: 'commands', commands: [{ robot: robot.id, request: task.value }] });
        pendingRequest = { task: task.value, tick: reply.tick, id: null };
        message(result, 'info', `${robot.id} asked for ${task.value} at tick ${reply.tick}; who answers shows once the session steps.`);
      } catch (error) {
        message(result, 'error', errorText(error));
      }
    } },
    h('div', { class: 'fields' }, h('label', { class: 'grow' }, 'Task', task), h('button', { type: 'submit' }, 'Request')),
    result);
    return h('section', { class: 'panel', 'aria-label': 'Robot request' }, h('h2', {}, `Request from ${robot.id}`), form,
      h('p', { class: 'muted session-note' }, 'The closest idle human within 3 m runs the task the scenario answers it with; with nobody, it is retried every 5 s and dropped after 30 s.'));
  }

  /** Follows the page's last request through its events: asked, accepted by someone, or dropped. */
  function trackRequest(event) {
    const result = requestUi.result;
    if (!pendingRequest || !result) return;
    if (event.kind === 'request' && pendingRequest.id === null && event.subject === robot.id && event.data.task === pendingRequest.task) {
      pendingRequest.id = event.data.request;
      message(result, 'info', `Request #${event.data.request} (${pendingRequest.task}) is open: waiting for an idle human within 3 m…`);
    } else if (event.data?.request === pendingRequest.id && pendingRequest.id !== null) {
      if (event.kind === 'request_accepted') {
        message(result, 'info', `Request #${pendingRequest.id} accepted by ${event.subject} (${formatNumber(event.data.distance)} m away) at ${event.time.toFixed(2)} s.`);
        pendingRequest = null;
      } else if (event.kind === 'request_dropped') {
        message(result, 'error', `Request #${pendingRequest.id} dropped: ${event.data.reason}.`);
        pendingRequest = null;
      }
    }
  }

  // ---- Ending ----

  async function endSession() {
    endButton.disabled = true;
    pause();
    if (socket) socket.closing = true;  // the server closes the socket: that is no error here
    try {
      await api.delete(`/api/v1/sessions/${encodeURIComponent(id)}`);
      location.hash = `#/scenarios/${encodeURIComponent(status.scenario)}`;
    } catch (error) {
      if (socket) socket.closing = false;
      endButton.disabled = false;
      message(endMessage, 'error', `Could not end the session: ${errorText(error)}`);
    }
  }
}

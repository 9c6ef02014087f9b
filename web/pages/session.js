// #/sessions/ID: a live lockstep session. The page steps it itself over the session's WebSocket at the
// chosen speed (one step message in flight at most), draws the agents in 3D with the robot's laser
// and proxemic rings, shows a camera's frames, the choreography's progress and the events as they
// happen, what was given when (and a snapshot file of the moment), goes back (or forth) to a tick, and lets the user drive the robot, command a human or make a
// robot request.
// The driver (session/driver.js) talks to the server; each panel under session/ renders its part of
// what the driver hears. This page lays them out and owns the session's head and its end.
import { h, loading, errorPage, formatNumber, pageTitle } from '../lib/ui.js';
import { showInAddress } from '../lib/hashquery.js';
import { routinesOf, routineOf } from '../lib/routines.js';
import { loadSession } from '../session/driver.js';
import { errorText, showMessage } from '../session/messages.js';
import { toolbar } from '../session/toolbar.js';
import { SessionScene } from '../session/scene3d.js';
import { cameraPanel } from '../session/camera.js';
import { taskPanel } from '../session/task.js';
import { teleopPanel } from '../session/teleop.js';
import { eventsPanel } from '../session/events.js';
import { inputsPanel } from '../session/inputs.js';
import { agentsPanel } from '../session/agents.js';
import { humanCommandPanel, robotRequestPanel } from '../session/commands.js';

/**
 * The 3D view the address names: `view=top|perspective` and `cam=PX,PY,PZ,TX,TY,TZ,ZOOM` (the camera's
 * position and target in the map frame, metres; the top view's zoom); null for none or a malformed one.
 */
function cameraOf(query) {
  const view = query?.get('view');
  if (view !== 'top' && view !== 'perspective') return null;
  const numbers = (query.get('cam') ?? '').split(',').map(Number);
  if (numbers.length !== 7 || !numbers.every(Number.isFinite) || numbers[6] <= 0) return { view };
  return { view, position: numbers.slice(0, 3), target: numbers.slice(3, 6), zoom: numbers[6] };
}

/**
 * Where Foxglove or Lichtblick opens this session (docs/foxglove.md): the address to paste into its
 * "Foxglove WebSocket" connection, this server's own.
 */
function foxgloveHint(id) {
  const scheme = window.location.protocol === 'https:' ? 'wss' : 'ws';
  const address = `${scheme}://${window.location.host}/api/v1/sessions/${encodeURIComponent(id)}/foxglove`;
  return h('p', { class: 'subtitle foxglove-hint' },
    'Open in Foxglove or Lichtblick: Open connection → Foxglove WebSocket → ', h('code', { class: 'foxglove-url' }, address),
    ' (docs/foxglove.md)');
}

export async function render(root, { id }, query) {
  const wait = loading(root, 'Loading the session');
  let loaded;
  try {
    loaded = await loadSession(id);
  } catch (error) {
    errorPage(root, `Session ${id}`, error, { href: '#/sessions', text: 'Back to the sessions' });
    return undefined;
  }
  wait.remove();
  const { driver, world, scenario, cameras, actionSpace, replayed } = loaded;
  const { status } = driver;

  const humans = world.agents.filter((agent) => agent.kind === 'human');
  const robot = world.agents.find((agent) => agent.kind === 'robot') ?? null;  // the robot under test
  const steps = scenario.steps ?? [];
  const answered = new Set((scenario.async ?? []).map(routineOf));
  // Routines a human answers first: the others are dropped at once.
  const routines = Object.keys(routinesOf(scenario)).sort((a, b) => Number(answered.has(b)) - Number(answered.has(a)));
  const canDrive = Boolean(robot && robot.model && actionSpace && actionSpace.shape?.[0] === 2);

  // ---- Layout ----
  pageTitle(root, `Session ${id}`);
  const scenarioLink = h('a', { href: `#/scenarios/${encodeURIComponent(status.scenario)}` }, scenario.name ?? status.scenario);
  const controllerText = status.controller ? status.controller.type : 'the scenario\'s own';
  const endButton = h('button', { type: 'button', class: 'secondary danger', onclick: endSession }, 'End session');
  const endMessage = h('p', { class: 'message error', role: 'alert', hidden: true });
  root.append(h('div', { class: 'session-head' },
    h('p', { class: 'subtitle' }, 'Scenario ', scenarioLink, ` · seed ${status.seed} · ${status.mode} · controller: ${controllerText} · dt ${formatNumber(driver.dt)} s`),
    endButton));
  root.append(endMessage);
  root.append(foxgloveHint(id));
  const connection = h('div', { class: 'message error', role: 'alert', hidden: true });
  root.append(connection);

  const scene = new SessionScene(driver, { world, robot, drivable: canDrive });
  // The page's keys listen on the document: they stop when the page is left.
  const keys = new AbortController();
  // The view and its camera are kept in the address, so a link opens the scene as it was seen.
  const shownCamera = cameraOf(query);
  const keepCameraInAddress = () => {
    const pose = scene.cameraPose();
    const values = Object.fromEntries(query ?? []);
    values.view = pose.view;
    values.cam = [...pose.position, ...pose.target, pose.zoom].join(',');
    showInAddress(`/sessions/${encodeURIComponent(id)}`, values, { replace: true });
  };
  const onView = (view) => {
    scene.setView(view);
    keepCameraInAddress();
  };
  root.append(...toolbar(driver, { steps, view: shownCamera?.view, onView, signal: keys.signal, replayTicks: replayed?.ticks }));
  root.append(h('div', { class: 'session-main' },
    scene.panel,
    h('div', { class: 'session-side' }, cameraPanel(driver, cameras.cameras), status.task ? taskPanel(driver) : null,
      robot ? teleopPanel(driver, { robot, actionSpace, canDrive, signal: keys.signal }) : null)));
  root.append(h('div', { class: 'session-lower' },
    eventsPanel(driver),
    agentsPanel(driver, world.agents),
    h('div', { class: 'session-commands' }, humans.length ? humanCommandPanel(driver, humans) : null,
      robot && routines.length ? robotRequestPanel(driver, { robot, routines, answered }) : null, inputsPanel(driver, id))));
  scene.mount();
  if (shownCamera?.position) scene.setCameraPose(shownCamera);
  else if (shownCamera) scene.setView(shownCamera.view);
  scene.onCameraMoved(keepCameraInAddress);

  // ---- Connection ----
  driver.on('closed', (event) => {
    for (const control of root.querySelectorAll('.session-toolbar button, .session-toolbar select, .session-toolbar input, .session-commands button, .teleop button')) {
      control.disabled = true;
    }
    showMessage(connection, 'error', `The connection to the session closed (code ${event.code}${event.reason ? `: ${event.reason}` : ''}). `
      + 'The session may have ended; reload the page to try again.');
  });
  await driver.connect();
  const connecting = loading(scene.box.parentElement, 'Connecting to the session');
  try {
    await driver.start();
    // A replay opened at a moment of its episode (#/sessions/ID?tick=N).
    const startTick = Number(query?.get('tick'));
    if (Number.isInteger(startTick) && startTick > 0 && !driver.realtime) await driver.seek(startTick);
  } catch (error) {
    if (!driver.disposed) showMessage(connection, 'error', `${error.message}.`);
  } finally {
    connecting.remove();
  }
  return cleanup;

  function cleanup() {
    keys.abort();
    driver.dispose();
    scene.dispose();
  }

  async function endSession() {
    endButton.disabled = true;
    try {
      await driver.end();
      location.hash = `#/scenarios/${encodeURIComponent(status.scenario)}`;
    } catch (error) {
      endButton.disabled = false;
      showMessage(endMessage, 'error', `Could not end the session: ${errorText(error)}`);
    }
  }
}

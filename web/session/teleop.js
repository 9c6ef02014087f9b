// Driving the robot by keys: while teleop is on, the arrow keys or W A S D held anywhere on the page
// (but in a form field) send the robot a velocity at once (keys up: stop); the panel shows the keys
// held and the velocity sent. A robot that takes no velocity gets a line saying why.
import { h, formatNumber } from '../lib/ui.js';
import { taskActions } from '../lib/tasks.js';
import { errorText, showMessage } from './messages.js';
import { isTyping, plainKey } from './keys.js';

const KEY_DIRECTIONS = { ArrowUp: 'forward', KeyW: 'forward', ArrowDown: 'back', KeyS: 'back', ArrowLeft: 'left', KeyA: 'left',
  ArrowRight: 'right', KeyD: 'right' };

/** Why `robot` cannot be driven by keys, from its action space (null when the session has none for it). */
function whyNotDriven(robot, actionSpace, task) {
  if (!robot.model) return 'Only a robot with a model can be driven.';
  if (!actionSpace) return `The ${robot.model} has no drive to steer.`;
  const size = actionSpace.shape.join(' × ');
  const actions = (task && taskActions(task.name)) ?? `${size} values`;
  return `${task ? `The ${task.name} task's actions are` : 'Its actions are'} ${actions} (action space: ${actionSpace.name} of ${size} `
    + `${actionSpace.dtype}), not a forward speed and a yaw rate: this session is not driven by the velocity keys.`;
}

/**
 * The panel to drive `robot` with `actionSpace`'s top speeds (a robot that `canDrive` only; others
 * get a line saying why not). Keys are heard on the document until `signal` aborts.
 */
export function teleopPanel(driver, { robot, actionSpace, canDrive, signal }) {
  if (!canDrive) {
    return h('section', { class: 'panel teleop', 'aria-label': 'Drive the robot' }, h('h2', {}, `Drive ${robot.id}`),
      h('p', { class: 'muted teleop-unavailable' }, whyNotDriven(robot, actionSpace, driver.status.task)));
  }
  const teleopController = driver.status.controller?.type === 'teleop';
  let teleopOn = teleopController;
  const pressed = new Set();
  const [maxLinear, maxAngular] = actionSpace.high.map(Number);
  const keys = Object.fromEntries(['forward', 'back', 'left', 'right'].map((direction) => [direction,
    h('kbd', { 'data-direction': direction }, { forward: '↑ W', back: '↓ S', left: '← A', right: '→ D' }[direction])]));
  const toggle = h('button', { type: 'button', class: 'secondary', 'aria-pressed': String(teleopOn), onclick: () => {
    teleopOn = !teleopOn;
    toggle.setAttribute('aria-pressed', String(teleopOn));
    toggle.textContent = teleopOn ? 'Release control' : 'Take control';
    if (!teleopOn) releaseKeys();
  } }, teleopOn ? 'Release control' : 'Take control');
  const error = h('p', { class: 'message error', role: 'alert', hidden: true });
  const velocity = h('p', { class: 'teleop-velocity', 'aria-live': 'polite' }, 'v 0.00 m/s · ω 0.00 rad/s');

  function sendVelocity() {
    const linear = ((pressed.has('forward') ? 1 : 0) - (pressed.has('back') ? 1 : 0)) * maxLinear;
    const angular = ((pressed.has('left') ? 1 : 0) - (pressed.has('right') ? 1 : 0)) * maxAngular;
    for (const [direction, key] of Object.entries(keys)) key.classList.toggle('pressed', pressed.has(direction));
    velocity.textContent = `v ${linear.toFixed(2)} m/s · ω ${angular.toFixed(2)} rad/s`;
    driver.command({ robot: robot.id, velocity: { linear, angular } })
      .then(() => { error.hidden = true; }, (reason) => showMessage(error, 'error', `Drive command refused: ${errorText(reason)}`));
  }

  function releaseKeys() {
    if (!pressed.size) return;
    pressed.clear();
    sendVelocity();
  }

  document.addEventListener('keydown', (event) => {
    const which = KEY_DIRECTIONS[event.code];
    if (!which || !teleopOn || !plainKey(event) || isTyping(event.target)) return;
    event.preventDefault();  // no scrolling while driving
    if (pressed.has(which)) return;  // key repeat
    pressed.add(which);
    sendVelocity();
  }, { signal });
  // A key let go anywhere stops its direction, even in a field the focus moved to meanwhile.
  document.addEventListener('keyup', (event) => {
    const which = KEY_DIRECTIONS[event.code];
    if (!which || !pressed.has(which)) return;
    event.preventDefault();
    pressed.delete(which);
    sendVelocity();
  }, { signal });
  window.addEventListener('blur', releaseKeys, { signal });

  return h('section', { class: 'panel teleop', 'aria-label': 'Drive the robot' },
    h('h2', {}, `Drive ${robot.id}`),
    h('p', { class: 'muted' }, teleopController
      ? 'Teleop controller: hold the keys, wherever the focus is but in a text field.'
      : 'Take control, then hold the keys, wherever the focus is but in a text field; the robot keeps to any path it is following.'),
    h('div', { class: 'row teleop-row' }, toggle,
      h('div', { class: 'keys', role: 'group', 'aria-label': 'Driving keys' }, h('span'), keys.forward, h('span'), keys.left, keys.back, keys.right)),
    velocity,
    h('p', { class: 'muted session-note' }, `Top speed ${formatNumber(maxLinear)} m/s, turn ${formatNumber(maxAngular)} rad/s. Keys up: stop. The session moves only while it plays or steps.`),
    error);
}

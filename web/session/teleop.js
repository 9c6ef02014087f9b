// Driving the robot by keys: while teleop is on, the arrow keys or W A S D held in the 3D view send
// the robot a velocity at once (keys up: stop); the panel shows the keys held and the velocity sent.
import { h, formatNumber } from '../lib/ui.js';
import { errorText, showMessage } from './messages.js';

const KEY_DIRECTIONS = { ArrowUp: 'forward', KeyW: 'forward', ArrowDown: 'back', KeyS: 'back', ArrowLeft: 'left', KeyA: 'left',
  ArrowRight: 'right', KeyD: 'right' };

/**
 * The panel to drive `robot` with `actionSpace`'s top speeds (a robot that `canDrive` only; others
 * get a line saying why not). `keyTarget` (the 3D view) takes the keys.
 */
export function teleopPanel(driver, { robot, actionSpace, canDrive, keyTarget }) {
  if (!canDrive) {
    return h('section', { class: 'panel teleop', 'aria-label': 'Drive the robot' }, h('h2', {}, `Drive ${robot.id}`),
      h('p', { class: 'muted' }, robot.model ? `The ${robot.model} has no drive to steer.` : 'Only a robot with a model can be driven.'));
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
    else keyTarget.focus();
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

  keyTarget.addEventListener('keydown', (event) => {
    const which = KEY_DIRECTIONS[event.code];
    if (!which || !teleopOn || event.altKey || event.ctrlKey || event.metaKey) return;
    event.preventDefault();  // no scrolling while driving
    if (pressed.has(which)) return;  // key repeat
    pressed.add(which);
    sendVelocity();
  });
  keyTarget.addEventListener('keyup', (event) => {
    const which = KEY_DIRECTIONS[event.code];
    if (!which || !pressed.has(which)) return;
    event.preventDefault();
    pressed.delete(which);
    sendVelocity();
  });
  keyTarget.addEventListener('blur', releaseKeys);

  return h('section', { class: 'panel teleop', 'aria-label': 'Drive the robot' },
    h('h2', {}, `Drive ${robot.id}`),
    h('p', { class: 'muted' }, teleopController
      ? 'Teleop controller: focus the 3D view and hold the keys.'
      : 'Take control, then focus the 3D view and hold the keys; the robot keeps to any path it is following.'),
    h('div', { class: 'row teleop-row' }, toggle,
      h('div', { class: 'keys', role: 'group', 'aria-label': 'Driving keys' }, h('span'), keys.forward, h('span'), keys.left, keys.back, keys.right)),
    velocity,
    h('p', { class: 'muted session-note' }, `Top speed ${formatNumber(maxLinear)} m/s, turn ${formatNumber(maxAngular)} rad/s. Keys up: stop. The session moves only while it plays or steps.`),
    error);
}

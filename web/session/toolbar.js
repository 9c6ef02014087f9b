// The session's toolbar: playback (play / pause, single steps, reset, speed and the speed actually
// reached) with its keyboard shortcuts, going to a tick, the view of the 3D scene, the clock and run
// state, and the choreography's progress; under it, why a finished session ended.
import { h, formatNumber } from '../lib/ui.js';
import { errorText, showMessage } from './messages.js';
import { playbackShortcuts } from './keys.js';
import { seekGroup } from './seek.js';

/** Playback speeds, simulated seconds per wall-clock second. */
const SPEEDS = [0.25, 0.5, 1, 2, 4];
/** The "actual speed" readout averages over this window, ms. */
const SPEED_WINDOW_MS = 2000;
/** Why a session ended, by its termination. */
const ENDINGS = {
  scenario_end: "its choreography's last step is done",
  timeout: 'it reached its time limit',
  goal: 'its task ended the episode',
};

/**
 * The toolbar and, under it, its shortcuts, the line where stepping errors show and the line that
 * says why the session ended: [toolbar, shortcuts, error line, end line]. `steps` are the choreography's; `onView(view)` turns the scene to 'top' or
 * 'perspective' (`view` the one shown first); the shortcuts listen until `signal` aborts.
 */
export function toolbar(driver, { steps, view: firstView = 'top', onView, signal, replayTicks }) {
  const { status } = driver;
  const speedSamples = [];
  const playButton = h('button', { type: 'button', class: 'play', onclick: () => (driver.playing ? driver.pause() : driver.play()), 'aria-pressed': 'false' }, 'Play');
  const stepButton = h('button', { type: 'button', class: 'secondary', onclick: () => driver.step() },
    status.task ? `Step 1 step (${driver.stepTicks} ticks)` : `Step 1 tick (${formatNumber(driver.dt, 2)} s)`);
  const resetButton = h('button', { type: 'button', class: 'secondary', onclick: () => reset() }, `Reset (seed ${status.seed})`);
  const speedSelect = h('select', { onchange: () => { driver.speed = Number(speedSelect.value); } },
    SPEEDS.map((value) => h('option', { value, selected: value === driver.speed }, `${value}× real time`)));
  const actualSpeed = h('span', { class: 'muted actual-speed' });
  const viewButtons = ['top', 'perspective'].map((view) => h('button', {
    type: 'button', class: 'secondary', 'data-view': view, 'aria-pressed': String(view === firstView),
    onclick: () => {
      for (const button of viewButtons) button.setAttribute('aria-pressed', String(button.dataset.view === view));
      onView(view);
    },
  }, view === 'top' ? 'Top' : 'Perspective'));
  const clock = h('span', { class: 'clock', 'aria-live': 'off' });
  const runState = h('span', { class: 'badge' });
  const stepText = h('span', { class: 'step-name' });
  const stepBar = h('progress', { max: Math.max(steps.length, 1), value: 0, 'aria-label': 'Choreography progress' });
  const playError = h('p', { class: 'message error', role: 'alert', hidden: true });
  const ended = h('p', { class: 'message info session-ended', role: 'status', hidden: true });
  const seeker = seekGroup(driver, { onError: (text) => showMessage(playError, 'error', text), replayTicks });
  const playback = driver.realtime
    ? h('div', { class: 'toolbar-group' }, h('span', {}, `Realtime: the server steps it at ${formatNumber(status.realtime_factor)}× real time.`), resetButton)
    : h('div', { class: 'toolbar-group', role: 'group', 'aria-label': 'Playback' }, playButton, stepButton, resetButton,
      h('label', { class: 'inline' }, 'Speed', speedSelect), actualSpeed);

  async function reset() {
    if (resetButton.disabled) return;
    resetButton.disabled = true;
    try {
      await driver.reset();
      seeker.restart();
      playError.hidden = true;
    } catch (error) {
      showMessage(playError, 'error', `Reset failed: ${errorText(error)}`);
    } finally {
      resetButton.disabled = false;
    }
  }
  const shortcuts = playbackShortcuts(driver, { onReset: reset, signal });

  driver.on('playing', (playing) => {
    playButton.textContent = playing ? 'Pause' : 'Play';
    playButton.setAttribute('aria-pressed', String(playing));
    stepButton.disabled = playing || driver.status.status === 'finished';
    if (playing) speedSamples.length = 0;
    else actualSpeed.textContent = '';
  });
  driver.on('round', () => { playError.hidden = true; });
  driver.on('stepError', (error) => showMessage(playError, 'error', `Stepping failed: ${errorText(error)}`));
  driver.on('status', (next) => {
    clock.textContent = `t = ${next.time.toFixed(2)} s · tick ${next.tick}`;
    clock.dataset.tick = String(next.tick);
    const finished = next.status === 'finished';
    runState.textContent = finished ? `finished: ${(next.termination ?? '').replace('_', ' ')}` : 'running';
    runState.className = `badge ${finished ? 'good' : ''}`;
    if (next.current_step) {
      stepBar.value = next.current_step.index;
      stepText.textContent = `step ${next.current_step.index + 1} of ${steps.length}: ${next.current_step.name}`;
    } else {
      stepBar.value = steps.length;
      stepText.textContent = steps.length ? `all ${steps.length} steps done` : 'no steps';
    }
    // Finished until a reset (or going back) starts it again.
    ended.hidden = !finished;
    if (finished) {
      ended.textContent = `The session ended: ${ENDINGS[next.termination] ?? next.termination}. `
        + 'Press R or Reset to start it again, or go back to an earlier tick.';
    }
    playButton.disabled = finished;
    stepButton.disabled = finished || driver.playing;
    if (driver.playing) {
      const now = performance.now();
      speedSamples.push([now, next.time]);
      while (speedSamples.length > 2 && now - speedSamples[0][0] > SPEED_WINDOW_MS) speedSamples.shift();
      const [t0, s0] = speedSamples[0];
      if (now - t0 > 500) actualSpeed.textContent = `actual ${((next.time - s0) / ((now - t0) / 1000)).toFixed(2)}×`;
    }
  });

  const bar = h('div', { class: 'panel session-toolbar' },
    playback,
    seeker.element,
    h('div', { class: 'toolbar-group', role: 'group', 'aria-label': 'View' }, h('span', { class: 'muted' }, 'View'), viewButtons),
    h('div', { class: 'toolbar-group status-group' }, clock, runState),
    h('div', { class: 'toolbar-group choreography' }, h('span', { class: 'muted' }, 'Choreography'), stepBar, stepText));
  return [bar, shortcuts, playError, ended];
}

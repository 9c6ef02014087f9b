// Going to a tick: a slider over the ticks this page has seen the session reach and a number field,
// both sent as the WebSocket's seek (driver.seek). Back, the session is as it was then, bit for bit;
// forth, a lockstep session runs on without new inputs. A realtime session only goes back (its clock
// runs on from there), and a lockstep one not while it plays.
import { h, formatNumber } from '../lib/ui.js';
import { errorText } from './messages.js';

/** The farthest a lockstep session may go forth in one seek, ticks (docs/api.md, Seek). */
const MAX_SEEK_AHEAD = 100000;

/**
 * The toolbar's "Go to tick" group: {element, restart()}; `onError(text)` shows why a seek failed.
 * After a reset from the page, restart() makes the slider cover the new episode only. A replay of a
 * stored episode (`replayTicks`: its length) has the whole episode on the slider from the start.
 */
export function seekGroup(driver, { onError, replayTicks = 0 }) {
  let reached = Math.max(driver.status.tick, replayTicks);
  let seeking = false;
  let wanted = null;  // the tick to go to next
  // Any tick: with a benchmark task the server goes on to the end of the env step that reaches it.
  const slider = h('input', { type: 'range', class: 'seek-slider', min: 0, max: reached, step: 1, value: reached });
  const field = h('input', { type: 'number', class: 'seek-tick', min: 0, step: 1, value: reached, required: true, inputmode: 'numeric', 'aria-label': 'Tick to go to' });
  const go = h('button', { type: 'submit', class: 'secondary' }, 'Go');
  const form = h('form', { class: 'toolbar-group seek', 'aria-label': 'Go to a tick', onsubmit: (event) => {
    event.preventDefault();
    seek(Number(field.value));
  } },
  h('label', { class: 'inline' }, driver.realtime ? 'Back to tick' : 'Go to tick', slider), field, go);

  const describe = (tick) => slider.setAttribute('aria-valuetext', `tick ${tick}, ${formatNumber(tick * driver.dt, 3)} s`);
  slider.addEventListener('input', () => {
    field.value = slider.value;
    describe(slider.value);
  });
  slider.addEventListener('change', () => seek(Number(slider.value)));

  /** Seeks to `tick`; one asked for while a seek is under way follows it (the last one asked for). */
  async function seek(tick) {
    wanted = tick;
    if (seeking) return;
    seeking = true;
    while (wanted !== null) {
      const target = wanted;
      wanted = null;
      try {
        await driver.seek(target);
      } catch (error) {
        onError(`Going to tick ${target} failed: ${errorText(error)}`);
      }
    }
    seeking = false;
    slider.value = field.value = driver.status.tick;
    describe(driver.status.tick);
  }

  function enable() {
    go.disabled = slider.disabled = field.disabled = driver.playing;
  }

  /** Follows the session: the slider's range grows with the ticks reached; the fields show the tick unless being edited. */
  function follow(status) {
    reached = driver.realtime ? status.tick : Math.max(reached, status.tick);
    slider.max = reached;
    field.max = driver.realtime ? status.tick : status.tick + MAX_SEEK_AHEAD;
    if (![slider, field].includes(document.activeElement)) {
      slider.value = field.value = status.tick;
      describe(status.tick);
    }
  }

  driver.on('status', follow);
  driver.on('playing', enable);
  describe(reached);
  return {
    element: form,
    /** After a reset the ticks reached are those of the new episode. */
    restart() {
      reached = replayTicks;
      follow(driver.status);
    },
  };
}

// The session page's keyboard: shortcuts for playback (Space play / pause, N one step, R reset to the
// session's seed) and which key events are the page's at all. Keys are listened to on the whole
// document while the page is shown, so they work wherever the focus is (after pressing Play, say),
// except while the user types in a field.
import { h } from '../lib/ui.js';

/** A form field takes the keys typed in it (letters, Space, arrows): text boxes, selects, sliders, text areas. */
export function isTyping(target) {
  return target instanceof Element && Boolean(target.closest('input, select, textarea, [contenteditable]:not([contenteditable=false])'));
}

/** Space already presses a focused button, link or summary: the shortcut must not press Play as well. */
function spacePresses(target) {
  return target instanceof Element && Boolean(target.closest('button, a[href], summary, [role=button]'));
}

/** No Alt, Ctrl or Meta: those keys are the browser's (Ctrl+R reloads). */
export const plainKey = (event) => !event.altKey && !event.ctrlKey && !event.metaKey;

/**
 * Space, N and R for `driver` on the document until `signal` aborts (lockstep sessions only play and
 * step; every session resets). `onReset()` resets. Returns the line that lists them.
 */
export function playbackShortcuts(driver, { onReset, signal }) {
  const keys = [
    ...(driver.realtime ? [] : [['Space', 'play / pause', () => (driver.playing ? driver.pause() : driver.play())], ['N', 'one step', () => driver.step()]]),
    ['R', `reset (seed ${driver.status.seed})`, onReset],
  ];
  document.addEventListener('keydown', (event) => {
    if (!plainKey(event) || event.shiftKey || isTyping(event.target)) return;
    const name = event.code === 'Space' ? 'Space' : event.code === 'KeyN' ? 'N' : event.code === 'KeyR' ? 'R' : null;
    const shortcut = keys.find(([key]) => key === name);
    if (!shortcut || (name === 'Space' && spacePresses(event.target))) return;
    event.preventDefault();  // Space would scroll the page
    if (event.repeat && name !== 'N') return;  // holding N steps on; holding Space or R does not toggle or reset over and over
    shortcut[2]();
  }, { signal });
  return h('p', { class: 'muted shortcuts' }, 'Keys: ',
    keys.map(([key, what], index) => [index ? ' · ' : '', h('kbd', {}, key), ` ${what}`]),
    ' (not while typing in a field).');
}

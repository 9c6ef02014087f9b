// The inputs panel: what drove the session so far (GET …/inputs) — runs of env steps and clock ticks,
// commands and placements — newest first, each at its simulated time; and the present moment saved
// as a snapshot file (docs/api.md#snapshot-files), which POST /api/v1/sessions {"snapshot"} or a
// reset with it brings back on any server of the same version.
import { h, formatNumber } from '../lib/ui.js';
import { api } from '../lib/api.js';
import { saveFile } from '../lib/download.js';
import { errorText, showMessage } from './messages.js';

/** The newest inputs shown; the file keeps them all. */
export const SHOWN_INPUTS = 200;
/** The list is fetched again this often while the page shows it, ms. */
const REFRESH_MS = 1000;

const plural = (count, word) => `${count} ${word}${count === 1 ? '' : 's'}`;

/** One input as a sentence. */
export function inputText(input) {
  if ('steps' in input) {
    return `${plural(input.steps, 'env step')}${input.action ? `, action [${input.action.map((value) => formatNumber(value)).join(', ')}]` : ''}`;
  }
  if ('ticks' in input) return `${plural(input.ticks, 'tick')} of the clock`;
  if ('place' in input) return `${input.place} placed at (${formatNumber(input.pose.x)}, ${formatNumber(input.pose.y)})`;
  const command = input.command;
  if (command.human) return `${command.human}: ${command.command}`;
  if (command.velocity) return `${command.robot}: velocity ${formatNumber(command.velocity.linear)} m/s, ${formatNumber(command.velocity.angular)} rad/s`;
  if (command.request) return `${command.robot} asks for ${command.request}`;
  if (command.gripper) return `${command.robot}: gripper ${command.gripper}`;
  return `${command.robot}: joints of ${command.joints.group}`;
}

export function inputsPanel(driver, sessionId) {
  const path = `/api/v1/sessions/${encodeURIComponent(sessionId)}`;
  const list = h('ol', { class: 'input-list', 'aria-label': 'Inputs, newest first', tabindex: 0 });
  const none = h('p', { class: 'muted' }, 'Nothing given yet.');
  const message = h('p', { class: 'message', role: 'status', hidden: true });
  let fetched = 0;
  let fetching = false;

  async function refresh() {
    if (fetching || !list.isConnected || driver.ending) return;
    fetching = true;
    fetched = Date.now();
    try {
      const { items } = await api.get(`${path}/inputs`);
      none.hidden = items.length > 0;
      list.replaceChildren(...items.slice(-SHOWN_INPUTS).reverse().map((input) => h('li', { 'data-tick': input.tick },
        h('span', { class: 'event-time' }, `${(input.tick * driver.dt).toFixed(2)} s`),
        h('span', {}, inputText(input)))));
    } catch (error) {
      showMessage(message, 'error', `The inputs could not be read: ${errorText(error)}`);
    } finally {
      fetching = false;
    }
  }
  // Looked at again once a REFRESH_MS while the page shows it: the session moves, and inputs come from
  // this page's panels and from other clients alike.
  const timer = setInterval(() => {
    if (!list.isConnected && fetched > 0) {
      clearInterval(timer);
      return;
    }
    refresh();
  }, REFRESH_MS);
  driver.on('reset', refresh);

  const save = h('button', { type: 'button', class: 'secondary', onclick: saveSnapshot }, 'Save a snapshot file');
  async function saveSnapshot() {
    save.disabled = true;
    try {
      const taken = await api.post(`${path}/snapshots`);
      const file = await api.get(`${path}/snapshots/${encodeURIComponent(taken.snapshot)}`);
      await api.delete(`${path}/snapshots/${encodeURIComponent(taken.snapshot)}`);  // kept in the file, not among the session's 32
      saveFile(new Blob([`${JSON.stringify(file, null, 2)}\n`], { type: 'application/json' }), `${file.scenario}-${sessionId}-tick${taken.tick}.json`);
      showMessage(message, 'info', `Saved the moment at tick ${taken.tick} (state hash ${taken.state_hash}).`);
    } catch (error) {
      showMessage(message, 'error', `The snapshot could not be saved: ${errorText(error)}`);
    } finally {
      save.disabled = false;
    }
  }
  refresh();
  return h('section', { class: 'panel inputs-panel', 'aria-label': 'Inputs' }, h('h2', {}, 'Inputs'), none, list, h('div', { class: 'row' }, save), message);
}

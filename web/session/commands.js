// Commands from the page: a command to a human, and a request from the robot whose fate (open,
// accepted by someone, dropped) the panel follows through the events.
import { h, formatNumber } from '../lib/ui.js';
import { errorText, showMessage } from './messages.js';

export function humanCommandPanel(driver, humans) {
  const who = h('select', { name: 'human' }, humans.map((human) => h('option', { value: human.id }, human.id)));
  const text = h('input', { name: 'command', type: 'text', placeholder: 'walk 2 3', required: true, autocomplete: 'off', spellcheck: 'false' });
  const result = h('p', { class: 'message', role: 'status', hidden: true });
  const form = h('form', { class: 'human-command', onsubmit: async (event) => {
    event.preventDefault();
    const command = text.value.trim();
    if (!command) return;
    try {
      const reply = await driver.command({ human: who.value, command });
      showMessage(result, 'info', `${who.value}: “${command}” given at tick ${reply.tick}; it runs as the session steps.`);
      result.setAttribute('role', 'status');
    } catch (error) {
      showMessage(result, 'error', errorText(error));
      result.setAttribute('role', 'alert');
    }
  } },
  h('div', { class: 'fields' }, h('label', {}, 'Human', who), h('label', { class: 'grow' }, 'Command', text), h('button', { type: 'submit' }, 'Send')),
  result);
  return h('section', { class: 'panel', 'aria-label': 'Command a human' }, h('h2', {}, 'Command a human'), form,
    h('p', { class: 'muted session-note' }, 'walk X Y (m) · wait S (s) · turn_to RAD · look_at NAME · motion NAME [S] · say S|CLIP · behaviour NAME. The command goes first, then the choreography resumes.'));
}

/** `routines` the robot may ask for; `answered` are those a human answers (the others are dropped at once). */
export function robotRequestPanel(driver, { robot, routines, answered }) {
  let pending = null;  // the page's last request: {routine, tick, id (null until its event names it)}
  const routine = h('select', { name: 'routine' }, routines.map((name) => h('option', { value: name },
    answered.has(name) ? `${name} (a human answers)` : name)));
  const result = h('p', { class: 'message', role: 'status', hidden: true });
  const form = h('form', { class: 'robot-request', onsubmit: async (event) => {
    event.preventDefault();
    try {
      const reply = await driver.command({ robot: robot.id, request: routine.value });
      pending = { routine: routine.value, tick: reply.tick, id: null };
      showMessage(result, 'info', `${robot.id} asked for ${routine.value} at tick ${reply.tick}; who answers shows once the session steps.`);
    } catch (error) {
      showMessage(result, 'error', errorText(error));
    }
  } },
  h('div', { class: 'fields' }, h('label', { class: 'grow' }, 'Routine', routine), h('button', { type: 'submit' }, 'Request')),
  result);

  driver.on('events', (events) => {
    for (const event of events) {
      if (!pending) return;
      if (event.kind === 'request' && pending.id === null && event.subject === robot.id && event.data.routine === pending.routine) {
        pending.id = event.data.request;
        showMessage(result, 'info', `Request #${event.data.request} (${pending.routine}) is open: waiting for an idle human within 3 m…`);
      } else if (event.data?.request === pending.id && pending.id !== null) {
        if (event.kind === 'request_accepted') {
          showMessage(result, 'info', `Request #${pending.id} accepted by ${event.subject} (${formatNumber(event.data.distance)} m away) at ${event.time.toFixed(2)} s.`);
          pending = null;
        } else if (event.kind === 'request_dropped') {
          showMessage(result, 'error', `Request #${pending.id} dropped: ${event.data.reason}.`);
          pending = null;
        }
      }
    }
  });

  return h('section', { class: 'panel', 'aria-label': 'Robot request' }, h('h2', {}, `Request from ${robot.id}`), form,
    h('p', { class: 'muted session-note' }, 'The closest idle human within 3 m performs the routine, when the scenario\'s async answers it; with nobody, it is retried every 5 s and dropped after 30 s.'));
}

// The events panel: the session's events as the driver hears them, newest first, the last MAX_EVENTS.
import { h, formatNumber } from '../lib/ui.js';
import { MAX_EVENTS } from './driver.js';

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

export function eventsPanel(driver) {
  // Focusable: a long list scrolls in its box, which keyboard users scroll once it has the focus.
  const list = h('ol', { class: 'event-list', 'aria-label': 'Events, newest first', tabindex: 0 });
  const none = h('p', { class: 'muted' }, 'No events yet: they appear as the session steps.');
  driver.on('events', (events) => {
    none.hidden = true;
    const items = events.map((event) => h('li', { 'data-kind': event.kind },
      h('span', { class: 'event-time' }, `${event.time.toFixed(2)} s`),
      h('span', { class: `badge ${eventTone(event.kind)}` }, event.kind),
      h('span', { class: 'event-subject' }, event.subject),
      h('span', { class: 'event-data muted' }, shortData(event.data))));
    list.prepend(...items.reverse());
    while (list.children.length > MAX_EVENTS) list.lastElementChild.remove();
  });
  driver.on('reset', () => {
    list.replaceChildren();
    none.hidden = false;
  });
  return h('section', { class: 'panel events-panel', 'aria-label': 'Events' }, h('h2', {}, 'Events'), none, list);
}

// The agents panel: the scenario clock's time of day (when it keeps one), each agent's pose, speed,
// what a person is doing (the activity of their activity model and the room of their daily
// schedule, else the motion they play; the seat they sit on and what they carry), their behaviour (and the robot they react to) and whether it
// is busy, as of the driver's last state (rows of inactive agents hidden), and the robots' open requests.
import { h, scrollBox } from '../lib/ui.js';

export function agentsPanel(driver, agents) {
  const rows = new Map();
  const table = h('table', { class: 'agent-table' },
    h('thead', {}, h('tr', {}, h('th', {}, 'Agent'), h('th', { class: 'number' }, 'x (m)'), h('th', { class: 'number' }, 'y (m)'),
      h('th', { class: 'number' }, 'θ (rad)'), h('th', { class: 'number' }, 'speed (m/s)'), h('th', {}, 'Doing'), h('th', {}, 'Behaviour'), h('th', {}, 'Actions left'))),
    h('tbody', {}, agents.map((agent) => {
      const cells = { x: h('td', { class: 'number' }), y: h('td', { class: 'number' }), theta: h('td', { class: 'number' }),
        speed: h('td', { class: 'number' }), doing: h('td', { class: 'doing' }), behaviour: h('td', { class: 'behaviour' }), busy: h('td', {}) };
      const row = h('tr', { 'data-agent': agent.id, 'data-kind': agent.kind },
        h('th', { scope: 'row' }, h('span', { class: `ss-dot ${agent.kind}` }), agent.id), cells.x, cells.y, cells.theta, cells.speed, cells.doing, cells.behaviour, cells.busy);
      rows.set(agent.id, { row, cells });
      return row;
    })));
  const openRequests = h('p', { class: 'muted open-requests' });
  const clock = h('p', { class: 'muted scenario-clock', hidden: true });
  driver.on('state', (state) => {
    clock.hidden = !state.clock;
    if (state.clock) clock.textContent = `Time of day ${state.clock.time_of_day}, day ${state.clock.day + 1} (clock ×${state.clock.speed})`;
    for (const agent of state.agents) {
      const entry = rows.get(agent.id);
      if (!entry) continue;
      entry.row.hidden = !agent.active;
      // The exact position, for tests and tools; the cells round it.
      entry.row.dataset.x = String(agent.x);
      entry.row.dataset.y = String(agent.y);
      entry.cells.x.textContent = agent.x.toFixed(2);
      entry.cells.y.textContent = agent.y.toFixed(2);
      entry.cells.theta.textContent = agent.theta.toFixed(2);
      entry.cells.speed.textContent = Math.hypot(agent.vx, agent.vy).toFixed(2);
      const doing = [agent.activity ?? agent.motion ?? '', agent.seat ? `on ${agent.seat}` : '', agent.carrying ? `carrying ${agent.carrying}` : '']
        .filter(Boolean).join(' ');
      entry.cells.doing.textContent = agent.room ? (doing ? `${doing} in ${agent.room}` : `in ${agent.room}`) : doing;
      entry.cells.behaviour.textContent = agent.behaviour ? `${agent.behaviour}${agent.reacting_to ? ` (reacting to ${agent.reacting_to})` : ''}` : '';
      entry.cells.busy.textContent = agent.busy ? 'yes' : 'no';
    }
    openRequests.textContent = state.requests.length
      ? `Open requests: ${state.requests.map((r) => `${r.robot} → ${r.routine}`).join(', ')}` : '';
  });
  return h('section', { class: 'panel agents-panel', 'aria-label': 'Agents' }, h('h2', {}, 'Agents'), clock, scrollBox(table, 'Agents'), openRequests);
}

// A benchmark task's panel: the last step's reward and its terms, the episode's return so far, its end.
import { h, formatNumber } from '../lib/ui.js';

export function taskPanel(driver) {
  const { task, tick } = driver.status;
  let episodeReturn = 0;
  let episodeTicks = tick;
  const reward = h('dd', { class: 'number', 'data-field': 'reward' }, '—');
  const total = h('dd', { class: 'number', 'data-field': 'return' }, '0');
  const ending = h('dd', { 'data-field': 'ending' }, task.terminated ? 'terminated' : 'running');
  const terms = h('dl', { class: 'facts task-terms', 'aria-label': 'The last step\'s reward terms' });
  driver.on('reset', (status) => {
    episodeReturn = 0;
    episodeTicks = status.tick;
    reward.textContent = '—';
    total.textContent = '0';
    ending.textContent = 'running';
    terms.replaceChildren();
  });
  driver.on('step', (reply) => {
    if (reply.tick < episodeTicks) episodeReturn = 0;  // another client reset the session
    episodeTicks = reply.tick;
    episodeReturn += reply.reward;
    reward.textContent = formatNumber(reply.reward, 3);
    total.textContent = formatNumber(episodeReturn, 3);
    ending.textContent = reply.terminated ? 'terminated' : reply.truncated ? 'truncated (episode length)' : 'running';
    terms.replaceChildren(...Object.entries(reply.info ?? {}).filter(([key]) => key !== 'tick' && key !== 'time')
      .flatMap(([key, value]) => [h('dt', {}, key.replaceAll('_', ' ')),
        h('dd', { class: typeof value === 'number' ? 'number' : '' }, typeof value === 'number' ? formatNumber(value, 3)
          : Array.isArray(value) ? (value.join(', ') || 'none') : String(value))]));
  });
  return h('section', { class: 'panel task-panel', 'aria-label': 'Task' },
    h('h2', {}, `Task: ${task.name}`),
    h('p', { class: 'muted' }, `One step is ${driver.stepTicks} ticks; the rewards are seed 003's (`, h('code', {}, 'docs/benchmark.md'), ').'),
    h('dl', { class: 'facts' }, h('dt', {}, 'Last reward'), reward, h('dt', {}, 'Return so far'), total, h('dt', {}, 'Episode'), ending),
    terms);
}

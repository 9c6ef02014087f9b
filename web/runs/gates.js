// Gates as the page checks them before the server does: `metric.statistic OP number`, as a run's gates
// and the runs list's conditions (`where`) are written. The statistics are the server's aggregates.

export const STATISTICS = ['count', 'nulls', 'mean', 'std', 'min', 'max', 'ci95_low', 'ci95_high'];
const GATE = /^([A-Za-z0-9_]+)\.([A-Za-z0-9_]+)\s*(==|!=|<=|>=|<|>)\s*(-?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)$/;

/**
 * What is wrong with one gate's text, or null. With `metrics` (loadMetrics()'s byKey) an unknown
 * metric is wrong too; without, only the server can tell.
 */
export function gateProblem(text, metrics = null) {
  const gate = GATE.exec(text);
  if (!gate) return `"${text}" is not metric.statistic OP number, e.g. collisions.max == 0`;
  if (metrics && !metrics.has(gate[1])) return `unknown metric '${gate[1]}'`;
  if (!STATISTICS.includes(gate[2])) return `unknown statistic '${gate[2]}' (${STATISTICS.join(', ')})`;
  return null;
}

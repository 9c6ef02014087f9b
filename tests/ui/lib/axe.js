'use strict';
// axe-core's accessibility rules on a page as it is now: a violation of impact "serious" or "critical"
// fails the test, naming each rule, what it asks for and the elements (CSS selectors) that break it.
// Lesser impacts (best practices, "moderate") are left to review.
const AXE_SCRIPT = require.resolve('axe-core/axe.min.js');

const FAILING_IMPACTS = ['serious', 'critical'];

/** Runs axe on `page` (injected once per document) and throws when it finds serious or critical violations. */
async function assertAccessible(page, where) {
  if (!(await page.evaluate(() => typeof window.axe === 'object'))) await page.addScriptTag({ path: AXE_SCRIPT });
  const violations = await page.evaluate(async (impacts) => {
    const result = await window.axe.run(document, { resultTypes: ['violations'] });
    return result.violations.filter((violation) => impacts.includes(violation.impact)).map((violation) => ({
      id: violation.id,
      impact: violation.impact,
      help: violation.help,
      targets: violation.nodes.map((node) => node.target.join(' ')),
    }));
  }, FAILING_IMPACTS);
  if (!violations.length) return;
  const lines = violations.map((v) => `  ${v.id} (${v.impact}: ${v.help}) at ${v.targets.slice(0, 8).join(', ')}${v.targets.length > 8 ? `, … (${v.targets.length})` : ''}`);
  throw new Error(`accessibility violations on ${where}:\n${lines.join('\n')}`);
}

module.exports = { assertAccessible };

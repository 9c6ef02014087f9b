// Small helpers every page uses: building elements, loading states, error messages, numbers.

/** An element: h('a', {href: '#/', class: 'x'}, 'text', child, …). Attributes starting with "on" are listeners. */
export function h(tag, attributes = {}, ...children) {
  const element = document.createElement(tag);
  for (const [name, value] of Object.entries(attributes ?? {})) {
    if (value === undefined || value === null || value === false) continue;
    if (name.startsWith('on') && typeof value === 'function') element.addEventListener(name.slice(2), value);
    else if (name === 'class') element.className = value;
    else if (value === true) element.setAttribute(name, '');
    else element.setAttribute(name, String(value));
  }
  // Any depth: a child may be a list of lists ([' ', h('code')] per item of a map()).
  for (const child of children.flat(Infinity)) {
    if (child === undefined || child === null || child === false) continue;
    element.append(child instanceof Node ? child : document.createTextNode(String(child)));
  }
  return element;
}

/** A "loading…" line with a spinner, returned so the caller can remove it. */
export function loading(root, what = 'Loading') {
  const line = h('p', { class: 'loading', role: 'status' }, `${what}…`);
  root.append(line);
  return line;
}

/** Where an API error's problem lies, in words: "at /seeds", "line 3, column 7". */
function place(problem) {
  if (problem.pointer) return ['at ', h('code', {}, problem.pointer)];
  if (Number.isInteger(problem.line)) return Number.isInteger(problem.column) ? `line ${problem.line}, column ${problem.column}` : `line ${problem.line}`;
  return null;
}

/**
 * An API error's details as readable lines: each listed problem with its place, else the place of the
 * one problem, and other plain values (a limit, a parameter) that the message does not already name.
 */
function readableDetails(error) {
  const details = error.details ?? {};
  if (Array.isArray(details.errors) && details.errors.length) {
    return h('ul', { class: 'details' }, details.errors.map((problem) => {
      const where = place(problem);
      return h('li', {}, where ? [where, ': '] : null, problem.message);
    }));
  }
  const where = place(details);
  const known = new Set(['pointer', 'line', 'column', 'errors']);
  const others = Object.entries(details).filter(([key, value]) => !known.has(key) && ['string', 'number'].includes(typeof value)
    && !String(error.message).includes(String(value)));
  if (!where && !others.length) return null;
  return h('p', { class: 'details' }, where, where && others.length ? '; ' : null,
    others.map(([key, value], index) => [index ? '; ' : null, `${key.replaceAll('_', ' ')} ${value}`]));
}

/** An error shown as a message where it happened (never only in the console), after what `root` holds. */
export function showError(root, error) {
  const box = h('div', { class: 'message error', role: 'alert' }, h('strong', {}, 'Error: '), error?.message ?? String(error),
    error?.details ? readableDetails(error) : null);
  root.append(box);
  return box;
}

/**
 * A page whose subject could not be loaded, as a page: a heading that says so, the error under it and
 * a way back. `subject` names what was asked for ("Run r1234"), `back` is {href, text} or null.
 */
export function errorPage(root, subject, error, back = null) {
  root.replaceChildren();
  pageTitle(root, error?.status === 404 ? `${subject}: not found` : `${subject}: could not be loaded`);
  showError(root, error);
  if (back) root.append(h('p', {}, h('a', { href: back.href }, back.text)));
}

/** A table in a box that scrolls sideways when the table is wider than its panel; keyboard users scroll it once focused. */
export function scrollBox(table, label) {
  return h('div', { class: 'table-scroll', tabindex: 0, role: 'region', 'aria-label': label }, table);
}

/** A number with a sensible count of digits; '—' for null. */
export function formatNumber(value, digits = 3) {
  if (value === null || value === undefined || Number.isNaN(value)) return '—';
  if (typeof value !== 'number') return String(value);
  if (Number.isInteger(value)) return value.toLocaleString('en');
  const magnitude = Math.abs(value);
  if (magnitude !== 0 && (magnitude < 1e-3 || magnitude >= 1e6)) return value.toExponential(2);
  return value.toLocaleString('en', { maximumSignificantDigits: digits + 1 });
}

/** A page title (h1, focused after each navigation: app.js) and its subtitle. */
export function pageTitle(root, title, subtitle) {
  root.append(h('h1', { tabindex: -1 }, title));
  if (subtitle) root.append(h('p', { class: 'subtitle' }, subtitle));
  document.title = `${title} · hrisim`;
}

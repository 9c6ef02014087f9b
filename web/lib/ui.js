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
  for (const child of children.flat()) {
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

/** An error shown as a message in the page (never only in the console). */
export function showError(root, error) {
  const details = error && error.details && Object.keys(error.details).length
    ? h('pre', { class: 'details' }, JSON.stringify(error.details, null, 2)) : null;
  const box = h('div', { class: 'message error', role: 'alert' }, h('strong', {}, 'Error: '), error.message ?? String(error), details);
  root.prepend(box);
  return box;
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

/** A page title (h1) and its subtitle. */
export function pageTitle(root, title, subtitle) {
  root.append(h('h1', {}, title));
  if (subtitle) root.append(h('p', { class: 'subtitle' }, subtitle));
  document.title = `${title} · hrisim`;
}

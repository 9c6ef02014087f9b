// A page's view (its filters, sorting, chosen columns and plots, a replay's time) kept in the query of
// its address, so that a link reopens the same view. Changes made on the page go into the history
// without app.js showing the page again (pushState and replaceState fire no hashchange); back and
// forward do fire one, and app.js then shows the page as the address it returns to says.

/**
 * `#path?key=value…` of the values given: null and undefined are left out, '' is kept (a list chosen
 * empty is not the default list). Commas and '=' stay readable: URLSearchParams reads them back as they are.
 */
export function hashFor(path, values) {
  const query = new URLSearchParams();
  for (const [key, value] of Object.entries(values)) {
    if (value !== null && value !== undefined) query.set(key, Array.isArray(value) ? value.join(',') : String(value));
  }
  const text = query.toString().replaceAll('%2C', ',').replaceAll('%3D', '=');
  return `#${path}${text ? `?${text}` : ''}`;
}

/** Puts the view in the address: as a new history entry (back returns to the last view), or `replace` the current one. */
export function showInAddress(path, values, { replace = false } = {}) {
  const hash = hashFor(path, values);
  if (hash === location.hash) return;
  history[replace ? 'replaceState' : 'pushState'](null, '', hash);
}

/** A comma-separated list of the query (`fallback` when the key is absent; [] when it is empty). */
export function listOf(query, key, fallback = []) {
  return query.has(key) ? query.get(key).split(',').map((item) => item.trim()).filter(Boolean) : fallback;
}

// Files from the page: the API's downloads (CSV, JUnit XML) as links, and files the page makes itself
// (a report as JSON, a plot as PNG or SVG). A server with a token needs it on the download too, which
// a plain link cannot send: the link then fetches the file with it when clicked.
import { savedToken, authorisedUrl } from './api.js';
import { h } from './ui.js';

function saveUrl(url, filename) {
  const link = h('a', { href: url, download: filename, hidden: true });
  document.body.append(link);
  link.click();
  link.remove();
}

/** Offers `blob` (made by the page) as a download named `filename`. */
export function saveFile(blob, filename) {
  const url = URL.createObjectURL(blob);
  saveUrl(url, filename);
  // The browser reads the object URL after the click returns: freed a while later.
  setTimeout(() => URL.revokeObjectURL(url), 60000);
}

/**
 * A button-like link that downloads the API's `path` as `filename` (the name the server gives it, if it
 * names one: the browser prefers that), with the saved token when there is one.
 */
export function downloadLink(path, filename, text, attributes = {}) {
  const link = h('a', { class: 'button secondary', href: path, download: filename, ...attributes }, text);
  link.addEventListener('click', async (event) => {
    if (!savedToken()) return;
    event.preventDefault();
    if (link.nextElementSibling?.matches('.download-error')) link.nextElementSibling.remove();
    try {
      const url = await authorisedUrl(path);
      saveUrl(url, filename);
      setTimeout(() => URL.revokeObjectURL(url), 60000);
    } catch (error) {
      link.after(h('span', { class: 'download-error field-error', role: 'alert' }, `${filename} could not be downloaded: ${error.message}`));
    }
  });
  return link;
}

/** A button that saves what `make()` gives ({blob, filename}, or a promise of it) as a download. */
export function saveButton(text, make, attributes = {}) {
  return h('button', { type: 'button', class: 'secondary', ...attributes,
    onclick: async () => {
      const { blob, filename } = await make();
      saveFile(blob, filename);
    } }, text);
}

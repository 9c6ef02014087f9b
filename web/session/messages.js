// The session page's message lines: an API error as one line, and a message element filled in place
// (each panel keeps its own, next to what it concerns).

/** An API error as one line, with the JSON pointer it names. */
export function errorText(error) {
  const pointer = error.details?.pointer;
  const where = pointer && !error.message.includes(pointer) ? ` (${pointer})` : '';
  return `${error.message}${where}`;
}

/** Shows `text` in the message element `target` with the tone ('info', 'error') as its class. */
export function showMessage(target, tone, text) {
  target.className = `message ${tone}`;
  target.textContent = text;
  target.hidden = false;
}

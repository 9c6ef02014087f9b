// The REST API from the page: JSON in and out, and the API's errors as exceptions that keep the
// server's message and details (a JSON pointer, an XML line) for showing next to what they concern.

export class ApiError extends Error {
  constructor(status, body) {
    const error = body && body.error ? body.error : { code: 'http', message: `HTTP ${status}`, details: {} };
    super(error.message);
    this.status = status;
    this.code = error.code;
    this.details = error.details ?? {};
  }
}

async function request(method, path, body, headers = {}) {
  const init = { method, headers: { ...headers } };
  if (body !== undefined) {
    if (typeof body === 'string') {
      init.body = body;
    } else {
      init.body = JSON.stringify(body);
      init.headers['content-type'] = 'application/json';
    }
  }
  const response = await fetch(path, init);
  const type = response.headers.get('content-type') ?? '';
  const text = await response.text();
  // 204 and other empty answers carry nothing to parse.
  const parsed = text === '' ? null : type.includes('json') ? JSON.parse(text) : text;
  if (!response.ok) throw new ApiError(response.status, typeof parsed === 'object' ? parsed : null);
  return parsed;
}

export const api = {
  get: (path) => request('GET', path),
  post: (path, body, headers) => request('POST', path, body ?? {}, headers),
  put: (path, body) => request('PUT', path, body ?? {}),
  delete: (path) => request('DELETE', path),
};

/** The WebSocket URL of a session (same host and port as the page). */
export function sessionSocketUrl(id) {
  const scheme = location.protocol === 'https:' ? 'wss' : 'ws';
  return `${scheme}://${location.host}/api/v1/sessions/${encodeURIComponent(id)}/ws`;
}

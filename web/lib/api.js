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

const TOKEN_KEY = 'hrisim.token';

/** The bearer token this browser keeps for a server started with --token ('' when none). */
export function savedToken() {
  return localStorage.getItem(TOKEN_KEY) ?? '';
}

/** Keeps (or, with '', forgets) the token; every later request carries it. */
export function saveToken(token) {
  if (token) localStorage.setItem(TOKEN_KEY, token);
  else localStorage.removeItem(TOKEN_KEY);
}

function authorised(headers) {
  const token = savedToken();
  return token ? { ...headers, authorization: `Bearer ${token}` } : { ...headers };
}

async function request(method, path, body, headers = {}) {
  const init = { method, headers: authorised(headers) };
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
  if (!response.ok) {
    // The page asks for a token once (app.js); the caller still gets its error.
    if (response.status === 401) window.dispatchEvent(new CustomEvent('hrisim-unauthorized'));
    throw new ApiError(response.status, typeof parsed === 'object' ? parsed : null);
  }
  return parsed;
}

export const api = {
  get: (path) => request('GET', path),
  post: (path, body, headers) => request('POST', path, body ?? {}, headers),
  put: (path, body) => request('PUT', path, body ?? {}),
  patch: (path, body) => request('PATCH', path, body ?? {}),
  delete: (path) => request('DELETE', path),
};

/**
 * The WebSocket URL of a session (same host and port as the page). With a token, a one-time ticket
 * from an authenticated POST opens it: a browser cannot put the token on the upgrade request.
 */
export async function sessionSocketUrl(id) {
  const scheme = location.protocol === 'https:' ? 'wss' : 'ws';
  if (!savedToken()) return `${scheme}://${location.host}/api/v1/sessions/${encodeURIComponent(id)}/ws`;
  const ticket = await request('POST', `/api/v1/sessions/${encodeURIComponent(id)}/ws-ticket`, {});
  return `${scheme}://${location.host}${ticket.url}`;
}

/**
 * A URL of the API for an <img> or a download link: the path itself, or with a token (which neither
 * can send) what the path answers, fetched with it, as an object URL.
 */
export async function authorisedUrl(path) {
  if (!savedToken()) return path;
  const response = await fetch(path, { headers: authorised({}) });
  if (!response.ok) throw new ApiError(response.status, null);
  return URL.createObjectURL(await response.blob());
}

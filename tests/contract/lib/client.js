'use strict';
// HTTP and WebSocket clients for a test server. Every reply they receive is checked against the specs
// (lib/contract.js) before a test sees it, so a test only asserts what it is about.
const http = require('node:http');
const WebSocket = require('ws');
const { checkHttpExchange, checkPlainError, checkSocketReply, checkSocketPush, isPushed } = require('./contract');

const REPLY_LIMIT_MS = 30000;

/** One request on a fresh connection; node:http leaves the path as given (`/..` reaches the server). */
function exchange(port, method, target, headers, body) {
  return new Promise((resolve, reject) => {
    const request = http.request({ host: '127.0.0.1', port, method, path: target, headers, agent: false }, (response) => {
      const chunks = [];
      response.on('data', (chunk) => chunks.push(chunk));
      response.on('end', () => {
        const bytes = Buffer.concat(chunks);
        resolve({ status: response.statusCode, headers: response.headers, body: bytes.toString('utf8'), bytes });
      });
      response.on('error', reject);
    });
    request.setTimeout(REPLY_LIMIT_MS, () => request.destroy(new Error(`${method} ${target}: no reply within ${REPLY_LIMIT_MS} ms`)));
    request.on('error', reject);
    request.end(body);
  });
}

class Client {
  /** A client of the server on `port` (or of the one given later to connect()), sending `token` if given. */
  constructor(port, { token } = {}) {
    this.port = port;
    this.token = token;
  }

  connect(port) {
    this.port = port;
  }

  /**
   * Sends a request; `json` is sent as application/json, `body` as it is with `contentType`, plus any
   * `headers`. Resolves to { status, headers, body, bytes, json } after the contract check: `body` as
   * UTF-8 text, `bytes` as received (an image).
   */
  async request(method, target, { json, body, contentType, token = this.token, headers: extraHeaders } = {}) {
    const headers = { ...extraHeaders };
    if (token !== undefined) headers.authorization = `Bearer ${token}`;
    if (json !== undefined) body = JSON.stringify(json);
    if (body !== undefined) headers['content-type'] = contentType ?? 'application/json';
    // A server without tokens takes POST, PUT and PATCH only as JSON (or XML), a body or not.
    else if (method === 'POST' || method === 'PUT' || method === 'PATCH') headers['content-type'] = contentType ?? 'application/json';
    const reply = await exchange(this.port, method, target, headers, body);
    checkHttpExchange({ method, target, json }, reply);
    reply.json = (reply.headers['content-type'] ?? '').startsWith('application/json') && reply.body !== '' ? JSON.parse(reply.body) : undefined;
    return reply;
  }

  get(target, options) { return this.request('GET', target, options); }
  post(target, json, options) { return this.request('POST', target, { json, ...options }); }
  put(target, json, options) { return this.request('PUT', target, { json, ...options }); }
  patch(target, json, options) { return this.request('PATCH', target, { json, ...options }); }
  delete(target, options) { return this.request('DELETE', target, options); }

  /**
   * Opens a session's WebSocket, with the client's token unless `token` says otherwise (null: none),
   * a `ticket` in the query, an `origin` header as a browser sends; a refused upgrade rejects with its
   * { status, headers, body, json } as `refused`.
   */
  openSocket(sessionId, { token = this.token, ticket, origin } = {}) {
    const headers = token == null ? {} : { authorization: `Bearer ${token}` };
    const target = `/api/v1/sessions/${sessionId}/ws${ticket === undefined ? '' : `?ticket=${ticket}`}`;
    const socket = new WebSocket(`ws://127.0.0.1:${this.port}${target}`, { headers, origin, handshakeTimeout: REPLY_LIMIT_MS });
    return new Promise((resolve, reject) => {
      socket.on('open', () => resolve(new SessionSocket(socket)));
      socket.on('error', reject);
      socket.on('unexpected-response', (request, response) => {
        const chunks = [];
        response.on('data', (chunk) => chunks.push(chunk));
        response.on('end', () => {
          const refused = { status: response.statusCode, headers: response.headers, body: Buffer.concat(chunks).toString('utf8') };
          try {
            checkPlainError(`upgrade of ${target} → ${refused.status}`, refused);
            refused.json = JSON.parse(refused.body);
            reject(Object.assign(new Error(`upgrade refused with ${refused.status}`), { refused }));
          } catch (error) {
            reject(error);
          }
          request.destroy();
        });
      });
    });
  }
}

/**
 * A session's WebSocket: each message sent gets the next answer, checked against the spec (a JSON
 * object, or a Buffer for a binary answer); state frames the server pushes, and the binary camera
 * frames that follow them when the subscription has a camera, are checked and kept apart for
 * nextFrame(). A binary message is a pushed camera frame while a state frame's is due, unless the
 * answer awaited is a laser frame (told apart by its magic) or a camera frame: then the two cannot be
 * told apart, and nextFrame() fails.
 */
class SessionSocket {
  constructor(socket) {
    this.socket = socket;
    this.waiting = [];  // { sent, resolve, reject }, oldest first
    this.strayReplies = [];  // answers to nothing sent: there must be none
    this.frames = [];  // pushed frames not yet taken, oldest first
    this.frameWaiters = [];  // resolve functions of nextFrame() calls
    this.problems = [];  // pushed frames that broke the spec
    this.cameraSubscribed = false;  // the last subscribed answer had a camera and a rate above 0
    this.cameraFramesDue = 0;  // pushed state frames whose camera frame has not come yet
    socket.on('message', (data, binary) => {
      let message;
      if (!binary) {
        try {
          message = JSON.parse(data.toString('utf8'));
        } catch {
          message = undefined;  // not JSON: checkSocketReply says so below
        }
        if (isPushed(message)) {
          if (message.type === 'state_frame' && this.cameraSubscribed) this.cameraFramesDue += 1;
          return this.pushed(message);
        }
        // State frames taken after this answer follow it; those taken before came before it.
        if (message?.type === 'subscribed') this.cameraSubscribed = message.rate > 0 && message.camera != null;
      } else if (this.cameraFramesDue > 0) {
        const awaited = this.waiting[0]?.sent?.type;
        if (awaited === 'camera') {
          this.problems.push(new Error('a binary message while both a camera answer and a pushed camera frame are due: they cannot be told apart'));
        } else if (awaited !== 'laser' || data.toString('latin1', 0, 4) === 'HRCF') {
          this.cameraFramesDue -= 1;
          return this.pushed(data, { binary: true });
        }
      }
      const next = this.waiting.shift();
      if (!next) {
        this.strayReplies.push(binary ? `${data.length} binary bytes` : data.toString('utf8'));
        return;
      }
      try {
        if (!binary && message === undefined) throw new Error(`an answer that is not JSON: ${data.toString('utf8').slice(0, 200)}`);
        checkSocketReply(next.sent, binary ? data : message, { binary });
        next.resolve(binary ? data : message);
      } catch (error) {
        next.reject(error);
      }
    });
    socket.on('close', (code) => {
      this.closed = code;
      for (const { reject } of this.waiting.splice(0)) reject(new Error(`the socket closed (${code}) before a reply`));
      for (const wake of this.frameWaiters.splice(0)) wake();
    });
  }

  pushed(frame, { binary = false } = {}) {
    try {
      checkSocketPush(frame, { binary });
    } catch (error) {
      this.problems.push(error);
    }
    this.frames.push(frame);
    for (const wake of this.frameWaiters.splice(0)) wake();
  }

  /** Sends a message (an object as JSON, a string as it is) and resolves to its answer. */
  send(message) {
    const text = typeof message === 'string' ? message : JSON.stringify(message);
    let sent;
    try {
      sent = JSON.parse(text);
    } catch {
      sent = undefined;  // not JSON: only an error may answer it
    }
    if (this.strayReplies.length) return Promise.reject(new Error(`replies to nothing sent: ${this.strayReplies}`));
    return new Promise((resolve, reject) => {
      const timer = setTimeout(() => reject(new Error(`no reply to ${text.slice(0, 200)} within ${REPLY_LIMIT_MS} ms`)), REPLY_LIMIT_MS);
      this.waiting.push({
        sent,
        resolve: (reply) => { clearTimeout(timer); resolve(reply); },
        reject: (error) => { clearTimeout(timer); reject(error); },
      });
      this.socket.send(text);
    });
  }

  /**
   * The oldest pushed frame not yet taken (a state frame's object, or a camera frame's Buffer),
   * waiting up to `withinMs` for one; undefined when none came. Fails when a frame broke the spec.
   */
  async nextFrame(withinMs = REPLY_LIMIT_MS) {
    const deadline = Date.now() + withinMs;
    while (!this.frames.length && this.closed === undefined && Date.now() < deadline) {
      await new Promise((resolve) => {
        const timer = setTimeout(resolve, deadline - Date.now());
        this.frameWaiters.push(() => { clearTimeout(timer); resolve(); });
      });
    }
    if (this.problems.length) throw this.problems[0];
    return this.frames.shift();
  }

  /** Forgets the frames pushed so far. */
  dropFrames() {
    this.frames.length = 0;
  }

  get isOpen() { return this.socket.readyState === WebSocket.OPEN; }

  close() {
    this.socket.close();
  }

  /** Closes it and resolves once it is closed (a forced end after 2 s). */
  async closeAndWait() {
    if (this.closed !== undefined) return;
    await new Promise((resolve) => {
      const timer = setTimeout(() => { this.socket.terminate(); resolve(); }, 2000);
      this.socket.once('close', () => { clearTimeout(timer); resolve(); });
      this.socket.close();
    });
  }
}

// The client every area file uses; contract.test.js connects it to the server it starts.
const api = new Client();

module.exports = { Client, api };

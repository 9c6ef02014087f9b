'use strict';
// HTTP and WebSocket clients for a test server. Every reply they receive is checked against the specs
// (lib/contract.js) before a test sees it, so a test only asserts what it is about.
const http = require('node:http');
const WebSocket = require('ws');
const { checkHttpExchange, checkPlainError, checkSocketReply } = require('./contract');

const REPLY_LIMIT_MS = 30000;

/** One request on a fresh connection; node:http leaves the path as given (`/..` reaches the server). */
function exchange(port, method, target, headers, body) {
  return new Promise((resolve, reject) => {
    const request = http.request({ host: '127.0.0.1', port, method, path: target, headers, agent: false }, (response) => {
      const chunks = [];
      response.on('data', (chunk) => chunks.push(chunk));
      response.on('end', () => resolve({ status: response.statusCode, headers: response.headers, body: Buffer.concat(chunks).toString('utf8') }));
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
   * `headers`. Resolves to { status, headers, body, json } after the contract check.
   */
  async request(method, target, { json, body, contentType, token = this.token, headers: extraHeaders } = {}) {
    const headers = { ...extraHeaders };
    if (token !== undefined) headers.authorization = `Bearer ${token}`;
    if (json !== undefined) body = JSON.stringify(json);
    if (body !== undefined) headers['content-type'] = contentType ?? 'application/json';
    const reply = await exchange(this.port, method, target, headers, body);
    checkHttpExchange({ method, target, json }, reply);
    reply.json = (reply.headers['content-type'] ?? '').startsWith('application/json') && reply.body !== '' ? JSON.parse(reply.body) : undefined;
    return reply;
  }

  get(target, options) { return this.request('GET', target, options); }
  post(target, json, options) { return this.request('POST', target, { json, ...options }); }
  put(target, json, options) { return this.request('PUT', target, { json, ...options }); }
  delete(target, options) { return this.request('DELETE', target, options); }

  /** Opens a session's WebSocket; a refused upgrade rejects with its { status, headers, body, json } as `refused`. */
  openSocket(sessionId, { token = this.token } = {}) {
    const headers = token === undefined ? {} : { authorization: `Bearer ${token}` };
    const target = `/api/v1/sessions/${sessionId}/ws`;
    const socket = new WebSocket(`ws://127.0.0.1:${this.port}${target}`, { headers, handshakeTimeout: REPLY_LIMIT_MS });
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

/** A session's WebSocket in lockstep: each message sent gets the next reply, checked against the spec. */
class SessionSocket {
  constructor(socket) {
    this.socket = socket;
    this.waiting = [];  // { sent, resolve, reject }, oldest first
    this.strayReplies = [];  // replies to nothing sent: lockstep allows none
    socket.on('message', (data, binary) => {
      const next = this.waiting.shift();
      if (!next) {
        this.strayReplies.push(data.toString('utf8'));
        return;
      }
      try {
        if (binary) throw new Error('a binary reply; the spec has only JSON text messages');
        const reply = JSON.parse(data.toString('utf8'));
        checkSocketReply(next.sent, reply);
        next.resolve(reply);
      } catch (error) {
        next.reject(error);
      }
    });
    socket.on('close', (code) => {
      for (const { reject } of this.waiting.splice(0)) reject(new Error(`the socket closed (${code}) before a reply`));
    });
  }

  /** Sends a message (an object as JSON, a string as it is) and resolves to its reply. */
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
      const timer = setTimeout(() => reject(new Error(`no reply to ${text} within ${REPLY_LIMIT_MS} ms`)), REPLY_LIMIT_MS);
      this.waiting.push({
        sent,
        resolve: (reply) => { clearTimeout(timer); resolve(reply); },
        reject: (error) => { clearTimeout(timer); reject(error); },
      });
      this.socket.send(text);
    });
  }

  get isOpen() { return this.socket.readyState === WebSocket.OPEN; }

  close() {
    this.socket.close();
  }
}

// The client every area file uses; contract.test.js connects it to the server it starts.
const api = new Client();

module.exports = { Client, api };

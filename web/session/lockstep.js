// The session's WebSocket as request → answer: answers come one per message, in order, so each one
// settles the oldest waiting promise. Error answers reject with an ApiError.
import { ApiError } from '../lib/api.js';

export class Lockstep {
  /** `onClose(event)` hears of a close the page did not ask for (close() and `closing` silence it). */
  constructor(url, onClose) {
    this.pending = [];
    this.closing = false;
    this.socket = new WebSocket(url);
    this.socket.binaryType = 'arraybuffer';
    this.opened = new Promise((resolve, reject) => {
      this.socket.addEventListener('open', () => resolve(), { once: true });
      this.socket.addEventListener('error', () => reject(new Error('could not open the session\'s WebSocket')), { once: true });
    });
    this.socket.addEventListener('message', (event) => {
      const waiting = this.pending.shift();
      if (!waiting) return;
      if (typeof event.data !== 'string') {
        waiting.resolve(event.data);
        return;
      }
      const message = JSON.parse(event.data);
      if (message.type === 'error') waiting.reject(new ApiError(0, message));
      else waiting.resolve(message);
    });
    this.socket.addEventListener('close', (event) => {
      for (const waiting of this.pending.splice(0)) waiting.reject(new Error('the connection closed'));
      if (!this.closing) onClose(event);
    });
  }

  get open() {
    return this.socket.readyState === WebSocket.OPEN;
  }

  send(message) {
    if (!this.open) return Promise.reject(new Error('not connected to the session'));
    return new Promise((resolve, reject) => {
      this.pending.push({ resolve, reject });
      this.socket.send(JSON.stringify(message));
    });
  }

  close() {
    this.closing = true;
    this.socket.close();
  }
}

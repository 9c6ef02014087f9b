"""A minimal RFC 6455 WebSocket client over a plain socket (standard library only).

Enough for hrisim's session socket: the HTTP/1.1 Upgrade handshake (Sec-WebSocket-Key checked
against Sec-WebSocket-Accept), masked client frames, text and binary messages, fragmented
messages, ping answered with pong, and the close handshake. No extensions, no TLS.
"""

import base64
import hashlib
import json
import os
import socket
import struct
import urllib.parse

_GUID = "258EAFA5-E914-47DA-95CA-C5AB0DC85B11"

OP_CONTINUATION = 0x0
OP_TEXT = 0x1
OP_BINARY = 0x2
OP_CLOSE = 0x8
OP_PING = 0x9
OP_PONG = 0xA


class WebSocketError(Exception):
    """The connection failed, the handshake was refused or the peer broke the protocol.

    For a refused handshake, ``status`` is the HTTP status and ``body`` the response body.
    """

    def __init__(self, message, status=None, body=b"", headers=None):
        super().__init__(message)
        self.status = status
        self.body = body
        self.headers = headers or {}


class WebSocketClosed(WebSocketError):
    """The peer closed the connection (``code`` and ``reason`` from its close frame)."""

    def __init__(self, code=None, reason=""):
        super().__init__("WebSocket closed (code %s%s)" % (code, ": " + reason if reason else ""))
        self.code = code
        self.reason = reason


def accept_key(key):
    """Sec-WebSocket-Accept for a Sec-WebSocket-Key (RFC 6455 section 4.2.2)."""
    digest = hashlib.sha1((key + _GUID).encode("ascii")).digest()
    return base64.b64encode(digest).decode("ascii")


def _mask(payload, key):
    if not payload:
        return b""
    n = len(payload)
    # XOR with the 4-byte key repeated, done on big integers for speed.
    repeated = (key * (n // 4 + 1))[:n]
    masked = int.from_bytes(payload, "little") ^ int.from_bytes(repeated, "little")
    return masked.to_bytes(n, "little")


class WebSocket:
    """A client WebSocket. ``WebSocket(url, headers)`` connects and does the handshake.

    ``url`` is ``ws://host:port/path?query``. ``recv()`` returns ``str`` for text messages and
    ``bytes`` for binary ones; ``send(str)`` sends text, ``send(bytes)`` binary.
    """

    def __init__(self, url, headers=None, timeout=60.0, max_message=64 * 1024 * 1024):
        parts = urllib.parse.urlsplit(url)
        if parts.scheme not in ("ws", "http"):
            raise WebSocketError("only ws:// URLs are supported, not %r" % url)
        self.host = parts.hostname or "127.0.0.1"
        self.port = parts.port or 80
        path = parts.path or "/"
        if parts.query:
            path += "?" + parts.query
        self.max_message = max_message
        self.closed = False
        self._buffer = b""
        self.sock = socket.create_connection((self.host, self.port), timeout=timeout)
        try:
            self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            self._handshake(path, headers or {})
        except BaseException:
            self.sock.close()
            self.closed = True
            raise

    # -- handshake ---------------------------------------------------------------------------
    def _handshake(self, path, headers):
        key = base64.b64encode(os.urandom(16)).decode("ascii")
        host = self.host if self.port == 80 else "%s:%d" % (self.host, self.port)
        if ":" in self.host and not self.host.startswith("["):
            host = "[%s]:%d" % (self.host, self.port)
        lines = [
            "GET %s HTTP/1.1" % path,
            "Host: %s" % host,
            "Upgrade: websocket",
            "Connection: Upgrade",
            "Sec-WebSocket-Key: %s" % key,
            "Sec-WebSocket-Version: 13",
        ]
        for name, value in headers.items():
            lines.append("%s: %s" % (name, value))
        self.sock.sendall(("\r\n".join(lines) + "\r\n\r\n").encode("latin-1"))

        while b"\r\n\r\n" not in self._buffer:
            chunk = self.sock.recv(65536)
            if not chunk:
                raise WebSocketError("connection closed during the WebSocket handshake")
            self._buffer += chunk
            if len(self._buffer) > 1 << 20:
                raise WebSocketError("handshake response too large")
        head, self._buffer = self._buffer.split(b"\r\n\r\n", 1)
        head_lines = head.decode("latin-1").split("\r\n")
        status_line = head_lines[0].split(" ", 2)
        try:
            status = int(status_line[1])
        except (IndexError, ValueError):
            raise WebSocketError("bad handshake status line %r" % head_lines[0])
        response_headers = {}
        for line in head_lines[1:]:
            if ":" in line:
                name, value = line.split(":", 1)
                response_headers[name.strip().lower()] = value.strip()
        if status != 101:
            body = self._read_body(response_headers)
            raise WebSocketError("WebSocket upgrade refused: HTTP %d" % status, status, body,
                                 response_headers)
        if response_headers.get("upgrade", "").lower() != "websocket":
            raise WebSocketError("handshake response without Upgrade: websocket")
        if "upgrade" not in response_headers.get("connection", "").lower():
            raise WebSocketError("handshake response without Connection: Upgrade")
        if response_headers.get("sec-websocket-accept") != accept_key(key):
            raise WebSocketError("wrong Sec-WebSocket-Accept in the handshake response")

    def _read_body(self, headers):
        try:
            length = int(headers.get("content-length", "0"))
        except ValueError:
            length = 0
        try:
            while len(self._buffer) < length:
                chunk = self.sock.recv(65536)
                if not chunk:
                    break
                self._buffer += chunk
        except OSError:
            pass
        body, self._buffer = self._buffer[:length], self._buffer[length:]
        return body

    # -- frames ------------------------------------------------------------------------------
    def _read_exact(self, n):
        while len(self._buffer) < n:
            chunk = self.sock.recv(max(65536, n - len(self._buffer)))
            if not chunk:
                self.closed = True
                raise WebSocketClosed(1006, "connection lost")
            self._buffer += chunk
        data, self._buffer = self._buffer[:n], self._buffer[n:]
        return data

    def _send_frame(self, opcode, payload, fin=True):
        header = bytearray([(0x80 if fin else 0) | opcode])
        n = len(payload)
        if n < 126:
            header.append(0x80 | n)
        elif n < 1 << 16:
            header.append(0x80 | 126)
            header += struct.pack("!H", n)
        else:
            header.append(0x80 | 127)
            header += struct.pack("!Q", n)
        key = os.urandom(4)
        self.sock.sendall(bytes(header) + key + _mask(payload, key))

    def _recv_frame(self):
        b0, b1 = self._read_exact(2)
        fin = bool(b0 & 0x80)
        if b0 & 0x70:
            raise WebSocketError("frame with reserved bits set (no extension was negotiated)")
        opcode = b0 & 0x0F
        masked = bool(b1 & 0x80)
        n = b1 & 0x7F
        if n == 126:
            (n,) = struct.unpack("!H", self._read_exact(2))
        elif n == 127:
            (n,) = struct.unpack("!Q", self._read_exact(8))
        if n > self.max_message:
            raise WebSocketError("frame of %d bytes over the limit" % n)
        key = self._read_exact(4) if masked else None
        payload = self._read_exact(n)
        if key:
            payload = _mask(payload, key)
        return fin, opcode, payload

    # -- messages ----------------------------------------------------------------------------
    def send(self, message):
        """Send a text (``str``) or binary (``bytes``) message as one frame."""
        if self.closed:
            raise WebSocketClosed(None, "already closed")
        if isinstance(message, str):
            self._send_frame(OP_TEXT, message.encode("utf-8"))
        else:
            self._send_frame(OP_BINARY, bytes(message))

    def send_json(self, obj):
        self.send(json.dumps(obj, separators=(",", ":")))

    def recv(self):
        """The next message: ``str`` (text) or ``bytes`` (binary). Pings are answered on the way."""
        opcode = None
        parts = []
        size = 0
        while True:
            fin, op, payload = self._recv_frame()
            if op == OP_PING:
                if len(payload) > 125:
                    raise WebSocketError("ping payload over 125 bytes")
                self._send_frame(OP_PONG, payload)
                continue
            if op == OP_PONG:
                continue
            if op == OP_CLOSE:
                code = struct.unpack("!H", payload[:2])[0] if len(payload) >= 2 else 1005
                reason = payload[2:].decode("utf-8", "replace")
                if not self.closed:
                    try:
                        self._send_frame(OP_CLOSE, payload[:2])
                    except OSError:
                        pass
                self.closed = True
                self.sock.close()
                raise WebSocketClosed(code, reason)
            if op == OP_CONTINUATION:
                if opcode is None:
                    raise WebSocketError("continuation frame without a message")
            elif op in (OP_TEXT, OP_BINARY):
                if opcode is not None:
                    raise WebSocketError("new message inside a fragmented one")
                opcode = op
            else:
                raise WebSocketError("unknown opcode %d" % op)
            parts.append(payload)
            size += len(payload)
            if size > self.max_message:
                raise WebSocketError("message over the limit")
            if fin:
                data = b"".join(parts)
                return data.decode("utf-8") if opcode == OP_TEXT else data

    def recv_json(self):
        message = self.recv()
        if isinstance(message, bytes):
            raise WebSocketError("expected a text message, got %d binary bytes" % len(message))
        return json.loads(message)

    def ping(self, payload=b""):
        self._send_frame(OP_PING, payload)

    def close(self, code=1000, reason=""):
        """Send a close frame, wait briefly for the peer's, and close the socket."""
        if self.closed:
            return
        try:
            self._send_frame(OP_CLOSE, struct.pack("!H", code) + reason.encode("utf-8")[:123])
            self.sock.settimeout(2.0)
            while True:
                _, op, _ = self._recv_frame()
                if op == OP_CLOSE:
                    break
        except (OSError, WebSocketError):
            pass
        finally:
            self.closed = True
            try:
                self.sock.close()
            except OSError:
                pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

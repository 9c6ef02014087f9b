"""Tests of the WebSocket client (hrisim._websocket) against a scripted peer; no hrisim server."""

import os
import socket
import struct
import sys
import threading
import unittest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "clients", "python"))

from hrisim import _websocket as ws  # noqa: E402


def frame(opcode, payload, fin=True):
    head = bytes([(0x80 if fin else 0) | opcode])
    n = len(payload)
    if n < 126:
        head += bytes([n])
    elif n < 65536:
        head += bytes([126]) + struct.pack("!H", n)
    else:
        head += bytes([127]) + struct.pack("!Q", n)
    return head + payload


def read_client_frame(conn, buf):
    def need(n):
        while len(buf[0]) < n:
            chunk = conn.recv(65536)
            if not chunk:
                raise EOFError
            buf[0] += chunk
        data, buf[0] = buf[0][:n], buf[0][n:]
        return data

    b0, b1 = need(2)
    assert b1 & 0x80, "client frames must be masked"
    n = b1 & 0x7F
    if n == 126:
        (n,) = struct.unpack("!H", need(2))
    elif n == 127:
        (n,) = struct.unpack("!Q", need(8))
    key = need(4)
    payload = bytes(b ^ key[i % 4] for i, b in enumerate(need(n)))
    return b0 & 0x0F, payload


class Peer:
    """A one-connection WebSocket server running ``script(conn, buf)`` after the handshake."""

    def __init__(self, script, accept=None, status=101):
        self.listener = socket.socket()
        self.listener.bind(("127.0.0.1", 0))
        self.listener.listen(1)
        self.port = self.listener.getsockname()[1]
        self.received = []
        self.error = None

        def run():
            conn, _ = self.listener.accept()
            try:
                request = b""
                while b"\r\n\r\n" not in request:
                    request += conn.recv(4096)
                head, rest = request.split(b"\r\n\r\n", 1)
                headers = dict(line.split(": ", 1) for line in head.decode().split("\r\n")[1:])
                self.request_headers = headers
                if status != 101:
                    body = b'{"error":{"code":"unauthorized","message":"no","details":{}}}'
                    conn.sendall(b"HTTP/1.1 %d No\r\nContent-Length: %d\r\n\r\n" % (status, len(body)) + body)
                    return
                key = accept or ws.accept_key(headers["Sec-WebSocket-Key"])
                conn.sendall(("HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\n"
                              "Connection: Upgrade\r\nSec-WebSocket-Accept: %s\r\n\r\n" % key).encode())
                script(conn, [rest], self.received)
            except Exception as e:  # pragma: no cover - shown by the test
                self.error = e
            finally:
                conn.close()
                self.listener.close()

        self.thread = threading.Thread(target=run, daemon=True)
        self.thread.start()

    @property
    def url(self):
        return "ws://127.0.0.1:%d/api/v1/sessions/s1/ws" % self.port


class WebSocketTest(unittest.TestCase):
    def test_accept_key_of_rfc_6455(self):
        self.assertEqual(ws.accept_key("dGhlIHNhbXBsZSBub25jZQ=="), "s3pPLMBiTxaQ9kYGzzhZRbK+xOo=")

    def test_messages_fragments_ping_and_close(self):
        big = os.urandom(70000)

        def script(conn, buf, received):
            received.append(read_client_frame(conn, buf))  # the text the client sent
            conn.sendall(frame(ws.OP_TEXT, b'{"type":', fin=False)
                         + frame(ws.OP_PING, b"hi")
                         + frame(ws.OP_CONTINUATION, b'"step"}'))
            received.append(read_client_frame(conn, buf))  # the pong
            conn.sendall(frame(ws.OP_BINARY, big))
            received.append(read_client_frame(conn, buf))  # the binary the client sent
            conn.sendall(frame(ws.OP_CLOSE, struct.pack("!H", 1000) + b"bye"))
            received.append(read_client_frame(conn, buf))  # the close echoed

        peer = Peer(script)
        client = ws.WebSocket(peer.url, timeout=5)
        client.send_json({"type": "step", "n": 1})
        self.assertEqual(client.recv_json(), {"type": "step"})
        self.assertEqual(client.recv(), big)
        client.send(b"\x00\x01" * 200)
        with self.assertRaises(ws.WebSocketClosed) as caught:
            client.recv()
        self.assertEqual(caught.exception.code, 1000)
        self.assertEqual(caught.exception.reason, "bye")
        peer.thread.join(5)
        self.assertIsNone(peer.error)
        self.assertEqual(peer.received[0], (ws.OP_TEXT, b'{"type":"step","n":1}'))
        self.assertEqual(peer.received[1], (ws.OP_PONG, b"hi"))
        self.assertEqual(peer.received[2], (ws.OP_BINARY, b"\x00\x01" * 200))
        self.assertEqual(peer.received[3][0], ws.OP_CLOSE)

    def test_wrong_accept_is_refused(self):
        peer = Peer(lambda conn, buf, received: None, accept="AAAA")
        with self.assertRaises(ws.WebSocketError):
            ws.WebSocket(peer.url, timeout=5)

    def test_refused_upgrade_keeps_status_and_body(self):
        peer = Peer(lambda conn, buf, received: None, status=401)
        with self.assertRaises(ws.WebSocketError) as caught:
            ws.WebSocket(peer.url, timeout=5)
        self.assertEqual(caught.exception.status, 401)
        self.assertIn(b"unauthorized", caught.exception.body)


if __name__ == "__main__":
    unittest.main()

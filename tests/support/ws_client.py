"""A minimal WebSocket client for the bridge's tests (RFC 6455 by hand: the
tests need no package beyond Python's standard library), shared by
tests/web/slow_browser.py and tests/integration/metrics_check.py."""
import base64
import json
import os
import socket
import struct
import sys
import threading


def fail(msg):
    print(f"FAIL: {msg}", flush=True)
    sys.exit(1)


class Ws:
    """A minimal WebSocket client: text frames out (masked), frames in."""

    def __init__(self, port, rcvbuf=None):
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        if rcvbuf:
            # before connect, so that the window offered to the bridge is small from the start
            self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, rcvbuf)
        self.sock.settimeout(15)
        self.sock.connect(("127.0.0.1", port))
        key = base64.b64encode(os.urandom(16)).decode()
        self.sock.sendall((f"GET /ws HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nUpgrade: websocket\r\n"
                           f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\n"
                           "Sec-WebSocket-Version: 13\r\n\r\n").encode())
        self.buf = b""
        while b"\r\n\r\n" not in self.buf:
            self._more()
        head, self.buf = self.buf.split(b"\r\n\r\n", 1)
        if b" 101 " not in head.split(b"\r\n")[0]:
            fail(f"no WebSocket upgrade: {head[:200]!r}")
        self.lock = threading.Lock()
        self.states = []  # seq of every state received
        self.sizes = []   # and its size in bytes
        self.events = []  # the size of every server event (warnings, errors) received
        self.stop = False  # ends read_on()

    def rcvbuf(self):
        return self.sock.getsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF)

    def _more(self):
        d = self.sock.recv(65536)
        if not d:
            raise ConnectionError("the bridge closed the connection")
        self.buf += d

    def _take(self, n):
        while len(self.buf) < n:
            self._more()
        out, self.buf = self.buf[:n], self.buf[n:]
        return out

    def send(self, obj):
        data = json.dumps(obj).encode()
        mask = os.urandom(4)
        n = len(data)
        head = bytes([0x81]) + (bytes([0x80 | n]) if n < 126 else bytes([0x80 | 126]) + struct.pack("!H", n))
        body = bytes(b ^ mask[i % 4] for i, b in enumerate(data))
        with self.lock:
            self.sock.sendall(head + mask + body)

    def recv(self):
        """The next text message as (object, its size in bytes)."""
        text = b""
        while True:
            b0, b1 = self._take(2)
            n = b1 & 0x7F
            if n == 126:
                n = struct.unpack("!H", self._take(2))[0]
            elif n == 127:
                n = struct.unpack("!Q", self._take(8))[0]
            payload = self._take(n)
            op = b0 & 0x0F
            if op == 8:
                raise ConnectionError("the bridge closed the WebSocket")
            if op == 9:  # ping: answer, keep reading
                with self.lock:
                    self.sock.sendall(bytes([0x8A, 0x80 | len(payload)]) + b"\0\0\0\0" + payload)
                continue
            if op in (0, 1):
                text += payload
                if b0 & 0x80:
                    m = json.loads(text)
                    if m.get("op") == "state":
                        self.states.append(m["seq"])
                        self.sizes.append(len(text))
                    elif m.get("op") == "event":
                        self.events.append(len(text))
                    return m, len(text)

    def until(self, pred, what, limit=5000):
        for _ in range(limit):
            m, size = self.recv()
            if m.get("op") == "error":
                fail(f"{what}: the bridge refused: {m}")
            if pred(m):
                return m
        fail(f"{limit} messages without {what}")

    def read_on(self):
        """Reads (and counts) on a thread of its own until stop is set."""
        def run():
            try:
                while not self.stop:
                    self.recv()
            except Exception:  # noqa: BLE001 - the socket closes at the end
                pass
        threading.Thread(target=run, daemon=True).start()

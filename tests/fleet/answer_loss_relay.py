#!/usr/bin/env python3
"""An etcd relay that loses one answer (tests/fleet/failover_test.sh, mode
lost_answer; tests/fleet/lost_claim_test.sh): it forwards every request of
the etcd JSON gateway to the first of ETCD_ENDPOINTS that answers and
returns the answer, except for the first /v3/kv/txn that puts an owners/
key of the kind KIND names (takeover: at epoch 2 or more; claim: at epoch
1): that txn is forwarded and applied by etcd, and its answer is withheld
until the client has given up waiting (its connection is then closed
unanswered), as when an answer is lost on its way under load. A client
that then tries the next endpoint finds the key already written.

  answer_loss_relay.py PORT ETCD_ENDPOINTS PREFIX [KIND=takeover]
Prints "relay: listening" once it listens, and one line for the lost answer.
"""
import base64
import http.client
import http.server
import json
import sys
import threading
import time
import urllib.parse

port = int(sys.argv[1])
upstreams = [urllib.parse.urlsplit(u) for u in sys.argv[2].split(",") if u]
owners_prefix = sys.argv[3].rstrip("/") + "/owners/"
kind = sys.argv[4] if len(sys.argv) > 4 else "takeover"
if kind not in ("takeover", "claim"):
    sys.exit(f"relay: KIND must be takeover or claim, got {kind!r}")
lost = threading.Event()
lock = threading.Lock()


def chosen(path, body):
    """True for a txn that puts an owners/ key of the chosen kind."""
    if path != "/v3/kv/txn":
        return False
    try:
        txn = json.loads(body)
        for op in txn.get("success", []):
            put = op.get("request_put") or op.get("requestPut")
            if not put:
                continue
            key = base64.b64decode(put.get("key", "")).decode()
            value = json.loads(base64.b64decode(put.get("value", "")).decode() or "{}")
            epoch = int(value.get("epoch", 0))
            if key.startswith(owners_prefix) and (epoch >= 2 if kind == "takeover" else epoch == 1):
                return True
    except (ValueError, TypeError, AttributeError):
        return False
    return False


def forward(path, body):
    last = None
    for u in upstreams:
        try:
            c = http.client.HTTPConnection(u.hostname, u.port, timeout=5)
            c.request("POST", path, body, {"Content-Type": "application/json"})
            r = c.getresponse()
            data = r.read()
            c.close()
            return r.status, data
        except OSError as e:
            last = e
    raise OSError(f"no etcd endpoint answered: {last}")


class Relay(http.server.BaseHTTPRequestHandler):
    protocol_version = "HTTP/1.1"

    def log_message(self, *args):
        pass

    def do_POST(self):
        body = self.rfile.read(int(self.headers.get("Content-Length", "0")))
        with lock:
            lose = not lost.is_set() and chosen(self.path, body)
            if lose:
                lost.set()
        try:
            status, data = forward(self.path, body)
        except OSError:
            self.close_connection = True
            return
        if lose:
            print(f"relay: applied a {kind} txn and lost its answer ({data[:120]!r})", flush=True)
            time.sleep(3)  # past the client's attempt timeout: it tries the next endpoint
            self.close_connection = True
            return
        self.send_response(status)
        self.send_header("Content-Type", "application/json")
        self.send_header("Content-Length", str(len(data)))
        self.send_header("Connection", "close")
        self.end_headers()
        self.wfile.write(data)
        self.close_connection = True


server = http.server.ThreadingHTTPServer(("127.0.0.1", port), Relay)
server.daemon_threads = True
print("relay: listening", flush=True)
server.serve_forever()

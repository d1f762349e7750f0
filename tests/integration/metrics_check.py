#!/usr/bin/env python3
"""GET /metrics and /health of groundsim-server (--metrics-port) and of
groundsim-web (on its HTTP port), as Prometheus and a load balancer see them
(docs/metrics.md).

Real processes, real HTTP on 127.0.0.1, in a private network namespace
(netns_run.sh). Sessions come from the real CLI: a realtime one that ends
after 3 s, a realtime one that keeps publishing, a fast one, a lockstep one.
Checked, on the server:

- every scrape passes `promtool check metrics` with nothing printed (no
  lint warnings), has the text format's Content-Type and groundsim_build_info;
- the sessions gauge counts the sessions by mode (realtime 2, fast 1,
  lockstep 1, vectorised 0), and 0 again once they are stopped;
- the states-published counter grows between two scrapes and agrees with
  the heartbeat's frames_published, read from the bus itself (server_status_t
  decoded here: the CLI has no `list --json`): between the heartbeats heard
  before and after a scrape while sessions run, and equal once every session
  is stopped; heartbeats_sent agrees with the heartbeat's seq;
- /health is 200 with {"status":"ok","sessions":4,"load":x};
- POST is 405, /nope is 404; a request header over 8 KiB and a request
  trickled slower than 2 s are closed unanswered; 200 connections that send
  nothing (held open, then closed) do not stop /metrics from answering.

On the bridge, with a WebSocket browser spectating the running session:
browsers 1, sessions watched 1, states forwarded growing, an undecodable
datagram counted as dropped, promtool clean, /health, 405, 404 and the 200
idle connections likewise.

Skips (exit 77) when promtool is missing (Debian: prometheus).
"""
import json
import os
import re
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time
import urllib.error
import urllib.request

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from ws_client import Ws  # noqa: E402

LCM_GROUP, LCM_PORT = "239.255.76.67", 7667
LCM_URL = f"udpm://{LCM_GROUP}:{LCM_PORT}?ttl=0"
METRICS_PORT = 9464  # a namespace of its own: nothing else listens here
CONTENT_TYPE = "text/plain; version=0.0.4"


def fail(msg):
    print(f"FAIL: {msg}", flush=True)
    sys.exit(1)


def check(cond, msg):
    if not cond:
        fail(msg)


# ---- HTTP ---------------------------------------------------------------------

def http(port, path, method="GET", data=None, timeout=5.0):
    """(status, headers, body text) of one request on a fresh connection."""
    req = urllib.request.Request(f"http://127.0.0.1:{port}{path}", method=method, data=data)
    try:
        with urllib.request.urlopen(req, timeout=timeout) as r:
            return r.status, r.headers, r.read().decode()
    except urllib.error.HTTPError as e:
        return e.code, e.headers, e.read().decode()


def parse_metrics(text):
    """{'name{labels}': value} of every sample."""
    out = {}
    for line in text.splitlines():
        if not line or line.startswith("#"):
            continue
        key, value = line.rsplit(" ", 1)
        out[key] = float(value)
    return out


def scrape(port, who):
    status, headers, body = http(port, "/metrics")
    check(status == 200, f"{who}: GET /metrics answered {status}")
    ctype = headers.get("Content-Type", "")
    check(ctype.startswith(CONTENT_TYPE), f"{who}: /metrics Content-Type {ctype!r}, want {CONTENT_TYPE}")
    promtool(body, who)
    m = parse_metrics(body)
    info = [k for k in m if k.startswith("groundsim_build_info{")]
    check(len(info) == 1 and m[info[0]] == 1, f"{who}: no groundsim_build_info 1: {info}")
    check(f'program="{who}"' in info[0] and 'version="' in info[0], f"{who}: build info labels {info[0]}")
    return m


def promtool(body, who):
    p = subprocess.run(["promtool", "check", "metrics"], input=body, capture_output=True, text=True, timeout=30)
    said = (p.stdout + p.stderr).strip()
    if p.returncode != 0 or said:
        print(body)
        fail(f"{who}: promtool check metrics exit {p.returncode}: {said}")


def health(port, who):
    status, headers, body = http(port, "/health")
    check(status == 200, f"{who}: GET /health answered {status}: {body!r}")
    check(headers.get("Content-Type", "").startswith("application/json"), f"{who}: /health is not JSON")
    check(body.count("\n") == 1 and body.endswith("\n"), f"{who}: /health is not one line: {body!r}")
    h = json.loads(body)
    check(h.get("status") == "ok", f"{who}: /health status {h}")
    return h


def hostile(port, who):
    """Methods, paths, and clients that send too much, too slowly, or nothing."""
    status, headers, _ = http(port, "/metrics", method="POST", data=b"x=1")
    check(status == 405, f"{who}: POST /metrics answered {status}, want 405")
    status, _, _ = http(port, "/nope")
    check(status == 404, f"{who}: GET /nope answered {status}, want 404")
    # 200 connections that send nothing, all held open while /metrics is asked for
    idle = []
    for _ in range(200):
        s = socket.create_connection(("127.0.0.1", port), timeout=5)
        idle.append(s)
    t0 = time.monotonic()
    status, _, body = http(port, "/metrics", timeout=10)
    check(status == 200 and "groundsim_build_info" in body,
          f"{who}: /metrics with 200 idle connections open answered {status}")
    print(f"{who}: /metrics answered beside 200 idle connections in {time.monotonic() - t0:.3f} s")
    for s in idle:
        s.close()
    status, _, _ = http(port, "/metrics")
    check(status == 200, f"{who}: /metrics after 200 idle connections answered {status}")


def closed_unanswered(port, send, pause_s=0.0, within_s=6.0):
    """True if the server closes the connection without an HTTP answer."""
    s = socket.create_connection(("127.0.0.1", port), timeout=within_s)
    try:
        for i, part in enumerate(send):
            if i and pause_s:
                time.sleep(pause_s)
            try:
                s.sendall(part)
            except OSError:
                return True  # reset while sending: closed
        got = b""
        while True:
            try:
                d = s.recv(65536)
            except ConnectionResetError:
                return got == b""
            except socket.timeout:
                return False
            if not d:
                return got == b""
            got += d
            if b"HTTP/1.1 200" in got:
                return False
    finally:
        s.close()


def bounds(port, who):
    big = b"GET /metrics HTTP/1.1\r\nHost: x\r\nX-Pad: " + b"a" * 9000 + b"\r\n\r\n"
    check(closed_unanswered(port, [big]), f"{who}: a 9 KiB request was answered")
    slow = [b"GET /metrics HTTP/1.1\r\n", b"Host: x\r\n", b"X-A: 1\r\n", b"\r\n"]
    t0 = time.monotonic()
    check(closed_unanswered(port, slow, pause_s=1.0), f"{who}: a request trickled over 3 s was answered")
    print(f"{who}: a request over 8 KiB closed; one trickled over 3 s closed after {time.monotonic() - t0:.1f} s")


# ---- the heartbeat, from the bus ------------------------------------------------

class Heartbeats:
    """server_status_t as the server publishes it on GROUNDSIM_STATUS (LCM's
    small-message datagram: "LC02", seq, channel, NUL, fingerprint, fields)."""

    def __init__(self):
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        if hasattr(socket, "SO_REUSEPORT"):
            self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEPORT, 1)
        self.sock.bind(("", LCM_PORT))
        mreq = struct.pack("4s4s", socket.inet_aton(LCM_GROUP), socket.inet_aton("127.0.0.1"))
        self.sock.setsockopt(socket.IPPROTO_IP, socket.IP_ADD_MEMBERSHIP, mreq)
        self.sock.settimeout(0.2)
        self.lock = threading.Lock()
        self.beats = []  # (arrival, seq, frames_published)
        self.stop = False
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self):
        while not self.stop:
            try:
                d = self.sock.recv(65536)
            except socket.timeout:
                continue
            if d[:4] != b"LC02":
                continue
            end = d.find(b"\0", 8)
            if end < 0 or d[8:end] != b"GROUNDSIM_STATUS":
                continue
            try:
                p = end + 1 + 8  # past the fingerprint
                utime, seq = struct.unpack_from(">qq", d, p)
                p += 16
                for _ in range(2):  # session_id, server_id
                    n = struct.unpack_from(">i", d, p)[0]
                    p += 4 + n
                workers, max_sessions, load, frames = struct.unpack_from(">iidq", d, p)
            except struct.error:
                continue  # not a heartbeat (the undecodable datagram sent to the bridge)
            with self.lock:
                self.beats.append((time.monotonic(), seq, frames))

    def latest(self):
        with self.lock:
            return self.beats[-1]

    def after(self, t, count=1, timeout=10.0):
        """The count-th heartbeat that arrived after monotonic time t."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            with self.lock:
                later = [b for b in self.beats if b[0] > t]
            if len(later) >= count:
                return later[count - 1]
            time.sleep(0.05)
        fail(f"no heartbeat heard on GROUNDSIM_STATUS within {timeout} s")


# ---- processes ----------------------------------------------------------------

def start(cmd, env=None):
    return subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=None, text=True, env=env)


def cli(env, *args):
    p = subprocess.run([env["GROUNDSIM_CLI"], *args, "--lcm-url", LCM_URL], capture_output=True, text=True,
                       timeout=60, env=env)
    check(p.returncode == 0, f"groundsim {' '.join(args)}: exit {p.returncode}: {p.stderr.strip()}")
    return p.stdout.strip().splitlines()[-1]


def wait_for(pred, what, timeout=15.0):
    deadline = time.monotonic() + timeout
    while True:
        v = pred()
        if v:
            return v
        if time.monotonic() > deadline:
            fail(f"{timeout} s without {what}")
        time.sleep(0.2)


def sessions_by_mode(m):
    return {mode: m.get(f'groundsim_sessions{{mode="{mode}"}}') for mode in ("realtime", "fast", "lockstep", "vectorised")}


# ---- a browser ------------------------------------------------------------------

# Ws: tests/support/ws_client.py


def undecodable_datagram():
    """One LCM datagram on GROUNDSIM_STATUS whose payload decodes as nothing."""
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
    s.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_TTL, 0)
    s.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_IF, socket.inet_aton("127.0.0.1"))
    s.sendto(b"LC02" + struct.pack(">I", 1) + b"GROUNDSIM_STATUS\0" + b"\x01\x02\x03", (LCM_GROUP, LCM_PORT))
    s.close()


# ---- the test -------------------------------------------------------------------

def check_server(env, hb):
    who = "groundsim-server"
    m = scrape(METRICS_PORT, who)
    check(sessions_by_mode(m) == {"realtime": 0, "fast": 0, "lockstep": 0, "vectorised": 0},
          f"{who}: sessions before any create: {sessions_by_mode(m)}")
    check(m.get("groundsim_workers") == 2, f"{who}: groundsim_workers {m.get('groundsim_workers')}, want 2")
    check(m.get("groundsim_sessions_limit") == 16, f"{who}: groundsim_sessions_limit {m.get('groundsim_sessions_limit')}")

    config = env["GROUNDSIM_CONFIG_DIR"]
    ids = [cli(env, "create", f"{config}/plain.json", "--duration", "3"),
           cli(env, "create", f"{config}/plain.json", "--duration", "120"),
           cli(env, "create", f"{config}/hills.json", "--mode", "fast"),
           cli(env, "create", f"{config}/plain.json", "--mode", "lockstep")]
    print(f"{who}: sessions {ids}")
    want = {"realtime": 2, "fast": 1, "lockstep": 1, "vectorised": 0}
    m1 = wait_for(lambda: (lambda m: m if sessions_by_mode(m) == want else None)(scrape(METRICS_PORT, who)),
                  f"the sessions gauge at {want}")
    time.sleep(1.2)
    m2 = scrape(METRICS_PORT, who)
    a, b = m1["groundsim_states_published_total"], m2["groundsim_states_published_total"]
    check(b > a, f"{who}: states published did not grow between two scrapes 1.2 s apart: {a} -> {b}")
    print(f"{who}: states published {a:.0f} -> {b:.0f} between two scrapes")

    # agrees with the heartbeat: heard before <= scraped <= heard after
    # (the second heartbeat after the scrape: sent after it, heartbeats are 1 s apart)
    before = hb.latest()
    m3 = scrape(METRICS_PORT, who)
    t = time.monotonic()
    after = hb.after(t, count=2)
    s = m3["groundsim_states_published_total"]
    check(before[2] <= s <= after[2],
          f"{who}: states published {s:.0f} outside the heartbeats around it ({before[2]}, {after[2]})")
    check(m3["groundsim_heartbeats_sent_total"] >= before[1] + 1,
          f"{who}: heartbeats sent {m3['groundsim_heartbeats_sent_total']}, heard seq {before[1]}")
    print(f"{who}: heartbeat frames_published {before[2]} <= scraped {s:.0f} <= {after[2]}")

    h = health(METRICS_PORT, who)
    check(h.get("sessions") == 4, f"{who}: /health sessions {h}")
    check(isinstance(h.get("load"), (int, float)) and 0 <= h["load"] <= 1, f"{who}: /health load {h}")
    print(f"{who}: /health {h}")

    hostile(METRICS_PORT, who)
    bounds(METRICS_PORT, who)
    return ids, m3


def finish_server(env, hb, ids):
    who = "groundsim-server"
    for sid in ids:
        cli(env, "stop", sid)
    m = wait_for(lambda: (lambda m: m if sum(v for v in sessions_by_mode(m).values()) == 0 else None)(
        scrape(METRICS_PORT, who)), "the sessions gauge at 0 after the stops")
    # nothing publishes now: the next heartbeat says exactly what a scrape says
    time.sleep(1.5)
    m = scrape(METRICS_PORT, who)
    t = time.monotonic()
    beat = hb.after(t, count=1)
    check(m["groundsim_states_published_total"] == beat[2],
          f"{who}: states published {m['groundsim_states_published_total']:.0f}, heartbeat says {beat[2]}")
    print(f"{who}: sessions stopped: states published {beat[2]} in the scrape and in the heartbeat")


def check_bridge(port, session):
    who = "groundsim-web"
    m0 = scrape(port, who)
    check(m0.get("groundsim_web_browsers") == 0, f"{who}: browsers before any connects: {m0.get('groundsim_web_browsers')}")
    ws = Ws(port)
    ws.until(lambda m: m["op"] == "welcome", "the welcome")
    ws.send({"op": "join", "session": session, "role": "spectate", "vehicle": -1})
    ws.until(lambda m: m["op"] == "joined", "joined")
    ws.until(lambda m: m["op"] == "state", "a state")
    ws.read_on()
    m1 = wait_for(lambda: (lambda m: m if m.get("groundsim_web_sessions_watched") == 1 else None)(scrape(port, who)),
                  "one session watched")
    check(m1.get("groundsim_web_browsers") == 1, f"{who}: browsers {m1.get('groundsim_web_browsers')}, want 1")
    undecodable_datagram()
    time.sleep(1.0)
    m2 = scrape(port, who)
    a, b = m1["groundsim_web_states_forwarded_total"], m2["groundsim_web_states_forwarded_total"]
    check(a >= 1 and b > a, f"{who}: states forwarded did not grow: {a} -> {b}")
    check(m2["groundsim_web_sent_bytes_total"] > m1["groundsim_web_sent_bytes_total"], f"{who}: bytes sent did not grow")
    check(m2["groundsim_web_lcm_messages_dropped_total"] >= 1,
          f"{who}: an undecodable datagram was not counted: {m2['groundsim_web_lcm_messages_dropped_total']}")
    check("groundsim_web_states_skipped_total" in m2, f"{who}: no states skipped counter")
    print(f"{who}: states forwarded {a:.0f} -> {b:.0f}, dropped {m2['groundsim_web_lcm_messages_dropped_total']:.0f}")
    h = health(port, who)
    check(h.get("browsers") == 1 and h.get("sessions_watched") == 1, f"{who}: /health {h}")
    print(f"{who}: /health {h}")
    hostile(port, who)
    ws.stop = True
    ws.sock.close()
    wait_for(lambda: (lambda m: m if m.get("groundsim_web_browsers") == 0 else None)(scrape(port, who)),
             "browsers back at 0 after the WebSocket closed")


def main():
    if not shutil.which("promtool"):
        print("SKIP: promtool not found (Debian: apt-get install prometheus; scripts/setup.sh installs it)", flush=True)
        sys.exit(77)
    env = dict(os.environ)
    tmp = tempfile.mkdtemp(prefix="groundsim-metrics-")
    env["HOME"] = tmp  # the CLI's token file
    procs = []
    try:
        hb = Heartbeats()
        server = start([env["GROUNDSIM_SERVER"], "--lcm-url", LCM_URL, "--workers", "2", "--max-sessions", "16",
                        "--metrics-port", str(METRICS_PORT), "--quiet"])
        procs.append(server)
        line = server.stdout.readline()
        check("groundsim-server ready" in line, f"the server printed no ready line: {line!r}")
        for _ in range(5):
            line = server.stdout.readline()
            if line.startswith("metrics on"):
                break
        check(f"http://127.0.0.1:{METRICS_PORT}/metrics" in line, f"the server printed no metrics line: {line!r}")
        hb.after(time.monotonic() - 1e9)  # the bus works: a heartbeat is heard
        ids, _ = check_server(env, hb)

        static = os.path.join(tmp, "dist")
        os.mkdir(static)
        with open(os.path.join(static, "index.html"), "w") as f:
            f.write("<!doctype html><title>groundsim</title>\n")
        bridge = start([env["GROUNDSIM_WEB"], "--lcm-url", LCM_URL, "--bind", "127.0.0.1", "--port", "0",
                        "--static", static, "--quiet"])
        procs.append(bridge)
        line = bridge.stdout.readline()
        mt = re.search(r"open http://127\.0\.0\.1:(\d+)/", line)
        check(mt, f"the bridge printed no URL: {line!r}")
        check_bridge(int(mt.group(1)), ids[1])

        finish_server(env, hb, ids)

        # a stopped server answers nothing (its /health says 503 only while it stops its sessions:
        # too short a moment to catch here)
        server.send_signal(signal.SIGTERM)
        check(server.wait(15) == 0, f"the server exited {server.returncode} on SIGTERM")
        try:
            http(METRICS_PORT, "/health", timeout=2)
            fail("the metrics port still answers after the server exited")
        except (urllib.error.URLError, ConnectionError, OSError):
            pass
        hb.stop = True
        print("PASS", flush=True)
    finally:
        for p in procs:
            if p.poll() is None:
                p.send_signal(signal.SIGTERM)
        for p in procs:
            try:
                p.wait(5)
            except subprocess.TimeoutExpired:
                p.kill()
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()

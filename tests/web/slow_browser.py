#!/usr/bin/env python3
"""A browser that stops reading never blocks another, and gets the newest
state, not a backlog, when it reads again.

Two WebSocket clients on the real groundsim-server and groundsim-web (run
in a private network namespace by netns_run.sh): the fast one creates an
8-sedan session publishing at 60 Hz and reads all along; the slow one, with a
4 KiB receive buffer, spectates it and stops reading for 4 s. Verdicts are
counts and sequence numbers, checked against the bridge's own account of
each browser (the pong: states written, states replaced by a newer one
before being written, bytes waiting), never durations:

- each client's gaps in seq are states the bridge says it skipped for it,
  and the fast one got every state the bridge did not skip (the pong's
  count is exactly what it read);
- the slow one's stale states after resuming (published before it resumed)
  are no more bytes than the kernel's buffers between them hold (the
  bridge's send buffer and the client's receive buffer), far fewer than
  were published while it slept: the bridge skipped the rest;
- while it slept, the bridge held no more for it than one message per slot;
- the bridge still serves a new client afterwards.

The clients are raw sockets (RFC 6455 framing by hand): Python sets the
small receive buffer a browser's socket API cannot.
"""
import os
import re
import signal
import subprocess
import sys
import threading
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from ws_client import Ws  # noqa: E402

LCM_URL = "udpm://239.255.76.67:7667?ttl=0"
PAUSE_S = 4.0       # the slow client's pause, at least
PAUSE_MAX_S = 90.0  # and at most, while too few states were published to judge (a slow server: sanitizers)
RCVBUF = 4096


def fail(msg):
    print(f"FAIL: {msg}", flush=True)
    sys.exit(1)


def start(cmd):
    return subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=None, text=True)


def gaps(seqs):
    return (seqs[-1] - seqs[0] + 1) - len(seqs) if seqs else 0


def main():
    env = os.environ
    server = start([env["GROUNDSIM_SERVER"], "--lcm-url", LCM_URL, "--workers", "1"])
    procs = [server]
    try:
        # a create published before the server has subscribed would be lost
        line = server.stdout.readline()
        if "groundsim-server ready" not in line:
            fail(f"the server printed no ready line: {line!r}")
        bridge = start([env["GROUNDSIM_WEB"], "--lcm-url", LCM_URL, "--bind", "127.0.0.1", "--port", "0"])
        procs.append(bridge)
        line = bridge.stdout.readline()
        m = re.search(r"open http://127\.0\.0\.1:(\d+)/", line)
        if not m:
            fail(f"the bridge printed no URL: {line!r}")
        run(int(m.group(1)))
    finally:
        for p in procs:
            p.send_signal(signal.SIGTERM)
        for p in procs:
            try:
                p.wait(5)
            except subprocess.TimeoutExpired:
                p.kill()


def run(port):
    fast = Ws(port)
    fast.until(lambda m: m["op"] == "welcome", "the welcome")
    # eight sedans: big states, and cheap enough (dt 4 ms) to keep real time
    # under ASan, where eight 20-point ring cars at dt 5e-5 reach ~1/60 of it
    fast.send({"op": "create", "config": "sedan.json", "mode": "realtime", "publish_rate": 60,
               "vehicles": 8, "drive": True})
    joined = fast.until(lambda m: m["op"] == "joined", "the created session joined")
    session = joined["session"]

    # the fast client reads all along, on its own thread
    fast_pongs, stop, errors = [], threading.Event(), []

    def read_fast():
        try:
            while not stop.is_set():
                m, _ = fast.recv()
                if m["op"] == "pong":
                    fast_pongs.append((m, len(fast.states)))
        except Exception as e:  # noqa: BLE001 - reported as the verdict
            if not stop.is_set():
                errors.append(repr(e))

    reader = threading.Thread(target=read_fast, daemon=True)
    reader.start()

    slow = Ws(port, rcvbuf=RCVBUF)
    slow.until(lambda m: m["op"] == "welcome", "the slow client's welcome")
    slow.send({"op": "join", "session": session, "role": "spectate", "vehicle": -1})
    slow.until(lambda m: m["op"] == "joined", "the slow client joined")
    slow.until(lambda m: len(slow.states) >= 10, "10 states")
    # what the kernel can hold for the slow client: the pause lasts until
    # states worth several times that were published (a slow server, e.g.
    # under ASan, publishes fewer than the 60 Hz asked for)
    slow.send({"op": "ping", "t": 0})
    first_pong = slow.until(lambda m: m["op"] == "pong", "the slow client's first pong")
    kernel = 2 * first_pong["send_buffer"] + 64 * 1024 + slow.rcvbuf()
    before = len(slow.states)
    events_before = len(slow.events)
    paused_at = max(fast.states[-1], slow.states[-1])

    # the slow client reads nothing; the bridge keeps writing to the fast one
    pause_start = time.monotonic()
    while True:
        time.sleep(0.05)
        paused = time.monotonic() - pause_start
        sizes = fast.sizes or [1]
        enough = (fast.states[-1] - paused_at) * sum(sizes) / len(sizes) > 3 * kernel
        if errors or paused >= PAUSE_MAX_S or (paused >= PAUSE_S and enough):
            break
    slow.send({"op": "ping", "t": 1})
    resumed_at = fast.states[-1]
    # reads what the kernel held, then fresh states (bounded: until() gives up)
    stalled_pong = None
    for _ in range(2000):
        m, _ = slow.recv()
        if m["op"] == "pong" and not stalled_pong:
            stalled_pong = (m, len(slow.states))
            # the server's events in the bridge's ordered queue when it answered
            # the ping (a slow server warns of overruns): delivered before the pong
            stalled_events = slow.events[events_before:]
        if stalled_pong and slow.states[-1] > resumed_at:
            break
    after = slow.states[before:]
    stale = [k for k, seq in enumerate(after) if seq <= resumed_at]
    stale_bytes = sum(slow.sizes[before + k] for k in stale)

    # final accounts: each pong says how many states the bridge wrote before it
    slow.send({"op": "ping", "t": 2})
    final_slow = slow.until(lambda m: m["op"] == "pong", "the slow client's last pong")
    slow_seqs = list(slow.states)
    fast.send({"op": "ping", "t": 2})
    deadline = time.monotonic() + 60  # a ceiling for a hung bridge only
    while not fast_pongs and time.monotonic() < deadline and not errors:
        time.sleep(0.01)
    stop.set()
    if errors:
        fail(f"the fast client lost its connection: {errors[0]}")
    if not fast_pongs:
        fail("the fast client got no pong")
    final_fast, fast_read = fast_pongs[-1]

    # a new client is served: the bridge neither stalled nor fell over
    late = Ws(port)
    late.until(lambda m: m["op"] == "welcome", "a new client's welcome")
    late.send({"op": "ping", "t": 3})
    late.until(lambda m: m["op"] == "pong", "a new client's pong")

    published = resumed_at - paused_at
    sizes = fast.sizes + slow.sizes
    smallest = min(sizes)
    # what the kernel can hold between them: the bridge's send buffer (Linux
    # books twice the SO_SNDBUF set, and lets one 64 KiB segment past it),
    # the client's receive buffer (getsockopt reports the doubled figure)
    send_buffer = stalled_pong[0]["send_buffer"]
    bound = 2 * send_buffer + 64 * 1024 + slow.rcvbuf()
    fs = fast.states[:fast_read]
    print(f"session {session}: states of {smallest}-{max(sizes)} bytes; {published} published while the slow "
          f"client slept ({paused:.1f} s)")
    print(f"fast: read {len(fs)} states, seq {fs[0]}..{fs[-1]}, {gaps(fs)} gaps; bridge: "
          f"{final_fast['states_sent']} written, {final_fast['states_skipped']} skipped")
    print(f"slow: read {len(slow_seqs)} states, {gaps(slow_seqs)} gaps; bridge: {final_slow['states_sent']} written, "
          f"{final_slow['states_skipped']} skipped; after resuming {len(stale)} stale states ({stale_bytes} bytes, "
          f"the kernel holds at most {bound}), then seq {after[-1]} (newest when it resumed: {resumed_at})")
    print(f"while it slept the bridge held {stalled_pong[0]['waiting_bytes']} bytes and "
          f"{stalled_pong[0]['queued']} ordered messages for it")

    if published * sum(sizes) / len(sizes) <= 2 * bound:
        fail(f"only {published} states published while the slow client slept: the test cannot tell "
             f"skipping from buffering ({bound} bytes in the kernel)")
    if final_fast["states_sent"] != fast_read:
        fail(f"the fast client read {fast_read} states before its pong, the bridge wrote {final_fast['states_sent']}")
    if gaps(fs) > final_fast["states_skipped"]:
        fail(f"the fast client missed {gaps(fs)} states, the bridge skipped {final_fast['states_skipped']} for it")
    # A client that reads is skipped too whenever it or the bridge waits for
    # the CPU (on a busy machine, a quarter of the states: the newest-only
    # slot at work); one the sleeper held up would be skipped like the
    # sleeper, nearly every state
    if final_fast["states_skipped"] * 2 > final_slow["states_skipped"]:
        fail(f"the fast client was skipped {final_fast['states_skipped']} states, the one that did not read "
             f"{final_slow['states_skipped']} ({published} were published while it slept)")
    if stalled_pong[0]["states_sent"] != stalled_pong[1]:
        fail(f"the slow client read {stalled_pong[1]} states before its pong, the bridge wrote "
             f"{stalled_pong[0]['states_sent']}")
    if gaps(slow_seqs) > final_slow["states_skipped"]:
        fail(f"the slow client missed {gaps(slow_seqs)} states, the bridge skipped {final_slow['states_skipped']}")
    if stale_bytes > bound:
        fail(f"after resuming the slow client read {len(stale)} stale states, {stale_bytes} bytes: more than "
             f"the kernel's buffers hold ({bound})")
    if final_slow["states_skipped"] < published - len(stale) - 2:
        fail(f"the bridge skipped {final_slow['states_skipped']} states for the slow client; "
             f"{published} were published while it slept")
    if after[-1] <= resumed_at:
        fail(f"the slow client's newest state {after[-1]} is older than the newest when it resumed ({resumed_at})")
    # the state slot, the car slot, the lobby and a few replies, and the
    # session's events, which are never dropped
    limit = 2 * max(sizes) + 64 * 1024 + sum(stalled_events)
    if stalled_pong[0]["queued"] > 4 + len(stalled_events) or stalled_pong[0]["waiting_bytes"] > limit:
        fail(f"the bridge held {stalled_pong[0]['queued']} messages, {stalled_pong[0]['waiting_bytes']} bytes "
             "for a browser that did not read")
    print("PASS", flush=True)


if __name__ == "__main__":
    main()

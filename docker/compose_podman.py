#!/usr/bin/env python3
"""Runs the services of a compose file with plain `podman run`, for hosts
without a compose tool that can start `network_mode: host` services (Debian's
podman-compose 1.0.3 cannot). Only what docker/compose*.y*ml use: image,
network_mode host, entrypoint, command, environment, named volumes,
stop_signal, stop_grace_period, restart. Healthchecks and depends_on are not
translated (podman's healthchecks need systemd timers): list the services in
dependency order and check readiness yourself. Containers are named
PREFIX-SERVICE, volumes PREFIX-VOLUME.

  docker/compose_podman.py docker/compose.fleet.yml up [SERVICE...]
  docker/compose_podman.py docker/compose.fleet.yml down      # podman stop (SIGTERM, grace), rm; volumes kept
  docker/compose_podman.py docker/compose.fleet.yml print     # the commands only
Options (before the file): --prefix P (default gsf).
"""
import shlex
import subprocess
import sys

import yaml


def seconds(v):
    v = str(v)
    return int(float(v[:-1]) if v.endswith("s") else float(v))


def run_command(prefix, name, s):
    assert s.get("network_mode") == "host", f"{name}: only network_mode: host is supported"
    cmd = ["podman", "run", "-d", "--name", f"{prefix}-{name}", "--network", "host"]
    if "stop_grace_period" in s:
        cmd += ["--stop-timeout", str(seconds(s["stop_grace_period"]))]
    if "stop_signal" in s:
        cmd += ["--stop-signal", s["stop_signal"]]
    if "restart" in s:
        cmd += ["--restart", s["restart"]]
    env = s.get("environment", {})
    for k, v in (env.items() if isinstance(env, dict) else (e.split("=", 1) for e in env)):
        cmd += ["-e", f"{k}={v}"]
    for v in s.get("volumes", []):
        vol, path = v.split(":", 1)
        cmd += ["-v", (f"{prefix}-{vol}" if not vol.startswith(("/", ".")) else vol) + ":" + path]
    ep = s.get("entrypoint")
    if ep:
        ep = [ep] if isinstance(ep, str) else ep
        cmd += ["--entrypoint", ep[0]]
    cmd.append(s["image"])
    cmd += (ep[1:] if ep else []) + list(s.get("command", []))
    return cmd


def main(argv):
    prefix = "gsf"
    if argv[:1] == ["--prefix"]:
        prefix, argv = argv[1], argv[2:]
    if len(argv) < 2 or argv[1] not in ("up", "down", "print"):
        sys.exit(__doc__)
    doc = yaml.safe_load(open(argv[0]))
    names = argv[2:] or list(doc["services"])
    if argv[1] == "down":
        names = list(reversed(names))
        subprocess.run(["podman", "stop", *[f"{prefix}-{n}" for n in names]], check=False)
        subprocess.run(["podman", "rm", *[f"{prefix}-{n}" for n in names]], check=False)
        return
    for n in names:
        cmd = run_command(prefix, n, doc["services"][n])
        print(" ".join(shlex.quote(c) for c in cmd), flush=True)
        if argv[1] == "up":
            subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)


if __name__ == "__main__":
    main(sys.argv[1:])

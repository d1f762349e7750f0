"""make_remote_vec(..., shards=3) on a fleet of 3 servers (issue 20,
docs/fleet.md): the shards are placed on 3 different servers, and the same
seed and actions give make_vec's bits. Run by shards_test.sh in a lab host;
prints the per-step time against the same batch in process (a figure)."""
import os
import subprocess
import sys
import time

import numpy as np

import groundsim

URL = "udpm://239.255.76.67:7667?ttl=1"
task = sys.argv[1]
n, shards, steps = 12, 3, 60

local = groundsim.make_vec(task, n, num_threads=2)
remote = groundsim.make_remote_vec(task, n, lcm_url=URL, shards=shards, timeout=10)

# the other servers' heartbeats (1 Hz) list their new sessions: listed
# again until the shards are on as many servers (or 60 s have passed: a
# ceiling for a hung fleet, not a verdict on its speed)
deadline = time.monotonic() + 60
while True:
    listing = subprocess.run([os.environ["GROUNDSIM"], "list", "--lcm-url", URL, "--timeout", "5"],
                             capture_output=True, text=True, check=True).stdout.splitlines()[1:]
    servers = {row.split()[-3] for row in listing if row.split()[2] == "vectorised"}
    if len(servers) >= shards or time.monotonic() > deadline:
        break
    time.sleep(0.25)
print(f"{shards} shards on servers {sorted(servers)}")
assert len(servers) == shards, listing

rng = np.random.default_rng(7)
low, high = local.single_action_space.low, local.single_action_space.high
seq = [rng.uniform(low, high, size=(n, low.size)).astype(np.float32) for _ in range(steps)]
for seed in (11, 12):
    a, b = local.reset(seed=seed)[0], remote.reset(seed=seed)[0]
    assert a.tobytes() == b.tobytes(), "reset observations differ"
    for k, act in enumerate(seq):
        x, y = local.step(act), remote.step(act)
        for u, v, what in zip(x[:4], y[:4], ("obs", "reward", "terminated", "truncated")):
            assert np.asarray(u).tobytes() == np.asarray(v).tobytes(), f"seed {seed} step {k}: {what} differ"
print(f"{2 * steps} steps of {n} envs bit-identical to make_vec")

def ms_per_step(env, actions):
    t = time.perf_counter()
    for act in actions:
        env.step(act)
    return 1e3 * (time.perf_counter() - t) / len(actions)


print(f"per step: in process {ms_per_step(local, seq):.2f} ms, {shards} shards over the lab "
      f"{ms_per_step(remote, seq):.2f} ms")
remote.close()
local.close()

# The benchmark (not in CTest's run): GROUNDSIM_SHARDS_BENCH=256
# steps 3 shards x 256 environments against the same batch in process.
per_shard = int(os.environ.get("GROUNDSIM_SHARDS_BENCH", "0"))
if per_shard:
    big = shards * per_shard
    local = groundsim.make_vec(task, big, num_threads=2)
    remote = groundsim.make_remote_vec(task, big, lcm_url=URL, shards=shards, timeout=30)
    local.reset(seed=3), remote.reset(seed=3)
    acts = [rng.uniform(low, high, size=(big, low.size)).astype(np.float32) for _ in range(20)]
    for act in acts[:5]:  # warm up both
        local.step(act), remote.step(act)
    a, b = ms_per_step(local, acts), ms_per_step(remote, acts)
    print(f"{shards} shards x {per_shard} envs: in process {a:.2f} ms per step, over the lab {b:.2f} ms "
          f"(overhead {b - a:.2f} ms, {b / a:.2f}x)")
    remote.close()
    local.close()

# A shard's server dies mid-rollout (shards_test.sh kills host 2 once the
# marker file is there): the loop goes on, that shard's environments come
# back truncated from a new shard elsewhere, no exception.
marker = os.environ.get("GROUNDSIM_KILL_MARKER")
if marker:
    env = groundsim.make_remote_vec(task, n, lcm_url=URL, shards=shards, timeout=10)
    env.reset(seed=5)
    open(marker, "w").close()
    deadline, longest, seen = time.perf_counter() + 120, 0.0, None  # a ceiling: the step time is printed
    while time.perf_counter() < deadline and seen is None:
        t = time.perf_counter()
        _, _, term, trunc, _ = env.step(seq[0])
        longest = max(longest, time.perf_counter() - t)
        blocks = [trunc[i:i + n // shards].all() for i in range(0, n, n // shards)]
        if sum(blocks) == 1 and trunc.sum() == n // shards:
            seen = blocks.index(True)
    assert seen is not None, "no shard came back truncated within 120 s of its server's death"
    for _ in range(20):  # and it goes on
        env.step(seq[0])
    print(f"shard {seen} lost and created again: the longest step took {longest:.2f} s, no exception")
    env.close()

#!/usr/bin/env python3
"""The Python package's speed (issue 17), in one process and one run, printed as Markdown:

1. per-run cost of `simulate_batch` against the whole `impactsweep run` command for the same
   runs (a noise-free e x m x d grid; every core; the command's wall time includes its start,
   the Parquet files and the manifest; the batch's includes building the pyarrow Table);
2. the fixed cost of one `simulate` call from Python: the median call minus the median
   simulator time of the same run measured inside a one-thread batch;
3. SciPy's `solve_ivp` (DOP853, rtol 1e-10, restart per impact: scripts/peer_scipy.py) on the
   same systems, from the same process.

Medians over --reps repetitions; ratios of those medians. Usage (scripts/bench_python.sh builds
what it needs): python scripts/bench_python.py --bin target/release/impactsweep
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import impactsweep as isw

sys.path.insert(0, str(Path(__file__).resolve().parent))
import peer_scipy  # noqa: E402

STUDY = """
[study]
name = "bench"
[sweep]
e = {{ start = 0.5, stop = 0.95, num = {ne} }}
m = {{ start = 0.005, stop = 0.03, num = 40 }}
d = {{ start = 0.004, stop = 0.02, num = 50 }}
"""


def median_time(f, reps):
    times = []
    for _ in range(reps):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--bin", required=True, help="the release binary")
    p.add_argument("--ne", type=int, default=100, help="e values (x 2000 runs)")
    p.add_argument("--reps", type=int, default=3)
    p.add_argument("--calls", type=int, default=20000, help="simulate calls timed")
    p.add_argument("--peer-runs", type=int, default=20)
    a = p.parse_args()

    n = a.ne * 40 * 50
    tmp = Path(tempfile.mkdtemp())
    study = tmp / "bench.toml"
    study.write_text(STUDY.format(ne=a.ne))
    k = [0]

    def command():
        k[0] += 1
        subprocess.run([a.bin, "run", study, "--out", tmp / f"out{k[0]}", "--quiet"], check=True)

    e, m, d = np.meshgrid(np.linspace(0.5, 0.95, a.ne), np.linspace(0.005, 0.03, 40),
                          np.linspace(0.004, 0.02, 50), indexing="ij")
    inputs = {"e": e.ravel(), "m": m.ravel(), "d": d.ravel()}
    isw.simulate_batch({"e": inputs["e"][:1000]})  # start rayon's pool

    t_cmd = median_time(command, a.reps) / n
    t_batch = median_time(lambda: isw.simulate_batch(inputs), a.reps) / n
    sub = {c: v[:: max(1, n // 20000)] for c, v in inputs.items()}
    t_batch1 = median_time(lambda: isw.simulate_batch(sub, threads=1), a.reps) / len(sub["e"])

    # One simulate call: the Table I system at e = 0.9, and its simulator time alone.
    reps = []
    for _ in range(a.reps):
        t0 = time.perf_counter()
        for _ in range(a.calls):
            isw.simulate(e=0.9)
        reps.append((time.perf_counter() - t0) / a.calls)
    t_call = statistics.median(reps)
    one = {"e": np.full(20000, 0.9)}
    t_sim = median_time(lambda: isw.simulate_batch(one, threads=1), a.reps) / 20000
    t_fixed = t_call - t_sim

    # SciPy on Table I systems over e, one thread, the same process.
    es = np.linspace(0.6, 0.95, a.peer_runs)
    peer, ours = [], []
    for ev in es:
        sysp = dict(peer_scipy.TABLE_I, e=float(ev))
        t0 = time.perf_counter()
        r = peer_scipy.simulate(sysp, "DOP853", 1e-10, 1e-12, 1000, 2.0)
        dt = time.perf_counter() - t0
        if r["outcome"] == "ok":
            peer.append(dt)
            ours.append(median_time(lambda: isw.simulate(e=float(ev)), 5))
    t_peer = statistics.median(peer)
    t_ours = statistics.median(ours)

    load = os.getloadavg()
    print(f"Machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}, numpy {np.__version__}; load average "
          f"{load[0]:.1f} / {load[1]:.1f} / {load[2]:.1f} (1 / 5 / 15 min) at the end.")
    print()
    print("| what | goal | measured |")
    print("|---|---|---|")
    print(f"| `simulate_batch`, every core, {n:,} noise-free runs, per run | | {t_batch * 1e6:.2f} µs |")
    print(f"| whole `impactsweep run` command, same runs, per run | | {t_cmd * 1e6:.2f} µs |")
    print(f"| ratio batch / command | ≤ 1.2 | {t_batch / t_cmd:.2f} |")
    print(f"| `simulate_batch`, one thread, per run | | {t_batch1 * 1e6:.2f} µs |")
    print(f"| one `simulate(e=0.9)` call from Python | | {t_call * 1e6:.2f} µs |")
    print(f"| of which the simulator (same run in a one-thread batch) | | {t_sim * 1e6:.2f} µs |")
    print(f"| fixed cost of a `simulate` call | < 20 µs | {t_fixed * 1e6:.2f} µs |")
    print(f"| SciPy `solve_ivp` DOP853 (rtol 1e-10), Table I over e, per run ({len(peer)} of {len(es)} finish) | | {t_peer * 1e3:.2f} ms |")
    print(f"| SciPy / one `simulate` call, same process | | {t_peer / t_ours:.0f}× |")
    print(f"| SciPy / `simulate_batch` per run (every core) | | {t_peer / t_batch:.0f}× |")


if __name__ == "__main__":
    main()

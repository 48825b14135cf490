#!/usr/bin/env python3
"""SciPy peer for `impactsweep tradeoff`: the impact damper solved the off-the-shelf way.

scipy.integrate.solve_ivp (RK45 and/or DOP853) integrates (x, v, y, w) of model.md §1 with
event location: the two walls are terminal events; at each one the impact law (eq. 3-4) is
applied and the integration restarts. Maxima (v = 0 while x > 0), impact kinks and the zero
crossings of x give the positive half-cycle maxima X1, X2 (model.md §3), so xmax, t1 and
DI = (X1 - X2) / (t2 - t1) compare one to one with `impactsweep simulate`.

There is no chatter rule: with e < 1 a rebound sequence can accumulate (a Zeno point), and the
restarted solver then never gets past it. A guard ends such a run after --max-impacts impacts or
--budget seconds of wall time and reports it as outcome "chatter" (it is not an error of the
peer, it is what an event-restart loop does; impactsweep replaces the accumulation by sticking).

Usage:
    python scripts/peer_scipy.py --method DOP853 --json          # one method, JSON on stdout
    python scripts/peer_scipy.py --out results/tradeoff/peer_scipy.json   # both methods
    python scripts/peer_scipy.py --e 0.45 --e 0.9                # a table for a person

The reference set is the paper's Table I system for e = 0.45 + 0.01 i, i = 0..50 (as
`impactsweep tradeoff` without a study). Timing: every run is timed (wall and thread CPU time)
over --reps repetitions of the whole set; the time per run is the median over repetitions of the
mean over the runs the peer finished (chatter runs stop at the guard and are left out of it).
"""

import argparse
import json
import math
import os
import platform
import sys
import time

import numpy as np
import scipy
from scipy.integrate import solve_ivp

TABLE_I = dict(M=0.1, m=0.02, K=400.0, C=0.1, d=0.01, e=0.9, x0=0.0, v0=2.0, y0=0.0, w0=0.0)


def impact(M, m, e, v, w):
    """Eq. 3-4: velocities just after an impact."""
    total = M + m
    va = ((M - m * e) * v + m * (1.0 + e) * w) / total
    wa = (M * (1.0 + e) * v + (m - M * e) * w) / total
    return va, wa


def simulate(sysp, method, rtol, atol, max_impacts, budget, peaks=2, t_max_periods=200.0):
    """One run; returns a dict with outcome, xmax, t1, di, impacts, t_stop."""
    M, m, K, C, d, e = (sysp[k] for k in ("M", "m", "K", "C", "d", "e"))
    half = 0.5 * d
    period = 2.0 * math.pi * math.sqrt(M / K)
    t_max = t_max_periods * period

    def rhs(_t, s):
        return [s[1], -(C * s[1] + K * s[0]) / M, s[3], 0.0]

    def right(_t, s):  # gap to the right wall, z = y - x = +d/2
        return half - (s[2] - s[0])

    def left(_t, s):  # gap to the left wall, z = -d/2
        return (s[2] - s[0]) + half

    def xzero(_t, s):
        return s[0]

    def vzero(_t, s):
        return s[1]

    right.terminal = left.terminal = True
    right.direction = left.direction = -1.0
    vzero.direction = -1.0  # maxima of x

    state = np.array([sysp["x0"], sysp["v0"], sysp["y0"], sysp["w0"]], dtype=float)
    t = 0.0
    impacts = 0
    # Observables, as in impactsweep's driver: positive half-cycles closed by x crossing down.
    x_pos = state[0] > 0.0 or (state[0] == 0.0 and state[1] > 0.0)
    found = []
    started = time.perf_counter()

    def candidate(x):
        nonlocal running
        if running is None or x > running[0]:
            running = (x, tc)

    running = (state[0], 0.0) if state[0] > 0.0 else None
    while True:
        if impacts >= max_impacts or time.perf_counter() - started > budget:
            return dict(outcome="chatter", xmax=None, t1=None, di=None, impacts=impacts, t_stop=t)
        sol = solve_ivp(
            rhs,
            (t, t_max),
            state,
            method=method,
            rtol=rtol,
            atol=atol,
            events=[right, left, xzero, vzero],
        )
        # Merge this segment's non-terminal events in time order.
        evs = []
        for kind, (ts, ys) in enumerate(zip(sol.t_events[2:], sol.y_events[2:])):
            for te, ye in zip(ts, ys):
                evs.append((te, "x" if kind == 0 else "v", ye))
        evs.sort(key=lambda ev: ev[0])
        wall_t = None
        if sol.status == 1:
            wall_hits = [(ts[0], i) for i, ts in enumerate(sol.t_events[:2]) if len(ts)]
            wall_t, wall_i = min(wall_hits)
        done = False
        for te, kind, ye in evs:
            if wall_t is not None and te > wall_t:
                break
            tc = te
            if kind == "v":
                if x_pos and ye[0] > 0.0:
                    candidate(ye[0])
            elif ye[1] < 0.0 and x_pos:
                if running is not None:
                    found.append(running)
                running = None
                x_pos = False
                if len(found) >= peaks:
                    t = te
                    done = True
                    break
            elif ye[1] > 0.0 and not x_pos:
                x_pos = True
        if done:
            break
        if sol.status == 0:  # reached t_max
            t = t_max
            break
        if sol.status < 0:
            return dict(outcome="solver_failed", xmax=None, t1=None, di=None, impacts=impacts,
                        t_stop=t)
        # Impact at the wall: the state at the event, the inner mass put on the wall.
        ye = sol.y_events[wall_i][0].copy()
        t = wall_t
        tc = t
        sign = 1.0 if wall_i == 0 else -1.0
        ye[2] = ye[0] + sign * half
        # Rounding may leave the inner mass a hair outside the wall; a gap that starts negative
        # would hide the next contact from the sign test of the event finder, letting the inner
        # mass pass through the wall. Step it back inside by ulps.
        while (right if sign > 0 else left)(t, ye) < 0.0:
            ye[2] = np.nextafter(ye[2], -sign * np.inf)
        if x_pos and ye[0] > 0.0:
            candidate(ye[0])
        ye[1], ye[3] = impact(M, m, e, ye[1], ye[3])
        impacts += 1
        state = ye
    if len(found) < 2:
        return dict(outcome="no_second_peak", xmax=None, t1=None, di=None, impacts=impacts,
                    t_stop=t)
    (x1, t1), (x2, t2) = found[0], found[1]
    return dict(outcome="ok", xmax=max(x for x, _ in found), t1=t1, di=(x1 - x2) / (t2 - t1),
                impacts=impacts, t_stop=t)


def paper_set():
    return [0.45 + 0.01 * i for i in range(51)]


def run_method(method, es, args):
    runs = None
    walls, cpus = [], []
    for _ in range(args.reps):
        rep_runs, wall, cpu = [], 0.0, 0.0
        n_done = 0
        for i, e in enumerate(es):
            if runs is not None and runs[i]["outcome"] == "chatter":
                # Stopped by the guard in the first repetition; not timed, not rerun.
                rep_runs.append(runs[i])
                continue
            sysp = dict(TABLE_I, e=e)
            w0, c0 = time.perf_counter(), time.thread_time()
            r = simulate(sysp, method, args.rtol, args.atol, args.max_impacts, args.budget)
            dw, dc = time.perf_counter() - w0, time.thread_time() - c0
            r["e"] = e
            r["wall_s"] = dw
            rep_runs.append(r)
            if r["outcome"] != "chatter":
                wall += dw
                cpu += dc
                n_done += 1
        walls.append(wall / max(n_done, 1))
        cpus.append(cpu / max(n_done, 1))
        runs = rep_runs
    return dict(
        method=method,
        rtol=args.rtol,
        atol=args.atol,
        time_per_run_s=float(np.median(walls)),
        cpu_per_run_s=float(np.median(cpus)),
        reps=args.reps,
        max_impacts=args.max_impacts,
        budget_s=args.budget,
        runs=runs,
    )


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--method", action="append", choices=["RK45", "DOP853"],
                   help="solve_ivp method (repeatable; default both)")
    p.add_argument("--rtol", type=float, default=1e-10)
    p.add_argument("--atol", type=float, default=1e-12)
    p.add_argument("--e", type=float, action="append", help="restitution values (default: the paper set)")
    p.add_argument("--reps", type=int, default=3, help="timed repetitions of the whole set")
    p.add_argument("--max-impacts", type=int, default=1000, help="chatter guard: impacts per run")
    p.add_argument("--budget", type=float, default=2.0, help="chatter guard: wall seconds per run")
    p.add_argument("--json", action="store_true", help="print JSON on stdout")
    p.add_argument("--out", help="also write the JSON to this file")
    args = p.parse_args()
    methods = args.method or ["RK45", "DOP853"]
    es = args.e or paper_set()
    doc = dict(
        tool="scipy",
        version=scipy.__version__,
        numpy=np.__version__,
        python=platform.python_version(),
        machine=f"{platform.machine()} {os.cpu_count()} cpus, {platform.platform()}",
        methods=[run_method(m, es, args) for m in methods],
    )
    text = json.dumps(doc, indent=1)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text + "\n")
    if args.json:
        print(text)
    else:
        for m in doc["methods"]:
            done = [r for r in m["runs"] if r["outcome"] != "chatter"]
            print(f"{m['method']} rtol={m['rtol']:g}: {m['time_per_run_s'] * 1e3:.2f} ms wall, "
                  f"{m['cpu_per_run_s'] * 1e3:.2f} ms CPU per finished run; "
                  f"{len(m['runs']) - len(done)} of {len(m['runs'])} runs stopped by the chatter guard")
            for r in m["runs"]:
                fmt = lambda v: "-" if v is None else f"{v:.9g}"
                print(f"  e={r['e']:.2f} {r['outcome']:15s} impacts={r['impacts']:5d} "
                      f"xmax={fmt(r['xmax'])} t1={fmt(r['t1'])} DI={fmt(r['di'])} t_stop={r['t_stop']:.6f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

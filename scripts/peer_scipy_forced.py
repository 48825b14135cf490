#!/usr/bin/env python3
"""SciPy peer for the forced (harmonic) scene: the impact damper under F0 cos(omega t), solved the
off-the-shelf way, as an independent check of `impactsweep simulate --set scene=harmonic`.

scipy.integrate.solve_ivp (DOP853 by default) integrates (x, v, y, w) of model.md §8:
    M x'' + C x' + K x = F0 cos(omega t),   y'' = 0,
one forcing period T = 2 pi / omega at a time (so the Poincaré section at t = k T is an end
point, not an interpolation). The two walls |y - x| = d/2 are terminal events; at each one the
impact law (eq. 3-4) is applied and the integration restarts. There is no chatter rule: a run
with more than --max-impacts impacts stops with outcome "chatter".

Measurement, as in impactsweep: after n_trans periods, over n_meas periods, amplitude = max |x|
at the window's ends, at every zero of v (a non-terminal event, located by SciPy) and at every
impact; impacts_per_period = impacts in the window / n_meas; the window's sections are returned.

Usage:
    python scripts/peer_scipy_forced.py --F0 0.3 --r 0.98 --n-trans 40 --n-meas 20 \
        --x0 ... --v0 ... --y0 ... --w0 ...            # one run, JSON on stdout
Every system key of Table I can be set (--M --m --K --C --d --e). Times: wall seconds of the run.
"""

import argparse
import json
import math
import time

import numpy as np
from scipy.integrate import solve_ivp

# The impact law (eq. 3-4) and the Table I system of the free-decay peer, beside this script.
from peer_scipy import TABLE_I, impact


def simulate(p, F0, omega, n_trans, n_meas, method="DOP853", rtol=1e-12, atol=1e-15,
             max_impacts=100_000):
    M, m, K, C, d, e = (p[k] for k in ("M", "m", "K", "C", "d", "e"))
    half = 0.5 * d
    T = 2.0 * math.pi / omega

    def rhs(t, s):
        return [s[1], (F0 * math.cos(omega * t) - C * s[1] - K * s[0]) / M, s[3], 0.0]

    def right(_t, s):  # z = y - x reaches +d/2
        return half - (s[2] - s[0])

    def left(_t, s):  # z reaches -d/2
        return (s[2] - s[0]) + half

    def vzero(_t, s):
        return s[1]

    right.terminal = left.terminal = True
    right.direction = left.direction = -1.0

    s = np.array([p["x0"], p["v0"], p["y0"], p["w0"]], dtype=float)
    impacts = 0
    window_impacts = 0
    amplitude = 0.0
    sections = []
    steps = 0
    for k in range(n_trans + n_meas):
        t0, t1 = k * T, (k + 1) * T
        measuring = k >= n_trans
        if measuring and k == n_trans:
            sections.append(s.tolist())
            amplitude = max(amplitude, abs(s[0]))
        t = t0
        while True:
            events = [right, left, vzero] if measuring else [right, left]
            sol = solve_ivp(rhs, (t, t1), s, method=method, rtol=rtol, atol=atol, events=events)
            steps += sol.nfev
            if measuring:
                for sv in sol.y_events[2]:
                    amplitude = max(amplitude, abs(sv[0]))
            hit = None
            for i in (0, 1):
                if len(sol.t_events[i]):
                    hit = i
            if hit is None:
                s = sol.y[:, -1].copy()
                break
            t = sol.t_events[hit][0]
            s = sol.y_events[hit][0].copy()
            # On the wall exactly, then the impact law.
            s[2] = s[0] + (half if hit == 0 else -half)
            s[1], s[3] = impact(M, m, e, s[1], s[3])
            impacts += 1
            if measuring:
                window_impacts += 1
                amplitude = max(amplitude, abs(s[0]))
            if impacts > max_impacts:
                return dict(outcome="chatter", impacts=impacts)
        if measuring:
            sections.append(s.tolist())
            amplitude = max(amplitude, abs(s[0]))
    return dict(
        outcome="ok",
        amplitude=amplitude,
        impacts_per_period=window_impacts / n_meas,
        impacts=impacts,
        sections=sections,
        nfev=steps,
    )


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    for k, v in TABLE_I.items():
        ap.add_argument(f"--{k}", type=float, default=v)
    ap.add_argument("--F0", type=float, default=1.0)
    ap.add_argument("--r", type=float, default=None)
    ap.add_argument("--omega", type=float, default=None)
    ap.add_argument("--n-trans", type=int, default=300)
    ap.add_argument("--n-meas", type=int, default=20)
    ap.add_argument("--method", default="DOP853")
    ap.add_argument("--rtol", type=float, default=1e-12)
    ap.add_argument("--atol", type=float, default=1e-15)
    a = ap.parse_args()
    p = {k: getattr(a, k) for k in TABLE_I}
    omega = a.omega if a.omega is not None else (a.r if a.r is not None else 1.0) * math.sqrt(p["K"] / p["M"])
    start = time.perf_counter()
    out = simulate(p, a.F0, omega, a.n_trans, a.n_meas, a.method, a.rtol, a.atol)
    out["wall_s"] = time.perf_counter() - start
    out["periods"] = a.n_trans + a.n_meas
    out["method"] = a.method
    out["rtol"] = a.rtol
    out["atol"] = a.atol
    print(json.dumps(out))


if __name__ == "__main__":
    main()

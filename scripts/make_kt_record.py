#!/usr/bin/env python3
"""Writes configs/records/kt-synthetic.csv: a synthetic accelerogram for the record scene's peers.

Kanai-Tajimi filtered white noise (docs/model.md §13) under Jennings et al.'s (1968) envelope,
scaled to a chosen peak ground acceleration. Written once and committed; the peers
(scripts/peer_random.py) and impactsweep read the same file, so nothing depends on this script
being run again, but it reproduces the file bit for bit with the same numpy.

    white noise  w_k ~ N(0, 2 pi S0 / dt), held over each sample (numpy PCG64, seed 44)
    soil filter  u'' + 2 zeta_g omega_g u' + omega_g^2 u = -w,  a = -(2 zeta_g omega_g u' + omega_g^2 u)
                 stepped exactly over each sample by its state-transition matrix (zero-order hold)
    envelope     (t / t1)^2 before t1, 1 up to t2, exp(-c (t - t2)) after
    scaling      the whole record times PGA / max |a|  (S0 only sets the shape's scale; it drops out)

Defaults: firm soil omega_g = 5 pi rad/s, zeta_g = 0.6; dt = 0.005 s, 20 s (4001 rows, t = 0 to 20);
envelope t1 = 2 s, t2 = 12 s, c = 0.3 1/s; PGA 3 m/s^2. The first row is a = 0 (at rest).

Usage: python scripts/make_kt_record.py [--out configs/records/kt-synthetic.csv] [--seed 44]
"""

import argparse

import numpy as np
from scipy.linalg import expm


def kt_record(seed, dt, duration, omega_g, zeta_g, t1, t2, c, pga):
    n = int(round(duration / dt))
    rng = np.random.default_rng(seed)
    w = rng.standard_normal(n) * np.sqrt(2.0 * np.pi / dt)  # S0 = 1: scaled away below
    # State (u, u'); u' ' = -2 zeta wg u' - wg^2 u - w. ZOH of w over each sample, exactly.
    A = np.array([[0.0, 1.0], [-omega_g**2, -2.0 * zeta_g * omega_g]])
    B = np.array([0.0, -1.0])
    big = np.zeros((3, 3))
    big[:2, :2] = A * dt
    big[:2, 2] = B * dt
    E = expm(big)
    Phi, Gam = E[:2, :2], E[:2, 2]
    s = np.zeros(2)
    a = np.zeros(n + 1)
    for k in range(n):
        s = Phi @ s + Gam * w[k]
        a[k + 1] = -(2.0 * zeta_g * omega_g * s[1] + omega_g**2 * s[0])
    t = np.arange(n + 1) * dt
    env = np.where(t < t1, (t / t1) ** 2, np.where(t <= t2, 1.0, np.exp(-c * (t - t2))))
    a *= env
    a *= pga / np.max(np.abs(a))
    return t, a


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="configs/records/kt-synthetic.csv")
    ap.add_argument("--seed", type=int, default=44)
    ap.add_argument("--dt", type=float, default=0.005)
    ap.add_argument("--duration", type=float, default=20.0)
    ap.add_argument("--omega-g", type=float, default=5.0 * np.pi)
    ap.add_argument("--zeta-g", type=float, default=0.6)
    ap.add_argument("--t1", type=float, default=2.0)
    ap.add_argument("--t2", type=float, default=12.0)
    ap.add_argument("--c", type=float, default=0.3)
    ap.add_argument("--pga", type=float, default=3.0, help="peak ground acceleration, m/s^2")
    args = ap.parse_args()
    t, a = kt_record(args.seed, args.dt, args.duration, args.omega_g, args.zeta_g, args.t1,
                     args.t2, args.c, args.pga)
    with open(args.out, "w") as f:
        f.write(f"# Kanai-Tajimi synthetic accelerogram (scripts/make_kt_record.py, seed {args.seed}):\n")
        f.write(f"# omega_g = {args.omega_g:.6g} rad/s, zeta_g = {args.zeta_g}, envelope t1 = {args.t1} s, "
                f"t2 = {args.t2} s, c = {args.c} 1/s, PGA {args.pga} m/s^2, dt = {args.dt} s\n")
        f.write("t,a\n")
        for tk, ak in zip(t, a):
            f.write(f"{tk:.3f},{ak:.9g}\n")
    print(f"{args.out}: {len(t)} rows, dt = {args.dt} s, PGA {np.max(np.abs(a)):.4g} m/s^2")


if __name__ == "__main__":
    main()

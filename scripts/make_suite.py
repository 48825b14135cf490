#!/usr/bin/env python3
"""Writes configs/records/suite/: eleven synthetic accelerograms compatible with a design spectrum.

The project cannot download real records, so its record-suite showcase (configs/seismic-records.toml)
uses synthetic ones, made here and committed; nothing depends on this script being run again, but
it reproduces the files bit for bit with the same numpy and scipy (the pins of setup-python.sh).

Target: the design spectrum of ASCE 7-16 §11.4.6 (5 % damping) with S_DS = 1.0 g, S_D1 = 0.6 g,
T_L = 8 s (a high-seismicity site on stiff soil):

    Sa(T) = S_DS (0.4 + 0.6 T / T0)   for T < T0 = 0.2 S_D1 / S_DS = 0.12 s
          = S_DS                      for T0 <= T <= TS = S_D1 / S_DS = 0.6 s
          = S_D1 / T                  for TS < T <= T_L

Each record (Gasparini and Vanmarcke's SIMQKE, 1976): a stationary motion of random phases
(numpy PCG64, seed 6700 + i) and an amplitude spectrum, times Jennings et al.'s (1968) envelope
((t / t1)^2 before t1, 1 up to t2, exp(-c (t - t2)) after; t1, t2, c and the length differ per
record); the amplitude spectrum is multiplied by target / Sa at every frequency f (Sa at T = 1 / f,
interpolated in log T over 80 periods from 0.04 (or 5 dt) to 5 s), 25 times. Sa is the 5 %-damped
oscillator's peak pseudo-acceleration over the samples, run exactly for a load linear between
samples. Last, a baseline correction a - (c0 + c1 t) so that the ground's velocity and
displacement end at zero, and the first sample set to 0 (the structure starts at rest).

Sample intervals differ as real suites' do: 0.005, 0.01 or 0.02 s. Each file is `t,a` (m/s^2)
with a `#` header stating its parameters and its match; README.md in the folder lists the suite's
mean Sa / target over 0.1-3 s.

Usage: python scripts/make_suite.py [--out configs/records/suite] [--records 11]
"""

import argparse
import os

import numpy as np
from scipy.linalg import expm

G = 9.80665
SDS, SD1, TL = 1.0, 0.6, 8.0
ZETA = 0.05
PERIODS = np.geomspace(0.04, 5.0, 80)
# Where the match is stated: 0.1 to 3 s.
BAND = PERIODS[(PERIODS >= 0.1) & (PERIODS <= 3.0)]
# Per record: dt (s), length (s), envelope t1, t2 (s), c (1/s).
SHAPES = [
    (0.01, 24.0, 2.0, 10.0, 0.35),
    (0.01, 20.0, 1.5, 8.0, 0.40),
    (0.02, 30.0, 2.5, 14.0, 0.30),
    (0.005, 18.0, 1.0, 7.0, 0.50),
    (0.01, 26.0, 3.0, 12.0, 0.30),
    (0.01, 22.0, 2.0, 9.0, 0.45),
    (0.02, 28.0, 2.0, 13.0, 0.35),
    (0.005, 20.0, 1.5, 8.0, 0.40),
    (0.01, 25.0, 2.5, 11.0, 0.35),
    (0.01, 21.0, 1.0, 9.0, 0.50),
    (0.02, 32.0, 3.0, 15.0, 0.25),
]


def target(T):
    """The design spectrum (g) at periods T (s)."""
    T = np.asarray(T, dtype=float)
    t0, ts = 0.2 * SD1 / SDS, SD1 / SDS
    return np.where(T < t0, SDS * (0.4 + 0.6 * T / t0),
                    np.where(T <= ts, SDS, np.where(T <= TL, SD1 / T, SD1 * TL / T**2)))


def propagators(dt, periods):
    """Per period, the exact step of (x, v) over dt under a load p0 + s t: x'' + 2 z w x' + w^2 x = -p."""
    out = []
    for T in periods:
        w = 2.0 * np.pi / T
        big = np.zeros((4, 4))
        big[0, 1] = 1.0
        big[1, 0], big[1, 1], big[1, 2] = -w * w, -2.0 * ZETA * w, -1.0
        big[2, 3] = 1.0
        out.append(expm(big * dt))
    E = np.array(out)
    return E[:, :2, :2], E[:, :2, 2], E[:, :2, 3]


def spectrum(a, dt, periods, prop):
    """Sa (g) of accelerogram a (m/s^2) at periods: max |x| w^2 over the samples."""
    P, Ga, Gs = prop
    x = np.zeros((len(periods), 2))
    peak = np.zeros(len(periods))
    slopes = np.diff(a) / dt
    for k in range(len(a) - 1):
        x = np.einsum("pij,pj->pi", P, x) + Ga * a[k] + Gs * slopes[k]
        np.maximum(peak, np.abs(x[:, 0]), out=peak)
    return peak * (2.0 * np.pi / periods) ** 2 / G


def baseline(a, dt):
    """a - (c0 + c1 t) with the velocity and displacement at the end zero (trapezoid rule)."""
    n = len(a)
    t = np.arange(n) * dt

    def end(f):
        v = np.concatenate([[0.0], np.cumsum((f[1:] + f[:-1]) * dt / 2)])
        d = np.sum((v[1:] + v[:-1]) * dt / 2)
        return v[-1], d

    v0, d0 = end(a)
    # The end velocity and displacement of 1 and of t, by the same rule.
    v1, d1 = end(np.ones(n))
    vt, dtt = end(t)
    c0, c1 = np.linalg.solve([[v1, vt], [d1, dtt]], [v0, d0])
    return a - (c0 + c1 * t)


def record(i, dt, length, t1, t2, c, iterations):
    n = int(round(length / dt)) + 1
    t = np.arange(n) * dt
    env = np.where(t < t1, (t / t1) ** 2, np.where(t <= t2, 1.0, np.exp(-c * (t - t2))))
    rng = np.random.default_rng(6700 + i)
    m = n // 2 + 1
    phase = np.exp(2j * np.pi * rng.random(m))
    freq = np.fft.rfftfreq(n, dt)
    amp = np.ones(m)
    amp[0] = 0.0
    # Matched from 5 dt up (a shorter period is not resolved by the samples; the frequencies
    # above take the ratio at the shortest matched period).
    grid = PERIODS[PERIODS >= 5.0 * dt]
    prop = propagators(dt, grid)
    tgt = target(grid)
    logT = np.log(grid)
    with np.errstate(divide="ignore"):
        Tf = np.where(freq > 0, 1.0 / np.maximum(freq, 1e-300), np.inf)
    for _ in range(iterations):
        sa = spectrum(env * np.fft.irfft(amp * phase, n), dt, grid, prop)
        r = np.interp(np.log(np.clip(Tf, grid[0], grid[-1])), logT, tgt / sa)
        amp = amp * r
        amp[0] = 0.0
    a = env * np.fft.irfft(amp * phase, n)
    a = baseline(a, dt)
    a[0] = 0.0
    sa = spectrum(a, dt, BAND, propagators(dt, BAND))
    return t, a, sa


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="configs/records/suite")
    ap.add_argument("--records", type=int, default=len(SHAPES))
    ap.add_argument("--iterations", type=int, default=25)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    tgt = target(BAND)
    ratios = []
    rows = []
    for i, (dt, length, t1, t2, c) in enumerate(SHAPES[: args.records]):
        t, a, sa = record(i, dt, length, t1, t2, c, args.iterations)
        r = sa / tgt
        ratios.append(r)
        name = f"syn-{i + 1:02d}.csv"
        pga = np.max(np.abs(a)) / G
        with open(os.path.join(args.out, name), "w") as f:
            f.write(f"# synthetic accelerogram {i + 1} of the bundled suite (scripts/make_suite.py, seed {6700 + i})\n")
            f.write(f"# ASCE 7-16 spectrum S_DS = {SDS} g, S_D1 = {SD1} g; envelope t1 = {t1} s, t2 = {t2} s, "
                    f"c = {c} 1/s; dt = {dt} s, {length} s\n")
            f.write(f"# PGA {pga:.4f} g; Sa / target over 0.1-3 s: {r.min():.3f} to {r.max():.3f}\n")
            f.write("t,a\n")
            for tk, ak in zip(t, a):
                f.write(f"{tk:.3f},{ak:.6g}\n")
        rows.append((name, dt, length, len(t), pga, r.min(), r.max()))
        print(f"{name}: {len(t)} rows, dt {dt} s, PGA {pga:.3f} g, Sa/target {r.min():.3f}..{r.max():.3f}")
    mean = np.mean(ratios, axis=0)
    with open(os.path.join(args.out, "README.md"), "w") as f:
        f.write("# A synthetic record suite\n\n")
        f.write("Eleven accelerograms made by `scripts/make_suite.py` (SIMQKE-style spectral matching, "
                "seeds 6700-6710) to the design spectrum of ASCE 7-16 §11.4.6 with S_DS = 1.0 g, "
                "S_D1 = 0.6 g, 5 % damping. They are not recordings: they stand in for a suite a user "
                "brings (docs/scenes.md says how to convert PEER NGA-West2 files). Each file is `t,a` "
                "in m/s^2.\n\n")
        f.write("| record | dt (s) | length (s) | samples | PGA (g) | Sa / target, 0.1-3 s |\n|---|---|---|---|---|---|\n")
        for name, dt, length, n, pga, lo, hi in rows:
            f.write(f"| {name} | {dt} | {length:g} | {n} | {pga:.3f} | {lo:.3f} to {hi:.3f} |\n")
        f.write(f"\nThe suite's mean Sa / target over 0.1-3 s: {mean.min():.3f} to {mean.max():.3f} "
                f"(at T1 = 0.4 s: {np.interp(np.log(0.4), np.log(BAND), mean):.3f}).\n")
    print(f"mean Sa/target over 0.1-3 s: {mean.min():.3f}..{mean.max():.3f}")


if __name__ == "__main__":
    main()

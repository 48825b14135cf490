#!/usr/bin/env python3
"""Peer of the capacities by incremental dynamic analysis (issue 67): impactsweep and OpenSeesPy.

One record (configs/records/kt-synthetic.csv, the record scene's peer's, scripts/peer_random.py)
and one design (peer_random.DESIGN: M = 1 kg, K = 246.7 N/m, 2 % damping, a damper m = 0.05 kg,
d = 2 cm, e = 0.6), and the structure alone (m = 0) as the check of the set-ups. The capacity is
the PGA (g) at which max |x| first passes the limit LIMIT as the record is scaled.

* impactsweep: a record study with `intensity = "pga"`, `threshold = LIMIT` and one stripe
  `im = [STRIPE]` (the design stripe), run by the binary (--bin) at ida_tol 1e-2 (its default),
  1e-3 and 1e-6; `capacity`, `capacity_runs`, `capacity_resurrected` read from `random_points`.
  The `run` command's wall and CPU time, per study of the two designs. Then the IDA curve itself:
  a record study without an intensity, `scale` swept over SCAN (the amplitude at each gain).
* OpenSeesPy: the model of peer_random.py (ops_build: zeroLength elements, `Elastic` K with
  damping C, two `ViscoelasticGap` contacts damped for e, `UniformExcitation` by a `Path` series,
  Newmark's average acceleration), max |x| over the steps from an `EnvelopeNode` recorder, the
  record times a gain s (the `Path` values multiplied). The search is impactsweep's own
  (src/sim/random/ida.rs, ported below as `capacity`): the first run at the stripe's gain, the
  bracket from the linear estimate, false position in (ln s, ln max|x|) and bisection until
  hi / lo <= 1 + tol, the capacity sqrt(lo hi) PGA. The damper at every (k, h) of
  peer_random.OPS_GRID at tol 1e-3, the structure alone at two steps at tol 1e-6. Then the
  IDA curve around its capacity at OPS_SCAN_CONFIG, to see whether it falls back too.

A run passes when max |x| > LIMIT (impactsweep's rule). "Falls back": the motion passes at a gain
and not at a larger one (`capacity_resurrected`); the searches flag it among their own trials,
the scans over their grids.

Usage: scripts/peer_ida.sh [--bin target/release/impactsweep] [--grid full|quick] [--reps 3]
(the wrapper sets up .venv-peers, as scripts/peer_random.sh does; CI does not need it).
Writes results/peer_ida.md and results/peer_ida.json. A measurement, never a test.
"""

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import peer_random as P  # noqa: E402  (re-executes this script with OpenSees's libraries found)

import numpy as np  # noqa: E402
import pyarrow.parquet as pq  # noqa: E402

ops = P.ops
G = 9.80665  # impactsweep's g (m/s²)
LIMIT = 0.05  # m: the limit on |x| (the threshold)
STRIPE = 0.3  # g: the design stripe, where each search starts
IDA_MAX = 10.0  # g
ISW_TOLS = [1e-2, 1e-3, 1e-6]
OPS_TOL_ALONE, OPS_TOL_DAMPER = 1e-6, 1e-3
OPS_H_ALONE = [1e-4, 2.5e-5]
OPS_GRID_QUICK = [(1e4, 2e-4), (1e5, 1e-4), (1e6, 2e-5), (1e7, 1e-5)]
OPS_SCAN_CONFIG = (1e5, 1e-4)
OPS_SCAN = np.round(np.arange(-0.03, 0.03001, 0.0025), 6)  # relative to its capacity's gain
SCAN = np.round(np.arange(0.8, 3.0000001, 0.0005), 6)  # impactsweep's IDA curve, gains
MAX_RUNS = 20


def capacity(own, b, first, tol, ida_max, amplitude):
    """impactsweep's search (src/sim/random/ida.rs::capacity), line for line: the capacity (g)
    of a motion of own intensity `own` against the limit b from a first run (s0, a0)."""
    tried = [first]
    s_max = ida_max / own
    streak, prev_hi = 0, None

    def ends():
        passing = [t for t in tried if t[1] > b]
        hi = min(passing, key=lambda t: t[0]) if passing else None
        below = [t for t in tried if t[1] <= b and (hi is None or t[0] < hi[0])]
        lo = max(below, key=lambda t: t[0]) if below else None
        return lo, hi

    def done(cap, censored):
        first_pass = min((t[0] for t in tried if t[1] > b), default=math.inf)
        return dict(capacity=cap, censored=censored, runs=len(tried), trials=list(tried),
                    resurrected=any(t[1] <= b and t[0] > first_pass for t in tried))

    while True:
        if any(math.isnan(t[1]) for t in tried):
            return done(math.nan, False)
        lo, hi = ends()
        if lo and hi and hi[0] / lo[0] <= 1.0 + tol:
            return done(math.sqrt(lo[0] * hi[0]) * own, False)
        if lo and hi:
            (l, al), (h, ah) = lo, hi
            moved_hi = tried[-1][1] > b
            streak = streak + 1 if prev_hi == moved_hi else 1
            prev_hi = moved_hi
            pad = math.log1p(tol / 4.0)
            x0, x1 = math.log(l), math.log(h)
            if streak >= 3 or x1 - x0 <= 4.0 * pad or al <= 0.0:
                trial = math.exp(0.5 * (x0 + x1))
            else:
                y0, y1 = math.log(al) - math.log(b), math.log(ah) - math.log(b)
                x = x0 + y0 / (y0 - y1) * (x1 - x0)
                half = math.log1p(tol / 2.0)
                x = x - half if moved_hi else x + half
                trial = math.exp(min(max(x, x0 + pad), x1 - pad))
        elif lo:
            l, al = lo
            if l >= s_max * (1.0 - 1e-12):
                return done(ida_max, True)
            guess = b / al * 1.02 if al > 0.0 else 4.0
            trial = min(l * min(max(guess, 1.05), 16.0), s_max)
        else:
            h, ah = hi
            trial = h * min(max(b / ah / 1.02, 1.0 / 16.0), 1.0 / 1.05)
        if len(tried) >= MAX_RUNS:
            if lo and hi:
                return done(math.sqrt(lo[0] * hi[0]) * own, False)
            return done(ida_max, True) if lo else done(math.nan, False)
        tried.append((trial, amplitude(trial)))


# ---------------------------------------------------------------- OpenSeesPy


def ops_peak(ag, dt_rec, gain, h, kc, tmp):
    """max |x| over the steps of one OpenSees run of the record times gain (NaN if it fails)."""
    env = os.path.join(tmp, "ops_env.out")
    P.ops_build(ag * gain, dt_rec, kc, tmp=tmp)
    ops.recorder("EnvelopeNode", "-file", env, "-precision", 17, "-node", 2, "-dof", 1, "disp")
    try:
        P.ops_analyze(h)
    except RuntimeError as err:
        print(err, file=sys.stderr)
        return math.nan
    ops.wipe()  # flushes the recorder: min, max, max abs
    with open(env) as f:
        return float(f.read().split()[-1])


def ops_ida(ag, dt_rec, own, h, kc, tol, tmp):
    w0, c0 = time.perf_counter(), time.process_time()
    s0 = STRIPE / own
    r = capacity(own, LIMIT, (s0, ops_peak(ag, dt_rec, s0, h, kc, tmp)), tol, IDA_MAX,
                 lambda s: ops_peak(ag, dt_rec, s, h, kc, tmp))
    r.update(kc=kc, h=h, tol=tol, wall=time.perf_counter() - w0, cpu=time.process_time() - c0)
    print("opensees ida", {k: v for k, v in r.items() if k != "trials"}, file=sys.stderr)
    return r


# ---------------------------------------------------------------- impactsweep

IDA_SCENE = 'intensity = "pga"\nthreshold = {b!r}\nida_tol = {tol!r}\nida_max = {imax!r}\n'


def isw_ida(binary, tmp, tol, reps):
    """The record study at ida_tol tol: `run` reps times (wall and CPU, medians), then `reduce`,
    whose capacities.csv must hold the points' capacities."""
    name = f"ida_{tol:g}".replace("-", "m").replace(".", "p")
    study = P.isw_study(tmp, name, f"m = [0.0, {P.DESIGN['m']!r}]\nim = [{STRIPE!r}]")
    with open(study) as f:
        text = f.read()
    # The scene's keys: after `duration`, before [sweep].
    text = text.replace("[sweep]", IDA_SCENE.format(b=LIMIT, tol=tol, imax=IDA_MAX) + "\n[sweep]")
    with open(study, "w") as f:
        f.write(text)
    out = os.path.join(tmp, "out_" + name)
    walls, cpus = zip(*(P.isw_run(binary, study, out) for _ in range(reps)))
    t = pq.read_table(os.path.join(out, name, "points")).to_pydict()
    cols = ["mass_inner", "pga", "scale", "im", "amplitude", "capacity", "capacity_censored",
            "capacity_resurrected", "capacity_runs"]
    rows = [{c: t[c][i] for c in cols} for i in range(len(t["point"]))]
    rows.sort(key=lambda r: r["mass_inner"])
    w0 = time.perf_counter()
    subprocess.run([binary, "reduce", os.path.join(out, name)], check=True,
                   stdout=subprocess.DEVNULL)
    reduce_wall = time.perf_counter() - w0
    with open(os.path.join(out, name, "capacities.csv")) as f:
        header = f.readline().strip().split(",")
        csv = sorted((dict(zip(header, line.strip().split(","))) for line in f),
                     key=lambda r: float(r["mass_inner"]))
    for r, c in zip(rows, csv):
        assert float(c["capacity"]) == r["capacity"] and int(c["runs"]) == r["capacity_runs"], (r, c)
    print("impactsweep ida", tol, rows, walls, file=sys.stderr)
    return dict(tol=tol, wall=float(np.median(walls)), cpu=float(np.median(cpus)), walls=walls,
                reduce_wall=reduce_wall, capacities_csv=csv, alone=rows[0], damper=rows[1])


def isw_scan(binary, tmp):
    """The IDA curve: max |x| at every gain of SCAN, both designs, one study."""
    scales = ", ".join(repr(float(s)) for s in SCAN)
    study = P.isw_study(tmp, "scan", f"m = [0.0, {P.DESIGN['m']!r}]\nscale = [{scales}]")
    out = os.path.join(tmp, "out_scan")
    wall, cpu = P.isw_run(binary, study, out)
    t = pq.read_table(os.path.join(out, "scan", "points")).to_pydict()
    res = dict(wall=wall, cpu=cpu, runs=len(t["point"]))
    m, s, a = (np.array(t[c]) for c in ("mass_inner", "scale", "amplitude"))
    for key, mm in (("alone", 0.0), ("damper", P.DESIGN["m"])):
        k = m == mm
        o = np.argsort(s[k])
        res[key] = curve(s[k][o], a[k][o])
    return res


def curve(gains, amps):
    """What an IDA curve on a grid says: the first passing gain, the gains above it that do not
    pass (fall back), and the amplitude's wiggles (a down step as the gain grows)."""
    gains, amps = np.asarray(gains, float), np.asarray(amps, float)
    p = amps > LIMIT
    if not p.any():
        return dict(first_pass=None, gains=gains.tolist(), amplitudes=amps.tolist())
    i = int(np.argmax(p))
    back = gains[i:][~p[i:]]
    down = np.diff(amps) < 0.0
    near = (gains >= gains[i] / 1.1) & (gains <= gains[i] * 1.1)
    slope = float(np.polyfit(np.log(gains[near]), np.log(amps[near]), 1)[0]) if near.sum() > 2 \
        else None
    return dict(slope=slope, first_pass=float(gains[i]), last_below=float(gains[i - 1]) if i else None,
                fall_back=back.tolist(), last_fall_back=float(back.max()) if len(back) else None,
                down_steps=int(down.sum()), steps=len(amps) - 1,
                largest_down=float(-np.min(np.diff(amps) / amps[:-1])) if down.any() else 0.0,
                gains=gains.tolist(), amplitudes=amps.tolist())


# ---------------------------------------------------------------- the report


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.path.join(P.ROOT, "target/release/impactsweep"))
    ap.add_argument("--record", default=os.path.join(P.ROOT, "configs/records/kt-synthetic.csv"))
    ap.add_argument("--out", default=os.path.join(P.ROOT, "results/peer_ida.md"))
    ap.add_argument("--json", default=os.path.join(P.ROOT, "results/peer_ida.json"))
    ap.add_argument("--grid", choices=["full", "quick"], default="full",
                    help="the damper's OpenSees (k, h): peer_random's whole grid, or one step a k")
    ap.add_argument("--reps", type=int, default=3, help="impactsweep's timing repetitions (medians)")
    ap.add_argument("--render", metavar="JSON", help="only write --out again from an earlier JSON")
    args = ap.parse_args()
    if args.render:
        with open(args.render) as f:
            res = json.load(f)
        with open(args.out, "w") as f:
            f.write(report(res))
        return
    binary = os.path.abspath(args.bin)
    if not os.access(binary, os.X_OK):
        sys.exit(f"error: {binary}: no such binary (cargo build --release, or --bin PATH)")
    load_before = P.uptime()
    print(load_before, file=sys.stderr)
    dt_rec, ag = P.read_record(args.record)
    own = float(np.max(np.abs(ag))) / G
    grid = P.OPS_GRID if args.grid == "full" else OPS_GRID_QUICK
    info = dict(
        record=os.path.relpath(os.path.abspath(args.record), P.ROOT), dt=dt_rec, samples=len(ag),
        pga=own, design=P.DESIGN, duration=P.DURATION, limit=LIMIT, stripe=STRIPE, ida_max=IDA_MAX,
        binary=subprocess.run([binary, "--version"], capture_output=True, text=True).stdout.strip(),
        commit=subprocess.run(["git", "-C", P.ROOT, "rev-parse", "--short", "HEAD"],
                              capture_output=True, text=True).stdout.strip(),
        python=P.platform.python_version(), numpy=np.__version__,
        openseespy=P._version("openseespy"),
        machine=f"{P.platform.machine()}, {os.cpu_count()} cpus, {P._cpu_model()}, "
                f"{P.platform.platform()}",
        load_before=load_before, grid=args.grid)
    res = dict(info=info)
    tmp = tempfile.mkdtemp(prefix="peer_ida_")
    try:
        shutil.copy(args.record, os.path.join(tmp, "record.csv"))
        res["impactsweep"] = [isw_ida(binary, tmp, tol, args.reps) for tol in ISW_TOLS]
        res["impactsweep_scan"] = isw_scan(binary, tmp)
        res["opensees_alone"] = [ops_ida(ag, dt_rec, own, h, None, OPS_TOL_ALONE, tmp)
                                 for h in OPS_H_ALONE]
        res["opensees"] = [ops_ida(ag, dt_rec, own, h, kc, OPS_TOL_DAMPER, tmp) for kc, h in grid]
        # OpenSees's IDA curve around its own capacity at one (k, h).
        kc, h = OPS_SCAN_CONFIG
        base = next(r for r in res["opensees"] if (r["kc"], r["h"]) == OPS_SCAN_CONFIG)
        g0 = base["capacity"] / own
        gains = g0 * (1.0 + OPS_SCAN)
        w0 = time.perf_counter()
        amps = [ops_peak(ag, dt_rec, g, h, kc, tmp) for g in gains]
        res["opensees_scan"] = dict(kc=kc, h=h, wall=time.perf_counter() - w0, **curve(gains, amps))
        print("opensees scan", res["opensees_scan"]["first_pass"],
              res["opensees_scan"]["fall_back"], file=sys.stderr)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    res["info"]["load_after"] = P.uptime()
    print(res["info"]["load_after"], file=sys.stderr)
    with open(args.json, "w") as f:
        json.dump(res, f, indent=1, default=float)
        f.write("\n")
    with open(args.out, "w") as f:
        f.write(report(res))
    print(f"wrote {args.out} and {args.json}", file=sys.stderr)


def rel(a, b):
    return (a - b) / b


def linear(b, trial, own):
    """The structure alone's capacity from one run (gain, max abs(x)): b / a times the gain."""
    return b / trial[1] * trial[0] * own


def report(res):
    i = res["info"]
    own, b = i["pga"], i["limit"]
    isw = {r["tol"]: r for r in res["impactsweep"]}
    fine, mid = isw[1e-6], isw[1e-3]
    A, D = fine["alone"], fine["damper"]
    A_lin = b / A["amplitude"] * A["scale"] * own  # from its stripe run
    sc = res["impactsweep_scan"]
    sd, so = sc["damper"], res["opensees_scan"]
    og = res["opensees"]
    per_run = sc["wall"] / sc["runs"]
    timed = next(o for o in og if (o["kc"], o["h"]) == tuple(OPS_SCAN_CONFIG))
    L = []
    w = L.append
    dz = i["design"]
    w("# Capacities by incremental dynamic analysis: impactsweep and OpenSeesPy (issue 67)\n")
    w("Written by `scripts/peer_ida.sh` (`scripts/peer_ida.py`, whose docstring states both "
      "searches; OpenSeesPy's model is `scripts/peer_random.py`'s) in one run; the raw numbers, "
      "every trial of every search and both IDA curves, are in `results/peer_ida.json`.\n")
    w(f"Record `{i['record']}` ({i['samples']} samples at dt = {i['dt']:g} s, PGA "
      f"{own:.6f} g at scale 1) as ground acceleration; design M = {dz['M']} kg, K = {dz['K']} "
      f"N/m, C = {dz['C']} N s/m (2 %), with a damper m = {dz['m']} kg, d = {dz['d']} m, e = "
      f"{dz['e']}, and the structure alone (m = 0); {i['duration']:g} s from rest. The capacity: "
      f"the PGA (g) at which max abs(x) first passes the limit b = {b} m as the record "
      f"is scaled (a run passes when max abs(x) > b). Both searches are impactsweep's "
      f"(`src/sim/random/ida.rs`; ported to Python for OpenSeesPy), both start at the stripe "
      f"{i['stripe']} g; impactsweep's is a record study with `intensity = \"pga\"`, "
      f"`threshold = {b}`, `im = [{i['stripe']}]`, read from `random_points` and from "
      "`capacities.csv` after `reduce` (the same bits).\n")
    w(f"Machine: {i['machine']}. Python {i['python']}, NumPy {i['numpy']}, OpenSeesPy "
      f"{i['openseespy']}; `{i['binary']}`; the scripts at `{i['commit']}`; OpenSeesPy's grid "
      f"`{i['grid']}`.  ")
    w(f"Load before: `{i['load_before']}`  ")
    w(f"Load after: `{i['load_after']}`\n")

    w("## Summary\n")
    oa = res["opensees_alone"]
    ocaps = [100 * rel(o["capacity"], D["capacity"]) for o in og]
    w("| design | impactsweep capacity (g), runs, `run` wall | OpenSeesPy capacity (g), runs, wall | difference |")
    w("|---|---|---|---|")
    w(f"| alone (m = 0), tol 1e-6 | {A['capacity']:.8f}, {A['capacity_runs']} runs, "
      f"{fine['wall']:.3f} s (both designs) | {oa[-1]['capacity']:.8f} (h = {oa[-1]['h']:g} s), "
      f"{oa[-1]['runs']} runs, {oa[-1]['wall']:.1f} s | "
      f"{rel(oa[-1]['capacity'], A['capacity']):+.1e} |")
    w(f"| damper, tol 1e-3 | {mid['damper']['capacity']:.6f}, {mid['damper']['capacity_runs']} "
      f"runs, {mid['wall']:.3f} s (both designs) | {timed['capacity']:.6f} (k = "
      f"{timed['kc']:.0e} N/m, h = {timed['h']:g} s), {timed['runs']} runs, {timed['wall']:.1f} s "
      f"| {100 * rel(timed['capacity'], mid['damper']['capacity']):+.2f} % |")
    w(f"| damper, OpenSeesPy over its {len(og)} (k, h) at tol 1e-3 against impactsweep at "
      f"tol 1e-6 ({D['capacity']:.6f} g) | | {min(o['capacity'] for o in og):.6f} … "
      f"{max(o['capacity'] for o in og):.6f} | {min(ocaps):+.2f} % … {max(ocaps):+.2f} % |")
    w("")

    w("## The structure alone\n")
    w("Linear: max abs(x) is in proportion to the gain, so the capacity is also b / max abs(x) "
      "times the gain of any one run (the closed form; from the search's first run, at the "
      "stripe). The searches find it to their tol / 2.\n")
    w("| peer | step | tol | capacity (g) | vs impactsweep (tol 1e-6) | closed form (g) | closed form vs impactsweep's | runs | falls back | wall (s) |")
    w("|---|---|---|---|---|---|---|---|---|---|")
    for r in res["impactsweep"]:
        a = r["alone"]
        w(f"| impactsweep | exact | {r['tol']:g} | {a['capacity']:.8f} | "
          f"{rel(a['capacity'], A['capacity']):+.1e} | {A_lin:.8f} | | {a['capacity_runs']} | "
          f"{'yes' if a['capacity_resurrected'] else 'no'} | {r['wall']:.3f} (both designs) |")
    for o in oa:
        lin = linear(b, o["trials"][0], own)
        w(f"| OpenSeesPy, Newmark | h = {o['h']:g} s | {o['tol']:g} | {o['capacity']:.8f} | "
          f"{rel(o['capacity'], A['capacity']):+.1e} | {lin:.8f} | {rel(lin, A_lin):+.1e} | "
          f"{o['runs']} | {'yes' if o['resurrected'] else 'no'} | {o['wall']:.2f} |")
    sa = sc["alone"]
    w(f"\nimpactsweep's IDA curve over gains {SCAN[0]:g} … {SCAN[-1]:g} (step "
      f"{SCAN[1] - SCAN[0]:g}): first passes at gain {sa['first_pass']:g} "
      f"({sa['first_pass'] * own:.6f} g), {len(sa['fall_back'])} gains above it fall back, "
      f"{sa['down_steps']} of {sa['steps']} steps lower max abs(x).\n")

    w("## With the damper\n")
    w(f"OpenSeesPy's penalty contacts over `scripts/peer_random.py`'s grid of contact stiffness "
      f"k and step h (`--grid {i['grid']}`), each searched to tol {OPS_TOL_DAMPER:g}; impactsweep "
      "(the restitution law, exact between samples) at three tolerances. Gain: the capacity over "
      "the record's own PGA.\n")
    w("| peer | contact k (N/m), step | tol | capacity (g) | gain | vs impactsweep (tol 1e-6) | peak at the stripe (mm) | runs | falls back (among its trials) | wall (s) |")
    w("|---|---|---|---|---|---|---|---|---|---|")
    for r in res["impactsweep"]:
        d = r["damper"]
        w(f"| impactsweep | exact | {r['tol']:g} | {d['capacity']:.6f} | "
          f"{d['capacity'] / own:.5f} | {100 * rel(d['capacity'], D['capacity']):+.3f} % | "
          f"{1e3 * d['amplitude']:.3f} | "
          f"{d['capacity_runs']} | {'yes' if d['capacity_resurrected'] else 'no'} | "
          f"{r['wall']:.3f} (both designs) |")
    for o in og:
        w(f"| OpenSeesPy, ViscoelasticGap | {o['kc']:.0e}, h = {o['h']:g} s | {o['tol']:g} | "
          f"{o['capacity']:.6f} | {o['capacity'] / own:.5f} | "
          f"{100 * rel(o['capacity'], D['capacity']):+.3f} % | {1e3 * o['trials'][0][1]:.3f} "
          f"({100 * rel(o['trials'][0][1], D['amplitude']):+.2f} %) | {o['runs']} | "
          f"{'yes' if o['resurrected'] else 'no'} | {o['wall']:.1f} |")
    w("")

    w("## The IDA curves near the limit\n")
    w(f"impactsweep: both designs at {len(SCAN)} gains {SCAN[0]:g} … {SCAN[-1]:g} (step "
      f"{SCAN[1] - SCAN[0]:g}; one record study of {sc['runs']} runs without an intensity, "
      f"`scale` swept: {sc['wall']:.2f} s, {1e6 * per_run:.0f} µs a run). OpenSeesPy: k = "
      f"{so['kc']:.0e} N/m, h = {so['h']:g} s, at {len(so['gains'])} gains within ±3 % of its "
      f"own capacity there (step 0.25 %; {so['wall']:.0f} s). The slope d ln max abs(x) / d ln "
      "gain is a least-squares line over ±10 % of the first passage.\n")
    w("| peer, damper | first passing gain (PGA, g) | last gain below it | gains above it that do not pass | the highest of them | steps down (of all steps) | largest step down | slope |")
    w("|---|---|---|---|---|---|---|---|")
    for name, c in (("impactsweep", sd), ("OpenSeesPy", so)):
        fb = c["fall_back"]
        slope = "" if c.get("slope") is None else f"{c['slope']:.2f}"
        w(f"| {name} | {c['first_pass']:.5f} ({c['first_pass'] * own:.5f}) | "
          f"{c['last_below']:.5f} | {len(fb)} | "
          f"{'' if c['last_fall_back'] is None else format(c['last_fall_back'], '.5f')} | "
          f"{c['down_steps']} of {c['steps']} | {100 * c['largest_down']:.2f} % | {slope} |")
    w("")
    g, a = np.array(sd["gains"]), np.array(sd["amplitudes"])
    top = sd["last_fall_back"] or sd["first_pass"]
    k = (g >= sd["first_pass"] - 0.01) & (g <= top + 0.01)
    w("impactsweep's max abs(x) near the limit (gain: mm): "
      + ", ".join(f"{gg:.4f}: {1e3 * aa:.3f}" for gg, aa in zip(g[k][::2], a[k][::2])) + ".\n")
    go, ao = np.array(so["gains"]), np.array(so["amplitudes"])
    w("OpenSeesPy's (gain: mm): " + ", ".join(f"{gg:.4f}: {1e3 * aa:.3f}" for gg, aa in
                                              zip(go, ao)) + ".\n")

    w("## Reading\n")
    lins = [rel(linear(b, o["trials"][0], own), A_lin) for o in oa]
    w(f"- **The structure alone agrees to {max(abs(x) for x in lins):.0e} in the closed form** "
      f"(OpenSeesPy's first run against impactsweep's: "
      + ", ".join(f"{x:+.1e} at h = {o['h']:g} s" for x, o in zip(lins, oa))
      + "; Newmark's period error and the peak read at the steps) and to "
      f"{max(abs(rel(o['capacity'], A['capacity'])) for o in oa):.0e} in the searched "
      f"capacities, which is the searches' tol / 2 = 5e-7 (impactsweep's search at tol 1e-6 ends "
      f"{rel(A['capacity'], A_lin):+.1e} from its own closed form). Same search, same runs: "
      f"{A['capacity_runs']} in impactsweep, {', '.join(str(o['runs']) for o in oa)} in OpenSeesPy. "
      f"Neither falls back (impactsweep's curve over {sa['steps'] + 1} gains never steps down).")
    speaks = [100 * rel(o["trials"][0][1], D["amplitude"]) for o in og]
    inside = [o for o in og if sd["first_pass"] / (1 + OPS_TOL_DAMPER) <= o["capacity"] / own
              <= top * (1 + OPS_TOL_DAMPER)]
    w(f"- **With the damper OpenSeesPy's capacities lie {min(ocaps):+.2f} % … {max(ocaps):+.2f} % "
      f"from impactsweep's** (tol 1e-6; median {float(np.median(ocaps)):+.2f} %) over "
      f"{len(og)} (k, h)"
      + "".join(f"; at the finest, k = {o['kc']:.0e} N/m, h = {o['h']:g} s, "
                f"{100 * rel(o['capacity'], D['capacity']):+.2f} %" for o in og
                if (o["kc"], o["h"]) == P.OPS_FINE)
      + f". At the stripe (gain {D['scale']:.4f}) the same "
      f"OpenSeesPy runs' peaks lie {min(speaks):+.2f} % … {max(speaks):+.2f} % from "
      f"impactsweep's (`results/peer_random.md` at scale 1: −2.1 % … +0.1 %). "
      f"{len(inside)} of the {len(og)} capacities lie within impactsweep's own zone of "
      f"crossings (gains {sd['first_pass']:.4f} … {top:.4f}, where its curve passes, falls back "
      "and passes again), where the impactsweep searches at its three tolerances also land "
      "(" + ", ".join(f"{r['damper']['capacity'] / own:.4f}" for r in res["impactsweep"])
      + "). Near the limit the peak grows about as the gain (slope "
      f"{sd['slope']:.2f} in impactsweep, {so['slope']:.2f} in OpenSeesPy), so a peak off by a "
      "percent moves the capacity by about a percent.")
    outside = [o for o in og if o not in inside]
    w(f"- **The damper's IDA curve is rough, in both.** impactsweep's max abs(x) steps down at "
      f"{sd['down_steps']} of its {sd['steps']} steps of {SCAN[1] - SCAN[0]:g} in gain (by up "
      f"to {100 * sd['largest_down']:.1f} %; the impacts' sequence changes with the gain). Near "
      f"b it first passes at gain {sd['first_pass']:.4f} ({sd['first_pass'] * own:.5f} g), "
      f"falls back at {len(sd['fall_back'])} gains up to {top:.4f}, then passes. The search at "
      f"tol 1e-6 ended on a crossing at {D['capacity'] / own:.5f}, "
      f"{100 * rel(D['capacity'] / own, sd['first_pass']):+.2f} % above the first passage on "
      "the grid, and says `capacity_resurrected = false`: a search flags a fall back only among "
      "its own trials and finds a crossing inside its bracket, the first one only where the "
      "curve is monotone (docs/scenes.md says so). No search of either tool flagged one here. "
      f"OpenSeesPy's curve is as rough: {so['down_steps']} of {so['steps']} steps of 0.25 % "
      f"down, {len(so['fall_back'])} gain(s) above its first passage "
      f"({so['first_pass']:.4f}) not passing. The zone where impactsweep's first passage is "
      f"ill-defined is {100 * (top / sd['first_pass'] - 1):.2f} % wide in gain; the two tools' "
      f"capacities differ by at most {max(abs(x) for x in ocaps):.2f} %"
      + (", within it." if not outside else
         f"; {len(outside)} of the {len(og)} lie outside the zone (" + ", ".join(
             f"k = {o['kc']:.0e}, h = {o['h']:g} s: gain {o['capacity'] / own:.4f}"
             for o in outside) + "), where the penalty contacts' own error shows (a "
         "restitution realized to about ±1 % per contact at fixed steps, a contact that lasts "
         "and indents; `results/peer_random.md`)."))
    w(f"- **Runs and time.** impactsweep's whole `run` command (start-up, plan, Parquet; both "
      f"designs, medians of {len(fine['walls'])}): {isw[1e-2]['wall']:.3f} s at tol 1e-2 "
      f"({isw[1e-2]['damper']['capacity_runs']} runs for the damper, "
      f"{isw[1e-2]['alone']['capacity_runs']} alone), {mid['wall']:.3f} s at 1e-3 "
      f"({mid['damper']['capacity_runs']} and {mid['alone']['capacity_runs']}), "
      f"{fine['wall']:.3f} s at 1e-6 ({D['capacity_runs']} and {A['capacity_runs']}); a run "
      f"costs about {1e6 * per_run:.0f} µs (the scan), so the damper's search at 1e-3 is about "
      f"{1e3 * mid['damper']['capacity_runs'] * per_run:.1f} ms of it. `reduce` "
      f"{mid['reduce_wall']:.2f} s. OpenSeesPy at tol 1e-3, per search: "
      + ", ".join(f"{o['runs']} runs in {o['wall']:.1f} s at k = {o['kc']:.0e}, h = {o['h']:g}"
                  for o in og)
      + f"; at k = {timed['kc']:.0e} N/m, h = {timed['h']:g} s (peer_random's timed "
      f"configuration) {timed['wall'] / mid['wall']:.0f}× impactsweep's whole command, "
      f"{timed['wall'] / timed['runs'] / per_run:.0f}× per run.")
    w("")
    return "\n".join(L) + "\n"


if __name__ == "__main__":
    main()

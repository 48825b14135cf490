"""`simulate(scene="random")` and `scene="record"` (issue 44): one realization with the same bits
as the sweep's row of it (compared with the points table `impactsweep run` writes), the stream's
normals handed back in giving the same run, and bad keys naming the key, the value and what is
allowed."""

from __future__ import annotations

import struct

import numpy as np
import pyarrow.parquet as pq
import pytest

import impactsweep as isw

OUTPUTS = ["outcome", "amplitude", "t_peak", "rms_x", "rms_acc", "first_passage_time", "impacts",
           "sticks", "energy_impact", "samples", "t_stop", "steps"]

# A damper under an enveloped Kanai-Tajimi ground acceleration (3 s, 600 samples), two
# intensities by two inner masses, four realizations each: impacts, sticking and first passages.
KT = dict(M=1.0, K=246.7, C=0.628, d=0.02, e=0.6, spectrum="kanai-tajimi", omega_g=15.708, zeta_g=0.6,
          duration=3.0, envelope={"t1": 0.5, "t2": 2.0, "c": 0.5}, threshold=0.01)
KT_STUDY = """
[study]
name = "kt"
seed = 11
[system]
M = 1.0
K = 246.7
C = 0.628
d = 0.02
e = 0.6
[scene]
kind = "random"
spectrum = "kanai-tajimi"
omega_g = 15.708
zeta_g = 0.6
duration = 3
envelope = { t1 = 0.5, t2 = 2, c = 0.5 }
threshold = 0.01
realizations = 4
[sweep]
S0 = [0.002, 0.02]
m = [0.0, 0.05]
"""

# White noise on a force (one normal per sample, 501), the default initial state overridden.
WHITE = dict(M=0.5, K=200.0, C=0.4, m=0.03, d=0.01, e=0.7, v0=0.1, input="force", spectrum="white",
             dt=0.004, duration=2.0)
WHITE_STUDY = """
[study]
name = "white"
seed = 18446744073709551615
[system]
M = 0.5
K = 200.0
C = 0.4
m = 0.03
d = 0.01
e = 0.7
v0 = 0.1
[scene]
kind = "random"
input = "force"
spectrum = "white"
dt = 0.004
duration = 2
realizations = 3
[sweep]
S0 = [0.5, 3.0]
"""


def bits(v):
    if isinstance(v, float):
        return ("f64", struct.unpack("<Q", struct.pack("<d", v))[0])
    return v


def rows(run_dir):
    files = sorted((run_dir / "points").glob("part-*.parquet"))
    return pq.read_table(files).to_pylist()


def same_as_the_sweep(cli, tmp_path, text, name, keys, seed):
    study = tmp_path / f"{name}.toml"
    study.write_text(text)
    p = cli("run", study, "--out", tmp_path / "out", "--quiet")
    assert p.returncode == 0, p.stderr
    table = rows(tmp_path / "out" / name)
    assert table
    keys = {k: v for k, v in keys.items() if k not in ("S0", "m")}
    for row in table:
        ours = isw.simulate(scene="random", **keys, S0=row["S0"], m=row["mass_inner"], seed=seed,
                            realization=row["case"])
        for k in OUTPUTS:
            v = ours[k]
            # The table's NaN is the record's None (JSON's null); its null first passage too.
            theirs = row[k]
            if isinstance(theirs, float) and np.isnan(theirs):
                theirs = None
            assert bits(v) == bits(theirs), (row["point_id"], k, v, theirs)
        assert ours["seed"] == seed and ours["realization"] == row["case"]
    return table


def test_a_realization_is_the_sweeps_row_bit_for_bit(cli, tmp_path):
    table = same_as_the_sweep(cli, tmp_path, KT_STUDY, "kt", KT, 11)
    assert len(table) == 16
    # The comparison saw what makes the scene hard: impacts and first passages.
    assert any(r["impacts"] > 0 for r in table)
    assert any(r["first_passage_time"] is not None for r in table)
    assert any(r["first_passage_time"] is None for r in table)


def test_white_noise_on_a_force_and_the_largest_seed(cli, tmp_path):
    table = same_as_the_sweep(cli, tmp_path, WHITE_STUDY, "white", WHITE, 2**64 - 1)
    assert len(table) == 6 and all(r["impacts"] > 0 for r in table)


def test_a_record_is_the_sweeps_row(cli, tmp_path):
    t = np.arange(401) * 0.005
    a = 3.0 * np.sin(2 * np.pi * 2.3 * t) * np.exp(-0.5 * t)
    csv = tmp_path / "quake.csv"
    csv.write_text("t,a\n" + "".join(f"{float(ti)!r},{float(ai)!r}\n" for ti, ai in zip(t, a)))
    study = tmp_path / "rec.toml"
    study.write_text('[study]\nname = "rec"\n[system]\nK = 246.7\nd = 0.02\n[scene]\nkind = "record"\n'
                     'record = "quake.csv"\nduration = 3\nthreshold = 0.02\n[sweep]\nscale = [0.5, 2.0]\n')
    p = cli("run", study, "--out", tmp_path / "out", "--quiet")
    assert p.returncode == 0, p.stderr
    table = rows(tmp_path / "out" / "rec")
    assert len(table) == 2
    for row in table:
        ours = isw.simulate(scene="record", record=csv, K=246.7, d=0.02, duration=3.0, threshold=0.02,
                            scale=row["scale"])
        assert [bits(ours[k]) for k in OUTPUTS[1:5]] == [bits(row[k]) for k in OUTPUTS[1:5]]
        assert [ours[k] for k in OUTPUTS[5:]] == [row[k] for k in OUTPUTS[5:]]
        assert ours["scene"] == "record" and ours["n_normals"] == 0 and ours["seed"] is None


def test_the_streams_normals_handed_in_are_the_same_run():
    for keys in (KT | {"S0": 0.02, "m": 0.05}, WHITE | {"S0": 3.0}):
        n = isw.n_normals(**keys)
        rec = isw.simulate(scene="random", **keys, seed=7, realization=5)
        assert rec["n_normals"] == n
        assert n == (600 if keys["spectrum"] == "kanai-tajimi" else 501)
        u = isw.realization_normals(n, seed=7, realization=5)
        given = isw.simulate(scene="random", **keys, normals=u)
        assert given["seed"] is None and given["realization"] is None
        assert {k: bits(given[k]) for k in OUTPUTS} == {k: bits(rec[k]) for k in OUTPUTS}
        # Another realization's normals, another run; the same normals twice, the same bits.
        other = isw.simulate(scene="random", **keys, normals=isw.realization_normals(n, seed=7, realization=6))
        assert bits(other["amplitude"]) != bits(rec["amplitude"])
        again = isw.simulate(scene="random", **keys, normals=list(u))
        assert {k: bits(again[k]) for k in OUTPUTS} == {k: bits(rec[k]) for k in OUTPUTS}
    # A duration that ends inside an interval: its last, short interval draws its normal too.
    for spectrum in ("white", "kanai-tajimi"):
        keys = KT | {"S0": 0.02, "m": 0.05, "spectrum": spectrum, "duration": 1.0013}
        if spectrum == "white":
            del keys["omega_g"], keys["zeta_g"]
        n = isw.n_normals(**keys)
        assert n == (202 if spectrum == "white" else 201)
        rec = isw.simulate(scene="random", **keys, seed=3, realization=1)
        given = isw.simulate(scene="random", **keys, normals=isw.realization_normals(n, seed=3, realization=1))
        assert rec["samples"] == 201 and bits(rec["t_stop"]) == bits(1.0013)
        assert {k: bits(given[k]) for k in OUTPUTS} == {k: bits(rec[k]) for k in OUTPUTS}
    # The normals scale the load: all zero, the structure stays at rest.
    rest = isw.simulate(scene="random", **KT, S0=0.02, normals=np.zeros(600))
    assert rest["amplitude"] == 0.0 and rest["impacts"] == 0


def test_a_motion_at_a_stripe_is_the_sweeps_row_normals_handed_in_included():
    """``intensity`` and ``im``: the motion scaled to the stripe as the sweep scales it, from its
    stream or from its normals handed in (subset simulation at a stripe from Python)."""
    cp = dict(M=1.0, K=246.7, C=0.628, m=0.05, d=0.02, e=0.6, spectrum="clough-penzien", S0=0.004,
              duration=3.0, threshold=0.02, intensity="sa")
    n = isw.n_normals(**cp)
    batch = isw.simulate_batch({"im": np.array([0.2, 0.2, 0.6]), "realization": np.array([2, 5, 5])},
                               scene="random", seed=4, **cp).to_pylist()
    for row in batch:
        keys = cp | {"im": row["im"]}
        streamed = isw.simulate(scene="random", **keys, seed=4, realization=row["case"])
        u = isw.realization_normals(n, seed=4, realization=row["case"])
        given = isw.simulate(scene="random", **keys, normals=u)
        for rec in (streamed, given):
            for k in OUTPUTS[1:] + ["pga", "sa", "scale", "capacity", "capacity_censored", "capacity_runs"]:
                theirs = row[k]
                if isinstance(theirs, float) and np.isnan(theirs):
                    theirs = None
                assert bits(rec[k]) == bits(theirs), (row["point_id"], k, rec[k], theirs)
        # The stripe is the motion's own Sa times its scale; the capacity is searched at it.
        assert abs(given["sa"] * given["scale"] / row["im"] - 1) < 1e-12
        assert given["capacity_runs"] >= 2 and given["random"]["intensity"] == "sa"
    # Another stripe, another run of the same motion: the same capacity to its tolerance (its
    # search starts from the stripe's run); the capacity only where asked for.
    low, high = (isw.simulate(scene="random", **cp, im=im, normals=u, outputs=["amplitude", "capacity"])
                 for im in (0.2, 0.6))
    assert low["amplitude"] < high["amplitude"] and abs(low["capacity"] / high["capacity"] - 1) < 0.01
    quick = isw.simulate(scene="random", **cp, im=0.6, normals=u, outputs=["amplitude", "scale"])
    assert bits(quick["amplitude"]) == bits(high["amplitude"]) and quick["scale"] > 0
    bare = isw.simulate(scene="random", **cp, im=0.6, normals=u, outputs=["capacity_runs", "sticks"])
    assert bare["capacity_runs"] == isw.simulate(scene="random", **cp, im=0.6, normals=u)["capacity_runs"] > 0
    # A stripe without an intensity measure, or out of range, is the study's error, named as the
    # keyword argument names it.
    with pytest.raises(ValueError, match="im"):
        isw.simulate(scene="random", **{k: v for k, v in cp.items() if k != "intensity"}, im=0.3)
    with pytest.raises(ValueError, match=r"^im = -1: a stripe's intensity \(g\) must be in \[1e-6, 1000\]"):
        isw.simulate(scene="random", **cp, im=-1)


def test_the_trace_of_a_motion_at_a_stripe():
    """``trace(scene="random")``: the realization ``simulate`` runs, its waveform every ``dt`` and
    at every impact, and the load at the scale it ran at."""
    cp = dict(M=1.0, K=246.7, C=0.628, m=0.05, d=0.02, e=0.6, spectrum="clough-penzien", duration=3.0,
              threshold=0.02, intensity="pga", im=0.4)
    u = isw.realization_normals(isw.n_normals(**cp), seed=2, realization=9)
    tr = isw.trace(scene="random", normals=u, dt=0.002, **cp)
    rec = isw.simulate(scene="random", normals=u, outputs=["amplitude", "impacts", "pga", "scale"], **cp)
    assert bits(tr["record"]["amplitude"]) == bits(rec["amplitude"]) and tr["record"]["capacity"] is None
    # The samples never pass the run's largest |x|, and come within a hair of it.
    top = np.abs(tr["x"]).max()
    assert top <= rec["amplitude"] and top > 0.98 * rec["amplitude"]
    assert len(tr["impacts"]) == rec["impacts"] > 0 and np.all(np.diff(tr["t"]) >= 0)
    assert tr["t"][-1] == pytest.approx(3.0) and np.all(np.abs(tr["x"] - tr["y"]) <= 0.01 + 1e-12)
    # The load at the stripe: its PGA is the stripe's 0.4 g.
    assert len(tr["load"]) == 601 and tr["load_dt"] == 0.005
    assert abs(np.abs(tr["load"]).max() / 9.80665 / 0.4 - 1) < 1e-12
    assert rec["pga"] * rec["scale"] == pytest.approx(0.4, rel=1e-12)
    # The stream it names, the same motion.
    streamed = isw.trace(scene="random", seed=2, realization=9, dt=0.002, **cp)
    assert all(np.array_equal(streamed[k], tr[k]) for k in ("t", "x", "v", "y", "w", "impacts", "load"))
    with pytest.raises(ValueError, match=r"^dt=1e-9: the trace of a 3 s run would hold 3e9 rows; allowed at most 1e7 \(dt >= duration / 1e7 = 3e-7 s\)"):
        isw.trace(scene="random", normals=u, dt=1e-9, **cp)
    with pytest.raises(ValueError, match=r"^t_end=1.0: a free-decay option"):
        isw.trace(scene="random", normals=u, t_end=1.0, **cp)


def test_the_record_names_its_setup():
    rec = isw.simulate(scene="random", spectrum="white", S0=0.01, duration=1.0)
    assert rec["scene"] == "random" and rec["outcome"] == "ok"
    assert rec["system"]["v0"] == 0.0                   # a random study starts at rest
    assert rec["random"]["dt"] == 0.005 and rec["random"]["threshold"] is None
    assert rec["first_passage_time"] is None and rec["samples"] == 200
    assert list(isw.simulate(scene="random", spectrum="white", S0=0.01, duration=1.0,
                             outputs=["amplitude", "rms_x"])) == ["amplitude", "rms_x"]


@pytest.mark.parametrize(
    "keys, message",
    [
        (dict(S0=-1.0), r"^S0 = -1: the two-sided spectral density must be in \(0, 1e12\]"),
        (dict(S0=0.01, duration=0.0), r"^duration = 0: the run's length \(s\) must be in \(0, 1000000\]"),
        (dict(S0=0.01, dt=2.0), r"^dt = 2: the load's sample interval \(s\) must be in \[1e-6, 1\]"),
        (dict(S0=0.01, e=1.3), r"^e = 1.3: "),
        (dict(S0=0.01, threshold=-0.1), r"^threshold = -0.1: the limit of \|x\| \(m\) must be a finite number > 0"),
        (dict(S0=0.01, omega_g=10.0), r"^omega_g = 10.0: spectrum = \"white\" has no omega_g"),
        (dict(S0=0.01, spectrum="pink"), r"^spectrum = \"pink\": unknown spectrum; allowed: white, kanai-tajimi"),
        (dict(S0=0.01, input="wind"), r"^input = \"wind\": unknown input; allowed: base"),
        (dict(S0=0.01, solver="rk4"), r"^solver = \"rk4\": "),
        (dict(S0=0.01, envelope={"t1": 2.0, "t2": 1.0, "c": 0.3}), r"^envelope.t2 = 1: .* at least its rise t1 = 2"),
        (dict(S0=0.01, envelope=(1, 2, 3)), r"^envelope=\(1, 2, 3\): expected a mapping"),
        (dict(S0=0.01, F0=0.1), r"^F0=0.1: unknown key for scene='random'; allowed keys: input spectrum S0"),
        (dict(S0=0.01, scale=2.0), r"^scale=2.0: a key of the record scene for scene='random'"),
        (dict(S0="big"), r"^S0='big': expected a number"),
        (dict(S0=0.01, max_steps=1.5), r"^max_steps=1.5: must be a whole number >= 0"),
        (dict(S0=0.01, realization=-1), r"^realization=-1: must be a whole number in \[0, 2\^64\)"),
        (dict(S0=0.01, seed=1.0), r"^seed=1.0: must be a whole number"),
        (dict(S0=0.01, normals=np.zeros(3)), r"^normals: 3 values; this load draws n_normals = 201 standard normals"),
        (dict(S0=0.01, normals=np.zeros((2, 201))), r"^normals: 2-dimensional"),
        (dict(S0=0.01, normals=np.full(201, np.nan)), r"^normals\[0\] = NaN: a standard normal must be finite"),
        (dict(S0=0.01, normals=np.zeros(201), seed=3), r"^normals: given with seed or realization"),
    ],
)
def test_bad_keys_name_the_key_the_value_and_what_is_allowed(keys, message):
    with pytest.raises(ValueError, match=message):
        isw.simulate(scene="random", spectrum=keys.pop("spectrum", "white"), duration=keys.pop("duration", 1.0),
                     **keys)


def test_other_bad_calls():
    with pytest.raises(ValueError, match=r"^spectrum: missing; the random scene needs a spectrum"):
        isw.simulate(scene="random", S0=0.01, duration=1.0)
    with pytest.raises(ValueError, match=r"^scene='noise': unknown scene; allowed: free, harmonic, random, record"):
        isw.simulate(scene="noise")
    with pytest.raises(ValueError, match=r"^realization: a key of the random scene"):
        isw.simulate(e=0.8, realization=3)
    with pytest.raises(ValueError, match=r"^record: missing; the record scene needs record"):
        isw.simulate(scene="record", duration=1.0)
    with pytest.raises(ValueError, match=r"^n=-1: must be a whole number >= 0"):
        isw.realization_normals(-1)
    with pytest.raises(ValueError, match=r"^subset=50: expected 0 \(Monte Carlo only\) or a whole number of samples per level"):
        isw.reduce("nowhere", subset=50)
    with pytest.raises(ValueError, match=r"^subset=-5: expected 0 \(Monte Carlo only\) or a whole number of samples per level"):
        isw.reduce("nowhere", subset=-5)
    with pytest.raises(ValueError, match=r"^subset_repeats=0: expected a whole number of independent subset simulations"):
        isw.reduce("nowhere", subset_repeats=0)

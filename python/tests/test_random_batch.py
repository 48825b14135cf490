"""`simulate_batch(scene="random")` and `scene="record"` (issue 67 item 9): one realization per
row, the `random_points` rows `impactsweep run` writes for the same designs, realizations and
seed, bit for bit (but for `point`, the row's own place), on 1 and 2 threads; the command line's
`simulate --set scene=random` gives the same row; bad columns name what is allowed."""

from __future__ import annotations

import json

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

import impactsweep as isw

# A damper under a Clough-Penzien ground acceleration scaled to the stripe PGA = 0.3 g (2 s),
# two inner masses, three realizations: capacities by incremental dynamic analysis, impacts and
# first passages. The filters and the initial state are the defaults of both sides.
FIXED = dict(M=1.0, K=246.7, C=0.628, d=0.02, e=0.6, spectrum="clough-penzien", S0=0.004,
             duration=2.0, envelope={"t1": 0.3, "t2": 1.5, "c": 0.5}, threshold=0.01, intensity="pga",
             im=0.3)
STUDY = """
[study]
name = "cp"
seed = 23
[system]
M = 1.0
K = 246.7
C = 0.628
d = 0.02
e = 0.6
[scene]
kind = "random"
spectrum = "clough-penzien"
S0 = 0.004
duration = 2
envelope = { t1 = 0.3, t2 = 1.5, c = 0.5 }
threshold = 0.01
intensity = "pga"
realizations = 3
[sweep]
m = [0.0, 0.05]
im = [0.3]
"""


def points(run_dir):
    files = sorted((run_dir / "points").glob("part-*.parquet"))
    return pa.concat_tables([pq.read_table(f) for f in files])


def assert_same(ours: pa.Table, theirs: pa.Table, skip=("point",)):
    assert ours.column_names == theirs.column_names
    assert ours.num_rows == theirs.num_rows
    for name in ours.column_names:
        if name in skip:
            continue
        a, b = ours.column(name).combine_chunks(), theirs.column(name).combine_chunks()
        if pa.types.is_floating(a.type):
            assert a.null_count == b.null_count, name
            va = a.fill_null(0.0).to_numpy(zero_copy_only=False).view(np.uint64)
            vb = b.fill_null(0.0).to_numpy(zero_copy_only=False).view(np.uint64)
            assert np.array_equal(va, vb), name
        else:
            if pa.types.is_dictionary(a.type):
                a, b = a.cast(pa.string()), b.cast(pa.string())
            assert a.to_pylist() == b.to_pylist(), name


def test_a_random_batch_is_the_sweeps_points_table(cli, tmp_path):
    study = tmp_path / "cp.toml"
    study.write_text(STUDY)
    p = cli("run", study, "--out", tmp_path / "out", "--quiet")
    assert p.returncode == 0, p.stderr
    theirs = points(tmp_path / "out" / "cp")
    assert theirs.num_rows == 6
    assert theirs.column("capacity").null_count == 0
    inputs = {"mass_inner": theirs.column("mass_inner").to_numpy(),
              "realization": theirs.column("case").to_numpy()}
    for threads in (1, 2):
        ours = isw.simulate_batch(inputs, threads=threads, scene="random", seed=23, **FIXED)
        assert_same(ours, theirs)
        assert ours.column("point").to_pylist() == list(range(6))
    # The command line's realization at hand is the same row.
    row = theirs.slice(4, 1).to_pylist()[0]
    sets = ["scene=random", "spectrum=clough-penzien", "S0=0.004", "duration=2", "envelope=0.3,1.5,0.5",
            "threshold=0.01", "intensity=pga", "im=0.3", "M=1", "K=246.7", "C=0.628", "d=0.02", "e=0.6",
            f"m={row['mass_inner']!r}", f"realization={row['case']}", "seed=23"]
    args = [a for s in sets for a in ("--set", s)]
    out = cli("simulate", *args, "--json")
    assert out.returncode == 0, out.stderr
    rec = json.loads(out.stdout)
    assert rec["record"]["amplitude"] == row["amplitude"]
    assert rec["capacity"]["capacity"] == row["capacity"]
    assert rec["own"]["pga"] == row["pga"]


def test_a_record_batch_and_the_default_realization(cli, tmp_path):
    t = np.arange(301) * 0.01
    a = 3.0 * np.sin(2 * np.pi * 2.3 * t) * np.exp(-0.5 * t)
    csv = tmp_path / "quake.csv"
    csv.write_text("t,a\n" + "".join(f"{float(ti)!r},{float(ai)!r}\n" for ti, ai in zip(t, a)))
    study = tmp_path / "rec.toml"
    study.write_text('[study]\nname = "rec"\n[system]\nK = 246.7\nd = 0.02\n[scene]\nkind = "record"\n'
                     'record = "quake.csv"\nthreshold = 0.02\n[sweep]\nscale = [0.5, 2.0]\n')
    p = cli("run", study, "--out", tmp_path / "out", "--quiet")
    assert p.returncode == 0, p.stderr
    theirs = points(tmp_path / "out" / "rec")
    ours = isw.simulate_batch({"scale": theirs.column("scale")}, scene="record", record=csv, K=246.7,
                              d=0.02, threshold=0.02)
    assert_same(ours, theirs, skip=())
    # Without a realization column every row runs the same load (realization 0): the same
    # design twice is the same row.
    same = isw.simulate_batch({"m": [0.01, 0.01]}, scene="random", spectrum="white", S0=0.01, duration=1.0)
    assert same.column("case").to_pylist() == [0, 0]
    assert same.column("amplitude")[0] == same.column("amplitude")[1]
    mc = isw.simulate_batch({"realization": np.arange(3)}, scene="random", spectrum="white", S0=0.01,
                            duration=1.0, seed=4)
    assert mc.column("case").to_pylist() == [0, 1, 2]
    assert len(set(mc.column("amplitude").to_pylist())) == 3


@pytest.mark.parametrize(
    "inputs, fixed, message",
    [
        ({"omega_g": [1.0]}, {}, r"^input column 'omega_g': not a key of this setup's load; allowed: M m K"),
        ({"F0": [1.0]}, {}, r"^input column 'F0': a key of the harmonic scene"),
        ({"realization": [0.5]}, {}, r"^row 0: realization = 0.5: must be a whole number in \[0, 9999999\]"),
        ({"S0": [0.01, -1.0]}, {}, r"^row 1: S0 = -1: the two-sided spectral density"),
        ({"im": [0.2]}, {}, r"^input column 'im': not a key of this setup's load"),
        ({"m": [0.01]}, {"realization": 10**7}, r"^--set realization=10000000: must be a whole number in \[0, 9999999\]"),
        ({"m": [0.01]}, {"zeta_g": 0.3}, r"^--set zeta_g = 0.3: spectrum = \"white\" has no zeta_g"),
        ({"m": [0.01]}, {"F0": 0.3}, r"^--set F0=0.3: a key of the harmonic scene for scene=random"),
    ],
)
def test_bad_random_batches_name_what_is_allowed(inputs, fixed, message):
    with pytest.raises(ValueError, match=message):
        isw.simulate_batch(inputs, scene="random", spectrum="white", S0=0.01, duration=1.0, **fixed)


def test_the_seed_of_a_batch_is_its_argument():
    sets = ["scene=random", "spectrum=white", "S0=0.01", "duration=1", "seed=3"]
    with pytest.raises(ValueError, match=r"^seed=3: the study seed of a batch is its seed argument"):
        isw._ext.simulate_batch(sets, [], [], 1, None, 0)


def test_a_batch_on_normals_handed_in_is_each_rows_run(cli, tmp_path):
    """``normals=``: row ``i`` runs on its row of standard normals, at the stripe: the sweep's row
    of the realization whose stream drew them (but ``case``, 0), ``simulate``'s record of them,
    on 1 and 2 threads; bad normals name what is wrong."""
    study = tmp_path / "cp.toml"
    study.write_text(STUDY)
    p = cli("run", study, "--out", tmp_path / "out", "--quiet")
    assert p.returncode == 0, p.stderr
    theirs = points(tmp_path / "out" / "cp")
    n = isw.n_normals(**FIXED)
    cases = theirs.column("case").to_pylist()
    u = np.stack([isw.realization_normals(n, seed=23, realization=c) for c in cases])
    inputs = {"mass_inner": theirs.column("mass_inner").to_numpy()}
    for threads in (1, 2):
        ours = isw.simulate_batch(inputs, threads=threads, scene="random", normals=u, **FIXED)
        assert ours.column("case").to_pylist() == [0] * len(cases)
        assert ours.column("noise_seed").null_count == len(cases)
        assert_same(ours, theirs, skip=("point", "case", "noise_seed"))
    # Each row is simulate's run of its normals; the normals alone give the rows.
    m = FIXED | {"m": 0.05}
    rows = isw.simulate_batch({}, scene="random", normals=u[:2], **m).to_pylist()
    for row, ui in zip(rows, u[:2]):
        rec = isw.simulate(scene="random", normals=ui, **m)
        assert [rec[k] for k in ("amplitude", "rms_x", "capacity", "scale")] == \
            [row[k] for k in ("amplitude", "rms_x", "capacity", "scale")]
    # Without the capacity search: the capacity columns null, every other column the same.
    quick = isw.simulate_batch(inputs, scene="random", normals=u, capacity=False, **FIXED)
    assert quick.column("capacity").null_count == len(cases)
    assert_same(quick, ours, skip=("capacity", "capacity_censored", "capacity_resurrected", "capacity_runs"))
    with pytest.raises(ValueError, match=r"^capacity=False: a random or record scene's option"):
        isw.simulate_batch({"e": [0.5]}, capacity=False)
    with pytest.raises(ValueError, match=r"^normals: 2 rows for input columns of 3"):
        isw.simulate_batch({"m": [0.01, 0.02, 0.03]}, scene="random", normals=u[:2], **FIXED)
    with pytest.raises(ValueError, match=r"^normals: 1-dimensional; expected one row"):
        isw.simulate_batch({}, scene="random", normals=u[0], **FIXED)
    with pytest.raises(ValueError, match=rf"^normals: {2 * (n - 1)} values for 2 rows; this load draws n_normals = {n}"):
        isw.simulate_batch({}, scene="random", normals=u[:2, 1:], **FIXED)
    with pytest.raises(ValueError, match=r"^normals: given with realization"):
        isw.simulate_batch({"realization": [0, 1]}, scene="random", normals=u[:2], **FIXED)
    bad = u[:2].copy()
    bad[1, 3] = np.nan
    with pytest.raises(ValueError, match=r"^normals\[1, 3\] = NaN: a standard normal must be finite"):
        isw.simulate_batch({}, scene="random", normals=bad, **FIXED)
    with pytest.raises(ValueError, match=r"^normals: only a random load draws normals"):
        isw.simulate_batch({}, scene="record", normals=u[:2], record="x.csv")

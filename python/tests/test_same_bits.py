"""The package gives the command line's bits (issue 17's acceptance): `simulate` equals
`impactsweep simulate --json` on 50 random systems of each scene, and `simulate_batch` equals
the points table `impactsweep run` writes for the same study, on 1 and 2 threads."""

from __future__ import annotations

import json
import math
import struct

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

import impactsweep as isw


def bits(v):
    """A JSON-like value with every float replaced by its IEEE-754 bits (so -0.0 != 0.0)."""
    if isinstance(v, float):
        return ("f64", struct.unpack("<Q", struct.pack("<d", v))[0])
    if isinstance(v, dict):
        return {k: bits(x) for k, x in v.items()}
    if isinstance(v, list):
        return [bits(x) for x in v]
    return v


def random_free(rng):
    return {
        "M": float(rng.uniform(0.05, 0.2)),
        "m": float(rng.uniform(0.002, 0.04)),
        "K": float(rng.uniform(200.0, 800.0)),
        "C": float(rng.uniform(0.0, 0.5)),
        "d": float(rng.uniform(0.002, 0.03)),
        "e": float(rng.uniform(0.3, 1.0)),
        "v0": float(rng.uniform(0.5, 3.0)),
    }


def random_harmonic(rng):
    return {
        "m": float(rng.uniform(0.002, 0.03)),
        "d": float(rng.uniform(0.003, 0.02)),
        "e": float(rng.uniform(0.4, 0.95)),
        "F0": float(rng.uniform(0.05, 0.2)),
        "r": float(rng.uniform(0.7, 1.3)),
        "n_meas": 4,
        # A brief design life: the bits compared are the same for any length, and the census's
        # chaotic leaders would otherwise each run 1,024,000 periods.
        "life_max_periods": 2000,
    }


@pytest.mark.parametrize("scene", ["free", "harmonic"])
def test_simulate_equals_the_command_line_on_50_random_systems(cli, scene):
    rng = np.random.default_rng(17 if scene == "free" else 71)
    for _ in range(50):
        keys = random_free(rng) if scene == "free" else random_harmonic(rng)
        ours = isw.simulate(scene=scene, **keys)
        args = ["simulate", "--json"]
        if scene != "free":
            args += ["--set", f"scene={scene}"]
        for k, v in keys.items():
            args += ["--set", f"{k}={v!r}"]
        p = cli(*args)
        assert p.returncode == 0, p.stderr
        theirs = json.loads(p.stdout)
        assert list(ours) == list(theirs)
        assert bits(ours) == bits(theirs), keys


def test_simulate_of_several_units_takes_their_census_as_the_command_line_does(cli):
    """Two units near resonance with four starts: the census of several units runs from
    Python as from the command line (the same bits), and its summary is in the record."""
    keys = {"m": 0.02, "d": 0.01, "e": 0.7, "C": 1.0, "v0": 0.0, "units": 2, "d_spread": 0.2,
            "F0": 0.5, "r": 1.0, "starts": 4, "n_meas": 50, "n_trans_max": 600}
    ours = isw.simulate(scene="harmonic", **keys)
    args = ["simulate", "--json", "--set", "scene=harmonic"]
    for k, v in keys.items():
        args += ["--set", f"{k}={v!r}"]
    p = cli(*args)
    assert p.returncode == 0, p.stderr
    assert bits(ours) == bits(json.loads(p.stdout))
    assert ours["starts"] == 4 and ours["attractors"] >= 1
    assert ours["amplitude_worst"] >= ours["amplitude"] * (1 - 1e-9)


def test_the_readme_line(cli):
    p = cli("simulate", "--set", "e=0.9", "--json")
    assert isw.simulate(e=0.9)["xmax"] == json.loads(p.stdout)["xmax"]


def test_outputs_selects_keys():
    assert list(isw.simulate(e=0.8, outputs=["xmax", "di"])) == ["xmax", "di"]
    with pytest.raises(ValueError, match="outputs: unknown key 'nope'"):
        isw.simulate(outputs=["nope"])


def read_points(run_dir):
    files = sorted((run_dir / "points").glob("part-*.parquet"))
    return pa.concat_tables([pq.read_table(f) for f in files])


#: The census columns of a harmonic run: a sweep's census seeds each frequency with its curve's
#: neighbours' attractors (docs/scenes.md, "A curve is one task"), a batch row has no curve.
CENSUS_COLUMNS = {
    "starts", "attractors", "amplitude_worst", "worst_period", "worst_impacts_per_period",
    "worst_basin_share", "rest_amplitude", "rest_period", "census_periods", "worst_kind",
    "worst_lyapunov", "worst_window_amplitude", "worst_life_lo", "worst_life_hi",
}


def assert_same_table(ours: pa.Table, theirs: pa.Table, skip=frozenset()):
    assert ours.column_names == theirs.column_names
    assert ours.num_rows == theirs.num_rows
    for name in ours.column_names:
        if name in skip:
            continue
        a, b = ours.column(name).combine_chunks(), theirs.column(name).combine_chunks()
        if pa.types.is_floating(a.type):
            assert b.type == a.type, name
            va = a.to_numpy(zero_copy_only=False).view(np.uint64)
            vb = b.to_numpy(zero_copy_only=False).view(np.uint64)
            assert np.array_equal(va, vb), name
        else:
            if pa.types.is_dictionary(a.type):
                a, b = a.cast(pa.string()), b.cast(pa.string())
            assert a.to_pylist() == b.to_pylist(), name


FREE_STUDY = """
[study]
name = "batch"
[system]
C = 0.2
[sweep]
e = { start = 0.5, stop = 0.95, num = 10 }
m = [0.005, 0.01, 0.03]
d = [0.004, 0.01, 0.02]
[run]
chunk_points = 16
"""

HARMONIC_STUDY = """
[study]
name = "fbatch"
[system]
v0 = 0.0
[scene]
kind = "harmonic"
F0 = 0.1
n_meas = 8
life_max_periods = 2000
[sweep]
m = [0.005, 0.02]
d = [0.005, 0.015]
r = { start = 0.85, stop = 1.15, num = 13 }
"""


@pytest.mark.parametrize(
    "text,name,columns,fixed",
    [
        (FREE_STUDY, "batch", ["e", "mass_inner", "d"], {"C": 0.2}),
        (HARMONIC_STUDY, "fbatch", ["mass_inner", "d", "r"], {"v0": 0.0, "F0": 0.1, "n_meas": 8, "life_max_periods": 2000, "scene": "harmonic"}),
    ],
    ids=["free", "harmonic"],
)
def test_simulate_batch_equals_the_points_table_on_1_and_2_threads(cli, tmp_path, text, name, columns, fixed):
    study = tmp_path / "study.toml"
    study.write_text(text)
    p = cli("run", study, "--out", tmp_path / "out", "--quiet", "--threads", 2)
    assert p.returncode == 0, p.stderr
    theirs = read_points(tmp_path / "out" / name)
    assert theirs.num_rows > 30
    inputs = theirs.select(columns)
    # A batch row's census is its own frequency's alone; the rest is the sweep's, bit for bit.
    skip = CENSUS_COLUMNS if fixed.get("scene") == "harmonic" else frozenset()
    first = None
    for threads in (1, 2):
        ours = isw.simulate_batch(inputs, threads=threads, **fixed)
        assert_same_table(ours, theirs, skip)
        if first is None:
            first = ours
        assert_same_table(ours, first)  # every column, the census's too, on any thread count
    # A mapping of NumPy arrays and (when polars is there) a polars DataFrame give the same.
    as_dict = {c: theirs.column(c).to_numpy() for c in columns}
    assert_same_table(isw.simulate_batch(as_dict, **fixed), first)
    pl = pytest.importorskip("polars")
    assert_same_table(isw.simulate_batch(pl.from_arrow(inputs), **fixed), first)


def test_run_from_python_writes_what_the_command_line_writes(cli, tmp_path):
    study = tmp_path / "study.toml"
    study.write_text(FREE_STUDY)
    p = cli("run", study, "--out", tmp_path / "cli", "--quiet")
    assert p.returncode == 0, p.stderr
    summary = isw.run(study, out=tmp_path / "py", threads=1)
    assert summary["runs"] == 90 and summary["chunks_left"] == 0
    for a, b in zip(
        sorted((tmp_path / "cli/batch/points").glob("*.parquet")),
        sorted((tmp_path / "py/batch/points").glob("*.parquet")),
    ):
        assert a.read_bytes() == b.read_bytes()
    st = isw.status(tmp_path / "py/batch")
    assert st["complete"] and st["runs_done"] == 90
    assert st["text"] == cli("status", tmp_path / "py/batch").stdout
    # One math library in both (the records' bits depend on it): the binary's fingerprint, as
    # its manifest records it, is the extension's.
    assert len(st["math"]) == 16 and st["math"] == st["math_here"]
    assert isw.status(tmp_path / "cli/batch")["math"] == st["math_here"]
    assert isw.load(tmp_path / "py/batch").count_rows() == 90
    pl = pytest.importorskip("polars")
    lazy = isw.load(tmp_path / "py/batch", polars=True)
    assert lazy.select(pl.len()).collect().item() == 90
    plan = isw.plan(study, out=tmp_path / "py")
    assert (plan["n_points"], plan["n_cases"], plan["n_runs"]) == (90, 1, 90)
    assert plan["axes"]["m"] == [0.005, 0.01, 0.03]
    line = isw.reduce(tmp_path / "py/batch")
    assert line and (tmp_path / "py/batch/report.md").exists()


def test_trace_gives_the_waveform_and_the_impacts():
    tr = isw.trace(e=0.8, dt=1e-3)
    assert len(tr["t"]) == len(tr["x"]) == len(tr["y"]) > 100
    assert np.all(np.diff(tr["t"]) >= 0)
    assert tr["record"]["impacts"] == len(tr["impacts"]) > 0
    assert math.isclose(tr["record"]["xmax"], isw.simulate(e=0.8)["xmax"], rel_tol=1e-9)
    assert math.isclose(np.max(tr["x"]), tr["record"]["xmax"], rel_tol=0.05)


def test_load_reads_the_attractors_table_every_case_and_names_a_missing_one(cli, tmp_path):
    study = tmp_path / "study.toml"
    study.write_text(HARMONIC_STUDY + "[perturb]\ndd = [0.001]\n[run]\nchunk_points = 13\n")
    p = cli("run", study, "--out", tmp_path / "out", "--quiet")
    assert p.returncode == 0, p.stderr
    run_dir = tmp_path / "out" / "fbatch"
    files = sorted((run_dir / "attractors").glob("part-*.parquet"))
    assert len(files) == 4
    direct = pa.concat_tables([pq.read_table(f) for f in files])
    table = isw.load(run_dir, table="attractors").to_table()
    assert_same_table(table, direct)  # every value to its last bit (NaN included)
    # Every run of every case has its steady states.
    runs = set(zip(table.column("point_id").to_pylist(), table.column("case").to_pylist()))
    points = isw.load(run_dir).to_table()
    assert runs == set(zip(points.column("point_id").to_pylist(), points.column("case").to_pylist()))
    assert len(runs) == 52 * 2
    pl = pytest.importorskip("polars")
    lazy = isw.load(run_dir, table="attractors", polars=True)
    assert lazy.select(pl.len()).collect().item() == table.num_rows
    # A free-decay run has no attractors table; an unknown table is named with the allowed ones.
    free = tmp_path / "free.toml"
    free.write_text(FREE_STUDY)
    assert cli("run", free, "--out", tmp_path / "out", "--quiet").returncode == 0
    with pytest.raises(ValueError, match=r"no attractors table .*only a harmonic study with a census"):
        isw.load(tmp_path / "out" / "batch", table="attractors")
    with pytest.raises(ValueError, match=r"table = 'runs': a run directory's tables are 'points', 'attractors', 'summary'"):
        isw.load(run_dir, "runs")
    # reduce's tables, once it has run: the same rows as its Parquet files.
    with pytest.raises(ValueError, match=r"no summary table .*run reduce\(run_dir\)"):
        isw.load(run_dir, "summary")
    isw.reduce(run_dir)
    for name in ("summary", "zones", "branches", "sensitivity"):
        assert_same_table(isw.load(run_dir, name).to_table(), pq.read_table(run_dir / f"{name}.parquet"))
    assert isw.load(run_dir, "summary", polars=True).select(pl.len()).collect().item() == 4

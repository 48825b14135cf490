"""Reads an impactsweep dataset with pyarrow, DuckDB and polars and checks it against the
values tests/interop.rs computed with the simulator (floats given as IEEE-754 bits).

Usage: python tests/interop.py EXPECTED.json   (prints "<client>: ok" per client; exit 1 on a
mismatch, with the reason).

       python tests/interop.py --tables TABLES.json   (DuckDB reads every Parquet table the tool
writes: points, summary, zones, jumps, tradeoff; prints "duckdb tables: ok").
"""

import json
import math
import struct
import sys


def f64(bits):
    return struct.unpack("<d", struct.pack("<Q", bits))[0]


def same(a, b):
    """Bitwise equality of two floats (NaN equals NaN)."""
    return struct.pack("<d", a) == struct.pack("<d", b)


def check_row(client, got, want):
    for key in ["point_id", "point", "case", "ideal", "noise_seed", "outcome", "solver", "impacts"]:
        if got[key] != want[key]:
            raise AssertionError(f"{client}: point_id {want['point_id']}: {key} = {got[key]!r}, want {want[key]!r}")
    for key, bits in want["bits"].items():
        w = f64(bits)
        if not same(float(got[key]), w):
            raise AssertionError(f"{client}: point_id {want['point_id']}: {key} = {got[key]!r}, want {w!r}")


UINT = {"point_id", "point", "noise_seed", "impacts", "sticks", "steps"}


def expected_arrow_type(name):
    if name in UINT:
        return "uint64"
    if name == "case":
        return "uint32"
    if name == "ideal":
        return "bool"
    if name in ("solver", "outcome"):
        return "dictionary<values=string, indices=int8, ordered=0>"
    return "double"


def check_pyarrow(exp):
    import pyarrow.dataset as ds
    import pyarrow.parquet as pq

    dataset = ds.dataset(exp["dir"] + "/points", format="parquet")
    table = dataset.to_table()
    assert table.num_rows == exp["n_rows"], (table.num_rows, exp["n_rows"])
    assert table.column_names == exp["columns"], table.column_names
    for field in table.schema:
        assert str(field.type) == expected_arrow_type(field.name), (field.name, str(field.type))
    files = sorted(dataset.files)
    assert len(files) == exp["n_files"], files
    for path in files:
        meta = pq.ParquetFile(path).metadata
        assert meta.num_row_groups == 1, (path, meta.num_row_groups)
        kv = {k.decode(): v.decode() for k, v in meta.metadata.items()}
        assert kv["impactsweep.study"] == exp["study"], kv
        assert kv["impactsweep.schema_version"] == exp["schema_version"], kv
        assert "impactsweep.version" in kv
        for i in range(meta.num_columns):
            col = meta.row_group(0).column(i)
            assert col.compression == "SNAPPY", (col.path_in_schema, col.compression)
    ids = table.column("point_id").to_pylist()
    assert ids == sorted(ids) and len(set(ids)) == len(ids)
    rows = table.to_pylist()
    by_id = {r["point_id"]: r for r in rows}
    for want in exp["rows"]:
        check_row("pyarrow", by_id[want["point_id"]], want)
    print("pyarrow: ok")


def check_duckdb(exp):
    import duckdb

    glob = exp["dir"] + "/points/*.parquet"
    con = duckdb.connect()
    (n,) = con.execute(f"SELECT count(*) FROM '{glob}'").fetchone()
    assert n == exp["n_rows"], (n, exp["n_rows"])
    desc = con.execute(f"DESCRIBE SELECT * FROM '{glob}'").fetchall()
    names = [d[0] for d in desc]
    # DuckDB matches identifiers without case: the names read back are the names written only
    # because no two are equal without case (issue 9).
    assert names == exp["columns"], names
    types = {d[0]: d[1] for d in desc}
    want_types = {"uint64": "UBIGINT", "uint32": "UINTEGER", "bool": "BOOLEAN", "double": "DOUBLE"}
    for name in names:
        t = expected_arrow_type(name)
        assert types[name] == want_types.get(t, "VARCHAR"), (name, types[name])
    cols = ", ".join(f'"{c}"' for c in names)
    for want in exp["rows"]:
        cur = con.execute(f"SELECT {cols} FROM '{glob}' WHERE point_id = ?", [want["point_id"]])
        got = dict(zip(names, cur.fetchone()))
        check_row("duckdb", got, want)
    (oks,) = con.execute(f"SELECT count(*) FROM '{glob}' WHERE outcome = 'ok'").fetchone()
    assert 0 < oks <= n
    print("duckdb: ok")


def check_polars(exp):
    import polars as pl

    df = pl.read_parquet(exp["dir"] + "/points/*.parquet")
    assert df.height == exp["n_rows"], df.height
    assert df.columns == exp["columns"], df.columns
    want_types = {"uint64": pl.UInt64, "uint32": pl.UInt32, "bool": pl.Boolean, "double": pl.Float64}
    for name, dtype in df.schema.items():
        t = expected_arrow_type(name)
        if t in want_types:
            assert dtype == want_types[t], (name, dtype)
        else:
            assert dtype in (pl.Categorical, pl.Utf8, pl.String) or isinstance(dtype, (pl.Categorical, pl.Enum)), (name, dtype)
    for want in exp["rows"]:
        got = df.filter(pl.col("point_id") == want["point_id"]).to_dicts()
        assert len(got) == 1, got
        row = got[0]
        row["outcome"] = str(row["outcome"])
        row["solver"] = str(row["solver"])
        check_row("polars", row, want)
    print("polars: ok")


def check_duckdb_tables(exp):
    """Every table: DuckDB reads each column under the name written (no two equal without case),
    and a query naming `mass_inner` returns exactly the study's inner masses."""
    import duckdb
    import pyarrow.parquet as pq

    con = duckdb.connect()
    for table, glob in exp["tables"].items():
        desc = con.execute(f"DESCRIBE SELECT * FROM '{glob}'").fetchall()
        names = [d[0] for d in desc]
        lower = [n.lower() for n in names]
        assert len(set(lower)) == len(lower), (table, names)
        first = sorted(__import__("glob").glob(glob))[0]
        written = pq.read_schema(first).names
        assert names == written, (table, names, written)
        for field in pq.read_schema(first):
            assert field.metadata is not None and b"unit" in field.metadata, (table, field.name)
        print(f"{table}: {len(names)} columns")

    def floats(sql):
        return sorted(float(r[0]) for r in con.execute(sql).fetchall())

    def bits(xs):
        return [struct.pack("<d", x) for x in xs]

    want_axis = [f64(b) for b in exp["mass_inner_axis"]]
    want_runs = sorted(f64(b) for b in exp["mass_inner_runs"])
    got = floats(f"SELECT DISTINCT mass_inner FROM '{exp['tables']['points']}'")
    assert bits(got) == bits(want_runs), (got, want_runs)
    got = floats(f"SELECT DISTINCT mass_inner FROM '{exp['tables']['summary']}'")
    assert bits(got) == bits(want_axis), (got, want_axis)
    # The ideal case of each design point runs the point's own inner mass.
    got = floats(f"SELECT DISTINCT mass_inner FROM '{exp['tables']['points']}' WHERE ideal")
    assert bits(got) == bits(want_axis), (got, want_axis)
    (lo, hi) = con.execute(
        f"SELECT min(mass_inner_from), max(mass_inner_to) FROM '{exp['tables']['zones']}'"
    ).fetchone()
    assert (lo, hi) == (want_axis[0], want_axis[-1]), (lo, hi)
    axes = {r[0] for r in con.execute(f"SELECT DISTINCT axis FROM '{exp['tables']['jumps']}'").fetchall()}
    assert axes <= {"e", "mass_inner"}, axes
    (n,) = con.execute(f"SELECT count(*) FROM '{exp['tables']['tradeoff']}' WHERE knob = 'tol'").fetchone()
    assert n > 0
    print("duckdb tables: ok")


def main():
    if sys.argv[1] == "--tables":
        with open(sys.argv[2]) as f:
            exp = json.load(f)
        try:
            check_duckdb_tables(exp)
        except Exception as e:
            print(f"check_duckdb_tables: FAILED: {type(e).__name__}: {e}", file=sys.stderr)
            sys.exit(1)
        return
    with open(sys.argv[1]) as f:
        exp = json.load(f)
    failed = False
    for check in (check_pyarrow, check_duckdb, check_polars):
        try:
            check(exp)
        except Exception as e:  # report every client, then fail
            failed = True
            print(f"{check.__name__}: FAILED: {type(e).__name__}: {e}", file=sys.stderr)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()

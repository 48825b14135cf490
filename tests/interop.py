"""Reads an impactsweep dataset with pyarrow, DuckDB and polars and checks it against the
values tests/interop.rs computed with the simulator (floats given as IEEE-754 bits).

Usage: python tests/interop.py EXPECTED.json   (prints "<client>: ok" per client; exit 1 on a
mismatch, with the reason).
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


def main():
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

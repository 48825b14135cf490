"""Bad input raises ValueError with the command line's message; Ctrl-C stops a batch and a run,
and `run(..., resume=True)` completes the run (issue 17's acceptance)."""

from __future__ import annotations

import os
import signal
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import impactsweep as isw

BAD = Path(__file__).resolve().parents[2] / "tests" / "bad_studies"


def test_every_bad_study_raises_the_command_lines_message(cli, monkeypatch):
    monkeypatch.chdir(BAD)
    files = sorted(p.name for p in BAD.glob("*.toml"))
    assert len(files) >= 40
    for name in files:
        p = cli("plan", name, cwd=BAD)
        assert p.returncode == 2, name
        assert p.stderr.startswith("error: "), name
        with pytest.raises(ValueError) as err:
            isw.plan(name)
        assert str(err.value) == p.stderr[len("error: ") :].rstrip("\n"), name


def test_a_bad_study_as_text_names_study_toml():
    with pytest.raises(ValueError, match=r"^study.toml: \[system\].e = 1.3: "):
        isw.plan('[study]\nname = "x"\n[system]\ne = 1.3\n')


def test_bad_keys_raise_the_command_lines_message(cli):
    for keys, sets in [
        ({"e": 1.3}, ["e=1.3"]),
        ({"nope": 1.0}, ["nope=1.0"]),
        ({"solver": "euler"}, ["solver=euler"]),
        ({"r": 1.0}, ["r=1.0"]),
        ({"max_impacts": 2.5}, ["max_impacts=2.5"]),
    ]:
        args = ["simulate", "--json"]
        for s in sets:
            args += ["--set", s]
        p = cli(*args)
        assert p.returncode == 2
        with pytest.raises(ValueError) as err:
            isw.simulate(**keys)
        assert str(err.value) == p.stderr[len("error: ") :].rstrip("\n")


def test_bad_batches_raise_value_error():
    with pytest.raises(ValueError, match=r"^row 2: e = 1.5: "):
        isw.simulate_batch({"e": [0.5, 0.6, 1.5]})
    with pytest.raises(ValueError, match="input column 'q': unknown key"):
        isw.simulate_batch({"q": [0.5]})
    with pytest.raises(ValueError, match="a key of the harmonic scene"):
        isw.simulate_batch({"r": [1.0]})
    with pytest.raises(ValueError, match="different lengths"):
        isw.simulate_batch({"e": [0.5, 0.6], "m": [0.01]})
    with pytest.raises(ValueError, match="threads=0"):
        isw.simulate_batch({"e": [0.5]}, threads=0)
    with pytest.raises(ValueError, match="expected a number"):
        isw.simulate(e=True)


def interrupt_after(seconds: float) -> threading.Timer:
    """Sends this process SIGINT (as Ctrl-C does) after `seconds`. Python's own Ctrl-C handler
    is installed first: a process started in the background by a non-interactive shell (nohup,
    some CI runners) inherits SIGINT ignored, and then Python never raises KeyboardInterrupt."""
    signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(seconds, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    return timer


def test_ctrl_c_stops_a_batch_within_a_second():
    n = 2_000_000  # about 5 s per core at ~5 us a run
    inputs = {"e": np.linspace(0.5, 0.95, n)}
    timer = interrupt_after(0.5)
    t0 = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        isw.simulate_batch(inputs)
    elapsed = time.perf_counter() - t0
    timer.join()
    assert elapsed < 0.5 + 1.0, elapsed
    # The package is still usable afterwards.
    assert isw.simulate_batch({"e": [0.9]}).num_rows == 1


STUDY = """
[study]
name = "long"
[sweep]
e = { start = 0.5, stop = 0.95, num = 500 }
m = { start = 0.005, stop = 0.03, num = 200 }
d = { start = 0.005, stop = 0.02, num = 10 }
[run]
chunk_points = 20000
"""


def test_ctrl_c_stops_a_run_and_resume_completes_it(tmp_path, cli):
    study = tmp_path / "long.toml"
    study.write_text(STUDY)
    timer = interrupt_after(0.5)
    t0 = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        isw.run(study, out=tmp_path)
    elapsed = time.perf_counter() - t0
    timer.join()
    assert elapsed < 0.5 + 1.5, elapsed
    st = isw.status(tmp_path / "long")
    assert not st["complete"] and st["missing"]
    done = isw.run(study, out=tmp_path, resume=True)
    assert done["chunks_left"] == 0 and done["chunks_kept"] == len(st["done"])
    assert isw.status(tmp_path / "long")["complete"]
    # The same bytes as an uninterrupted run of the command line.
    p = cli("run", study, "--out", tmp_path / "cli", "--quiet")
    assert p.returncode == 0, p.stderr
    for a, b in zip(
        sorted((tmp_path / "long/points").glob("*.parquet")),
        sorted((tmp_path / "cli/long/points").glob("*.parquet")),
        strict=True,
    ):
        assert a.read_bytes() == b.read_bytes(), a.name

"""impactsweep from Python: the exact vibro-impact simulator, batches of runs, and the sweeps.

A thin layer over the Rust library that the ``impactsweep`` command line runs (the extension
module ``impactsweep._impactsweep``): the same simulator, study files, sweep engine, Parquet
store and reducer, so a number computed here has the same bits as the command line's.

>>> import impactsweep as isw
>>> isw.simulate(e=0.9)["xmax"]                      # one run, as `impactsweep simulate --json`
>>> isw.simulate_batch({"e": es, "m": ms}, d=0.01)   # one run per row, a pyarrow Table
>>> isw.simulate(scene="random", spectrum="white", S0=0.01, duration=5, realization=3)
>>> isw.simulate_batch({"realization": range(100)}, scene="random", spectrum="white", S0=0.01)

Keys are those of ``impactsweep simulate --set KEY=VALUE``: the system ``M m K C d e x0 v0 y0
w0`` (SI units), the solver's (``solver tol h rtol atol chatter_tol max_impacts max_steps
t_max_periods``), ``peaks``/``t_end`` for free decay, and with ``scene="harmonic"`` the forcing
``F0 omega r n_trans n_trans_max n_meas trans_tol period_tol``. ``scene="random"`` and
``scene="record"`` take the keys of a random or record study's ``[scene]`` (``spectrum S0
omega_g zeta_g omega_f zeta_f dt duration envelope threshold input``; ``record scale``) with the
system and solver keys, and run one realization: the stream of ``seed`` and ``realization``
(the sweep's row), or the standard ``normals`` handed in.

Errors: bad input raises ``ValueError`` with the command line's message (the file or key, the
value, what is allowed); Ctrl-C raises ``KeyboardInterrupt`` in a long ``simulate_batch`` or
``run`` within a second, and ``run(..., resume=True)`` then completes the run. See
``docs/python.md``.
"""

from __future__ import annotations

import json
import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np
import pyarrow as pa

from . import _impactsweep as _ext

__all__ = [
    "simulate",
    "simulate_batch",
    "n_normals",
    "realization_normals",
    "trace",
    "period_maxima",
    "life_amplitude",
    "plan",
    "run",
    "reduce",
    "load",
    "status",
    "SYSTEM_KEYS",
]

__version__: str = _ext.__version__

#: The system keys (SI units): main mass, inner mass, stiffness, damping, clearance, restitution
#: and the initial state.
SYSTEM_KEYS: List[str]
SOLVER_KEYS: List[str]
HARMONIC_KEYS: List[str]
SYSTEM_KEYS, SOLVER_KEYS, HARMONIC_KEYS = (list(k) for k in _ext.keys())

#: The points table's names of the masses (``docs/schema.md``), accepted as input columns.
_COLUMN_KEYS = {"mass_main": "M", "mass_inner": "m"}

StudyLike = Union[str, "os.PathLike[str]"]


def _value(key: str, v: Any) -> str:
    """One ``KEY=VALUE`` value as the command line would read it (floats round-trip exactly)."""
    if isinstance(v, str):
        return v
    if isinstance(v, (bool, np.bool_)):
        raise ValueError(f"{key}={v!r}: expected a number")
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    try:
        return repr(float(v))
    except (TypeError, ValueError):
        raise ValueError(f"{key}={v!r}: expected a number") from None


def _sets(keys: Mapping[str, Any], scene: str) -> List[str]:
    sets = [] if scene == "free" else [f"scene={scene}"]
    sets.extend(f"{k}={_value(k, v)}" for k, v in keys.items())
    return sets


#: The scenes: free decay and the harmonic scene take ``impactsweep simulate --set`` keys; the
#: random and record scenes the keys of their study's ``[scene]``.
SCENES = ("free", "harmonic", "random", "record")
_RANDOM_SCENES = ("random", "record")
#: The keys of ``scene="random"`` and ``scene="record"`` besides the system's and the solver's
#: (docs/scenes.md, "Inputs"): the ``[scene]`` keys (the limit state's and the intensity
#: measure's among them) and a stripe ``im`` (g, the study's ``[sweep] im = [im]``); the run's
#: own ``seed``, ``realization`` and ``normals``.
_LIMIT_KEYS = ("drift_ratio", "storey_height", "yield_coefficient", "intensity", "T", "ida_tol", "ida_max", "im")
RANDOM_KEYS = ("input", "spectrum", "S0", "omega_g", "zeta_g", "omega_f", "zeta_f", "dt", "duration",
               "envelope", "threshold", *_LIMIT_KEYS)
RECORD_KEYS = ("input", "record", "scale", "duration", "threshold", *_LIMIT_KEYS)
_RUN_KEYS = ("seed", "realization", "normals")
_STRING_KEYS = ("input", "spectrum", "record", "solver", "intensity")
#: The capacity columns of a run at a stripe: searched only when the record asked for holds one.
_CAPACITY_KEYS = ("capacity", "capacity_censored", "capacity_resurrected", "capacity_runs")
_INTEGER_KEYS = ("max_impacts", "max_steps")


def _scene(scene: Any) -> str:
    if scene not in SCENES:
        raise ValueError(f"scene={scene!r}: unknown scene; allowed: {', '.join(SCENES)}")
    return scene


def _toml(key: str, v: Any) -> str:
    """One value of a random or record setup as the study file would hold it."""
    if key in _STRING_KEYS:
        if key == "record" and isinstance(v, os.PathLike):
            v = os.fspath(v)
        if not isinstance(v, str):
            raise ValueError(f"{key}={v!r}: expected a string")
        return json.dumps(v)
    if key == "envelope":
        if not isinstance(v, Mapping) or sorted(v) != ["c", "t1", "t2"]:
            raise ValueError(f"envelope={v!r}: expected a mapping {{'t1': s, 't2': s, 'c': 1/s}}")
        return "{ " + ", ".join(f"{k} = {_toml(f'envelope.{k}', v[k])}" for k in ("t1", "t2", "c")) + " }"
    if isinstance(v, (bool, np.bool_)) or isinstance(v, str):
        raise ValueError(f"{key}={v!r}: expected a number")
    if key in _INTEGER_KEYS:
        try:
            n = int(v)
        except (TypeError, ValueError, OverflowError):
            n = -1
        if n != v or n < 0:
            raise ValueError(f"{key}={v!r}: must be a whole number >= 0")
        return str(n)
    try:
        return repr(float(v))
    except (TypeError, ValueError):
        raise ValueError(f"{key}={v!r}: expected a number") from None


def _random_text(scene: str, keys: Mapping[str, Any]) -> str:
    """The study text of a random or record setup: one design point, the keys in their tables
    (the Rust side parses and checks it as a study file, so the defaults are a study's: the
    structure at rest)."""
    own = RANDOM_KEYS if scene == "random" else RECORD_KEYS
    tables: Dict[str, List[str]] = {"scene": [f'kind = "{scene}"'], "system": [], "solver": [], "sweep": []}
    for key, v in keys.items():
        if key == "im":
            tables["sweep"].append(f"im = [{_toml(key, v)}]")
            continue
        if key in own:
            table = "scene"
        elif key in SYSTEM_KEYS:
            table = "system"
        elif key in SOLVER_KEYS:
            table = "solver"
        else:
            other = [s for s in _RANDOM_SCENES if s != scene][0]
            if key in (RECORD_KEYS if scene == "random" else RANDOM_KEYS):
                why = f"a key of the {other} scene"
            else:
                why = "unknown key"
            allowed = " ".join((*own, *SYSTEM_KEYS, *SOLVER_KEYS, *_RUN_KEYS))
            raise ValueError(f"{key}={v!r}: {why} for scene={scene!r}; allowed keys: {allowed}")
        if v is None and key == "threshold":
            continue
        tables[table].append(f"{'kind' if key == 'solver' else key} = {_toml(key, v)}")
    parts = ['[study]\nname = "simulate"\n']
    parts += [f"[{t}]\n" + "".join(f"{line}\n" for line in lines) for t, lines in tables.items() if lines or t != "sweep"]
    return "".join(parts)


def _whole(key: str, v: Any) -> int:
    """A seed or a realization number: a whole number in [0, 2^64)."""
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, np.integer)) or not 0 <= int(v) < 2**64:
        raise ValueError(f"{key}={v!r}: must be a whole number in [0, 2^64)")
    return int(v)


def _normals(u: Any) -> bytes:
    arr = np.ascontiguousarray(np.asarray(u, dtype=np.float64))
    if arr.ndim != 1:
        raise ValueError(f"normals: {arr.ndim}-dimensional; expected one standard normal per entry (1-D)")
    return arr.tobytes()


def _run_keys(keys: Dict[str, Any]) -> tuple:
    """(seed, realization, normals as bytes or None) of a random or record run, taken out of
    ``keys``: the stream it names, or the normals that replace it."""
    run = {k: keys.pop(k) for k in _RUN_KEYS if k in keys}
    normals = run.get("normals")
    if normals is not None and ("seed" in run or "realization" in run):
        raise ValueError("normals: given with seed or realization; the normals replace the stream they name")
    return (_whole("seed", run.get("seed", 0)), _whole("realization", run.get("realization", 0)),
            None if normals is None else _normals(normals))


def simulate(*, scene: str = "free", outputs: Optional[Sequence[str]] = None, **keys: Any) -> Dict[str, Any]:
    """One run: the record ``impactsweep simulate --set KEY=VALUE ... --json`` prints, as a dict.

    Same keys and the same float bits as the command line (NaN observables are ``None``, as
    JSON's null). ``scene="harmonic"`` runs the forced scene. ``outputs`` keeps only those
    keys of the record.

    ``scene="random"`` (or ``"record"``) runs one realization of a random (record) study's
    design: the keys of its ``[scene]`` (``spectrum S0 omega_g zeta_g omega_f zeta_f dt
    duration envelope threshold input``; a record's ``record scale duration threshold input``,
    ``record`` a CSV path; the limit state's ``drift_ratio storey_height yield_coefficient`` and
    the intensity measure's ``intensity T ida_tol ida_max``) and a stripe ``im`` in g, with the
    system's and the solver's, the same defaults and checks as the study file (the structure
    starts at rest). The load is realization ``realization`` (default 0) of study seed ``seed``
    (default 0): the same bits as the sweep's row of that realization at that design.
    ``normals`` (a 1-D array of ``n_normals`` standard normals) replaces the stream, as subset
    simulation hands them in. With ``intensity`` and ``im`` the motion is scaled to the stripe
    (its ``pga`` or ``sa`` to ``im``) as the sweep scales it, normals handed in included. The
    record has the run's observables (``amplitude t_peak rms_x rms_acc first_passage_time
    impacts sticks energy_impact samples t_stop steps outcome``; ``first_passage_time`` is None
    when ``|x|`` never passed ``threshold``); under an intensity measure the motion's own ``pga
    sa`` (g, at scale 1), the ``scale`` it ran at and its capacity (``capacity
    capacity_censored capacity_resurrected capacity_runs``, the ``random_points`` columns; with
    a ``threshold``, searched only when ``outputs`` is None or names one of them); then ``scene
    seed realization`` (None with ``normals`` or a record), ``n_normals``, ``system``,
    ``solver`` and the scene's settings under its name.
    """
    scene = _scene(scene)
    if scene in _RANDOM_SCENES:
        run = _run_keys(keys)
        capacity = outputs is None or any(k in _CAPACITY_KEYS for k in outputs)
        rec = _ext.simulate_random(_random_text(scene, keys), *run, capacity)
    else:
        for k in _RUN_KEYS:
            if k in keys:
                raise ValueError(f"{k}: a key of the random scene; add scene=\"random\"")
        rec = _ext.simulate(_sets(keys, scene))
    if outputs is None:
        return rec
    unknown = [k for k in outputs if k not in rec]
    if unknown:
        raise ValueError(f"outputs: unknown key '{unknown[0]}'; allowed: {' '.join(rec)}")
    return {k: rec[k] for k in outputs}


def n_normals(*, scene: str = "random", **keys: Any) -> int:
    """The standard normals one run of the random setup of ``keys`` (as :func:`simulate` takes
    them) draws: the length of its ``normals``. One per load sample for white noise
    (``ceil(duration / dt) + 1``), one per interval through a filter (``ceil(duration / dt)``),
    0 for a record."""
    scene = _scene(scene)
    if scene not in _RANDOM_SCENES:
        raise ValueError(f"scene={scene!r}: only a random load draws normals; allowed: random, record")
    return _ext.random_n_normals(_random_text(scene, keys))


def realization_normals(n: int, *, seed: int = 0, realization: int = 0) -> np.ndarray:
    """The first ``n`` standard normals of the load stream of realization ``realization`` under
    study seed ``seed``: what that realization's run draws, in order (so
    ``simulate(normals=realization_normals(n_normals(**keys), seed=s, realization=c), **keys)``
    is ``simulate(seed=s, realization=c, **keys)`` bit for bit)."""
    if isinstance(n, (bool, np.bool_)) or not isinstance(n, (int, np.integer)) or n < 0:
        raise ValueError(f"n={n!r}: must be a whole number >= 0")
    raw = _ext.realization_normals(_whole("seed", seed), _whole("realization", realization), int(n))
    return np.frombuffer(raw, dtype=np.float64).copy()


def _columns(inputs: Any) -> Dict[str, np.ndarray]:
    """Input columns as contiguous float64 arrays, from a mapping, a pyarrow Table or a polars
    DataFrame."""
    if isinstance(inputs, pa.Table):
        raw = {name: inputs.column(name).to_numpy() for name in inputs.column_names}
    elif type(inputs).__module__.split(".")[0] == "polars":
        raw = {name: inputs.get_column(name).to_numpy() for name in inputs.columns}
    elif isinstance(inputs, Mapping):
        raw = dict(inputs)
    else:
        raise ValueError(
            f"inputs: a {type(inputs).__name__}; expected a mapping of column name to array, "
            "a pyarrow Table or a polars DataFrame"
        )
    cols: Dict[str, np.ndarray] = {}
    for name, values in raw.items():
        key = _COLUMN_KEYS.get(name, name)
        arr = np.ascontiguousarray(np.asarray(values, dtype=np.float64))
        if arr.ndim != 1:
            raise ValueError(f"input column '{name}': {arr.ndim}-dimensional; expected one value per row")
        if key in cols:
            raise ValueError(f"input column '{name}': given twice")
        cols[key] = arr
    return cols


def _random_sets(fixed: Mapping[str, Any], scene: str) -> List[str]:
    """The ``--set`` keys of a random or record batch: ``envelope`` as ``t1,t2,c``, ``record``
    a path, ``realization`` a whole number, the rest as :func:`_sets` writes them."""
    sets = [f"scene={scene}"]
    for key, v in fixed.items():
        if key == "seed":
            raise ValueError("seed: the study seed of a batch is simulate_batch's seed argument")
        if key == "envelope":
            if not isinstance(v, Mapping) or sorted(v) != ["c", "t1", "t2"]:
                raise ValueError(f"envelope={v!r}: expected a mapping {{'t1': s, 't2': s, 'c': 1/s}}")
            sets.append("envelope=" + ",".join(_value(f"envelope.{k}", v[k]) for k in ("t1", "t2", "c")))
        elif key == "record" and isinstance(v, os.PathLike):
            sets.append(f"record={os.fspath(v)}")
        elif key == "realization":
            sets.append(f"realization={_whole('realization', v)}")
        elif v is None and key == "threshold":
            continue
        else:
            sets.append(f"{key}={_value(key, v)}")
    return sets


def simulate_batch(
    inputs: Any,
    *,
    threads: Optional[int] = None,
    scene: str = "free",
    seed: int = 0,
    normals: Any = None,
    capacity: bool = True,
    **fixed: Any,
) -> pa.Table:
    """One run per row of ``inputs``, in parallel, as a pyarrow Table.

    ``inputs`` maps column names (system keys such as ``e m d``, ``mass_inner``/``mass_main``
    as the points table names them, and with ``scene="harmonic"`` also ``F0 omega r``) to
    arrays of one value per row; a pyarrow Table or a polars DataFrame works too. ``fixed``
    holds the keys shared by every row (as :func:`simulate` takes them).

    The result has the columns of the scene's points table (``docs/schema.md``): row ``i`` is
    run ``i`` of a one-case noise-free study with study seed ``seed`` (``point_id = point = i``),
    simulated by the sweep engine's own per-run function. The runs are spread over
    ``threads`` threads (default: every core) with the GIL released; the result does not depend
    on the thread count. Every row is validated before the first run. Ctrl-C raises
    ``KeyboardInterrupt`` within a second.

    ``scene="random"`` and ``scene="record"``: each row is one realization of a random or record
    design, the ``random_points`` table's row (``docs/schema.md``) the sweep of the one-point
    study of the row's keys stores, bit for bit. ``fixed`` takes a random or record study's
    ``[scene]`` keys (``spectrum S0 omega_g zeta_g omega_f zeta_f dt duration envelope threshold
    input``; ``record scale``; ``drift_ratio storey_height yield_coefficient``; ``intensity T
    ida_tol ida_max`` and a stripe ``im`` in g), the system's and the solver's, and
    ``realization``; the study defaults apply (firm soil's filters, 20 s, ``dt`` 0.005 s, the
    structure at rest). The input columns may be system keys, the load's sweepable keys (``S0
    omega_g zeta_g omega_f zeta_f``, ``scale``, ``im``) and ``realization``: row ``i`` runs the
    load of realization ``realization[i]`` (without the column, the fixed ``realization``, 0 by
    default: every row the same load, as a sweep compares designs) under study seed ``seed``;
    ``np.arange(n)`` as the column gives ``n`` realizations of one design. Its ``case`` is the
    realization, ``point_id = point = i``. A row with a stripe ``im`` and a ``threshold`` is
    its own design stripe: it carries the motion's capacity.

    ``normals`` (``scene="random"``): a 2-D array of one row of ``n_normals`` standard normals
    per run; row ``i`` runs on its row in place of a realization's stream (its ``case`` is 0),
    as :func:`simulate` with ``normals`` runs it, bit for bit, and on the normals of
    :func:`realization_normals` as the row of that realization. ``inputs`` may then be empty
    (``{}``): the normals give the rows. A reliability library's whole sample of standard
    normals, a stripe ``im`` among the keys, is one call on every core.

    ``capacity=False`` (random and record scenes): no row searches its motion's capacity (the
    ``capacity`` columns null, every other column the same), where a row at its stripe with a
    ``threshold`` would: a limit state that reads the amplitude then costs one run a row, not
    the search's five to ten.
    """
    scene = _scene(scene)
    cols = _columns(inputs)
    lengths = {len(a) for a in cols.values()}
    if len(lengths) > 1:
        raise ValueError(f"inputs: columns of different lengths {sorted(lengths)}")
    raw = None
    if normals is not None:
        if scene != "random":
            raise ValueError(f"normals: only a random load draws normals; scene={scene!r}")
        u = np.ascontiguousarray(np.asarray(normals, dtype=np.float64))
        if u.ndim != 2:
            raise ValueError(f"normals: {u.ndim}-dimensional; expected one row of n_normals standard normals per run (2-D)")
        if lengths and lengths != {len(u)}:
            raise ValueError(f"normals: {len(u)} rows for input columns of {lengths.pop()}")
        lengths, raw = {len(u)}, u.tobytes()
    n = lengths.pop() if lengths else 1
    if not isinstance(capacity, (bool, np.bool_)):
        raise ValueError(f"capacity={capacity!r}: expected True or False")
    if scene in _RANDOM_SCENES:
        sets, seed = _random_sets(fixed, scene), _whole("seed", seed)
    elif not capacity:
        raise ValueError(f"capacity=False: a random or record scene's option (a capacity by incremental dynamic analysis); scene={scene!r}")
    else:
        sets, seed = _sets(fixed, scene), int(seed)
    batch = _ext.simulate_batch(
        sets, list(cols), [a.tobytes() for a in cols.values()], n, threads, seed, raw, bool(capacity)
    )
    return pa.Table.from_batches([batch])


def trace(*, dt: float = 1e-4, t_end: Optional[float] = None, scene: str = "free", **keys: Any) -> Dict[str, Any]:
    """One run with its waveform: the state every ``dt`` seconds and at every impact.

    Returns NumPy arrays ``t`` (s), ``x v`` (main mass, m and m/s), ``y w`` (inner mass),
    ``impacts`` (the impact times, s), and ``record`` (the dict of :func:`simulate`). The rows
    are those of ``impactsweep simulate --trace FILE --dt DT``.

    ``scene="random"`` (or ``"record"``): the realization :func:`simulate` runs for the same keys
    (``seed``, ``realization`` or ``normals``; at a stripe ``im``, scaled to it), displacements
    relative to the ground under a ground motion; ``record`` is :func:`simulate`'s record without
    the capacity search (its columns None), and ``load`` the load's samples at the scale the
    motion ran at (m/s^2 or N; ``load[k]`` at ``k * load_dt``, ``load_dt`` the scene's ``dt``),
    so the motion behind a failure can be looked at. ``t_end`` is free decay's.
    """
    scene = _scene(scene)
    if scene in _RANDOM_SCENES:
        if t_end is not None:
            raise ValueError(f"t_end={t_end!r}: a free-decay option; a random or record run lasts its duration")
        run = _run_keys(keys)
        rec, samples, impacts, load = _ext.trace_random(_random_text(scene, keys), *run, float(dt))
    else:
        rec, samples, impacts = _ext.trace(_sets(keys, scene), float(dt), None if t_end is None else float(t_end))
        load = None
    rows = np.frombuffer(samples, dtype=np.float64).reshape(-1, 5)
    out: Dict[str, Any] = {name: rows[:, j].copy() for j, name in enumerate(("t", "x", "v", "y", "w"))}
    out["impacts"] = np.frombuffer(impacts, dtype=np.float64).copy()
    out["record"] = rec
    if load is not None:
        out["load"] = np.frombuffer(load, dtype=np.float64).copy()
        out["load_dt"] = rec[scene]["dt"]
    return out


def period_maxima(periods: int, *, burn: int = 2000, **keys: Any) -> np.ndarray:
    """The largest ``|x|`` (m) in each of ``periods`` forcing periods of the harmonic scene's
    motion from the initial state, after ``burn`` periods of transient: the per-period maxima a
    design-life estimate starts from (docs/scenes.md, "The amplitude over a design life").
    Keys as :func:`simulate` with ``scene="harmonic"`` (implied).
    """
    raw = _ext.period_maxima(_sets(keys, "harmonic"), int(periods), int(burn))
    return np.frombuffer(raw, dtype=np.float64).copy()


def life_amplitude(
    maxima: Any,
    design_periods: float,
    *,
    quantile: float = 0.5,
    run: int = 3,
    xi_min: float = -0.5,
    xi_max: float = 0.0,
) -> Optional[Dict[str, float]]:
    """The ``quantile`` of the largest value over ``design_periods`` periods, from per-period
    maxima, by the tool's own estimator (peaks over three thresholds that keep the highest
    cluster maxima, declustered by runs of ``run`` periods below them, a generalized Pareto tail
    of shape in ``[xi_min, xi_max]``; docs/model.md §11). Returns ``amplitude lo hi`` (the
    median of the three fits and the union of their 90 % profile-likelihood intervals; each
    fit's value is the posterior median of the quantile under Jeffreys's prior when the shapes
    lie within ``[-0.5, 0]``, the fitted law's quantile otherwise),
    ``threshold sigma xi xi_se end_point exceedances measured`` (of the middle fit); ``None``
    when the sample leaves too few clusters. ``[-0.5, 0]`` is the tool's bounded tail; down to
    -0.95 and up to 0.95 lets the shape free, as a general-purpose fit does.
    """
    z = np.ascontiguousarray(np.asarray(maxima, dtype=np.float64))
    if z.ndim != 1:
        raise ValueError(f"maxima: {z.ndim}-dimensional; expected one value per period")
    return _ext.life_estimate(
        z.tobytes(), float(design_periods), float(quantile), int(run), float(xi_min), float(xi_max)
    )


def _study(study: StudyLike) -> tuple:
    """(path, text): a study file, or TOML text (any string with a line break)."""
    if isinstance(study, str) and "\n" in study:
        return "study.toml", study
    return os.fspath(study), None


def plan(study: StudyLike, *, out: StudyLike = "out", allow_large: bool = False) -> Dict[str, Any]:
    """``impactsweep plan``: validates a study (a file, or TOML text) and sizes it.

    Returns ``name scene n_points n_cases n_runs n_chunks axes run_dir`` and ``text``, what
    the command prints (with its time and disk estimates). A bad study raises ``ValueError``
    with the command line's message.
    """
    path, text = _study(study)
    return _ext.plan(path, text, os.fspath(out), allow_large)


def run(
    study: StudyLike,
    *,
    out: StudyLike = "out",
    resume: bool = False,
    reduce: bool = False,
    threads: Optional[int] = None,
    chunk_points: Optional[int] = None,
    allow_large: bool = False,
) -> Dict[str, Any]:
    """``impactsweep run``: sweeps a study (a file, or TOML text) into ``out/<name>/``.

    The same engine, files and bits as the command line. ``resume=True`` continues a run
    directory (one stopped by Ctrl-C, which raises ``KeyboardInterrupt`` after the chunks in
    hand are written); ``reduce=True`` reduces it once complete. Returns what was done
    (``run_dir runs chunks_written chunks_kept chunks_left outcomes seconds line``, and
    ``reduce``, the reducer's line).
    """
    path, text = _study(study)
    return _ext.run(path, text, os.fspath(out), resume, reduce, threads, chunk_points, allow_large)


def reduce(run_dir: StudyLike, *, subset: int = 1000, subset_repeats: int = 1) -> str:
    """``impactsweep reduce``: writes the summary, zones, report and charts into ``run_dir``;
    returns the reducer's one-line summary. ``subset=N`` is ``--subset N``: a random study's
    designs with fewer than 10 exceedances get ``p_f`` by subset simulation, ``N`` samples a
    level (a multiple of 10 in [100, 10^6]; 1000 by default), which ranks them; ``subset=0``
    keeps Monte Carlo alone. ``subset_repeats=R`` is ``--subset-repeats R``: each such design's
    ``p_f`` is the mean of ``R`` independent subset simulations (1 to 1000; 1 by default), its
    interval from their spread."""
    if isinstance(subset, (bool, np.bool_)) or not isinstance(subset, (int, np.integer)) or subset < 0:
        raise ValueError(
            f"subset={subset!r}: expected 0 (Monte Carlo only) or a whole number of samples per level, "
            "a multiple of 10 in [100, 1000000]"
        )
    if (
        isinstance(subset_repeats, (bool, np.bool_))
        or not isinstance(subset_repeats, (int, np.integer))
        or not 1 <= subset_repeats <= 1000
    ):
        raise ValueError(
            f"subset_repeats={subset_repeats!r}: expected a whole number of independent subset "
            "simulations per design in [1, 1000]"
        )
    return _ext.reduce(os.fspath(run_dir), int(subset), int(subset_repeats))


def status(run_dir: StudyLike) -> Dict[str, Any]:
    """``impactsweep status`` of a run directory: ``complete n_chunks n_runs runs_done done
    missing damaged``, ``math`` (the fingerprint of the math library that wrote the records,
    ``None`` in directories written before it) and ``math_here`` (this process's: a run or
    resume into the directory is refused when they differ), and ``text`` (what the command
    prints)."""
    return _ext.status(os.fspath(run_dir))


#: The tables ``load`` reads from a run directory: the sweep's, one part file per chunk in a
#: folder of that name, and ``reduce``'s, one ``NAME.parquet`` each (docs/schema.md).
SWEEP_TABLES = ("points", "attractors")
REDUCE_TABLES = ("summary", "zones", "jumps", "sensitivity", "branches", "bifurcations")


def load(run_dir: StudyLike, table: str = "points", *, polars: bool = False) -> Any:
    """A table of a run directory: a ``pyarrow.dataset.Dataset``, or with ``polars=True`` a
    polars ``LazyFrame``. ``table`` is a table of the sweep, ``"points"`` (one row per run) or
    ``"attractors"`` (a harmonic study with a census: one row per run and steady state, every
    case's), or one that ``reduce`` writes: ``"summary"``, ``"zones"``, ``"jumps"``,
    ``"sensitivity"``, ``"branches"``, ``"bifurcations"`` (docs/schema.md). Raises
    ``ValueError`` naming the table and the directory when it has no such table."""
    if table not in SWEEP_TABLES + REDUCE_TABLES:
        names = ", ".join(repr(t) for t in SWEEP_TABLES + REDUCE_TABLES)
        raise ValueError(f"table = {table!r}: a run directory's tables are {names}")
    run = os.fspath(run_dir)
    if table in SWEEP_TABLES:
        folder = os.path.join(run, table)
        where = f"{folder}/part-*.parquet"
        files = sorted(
            os.path.join(folder, f)
            for f in (os.listdir(folder) if os.path.isdir(folder) else [])
            if f.startswith("part-") and f.endswith(".parquet")
        )
    else:
        where = os.path.join(run, f"{table}.parquet")
        files = [where] if os.path.isfile(where) else []
    if not files:
        if table == "attractors":
            why = 'only a harmonic study with a census ([scene] kind = "harmonic", starts >= 1) writes one'
        elif table == "points":
            why = "is it a run directory (OUT/<study name>) whose run has written a chunk?"
        elif table in ("branches", "bifurcations"):
            why = "`reduce` writes it for a harmonic study (bifurcations: with a design axis); run reduce(run_dir)"
        else:
            why = "`reduce` writes it; run reduce(run_dir)"
        raise ValueError(f"{run}: no {table} table ({where}): {why}")
    if polars:
        import polars as pl

        return pl.scan_parquet(files)
    import pyarrow.dataset as ds

    return ds.dataset(files, format="parquet")

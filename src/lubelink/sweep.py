"""Parameter studies on Dask: sweeps that resume and never lose a point.

A sweep file (TOML) names a base configuration and the parameters to vary
(lists, linear or log ranges, explicit points); every point of the full
factorial grid is one simulation, run in Dask tasks (one point each, or a few
when points are short). The summary quantities of each point are written to
one labelled store over the swept dimensions as soon as its task finishes, so
a crash loses nothing already stored and running the same sweep again resumes
it. docs/sweeps.md is the reference.

==========================  =================================================
piece                       job
==========================  =================================================
:func:`read_sweep`          sweep file -> :class:`Sweep` (validated, hashed)
:meth:`Sweep.point_configs` every point -> validated ``Config`` (or problems)
:func:`summarise`           one results Dataset -> summary quantities
:func:`run_sweep`           run the missing points on Dask, store, return all
:func:`load_sweep`          the stored results as an ``xarray.Dataset``
:func:`point_config`        the ``Config`` of one stored point (to run it again)
:func:`plot_sweep`          response map (heat map, curves, facets)
==========================  =================================================

Store layout (Zarr directory, the default): one array per quantity over the
swept dimensions, a boolean ``done`` mask, the swept parameters as
coordinates, and the sweep definition and its hash in the attributes. The
client appends every finished point to ``journal.jsonl`` inside the store
(one line, a few microseconds) and folds the journal into the arrays every few
seconds and at the end; a point is stored once its journal line is written.
A NetCDF result (``.nc``) is exported atomically at the end of each run from a
Zarr side store ``<name>.nc.partial.zarr``, which is removed once every point
is stored.

Heavy libraries (Dask, Zarr, xarray, Matplotlib) are imported inside the
functions that need them.
"""

from __future__ import annotations

import contextlib
import difflib
import hashlib
import json
import logging
import math
import os
import re
import shutil
import sys
import time
import tomllib
import uuid
from dataclasses import dataclass, fields, replace
from functools import cached_property
from pathlib import Path

import numpy as np

from .config import SCENARIOS, ConfigError

__all__ = [
    "Axis",
    "Sweep",
    "SweepError",
    "QUANTITIES",
    "SERIES",
    "LOCAL_CLUSTER_CONFIG",
    "read_sweep",
    "summarise",
    "run_sweep",
    "sweep",
    "load_sweep",
    "point_config",
    "plot_sweep",
    "register_cli",
]

log = logging.getLogger(__name__)

#: Version of the store layout; :func:`load_sweep` and resuming refuse other major versions.
SWEEP_FORMAT = "1.0"

#: Summary quantities per point: name -> (units, long name, kind). ``kind`` is
#: ``"f"`` (float, NaN when absent), ``"i"`` (integer, -1 when absent) or
#: ``"impacts"`` (floats along an extra ``impact`` dimension).
QUANTITIES = {
    "peak_u2_mid": ("m", "peak absolute midpoint deflection, max |u2_mid|", "f"),
    "impact_count": ("1", "number of impacts", "i"),
    "first_impact_time": ("s", "time of the first impact (NaN: no impact)", "f"),
    "peak_pressure": ("Pa", "peak absolute gauge film pressure, max |P - p_am| (NaN: no film)", "f"),
    "min_film": ("m", "thinnest film on the pad (NaN: gap not monitored)", "f"),
    "peak_film_force": ("N", "peak absolute film force on the link (NaN: no film)", "f"),
    "end_time": ("s", "simulated time reached (solver.t_end unless the run ended early)", "f"),
    "nfev": ("1", "right-hand-side evaluations", "i"),
    "impact_times": ("s", "times of the first store.max_impacts impacts (NaN: fewer impacts)", "impacts"),
}
#: Stored when ``[store] quantities`` is not given.
DEFAULT_QUANTITIES = tuple(q for q in QUANTITIES if q != "impact_times")
#: Always stored for every point, whatever ``quantities`` says.
ALWAYS = {
    "status": ("1", "outcome: complete, film_breakdown, chatter, solver_failure, timeout, "
                    "error, worker_died or invalid"),
    "message": ("1", "why the point ended (the error for a failed point)"),
    "wall_time": ("s", "wall-clock time of the simulation on its worker"),
}
#: Time series that ``[store] time_series`` may keep: name -> extra dimension
#: (after ``time``) and the parameters that fix that dimension's coordinate.
SERIES = {
    "u2_mid": (None, ()),
    "x_star": (None, ()),
    "V_r": (None, ()),
    "film_min": (None, ()),
    "film_force": (None, ()),
    "q": ("mode", ("beam.modes",)),
    "q_dot": ("mode", ("beam.modes",)),
    "u2": ("x", ("mechanism.rod_length", "output.x_points")),
    "pressure": ("X", ("film.pad_length", "output.pad_points")),
}
_TIME_KEYS = ("solver.t_end", "solver.output_step")

_TOP_KEYS = ("base", "description", "invalid_points", "set", "vary", "points", "store")
_STORE_KEYS = ("quantities", "time_series", "max_impacts")
_RANGE_KEYS = ("start", "stop", "num", "scale")
#: Largest sweep accepted (each point is validated and held in memory by the client).
MAX_POINTS = 10_000_000
JOURNAL = "journal.jsonl"
LOCK = "lock"
#: Seconds between folds of the journal into the Zarr arrays.
COMPACT_INTERVAL = 10.0
#: Dask settings of the local cluster that :func:`run_sweep` starts: Dask's diagnostics sampling
#: (event-loop tick every 20 ms, system monitor, worker profiler) costs about a tenth of a core per
#: process on a small machine, taken from the simulations; a sweep does without it.
LOCAL_CLUSTER_CONFIG = {
    "distributed.admin.tick.interval": "500ms",
    "distributed.admin.system-monitor.interval": "2s",
    "distributed.worker.profile.enabled": False,
}


class SweepError(RuntimeError):
    """A sweep that cannot start or go on: store of another sweep, store in use, no scheduler."""


# ====================================================================== parameters
def _parameters():
    """``{"section.key": (field type, units, long name)}`` from the parameter dataclasses.

    Units and descriptions come from the numpydoc ``Attributes`` of
    :mod:`lubelink.params`, the single source of truth.
    """
    from .params import SECTION_TYPES

    out = {}
    for section, cls in SECTION_TYPES.items():
        docs = {}
        for m in re.finditer(r"^ {4}([\w, ]+) : [\w ]+\n((?: {8}.*\n?)+)", cls.__doc__ or "", re.M):
            text = " ".join(line.strip() for line in m.group(2).splitlines())
            unit = re.search(r"\[([^\]]+)\]", text)
            units = unit.group(1) if unit else ""
            units = "1" if units == "-" else units
            long_name = text.split(" [")[0].split(" (")[0].rstrip(".")
            for name in m.group(1).split(","):
                docs[name.strip()] = (units, long_name)
        for f in fields(cls):
            units, long_name = docs.get(f.name, ("", f.name))
            ftype = f.type if isinstance(f.type, str) else getattr(f.type, "__name__", str(f.type))
            out[f"{section}.{f.name}"] = (ftype, units, long_name)
    return out


def _suggest(name, options):
    close = difflib.get_close_matches(str(name), list(options), n=1)
    return f" (did you mean '{close[0]}'?)" if close else ""


def _fmt(v):
    if isinstance(v, float):
        return f"{v:.6g}"
    return repr(v) if isinstance(v, str) else str(v)


def _scalar(name, ftype, value, where, problems):
    """``value`` as the Python type of parameter ``name``, or None with a problem recorded."""
    ok = True
    if ftype == "float":
        ok = isinstance(value, (int, float)) and not isinstance(value, bool)
        value = float(value) if ok else value
        kind = "a number"
    elif ftype == "int":
        if isinstance(value, float) and value.is_integer():
            value = int(value)
        ok = isinstance(value, int) and not isinstance(value, bool)
        kind = "an integer"
    elif ftype == "str":
        ok = isinstance(value, str)
        kind = "a string"
    elif ftype == "bool":
        ok = isinstance(value, bool)
        kind = "true or false"
    else:
        problems.append(f"{where}: {name} ({ftype}) cannot be swept")
        return None
    if not ok:
        problems.append(f"{where} = {_fmt(value)}: must be {kind} ({name} is {ftype})")
        return None
    return value


def _flatten(table, where, params, problems):
    """``{"section.key": value}`` from a table with quoted dotted keys or section sub-tables."""
    out = {}
    if not isinstance(table, dict):
        problems.append(f"{where}: must be a table of section.key = value, got {_fmt(table)}")
        return out
    sections = {name.split(".")[0] for name in params}
    for key, value in table.items():
        if "." not in key and key in sections and isinstance(value, dict) \
                and not set(value) & set(_RANGE_KEYS):
            items = [(f"{key}.{k}", v) for k, v in value.items()]
        else:
            items = [(key, value)]
        for name, v in items:
            if name not in params:
                problems.append(f"{where}.\"{name}\": unknown parameter, must be section.key"
                                + _suggest(name, params))
                continue
            out[name] = v
    return out


# ====================================================================== sweep definition
@dataclass(frozen=True)
class Axis:
    """One swept parameter: a dimension of the results.

    Attributes
    ----------
    name : str
        ``"section.key"``; also the name of the dimension and its coordinate.
    values : tuple
        The values in order, in the parameter's type.
    scale : str
        ``"list"``, ``"linear"`` or ``"log"`` (how the values were given).
    """

    name: str
    values: tuple
    scale: str = "list"


@dataclass(frozen=True)
class Sweep:
    """A parsed, validated sweep definition (see :func:`read_sweep`).

    The results have one dimension per :class:`Axis` (in file order) and, when
    explicit points are given, a last dimension ``point``. ``hash`` identifies
    everything that decides the stored values and their layout.
    """

    base: str
    base_config: object
    fixed: dict
    axes: tuple
    point_names: tuple
    point_rows: tuple
    quantities: tuple
    time_series: tuple
    max_impacts: int
    invalid_points: str
    origin: str

    # ------------------------------------------------------------ shape
    @property
    def dims(self) -> tuple:
        return tuple(a.name for a in self.axes) + (("point",) if self.point_rows else ())

    @property
    def shape(self) -> tuple:
        return tuple(len(a.values) for a in self.axes) + ((len(self.point_rows),) if self.point_rows else ())

    @property
    def size(self) -> int:
        return int(np.prod(self.shape))

    def overrides(self, flat: int) -> dict:
        """``{"section.key": value}`` of point ``flat`` (C order over :attr:`shape`)."""
        index = np.unravel_index(flat, self.shape)
        out = {a.name: a.values[i] for a, i in zip(self.axes, index)}
        if self.point_rows:
            out.update(zip(self.point_names, self.point_rows[index[-1]]))
        return out

    def label(self, flat: int) -> str:
        return ", ".join(f"{k}={_fmt(v)}" for k, v in self.overrides(flat).items())

    # ------------------------------------------------------------ identity
    def definition(self) -> dict:
        """The sweep as a TOML-ready dict, with the base configuration resolved in full."""
        from .config import to_dict

        store = {"quantities": list(self.quantities), "time_series": list(self.time_series)}
        if "impact_times" in self.quantities:
            store["max_impacts"] = self.max_impacts
        data = {"base": self.base, "vary": {a.name: list(a.values) for a in self.axes}, "store": store}
        if self.fixed:
            data["set"] = {k: list(v) if isinstance(v, tuple) else v for k, v in self.fixed.items()}
        if self.point_rows:
            data["points"] = [dict(zip(self.point_names, row)) for row in self.point_rows]
        data["base_config"] = to_dict(self.base_config)
        return data

    @cached_property
    def hash(self) -> str:
        """SHA-256 of the resolved base configuration, the grid and the stored quantities."""
        data = self.definition()
        data.pop("base")  # the resolved configuration counts, not how it was named
        data.pop("set", None)  # already folded into base_config
        data["format"] = SWEEP_FORMAT.split(".")[0]
        text = json.dumps(data, sort_keys=True, default=list)
        return hashlib.sha256(text.encode()).hexdigest()

    def to_toml(self) -> str:
        import tomli_w

        data = self.definition()
        data.pop("base_config")
        return tomli_w.dumps(data)

    # ------------------------------------------------------------ points
    def point_configs(self, progress=None):
        """Validate every point: ``(configs, invalid)`` keyed by flat index.

        ``configs[flat]`` is the validated :class:`~lubelink.params.Config`;
        ``invalid[flat]`` the list of problems of a point that fails
        :func:`lubelink.config.validate`. ``progress`` is called with the count
        of points checked.
        """
        from .config import validate

        configs, invalid = {}, {}
        for flat in range(self.size):
            over = self.overrides(flat)
            by_section = {}
            for name, value in over.items():
                section, key = name.split(".", 1)
                by_section.setdefault(section, {})[key] = value
            cfg = replace(self.base_config, **{s: replace(getattr(self.base_config, s), **kv)
                                               for s, kv in by_section.items()})
            try:
                configs[flat] = validate(cfg)
            except ConfigError as exc:
                invalid[flat] = exc.problems
            if progress is not None:
                progress(flat + 1)
        return configs, invalid

    def invalid_report(self, invalid: dict) -> list:
        """One line per distinct problem, naming the first point it occurs at and how many more."""
        groups = {}
        for flat, problems in invalid.items():
            for p in problems:
                groups.setdefault(p, []).append(flat)
        lines = []
        for problem, flats in list(groups.items())[:20]:
            more = f" and {len(flats) - 1} more point(s)" if len(flats) > 1 else ""
            lines.append(f"{self.origin}: invalid point ({self.label(flats[0])}{more}): {problem}")
        if len(groups) > 20:
            lines.append(f"{self.origin}: ... and {len(groups) - 20} more distinct problems")
        lines.append(f"{self.origin}: {len(invalid)} of {self.size} points are invalid; fix the "
                     "ranges, or set invalid_points = \"record\" to store them as failed points")
        return lines


def read_sweep(source) -> Sweep:
    """Parse and validate a sweep definition.

    Parameters
    ----------
    source : str, os.PathLike, dict or Sweep
        Path of a sweep TOML file, or its parsed content (``base`` paths are
        then relative to the current folder).

    Raises
    ------
    lubelink.ConfigError
        Listing every problem, one line each, naming the key.
    """
    if isinstance(source, Sweep):
        return source
    if isinstance(source, dict):
        return _parse(dict(source), origin="sweep", root=Path.cwd())
    path = Path(source)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise ConfigError([f"{path}: cannot read the sweep file ({exc.strerror or exc})"]) from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError([f"{path}: not valid TOML ({exc})"]) from None
    return _parse(data, origin=str(path), root=path.parent)


def _parse(data, origin, root) -> Sweep:
    from .config import resolve

    params = _parameters()
    problems = []
    for key in data:
        if key not in _TOP_KEYS:
            problems.append(f"{origin}: unknown key '{key}'{_suggest(key, _TOP_KEYS)}; a sweep file has "
                            + ", ".join(_TOP_KEYS))

    # ---- base and fixed overrides
    base = data.get("base", "paper")
    base_source = None
    if not isinstance(base, str):
        problems.append(f"{origin}: base = {_fmt(base)}: must be a scenario name or a configuration file")
    elif base in SCENARIOS:
        base_source = base
    elif (root / base).is_file():
        base_source = root / base
    else:
        problems.append(f"{origin}: base = {base!r}: not a scenario (" + ", ".join(SCENARIOS)
                        + f") nor a configuration file (looked for {root / base})" + _suggest(base, SCENARIOS))
    fixed = {}
    for name, value in _flatten(data.get("set", {}), "set", params, problems).items():
        ftype = params[name][0]
        if ftype == "tuple" and isinstance(value, list):
            fixed[name] = tuple(value)
        else:
            v = _scalar(name, ftype, value, f"set.\"{name}\"", problems)
            if v is not None:
                fixed[name] = v

    # ---- axes
    axes = []
    for name, spec in _flatten(data.get("vary", {}), "vary", params, problems).items():
        where = f"vary.\"{name}\""
        if name in fixed:
            problems.append(f"{where}: also given in [set]; a parameter is either fixed or varied")
            continue
        axis = _axis(name, spec, params[name][0], where, problems)
        if axis is not None:
            axes.append(axis)

    # ---- explicit points
    point_names, point_rows = (), ()
    if "points" in data:
        point_names, point_rows = _points(data["points"], params, fixed, {a.name for a in axes}, problems)
    if not axes and not point_rows and not problems:
        problems.append(f"{origin}: nothing to sweep: give [vary] parameters or [[points]]")
    size = math.prod(len(a.values) for a in axes) * max(1, len(point_rows))
    if size > MAX_POINTS:
        problems.append(f"{origin}: {size:.3g} points: more than {MAX_POINTS:.0e}; split the sweep")

    # ---- store
    store = data.get("store", {})
    quantities, series, max_impacts = DEFAULT_QUANTITIES, (), 10
    if not isinstance(store, dict):
        problems.append(f"{origin}: [store] must be a table, got {_fmt(store)}")
        store = {}
    for key in store:
        if key not in _STORE_KEYS:
            problems.append(f"store.{key}: unknown key{_suggest(key, _STORE_KEYS)}; [store] has "
                            + ", ".join(_STORE_KEYS))
    if "quantities" in store:
        quantities = _names(store["quantities"], "store.quantities", QUANTITIES, problems)
    if "time_series" in store:
        series = _names(store["time_series"], "store.time_series", SERIES, problems)
    if "max_impacts" in store:
        m = store["max_impacts"]
        if isinstance(m, bool) or not isinstance(m, int) or not 1 <= m <= 10_000:
            problems.append(f"store.max_impacts = {_fmt(m)}: must be an integer in [1, 10000]")
        else:
            max_impacts = m
    swept = {a.name for a in axes} | set(point_names)
    if series:
        for key in _TIME_KEYS:
            if key in swept:
                problems.append(f"store.time_series: {key} is swept, so the points have no common time "
                                "axis; store summary quantities only, or fix it")
        for name in series:
            for key in SERIES[name][1]:
                if key in swept:
                    problems.append(f"store.time_series: {name} needs {key} fixed (it sets the "
                                    f"'{SERIES[name][0]}' coordinate), but {key} is swept")

    policy = data.get("invalid_points", "error")
    if policy not in ("error", "record"):
        problems.append(f"{origin}: invalid_points = {_fmt(policy)}: must be \"error\" (refuse to start, "
                        "listing them) or \"record\" (store them with status 'invalid')")

    base_config = None
    if base_source is not None:
        try:
            base_config = resolve(base_source, fixed)
        except ConfigError as exc:
            problems.extend(f"{origin}: base {base!r} with [set]: {p}" for p in exc.problems)
    if problems:
        raise ConfigError([p if p.startswith(f"{origin}: ") else f"{origin}: {p}" for p in problems])
    return Sweep(base=base, base_config=base_config, fixed=fixed, axes=tuple(axes),
                 point_names=point_names, point_rows=point_rows, quantities=tuple(quantities),
                 time_series=tuple(series), max_impacts=max_impacts, invalid_points=policy,
                 origin=origin)


def _axis(name, spec, ftype, where, problems):
    if isinstance(spec, dict):
        for key in spec:
            if key not in _RANGE_KEYS:
                problems.append(f"{where}.{key}: unknown key{_suggest(key, _RANGE_KEYS)}; a range has "
                                "start, stop, num and optionally scale = \"linear\" | \"log\"")
        missing = [k for k in ("start", "stop", "num") if k not in spec]
        if missing:
            problems.append(f"{where}: a range needs " + ", ".join(missing))
            return None
        start, stop, num = spec["start"], spec["stop"], spec["num"]
        scale = spec.get("scale", "linear")
        bad = len(problems)
        for key, v in (("start", start), ("stop", stop)):
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                problems.append(f"{where}.{key} = {_fmt(v)}: must be a finite number")
        if isinstance(num, bool) or not isinstance(num, int) or not 1 <= num <= 1_000_000:
            problems.append(f"{where}.num = {_fmt(num)}: must be an integer in [1, 1000000]")
        if scale not in ("linear", "log"):
            problems.append(f"{where}.scale = {_fmt(scale)}: must be \"linear\" or \"log\"")
        if len(problems) > bad:
            return None
        if scale == "log" and not (start > 0 and stop > 0):
            problems.append(f"{where}: scale = \"log\" needs start > 0 and stop > 0 "
                            f"(got {_fmt(start)}, {_fmt(stop)})")
            return None
        if ftype not in ("float", "int"):
            problems.append(f"{where}: a range needs a numeric parameter ({name} is {ftype}); give a list")
            return None
        values = (np.geomspace if scale == "log" else np.linspace)(float(start), float(stop), num)
        values = [float(v) for v in values]
        if num >= 2:  # exact end points, whatever the rounding inside linspace/geomspace
            values[0], values[-1] = float(start), float(stop)
        if ftype == "int":
            if not all(v.is_integer() for v in values):
                problems.append(f"{where}: {name} is an integer but the range gives "
                                + ", ".join(_fmt(v) for v in values[:4]) + "...; give a list")
                return None
        elif len(set(values)) != len(values):
            problems.append(f"{where}: the range repeats values; use a larger span or fewer points")
            return None
    elif isinstance(spec, list):
        if not spec:
            problems.append(f"{where}: an empty list; give at least one value")
            return None
        values, scale = spec, "list"
    else:
        problems.append(f"{where} = {_fmt(spec)}: must be a list of values or a range "
                        "{ start = ..., stop = ..., num = ..., scale = \"linear\" | \"log\" }")
        return None
    out = []
    for i, v in enumerate(values):
        v = _scalar(name, ftype, v, f"{where}[{i}]", problems)
        if v is None:
            return None
        out.append(v)
    if len(set(out)) != len(out):
        dup = next(v for v in out if out.count(v) > 1)
        problems.append(f"{where}: value {_fmt(dup)} appears twice; each value of a dimension must be unique")
        return None
    return Axis(name, tuple(out), scale)


def _points(spec, params, fixed, varied, problems):
    """Explicit points as ``(names, rows)`` from an array of tables or a table of columns."""
    if isinstance(spec, dict):  # columns: [points] "a.b" = [...], "c.d" = [...]
        cols = _flatten(spec, "points", params, problems)
        lengths = {k: len(v) if isinstance(v, list) else -1 for k, v in cols.items()}
        if any(n < 0 for n in lengths.values()):
            problems.append("points: as a table, every entry must be a list of values (one per point)")
            return (), ()
        if len(set(lengths.values())) > 1:
            problems.append("points: the columns have different lengths: "
                            + ", ".join(f"{k} {n}" for k, n in lengths.items()))
            return (), ()
        n = next(iter(lengths.values()), 0)
        rows = [{k: v[i] for k, v in cols.items()} for i in range(n)]
    elif isinstance(spec, list) and all(isinstance(r, dict) for r in spec):
        rows = [_flatten(r, f"points[{i}]", params, problems) for i, r in enumerate(spec)]
    else:
        problems.append("points: must be an array of tables ([[points]]) or a table of equal-length lists")
        return (), ()
    if not rows:
        problems.append("points: no points given")
        return (), ()
    names = tuple(rows[0])
    out = []
    for i, row in enumerate(rows):
        if set(row) != set(names):
            problems.append(f"points[{i}]: sets {', '.join(sorted(row))}, but points[0] sets "
                            f"{', '.join(names)}; every point must set the same parameters")
            continue
        values = []
        for name in names:
            v = _scalar(name, params[name][0], row[name], f"points[{i}].\"{name}\"", problems)
            values.append(v)
        out.append(tuple(values))
    for name in names:
        if name in fixed or name in varied:
            problems.append(f"points: {name} is also in [{'set' if name in fixed else 'vary'}]; "
                            "a parameter is fixed, varied or given per point, not twice")
    return names, tuple(out)


def _names(value, where, known, problems):
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        problems.append(f"{where} = {_fmt(value)}: must be a list of names from " + ", ".join(known))
        return ()
    out = []
    for v in value:
        if v not in known:
            problems.append(f"{where}: unknown name {v!r}{_suggest(v, known)}; choose from " + ", ".join(known))
        elif v not in out:
            out.append(v)
    return tuple(out)


# ====================================================================== one point
def summarise(ds, quantities=DEFAULT_QUANTITIES, max_impacts=10) -> dict:
    """Summary quantities of one results Dataset (:func:`lubelink.simulate`).

    Returns ``{name: value}`` with ``status``, ``message`` and ``wall_time``
    [s] and each of ``quantities`` (see :data:`QUANTITIES` for units):
    floats (NaN when the quantity does not exist for this run, e.g. the film
    pressure of a dry joint), integers, and for ``impact_times`` a list of
    ``max_impacts`` floats.
    """

    def peak(name):
        if name not in ds or ds[name].size == 0:
            return math.nan
        return float(np.nanmax(np.abs(ds[name].values)))

    times = ds.impact_time.values if "impact_time" in ds else np.array([])
    compute = {
        "peak_u2_mid": lambda: peak("u2_mid"),
        "impact_count": lambda: int(ds.attrs.get("impact_count", len(times))),
        "first_impact_time": lambda: float(times[0]) if len(times) else math.nan,
        "peak_pressure": lambda: peak("pressure"),
        "min_film": lambda: (float(np.nanmin(ds.film_min.values))
                             if "film_min" in ds and ds.film_min.size else math.nan),
        "peak_film_force": lambda: peak("film_force"),
        "end_time": lambda: float(ds.time.values[-1]) if ds.sizes.get("time") else math.nan,
        "nfev": lambda: int(ds.attrs.get("nfev", -1)),
        "impact_times": lambda: [float(t) for t in times[:max_impacts]]
                                + [math.nan] * (max_impacts - min(len(times), max_impacts)),
    }
    out = {"status": str(ds.attrs.get("status", "complete")), "message": str(ds.attrs.get("message", "")),
           "wall_time": float(ds.attrs.get("wall_time", math.nan))}
    for name in quantities:
        out[name] = compute[name]()
    return out


def _empty_record(quantities, max_impacts, status, message, wall_time=math.nan):
    """The record of a point without results (an exception, a lost worker, an invalid point)."""
    out = {"status": status, "message": message, "wall_time": wall_time}
    for name in quantities:
        kind = QUANTITIES[name][2]
        out[name] = -1 if kind == "i" else [math.nan] * max_impacts if kind == "impacts" else math.nan
    return out


@dataclass(frozen=True)
class _TaskOptions:
    quantities: tuple
    time_series: tuple
    max_impacts: int
    n_time: int
    output_step: float
    tag: str


def _trace(path, event, tag, flat):
    """Append one line to the audit trace (O_APPEND, one write: safe from many processes)."""
    fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
    try:
        os.write(fd, f"{time.time():.6f} {os.getpid()} {event} {tag} {flat}\n".encode())
    finally:
        os.close(fd)


def _sample(ds, name, n_time, output_step):
    """Series ``name`` on the sweep's common time axis, NaN after an early end."""
    extra = ds[name].shape[1:] if name in ds else ()
    out = np.full((n_time,) + tuple(extra), np.nan)
    if name in ds and ds.sizes.get("time"):
        idx = np.rint(ds.time.values / output_step).astype(int)
        keep = (idx >= 0) & (idx < n_time)
        out[idx[keep]] = ds[name].values[keep]
    return out


def _compute_point(flat, config, opts, trace=None):
    """Worker task: simulate one point and return ``(record, series)``.

    A simulation that raises is a failed point (status ``error``), not a failed
    sweep.
    """
    if trace:
        _trace(trace, "start", opts.tag, flat)
    t0 = time.perf_counter()
    series = {}
    try:
        from .simulate import run, to_dataset

        ds = to_dataset(run(config))
        record = summarise(ds, opts.quantities, opts.max_impacts)
        for name in opts.time_series:
            series[name] = _sample(ds, name, opts.n_time, opts.output_step)
    except Exception as exc:  # noqa: BLE001 - a failing point is data, the sweep goes on
        record = _empty_record(opts.quantities, opts.max_impacts, "error", _describe(exc),
                               time.perf_counter() - t0)
        series = {}
    if trace:
        _trace(trace, "end", opts.tag, flat)
    return record, series


def _compute_points(flats, configs, opts, trace=None):
    """Worker task: several points in a row, ``([(flat, record, series), ...], seconds)``."""
    t0 = time.perf_counter()
    out = [(flat, *_compute_point(flat, config, opts, trace)) for flat, config in zip(flats, configs)]
    return out, time.perf_counter() - t0


def _describe(exc):
    import traceback

    tb = traceback.extract_tb(exc.__traceback__)
    where = f" (at {Path(tb[-1].filename).name}:{tb[-1].lineno})" if tb else ""
    return f"{type(exc).__name__}: {exc}{where}"


# ====================================================================== the store
def _chunks(shape, target=4096):
    """Chunk shape over the swept dimensions holding about ``target`` points."""
    chunks, room = [], target
    for n in reversed(shape):
        c = max(1, min(n, room))
        chunks.append(c)
        room = max(1, room // c)
    return tuple(reversed(chunks))


def _time_axis(config):
    s = config.solver
    n = int(np.floor(s.t_end / s.output_step * (1 + 1e-12))) + 1  # as lubelink.simulate.run
    return np.arange(n) * s.output_step


_SERIES_ATTRS = {
    "u2_mid": ("m", "midpoint deflection"),
    "x_star": ("m", "collar position along the link"),
    "V_r": ("m s-1", "collar velocity relative to the link"),
    "film_min": ("m", "thinnest film on the pad (sampled)"),
    "film_force": ("N", "resultant film force on the link along +j"),
    "q": ("m", "modal coordinate"),
    "q_dot": ("m s-1", "modal velocity"),
    "u2": ("m", "transverse deflection"),
    "pressure": ("Pa", "gauge film pressure P - p_am"),
}


def _template(sp: Sweep):
    """``(Dataset, encoding)`` of an empty store: summaries filled with their
    no-data values (NaN, -1, ""), time series as lazy Dask arrays (never written
    until a point arrives)."""
    import xarray as xr

    from .config import to_toml

    params = _parameters()
    dims, shape = sp.dims, sp.shape
    chunks = _chunks(shape)
    coords, data, encoding = {}, {}, {}

    def param_attrs(name, scale):
        _, units, long_name = params[name]
        return {"units": units, "long_name": long_name, "parameter": name, "scale": scale}

    def array(values):
        values = list(values)
        return np.array(values, dtype=object) if isinstance(values[0], str) else np.array(values)

    for a in sp.axes:
        coords[a.name] = ((a.name,), array(a.values), param_attrs(a.name, a.scale))
    if sp.point_rows:
        coords["point"] = (("point",), np.arange(len(sp.point_rows)), {"units": "1", "long_name": "point number"})
        for j, name in enumerate(sp.point_names):
            coords[name] = (("point",), array(r[j] for r in sp.point_rows), param_attrs(name, "list"))

    for name in list(ALWAYS) + list(sp.quantities):
        if name in ALWAYS:
            units, long_name = ALWAYS[name]
            kind = "s" if name in ("status", "message") else "f"
        else:
            units, long_name, kind = QUANTITIES[name]
        vdims, vchunks = dims, chunks
        if kind == "s":
            values = np.full(shape, "", dtype=object)
        elif kind == "i":
            values = np.full(shape, -1, dtype=np.int64)
        elif kind == "impacts":
            values = np.full(shape + (sp.max_impacts,), np.nan)
            vdims, vchunks = dims + ("impact",), chunks + (sp.max_impacts,)
            coords["impact"] = (("impact",), np.arange(sp.max_impacts), {"units": "1", "long_name": "impact number"})
        else:
            values = np.full(shape, np.nan)
        data[name] = (vdims, values, {"units": units, "long_name": long_name})
        encoding[name] = {"chunks": vchunks}
    data["done"] = (dims, np.zeros(shape, dtype=bool),
                    {"long_name": "point stored: computed, or recorded as failed or invalid"})
    encoding["done"] = {"chunks": chunks}

    if sp.time_series:
        import dask.array as dsa

        cfg = sp.base_config
        t = _time_axis(cfg)
        coords["time"] = (("time",), t, {"units": "s", "long_name": "time"})
        extra = {
            "mode": (np.arange(1, cfg.beam.modes + 1), "1", "mode number"),
            "x": (np.linspace(0.0, cfg.mechanism.rod_length, cfg.output.x_points), "m",
                  "position along the link from the crank pin O"),
            "X": (np.linspace(0.0, cfg.film.pad_length, cfg.output.pad_points), "m",
                  "position along the pad from its start"),
        }
        for name in sp.time_series:
            edim = SERIES[name][0]
            eshape = ()
            if edim:
                values, units, long_name = extra[edim]
                coords[edim] = ((edim,), values, {"units": units, "long_name": long_name})
                eshape = (len(values),)
            vshape = shape + (len(t),) + eshape
            vchunks = (1,) * len(shape) + (len(t),) + eshape
            units, long_name = _SERIES_ATTRS[name]
            data[name] = (dims + ("time",) + ((edim,) if edim else ()),
                          dsa.full(vshape, np.nan, chunks=vchunks), {"units": units, "long_name": long_name})
            encoding[name] = {"chunks": vchunks}

    from . import __version__

    attrs = {
        "title": "lubelink parameter sweep",
        "lubelink_sweep_format": SWEEP_FORMAT,
        "lubelink_version": __version__,
        "sweep_hash": sp.hash,
        "swept_dims": " ".join(dims),
        "quantities": " ".join(sp.quantities),
        "time_series": " ".join(sp.time_series),
        "points_total": sp.size,
        "sweep": sp.to_toml(),
        "base_config": to_toml(sp.base_config),
        "created": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        "runs": "[]",
    }
    return xr.Dataset(data, coords=coords, attrs=attrs), encoding


def _read_journal(path):
    """Records of a journal file; a torn last line (a kill mid-write) is ignored."""
    try:
        text = Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        return []
    records = []
    for line in text.splitlines():
        try:
            rec = json.loads(line)
        except json.JSONDecodeError:
            continue
        if isinstance(rec, dict) and isinstance(rec.get("i"), int):
            records.append(rec)
    return records


def _scatter(records, shape, quantities, max_impacts):
    """``{variable: (index, values)}`` of journal records; ``done`` comes last.

    A point recorded twice (a retried failure) keeps its latest record.
    """
    latest = {}
    for rec in records:
        if 0 <= rec["i"] < int(np.prod(shape)):
            latest[rec["i"]] = rec
    if not latest:
        return {}
    recs = list(latest.values())
    idx = np.unravel_index(np.array([r["i"] for r in recs]), shape)
    out = {}
    for name in list(ALWAYS) + list(quantities):
        vals = [r.get(name) for r in recs]
        kind = "s" if name in ("status", "message") else QUANTITIES.get(name, ("", "", "f"))[2]
        if kind == "impacts":
            k = max_impacts
            ix = tuple(np.repeat(i, k) for i in idx) + (np.tile(np.arange(k), len(recs)),)
            out[name] = (ix, np.array(vals, dtype=float).reshape(-1))
        elif kind == "s":
            out[name] = (idx, np.array([str(v) for v in vals], dtype=object))
        elif kind == "i":
            out[name] = (idx, np.array(vals, dtype=np.int64))
        else:
            out[name] = (idx, np.array([math.nan if v is None else v for v in vals], dtype=float))
    out["done"] = (idx, np.ones(len(recs), dtype=bool))
    return out


def _store_attrs(path):
    """Group attributes of a Zarr store, or None when ``path`` is not a Zarr group."""
    import zarr

    try:
        return dict(zarr.open_group(str(path), mode="r").attrs)
    except Exception:  # noqa: BLE001 - anything unreadable is "not a sweep store"
        return None


def _check_attrs(path, attrs, sp, overwrite):
    """Refuse a store of another sweep (or not a sweep store); True when it must be replaced."""
    if attrs is None or "lubelink_sweep_format" not in attrs:
        raise SweepError(f"{path} exists and is not a lubelink sweep store; choose another output")
    version = str(attrs["lubelink_sweep_format"])
    if version.split(".")[0] != SWEEP_FORMAT.split(".")[0]:
        if overwrite:
            return True
        raise SweepError(f"{path}: sweep store format {version}, this lubelink writes {SWEEP_FORMAT}; "
                         "add --overwrite to start it again")
    if attrs.get("sweep_hash") != sp.hash:
        if overwrite:
            return True
        raise SweepError(
            f"{path} holds a different sweep (hash {str(attrs.get('sweep_hash'))[:12]}, this sweep file gives "
            f"{sp.hash[:12]}): the base configuration, the grid or the stored quantities differ; "
            "use another output, or add --overwrite to discard it")
    return False


class _Store:
    """Writer of a Zarr sweep store; one process at a time (a lock file inside the store).

    Points are committed by one line appended to the journal; :meth:`compact`
    folds the journal into the arrays (values first, ``done`` last, then the
    journal is emptied), so a kill at any instant leaves every committed point
    either in the arrays or in the journal, never half-written (Zarr replaces
    chunk files atomically).
    """

    def __init__(self, path: Path, sp: Sweep):
        self.path, self.sweep = Path(path), sp
        self.group = None
        self._arrays = {}
        self._lock_fd = self._journal_fd = None
        self._last_compact = time.monotonic()

    @classmethod
    def open(cls, path, sp: Sweep, overwrite=False) -> "_Store":
        st = cls(path, sp)
        try:
            if st.path.exists():
                attrs = _store_attrs(st.path)
                if attrs is None or "lubelink_sweep_format" not in attrs:  # never touch a foreign folder
                    raise SweepError(f"{st.path} exists and is not a lubelink sweep store; choose another output")
                st._lock()
                if _check_attrs(st.path, _store_attrs(st.path), sp, overwrite):
                    st._unlock()
                    shutil.rmtree(st.path)
            if not st.path.exists():
                st._create()
                st._lock()
            import zarr

            st.group = zarr.open_group(str(st.path), mode="r+")
            for tmp in st.path.rglob("*.partial"):  # temporaries of a chunk write cut by a kill
                tmp.unlink(missing_ok=True)
            st._journal_fd = os.open(st.path / JOURNAL, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
            st.compact()  # fold what a killed run left in the journal
        except BaseException:
            st.close_files()
            raise
        return st

    def _create(self):
        """Build the empty store under a temporary name and rename it into place (atomic)."""
        parent = self.path.parent
        if not parent.is_dir():
            raise SweepError(f"{self.path}: folder {parent} does not exist")
        tmp = parent / f".{self.path.name}.{uuid.uuid4().hex[:8]}.creating"
        try:
            ds, encoding = _template(self.sweep)
            import warnings

            with warnings.catch_warnings():
                warnings.simplefilter("ignore", category=UserWarning)
                ds.to_zarr(str(tmp), mode="w-", compute=False, consolidated=False, encoding=encoding)
            import zarr

            g = zarr.open_group(str(tmp), mode="r+")
            for name, var in ds.variables.items():  # compute=False leaves numpy-backed arrays unwritten
                if not hasattr(var.data, "dask"):
                    g[name][...] = var.values
            (tmp / JOURNAL).touch()
            os.rename(tmp, self.path)
        except BaseException:
            shutil.rmtree(tmp, ignore_errors=True)
            raise

    def _lock(self):
        try:
            import fcntl
        except ImportError:  # Windows: no advisory locks; one writer is the user's responsibility
            return
        fd = os.open(self.path / LOCK, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            other = os.read(fd, 64).decode(errors="replace").strip() or "?"
            os.close(fd)
            raise SweepError(f"{self.path} is being written by another sweep (process {other}); "
                             "wait for it to finish or stop it") from None
        os.ftruncate(fd, 0)
        os.write(fd, f"{os.getpid()}\n".encode())
        self._lock_fd = fd

    def _unlock(self):
        if self._lock_fd is not None:
            os.close(self._lock_fd)
            self._lock_fd = None

    def array(self, name):
        if name not in self._arrays:
            self._arrays[name] = self.group[name]
        return self._arrays[name]

    def state(self):
        """``(done, status)`` as flat arrays over the points (journal folded in first)."""
        self.compact()
        done = np.asarray(self.array("done")[...]).reshape(-1)
        status = np.asarray(self.array("status")[...], dtype=object).reshape(-1)
        return done, status

    def write(self, results):
        """Store points ``[(flat, record, series), ...]``: their time series (if any), then one
        journal line each, in one append (the commit)."""
        lines = []
        for flat, record, series in results:
            if self.sweep.time_series:
                index = tuple(int(i) for i in np.unravel_index(flat, self.sweep.shape))
                for name in self.sweep.time_series:
                    if name in series:
                        self.array(name)[index] = series[name]
                    else:  # a point without results: clear what a previous attempt may have left
                        self.array(name)[index] = np.nan
            lines.append(json.dumps({"i": int(flat), **record}, default=_plain) + "\n")
        os.write(self._journal_fd, "".join(lines).encode())
        if time.monotonic() - self._last_compact > COMPACT_INTERVAL:
            self.compact()

    def compact(self):
        records = _read_journal(self.path / JOURNAL)
        sp = self.sweep
        for name, (index, values) in _scatter(records, sp.shape, sp.quantities, sp.max_impacts).items():
            self.array(name).vindex[index] = values
        if records:
            os.ftruncate(self._journal_fd, 0)
        self._last_compact = time.monotonic()

    def import_dataset(self, ds):
        """Fill the store from a loaded results Dataset (a NetCDF export being resumed)."""
        for name in list(ALWAYS) + list(self.sweep.quantities) + list(self.sweep.time_series):
            values = ds[name].values
            self.array(name)[...] = values.astype(object) if values.dtype.kind in "OUST" else values
        self.array("done")[...] = ds["done"].values.astype(bool)

    def close(self, session=None):
        try:
            self.compact()
            if session is not None:
                runs = json.loads(self.group.attrs.get("runs", "[]"))
                runs.append(session)
                self.group.attrs.update({"runs": json.dumps(runs)})
        finally:
            self.close_files()

    def close_files(self):
        if self._journal_fd is not None:
            os.close(self._journal_fd)
            self._journal_fd = None
        self._unlock()


def _plain(value):
    """JSON form of NumPy scalars and arrays in a record."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    raise TypeError(f"cannot store {type(value).__name__} in a sweep record")


def _side_store(path: Path) -> Path:
    return path.with_name(path.name + ".partial.zarr")


def _is_netcdf(path) -> bool:
    return Path(path).suffix.lower() in (".nc", ".nc4", ".netcdf")


def _export_netcdf(side: Path, path: Path):
    """Write the side store's results to ``path`` atomically (:func:`lubelink.results.atomic_path`)."""
    from .results import atomic_path

    ds = load_sweep(side)
    with atomic_path(path) as tmp:
        ds.to_netcdf(tmp, engine="netcdf4")
    return ds


# ====================================================================== reading
def _normalise(ds):
    """Strings as Python objects, whichever backend (Zarr StringDType, NetCDF fixed width)."""
    for name in list(ds.variables):
        if ds[name].dtype.kind in "TUS":
            if name in ds.coords:
                ds = ds.assign_coords({name: ds[name].astype(object)})
            else:
                ds[name] = ds[name].astype(object)
    first = ["done", "status", "message"] + ds.attrs.get("quantities", "").split() + ["wall_time"]
    order = [v for v in first if v in ds.data_vars] + [v for v in ds.data_vars if v not in first]
    return ds[order]


def load_sweep(path):
    """The results of a sweep as an in-memory :class:`xarray.Dataset`.

    Works on a store being written (it reads the arrays and the journal, both
    written atomically) and on a NetCDF export (preferring its side store when
    a run was interrupted). Points with ``done == False`` hold the no-data
    values: NaN, -1 and empty strings.
    """
    import warnings

    import xarray as xr

    path = Path(path)
    if _is_netcdf(path) and not _side_store(path).exists():
        if not path.exists():
            raise SweepError(f"{path}: no such sweep results file")
        try:
            ds = xr.load_dataset(path, engine="netcdf4")
        except Exception as exc:  # noqa: BLE001 - the backend raises many types for a foreign file
            raise SweepError(f"{path}: not a readable NetCDF file ({exc})") from None
        _check_format(path, ds.attrs)
        return _normalise(ds)
    if _is_netcdf(path):
        path = _side_store(path)
    if not path.exists():
        raise SweepError(f"{path}: no such sweep store")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", category=UserWarning)
        try:
            ds = xr.open_zarr(str(path), consolidated=False, chunks=None).load()
        except Exception as exc:  # noqa: BLE001 - many backend error types
            raise SweepError(f"{path}: not a readable Zarr store ({exc})") from None
    _check_format(path, ds.attrs)
    ds = _normalise(ds)
    records = _read_journal(path / JOURNAL)
    if records:
        shape = tuple(ds.sizes[d] for d in ds.attrs["swept_dims"].split())
        quantities = ds.attrs.get("quantities", "").split()
        for name, (index, values) in _scatter(records, shape, quantities, ds.sizes.get("impact", 0)).items():
            ds[name].data[index] = values
    return ds


def point_config(results, point):
    """The validated :class:`~lubelink.params.Config` of one point of a sweep's results.

    Parameters
    ----------
    results : xarray.Dataset or path
        Results of :func:`run_sweep` (or a store path).
    point : dict
        ``{dimension: value}`` for every swept dimension (``point`` takes the
        point number), e.g. ``{"film.viscosity": 0.1, "mechanism.crank_speed": 30.0}``.

    Example: ``lubelink.simulate(point_config(ds, {...}))`` runs that point again
    with its full results.
    """
    from .config import from_dict, resolve

    ds = results if hasattr(results, "data_vars") else load_sweep(results)
    dims = ds.attrs["swept_dims"].split()
    missing = [d for d in dims if d not in point]
    if missing or set(point) - set(dims):
        raise SweepError(f"point {point}: give exactly one value for each of " + ", ".join(dims))
    try:
        one = ds.sel(point)
    except KeyError as exc:
        raise SweepError(f"point {point}: no such value {exc}") from None
    overrides = {str(c.attrs["parameter"]): c.values.item() for c in one.coords.values() if "parameter" in c.attrs}
    return resolve(from_dict(tomllib.loads(ds.attrs["base_config"])), overrides)


def _check_format(path, attrs):
    version = str(attrs.get("lubelink_sweep_format", ""))
    if not version:
        raise SweepError(f"{path}: not a lubelink sweep store (no lubelink_sweep_format attribute)")
    if version.split(".")[0] != SWEEP_FORMAT.split(".")[0]:
        raise SweepError(f"{path}: sweep store format {version}, this lubelink reads {SWEEP_FORMAT}")


# ====================================================================== running
def _cpu_count() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


@contextlib.contextmanager
def _dask_client(client, scheduler, workers):
    """``(client, description)``: the user's client, one connected to ``scheduler``, or a LocalCluster."""
    if client is not None:
        yield client, f"Dask client {getattr(client, 'scheduler', None) and client.scheduler.address}"
        return
    from distributed import Client, LocalCluster

    if scheduler:
        try:
            c = Client(scheduler)  # waits distributed.comm.timeouts.connect (Dask config, 30 s)
        except Exception as exc:  # noqa: BLE001 - OSError, TimeoutError, ValueError for a bad address
            raise SweepError(f"scheduler {scheduler}: cannot connect ({exc})") from None
        try:
            yield c, f"Dask scheduler {scheduler}"
        finally:
            c.close()
        return
    import dask

    n = workers or _cpu_count()
    with dask.config.set(LOCAL_CLUSTER_CONFIG):
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               silence_logs=logging.ERROR, dashboard_address=":0")
        c = Client(cluster)
    try:
        yield c, f"LocalCluster, {n} worker process(es)"
    finally:
        c.close()
        cluster.close()


def run_sweep(sweep, store=None, *, client=None, scheduler=None, workers=None, retry_failed=False,
              overwrite=False, progress=True, trace=None, task_seconds=0.5):
    """Run a parameter sweep on Dask and return every point's results.

    Points already in ``store`` are skipped (the run resumes); each finished
    point is stored at once, so interrupting loses at most the points being
    computed at that moment.

    Parameters
    ----------
    sweep : str, os.PathLike, dict or Sweep
        Sweep file or its parsed content (:func:`read_sweep`).
    store : str or os.PathLike, optional
        Results: a Zarr directory (default ``<sweep file name>.zarr``), or a
        ``.nc`` file (NetCDF, written when the run ends).
    client : distributed.Client, optional
        Your own Dask client (kept open). Otherwise ``scheduler`` is connected
        to, or a ``LocalCluster`` of ``workers`` processes (default: one per
        core, one thread each) is started for this call.
    scheduler : str, optional
        Address of a running Dask scheduler, e.g. ``"tcp://10.0.0.5:8786"``.
    workers : int, optional
        Worker processes of the local cluster.
    retry_failed : bool
        Compute again the stored points whose status is not ``complete``
        (except ``invalid``).
    overwrite : bool
        Discard a store that holds another sweep instead of refusing.
    progress : bool
        Show a progress bar (done, failed, remaining, time left).
    trace : str or os.PathLike, optional
        Audit file: every point computation appends a ``start`` and an ``end``
        line (it must be on a file system that the workers can write).
    task_seconds : float
        Once the points' duration is known, a Dask task computes as many
        points as take about this long [s] (at least one), so that Dask's
        per-task overhead stays small for short points; 0 sends one point
        per task. A crash loses at most the tasks being computed.

    Returns
    -------
    xarray.Dataset
        Over the swept dimensions: ``done``, ``status``, ``message``,
        ``wall_time`` and the chosen quantities (units in their attrs); the
        attrs hold the sweep, its hash, the base configuration and ``runs``
        (JSON, one entry per run of this sweep).

    Raises
    ------
    lubelink.ConfigError
        An invalid sweep file, or invalid points (unless
        ``invalid_points = "record"``), before anything is computed.
    SweepError
        A store of another sweep, a store in use, an unreachable scheduler.
    """
    sp = read_sweep(sweep)
    if store is None:
        if sp.origin in ("sweep", "store"):
            raise SweepError("run_sweep: give store=... for a sweep that is not read from a file")
        store = Path(f"{Path(sp.origin).stem}.zarr")
    path = Path(store)
    if scheduler and workers:
        raise SweepError("give either a scheduler address or a number of local workers, not both")
    if client is not None and (scheduler or workers):
        raise SweepError("give either a Dask client or a scheduler address / number of workers")

    bar = _bar(progress, sp.size, "validating") if sp.size >= 500 else None
    try:
        configs, invalid = sp.point_configs(progress=(lambda n: bar.update(n - bar.n)) if bar else None)
    finally:
        if bar is not None:
            bar.close()
    if invalid and sp.invalid_points == "error":
        raise ConfigError(sp.invalid_report(invalid))

    export = None
    if _is_netcdf(path):
        export, side = path, _side_store(path)
        if not path.parent.is_dir():
            raise SweepError(f"{path}: folder {path.parent} does not exist")
        if path.exists() and not side.exists():
            previous = load_sweep(path)
            if _check_attrs(path, previous.attrs, sp, overwrite):
                previous = None
            elif not _pending(sp, configs, previous.done.values.reshape(-1),
                              previous.status.values.reshape(-1), retry_failed) \
                    and not _unrecorded(invalid, previous.done.values.reshape(-1)):
                return previous  # nothing to do
        else:
            previous = None
        st = _Store.open(side, sp, overwrite=overwrite)
        if previous is not None:
            st.import_dataset(previous)
    else:
        st = _Store.open(path, sp, overwrite=overwrite)

    session = {"started": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()), "computed": 0, "failed": 0,
               "interrupted": False, "host": os.uname().nodename if hasattr(os, "uname") else "",
               "lubelink_version": _lubelink_version()}
    t0 = time.perf_counter()
    try:
        done, status = st.state()
        st.write([(flat, _empty_record(sp.quantities, sp.max_impacts, "invalid", "; ".join(invalid[flat]), 0.0), {})
                  for flat in _unrecorded(invalid, done)])
        done, status = st.state()
        pending = _pending(sp, configs, done, status, retry_failed)
        session["resumed"] = int(done.sum()) - int(done[pending].sum()) if pending else int(done.sum())
        if pending:
            with _dask_client(client, scheduler, workers) as (cl, where):
                session["scheduler"] = where
                _execute(cl, st, sp, configs, pending, done, status, progress, trace, session, task_seconds)
    except KeyboardInterrupt:
        session["interrupted"] = True
        raise
    finally:
        session["wall_time"] = round(time.perf_counter() - t0, 3)
        session["finished"] = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
        st.close(session)
        if export is not None:
            ds = _export_netcdf(st.path, export)
            if bool(ds.done.all()):
                shutil.rmtree(st.path, ignore_errors=True)
    return load_sweep(path)


#: Alias of :func:`run_sweep`.
sweep = run_sweep


def _lubelink_version():
    from . import __version__

    return __version__


def _unrecorded(invalid, done):
    return [flat for flat in invalid if not done[flat]]


def _pending(sp, configs, done, status, retry_failed):
    """Flat indices to compute: valid points not stored (and failed ones with ``retry_failed``)."""
    return [flat for flat in configs
            if not done[flat] or (retry_failed and str(status[flat]) not in ("complete", "invalid"))]


def _bar(progress, total, desc, initial=0):
    from tqdm.auto import tqdm

    return tqdm(total=total, initial=initial, desc=desc, unit="pt", file=sys.stderr, disable=not progress,
                dynamic_ncols=True, smoothing=0.05, mininterval=0.2,
                bar_format="{desc}: {percentage:3.0f}%|{bar}| {n}/{total} [{elapsed}<{remaining}, "
                           "{rate_fmt}{postfix}]")


def _execute(client, st, sp, configs, pending, done, status, progress, trace, session, task_seconds):
    """Submit the pending points in a moving window of tasks; store each task's points as it completes.

    A task computes one point, or, once the points are known to be short, as many as take about
    ``task_seconds`` on a worker, so that Dask's per-task cost (a few milliseconds of scheduler,
    network and worker time) stays small beside the simulations.
    """
    from collections import deque

    from distributed import as_completed

    opts = _TaskOptions(quantities=sp.quantities, time_series=sp.time_series, max_impacts=sp.max_impacts,
                        n_time=len(_time_axis(sp.base_config)) if sp.time_series else 0,
                        output_step=sp.base_config.solver.output_step, tag=sp.hash[:12])
    trace = str(Path(trace).resolve()) if trace else None
    token = uuid.uuid4().hex[:8]
    queue = deque(pending)
    single = deque()  # points of a batch that killed its workers: run again one per task
    active = {}
    ac = as_completed(with_results=True, raise_errors=False)
    retried = set(pending) & set(np.flatnonzero(done).tolist())
    failed = sum(1 for f in range(sp.size) if done[f] and str(status[f]) != "complete") - len(retried)
    n_done = int(done.sum()) - len(retried)
    per_point = None  # seconds per point on a worker (moving average)

    def threads():
        try:
            return max(1, sum(client.nthreads().values()))
        except Exception:  # noqa: BLE001 - a scheduler without workers yet
            return 1

    def batch():
        if single:
            return [single.popleft()]
        n = 1
        if per_point is not None and task_seconds > 0:
            n = int(task_seconds / max(per_point, 1e-6))
            n = min(n, 256, len(queue) // (2 * nthreads))  # keep every worker busy to the end
        return [queue.popleft() for _ in range(min(max(1, n), len(queue)))]

    def submit(n_tasks):
        """Submit up to ``n_tasks`` more tasks in one graph update."""
        tasks = []
        while len(tasks) < n_tasks and (queue or single):
            tasks.append(batch())
        if not tasks:
            return
        futures = client.map(_compute_points, tasks, [[configs[f] for f in t] for t in tasks], opts=opts,
                             trace=trace, pure=False,
                             key=[f"lubelink-sweep-{sp.hash[:8]}-{token}-{t[0]}-{len(t)}" for t in tasks])
        for task, fut in zip(tasks, futures):
            active[fut] = task
        ac.update(futures)

    nthreads = threads()
    window = 3 * nthreads + 2
    last_window = time.monotonic()
    submit(window)
    bar = _bar(progress, sp.size, "sweep", initial=n_done)
    bar.set_postfix_str(f"failed {failed}, remaining {sp.size - n_done}", refresh=False)
    lost = 0
    try:
        for fut, result in ac:
            task = active.pop(fut)
            if fut.status == "finished":
                results, seconds = result
                per_point = seconds / len(task) if per_point is None else \
                    0.8 * per_point + 0.2 * seconds / len(task)
            elif fut.status == "error" and len(task) > 1:  # find which point kills its workers
                single.extend(task)
                results = []
            elif fut.status == "error":
                exc = result[1] if isinstance(result, tuple) else result
                state = "worker_died" if type(exc).__name__ == "KilledWorker" else "error"
                results = [(task[0], _empty_record(sp.quantities, sp.max_impacts, state, _describe(exc)), {})]
            else:  # cancelled or lost with the connection: not stored, computed on the next run
                lost += len(task)
                results = []
            if results:
                st.write(results)
                new_failed = sum(1 for _, record, _ in results if record["status"] != "complete")
                session["computed"] += len(results)
                session["failed"] += new_failed
                n_done += len(results)
                failed += new_failed
                bar.set_postfix_str(f"failed {failed}, remaining {sp.size - n_done}", refresh=False)
                bar.update(len(results))
            del fut, result, results
            if time.monotonic() - last_window > 30.0:  # follow a cluster that scales
                nthreads, last_window = threads(), time.monotonic()
                window = 3 * nthreads + 2
            if len(active) <= window // 2:  # refill in batches: fewer messages to the scheduler
                submit(window - len(active))
    except BaseException:
        with contextlib.suppress(Exception):
            client.cancel(list(active))
        raise
    finally:
        bar.close()
    session["lost"] = lost
    if lost:
        log.warning("%d point(s) were not computed (their tasks were cancelled or lost with the Dask "
                    "connection); run the sweep again to compute them", lost)


# ====================================================================== plotting
def _edges(values, log):
    v = np.asarray(values, dtype=float)
    if log:
        return np.exp(_edges(np.log(v), False))
    if v.size == 1:
        half = 0.5 if v[0] == 0 else 0.1 * abs(v[0])
        return np.array([v[0] - half, v[0] + half])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[v[0] - (mid[0] - v[0])], mid, [v[-1] + (v[-1] - mid[-1])]])


def _axis_values(ds, dim, lists_as_categories):
    """``(positions, tick labels or None, log)`` of a dimension coordinate on a plot axis.

    Strings, and in heat maps lists of values, are placed at equal spacing and
    labelled; ranges keep their linear or log scale; a numeric list spanning two
    decades or more is drawn on a log axis.
    """
    def text(v):
        return _fmt(v.item() if hasattr(v, "item") else v)

    c = ds[dim]
    if dim == "point":  # explicit points: label each with its parameter values
        params = [n for n, v in ds.coords.items() if v.dims == ("point",) and n != "point"]
        labels = [", ".join(f"{n.split('.')[-1]}={text(ds[n].values[i])}" for n in params) for i in range(c.size)]
        return np.arange(c.size, dtype=float), labels, False
    scale = c.attrs.get("scale", "list")
    if c.dtype.kind not in "fiu" or (lists_as_categories and scale == "list" and c.size > 1):
        return np.arange(c.size, dtype=float), [text(v) for v in c.values], False
    v = c.values.astype(float)
    wide = scale == "list" and v.size > 1 and v.min() > 0 and v.max() / v.min() >= 100
    return v, None, scale == "log" or wide


def _label(ds, name):
    units = ds[name].attrs.get("units", "")
    return f"{name} [{units}]" if units and units != "1" else name


def plot_sweep(results, quantity=None, *, select=None, fig=None):
    """Response map of one quantity over the swept dimensions.

    One dimension left (after ``select``): curves; two: a heat map; three:
    heat maps faceted along the last one. Points that failed are marked with
    a cross; points not yet computed are left blank.

    Parameters
    ----------
    results : xarray.Dataset or path
        :func:`run_sweep` / :func:`load_sweep` output, or a store path.
    quantity : str, optional
        Stored quantity (default ``peak_u2_mid`` when stored); ``status``
        draws a map of the outcomes.
    select : dict, optional
        ``{dimension: value}`` slices (nearest value for numbers); ``impact``
        selects which of ``impact_times``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    ds = results if hasattr(results, "data_vars") else load_sweep(results)
    dims = ds.attrs.get("swept_dims", "").split()
    stored = [q for q in ds.attrs.get("quantities", "").split() if q in ds] + ["status", "wall_time"]
    if quantity is None:
        quantity = "peak_u2_mid" if "peak_u2_mid" in ds else stored[0]
    if quantity not in ds or quantity not in stored:
        raise SweepError(f"quantity {quantity!r}: not stored in these results; choose from "
                         + ", ".join(stored) + _suggest(quantity, stored))
    select = dict(select or {})
    for dim, value in list(select.items()):
        if dim not in ds.dims:
            raise SweepError(f"select {dim}: no such dimension; the dimensions are "
                             + ", ".join(ds[quantity].dims) + _suggest(dim, ds.dims))
        if dim in ds.coords and ds[dim].dtype.kind in "fiu":
            try:
                select[dim] = float(value)
            except (TypeError, ValueError):
                raise SweepError(f"select {dim}={value!r}: must be a number") from None
    numeric = {d: v for d, v in select.items() if d in ds.coords and ds[d].dtype.kind in "fiu"}
    exact = {d: v for d, v in select.items() if d not in numeric}
    if "impact" in ds[quantity].dims and "impact" not in select:
        exact["impact"] = 0
    try:
        sub = ds.sel(numeric, method="nearest") if numeric else ds
        sub = sub.sel({d: v for d, v in exact.items() if d in ds.coords and d != "impact"})
        if "impact" in exact:
            sub = sub.isel(impact=int(exact["impact"]))
    except KeyError as exc:
        raise SweepError(f"select: no such value {exc}") from None
    free = [d for d in dims if d in sub[quantity].dims]
    if len(free) > 3 or not free:
        raise SweepError(f"{len(free)} swept dimensions left ({', '.join(free) or 'none'}): plot-sweep draws "
                         "1 (curves), 2 (heat map) or 3 (facets); fix the others with --select DIM=VALUE")
    done = sub["done"].values.astype(bool)
    failed = done & (sub["status"].values.astype(str) != "complete")
    values = sub[quantity]
    units = ds[quantity].attrs.get("units", "")
    title = quantity + (f" [{units}]" if units and units != "1" else "")
    categories = None
    if quantity == "status" or values.dtype.kind in "OUS":
        categories = sorted({str(v) for v in values.values.reshape(-1)[done.reshape(-1)]}) or ["(none)"]
        codes = np.vectorize(lambda v: categories.index(str(v)) if str(v) in categories else -1,
                             otypes=[float])(values.values)
        data = np.where(done, codes, np.nan)
    else:
        data = np.where(done, values.values.astype(float), np.nan)
    da = values.copy(data=data).transpose(*free)
    failed = values.copy(data=failed).transpose(*free).values
    if select:
        title += "  (" + ", ".join(f"{d} = {_fmt(sub[d].item()) if d in sub.coords else v}"
                                   for d, v in select.items()) + ")"

    panels = [None] if len(free) < 3 else list(range(sub.sizes[free[2]]))
    if len(panels) > 16:
        raise SweepError(f"{free[2]} has {len(panels)} values, too many panels: fix it with --select "
                         f"{free[2]}=VALUE, or another dimension")
    ncols = min(len(panels), 4)
    nrows = math.ceil(len(panels) / ncols)
    fig = fig or plt.figure(figsize=(7.0, 4.8) if len(free) < 3 else (3.6 * ncols + 1.0, 3.0 * nrows + 0.6))
    if len(free) == 1:
        ax = fig.add_subplot()
        x, ticks, log = _axis_values(sub, free[0], False)
        ax.plot(x, da.values, "o-", label=quantity)
        if failed.any():
            ax.plot(x[failed], da.values[failed], "x", color="tab:red", ms=9, mew=2,
                    label="failed (status not complete)")
            ax.legend()
        if ticks:
            ax.set_xticks(x, ticks)
        if log:
            ax.set_xscale("log")
        if categories:
            ax.set_yticks(range(len(categories)), categories)
        ax.set_xlabel(_label(sub, free[0]))
        ax.set_ylabel(title)
        ax.set_title(ds[quantity].attrs.get("long_name", quantity), fontsize=10)
        ax.grid(True, alpha=0.3)
        return fig

    finite = data[np.isfinite(data)]
    vmin, vmax = (finite.min(), finite.max()) if finite.size else (0.0, 1.0)
    cmap = plt.get_cmap("viridis", len(categories)) if categories else "viridis"
    if categories:
        vmin, vmax = -0.5, len(categories) - 0.5
    axes = fig.subplots(nrows, ncols, squeeze=False)
    mesh = None
    for k, panel in enumerate(panels):
        ax = axes.flat[k]
        z = da.values if panel is None else da.values[..., panel]
        f = failed if panel is None else failed[..., panel]
        x, xt, xlog = _axis_values(sub, free[0], True)
        y, yt, ylog = _axis_values(sub, free[1], True)
        mesh = ax.pcolormesh(_edges(x, xlog), _edges(y, ylog), z.T, cmap=cmap, vmin=vmin, vmax=vmax,
                             shading="flat")
        if f.any() and not categories:
            ix, iy = np.nonzero(f)
            ax.plot(x[ix], y[iy], "x", color="white", ms=7, mew=2, markeredgecolor="black")
        if xt:
            ax.set_xticks(x, xt)
        if yt:
            ax.set_yticks(y, yt)
        if xlog:
            ax.set_xscale("log")
        if ylog:
            ax.set_yscale("log")
        ax.set_xlabel(_label(sub, free[0]))
        ax.set_ylabel(_label(sub, free[1]))
        if panel is not None:
            ax.set_title(f"{free[2]} = {_fmt(sub[free[2]].values[panel].item())}", fontsize=9)
        else:
            ax.set_title(ds[quantity].attrs.get("long_name", quantity), fontsize=10)
    for ax in axes.flat[len(panels):]:
        ax.set_visible(False)
    cbar = fig.colorbar(mesh, ax=axes.ravel().tolist())
    if categories:
        cbar.set_ticks(range(len(categories)), labels=categories)
    cbar.set_label(title + ("   x: failed" if failed.any() and not categories else ""))
    return fig


# ====================================================================== command line
def register_cli(subparsers, add_config_args):
    """Add the ``sweep`` and ``plot-sweep`` subcommands."""
    del add_config_args  # a sweep file names its own base configuration
    p = subparsers.add_parser(
        "sweep", help="run a parameter sweep on Dask (resumable)",
        description="Run every point of a sweep file on Dask and store the results (Zarr, or NetCDF "
                    "for FILE.nc) as they finish. Running the same command again resumes: stored points "
                    "are skipped. See docs/sweeps.md.")
    p.add_argument("sweep_file", metavar="SWEEP.toml", help="the sweep definition")
    p.add_argument("-o", "--output", metavar="RESULTS",
                   help="results store: DIR.zarr or FILE.nc (default: <sweep file name>.zarr here)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="address of a running Dask scheduler, e.g. tcp://10.0.0.5:8786 "
                        "(default: a local cluster)")
    p.add_argument("--workers", metavar="N", help="worker processes of the local cluster (default: one per core)")
    p.add_argument("--retry-failed", action="store_true",
                   help="compute again the stored points whose status is not 'complete'")
    p.add_argument("--overwrite", action="store_true", help="discard a store that holds a different sweep")
    p.add_argument("--check", action="store_true",
                   help="validate the sweep file and every point, print the plan and what is stored; compute nothing")
    p.add_argument("--trace", metavar="FILE",
                   help="append a start and an end line per point computation to FILE (audit)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar and no summary")
    p.set_defaults(handler=_cmd_sweep)

    p = subparsers.add_parser(
        "plot-sweep", help="draw a response map of a sweep's results",
        description="Heat map of a stored quantity over two swept parameters, curves for one, facets for "
                    "three (fix more with --select).")
    p.add_argument("results", metavar="RESULTS", help="a sweep store (DIR.zarr or FILE.nc)")
    p.add_argument("--quantity", metavar="NAME", help="quantity to draw (default peak_u2_mid); 'status' maps outcomes")
    p.add_argument("--select", action="append", default=[], metavar="DIM=VALUE",
                   help="fix a swept dimension at (the value nearest to) VALUE; repeatable")
    p.add_argument("-o", "--output", metavar="FILE.png",
                   help="image file (default: <results name>-<quantity>.png here)")
    p.set_defaults(handler=_cmd_plot_sweep)


def _usage(message):
    from .errors import UsageError

    return UsageError(message)


def _require(*modules, extra):
    """A one-line usage error when an optional dependency is missing."""
    import importlib.util

    missing = [m for m in modules if importlib.util.find_spec(m) is None]
    if missing:
        raise _usage(f"{', '.join(missing)} not installed; install the extra: pip install 'lubelink[{extra}]'")


def _plan(sp: Sweep, invalid, path):
    params = _parameters()
    rows = [("sweep", sp.origin), ("base", f"{sp.base}" + (f", with [set] {', '.join(sp.fixed)}" if sp.fixed else ""))]
    for i, a in enumerate(sp.axes):
        units = params[a.name][1]
        span = f"{_fmt(a.values[0])} .. {_fmt(a.values[-1])}" if len(a.values) > 1 else _fmt(a.values[0])
        rows.append(("dimensions" if i == 0 else "", f"{a.name}: {len(a.values)} ({a.scale}, {span}"
                     + (f" {units}" if units and units != "1" else "") + ")"))
    if sp.point_rows:
        rows.append(("dimensions" if not sp.axes else "",
                     f"point: {len(sp.point_rows)} explicit points of {', '.join(sp.point_names)}"))
    rows.append(("points", f"{sp.size}" + (f", {len(invalid)} invalid" if invalid else ", all valid")))
    rows.append(("stored per point", ", ".join(("status", "message", "wall_time") + sp.quantities)
                 + (f"; time series {', '.join(sp.time_series)}" if sp.time_series else "")))
    rows.append(("hash", sp.hash[:16]))
    if path is not None and (path.exists() or _side_store(path).exists()):
        try:
            ds = load_sweep(path)
            same = ds.attrs.get("sweep_hash") == sp.hash
            rows.append(("results", f"{path}: {int(ds.done.sum())} of {sp.size} points stored" if same
                         else f"{path}: holds a different sweep (would need --overwrite)"))
        except SweepError as exc:
            rows.append(("results", str(exc)))
    elif path is not None:
        rows.append(("results", f"{path} (new)"))
    return _table(rows)


def _table(rows):
    width = max(len(k) for k, _ in rows)
    return "\n".join(f"{k:<{width}}  {v}" for k, v in rows)


def _summary(ds, sp: Sweep, path):
    status = ds.status.values.reshape(-1)[ds.done.values.reshape(-1)]
    counts = {}
    for s in status:
        counts[str(s)] = counts.get(str(s), 0) + 1
    n_done = int(ds.done.sum())
    complete = counts.pop("complete", 0)
    run = json.loads(ds.attrs.get("runs", "[]") or "[]")
    last = run[-1] if run else {}
    rows = [
        ("sweep", f"{sp.origin}: {sp.size} points (" + " x ".join(f"{d} {n}" for d, n in zip(sp.dims, sp.shape)) + ")"),
        ("results", str(path)),
        ("stored", f"{n_done} of {sp.size}: {complete} complete, {n_done - complete} failed"
                   + (" (" + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())) + ")" if counts else "")),
    ]
    if last:
        rate = last["computed"] / last["wall_time"] if last.get("wall_time") else 0.0
        rows.append(("this run", f"{last['computed']} computed in {last['wall_time']:.1f} s"
                     + (f" ({rate:.3g} points/s)" if last["computed"] else "")
                     + (f" on {last['scheduler']}" if last.get("scheduler") else "")
                     + f"; {last.get('resumed', 0)} were already stored"))
    if n_done < sp.size:
        rows.append(("remaining", f"{sp.size - n_done} points; run the same command again to compute them"))
    if counts:
        first = next(i for i, s in enumerate(ds.status.values.reshape(-1)) if str(s) not in ("complete", ""))
        rows.append(("first failure", f"{sp.label(first)}: {ds.message.values.reshape(-1)[first]}"))
    return _table(rows)


def _cmd_sweep(args):
    path_in = Path(args.sweep_file)
    if not path_in.is_file():
        raise _usage(f"SWEEP.toml = {args.sweep_file!r}: no such file")
    workers = None
    if args.workers is not None:
        try:
            workers = int(args.workers)
        except ValueError:
            workers = 0
        if workers < 1:
            raise _usage(f"--workers {args.workers}: must be a whole number >= 1")
    if args.scheduler and workers:
        raise _usage("give either --scheduler ADDRESS (an existing cluster) or --workers N (a local one), not both")
    sp = read_sweep(path_in)
    out = Path(args.output) if args.output else Path(f"{path_in.stem}.zarr")
    if not out.parent.is_dir():
        raise _usage(f"-o {out}: folder {out.parent} does not exist")
    if args.check:
        configs, invalid = sp.point_configs()
        print(_plan(sp, invalid, out))
        if invalid and sp.invalid_points == "error":
            raise ConfigError(sp.invalid_report(invalid))
        return 0
    _require("distributed", "zarr", "xarray", extra="sweep")
    if not args.quiet:
        print(f"{sp.origin}: {sp.size} points -> {out}", file=sys.stderr)
    try:
        ds = run_sweep(sp, out, scheduler=args.scheduler, workers=workers, retry_failed=args.retry_failed,
                       overwrite=args.overwrite, progress=not args.quiet, trace=args.trace)
    except SweepError as exc:
        raise _usage(str(exc)) from None
    except KeyboardInterrupt:
        stored = "?"
        with contextlib.suppress(Exception):
            stored = int(load_sweep(out).done.sum())
        print(f"lubelink: interrupted; {stored} of {sp.size} points are stored in {out}; run the same "
              "command again to resume", file=sys.stderr)
        return 130
    if not args.quiet:
        print(_summary(ds, sp, out))
    return 0 if bool(ds.done.all()) else 1


def _cmd_plot_sweep(args):
    path = Path(args.results)
    if not (path.exists() or (_is_netcdf(path) and _side_store(path).exists())):
        raise _usage(f"RESULTS = {args.results!r}: no such sweep store")
    select = {}
    for text in args.select:
        if "=" not in text:
            raise _usage(f"--select {text!r}: must look like DIM=VALUE, e.g. film.viscosity=0.1")
        dim, value = (part.strip() for part in text.split("=", 1))
        select[dim] = value
    _require("matplotlib", "zarr", "xarray", extra="plot,sweep")
    import matplotlib

    matplotlib.use("Agg")
    try:
        ds = load_sweep(path)
        quantity = args.quantity
        fig = plot_sweep(ds, quantity, select=select)
    except SweepError as exc:
        raise _usage(str(exc)) from None
    quantity = quantity or ("peak_u2_mid" if "peak_u2_mid" in ds else "status")
    out = Path(args.output) if args.output else Path(f"{path.name.split('.')[0]}-{quantity}.png")
    if not out.parent.is_dir():
        raise _usage(f"-o {out}: folder {out.parent} does not exist")
    from .results import atomic_path

    with atomic_path(out) as tmp:
        fig.savefig(tmp, dpi=120, bbox_inches="tight", format=out.suffix.lstrip(".").lower() or "png")
    print(f"wrote {out}")
    return 0

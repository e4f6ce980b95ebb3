"""Reading and validating a sweep file: :func:`read_sweep` -> :class:`~.spec.Sweep`.

Every problem is collected (unknown keys with a "did you mean", bad values, ranges, explicit
points, stored names, a swept parameter that a stored time series needs fixed) and raised at once
as one :class:`lubelink.ConfigError`, one line per problem naming the key. The points themselves
are validated later, by :meth:`Sweep.point_configs <.spec.Sweep.point_configs>`.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..config import SCENARIOS, ConfigError, _name, read_toml
from ..errors import suggest
from .schema import DEFAULT_QUANTITIES, QUANTITIES, SERIES, _fmt, _parameters, with_spatial_companions
from .spec import Axis, Sweep

__all__ = ["read_sweep", "MAX_POINTS"]

_TIME_KEYS = ("solver.t_end", "solver.output_step")

_TOP_KEYS = ("base", "description", "invalid_points", "set", "vary", "points", "store")
_STORE_KEYS = ("quantities", "time_series", "max_impacts")
_RANGE_KEYS = ("start", "stop", "num", "scale")
#: Largest sweep run (or checked) without asking: a larger one is refused up front, with its
#: estimated time and memory, unless ``--max-points`` (``run_sweep(max_points=...)``) allows it.
MAX_POINTS = 100_000
#: Largest ``--max-points``: the flat index of a point must fit the store's integer types.
MAX_POINTS_LIMIT = 1_000_000_000


def _scalar(name, ftype, value, where, problems):
    """``value`` as the Python type of parameter ``name``, or None with a problem recorded."""
    ok = True
    if ftype == "float":
        ok = isinstance(value, (int, float)) and not isinstance(value, bool) and _finite_or_float(value)
        value = float(value) if ok else value
        kind = "a number within the range of a float"
    elif ftype == "int":
        if isinstance(value, float) and value.is_integer():
            value = int(value)
        ok = isinstance(value, int) and not isinstance(value, bool) and abs(value) < 2**63
        kind = "an integer (of 64 bits)"
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


def _finite_or_float(value) -> bool:
    """True when ``float(value)`` works: a float, or an integer within the range of a float."""
    return not isinstance(value, int) or abs(value) <= _FLOAT_MAX


_FLOAT_MAX = 1.7976931348623157e308


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
                problems.append(f"{where}.\"{_name(name)}\": unknown parameter, must be section.key"
                                + suggest(name, params))
                continue
            out[name] = v
    return out


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
    data = read_toml(path, "sweep file")
    return _parse(data, origin=str(path), root=path.parent)


def _parse(data, origin, root) -> Sweep:
    from ..config import resolve

    params = _parameters()
    problems = []
    for key in data:
        if key not in _TOP_KEYS:
            problems.append(f"{origin}: unknown key '{_name(key)}'{suggest(key, _TOP_KEYS)}; a sweep file has "
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
        problem = _base_file_problem(base_source)
        if problem:
            problems.append(f"{origin}: base = {_fmt(base)}: {problem}")
            base_source = None
    else:
        problems.append(f"{origin}: base = {_fmt(base)}: not a scenario (" + ", ".join(SCENARIOS)
                        + f") nor a configuration file (looked for {root / base})" + suggest(base, SCENARIOS))
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

    # ---- store
    store = data.get("store", {})
    quantities, series, max_impacts = DEFAULT_QUANTITIES, (), 10
    if not isinstance(store, dict):
        problems.append(f"{origin}: [store] must be a table, got {_fmt(store)}")
        store = {}
    for key in store:
        if key not in _STORE_KEYS:
            problems.append(f"store.{_name(key)}: unknown key{suggest(key, _STORE_KEYS)}; [store] has "
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
    if _spatial(base_config, axes, point_names, point_rows):
        quantities, series = with_spatial_companions(quantities), with_spatial_companions(series)
    return Sweep(base=base, base_config=base_config, fixed=fixed, axes=tuple(axes),
                 point_names=point_names, point_rows=point_rows, quantities=tuple(quantities),
                 time_series=tuple(series), max_impacts=max_impacts, invalid_points=policy,
                 origin=origin)


def _spatial(base_config, axes, point_names, point_rows) -> bool:
    """Whether some point of the sweep runs ``beam.model = "spatial"`` (the base's, or a swept value)."""
    models = {base_config.beam.model}
    models.update(v for a in axes if a.name == "beam.model" for v in a.values)
    if "beam.model" in point_names:
        j = point_names.index("beam.model")
        models.update(row[j] for row in point_rows)
    return "spatial" in models


def _base_file_problem(path):
    """Why the configuration file ``path`` cannot be a sweep's base, or None.

    Its faults are not quoted: a sweep file may name any file (``base = "../../secrets.toml"``),
    and whoever runs the sweep would see pieces of it in the messages. The user checks the file
    with ``lubelink config FILE``, which does quote it.
    """
    from ..config import load

    try:
        load(path)
    except ConfigError as exc:
        n = len(exc.problems)
        return (f"{path} is not a valid lubelink configuration file ({n} problem{'s' if n > 1 else ''}, not "
                f"shown here; run: lubelink config {path})")
    return None


def _axis(name, spec, ftype, where, problems):
    if isinstance(spec, dict):
        for key in spec:
            if key not in _RANGE_KEYS:
                problems.append(f"{where}.{_name(key)}: unknown key{suggest(key, _RANGE_KEYS)}; a range has "
                                "start, stop, num and optionally scale = \"linear\" | \"log\"")
        missing = [k for k in ("start", "stop", "num") if k not in spec]
        if missing:
            problems.append(f"{where}: a range needs " + ", ".join(missing))
            return None
        start, stop, num = spec["start"], spec["stop"], spec["num"]
        scale = spec.get("scale", "linear")
        bad = len(problems)
        for key, v in (("start", start), ("stop", stop)):
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not _finite_or_float(v) \
                    or not math.isfinite(v):
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
    empty = [i for i, row in enumerate(rows) if not row]
    if empty:
        problems.append(f"points[{empty[0]}]: an empty point; each point sets at least one parameter"
                        + (f" ({len(empty)} empty points)" if len(empty) > 1 else ""))
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
            problems.append(f"{where}: unknown name {v!r}{suggest(v, known)}; choose from " + ", ".join(known))
        elif v not in out:
            out.append(v)
    return tuple(out)

"""Computing points (the worker side): simulate, summarise, sample the stored time series.

:func:`_compute_points` is the Dask task of :mod:`.execute`; it never raises for a failing
point, which becomes a record with status ``error`` instead. :func:`_simulate_point` is the one
call of the simulation core.
"""

from __future__ import annotations

import math
import os
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .schema import DEFAULT_QUANTITIES, QUANTITIES
from .spec import config_with

__all__ = ["summarise", "regime", "MIXED_SHARE"]

#: The asperities' peak force, as a share of the film's, above which a run is in mixed lubrication.
MIXED_SHARE = 0.01


def _peak(ds, name, absent=math.nan):
    """``max |ds[name]|`` (NaN ignored), or ``absent`` where the variable is missing or empty."""
    v = np.asarray(ds[name]) if name in ds else np.array([])
    return float(np.nanmax(np.abs(v))) if v.size else absent


def regime(ds) -> str:
    """The lubrication regime of one run's results: ``"contact"``, ``"dry"``, ``"mixed"`` or ``"full film"``.

    ``"contact"``: the collar touched the link (an impact, a compliant contact force, or the run
    ended at a film breakdown or a penetration); else ``"dry"`` without a film; else ``"mixed"``
    where the asperities' peak force exceeds :data:`MIXED_SHARE` of the film's (the rough surfaces
    carry part of the load); else ``"full film"``.
    """
    def peak(name):
        return _peak(ds, name, 0.0)

    impacts = int(ds.attrs.get("impact_count", ds["impact_time"].size if "impact_time" in ds else 0))
    if (impacts > 0 or peak("contact_force") > 0.0
            or str(ds.attrs.get("status", "complete")) in ("film_breakdown", "penetration")):
        return "contact"
    if "film_force" not in ds:
        return "dry"
    asperity = peak("asperity_force")
    return "mixed" if asperity > 0.0 and asperity > MIXED_SHARE * peak("film_force") else "full film"


# ====================================================================== one point
def summarise(ds, quantities=DEFAULT_QUANTITIES, max_impacts=10) -> dict:
    """Summary quantities of one results Dataset (:func:`lubelink.simulate`) or
    :class:`lubelink.results.Results`.

    Returns ``{name: value}`` with ``status``, ``message`` (the run's, then its
    ``contact_warning`` if any: :func:`lubelink.contact.penetration`) and ``wall_time``
    [s] and each of ``quantities`` (see :data:`QUANTITIES` for units):
    floats (NaN when the quantity does not exist for this run, e.g. the film
    pressure of a dry joint), integers, and for ``impact_times`` a list of
    ``max_impacts`` floats.
    """

    def values(name):
        return np.asarray(ds[name]) if name in ds else np.array([])

    def peak(name):
        return _peak(ds, name)

    times, film_min, t = values("impact_time"), values("film_min"), values("time")
    compute = {
        "peak_u2_mid": lambda: peak("u2_mid"),
        "peak_u3_mid": lambda: peak("u3_mid"),
        "peak_axial": lambda: peak("u1"),
        "impact_count": lambda: int(ds.attrs.get("impact_count", len(times))),
        "first_impact_time": lambda: float(times[0]) if len(times) else math.nan,
        "peak_pressure": lambda: peak("pressure"),
        "min_film": lambda: float(np.nanmin(film_min)) if film_min.size else math.nan,
        "peak_film_force": lambda: peak("film_force"),
        "peak_asperity_force": lambda: peak("asperity_force"),
        "peak_contact_force": lambda: peak("contact_force"),
        "regime": lambda: regime(ds),
        "peak_stress": lambda: peak("bending_stress"),
        "peak_film_friction": lambda: peak("film_friction"),
        "mean_film_power_loss": lambda: float(np.mean(values("film_power_loss"))) if values("film_power_loss").size
        else math.nan,
        "peak_crank_pin_force": lambda: float(np.max(np.hypot(values("crank_pin_force_X"),
                                                              values("crank_pin_force_Y"))))
        if values("crank_pin_force_X").size else math.nan,
        "peak_slider_pin_force": lambda: peak("slider_pin_force"),
        "end_time": lambda: float(t[-1]) if t.size else math.nan,
        "nfev": lambda: int(ds.attrs.get("nfev", -1)),
        "impact_times": lambda: [float(t) for t in times[:max_impacts]]
                                + [math.nan] * (max_impacts - min(len(times), max_impacts)),
    }
    message, warning = str(ds.attrs.get("message", "")), str(ds.attrs.get("contact_warning", ""))
    out = {"status": str(ds.attrs.get("status", "complete")),
           "message": f"{message}; {warning}" if message and warning else message or warning,
           "wall_time": float(ds.attrs.get("wall_time", math.nan))}
    for name in quantities:
        out[name] = compute[name]()
    return out


def _empty_record(quantities, max_impacts, status, message, wall_time=math.nan):
    """The record of a point without results (an exception, a lost worker, an invalid point)."""
    out = {"status": status, "message": message, "wall_time": wall_time}
    for name in quantities:
        kind = QUANTITIES[name][2]
        out[name] = (-1 if kind == "i" else [math.nan] * max_impacts if kind == "impacts" else "" if kind == "s"
                     else math.nan)
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
    fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o666)
    try:
        os.write(fd, f"{time.time():.6f} {os.getpid()} {event} {tag} {flat}\n".encode())
    finally:
        os.close(fd)


def _sample(ds, name, n_time, output_step):
    """Series ``name`` on the sweep's common time axis, NaN after an early end."""
    values = np.asarray(ds[name]) if name in ds else None
    out = np.full((n_time,) + (values.shape[1:] if values is not None else ()), np.nan)
    t = np.asarray(ds["time"])
    if values is not None and t.size:
        idx = np.rint(t / output_step).astype(int)
        keep = (idx >= 0) & (idx < n_time)
        out[idx[keep]] = values[keep]
    return out


#: The variables each summary quantity is computed from.
_SOURCES = {"peak_u2_mid": ("u2_mid",), "peak_pressure": ("pressure",), "min_film": ("film_min",),
            "peak_film_force": ("film_force",), "peak_u3_mid": ("u3_mid",), "peak_axial": ("u1",),
            "peak_asperity_force": ("asperity_force",), "peak_contact_force": ("contact_force",),
            "regime": ("film_force", "asperity_force", "contact_force"), "peak_stress": ("bending_stress",),
            "peak_film_friction": ("film_friction",), "mean_film_power_loss": ("film_power_loss",),
            "peak_crank_pin_force": ("crank_pin_force_X", "crank_pin_force_Y"),
            "peak_slider_pin_force": ("slider_pin_force",)}


#: Quantities :func:`reduce_run` takes from the integrator's arrays (no :class:`~lubelink.results.Results`).
FAST = frozenset({"peak_u2_mid", "impact_count", "first_impact_time", "impact_times", "min_film", "peak_film_force",
                  "peak_pressure", "end_time", "nfev"})


def fast_reducible(model, opts) -> bool:
    """Whether :func:`reduce_run` gives ``opts``'s record of a run of ``model``: no time series stored,
    only quantities of :data:`FAST`, the compiled planar model with the 1-D film (or none) and a
    contact law whose run needs no penetration check of the samples (not ``restitution``)."""
    cfg = model.config
    return (not opts.time_series and set(opts.quantities) <= FAST and model.compiled
            and model.params.spatial is None and cfg.contact.law != "restitution"
            and (not cfg.film.enabled or cfg.film.reynolds == "1d"))


def reduce_run(result, quantities, max_impacts):
    """The record of one run (:func:`summarise`'s) straight from its arrays, without the results.

    The same kernels as :func:`lubelink.results.collect` on the same samples, each reduced at
    once: ``max |u2(L/2)|``, the thinnest film, the peak film force and pad pressure; the impacts,
    the end time and the evaluations from the run. Only where :func:`fast_reducible`.
    """
    from .. import film
    from ..beam import deflection
    from ..film.force import film_force_many
    from ..link.model import thinnest_many
    from ..results import PRESSURE_NODES, collar_of

    model = result.model
    cfg, p = model.config, model.params
    L, N = cfg.mechanism.rod_length, model.modes
    t = np.ascontiguousarray(result.t)
    y = np.ascontiguousarray(model.planar_state(np.asarray(result.y)))
    q, q_dot = np.ascontiguousarray(y[:, :N]), np.ascontiguousarray(y[:, N:])
    collar = []

    def kin():
        if not collar:
            collar.extend(collar_of(model, t))
        return collar

    def peak(values):
        return float(np.nanmax(np.abs(values))) if values.size else math.nan

    fm = cfg.film
    times = [i[0] for i in result.impacts]
    compute = {
        "peak_u2_mid": lambda: peak(deflection(q, np.array([0.5 * L]), L)[:, 0]),
        "impact_count": lambda: len(times),
        "first_impact_time": lambda: float(times[0]) if times else math.nan,
        "impact_times": lambda: [float(x) for x in times[:max_impacts]]
                                + [math.nan] * (max_impacts - min(len(times), max_impacts)),
        "min_film": lambda: float(np.nanmin(thinnest_many(kin()[0], y, p)[:, 0])) if t.size and
        (fm.enabled or cfg.contact.law != "none") else math.nan,
        "peak_film_force": lambda: peak(film_force_many(q, q_dot, *kin(), p.film, p.beam.width, p.pad, L))
        if fm.enabled else math.nan,
        "peak_pressure": lambda: _peak_pressure(model, q, q_dot, *kin(), film, PRESSURE_NODES) if fm.enabled
        else math.nan,
        "end_time": lambda: float(t[-1]) if t.size else math.nan,
        "nfev": lambda: int(result.nfev),
    }
    out = {"status": str(result.status), "message": str(result.message), "wall_time": float(result.wall_time)}
    for name in quantities:
        out[name] = compute[name]()
    return out


def _peak_pressure(model, q, q_dot, x_star, V_r, film, nodes):
    """``max |P - p_am|`` [Pa] over the samples and the pad points, on the film's first side."""
    cfg, fm = model.config, model.config.film
    L = cfg.mechanism.rod_length
    X = np.linspace(0.0, fm.pad_length, cfg.output.pad_points)
    tables = film.pressure_points(X, model.modes, L, nodes, fm.grid_points if fm.cavitation == "reynolds" else 0)
    P = film.pad_pressure_many(X, q, q_dot, x_star, V_r, float(model.sides[0]), model.params.film, L, *tables)
    return float(np.nanmax(np.abs(P))) if P.size else math.nan


def _simulate_point(config, opts):
    """The results of one point, only the variables it summarises and stores (or the run itself where
    :func:`reduce_run` makes its record): the sweep's only call of the simulation core. In one thread: a worker's other cores belong to the other workers (a
    second thread for the pad pressure made a 2-worker sweep on 2 cores about 5 % slower). Without
    the configuration's TOML text in its attributes: the store records the sweep."""
    from ..results import collect
    from ..simulate import run

    result = run(config)
    if fast_reducible(result.model, opts):
        return result
    wanted = {v for q in opts.quantities for v in _SOURCES.get(q, ())} | set(opts.time_series)
    return collect(result, variables=wanted, threads=1, config_text=False)


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
        ds = _simulate_point(config, opts)
        if hasattr(ds, "model"):  # a run whose record comes from its arrays
            record = reduce_run(ds, opts.quantities, opts.max_impacts)
            ds = None
        else:
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


def _compute_points(flats, overrides, base, opts, trace=None):
    """Worker task: several points in a row, ``([(flat, record, series), ...], seconds)``.

    A point comes as its overrides of the sweep's ``base`` configuration (validated by the client),
    not as a configuration: a task then carries one configuration, not one a point, which the
    client pickles, the scheduler unpickles and pickles again and the worker unpickles.
    """
    t0 = time.perf_counter()
    out = [(flat, *_compute_point(flat, config_with(base, o), opts, trace)) for flat, o in zip(flats, overrides)]
    return out, time.perf_counter() - t0


def _describe(exc):
    import traceback

    tb = traceback.extract_tb(exc.__traceback__)
    where = f" (at {Path(tb[-1].filename).name}:{tb[-1].lineno})" if tb else ""
    return f"{type(exc).__name__}: {exc}{where}"

"""Results as an :class:`xarray.Dataset`: the variable registry and the assembly of a run's results.

Every variable is declared once in :data:`VARIABLES` (dimensions, units, long name): the Dataset,
the sweep store and the plots read it there. :func:`to_dataset` computes the film force,
pressure and thinnest film of the samples with the functions the right-hand side and the gap
used, batched in compiled code. The dataset's attrs hold the run status, solver statistics,
versions and the full configuration as TOML text, enough to re-run it (:func:`config_of`).
Files: :mod:`lubelink.netcdf` (its functions are also found here).
"""

from __future__ import annotations

import os
import platform
import time
from dataclasses import dataclass, field
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from ._files import atomic_path  # noqa: F401 - found here too
from .netcdf import (EXISTS, FORMAT_VERSION, NETCDF_SUFFIXES, ResultsFileError, config_of, file_attrs,
                     library_versions, load, output_problem, save, write)
from .variables import CONVENTIONS, VARIABLE_ATTRS, VARIABLES, Variable, entry as _entry, variable  # noqa: F401


__all__ = ["Run", "FORMAT_VERSION", "VARIABLES", "Variable", "Results", "collect", "dataset", "to_dataset", "write", "save", "load",
           "config_of", "atomic_path", "ResultsFileError", "versions", "output_problem", "NETCDF_SUFFIXES",
           "CONVENTIONS", "VARIABLE_ATTRS", "file_attrs", "library_versions", "EXISTS"]


@dataclass
class Run:
    """Raw outcome of :func:`lubelink.simulate.run`: samples, impacts, status and statistics."""

    model: object
    t: np.ndarray
    y: np.ndarray
    status: str = "complete"
    message: str = "reached solver.t_end"
    impacts: list = field(default_factory=list)
    nfev: int = 0
    nsteps: int = 0
    wall_time: float = 0.0
    event_time: float = np.nan
    method: str = ""
    method_note: str = ""
    contacts: list = field(default_factory=list)
    phase_side: np.ndarray | None = None
    phase_v: np.ndarray | None = None
    phase_point: np.ndarray | None = None
    section: object = None  # the lubelink.link.section.Section run() was given, if any
    coupling: object = None  # drive.coupling = "two-way": the relaxation's lubelink.coupling.Coupling

    @property
    def complete(self) -> bool:
        return self.status == "complete"


#: Gauss-Legendre nodes per piece between two ``X`` of the pad pressure. The film is a sum of
#: sines of wavelength ``2 L / N`` much longer than a piece, so 4 nodes (exact to degree 7) leave
#: the pressure within rounding (1e-8 of its peak) of 16 nodes on the paper's runs.
PRESSURE_NODES = 4


def collar_of(model, t):
    """``(x_star, V_r)`` of the samples ``t``: the collar's position [m] and relative speed [m/s]."""
    from .link.kinematics import collar_many

    if model.compiled and model.params.spatial is None and model.motion.table() is not None:
        return collar_many(np.ascontiguousarray(t), model.params.motion)
    kin = model.motion(t)
    return (np.ascontiguousarray(np.broadcast_to(kin.x_star, t.shape), dtype=float),
            np.ascontiguousarray(np.broadcast_to(kin.V_r, t.shape), dtype=float))


@lru_cache(maxsize=1)
def versions():
    """``(lubelink version, the versions string of the attrs)``, looked up once per process."""
    import importlib.metadata

    def version(package):
        try:
            return importlib.metadata.version(package)
        except importlib.metadata.PackageNotFoundError:
            return "unknown"

    libs = ", ".join(f"{name} {version(name)}" for name in ("numpy", "scipy", "numba", "xarray", "netCDF4"))
    return version("lubelink"), f"python {platform.python_version()}, {libs}"


def _select(kernel, compiled):
    return kernel if compiled else kernel.py_func


_POOL = {}


def _pool():
    """One worker thread for a compiled kernel beside the main thread, or None on a single core.

    Kept per process: a forked child inherits the executor but not its thread.
    """
    pid = os.getpid()
    if pid not in _POOL:
        from ._jit import cores

        if cores() < 2:
            _POOL[pid] = None
        else:
            from concurrent.futures import ThreadPoolExecutor

            _POOL.clear()
            _POOL[pid] = ThreadPoolExecutor(max_workers=1, thread_name_prefix="lubelink-results")
    return _POOL[pid]


def _beside(compiled, func, *args):
    """``func(*args)`` in the worker thread when ``func`` is a compiled kernel (it releases the GIL)
    and there are two cores, else at once; returns a function giving the value."""
    pool = _pool() if compiled else None
    if pool is None:
        value = func(*args)
        return lambda: value
    return pool.submit(func, *args).result


class Results(NamedTuple):
    """A run's results before they become an :class:`xarray.Dataset` or a file.

    ``data_vars`` and ``coords`` map names to ``(dims, array, attrs)``, ``attrs`` are the
    global attributes: what :func:`to_dataset` wraps (xarray) and :func:`write` writes (netCDF4
    directly, without importing xarray).
    """

    data_vars: dict
    coords: dict
    attrs: dict

    def __getitem__(self, name):
        """The array of variable or coordinate ``name``."""
        entry = self.data_vars.get(name) or self.coords[name]
        return entry[1]

    def __contains__(self, name):
        return name in self.data_vars or name in self.coords


def to_dataset(result):
    """Sample a :class:`~lubelink.simulate.Run` into the results :class:`xarray.Dataset`."""
    return dataset(collect(result))


def dataset(results: Results):
    """The :class:`xarray.Dataset` of ``results``.

    Assembled from its variables and indexes without the constructor's alignment and merge, which
    find nothing to do here (every coordinate is a 1-D index of its own dimension, every variable
    lies on those dimensions) and cost about as much as the rest of the results (0.5 of 0.9 ms on
    ``paper``). Each coordinate's variable is made by its index (``Index.create_variables``,
    xarray's API for custom indexes), so its pandas.Index is built once, not twice (0.83 -> 0.55 ms
    on ``paper-dry``). ``xarray.Dataset._construct_direct`` is xarray's own shortcut for this; should a
    release drop it, the constructor takes over (``tests/test_results.py`` checks both give the
    same Dataset).
    """
    import xarray as xr

    direct = getattr(xr.Dataset, "_construct_direct", None)
    if direct is not None:
        try:
            import pandas as pd
            from xarray.core.indexes import PandasIndex

            variables, indexes = {}, {}
            for name, (dims, data, attrs) in results.coords.items():
                if dims != (name,):  # a coordinate beside an index (crank_angle beside time): no index of its own
                    variables[name] = xr.Variable(dims, data, attrs, fastpath=True)
                    continue
                # the pandas.Index named already and its dtype given (fastpath): the index neither
                # re-cast nor copied to name it (4 coordinates 0.36 -> 0.23 ms); from a NumPy array 1.5x
                index = pd.Index(data, copy=False, name=name)
                indexes[name] = PandasIndex(index, name, coord_dtype=index.dtype, fastpath=True)
                variables[name] = indexes[name].create_variables()[name]  # on the index's own pandas.Index
                variables[name].attrs = attrs
            for name, (dims, data, attrs) in results.data_vars.items():
                variables[name] = xr.Variable(dims, data, attrs, fastpath=True)  # data: NumPy arrays already
            return direct(variables, set(results.coords), attrs=dict(results.attrs), indexes=indexes)
        except (ImportError, TypeError, ValueError):  # another xarray: the constructor below
            pass
    return xr.Dataset(results.data_vars, coords=results.coords, attrs=results.attrs)


def collect(result, variables=None, *, threads=2, config_text=True) -> Results:
    """Sample a :class:`~lubelink.simulate.Run` into :class:`Results`: the variables of :data:`VARIABLES`.

    ``variables``: names to compute (default all); the coordinates, ``q``, ``q_dot``, ``x_star``,
    ``V_r``, ``omega_n`` and the impacts always come (they cost nothing). A sweep point asks only
    for what it summarises and stores. ``threads``: 2 computes the pad pressure in a second thread
    where there are two cores; 1 in this one (a sweep's worker, which its cluster gives one thread
    and other workers the other cores). ``config_text``: False leaves ``attrs["config"]`` empty, for a
    caller that keeps the configuration itself (a sweep point, whose store holds the sweep; the TOML
    text of a configuration seen for the first time costs 0.4 ms).
    """
    from . import beam, contact, derived, film
    from .config import to_toml
    from .link.model import thinnest_many

    want = VARIABLES.keys() if variables is None else set(variables)
    if any(name in want for name in derived.REACTIONS):
        want = set(want) | {"film_force", "film_friction", "asperity_force", "contact_force"}
    model = result.model
    cfg = model.config
    p = model.params
    L = cfg.mechanism.rod_length
    N = model.modes
    t = np.ascontiguousarray(result.t)
    y_state = np.asarray(result.y)
    y = np.ascontiguousarray(model.planar_state(y_state))  # the in-plane block of the spatial model
    q, q_dot = np.ascontiguousarray(y[:, :N]), np.ascontiguousarray(y[:, N:])
    x = np.linspace(0.0, L, cfg.output.x_points)
    compiled = model.compiled
    x_star, V_r = collar_of(model, t)
    data = {
        "q": _entry("q", q),
        "q_dot": _entry("q_dot", q_dot),
        "x_star": _entry("x_star", x_star),
        "V_r": _entry("V_r", V_r),
        "omega_n": _entry("omega_n", model.omega_n),
    }
    if "u2" in want:
        data["u2"] = _entry("u2", beam.deflection(q, x, L))
    if "u2_mid" in want:
        data["u2_mid"] = _entry("u2_mid", beam.deflection(q, np.array([0.5 * L]), L)[:, 0])
    if model.params.spatial is not None:
        u1, _, u3 = model.deflections(y_state, np.r_[x, 0.5 * L])
        for name, value in (("u1", u1[:, :-1]), ("u3", u3[:, :-1]), ("u3_mid", u3[:, -1])):
            if name in want:
                data[name] = _entry(name, value)
        data["omega_spatial"] = _entry("omega_spatial", np.reshape(model.state_frequencies, (3, N)))
    coords = {"time": _entry("time", t), "x": _entry("x", x), "mode": _entry("mode", np.arange(1, N + 1))}
    if "omega_spatial" in data:
        coords["direction"] = _entry("direction", np.arange(1, 4))
    fm = cfg.film
    later = {}
    if "bending_stress" in want:  # beside the others, as the pressure (NumPy and modal_sum release the GIL)
        later["bending_stress"] = _beside(model.compiled and threads > 1, derived.stress_field, result, q, y_state, x)
    if fm.enabled:
        X = np.linspace(0.0, fm.pad_length, cfg.output.pad_points)
        coords["x_pad"] = _entry("x_pad", X)
        if fm.reynolds == "1d":
            tables = film.pressure_points(X, N, L, PRESSURE_NODES,
                                          fm.grid_points if fm.cavitation == "reynolds" else 0)
            pressure = _select(film.pad_pressure_many, compiled)
            for side, name in zip(model.sides, ("pressure", "pressure_lower")):
                if name in want:  # the costliest series: computed beside the others
                    later[name] = _beside(compiled and threads > 1, pressure, X, q, q_dot, x_star, V_r,
                                          float(side), p.film, L, *tables)
        else:  # the finite-width film: its centre line Z = 0
            pressure = _select(film.centre_pressure_many, compiled)
            for side, name in zip(model.sides, ("pressure", "pressure_lower")):
                if name in want:
                    data[name] = _entry(name, pressure(X, q, q_dot, x_star, V_r, float(side), p.film, p.beam.width,
                                                       L, p.pad.grid_trig, p.pad.width))
        if fm.reynolds == "1d" and ("film_friction" in want or "film_power_loss" in want):
            later["film_losses"] = _beside(compiled and threads > 1, derived.film_losses, model, q, q_dot, x_star, V_r)
        if "film_force" in want:
            force = _select(film.film_force_many, compiled)(q, q_dot, x_star, V_r, p.film, p.beam.width, p.pad, L)
            data["film_force"] = _entry("film_force", force)
    film_min = thinnest = None  # (the restitution law's penetration check needs it even when it is not stored)
    if (fm.enabled or cfg.contact.law != "none") and ("film_min" in want or cfg.contact.law == "restitution"):
        thinnest = _select(thinnest_many, compiled)(x_star, y, p)  # (xi, x_c): the film and where it is thinnest
        film_min = thinnest[:, 0]
        if "film_min" in want:
            data["film_min"] = _entry("film_min", film_min)
    if fm.roughness > 0.0 and "asperity_force" in want:
        from .film.asperity import asperity_force_many

        data["asperity_force"] = _entry("asperity_force", _select(asperity_force_many, compiled)(
            np.ascontiguousarray(q), x_star, p.film, p.beam.width, p.pad, L))
    if model.params.spatial is not None and fm.faces == "u2+u3":
        data.update(derived.u3_faces(model, want, y_state, x_star, V_r))
    if cfg.contact.law != "none":
        side = result.phase_side if result.phase_side is not None else np.zeros(t.size)
        data["contact_phase"] = _entry("contact_phase", (side != 0).astype(np.int8),
                                       flag_values=np.array([0, 1], dtype=np.int8), flag_meanings="free contact")
        if "contact_force" in want:
            data["contact_force"] = _entry("contact_force", derived.contact_force(result, model, t, y_state, side))
    imp = result.impacts
    coords["impact"] = _entry("impact", np.arange(len(imp)))
    data["impact_time"] = _entry("impact_time", [i[0] for i in imp])
    data["impact_position"] = _entry("impact_position", [i[1] for i in imp])
    data["impact_velocity"] = _entry("impact_velocity", [i[2] for i in imp])
    data["impact_velocity_after"] = _entry("impact_velocity_after", [i[3] for i in imp])
    codes = np.array([i[4] for i in imp], dtype=int)
    data["impact_side"] = _entry("impact_side", np.sign(codes))  # the spatial model's codes +-2: the u3 faces
    if model.params.spatial is not None and fm.faces == "u2+u3":
        data["impact_face"] = _entry("impact_face", 2 + (np.abs(codes) == 2))
    energy_note, residual, relative = derived.energy_budget(result, want, t, np.ascontiguousarray(y_state, dtype=float), data)
    losses = None
    for name, value in later.items():
        if name == "film_losses":
            losses = value()
            friction, loss, _ = losses
            for name, series in (("film_friction", friction.sum(axis=0)), ("film_power_loss", loss)):
                if name in want:
                    data[name] = _entry(name, series)
        else:
            data[name] = _entry(name, value())
    if any(name in want for name in derived.REACTIONS) and not derived.reactions_apply(model):
        for name, value in derived.joint_reactions(result, t, y, losses if fm.enabled else None, data,
                                                      thinnest).items():
            if name in want:
                data[name] = _entry(name, value)
    crank = getattr(model.motion, "crank", None)  # a driven crank (lubelink.link.drive): its integrated motion
    if crank is not None:
        phi, phi_dot, _, torque = crank(t)
        coords["crank_angle"] = _entry("crank_angle", phi)
        data["crank_speed"] = _entry("crank_speed", phi_dot)
        data["motor_torque"] = _entry("motor_torque", torque)
    period = derived.crank_period(model)
    if period is not None:
        coords["crank_angle"] = _entry("crank_angle", cfg.mechanism.crank_speed * t)
        lost = (data["impact_time"][1], data["impact_dissipation"][1]) if "impact_dissipation" in data else ((), ())
        stats = derived.revolutions(t, period, data, lost)
        coords["revolution"] = _entry("revolution", np.arange(1, stats["revolution_start"].size + 1))
        for name, value in stats.items():
            if name == "revolution_start" or name in want:
                data[name] = _entry(name, value)
    data = {name: data[name] for name in VARIABLES if name in data}
    warning = ""
    if cfg.contact.law == "restitution":
        side = result.phase_side if result.phase_side is not None else np.zeros(t.size)
        for film_min in (film_min, data["film_min_u3"][1] if "film_min_u3" in data else None):
            if film_min is not None and not warning:
                warning = contact.penetration(t, film_min, side, cfg.contact.min_film)
    if cfg.contact.law == "restitution" and N > 1 and not warning:
        warning = (f"the restitution law is the paper's law for one mode: with beam.modes = {N} its velocity jump "
                   "scales like 2/N and the results after an impact do not converge as N grows (docs/model.md "
                   "5.3); contact.law = 'compliant' converges")
    status, message = result.status, result.message
    if warning and status == "complete" and "went through" in warning:  # the samples show the link through the face: not a complete run
        status, message = "penetration", warning
    version, libs = versions()
    attrs = {
        "Conventions": CONVENTIONS,
        "title": "lubelink simulation of a flexible link with a lubricated prismatic joint",
        "source": f"lubelink {version}",
        "references": "Marghitu & Guran, The Dynamics of a Flexible Beam With a Lubricated Prismatic Kinematic "
                      "Pair, J. Vibration and Acoustics; the equations as lubelink implements them: docs/model.md "
                      "sections 1-7, its corrections to the paper: section 8, its parameter choices: section 9",
        "lubelink_version": version,
        "lubelink_format": FORMAT_VERSION,
        "versions": libs,
        "config": to_toml(cfg) if config_text else "",
        "status": status,
        "complete": int(status == "complete"),
        "message": message,
        "solver_method": result.method or cfg.solver.method,
        "solver_note": getattr(result, "method_note", ""),
        "backend": model.backend,
        "backend_note": model.backend_note,
        "nfev": result.nfev,
        "nsteps": result.nsteps,
        "impact_count": len(imp),
        "wall_time": result.wall_time,
        "wall_time_units": "s",
        "contact_warning": warning,
        "energy_residual_max": residual,
        "energy_residual_units": "J",
        "energy_residual_relative": relative,
        "energy_note": energy_note,
        "stress_utilisation": _utilisation(data, cfg.beam.yield_strength),
        "created": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    }
    if result.coupling is not None:  # the two-way relaxation (lubelink.coupling)
        attrs.update(coupling_runs=result.coupling.runs, coupling_change=result.coupling.changes[-1],
                     coupling_change_units="rad s-1", coupling_contraction=result.coupling.contraction)
    return Results(data, coords, attrs)


def _utilisation(data, yield_strength):
    """Peak bending stress over the yield strength [-] (NaN: no yield strength given, or no stress computed)."""
    if "bending_stress" not in data or not np.isfinite(yield_strength) or not np.size(data["bending_stress"][1]):
        return np.nan
    return float(np.max(data["bending_stress"][1])) / yield_strength

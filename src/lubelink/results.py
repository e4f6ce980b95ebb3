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

    @property
    def complete(self) -> bool:
        return self.status == "complete"


class Variable(NamedTuple):
    """A result variable: dimensions, units (UDUNITS) and long name."""

    dims: tuple
    units: str
    long_name: str


#: Every variable and coordinate of a results Dataset.
VARIABLES = {
    "time": Variable(("time",), "s", "time"),
    "x": Variable(("x",), "m", "position along the link from the crank pin O"),
    "mode": Variable(("mode",), "1", "mode number"),
    "direction": Variable(("direction",), "1", "displacement direction (spatial model): 1 axial u1, 2 in-plane u2, "
                                               "3 out-of-plane u3"),
    "X": Variable(("X",), "m", "position along the pad from its start"),
    "impact": Variable(("impact",), "1", "impact number"),
    "q": Variable(("time", "mode"), "m", "modal coordinate"),
    "q_dot": Variable(("time", "mode"), "m s-1", "modal velocity"),
    "u2": Variable(("time", "x"), "m", "transverse deflection"),
    "u2_mid": Variable(("time",), "m", "midpoint deflection"),
    "u1": Variable(("time", "x"), "m", "axial displacement (spatial model)"),
    "u3": Variable(("time", "x"), "m", "out-of-plane deflection (spatial model)"),
    "u3_mid": Variable(("time",), "m", "midpoint out-of-plane deflection (spatial model)"),
    "bending_stress": Variable(("time", "x"), "Pa", "largest bending stress in the section (spatial: at a corner)"),
    "x_star": Variable(("time",), "m", "collar position along the link"),
    "V_r": Variable(("time",), "m s-1", "collar velocity relative to the link"),
    "omega_n": Variable(("mode",), "rad s-1", "natural circular frequency"),
    "omega_spatial": Variable(("direction", "mode"), "rad s-1", "natural circular frequencies of the axial, "
                                                               "in-plane and out-of-plane modes (spatial model)"),
    "film_min": Variable(("time",), "m", "thinnest film on the pad (spatial model: of the u2 faces)"),
    "pressure": Variable(("time", "X"), "Pa", "gauge film pressure P - p_am (film at H/2 - u2, the paper's; "
                         "on the centre line Z = 0 with film.reynolds '2d' or 'short')"),
    "pressure_lower": Variable(("time", "X"), "Pa", "gauge film pressure of the film at H/2 + u2"),
    "film_force": Variable(("time",), "N", "resultant film force on the link along +j"),
    "asperity_force": Variable(("time",), "N", "resultant asperity contact force on the link along +j "
                                                "(Greenwood-Tripp, mixed lubrication)"),
    "film_min_u3": Variable(("time",), "m", "thinnest film of the pair on the u3 faces (spatial model, film.faces "
                                          "u2+u3)"),
    "film_force_u3": Variable(("time",), "N", "resultant film force of the pair on the u3 faces on the link along +e3 "
                                              "(spatial model, film.faces u2+u3)"),
    "asperity_force_u3": Variable(("time",), "N", "resultant asperity contact force of the u3 faces along +e3 "
                                                  "(spatial model, film.faces u2+u3)"),
    "contact_phase": Variable(("time",), "1", "contact phase of the sample: 0 free, 1 in contact with the collar"),
    "contact_force": Variable(("time",), "N", "contact force of the collar on the link, pushing it from the collar "
                                              "face (sustained or compliant contact)"),
    "energy": Variable(("time",), "J", "vibration energy of the link relative to its rigid motion (kinetic plus strain)"),
    "work_rigid": Variable(("time",), "J", "work done on the vibration by the rigid motion's inertial loads and gravity"),
    "work_damping": Variable(("time",), "J", "work of the structural damping (beam.damping_ratio)"),
    "work_film": Variable(("time",), "J", "work of the film force on the link"),
    "work_asperity": Variable(("time",), "J", "work of the asperity contact force on the link"),
    "work_reaction": Variable(("time",), "J", "work of the collar's joint reaction on the link"),
    "work_contact": Variable(("time",), "J", "work of the contact force (compliant, or a sustained contact's)"),
    "work_impacts": Variable(("time",), "J", "change of the vibration energy in the restitution impacts so far"),
    "energy_residual": Variable(("time",), "J", "energy - energy(0) minus the sum of the works: the balance's "
                                                "residual (integration and sampling error)"),
    "impact_time": Variable(("impact",), "s", "impact time (contact start)"),
    "impact_position": Variable(("impact",), "m", "contact point on the link"),
    "impact_velocity": Variable(("impact",), "m s-1", "normal approach velocity before impact (positive closing)"),
    "impact_velocity_after": Variable(("impact",), "m s-1",
                                      "normal approach velocity after impact (negative opening)"),
    "impact_side": Variable(("impact",), "1", "film side of the contact: 1 the film H/2 - u2 (the link's +j side), "
                                              "-1 the film H/2 + u2 (its -j side)"),
    "impact_face": Variable(("impact",), "1", "face pair of the contact (spatial model, film.faces u2+u3): 2 the u2 "
                                              "faces, 3 the u3 faces (impact_side then the film H/2 -+ u3)"),
    "impact_energy_change": Variable(("impact",), "J", "change of the link's vibration energy in the impact"),
    "impact_dissipation": Variable(("impact",), "J", "energy lost at the contact point, in the frame of the collar "
                                                    "face (>= 0)"),
    "impact_collar_work": Variable(("impact",), "J", "work of the collar's impulse on the link: energy change plus "
                                                    "dissipation"),
}

#: Attributes beyond units and long name, by variable: the CF flag attributes of the flag variables.
VARIABLE_ATTRS = {
    "impact_side": {"flag_values": np.array([1, -1], dtype=np.int64),
                    "flag_meanings": "positive_j_side negative_j_side"},
    "impact_face": {"flag_values": np.array([2, 3], dtype=np.int64), "flag_meanings": "u2_faces u3_faces"},
}

#: The CF conventions the results files follow (global attribute ``Conventions``).
CONVENTIONS = "CF-1.10"


#: Gauss-Legendre nodes per piece between two ``X`` of the pad pressure. The film is a sum of
#: sines of wavelength ``2 L / N`` much longer than a piece, so 4 nodes (exact to degree 7) leave
#: the pressure within rounding (1e-8 of its peak) of 16 nodes on the paper's runs.
PRESSURE_NODES = 4


def variable(dims, data, units, long_name, **attrs):
    """``(dims, data, attrs)`` tuple for :class:`xarray.Dataset` construction."""
    return dims, np.asarray(data), {"units": units, "long_name": long_name, **attrs}


def _entry(name, data, **attrs):
    v = VARIABLES[name]
    return variable(v.dims, data, v.units, v.long_name, **VARIABLE_ATTRS.get(name, {}), **attrs)


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
    if direct is not None and all(dims == (name,) for name, (dims, _, _) in results.coords.items()):
        try:
            import pandas as pd
            from xarray.core.indexes import PandasIndex

            variables, indexes = {}, {}
            for name, (dims, data, attrs) in results.coords.items():
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
    from . import beam, contact, film
    from .config import to_toml
    from .link.kinematics import collar_many
    from .link.model import thinnest_many

    want = VARIABLES.keys() if variables is None else set(variables)
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
    if compiled and model.params.spatial is None and model.motion.table() is not None:
        x_star, V_r = collar_many(t, p.motion)
    else:
        kin = model.motion(t)
        x_star = np.ascontiguousarray(np.broadcast_to(kin.x_star, t.shape), dtype=float)
        V_r = np.ascontiguousarray(np.broadcast_to(kin.V_r, t.shape), dtype=float)
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
        later["bending_stress"] = _beside(model.compiled and threads > 1, _bending_stress, result, q, y_state, x)
    if fm.enabled:
        X = np.linspace(0.0, fm.pad_length, cfg.output.pad_points)
        coords["X"] = _entry("X", X)
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
                                                       L, p.pad.grid_trig, p.pad.zsin))
        if "film_force" in want:
            force = _select(film.film_force_many, compiled)(q, q_dot, x_star, V_r, p.film, p.beam.width, p.pad, L)
            data["film_force"] = _entry("film_force", force)
    film_min = None  # (the restitution law's penetration check needs it even when it is not stored)
    if (fm.enabled or cfg.contact.law != "none") and ("film_min" in want or cfg.contact.law == "restitution"):
        film_min = _select(thinnest_many, compiled)(x_star, y, p)
        if "film_min" in want:
            data["film_min"] = _entry("film_min", film_min)
    if fm.roughness > 0.0 and "asperity_force" in want:
        from .film.asperity import asperity_force_many

        data["asperity_force"] = _entry("asperity_force", _select(asperity_force_many, compiled)(
            np.ascontiguousarray(q), x_star, p.film, p.beam.width, p.pad, L))
    if model.params.spatial is not None and fm.faces == "u2+u3":
        data.update(_u3_faces(model, want, y_state, x_star, V_r))
    if cfg.contact.law != "none":
        side = result.phase_side if result.phase_side is not None else np.zeros(t.size)
        data["contact_phase"] = _entry("contact_phase", (side != 0).astype(np.int8),
                                       flag_values=np.array([0, 1], dtype=np.int8), flag_meanings="free contact")
        if "contact_force" in want:
            data["contact_force"] = _entry("contact_force", _contact_force(result, model, t, y_state, side))
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
    energy_note, residual, relative = _energy(result, want, t, np.ascontiguousarray(y_state, dtype=float), data)
    for name, value in later.items():
        data[name] = _entry(name, value())
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
        "created": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    }
    return Results(data, coords, attrs)


def _bending_stress(result, q, y_state, x):
    """:func:`~lubelink.link.section.bending_stress` of the run's section (spatial: both directions, a corner) [Pa]."""
    from .link.section import bending_stress, taper

    model, cfg = result.model, result.model.config
    E, L = cfg.beam.youngs_modulus, cfg.mechanism.rod_length
    sec = result.section or taper(cfg.beam, L)
    stress = bending_stress(sec, E, q, x, L)
    if model.params.spatial is not None:
        q3 = np.asarray(model.block_state(y_state, 2))[:, :model.modes]
        stress += bending_stress(sec, E, q3, x, L, "second_moment_y")
    return stress


_ENERGY = ("energy", "work_rigid", "work_damping", "work_film", "work_asperity", "work_reaction", "work_contact",
           "work_impacts", "energy_residual", "impact_energy_change", "impact_dissipation", "impact_collar_work")


def _energy(result, want, t, y, data):
    """Add the energy budget's variables (:mod:`lubelink.energy`) to ``data``; return ``(note, largest residual [J],
    relative to the largest energy or work)``."""
    from . import energy

    if not any(name in want for name in _ENERGY):
        return "not asked for", np.nan, np.nan
    side = result.phase_side if result.phase_side is not None else np.zeros(t.size)
    series, (change, loss, collar), residual = energy.of_run(result, t, y, side)
    for name, value in series.items():
        if name in want:
            data[name] = _entry(name, value)
    for name, value in (("impact_energy_change", change), ("impact_dissipation", loss),
                        ("impact_collar_work", collar)):
        if name in want and result.model.config.contact.law == "restitution":
            data[name] = _entry(name, value)
    scale = max(float(np.max(np.abs(value))) for name, value in series.items() if name != "energy_residual")
    return ("works by Simpson's rule over the samples and the impacts; the residual is the integration error and "
            "the quadrature error of the sampling (refine solver.output_step if it matters)",
            residual, residual / scale if scale > 0.0 else 0.0)


def _u3_faces(model, want, y_state, x_star, V_r):
    """The variables of the spatial model's film pair on the ``u3`` faces: the planar batched kernels on the ``q3`` block."""
    from . import film
    from .film.asperity import asperity_force_many
    from .link.model import thinnest_many

    p, N, cfg = model.params, model.modes, model.config
    L, compiled = cfg.mechanism.rod_length, model.compiled
    y3 = np.ascontiguousarray(model.block_state(y_state, 2))
    q3, q3_t = np.ascontiguousarray(y3[:, :N]), np.ascontiguousarray(y3[:, N:])
    out = {}
    if (cfg.film.enabled or cfg.contact.law != "none") and "film_min_u3" in want:
        out["film_min_u3"] = _entry("film_min_u3", _select(thinnest_many, compiled)(x_star, y3, p))
    if cfg.film.enabled and "film_force_u3" in want:
        out["film_force_u3"] = _entry("film_force_u3", _select(film.film_force_many, compiled)(
            q3, q3_t, x_star, V_r, p.film, p.beam.height, p.pad, L))
    if cfg.film.roughness > 0.0 and "asperity_force_u3" in want:
        out["asperity_force_u3"] = _entry("asperity_force_u3", _select(asperity_force_many, compiled)(
            q3, x_star, p.film, p.beam.height, p.pad, L))
    return out


def _contact_force(result, model, t, y, side):
    """Contact force at every sample [N]: the sustained contact's multiplier or the compliant force, 0 when free."""
    force = np.zeros(t.size)
    inside = np.flatnonzero(side != 0)
    if inside.size == 0:
        return force
    if model.config.contact.law == "restitution":
        force[inside] = model.sustained_force(t[inside], y[inside], side[inside], result.phase_point[inside])
    else:
        force[inside] = model.compliant_loads(t[inside], y[inside], side[inside], result.phase_v[inside])[0]
    return force

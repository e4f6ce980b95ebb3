"""Response curves: the branch of periodic responses over a parameter, and its results.

:func:`find_branch` follows the periodic response of a configuration as ``section.key`` (the
crank speed by default) goes from its value to ``stop`` (:func:`~.arclength.continue_branch`
on the :class:`~.problem.Family` of period maps), summarising each orbit as it is accepted;
:func:`branch_results` lays the branch out as :class:`~lubelink.results.Results` (written by
:func:`lubelink.netcdf.write`); :func:`continuation` returns it as an :class:`xarray.Dataset`.
"""

from __future__ import annotations

import time

import numpy as np

from ..results import Variable, variable
from . import floquet
from .arclength import continue_branch
from .problem import Family

__all__ = ["find_branch", "branch_results", "continuation", "BRANCH_VARIABLES", "SPATIAL_BRANCH_VARIABLES",
           "BIFURCATION_CODES"]

#: Every variable and coordinate of a branch Dataset (``point``: the orbits along the branch).
BRANCH_VARIABLES = {
    "point": Variable(("point",), "1", "orbit number along the branch"),
    "mode": Variable(("mode",), "1", "mode number"),
    "multiplier": Variable(("multiplier",), "1", "Floquet multiplier, largest modulus first"),
    "bifurcation": Variable(("bifurcation",), "1", "bifurcation number"),
    "parameter": Variable(("point",), "", "the continuation parameter"),
    "period": Variable(("point",), "s", "period of the response"),
    "q0": Variable(("point", "mode"), "m", "modal coordinate of the periodic state at t = 0"),
    "q_dot0": Variable(("point", "mode"), "m s-1", "modal velocity of the periodic state at t = 0"),
    "peak_u2_mid": Variable(("point",), "m", "peak absolute midpoint deflection over the period, max |u2_mid|"),
    "peak_q": Variable(("point", "mode"), "m", "peak absolute modal coordinate over the period"),
    "min_film": Variable(("point",), "m", "thinnest film on the pad over the period (NaN: gap not monitored)"),
    "impact_count": Variable(("point",), "1", "contact events (impacts) in the period"),
    "floquet_modulus": Variable(("point", "multiplier"), "1", "modulus of the Floquet multiplier"),
    "floquet_argument": Variable(("point", "multiplier"), "rad", "argument of the Floquet multiplier"),
    "floquet_error": Variable(("point", "multiplier"), "1", "accuracy estimate of the Floquet multiplier"),
    "max_modulus": Variable(("point",), "1", "largest modulus of the Floquet multipliers"),
    "stable": Variable(("point",), "1", "1 if every Floquet multiplier is inside the unit circle by more than its "
                                        "accuracy estimate, else 0"),
    "omega_n": Variable(("point", "mode"), "rad s-1", "natural circular frequency"),
    "arclength": Variable(("point",), "1", "scaled arclength along the branch"),
    "iterations": Variable(("point",), "1", "Newton steps of the corrector"),
    "residual": Variable(("point",), "1", "scaled residual max |y(T) - y0| / scale"),
    "bifurcation_type": Variable(("bifurcation",), "1", "kind of bifurcation"),
    "bifurcation_parameter": Variable(("bifurcation",), "", "estimated parameter of the bifurcation"),
    "bifurcation_point": Variable(("bifurcation",), "1", "the first point after the bifurcation"),
    "bifurcation_modulus": Variable(("bifurcation",), "1", "modulus of the crossing multiplier"),
    "bifurcation_argument": Variable(("bifurcation",), "rad", "argument of the crossing multiplier"),
}

#: What a branch of the spatial model adds (``beam.model = "spatial"``; ``q0``, ``q_dot0``,
#: ``peak_q``, ``omega_n`` are the in-plane modes, as in every results Dataset).
SPATIAL_BRANCH_VARIABLES = {
    "q1_0": Variable(("point", "mode"), "m", "axial modal coordinate of the periodic state at t = 0"),
    "q1_dot0": Variable(("point", "mode"), "m s-1", "axial modal velocity of the periodic state at t = 0"),
    "q3_0": Variable(("point", "mode"), "m", "out-of-plane modal coordinate of the periodic state at t = 0"),
    "q3_dot0": Variable(("point", "mode"), "m s-1", "out-of-plane modal velocity of the periodic state at t = 0"),
    "peak_u1_mid": Variable(("point",), "m", "peak absolute axial displacement at the midpoint over the period"),
    "peak_u3_mid": Variable(("point",), "m", "peak absolute out-of-plane midpoint deflection over the period"),
    "omega_n1": Variable(("point", "mode"), "rad s-1", "natural circular frequency of the axial modes"),
    "omega_n3": Variable(("point", "mode"), "rad s-1", "natural circular frequency of the out-of-plane modes"),
}

#: ``bifurcation_type`` codes (CF ``flag_values``/``flag_meanings``).
BIFURCATION_CODES = {kind: i for i, kind in enumerate(floquet.KINDS)}
_FLAG_MEANINGS = ("fold branch_point_plus_one period_doubling_minus_one neimark_sacker_complex_pair "
                  "resonance_plus_one_on_circle")


def _summary(pmap, value):
    """Per-orbit quantities from the samples of the period map's run (and the spatial model's other directions)."""
    from ..beam import deflection
    from ..link.model import thinnest_many

    model = pmap.model
    N = model.modes
    t, y_state = value.info["t"], np.ascontiguousarray(value.info["y"])
    y = np.ascontiguousarray(model.planar_state(y_state))  # the in-plane block of the spatial model
    L = model.config.mechanism.rod_length
    u_mid = deflection(y[:, :N], np.array([0.5 * L]), L)[:, 0]
    film = np.nan
    if pmap.monitored:
        x_star = np.ascontiguousarray(np.broadcast_to(model.motion(t).x_star, t.shape), dtype=float)
        f = thinnest_many if model.compiled else thinnest_many.py_func
        film = float(np.min(f(x_star, y, model.params)[:, 0]))
    out = {"peak_u2_mid": float(np.max(np.abs(u_mid))), "peak_q": np.max(np.abs(y[:, :N]), axis=0),
           "min_film": film, "impact_count": int(value.info["events"]), "period": pmap.period,
           "omega_n": np.array(model.omega_n)}
    if pmap.spatial:
        u1, _, u3 = model.deflections(y_state, np.array([0.5 * L]))
        W = np.array(model.state_frequencies)
        out.update(peak_u1_mid=float(np.max(np.abs(u1))), peak_u3_mid=float(np.max(np.abs(u3))),
                   omega_n1=W[:N], omega_n3=W[2 * N:])
    return out


def _state_scale(y, samples, period):
    """Scale of the state: peak |q| and |q_dot| of an orbit (``samples``), or of ``y`` alone."""
    N = y.size // 2
    if samples is None:
        samples = y[None, :]
    d = max(float(np.max(np.abs(samples[:, :N]))), 1e-9)
    v = max(float(np.max(np.abs(samples[:, N:]))), d * 2.0 * np.pi / period)
    return np.concatenate([np.full(N, d), np.full(N, v)])


def find_branch(config, stop, parameter="mechanism.crank_speed", *, start=None, motion=None, period=None, periods=1,
                y0=None, warmup=0, jacobian="auto", samples=256, ds=0.02, ds_max=0.1, max_parameter_step=None,
                max_points=2000, tol=1e-9, max_angle=15.0, progress=None):
    """``(branch, summaries, family)``: the periodic responses of ``config`` as ``parameter`` goes to ``stop``.

    Parameters
    ----------
    config : Config
        Validated configuration.
    stop : float
        Where the branch ends (in the units of the parameter).
    parameter : str
        ``section.key`` of a real parameter; ``mechanism.crank_speed`` [rad/s] by default (the
        period ``2 pi / |omega0|`` follows it).
    start : float, optional
        Where the branch starts (default: the configuration's value).
    motion, period, periods
        As for :func:`~.orbit.find_periodic` (a user motion keeps its period).
    y0, warmup
        Initial guess at ``start`` (default rest) and periods of transient before shooting; the
        first orbit is found by :func:`~.orbit.find_periodic` (with its restarts).
    jacobian : str
        As for :func:`~.orbit.find_periodic`: ``"auto"``, the variational equations (compiled)
        in a smooth period, differences of the map where an impact occurs. (Until the variational
        equations were compiled the default was ``"finite-difference"``, whose fixed step of
        ``1e-5`` against a map integrated at ``rtol = 1e-10`` put errors of ``1e-5`` in the
        multipliers and false Neimark-Sacker crossings on the undamped link.)
    samples : int
        Samples per period of each orbit for its summary (peak deflection, thinnest film).
    ds, ds_max, max_parameter_step, max_points, tol, max_angle
        See :func:`~.arclength.continue_branch`; ``max_parameter_step`` defaults to
        ``|stop - start| / 100``.
    progress : callable, optional
        ``progress(value)`` after each orbit.

    Returns
    -------
    branch : Branch
        Its ``wall_time`` [s] is this whole call's, the first orbit's shooting included.
    summaries : list of dict
        Per point: ``peak_u2_mid``, ``peak_q``, ``min_film``, ``impact_count``, ``period``,
        ``omega_n``; for the spatial model also ``peak_u1_mid``, ``peak_u3_mid``, ``omega_n1``,
        ``omega_n3``.
    family : Family
    """
    from .orbit import find_periodic

    began = time.perf_counter()
    family = Family(config, parameter, motion=motion, period=period, periods=periods, jacobian=jacobian,
                    samples=samples)
    lam0 = family.value0 if start is None else float(start)
    family.config_at(stop)  # an end outside the parameter's range is refused now (ConfigError), not met on the way
    if float(stop) == lam0:
        from ..validation import ConfigError

        raise ConfigError([f"{parameter}: the end of the branch ({float(stop):g}) must differ from its start "
                           f"({lam0:g})"])
    fmap0 = family(lam0)
    # the first orbit as lubelink.periodic finds it (restarts after transients if need be)
    y = find_periodic(fmap0.config, motion, period=period, periods=periods, y0=y0, warmup=warmup,
                      jacobian=jacobian, tol=tol).y0
    summaries = []

    def scale_of(y, value):
        if value is None:
            return fmap0.scale(y)
        return _state_scale(y, value.info["y"], value.info["t"][-1] or 1.0)

    def on_point(point):
        summaries.append(_summary(family(point.parameter), point.value))
        if progress:
            progress(point.parameter)

    branch = continue_branch(family, y, lam0, float(stop), scale_of, ds=ds, ds_max=ds_max,
                             max_parameter_step=max_parameter_step or abs(float(stop) - lam0) / 100.0,
                             max_points=max_points, tol=tol, max_angle=max_angle, on_point=on_point)
    branch.wall_time = time.perf_counter() - began
    return branch, summaries, family


def _entry(name, data, **attrs):
    v = BRANCH_VARIABLES.get(name) or SPATIAL_BRANCH_VARIABLES[name]
    return variable(v.dims, data, attrs.pop("units", v.units), attrs.pop("long_name", v.long_name), **attrs)


def branch_results(branch, summaries, family):
    """The branch as :class:`~lubelink.results.Results` (``point``, ``mode``, ``multiplier``, ``bifurcation``)."""
    from ..config import to_toml
    from ..results import CONVENTIONS, Results, versions

    pts = branch.points
    n = pts[0].y.size
    N = family.config.beam.modes
    spatial = n == 6 * N  # the spatial state [q1, q2, q3, q1_t, q2_t, q3_t]
    y0 = np.array([p.y for p in pts]).reshape(len(pts), n)
    inplane = slice(N, 2 * N) if spatial else slice(0, N)
    rates = slice(4 * N, 5 * N) if spatial else slice(N, 2 * N)
    units, long_name = _parameter_units(family.parameter)
    mu = np.array([p.multipliers for p in pts]).reshape(len(pts), n)
    coords = {"point": _entry("point", np.arange(len(pts))), "mode": _entry("mode", np.arange(1, N + 1)),
              "multiplier": _entry("multiplier", np.arange(1, n + 1)),
              "bifurcation": _entry("bifurcation", np.arange(len(branch.bifurcations)))}
    col = lambda key: np.array([s[key] for s in summaries])  # noqa: E731
    bif = branch.bifurcations
    data = {
        "parameter": _entry("parameter", [p.parameter for p in pts], units=units,
                            long_name=f"{family.parameter}: {long_name}", parameter=family.parameter),
        "period": _entry("period", col("period")),
        "q0": _entry("q0", y0[:, inplane]),
        "q_dot0": _entry("q_dot0", y0[:, rates]),
        "peak_u2_mid": _entry("peak_u2_mid", col("peak_u2_mid")),
        "peak_q": _entry("peak_q", np.array([s["peak_q"] for s in summaries]).reshape(len(pts), N)),
        "min_film": _entry("min_film", col("min_film")),
        "impact_count": _entry("impact_count", col("impact_count").astype(np.int32)),
        "floquet_modulus": _entry("floquet_modulus", np.abs(mu)),
        "floquet_argument": _entry("floquet_argument", np.angle(mu)),
        "floquet_error": _entry("floquet_error", np.array([p.errors for p in pts]).reshape(len(pts), n)),
        "max_modulus": _entry("max_modulus", np.abs(mu).max(axis=1)),
        "stable": _entry("stable", np.array([int(p.stable) for p in pts], dtype=np.int8)),
        "omega_n": _entry("omega_n", np.array([s["omega_n"] for s in summaries]).reshape(len(pts), N)),
        "arclength": _entry("arclength", [p.arclength for p in pts]),
        "iterations": _entry("iterations", np.array([p.iterations for p in pts], dtype=np.int32)),
        "residual": _entry("residual", [p.residual for p in pts]),
        "bifurcation_type": _entry("bifurcation_type", np.array([BIFURCATION_CODES[b.kind] for b in bif],
                                                                dtype=np.int8),
                                   flag_values=np.arange(len(floquet.KINDS), dtype=np.int8),
                                   flag_meanings=_FLAG_MEANINGS),
        "bifurcation_parameter": _entry("bifurcation_parameter", [b.parameter for b in bif], units=units),
        "bifurcation_point": _entry("bifurcation_point", np.array([b.index for b in bif], dtype=np.int32)),
        "bifurcation_modulus": _entry("bifurcation_modulus", [abs(b.multiplier) for b in bif]),
        "bifurcation_argument": _entry("bifurcation_argument", [np.angle(b.multiplier) for b in bif]),
    }
    if spatial:
        for name, k in (("q1_0", 0), ("q3_0", 2), ("q1_dot0", 3), ("q3_dot0", 5)):
            data[name] = _entry(name, y0[:, k * N:(k + 1) * N])
        for name in ("peak_u1_mid", "peak_u3_mid"):
            data[name] = _entry(name, col(name))
        for name in ("omega_n1", "omega_n3"):
            data[name] = _entry(name, np.array([s[name] for s in summaries]).reshape(len(pts), N))
    methods = {}
    for p in pts:
        methods[p.jacobian_method] = methods.get(p.jacobian_method, 0) + 1
    version, libs = versions()
    attrs = {
        "Conventions": CONVENTIONS,
        "title": "lubelink response curve: periodic responses of a flexible link with a lubricated prismatic joint",
        "source": f"lubelink {version}",
        "references": "pseudo-arclength continuation of the periodic response with its Floquet multipliers: "
                      "docs/periodic.md",
        "lubelink_version": version,
        "versions": libs,
        "config": to_toml(family.config),
        "parameter": family.parameter,
        "status": branch.status,
        "complete": int(branch.status == "complete"),
        "message": branch.message,
        "jacobian": ", ".join(f"{k} at {v} point(s)" for k, v in methods.items()),
        "bifurcations": "; ".join(f"{b.kind} at {family.parameter} = {b.parameter:.6g}" for b in bif) or "none",
        "map_evaluations": branch.evaluations,
        "wall_time": branch.wall_time,
        "wall_time_units": "s",
        "created": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    }
    return Results(data, coords, attrs)


def _parameter_units(name):
    """``(units, long name)`` of a configuration key, from the parameter docs (as the sweeps do)."""
    from ..sweep.schema import _parameters

    _, units, long_name = _parameters().get(name, ("", "", name))
    return units, long_name


def continuation(source="paper", set=None, *, stop, parameter="mechanism.crank_speed", start=None, motion=None,
                 period=None, periods=1, y0=None, warmup=0, jacobian="auto", ds=0.02, ds_max=0.1,
                 max_parameter_step=None, max_points=2000, tol=1e-9, max_angle=15.0, progress=None):
    """The response curve: periodic responses and their stability as a parameter varies.

    Pseudo-arclength continuation of the periodic response (shooting on the period map, whose
    period follows the crank speed) from the configuration's value of ``parameter`` (or
    ``start``) to ``stop``; folds and Floquet bifurcations (a multiplier leaving the unit circle
    through +1, -1 or as a complex pair) are detected between neighbouring orbits.

    Parameters
    ----------
    source, set
        The configuration, as for :func:`lubelink.simulate`.
    stop : float
        End of the parameter range.
    parameter : str
        ``section.key`` of a real parameter (default ``mechanism.crank_speed``).
    start, motion, period, periods, y0, warmup, jacobian, ds, ds_max, max_parameter_step, max_points, tol,
    max_angle, progress
        See :func:`find_branch`.

    Returns
    -------
    xarray.Dataset
        Over ``point``: ``parameter``, ``period``, ``q0``/``q_dot0`` (the periodic state at
        t = 0), ``peak_u2_mid``, ``peak_q``, ``min_film``, ``impact_count``,
        ``floquet_modulus``/``floquet_argument``/``floquet_error`` (over ``multiplier``; the last
        the accuracy estimate that the stability and the crossings use as margin), ``max_modulus``,
        ``stable``; over ``bifurcation``: ``bifurcation_type`` (see ``flag_meanings``),
        ``bifurcation_parameter``, ``bifurcation_point``; for the spatial model (``q0``,
        ``q_dot0``, ``peak_q``, ``omega_n``: the in-plane modes) also ``q1_0``, ``q1_dot0``,
        ``q3_0``, ``q3_dot0``, ``peak_u1_mid``, ``peak_u3_mid``, ``omega_n1``, ``omega_n3``
        (:data:`SPATIAL_BRANCH_VARIABLES`). ``attrs["status"]`` is
        ``"complete"``, or ``"stopped"`` with the reason in ``attrs["message"]``.
    """
    from ..config import resolve
    from ..results import dataset

    config = resolve(source, set)
    branch, summaries, family = find_branch(
        config, stop, parameter, start=start, motion=motion, period=period, periods=periods, y0=y0, warmup=warmup,
        jacobian=jacobian, ds=ds, ds_max=ds_max, max_parameter_step=max_parameter_step, max_points=max_points,
        tol=tol, max_angle=max_angle, progress=progress)
    return dataset(branch_results(branch, summaries, family))

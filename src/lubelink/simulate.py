"""The orchestrator: configuration -> model -> integration with impacts -> Dataset."""

from __future__ import annotations

import functools
import importlib.metadata
import platform
import time
from dataclasses import dataclass, field

import numpy as np

from . import beam, film
from .config import resolve, to_toml
from .integrate import integrate_segment
from .model import ContactPhase, build_model
from .results import FORMAT_VERSION, variable

__all__ = ["simulate", "Run", "run"]

#: Impacts allowed in one run before it is declared chattering.
MAX_IMPACTS = 100_000


@dataclass
class Run:
    """Raw outcome of :func:`run`: samples, impacts, status and statistics."""

    model: object
    t: np.ndarray
    y: np.ndarray
    status: str = "complete"
    message: str = "reached solver.t_end"
    impacts: list = field(default_factory=list)
    nfev: int = 0
    nsteps: int = 0
    wall_time: float = 0.0

    @property
    def complete(self) -> bool:
        return self.status == "complete"


def reference_segment_integrator(model):
    """Segment integrator on the NumPy right-hand side and a SciPy-style step solver.

    Returns ``segment(t0, y0, t_end, t_eval, *, phase, event_sign,
    event_resolution, deadline, progress) -> Segment``: it integrates from
    ``t0`` until ``t_end`` or until the gap function (``model.gap``) falls
    to zero (``event_sign = -1``) or rises to zero (``+1``, the end of a
    compliant contact ``phase``); ``event_sign = None`` watches nothing.
    """
    s = model.config.solver

    def segment(t0, y0, t_end, t_eval, *, phase, event_sign, event_resolution, deadline, progress):
        fun = model.rhs if phase is None else functools.partial(model.rhs, phase=phase)
        event = None
        if event_sign == -1:
            event = model.gap
        elif event_sign == 1:
            event = lambda t_, y_: -model.gap(t_, y_)  # noqa: E731
        return integrate_segment(fun, t0, y0, t_end, t_eval, method=s.method, rtol=s.rtol, atol=s.atol,
                                 max_step=s.max_step, event=event, event_resolution=event_resolution,
                                 deadline=deadline, progress=progress)

    return segment


def segment_integrator(model):
    """The segment integrator for ``model``: the compiled fast path where it applies, else the reference.

    ``solver.backend``: ``"numpy"`` always takes the reference; ``"numba"``
    requires the fast path; ``"auto"`` takes it when Numba is installed and
    the configuration is supported.
    """
    backend = model.config.solver.backend
    if backend != "numpy":
        try:
            from .integrate.fast import make_segment_integrator
        except ImportError:
            if backend == "numba":
                raise
        else:
            fast = make_segment_integrator(model)
            if fast is not None:
                return fast
            if backend == "numba":
                raise ValueError("solver.backend = 'numba': this configuration is not supported by the "
                                 "compiled path; use backend = 'auto' or 'numpy'")
    return reference_segment_integrator(model)


def run(config, motion=None, progress=None) -> Run:
    """Integrate a validated configuration, handling film breakdown as it occurs.

    The integration proceeds in segments between events of the gap function
    (thinnest film minus ``contact.min_film``): with the restitution law a
    segment ends at an impact, the modal velocities jump and the next
    segment starts; with the compliant law the contact force is switched on
    from the crossing until the film reopens.

    Parameters
    ----------
    config : Config
        Validated configuration.
    motion : object, optional
        Motion provider replacing the slider-crank.
    progress : callable, optional
        ``progress(t)`` after every solver step.

    Returns
    -------
    Run
        ``status`` is ``"complete"``, or ``"film_breakdown"``, ``"chatter"``,
        ``"solver_failure"``, ``"timeout"`` with the samples computed so far.
        ``impacts`` holds one tuple ``(t, x_c, v_minus, v_plus, side, q,
        q_dot_before, q_dot_after)`` per impact (compliant contact: ``t`` is
        the start, ``v_plus`` the approach velocity when it ends).
    """
    start = time.perf_counter()
    model = build_model(config, motion)
    s, ct = config.solver, config.contact
    N = model.modes
    deadline = start + s.max_wall_time if np.isfinite(s.max_wall_time) else None
    n_out = int(np.floor(s.t_end / s.output_step * (1 + 1e-12))) + 1
    t_eval = np.minimum(np.arange(n_out) * s.output_step, s.t_end)  # 0.7/1e-3 * 1e-3 > 0.7
    monitored = config.film.enabled or ct.law != "none"
    # the gap moves on the time scale of the fastest mode: sample it at least 8 times a period
    event_resolution = 2.0 * np.pi / model.omega_n[-1] / 8.0
    t, y = 0.0, model.initial_state()
    ts, ys = [t_eval[:1]], [y[None, :]]
    out = Run(model=model, t=None, y=None)
    phase = None  # compliant contact in progress
    segment = segment_integrator(model)
    while True:
        event_sign = None if not monitored else (-1 if phase is None else 1)
        seg = segment(t, y, s.t_end, t_eval[t_eval > t], phase=phase, event_sign=event_sign,
                      event_resolution=event_resolution, deadline=deadline, progress=progress)
        ts.append(seg.t)
        ys.append(seg.y)
        out.nfev += seg.nfev
        out.nsteps += seg.nsteps
        t, y = seg.t_final, seg.y_final
        if seg.status == "finished":
            break
        if seg.status == "failed":
            out.status, out.message = "solver_failure", seg.message
            break
        if seg.status == "timeout":
            out.status = "timeout"
            out.message = f"{seg.message} (solver.max_wall_time = {s.max_wall_time} s)"
            break
        if ct.law == "none":
            out.status = "film_breakdown"
            out.message = (f"the film thinned to contact.min_film = {ct.min_film} m at t = {t:.9g} s and "
                           "contact.law = 'none'; set contact.law = 'restitution' or 'compliant', or a "
                           "larger film.clearance")
            break
        if ct.law == "compliant":
            v, x_c, side = model.approach(t, y)
            if phase is None:
                phase = ContactPhase(side=side, v_minus=v)
                out.impacts.append([t, x_c, v, np.nan, side, y[:N].copy(), y[N:].copy(), None])
            else:
                out.impacts[-1][3] = v
                out.impacts[-1][7] = y[N:].copy()
                phase = None
            continue
        y_plus, x_c, v_minus, side = model.impact(t, y)
        v_plus = -ct.restitution * v_minus if v_minus > 0 else v_minus
        out.impacts.append([t, x_c, v_minus, v_plus, side, y[:N].copy(), y[N:].copy(), y_plus[N:].copy()])
        previous = out.impacts[-2][0] if len(out.impacts) > 1 else -np.inf
        if t - previous < ct.chatter_interval or len(out.impacts) > MAX_IMPACTS:
            out.status = "chatter"
            out.message = (f"impacts at t = {previous:.12g} s and {t:.12g} s are closer than "
                           f"contact.chatter_interval = {ct.chatter_interval} s: the link chatters "
                           "(sustained contact), which the restitution law cannot resolve; "
                           "try contact.law = 'compliant'")
            break
        y = y_plus
        if t >= s.t_end:
            break
    out.t = np.concatenate(ts)
    out.y = np.concatenate(ys)
    out.wall_time = time.perf_counter() - start
    return out


def _version(package):
    try:
        return importlib.metadata.version(package)
    except importlib.metadata.PackageNotFoundError:
        return "unknown"


def to_dataset(result: Run):
    """Sample a :class:`Run` into the results :class:`xarray.Dataset`."""
    import xarray as xr

    model = result.model
    cfg = model.config
    L = cfg.mechanism.rod_length
    N = model.modes
    q, q_dot = result.y[:, :N], result.y[:, N:]
    x = np.linspace(0.0, L, cfg.output.x_points)
    kin = model.motion(result.t)
    data = {
        "q": variable(("time", "mode"), q, "m", "modal coordinate"),
        "q_dot": variable(("time", "mode"), q_dot, "m s-1", "modal velocity"),
        "u2": variable(("time", "x"), beam.deflection(q, x, L), "m", "transverse deflection"),
        "u2_mid": variable(("time",), beam.deflection(q, np.array([0.5 * L]), L)[:, 0], "m",
                           "midpoint deflection"),
        "x_star": variable(("time",), kin.x_star, "m", "collar position along the link"),
        "V_r": variable(("time",), kin.V_r, "m s-1", "collar velocity relative to the link"),
        "omega_n": variable(("mode",), model.omega_n, "rad s-1", "natural circular frequency"),
    }
    coords = {
        "time": variable(("time",), result.t, "s", "time"),
        "x": variable(("x",), x, "m", "position along the link from the crank pin O"),
        "mode": variable(("mode",), np.arange(1, N + 1), "1", "mode number"),
    }
    fm = cfg.film
    x0 = film.pad_start(np.asarray(kin.x_star), fm.pad_length, fm.pad_reference)
    if fm.enabled or cfg.contact.law != "none":
        X_probe = np.linspace(0.0, fm.pad_length, 4 * cfg.output.pad_points)
        u_pad = np.einsum("tmk,tk->tm",
                          np.sin((x0[:, None] + X_probe)[..., None] * (np.arange(1, N + 1) * np.pi / L)), q)
        xi = 0.5 * fm.clearance - np.abs(u_pad) if fm.sides == 2 else 0.5 * fm.clearance - u_pad
        data["film_min"] = variable(("time",), xi.min(axis=1), "m", "thinnest film on the pad (sampled)")
    if fm.enabled:
        X = np.linspace(0.0, fm.pad_length, cfg.output.pad_points)
        coords["X"] = variable(("X",), X, "m", "position along the pad from its start")
        squeeze = fm.model == "wedge+squeeze"
        p_cav = fm.cavitation_pressure - fm.ambient_pressure
        p = []
        for side in model.sides:
            if fm.cavitation == "reynolds":
                grid_X = np.linspace(0.0, fm.pad_length, fm.grid_points)
                p_side = np.array([np.interp(X, grid_X, film.pressure(
                    grid_X, film.mode_film(side * qi, x0i, fm.clearance, L), Vi, fm.viscosity,
                    xi_t=film.mode_film_rate(side * qdi, x0i, L) if squeeze else None,
                    cavitation="reynolds", p_cav=p_cav, grid_points=fm.grid_points))
                    for qi, qdi, x0i, Vi in zip(q, q_dot, x0, kin.V_r)])
            else:
                p_side = film.pad_pressure(X, side * q, side * q_dot, x0, kin.V_r, mu=fm.viscosity,
                                           clearance=fm.clearance, rod_length=L, squeeze=squeeze)
                if fm.cavitation == "half-sommerfeld":
                    p_side = np.maximum(p_side, p_cav)
            p.append(p_side)
        data["pressure"] = variable(("time", "X"), p[0], "Pa", "gauge film pressure P - p_am "
                                    "(film at H/2 - u2, the paper's)")
        if len(p) == 2:
            data["pressure_lower"] = variable(("time", "X"), p[1], "Pa",
                                              "gauge film pressure of the film at H/2 + u2")
        if fm.cavitation == "none":
            force = sum(side * film.resultant_force(side * q, side * q_dot, x0, kin.V_r, mu=fm.viscosity,
                                                    clearance=fm.clearance, pad_length=fm.pad_length,
                                                    width=cfg.beam.width, rod_length=L, squeeze=squeeze,
                                                    nodes=fm.quadrature_nodes)
                        for side in model.sides)
        else:
            force = np.array([model.film_loads(ti, yi)[1] for ti, yi in zip(result.t, result.y)])
        data["film_force"] = variable(("time",), force, "N", "resultant film force on the link along +j")
    imp = result.impacts
    coords["impact"] = variable(("impact",), np.arange(len(imp)), "1", "impact number")
    data["impact_time"] = variable(("impact",), [i[0] for i in imp], "s", "impact time (contact start)")
    data["impact_position"] = variable(("impact",), [i[1] for i in imp], "m", "contact point on the link")
    data["impact_velocity"] = variable(("impact",), [i[2] for i in imp], "m s-1",
                                       "normal approach velocity before impact (positive closing)")
    data["impact_velocity_after"] = variable(("impact",), [i[3] for i in imp], "m s-1",
                                             "normal approach velocity after impact (negative opening)")
    data["impact_side"] = variable(("impact",), np.array([i[4] for i in imp], dtype=int), "1",
                                   "film side of the contact")
    attrs = {
        "title": "lubelink simulation of a flexible link with a lubricated prismatic joint",
        "references": "Marghitu & Guran, The Dynamics of a Flexible Beam With a Lubricated "
                      "Prismatic Kinematic Pair, J. Vibration and Acoustics; corrected per lubelink MODEL.md",
        "lubelink_version": _version("lubelink"),
        "lubelink_format": FORMAT_VERSION,
        "versions": f"python {platform.python_version()}, numpy {np.__version__}, "
                    f"scipy {_version('scipy')}, xarray {_version('xarray')}",
        "config": to_toml(cfg),
        "status": result.status,
        "complete": int(result.complete),
        "message": result.message,
        "solver_method": cfg.solver.method,
        "nfev": result.nfev,
        "nsteps": result.nsteps,
        "impact_count": len(imp),
        "wall_time": result.wall_time,
        "created": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    }
    return xr.Dataset(data, coords=coords, attrs=attrs)


def simulate(source="paper", set=None, *, motion=None, progress=False):
    """Run one simulation and return its results.

    Parameters
    ----------
    source : str, os.PathLike, dict or Config
        Scenario name (``"paper"``, ``"paper-dry"``, ``"paper-impact"``), a
        TOML file, a parsed TOML dict or a :class:`~lubelink.params.Config`.
    set : dict, optional
        Overrides ``{"section.key": value}``, e.g. ``{"beam.modes": 5}``.
    motion : object, optional
        A motion provider (:mod:`lubelink.kinematics`) replacing the
        slider-crank.
    progress : bool or callable
        ``True`` shows a progress bar on stderr; a callable receives the
        simulated time after every step.

    Returns
    -------
    xarray.Dataset
        See :func:`to_dataset`. ``attrs["status"]`` is ``"complete"`` or
        says why the run stopped early (the samples up to there are kept).

    Raises
    ------
    lubelink.ConfigError
        For invalid parameters, before anything is computed.
    """
    config = resolve(source, set)
    if progress is True:
        from tqdm.auto import tqdm

        with tqdm(total=config.solver.t_end, unit="s", unit_scale=True, desc="simulating",
                  leave=False, mininterval=0.25) as bar:
            def report(t):
                bar.n = t
                bar.refresh() if bar.n - bar.last_print_n > 0.01 * bar.total else None

            result = run(config, motion, report)
    else:
        result = run(config, motion, progress or None)
    return to_dataset(result)

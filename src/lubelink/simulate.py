"""The orchestrator: configuration -> model -> integration between contact events -> results.

:func:`run` integrates in segments between zeros of the gap function (thinnest film minus
``contact.min_film``) and asks :class:`~lubelink.contact.ContactLogic` what each zero means;
:func:`simulate` is :func:`run` plus :func:`~lubelink.results.to_dataset`.
"""

from __future__ import annotations

import logging
import time
from dataclasses import replace

import numpy as np

from . import integrate
from .config import resolve
from .contact import ContactLogic
from . import coupling
from .coupling import relax, relax_windows
from ._jit import compile_errors
from ._prewarm import announcing, first_run
from .assembly import compile_failed
from .build import build_model
from .errors import BackendError
from .choice import method_choice, method_name
from .params import sample_times
from .results import Run, to_dataset
from .beam import wavenumbers

_log = logging.getLogger("lubelink")

__all__ = ["simulate", "Run", "run", "to_dataset", "sample_times", "event_resolution", "method_name", "method_choice"]


def event_resolution(model):
    """Longest interval between two samples of the gap inside a step [s]: 1/4 of the fastest modal period.

    Between two samples the event detector looks for a change of sign of the gap and of its rate
    (a minimum): the rate of a ripple of period ``T`` changes sign every ``T/2``, so samples
    ``T/4`` apart see each of its minima.
    """
    return 2.0 * np.pi / model.omega_n[-1] / 4.0


#: Quantities of :func:`lubelink.beam.linear_domain` and the ``solver`` limits they are checked against.
DOMAIN = (("max |u2|/L", "max_deflection"), ("max |u2'|", "max_slope"), ("stretching strain", "max_axial_strain"))


def domain_exit(model, y):
    """``(index, message)`` of the first state of ``y`` ``(T, 2N)`` outside the linear theory's domain, or None.

    The limits are ``solver.max_deflection``, ``max_slope``, ``max_axial_strain``
    (:func:`lubelink.beam.linear_domain`); a non-finite state is outside too.
    """
    from .beam import linear_domain

    s = model.config.solver
    limits = np.array([getattr(s, key) for _, key in DOMAIN])
    if y.shape[0] == 0 or not np.isfinite(limits).any():
        return None
    # the deflections: u2, and for the spatial link u3 (the stretching strain is then that of both)
    blocks = [model.planar_state(y)[:, :model.modes]]
    names = [name for name, _ in DOMAIN]
    if hasattr(model, "block_state"):
        blocks.append(model.block_state(y, 2)[:, :model.modes])
        names = ["max |u2|/L, |u3|/L", "max |u2'|, |u3'|", names[2]]
    L = model.config.mechanism.rod_length
    beta = wavenumbers(model.modes, L)

    # |u| <= sum |q_n| and |u'| <= sum beta_n |q_n|: only the states these bounds do not clear are sampled,
    # and none when the bounds of the largest |q_n| of all states clear (NaN clears nothing)
    def bounds(a):  # a = |q| of each block, shape (..., N): the bounds of (|u|/L, |u'|, strain)
        return np.stack([np.max([b.sum(axis=-1) / L for b in a], axis=0),
                         np.max([(b * beta).sum(axis=-1) for b in a], axis=0),
                         np.sum([0.25 * ((beta * b) ** 2).sum(axis=-1) for b in a], axis=0)], axis=-1)

    largest = [np.abs(np.ascontiguousarray(q.T)).max(axis=1) for q in blocks]  # (along rows: 5x faster than axis=0)
    if np.all(bounds(largest) <= limits):
        return None
    first = bounds([np.abs(q) for q in blocks])
    check = ~np.all(first <= limits, axis=1)
    if not check.any():
        return None
    m = np.zeros((y.shape[0], 3))
    m[:, 2] = first[:, 2]
    each = [linear_domain(q[check], L, 16 + 8 * model.modes) for q in blocks]
    m[check] = np.stack([np.max([e[:, 0] for e in each], axis=0), np.max([e[:, 1] for e in each], axis=0),
                         np.sum([e[:, 2] for e in each], axis=0)], axis=-1)
    bad = ~(m <= limits)
    rows = np.flatnonzero(bad.any(axis=1))
    if rows.size == 0:
        return None
    i = int(rows[0])
    j = int(np.flatnonzero(bad[i])[0])
    name, key = names[j], DOMAIN[j][1]
    return i, (f"{name} = {m[i, j]:.4g} exceeds solver.{key} = {limits[j]:g}: the state left the domain of the "
               "linear (small-deflection) theory, so the results beyond are meaningless; the run stopped "
               "(raise the limit, or set it to inf, to go on regardless)")


def _compiled_loop(model, method):
    """Whether ``model`` integrates in the compiled loop with ``method`` (its name)."""
    return model.compiled and method in integrate.COMPILED_METHODS


def _failure_message(message, config):
    """A failed integration's ``message``, with the cause where the configuration is known to make the
    loads unbounded (a film without a floor that a compliant contact closes)."""
    if config.film.enabled and config.film.thickness_floor == 0.0 and config.contact.law == "compliant":
        from .params import Film

        sigma = config.film.roughness
        if sigma > 0.0:
            return (f"{message.rstrip('.')}; with film.thickness_floor = 0 the film of the rough surfaces (their "
                    f"mean gap) stiffens without limit as the asperities are pressed together: a floor of "
                    f"0.04 film.roughness ({0.04 * sigma:.3g} m) bounds it and changes nothing while they are "
                    f"pressed less than film.roughness into each other")
        return (f"{message.rstrip('.')}; with film.thickness_floor = 0 the film force grows without bound "
                f"where the compliant contact closes the gap: set film.thickness_floor > 0 (the default is "
                f"{Film.thickness_floor} m)")
    return message


def run(config, motion=None, progress=None, model=None, y0=None, section=None) -> Run:
    """Integrate a validated configuration, handling film breakdown as it occurs.

    Parameters
    ----------
    config : Config
        Validated configuration.
    motion : object, optional
        Motion provider replacing the slider-crank.
    progress : callable, optional
        ``progress(t)`` as the integration advances.
    model : Model, optional
        An assembled model of ``config`` (default: :func:`~lubelink.build.build_model`).
    y0 : array_like, shape ``(2N,)``, optional
        State ``[q, q_dot]`` at t = 0 [m, m/s] (default: zero, the paper's). It must not lie
        inside a contact (thinnest film below ``contact.min_film``).
    section : lubelink.link.section.Section, optional
        ``A(x)``, ``I(x)`` of the link replacing the beam's section (ignored with ``model``).

    Returns
    -------
    Run
        ``y`` holds the sine-mode states ``[q, q_dot]`` (also for a variable section, which is
        integrated in its eigen-coordinates, :mod:`lubelink.link.section`); for ``beam.model =
        "spatial"`` ``[q1, q2, q3, q1_t, q2_t, q3_t]`` (:mod:`lubelink.link.spatial_model`). ``status`` is
        ``"complete"``, or ``"film_breakdown"``, ``"chatter"``, ``"penetration"`` (a second point of the pad reaching
        the face in a sustained contact), ``"solver_failure"``, ``"timeout"``, ``"out_of_domain"`` (:func:`domain_exit`) with the
        samples computed so far. ``impacts`` holds one list
        ``[t, x_c, v_minus, v_plus, side, q, q_dot_before, q_dot_after]`` per impact (compliant
        contact: ``t`` is the start, ``v_plus`` the approach velocity at the end); ``contacts``
        ``[t_start, t_end, side]`` per contact phase; ``phase_side``, ``phase_v`` the contact
        phase of every sample (side 0: free). With ``drive.coupling = "two-way"`` the last run of the
        relaxation (:func:`lubelink.coupling.relax`; a run longer than 1.5 ``coupling.WINDOW_TURNS`` crank turns
        in windows, :func:`lubelink.coupling.relax_windows`), ``coupling`` its record.
    """
    if config.drive.coupling == "two-way" and motion is None:
        first = None if model is None else model.motion
        turns = abs(config.mechanism.crank_speed) * config.solver.t_end / (2.0 * np.pi)
        window = coupling.WINDOW_TURNS
        if y0 is None and turns > 1.5 * window:  # a long run: relaxed in windows
            def part(driven, t_end, start_state):
                local = replace(config, solver=replace(config.solver, t_end=t_end))
                return _run(local, progress, build_model(local, driven, section), start_state, section)

            result, record = relax_windows(config, part, lambda whole: build_model(config, whole, section), section,
                                           turns=window)
        else:
            def once(driven):
                built = model if driven is first else build_model(config, driven, section)
                return _run(config, progress, built, y0, section)

            result, record = relax(config, once, section, first)
        result.coupling = record
        return result
    return _run(config, progress, build_model(config, motion, section) if model is None else model, y0, section)


def _run(config, progress, model, y0, section) -> Run:
    """:func:`run` of one model (one-way)."""
    start = time.perf_counter()
    s = config.solver
    deadline = start + s.max_wall_time if np.isfinite(s.max_wall_time) else None
    t_eval = sample_times(s)
    monitored = model.watched
    resolution = event_resolution(model)
    out_method = method_name(config)
    method = integrate.method(out_method)
    stiff = out_method == "rodas"
    if stiff:
        missing = model.jacobian_missing(None)
        note = "Jacobian analytic" if not missing else f"Jacobian by finite differences: {missing}"
    t = 0.0
    y = model.initial_state() if y0 is None else np.array(y0, dtype=float).reshape(model.initial_state().size)
    ts, ys, sides, vs, points = [t_eval[:1]], [y[None, :]], [np.zeros(1)], [np.zeros(1)], [np.zeros(1)]
    out = Run(model=model, t=None, y=None, method=out_method, section=section)
    logic = ContactLogic(model)
    phase = None
    exited = None if y0 is None else domain_exit(model, y[None, :])  # (the rest state is inside)
    if exited is not None:
        out.status, out.message, out.event_time = "out_of_domain", f"at t = 0 s: {exited[1]}", 0.0
    y = model.to_state(y)
    sustained = config.contact.law == "restitution"
    while exited is None:
        event_sign = 0 if not monitored else (-1 if phase is None or sustained else 1)
        compiled_loop = _compiled_loop(model, out_method)
        jacobian = stiff and not model.jacobian_missing(phase)
        if stiff and not jacobian and "finite differences" not in note:
            note += f"; by finite differences in {model.jacobian_missing(phase)}"
        problem = integrate.Problem(*model.functions(), model.with_phase(phase),
                                    p_type=model.params_type if compiled_loop else None,
                                    omega=model.state_frequencies, zeta=config.beam.damping_ratio, jacobian=jacobian)
        options = integrate.Options(rtol=s.rtol, atol=s.atol, max_step=s.max_step, event_resolution=resolution,
                                    deadline=deadline, compiled=compiled_loop)
        try:
            seg = integrate.integrate(method, problem, t, y, s.t_end, t_eval[t_eval > t], options=options,
                                      event_sign=event_sign, progress=progress)
        except compile_errors() as exc:
            if not model.compiled:
                raise
            if s.backend == "numba":
                raise BackendError(f"solver.backend = 'numba': compiling the kernels failed ({type(exc).__name__}: "
                                   f"{str(exc).splitlines()[0] if str(exc) else ''}); use solver.backend = 'auto' "
                                   "(falls back to numpy) or 'numpy'") from exc
            model = compile_failed(model, exc)
            out.model = logic.model = model
            continue
        seg_t, seg_y = seg.t, model.to_physical(seg.y)
        exited = domain_exit(model, seg_y)
        if exited is not None:
            seg_t, seg_y = seg_t[:exited[0] + 1], seg_y[:exited[0] + 1]
        ts.append(seg_t)
        ys.append(seg_y)
        sides.append(np.full(seg_t.size, 0.0 if phase is None else float(phase[0])))
        vs.append(np.full(seg_t.size, 0.0 if phase is None else float(phase[1])))
        points.append(np.full(seg_t.size, 0.0 if phase is None or len(phase) < 3 else float(phase[2])))
        out.nfev += seg.nfev
        out.nsteps += seg.nsteps
        if exited is not None:
            out.status, out.event_time = "out_of_domain", float(seg_t[-1])
            out.message = f"at t = {seg_t[-1]:.9g} s: {exited[1]}"
            break
        t, y = seg.t_final, seg.y_final
        if seg.status == "finished":
            break
        if seg.status == "failed":
            out.status, out.message = "solver_failure", _failure_message(seg.message, config)
            break
        if seg.status == "timeout":
            out.status = "timeout"
            out.message = f"{seg.message} (solver.max_wall_time = {s.max_wall_time} s)"
            break
        status, message, t, y, phase = logic.on_event(seg.t_before, model.to_physical(seg.y_before), seg.t_final,
                                                      model.to_physical(seg.y_final), phase)
        y = model.to_state(y)
        if status is not None:
            out.status, out.message, out.event_time = status, message, seg.t_final
            break
        if t >= s.t_end:
            break
    if out.status not in ("complete", "out_of_domain") and t > max(float(a[-1]) for a in ts if a.size):
        final = model.to_physical(y)  # a run that ends early keeps the state where it stopped as its last sample
        if np.all(np.isfinite(final)):
            ts.append(np.array([t]))
            ys.append(final[None, :])
            for series, value in ((sides, 0), (vs, 1), (points, 2)):
                series.append(np.full(1, 0.0 if phase is None or len(phase) <= value else float(phase[value])))
    out.method_note = "; ".join(x for x in (method_choice(config)[1], note if stiff else "") if x)
    out.impacts = logic.impacts
    out.contacts = logic.contacts
    out.t = np.concatenate(ts)
    out.y = np.concatenate(ys)
    out.phase_side = np.concatenate(sides)
    out.phase_v = np.concatenate(vs)
    out.phase_point = np.concatenate(points)
    out.wall_time = time.perf_counter() - start
    return out


def simulate(source="paper", set=None, *, motion=None, progress=False, section=None):
    """Run one simulation and return its results.

    Parameters
    ----------
    source : str, os.PathLike, dict or Config
        Scenario name (``"paper"``, ``"paper-dry"``, ``"paper-impact"``), a TOML file, a parsed
        TOML dict or a :class:`~lubelink.params.Config`.
    set : dict, optional
        Overrides ``{"section.key": value}``, e.g. ``{"beam.modes": 5}``.
    motion : object, optional
        A motion provider (:mod:`lubelink.link.kinematics`) replacing the slider-crank; with
        ``beam.model = "spatial"`` a spatial one (:mod:`lubelink.link.spatial_motion`:
        ``sampled_spatial_motion`` or ``SpatialPrescribedMotion``).
    progress : bool or callable
        ``True`` shows a progress bar on stderr where it is a terminal (elsewhere a line at the
        start and one at the end: :class:`lubelink.progress.Bar`); a callable receives the
        simulated time.
    section : lubelink.link.section.Section, optional
        ``A(x)``, ``I(x)`` of the link (callables or sampled tables) replacing the beam's section.

    Returns
    -------
    xarray.Dataset
        See :func:`~lubelink.results.to_dataset`. ``attrs["status"]`` is ``"complete"`` or says
        why the run stopped early (the samples up to there are kept).

    Raises
    ------
    lubelink.ConfigError
        For invalid parameters, before anything is computed.
    """
    config = resolve(source, set)
    with announcing(lambda line: _log.warning("lubelink: %s", line)) as once:
        model = first_run(build_model(config, motion, section), motion, say=once)
        if progress is True:  # tqdm's bar on a terminal, a line at the start and the end in a log
            from .progress import Bar

            with Bar(config.solver.t_end, "simulating", "s", unit_scale=True, leave=False, mininterval=0.25) as bar:
                bar.stage(f"{config.solver.t_end:g} s of motion")
                result = run(config, motion, bar.advance_to, model=model)
        else:
            result = run(config, motion, progress or None, model=model)
        ds = to_dataset(result)
    if ds.attrs["contact_warning"]:
        import warnings

        warnings.warn(f"lubelink: {ds.attrs['contact_warning']}", RuntimeWarning, stacklevel=2)
    return ds

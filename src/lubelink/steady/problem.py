"""lubelink's period map: the model's flow over one period of the rigid motion, for the shooting code.

:class:`PeriodMap` is the one place where the periodic machinery meets the model. Its value at a
state ``y0`` (at t = 0) is the state one period later, computed by :func:`lubelink.simulate.run`
from ``y0``, so that film breakdown and impacts are handled by the same
:class:`~lubelink.contact.ContactLogic` as in any run: a period with impacts is the composition of
the smooth flows and the impact maps. Its Jacobian (the monodromy matrix) comes from the
variational equations integrated with the state (:mod:`.variational`, compiled): over the whole
period when it is smooth, else stretch by stretch between the run's impacts, composed with the
saltation matrix of each impact (:mod:`.saltation`, the pieces from :mod:`lubelink.jumps`). Where
an event has no saltation matrix here (a compliant or a sustained contact) or is a graze, ``"auto"``
takes central differences of the map (:meth:`PeriodMap.differences`) and ``info["jacobian_note"]``
says why. Asked for ``"checked"``, the map adds a second, less accurate matrix for the multipliers'
accuracy estimates: the variational equations at :data:`CHECK_FACTOR` times the tolerances, or
differences of twice the step.

:class:`Family` is the map as a function of one parameter ``section.key``; the period follows the
parameter (``T = 2 pi / |crank_speed|``), i.e. the map is taken over a fixed interval of crank
phase, so a change of crank speed changes the period of the map as well as the loads.

The state is the model's whole integration state: ``[q, q_dot]`` (``2 N``) of the planar model,
``[q1, q2, q3, q1_t, q2_t, q3_t]`` (``6 N``) of the spatial one (``beam.model = "spatial"``,
:mod:`lubelink.link.spatial_model`); nothing here depends on which. (Until the variational
equations were compiled, ``"auto"`` took differences for the spatial model, whose axial modes
hold an explicit method to short steps: compiled, the variational equations of the dry spatial
link with one mode take 0.15 s against 1.7 s for the checked differences.)

Shooting tightens the solver tolerances to at least ``rtol = 1e-10``, ``atol = 1e-13`` [m, m/s]:
Newton's method and the finite-difference Jacobians need a map accurate well beyond plotting.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from .saltation import Grazing, compose, saltation_matrix
from .shooting import MapFailure, MapValue

__all__ = ["PeriodMap", "Family", "Unsupported", "crank_period", "SHOOTING_RTOL", "SHOOTING_ATOL", "DIFFERENCE_RTOL",
           "DIFFERENCE_ATOL", "CHECK_FACTOR", "JACOBIANS"]

#: Loosest tolerances of the map's integration (a configuration's tighter ones are kept).
SHOOTING_RTOL = 1e-10
SHOOTING_ATOL = 1e-13
#: Tolerances of the runs whose differences give a monodromy matrix: the map's error ``delta``
#: (about ``rtol`` of the scale) enters a central difference of step ``h`` as ``delta / h``, its
#: truncation as ``h^2``; at ``rtol = 1e-12`` the balanced step is ``1.4e-4`` of the scale and both
#: errors about ``1e-8``, where the map's own ``1e-10`` gave ``7e-4`` and ``1.5e-7``.
DIFFERENCE_RTOL = 1e-12
DIFFERENCE_ATOL = 1e-15
#: The check of a monodromy matrix from the variational equations (:func:`.floquet.multiplier_errors`):
#: integrated again at this many times the tolerances, its difference from the first divided by the
#: square root of this factor. That assumes an error falling at least as the square root of the
#: tolerance; DOP853's falls about in proportion to it (undamped ``paper-dry`` at 5.04 rad/s: 4.6e-7
#: at 100 times the tolerance, 5.8e-10 at it), so the estimate is an upper one.
CHECK_FACTOR = 100.0
#: Tolerance of the variational equations for the Jacobians of Newton's steps (not of the
#: multipliers): Newton's method needs the direction, not the last digits.
NEWTON_RTOL = 1e-7
#: How the monodromy matrix is obtained: ``"auto"`` (variational equations, through impacts by saltation
#: matrices; finite differences where an event has none, :class:`Unsupported`, or grazes),
#: ``"variational"`` (an error in those cases), ``"finite-difference"``.
JACOBIANS = ("auto", "variational", "finite-difference")


def crank_period(config) -> float:
    """Period of the slider-crank's motion, ``2 pi / |omega0|`` [s]."""
    return 2.0 * math.pi / abs(config.mechanism.crank_speed)


class Unsupported(ValueError):
    """Events in the period that have no saltation matrix here (:func:`lubelink.jumps.unsupported`)."""


class PeriodMap:
    """``y0 -> y(T)``: the state one period after ``y0`` at t = 0, a map for :func:`~.shooting.shoot`.

    Parameters
    ----------
    config : Config
        Validated configuration (its solver tolerances are tightened, see the module docstring).
    motion : object, optional
        A motion provider replacing the slider-crank; then ``period`` is required.
    period : float, optional
        Period of the map [s]. Default: the slider-crank's ``2 pi / |omega0|`` times ``periods``.
    periods : int
        For the slider-crank: the map spans this many crank turns (2 looks for period-2 orbits).
    jacobian : str
        One of :data:`JACOBIANS`.
    samples : int
        Samples of the orbit per period kept in ``MapValue.info`` (``"t"``, ``"y"``).
    """

    def __init__(self, config, motion=None, period=None, periods=1, jacobian="auto", samples=64):
        from ..build import build_model

        if jacobian not in JACOBIANS:
            raise ValueError(f"jacobian = {jacobian!r}: must be one of {', '.join(JACOBIANS)}")
        if motion is None and period is None:
            period = crank_period(config) * int(periods)
        if period is None:
            raise ValueError("a user motion needs its period: pass period = T [s]")
        if not (period > 0 and math.isfinite(period)):
            raise ValueError(f"period = {period}: must be a positive number of seconds")
        s = config.solver
        solver = replace(s, rtol=min(s.rtol, SHOOTING_RTOL), atol=min(s.atol, SHOOTING_ATOL), t_end=float(period),
                         output_step=float(period) / samples)
        self.config = config.replace(solver=solver)
        self.user_output_step = s.output_step
        self.period = float(period)
        self.jacobian = jacobian
        self.motion = motion
        self.model = build_model(self.config, motion)
        self.n = self.model.initial_state().size  # 2N planar, 6N spatial
        self.spatial = config.beam.model == "spatial"
        self._scale = None
        self._last = None  # (state bytes, run): the last period integrated
        #: The map's relative accuracy, for the steps of differences of the map (:mod:`.shooting`).
        self.accuracy = self.config.solver.rtol
        self.monitored = config.film.enabled or config.contact.law != "none"

    # --- the map ------------------------------------------------------------------------------------
    def run(self, y0, t_end=None, config=None):
        """The :class:`~lubelink.simulate.Run` from ``y0`` over one period (or to ``t_end``; with the tolerances of
        ``config`` if given); MapFailure if it ends early."""
        from ..simulate import run

        y0 = np.asarray(y0, dtype=float)
        if not np.all(np.isfinite(y0)):
            raise MapFailure("the state is not finite")
        if self.monitored and self.model.gap(0.0, self.model.to_state(y0)) < 0.0:
            raise MapFailure(f"the state at t = 0 lies inside the contact (the film is thinner than "
                             f"contact.min_film = {self.config.contact.min_film} m)")
        config = self.config if config is None else config
        if t_end is not None:
            config = config.replace(solver=replace(config.solver, t_end=float(t_end)))
        r = run(config, model=self.model, y0=y0)
        if not r.complete:
            raise MapFailure(f"{r.status}: {r.message}")
        return r

    def __call__(self, y0, jacobian=False) -> MapValue:
        """The state one period after ``y0``, with the monodromy matrix if asked for (``"checked"``: and its check).

        The variational equations (``"auto"``; through impacts with their saltation matrices,
        :meth:`jumps`), else central differences of the map at :data:`DIFFERENCE_RTOL`
        (:meth:`differences`); ``info["jacobian"]`` says which (``"variational"``,
        ``"variational+saltation"``, ``"finite-difference"``), ``info["jacobian_note"]`` why ``"auto"``
        took differences in a period with events.
        """
        y0 = np.asarray(y0, dtype=float)
        key = y0.tobytes()
        r = self._last[1] if self._last is not None and self._last[0] == key else self.run(y0)
        self._last = (key, r)
        events = len(r.impacts)
        info = {"t": r.t, "y": r.y, "events": events, "nfev": r.nfev}
        J = check = None
        if jacobian:
            if self._scale is None:
                self._scale = self._scale_of(r.y)
            checked = jacobian == "checked"
            note = ""
            if self.jacobian in ("auto", "variational"):
                rtol = self.config.solver.rtol
                try:
                    jumps = self.jumps(r) if events else []
                    J = self.variational(y0, rtol if checked else max(rtol, NEWTON_RTOL), r, jumps)
                    if checked:  # the check's difference scaled to the error at rtol (see CHECK_FACTOR)
                        check = J + (self._loose(y0, r, jumps) - J) / math.sqrt(CHECK_FACTOR)
                except (Unsupported, Grazing) as exc:
                    if self.jacobian == "variational":
                        raise MapFailure(f"jacobian = 'variational': {exc}; use 'auto' or 'finite-difference'") from None
                    note = f"finite differences: {exc}"
                    J = check = None
                else:
                    info["jacobian"] = "variational+saltation" if events else "variational"
            if J is None:
                J, count, check = self.differences(y0, checked)
                info["jacobian"], info["evaluations"] = "finite-difference", count
            info["jacobian_note"] = note
        return MapValue(np.array(r.y[-1], dtype=float), J, info, check)

    def _loose(self, y0, run, jumps):
        """The monodromy at :data:`CHECK_FACTOR` times the tolerances, for the check: the variational
        equations, and with events the period's run as well (so that its events, their times and states,
        and their saltation matrices move by their own errors at that tolerance)."""
        rtol = CHECK_FACTOR * self.config.solver.rtol
        if not jumps:
            return self.variational(y0, rtol, run, jumps)
        s = self.config.solver
        loose = self.config.replace(solver=replace(s, rtol=rtol, atol=CHECK_FACTOR * s.atol))
        r = self.run(y0, config=loose)
        if len(r.impacts) != len(run.impacts) or len(r.contacts) != len(run.contacts):  # (a Zeno cascade's count)
            return self.variational(y0, rtol, run, jumps)
        return self.variational(y0, rtol, r, self.jumps(r))

    def variational(self, y0, rtol=None, run=None, jumps=()):
        """The monodromy matrix ``dy(T)/dy0`` from the variational equations, compiled
        (:func:`~.variational.flow_with_jacobian`), at the map's tolerances or ``rtol``.

        With the events ``jumps`` of ``run`` (the period from ``y0``, :meth:`jumps`: pairs of a
        :class:`lubelink.phases.Event` and its saltation matrix), the stretches between events are
        integrated one by one, each in its contact phase, from the run's state after the event (or
        where the last stretch arrived), and composed with the saltation matrices
        (:func:`.saltation.compose`). Through a contact phase the state is augmented by the phase's
        parameter (:mod:`lubelink.phases`): the matrices are then ``n + 1`` square and the result their
        ``y`` block.
        """
        from .variational import flow_with_jacobian

        s = self.config.solver
        rtol = s.rtol if rtol is None else rtol
        model = self.model
        n = self.n
        eye = np.eye(n)
        to_state, to_physical = model.to_state(eye).T, model.to_physical(eye).T
        starts = [(0.0, np.asarray(y0, dtype=float), None, None)]
        starts += [(ev.t, ev.y_after, ev.phase, ev.parameter) for ev, _ in jumps]
        ends = [t for t, *_ in starts[1:]] + [self.period]
        flows = []
        y_end = None
        for (t0, y_start, phase, parameter), t1 in zip(starts, ends):
            y_start = y_end if y_start is None else y_start
            if t1 <= t0:  # an event at the start of the period, or two at one instant
                flows.append(np.eye(n + 1))
                y_end = y_start
                continue
            extra = None
            if parameter is not None:
                P, h = parameter.value, parameter.step
                extra = (model.with_phase(parameter.phase(P + 0.5 * h)), model.with_phase(parameter.phase(P - 0.5 * h)),
                         h, parameter.size)
            try:
                y1, M, _ = flow_with_jacobian(model.functions()[0], model.with_phase(phase), t0,
                                              model.to_state(y_start), t1, self.scale(), rtol=rtol,
                                              atol=s.atol * rtol / s.rtol, jacobian=not model.jacobian_missing(phase),
                                              p_type=model.params_type if model.compiled else None,
                                              compiled=model.compiled, parameter=extra)
            except RuntimeError as exc:
                raise MapFailure(str(exc)) from None
            A = np.eye(n + 1)
            A[:n, :M.shape[1]] = M
            if not model.uniform:  # eigen-coordinates -> sine modes
                A[:n, :n] = to_physical @ A[:n, :n] @ to_state
                A[:n, n] = to_physical @ A[:n, n]
            flows.append(A)
            y_end = model.to_physical(y1)
        return compose(flows, [S for _, S in jumps])[:n, :n]

    def jumps(self, run):
        """The events of ``run`` with their saltation matrices: ``(event, S)`` pairs (:func:`lubelink.phases.period_events`;
        ``S`` of the state augmented by a contact phase's parameter, ``n + 1`` square), for :meth:`variational`.

        Raises :class:`Unsupported` for events without one (:func:`lubelink.jumps.unsupported`) and
        :class:`~.saltation.Grazing` at a graze.
        """
        from ..jumps import unsupported
        from ..phases import period_events

        why = unsupported(self.model, run)
        if why:
            raise Unsupported(why)
        scale = self.scale()
        N = self.n // 2
        rate_scale = np.concatenate([scale[N:], scale[N:] * float(np.max(self.model.state_frequencies)), [0.0]])
        out = []
        for event in period_events(self.model, run, scale, self.period / (2.0 * math.pi)):
            S = np.eye(self.n + 1) if event.terms is None else saltation_matrix(*event.terms, rate_scale,
                                                                                 event.grazing, where=event.where)
            out.append((event, S))
        return out

    def differences(self, y0, check=False):
        """``(M, evaluations, M_check)``: the monodromy matrix by central differences of the map.

        With ``check`` (the multipliers' matrix) the runs take the tolerances
        :data:`DIFFERENCE_RTOL`, :data:`DIFFERENCE_ATOL` (or the configuration's, if tighter), the
        steps :func:`~.shooting.difference_step` of that accuracy times the scale, and steps twice
        as long for ``M_check``; without (a Newton step's), the map's own tolerances.
        """
        from .shooting import difference_step, finite_difference_jacobian

        s = self.config.solver
        rtol = min(s.rtol, DIFFERENCE_RTOL) if check else s.rtol
        fine = self.config.replace(solver=replace(s, rtol=rtol, atol=min(s.atol, DIFFERENCE_ATOL) if check else s.atol))

        def fmap(y, jacobian=False):
            return MapValue(np.array(self.run(y, config=fine).y[-1], dtype=float))

        return finite_difference_jacobian(fmap, np.asarray(y0, dtype=float), self.scale(), difference_step(rtol),
                                          check=check)

    # --- sizes ------------------------------------------------------------------------------------
    def scale(self, y=None):
        """Size of each state component [m, m/s]: the peak ``|q|`` and ``|q_dot|`` of an orbit.

        From the orbit through ``y`` when given (the scale is then fixed), else from the first
        orbit asked for, or from one period from rest.
        """
        if y is not None or self._scale is None:
            self._scale = self._scale_of(self.run(np.zeros(self.n) if y is None else y).y)
        return self._scale

    def _scale_of(self, samples):
        N = self.n // 2
        d = max(float(np.max(np.abs(samples[:, :N]))), 1e-9)
        v = max(float(np.max(np.abs(samples[:, N:]))), d * 2.0 * math.pi / self.period)
        return np.concatenate([np.full(N, d), np.full(N, v)])

    def set_scale(self, scale):
        self._scale = np.asarray(scale, dtype=float)


class Family:
    """The period map as a function of one parameter ``section.key`` (e.g. ``mechanism.crank_speed``).

    ``family(value)`` is the :class:`PeriodMap` at that value (the last few are kept); for the
    slider-crank the period follows the crank speed. Invalid values raise
    :class:`~lubelink.config.ConfigError`.
    """

    def __init__(self, config, parameter, motion=None, period=None, periods=1, jacobian="auto", samples=64):
        section, _, key = parameter.partition(".")
        if not key or not hasattr(getattr(config, section, None), key):
            from ..config import ConfigError
            from ..errors import suggest

            names = [f"{s}.{k}" for s in ("mechanism", "beam", "film", "collar", "contact", "solver")
                     for k in getattr(config, s).__dataclass_fields__]
            raise ConfigError([f"parameter = {parameter!r}: not a configuration key{suggest(parameter, names)}"])
        value = getattr(getattr(config, section), key)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            from ..config import ConfigError

            raise ConfigError([f"parameter = {parameter!r}: {value!r} is not a number; continuation needs a "
                               "real parameter"])
        self.config = config
        self.parameter = parameter
        self.value0 = float(value)
        self.kwargs = dict(motion=motion, period=period, periods=periods, jacobian=jacobian, samples=samples)
        self._cache = {}
        self._params_type = None

    def config_at(self, value):
        """The validated configuration with the parameter at ``value``."""
        from ..config import validate

        section, _, key = self.parameter.partition(".")
        part = replace(getattr(self.config, section), **{key: float(value)})
        return validate(self.config.replace(**{section: part}))

    def __call__(self, value) -> PeriodMap:
        value = float(value)
        found = self._cache.get(value)
        if found is None:
            found = PeriodMap(self.config_at(value), **self.kwargs)
            if self._params_type is None:
                self._params_type = found.model.params_type
            else:  # one real parameter changed: the same Numba type (typeof of the tuple costs ~1 ms)
                found.model.__dict__["params_type"] = self._params_type
            if len(self._cache) >= 4:
                self._cache.pop(next(iter(self._cache)))
            self._cache[value] = found
        return found

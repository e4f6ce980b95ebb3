"""lubelink's period map: the model's flow over one period of the rigid motion, for the shooting code.

:class:`PeriodMap` is the one place where the periodic machinery meets the model. Its value at a
state ``y0`` (at t = 0) is the state one period later, computed by :func:`lubelink.simulate.run`
from ``y0``, so that film breakdown and impacts are handled by the same
:class:`~lubelink.contact.ContactLogic` as in any run: a period with impacts is the composition of
the smooth flows and the impact maps. Its Jacobian (the monodromy matrix) comes from the
variational equations integrated with the state (:mod:`.variational`) when the period is smooth
(no contact event in it), or is left to finite differences of the map (:mod:`.shooting`) when an
event occurs, since the variational equations would then need the saltation matrix of every
impact.

:class:`Family` is the map as a function of one parameter ``section.key``; the period follows the
parameter (``T = 2 pi / |crank_speed|``), i.e. the map is taken over a fixed interval of crank
phase, so a change of crank speed changes the period of the map as well as the loads.

The state is the model's whole integration state: ``[q, q_dot]`` (``2 N``) of the planar model,
``[q1, q2, q3, q1_t, q2_t, q3_t]`` (``6 N``) of the spatial one (``beam.model = "spatial"``,
:mod:`lubelink.link.spatial_model`); nothing here depends on which. For the spatial model ``"auto"``
takes the monodromy matrix by finite differences even in a smooth period: the variational
equations are integrated in Python by an explicit method, whose step the axial modes (8 krad/s
and up with the free axial end, 16 with the fixed one) limit, while the map itself runs compiled (the
configuration's ``solver.method``; docs/periodic.md, "The spatial model", compares the accuracy of the
differences under the exponential method and under DOP853).

Shooting tightens the solver tolerances to at least ``rtol = 1e-10``, ``atol = 1e-13`` [m, m/s]:
Newton's method and the finite-difference Jacobians need a map accurate well beyond plotting.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from .shooting import MapFailure, MapValue

__all__ = ["PeriodMap", "Family", "crank_period", "SHOOTING_RTOL", "SHOOTING_ATOL", "JACOBIANS"]

#: Loosest tolerances of the map's integration (a configuration's tighter ones are kept).
SHOOTING_RTOL = 1e-10
SHOOTING_ATOL = 1e-13
#: How the monodromy matrix is obtained: ``"auto"`` (variational equations when no contact event
#: occurs in the period, else finite differences; always finite differences for the spatial model),
#: ``"variational"``, ``"finite-difference"``.
JACOBIANS = ("auto", "variational", "finite-difference")


def crank_period(config) -> float:
    """Period of the slider-crank's motion, ``2 pi / |omega0|`` [s]."""
    return 2.0 * math.pi / abs(config.mechanism.crank_speed)


def _fast_rhs(model):
    """The model's right-hand side, called from Python without Numba's type dispatch when compiled."""
    rhs = model.functions()[0]
    if not model.compiled:
        return rhs
    try:
        from numba import types

        f8 = types.float64
        sig = (f8, f8[::1], f8[::1], model.params_type)
        rhs.compile(sig)
        return rhs.overloads[sig].entry_point
    except Exception:  # another Numba layout: the dispatcher itself (slower, same result)
        return rhs


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
        self._rhs = None
        self._scale = None
        self.monitored = config.film.enabled or config.contact.law != "none"

    # --- the map ------------------------------------------------------------------------------------
    def run(self, y0, t_end=None):
        """The :class:`~lubelink.simulate.Run` from ``y0`` over one period (or to ``t_end``); MapFailure if it ends early."""
        from ..simulate import run

        y0 = np.asarray(y0, dtype=float)
        if not np.all(np.isfinite(y0)):
            raise MapFailure("the state is not finite")
        if self.monitored and self.model.gap(0.0, self.model.to_state(y0)) < 0.0:
            raise MapFailure(f"the state at t = 0 lies inside the contact (the film is thinner than "
                             f"contact.min_film = {self.config.contact.min_film} m)")
        config = self.config
        if t_end is not None:
            config = config.replace(solver=replace(config.solver, t_end=float(t_end)))
        r = run(config, model=self.model, y0=y0)
        if not r.complete:
            raise MapFailure(f"{r.status}: {r.message}")
        return r

    def __call__(self, y0, jacobian=False) -> MapValue:
        """The state one period after ``y0``, with the monodromy matrix if asked for and available."""
        r = self.run(y0)
        events = len(r.impacts)
        info = {"t": r.t, "y": r.y, "events": events, "nfev": r.nfev}
        J = None
        if jacobian and (self.jacobian == "variational" or (self.jacobian == "auto" and not self.spatial)):
            if events == 0:
                J = self.variational(y0)
            elif self.jacobian == "variational":
                raise MapFailure(f"jacobian = 'variational': {events} contact event(s) in the period; the "
                                 "variational equations do not cross impacts, use 'auto' or 'finite-difference'")
        return MapValue(np.array(r.y[-1], dtype=float), J, info)

    def variational(self, y0):
        """The monodromy matrix ``dy(T)/dy0`` from the variational equations (a smooth period)."""
        from .variational import flow_with_jacobian

        if self._rhs is None:
            self._rhs = _fast_rhs(self.model)
        s = self.config.solver
        try:
            _, M, _ = flow_with_jacobian(self._rhs, self.model.with_phase(None), 0.0, self.model.to_state(y0),
                                         self.period, self.scale(), rtol=s.rtol, atol=s.atol,  # eta ~ q in size
                                         jacobian=not self.model.jacobian_missing(None))
        except RuntimeError as exc:
            raise MapFailure(str(exc)) from None
        if not self.model.uniform:  # the integrator's eigen-coordinates -> the sine modes of the map
            eye = np.eye(self.n)
            M = self.model.to_physical(eye).T @ M @ self.model.to_state(eye).T
        return M

    # --- sizes ------------------------------------------------------------------------------------
    def scale(self, y=None):
        """Size of each state component [m, m/s]: the peak ``|q|`` and ``|q_dot|`` of an orbit.

        From the orbit through ``y`` when given (the scale is then fixed), else from the first
        orbit asked for, or from one period from rest.
        """
        if y is not None or self._scale is None:
            samples = self.run(np.zeros(self.n) if y is None else y).y
            N = self.n // 2
            d = max(float(np.max(np.abs(samples[:, :N]))), 1e-9)
            v = max(float(np.max(np.abs(samples[:, N:]))), d * 2.0 * math.pi / self.period)
            self._scale = np.concatenate([np.full(N, d), np.full(N, v)])
        return self._scale

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

"""The periodic response of one configuration: shooting, Floquet multipliers, and its results.

:func:`find_periodic` solves ``y(T; y0) = y0`` (:func:`~.shooting.shoot` on the
:class:`~.problem.PeriodMap`) and returns a :class:`PeriodicOrbit`; :func:`orbit_results` samples
one period of it into the usual results variables (:func:`lubelink.results.collect` on a run
from the periodic state) plus the Floquet multipliers; :func:`periodic` is the two in one, as an
:class:`xarray.Dataset`.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

import numpy as np

from ..results import Variable, variable
from . import floquet
from .problem import PeriodMap
from .shooting import MapFailure, ShootingError, shoot

__all__ = ["PeriodicOrbit", "find_periodic", "orbit_results", "periodic", "FLOQUET_VARIABLES", "SPATIAL_VARIABLES",
           "multiplier_directions"]

#: The variables a periodic response adds to those of :data:`lubelink.results.VARIABLES`.
FLOQUET_VARIABLES = {
    "multiplier": Variable(("multiplier",), "1", "Floquet multiplier, largest modulus first"),
    "floquet_modulus": Variable(("multiplier",), "1", "modulus of the Floquet multiplier"),
    "floquet_argument": Variable(("multiplier",), "rad", "argument of the Floquet multiplier, in (-pi, pi]"),
    "floquet_error": Variable(("multiplier",), "1", "accuracy estimate of the Floquet multiplier (its distance from "
                                                     "the same multiplier of a less accurate monodromy matrix)"),
}

#: What a periodic response of the spatial model adds (``beam.model = "spatial"``): the modal
#: coordinates of the other two directions (``q``, ``q_dot`` are the in-plane ones, as in every
#: results Dataset), so that the whole periodic state is in the file, and the direction of each
#: Floquet multiplier's eigenvector.
SPATIAL_VARIABLES = {
    "q1": Variable(("time", "mode"), "m", "axial modal coordinate (spatial model)"),
    "q1_dot": Variable(("time", "mode"), "m s-1", "axial modal velocity (spatial model)"),
    "q3": Variable(("time", "mode"), "m", "out-of-plane modal coordinate (spatial model)"),
    "q3_dot": Variable(("time", "mode"), "m s-1", "out-of-plane modal velocity (spatial model)"),
    "floquet_direction": Variable(("multiplier",), "1", "direction whose coordinates carry most of the Floquet "
                                                         "multiplier's eigenvector (scaled state)"),
}
#: ``floquet_direction`` codes (CF ``flag_values``/``flag_meanings``).
DIRECTIONS = {1: "axial", 2: "in_plane", 3: "out_of_plane"}


@dataclass
class PeriodicOrbit:
    """A periodic response found by shooting.

    Attributes
    ----------
    config : Config
        The configuration (with the tightened tolerances of the period map).
    period : float
        Its period [s].
    y0 : ndarray
        The periodic state at t = 0 [m, m/s]: ``[q, q_dot]``, or for the spatial model
        ``[q1, q2, q3, q1_t, q2_t, q3_t]``.
    monodromy : ndarray
        ``dy(T)/dy0`` [-].
    multipliers : ndarray
        Floquet multipliers (its eigenvalues), largest modulus first [-].
    multiplier_errors : ndarray
        Accuracy estimate of each multiplier [-] (:func:`.floquet.multiplier_errors`).
    jacobian : str
        How the monodromy matrix was obtained: ``"variational"``, ``"variational+saltation"`` (through
        impacts, :mod:`.saltation`) or ``"finite-difference"``.
    residual : float
        ``max |y(T) - y0| / scale`` of the last Newton iterate [-].
    iterations : int
        Newton steps.
    history : list
        Scaled residual before each Newton step and at the end.
    scale : ndarray
        The sizes of the state components that scale the residual [m, m/s].
    period_map : PeriodMap
        The map (its model, for sampling).
    evaluations : int
        Map evaluations of the successful attempt (each one period of integration).
    wall_time : float
        Wall-clock time of the search [s].
    warmup : int
        Periods of transient integrated before the successful attempt.
    jacobian_note : str
        Why ``"auto"`` took differences in a period with events (a graze, a compliant contact), else ``""``.
    """

    config: object
    period: float
    y0: np.ndarray
    monodromy: np.ndarray
    multipliers: np.ndarray
    multiplier_errors: np.ndarray
    jacobian: str
    residual: float
    iterations: int
    history: list
    scale: np.ndarray
    period_map: PeriodMap
    evaluations: int
    wall_time: float
    warmup: int = 0
    jacobian_note: str = ""

    @property
    def stable(self) -> bool:
        """Asymptotically stable: every multiplier inside the unit circle by more than its accuracy estimate."""
        return floquet.is_stable(self.multipliers, self.multiplier_errors)


def find_periodic(config, motion=None, *, period=None, periods=1, y0=None, warmup=0, restarts=2, jacobian="auto",
                  tol=1e-9, max_iter=30) -> PeriodicOrbit:
    """The ``T``-periodic response of a validated configuration, by shooting.

    Parameters
    ----------
    config : Config
        Validated configuration.
    motion : object, optional
        A motion provider replacing the slider-crank (then ``period`` is required).
    period : float, optional
        Period [s]; default ``periods * 2 pi / |omega0|``.
    periods : int
        Crank turns in the period (slider-crank only): 2 finds period-2 responses.
    y0 : array_like, optional
        Initial guess of the state at t = 0 (default: rest): ``2 N`` values ``[q, q_dot]``, or
        ``6 N`` ``[q1, q2, q3, q1_t, q2_t, q3_t]`` for the spatial model.
    warmup : int
        Periods of transient from ``y0`` before Newton's method starts.
    restarts : int
        When Newton's method fails, it starts again this many times at most, each time after
        ``8, 16, ...`` more periods of transient (which approach a stable response, and leave
        behind the impacts of the start-up that make the map non-smooth).
    jacobian : str
        ``"auto"`` (variational equations, with a saltation matrix at each impact; finite differences
        at a graze or a compliant or sustained contact), ``"variational"`` or ``"finite-difference"``.
    tol : float
        Scaled residual ``max |y(T) - y0| / scale`` at which Newton's method stops; ``scale``
        is the peak ``|q|`` and ``|q_dot|`` of the orbit through the initial guess.
    max_iter : int
        Most Newton steps of one attempt.

    Raises
    ------
    ShootingError
        No periodic response found; the message says how far Newton's method got.
    """
    began = time.perf_counter()
    pmap = PeriodMap(config, motion, period=period, periods=periods, jacobian=jacobian)
    if y0 is not None and np.size(y0) != pmap.n:
        layout = "[q1, q2, q3, q1_t, q2_t, q3_t]" if pmap.spatial else "[q, q_dot]"
        raise ValueError(f"y0: {np.size(y0)} values; the state of this model is {layout}, {pmap.n} values "
                         f"({config.beam.modes} mode(s))")
    y = np.zeros(pmap.n) if y0 is None else np.array(y0, dtype=float).reshape(pmap.n)
    done = 0  # periods of transient so far
    for attempt in range(restarts + 1):
        more = warmup if attempt == 0 else 8 * 2 ** (attempt - 1)
        try:
            if more:
                y = np.array(pmap.run(y, t_end=more * pmap.period).y[-1])
                done += more
            scale = pmap.scale(y)
            r = shoot(pmap, y, scale, tol=tol, max_iter=max_iter,
                      what=f"the {pmap.period:.6g} s periodic response")
            break
        except MapFailure as exc:  # the integration itself ends early: no restart helps
            raise ShootingError(f"no periodic response: the integration over a period ended early ({exc})") from None
        except ShootingError as exc:
            if attempt == restarts:
                raise ShootingError(f"{exc} [{attempt + 1} attempt(s), after {done} periods of transient]") from None
    mu = floquet.multipliers(r.jacobian)
    err = floquet.multiplier_errors(mu, r.jacobian_check)
    return PeriodicOrbit(pmap.config, pmap.period, r.y, r.jacobian, mu, err, r.jacobian_method, r.residual,
                         r.iterations, r.history, scale, pmap, r.evaluations, time.perf_counter() - began, done,
                         r.value.info.get("jacobian_note", ""))


def orbit_run(orbit: PeriodicOrbit, output_step=None):
    """``(run, config)``: one period from the periodic state, samples ``T/n`` apart, ending on ``t = T``.

    ``n`` is the nearest whole number to ``T / output_step`` (default: the configuration's
    ``solver.output_step``), at least 16.
    """
    from ..simulate import run

    step = output_step or orbit.period_map.user_output_step
    n = max(16, int(round(orbit.period / step)))
    config = orbit.config.replace(solver=replace(orbit.config.solver, t_end=orbit.period,
                                                 output_step=orbit.period / n))
    return run(config, model=orbit.period_map.model, y0=orbit.y0), config


def orbit_results(orbit: PeriodicOrbit, output_step=None):
    """One period of ``orbit`` as :class:`~lubelink.results.Results`: the usual variables and the multipliers.

    For the spatial model also the variables of :data:`SPATIAL_VARIABLES` (``q1``, ``q3``,
    ``q1_dot``, ``q3_dot``, ``floquet_direction``) beside its usual ``u1``, ``u3``, ``u3_mid``.
    Attributes added: ``period`` [s], ``residual`` (scaled, of the sampled period), ``residual_q``
    [m] (every displacement coordinate), ``residual_q_dot`` [m/s], ``iterations``, ``stable`` (1/0), ``jacobian``, ``jacobian_note``,
    ``floquet_max_modulus``, ``newton_residuals``, ``map_evaluations``.
    """
    from ..results import Results, collect

    began = time.perf_counter()
    r, config = orbit_run(orbit, output_step)
    res = collect(r)
    N = orbit.y0.size // 2
    end = r.y[-1]
    gap = end - orbit.y0
    data = dict(res.data_vars)
    coords = dict(res.coords)
    mu = orbit.multipliers
    coords["multiplier"] = _entry("multiplier", np.arange(1, mu.size + 1))
    data["floquet_modulus"] = _entry("floquet_modulus", np.abs(mu))
    data["floquet_argument"] = _entry("floquet_argument", np.angle(mu))
    data["floquet_error"] = _entry("floquet_error", orbit.multiplier_errors)
    if orbit.period_map.spatial:
        _add_spatial(data, r.y, orbit)
    attrs = dict(res.attrs)
    from ..config import to_toml

    attrs.update({
        "title": "lubelink periodic response of a flexible link with a lubricated prismatic joint",
        "config": to_toml(config),
        "period": orbit.period,
        "residual": float(np.max(np.abs(gap / orbit.scale))),
        "residual_q": float(np.max(np.abs(gap[:N]))),
        "residual_q_dot": float(np.max(np.abs(gap[N:]))),
        "iterations": orbit.iterations,
        "stable": int(orbit.stable),
        "jacobian": orbit.jacobian,
        "jacobian_note": orbit.jacobian_note,
        "floquet_max_modulus": floquet.max_modulus(mu),
        "floquet_undecided": floquet.undecided(mu, orbit.multiplier_errors),
        "newton_residuals": ", ".join(f"{h:.3g}" for h in orbit.history),
        "map_evaluations": orbit.evaluations,
        "warmup_periods": orbit.warmup,
        "wall_time": orbit.wall_time + time.perf_counter() - began,
    })
    return Results(data, coords, attrs)


def _entry(name, data, **attrs):
    v = FLOQUET_VARIABLES.get(name) or SPATIAL_VARIABLES[name]
    return variable(v.dims, data, v.units, v.long_name, **attrs)


def multiplier_directions(monodromy, scale, mu):
    """The direction of each Floquet multiplier ``mu`` (eigenvalues of ``monodromy``): 1 (axial), 2
    (in-plane) or 3 (out-of-plane), the one whose coordinates and velocities carry most of its
    eigenvector in the scaled spatial state ``y / scale``, ``y = [q1, q2, q3, q1_t, q2_t, q3_t]``.

    In planar motion the out-of-plane block is decoupled from the rest: the eigenvectors of its
    multipliers lie wholly in direction 3.
    """
    import scipy.linalg

    scale = np.asarray(scale, dtype=float)
    A = np.asarray(monodromy, dtype=float) * scale[None, :] / scale[:, None]  # D^-1 M D: the same eigenvalues
    lam, V = scipy.linalg.eig(A)
    N = scale.size // 6
    weight = np.abs(V) ** 2
    blocks = np.stack([weight[k * N:(k + 1) * N].sum(axis=0) + weight[(3 + k) * N:(4 + k) * N].sum(axis=0)
                       for k in range(3)])
    direction = np.argmax(blocks, axis=0) + 1
    free = list(range(lam.size))
    out = np.empty(len(mu), dtype=np.int8)
    for i, m in enumerate(mu):  # each multiplier matched to the nearest eigenvalue not yet taken
        j = min(free, key=lambda k: abs(lam[k] - m))
        free.remove(j)
        out[i] = direction[j]
    return out


def _add_spatial(data, y, orbit):
    """The spatial variables of :data:`SPATIAL_VARIABLES` from the sampled states ``y`` ``(time, 6 N)``."""
    N = y.shape[1] // 6
    for name, k in (("q1", 0), ("q3", 2), ("q1_dot", 3), ("q3_dot", 5)):
        data[name] = _entry(name, y[:, k * N:(k + 1) * N])
    direction = multiplier_directions(orbit.monodromy, orbit.scale, orbit.multipliers)
    data["floquet_direction"] = _entry("floquet_direction", direction, flag_values=np.array([1, 2, 3], dtype=np.int8),
                                       flag_meanings=" ".join(DIRECTIONS.values()))


def periodic(source="paper", set=None, *, motion=None, period=None, periods=1, y0=None, warmup=0, restarts=2,
             jacobian="auto", tol=1e-9, max_iter=30):
    """The periodic steady state of a configuration, with its Floquet multipliers.

    Shooting (Newton's method on ``y(T; y0) - y0 = 0``, damped by step halving) finds the state
    at t = 0 of the ``T``-periodic response, ``T = 2 pi / |omega0|`` for the slider-crank. The
    monodromy matrix comes from the variational equations integrated with the state, or from
    finite differences of the period map when a contact event (impact) occurs in the period;
    ``attrs["jacobian"]`` says which. Films (wedge, squeeze, cavitation, two sides) and impacts
    (the restitution or compliant law inside the period) are handled as in :func:`lubelink.simulate`.

    Parameters
    ----------
    source, set
        The configuration, as for :func:`lubelink.simulate`.
    motion : object, optional
        A motion provider replacing the slider-crank; ``period`` [s] is then required.
    period, periods, y0, warmup, restarts, jacobian, tol, max_iter
        See :func:`find_periodic`.

    Returns
    -------
    xarray.Dataset
        One period (``time`` from 0 to ``T``) of the variables of :func:`lubelink.simulate`,
        plus ``floquet_modulus(multiplier)``, ``floquet_argument(multiplier)`` and
        ``floquet_error(multiplier)``, each multiplier's accuracy estimate (and for the
        spatial model ``q1``, ``q3``, ``q1_dot``, ``q3_dot`` and ``floquet_direction``); attrs
        ``period`` [s], ``residual`` (scaled ``max |y(T) - y0|``; ``residual_q`` [m] and
        ``residual_q_dot`` [m/s] unscaled), ``iterations``, ``stable`` (1 if every multiplier is
        inside the unit circle by more than its accuracy estimate, else 0), ``jacobian``.

    Raises
    ------
    lubelink.ConfigError
        Invalid parameters.
    ShootingError
        No periodic response found.
    """
    from ..config import resolve
    from ..results import dataset

    config = resolve(source, set)
    orbit = find_periodic(config, motion, period=period, periods=periods, y0=y0, warmup=warmup, restarts=restarts,
                          jacobian=jacobian, tol=tol, max_iter=max_iter)
    return dataset(orbit_results(orbit))

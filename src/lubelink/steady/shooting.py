"""Shooting: a fixed point of a map ``y -> P(y)`` by a damped Newton method.

Nothing here knows what the map is. A *map* is a callable ``fmap(y, jacobian) -> MapValue``:
``MapValue.y`` is ``P(y)``, ``MapValue.jacobian`` is ``dP/dy`` when ``jacobian`` was asked for
and the map could compute it (for a flow map: the monodromy matrix from the variational
equations), else None, and then :func:`finite_difference_jacobian` differentiates the map
itself. A map that cannot be evaluated at ``y`` raises :class:`MapFailure`.

All norms are of the scaled vector ``v / scale`` (max norm), so that components of different
units and sizes weigh alike.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["MapValue", "MapFailure", "ShootingError", "ShootingResult", "finite_difference_jacobian",
           "jacobian_of", "shoot"]


@dataclass
class MapValue:
    """One evaluation of a map: ``y`` = P(y0), its ``jacobian`` dP/dy0 or None, and what the map reports."""

    y: np.ndarray
    jacobian: np.ndarray | None = None
    info: dict = field(default_factory=dict)


class MapFailure(RuntimeError):
    """The map cannot be evaluated at this point (e.g. the integration stopped early)."""


class ShootingError(RuntimeError):
    """Newton's method found no fixed point; the message says how far it got and what to try."""


@dataclass
class ShootingResult:
    """A fixed point ``y`` of the map and what it took.

    ``value`` is the map at ``y`` (``value.y`` = P(y)); ``jacobian`` dP/dy at ``y`` and
    ``jacobian_method`` how it was obtained (``"variational"``: given by the map,
    ``"finite-difference"``); ``residual`` the scaled max norm of P(y) - y; ``iterations`` the
    Newton steps taken; ``history`` the residual before each step and at the end.
    """

    y: np.ndarray
    value: MapValue
    jacobian: np.ndarray
    jacobian_method: str
    residual: float
    iterations: int
    history: list
    evaluations: int


def _norm(v, scale):
    return float(np.max(np.abs(v / scale))) if v.size else 0.0


def finite_difference_jacobian(fmap, y, scale, step=1e-5, central=True, value=None):
    """``dP/dy`` by finite differences of the map, steps ``step * scale`` per component.

    Parameters
    ----------
    fmap : callable
        The map, ``fmap(y, jacobian=False) -> MapValue``.
    y : ndarray, shape ``(n,)``
        Where.
    scale : ndarray, shape ``(n,)``
        Size of each component (the step is ``step * scale``).
    step : float
        Relative step [-]: about the cube root (central) or square root (forward) of the map's
        relative accuracy.
    central : bool
        Central differences (``2n`` evaluations, error ``O(step^2)``) or forward (``n``, using
        ``value`` = P(y) if given).

    Returns
    -------
    jacobian : ndarray, shape ``(n, n)``
    evaluations : int
    """
    n = y.size
    J = np.empty((n, n))
    count = 0
    if not central and value is None:
        value = fmap(y, False).y
        count += 1
    for j in range(n):
        h = step * scale[j]
        e = np.zeros(n)
        e[j] = h
        plus = fmap(y + e, False).y
        if central:
            J[:, j] = (plus - fmap(y - e, False).y) / (2.0 * h)
            count += 2
        else:
            J[:, j] = (plus - value) / h
            count += 1
    return J, count


def jacobian_of(fmap, y, value, scale, fd_step=1e-5):
    """``(dP/dy, method, evaluations)`` at ``y``: the map's own if ``value`` carries it, else by central differences."""
    if value.jacobian is not None:
        return value.jacobian, "variational", 0
    J, count = finite_difference_jacobian(fmap, y, scale, fd_step, central=True)
    return J, "finite-difference", count


def shoot(fmap, y0, scale, *, tol=1e-9, max_iter=30, fd_step=1e-5, min_damping=1.0 / 1024, what="the map"):
    """A fixed point ``P(y) = y`` by Newton's method on ``P(y) - y``, damped by step halving.

    Each step solves ``(dP/dy - I) dy = -(P(y) - y)`` and takes the longest of ``dy, dy/2,
    dy/4, ...`` that reduces the scaled residual (Armijo: by at least the fraction ``lambda/4``
    of it), down to ``min_damping``.

    Parameters
    ----------
    fmap : callable
        ``fmap(y, jacobian) -> MapValue`` (see the module docstring).
    y0 : array_like, shape ``(n,)``
        Initial guess.
    scale : array_like, shape ``(n,)``
        Size of each component; the residual is ``max |P(y) - y| / scale``.
    tol : float
        Converged when the scaled residual is below ``tol``.
    max_iter : int
        Most Newton steps.
    fd_step : float
        Relative step of the finite-difference Jacobian, when the map gives none.
    what : str
        What is being solved for, in error messages.

    Returns
    -------
    ShootingResult

    Raises
    ------
    ShootingError
        No convergence: the message gives the residual reached and what to try.
    MapFailure
        The map fails at the initial guess itself.
    """
    scale = np.asarray(scale, dtype=float)
    y = np.array(y0, dtype=float)
    n = y.size
    value = fmap(y, True)
    evaluations = 1
    asked = True  # whether value was computed with the Jacobian asked for
    res = _norm(value.y - y, scale)
    history = [res]
    iterations = 0
    while res >= tol:
        if iterations >= 8 and res > 0.5 * history[-8]:
            raise ShootingError(
                f"shooting for {what} stagnates: scaled residual {res:.3g} after {iterations} Newton steps, "
                f"halved less than once in the last 7 (residuals {_history(history)}): the initial state is "
                "far from the periodic response, or the map is not smooth near it; try warmup periods of "
                "transient first, or a nearby solution")
        if iterations >= max_iter:
            raise ShootingError(
                f"shooting for {what} did not converge: scaled residual {res:.3g} after {iterations} Newton "
                f"steps (tolerance {tol:.3g}; residuals {_history(history)}). The periodic response may not "
                "exist here, or the map is not smooth near it (impacts appearing or vanishing); try a better "
                "initial state (warmup periods of transient), some damping, or a nearby solution")
        if not asked:
            value, asked = fmap(y, True), True
            evaluations += 1
        J, method, count = jacobian_of(fmap, y, value, scale, fd_step)
        evaluations += count
        r = value.y - y
        A = (J - np.eye(n)) * scale[None, :] / scale[:, None]  # scaled, D^-1 (J - I) D with D = diag(scale)
        cond = np.linalg.cond(A)
        if not np.isfinite(cond) or cond > 1e13:
            raise ShootingError(
                f"shooting for {what}: dP/dy - I is singular (condition number {cond:.3g}): a Floquet "
                "multiplier is 1, as at a resonance k omega0 = omega_n without damping or at a fold; no "
                "isolated periodic response there (add damping or move the parameter)")
        dz = np.linalg.solve(A, -r / scale)
        dy = dz * scale
        lam = 1.0
        while True:
            trial_y = y + lam * dy
            try:
                trial = fmap(trial_y, False)
                evaluations += 1
                trial_res = _norm(trial.y - trial_y, scale)
            except MapFailure as exc:
                trial, trial_res, why = None, math.inf, str(exc)
            else:
                why = ""
            if trial_res <= (1.0 - 0.25 * lam) * res or trial_res < tol:
                break
            lam *= 0.5
            if lam < min_damping:
                raise ShootingError(
                    f"shooting for {what}: no step along the Newton direction reduces the scaled residual "
                    f"{res:.3g} (step halved {int(round(math.log2(1 / min_damping)))} times, after {iterations} "
                    f"steps; residuals {_history(history)})" + (f"; the map failed: {why}" if why else "")
                    + ". The map is not smooth near here (impacts appearing or vanishing, or a film "
                    "breakdown), or the initial state is too far; try warmup periods of transient first")
        y, value, res, asked = trial_y, trial, trial_res, False
        iterations += 1
        history.append(res)
    if not asked:
        value = fmap(y, True)
        evaluations += 1
    J, method, count = jacobian_of(fmap, y, value, scale, fd_step)
    evaluations += count
    return ShootingResult(y, value, J, method, res, iterations, history, evaluations)


def _history(history):
    return ", ".join(f"{h:.2g}" for h in history[-6:])

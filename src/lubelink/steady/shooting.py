"""Shooting: a fixed point of a map ``y -> P(y)`` by a damped Newton method.

Nothing here knows what the map is. A *map* is a callable ``fmap(y, jacobian) -> MapValue``:
``MapValue.y`` is ``P(y)``, ``MapValue.jacobian`` is ``dP/dy`` when ``jacobian`` was asked for
and the map could compute it (for a flow map: the monodromy matrix from the variational
equations), else None, and then :func:`finite_difference_jacobian` differentiates the map
itself. ``jacobian = "checked"`` asks for a second, less accurate ``dP/dy`` as well
(``MapValue.jacobian_check``), from which :func:`.floquet.multiplier_errors` estimates the
multipliers' accuracy. A map that cannot be evaluated at ``y`` raises :class:`MapFailure`.

Newton's method takes the Jacobian at the first iterate and then updates it by Broyden's formula
after each step (one evaluation of the map a step), taking a fresh one only after a step that
reduced the residual by less than the factor :data:`REFRESH`; the Jacobian at the fixed point,
for the multipliers, is always computed anew and checked.

All norms are of the scaled vector ``v / scale`` (max norm), so that components of different
units and sizes weigh alike.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["MapValue", "MapFailure", "ShootingError", "ShootingResult", "finite_difference_jacobian",
           "jacobian_of", "shoot", "difference_step", "REFRESH", "CHECK_SAFETY"]

#: A Newton step that reduces the scaled residual by less than this factor makes the next step take a
#: fresh Jacobian instead of Broyden's update of the last one.
REFRESH = 0.1
#: The check of a Jacobian by differences is this many times the difference between the steps ``h`` and
#: ``2 h`` (:func:`finite_difference_jacobian`): measured on the damped 3-mode dry link, the moduli's
#: errors were up to 2 times that difference (1.8e-10 against 9.2e-11).
CHECK_SAFETY = 3.0


def difference_step(accuracy, central=True) -> float:
    """The relative step of a difference quotient of a map accurate to ``accuracy`` (relative) [-].

    The truncation error, ``h^2 |P'''| / 6`` (central) or ``h |P''| / 2`` (forward), against the
    error the map's own carries into the quotient, ``accuracy / h``: the two balance at
    ``h = (3 accuracy)^(1/3)`` (central) or ``(2 accuracy)^(1/2)`` (forward) for derivatives of
    the size of the scaled map's.
    """
    return (3.0 * accuracy) ** (1.0 / 3.0) if central else math.sqrt(2.0 * accuracy)


@dataclass
class MapValue:
    """One evaluation of a map: ``y`` = P(y0), its ``jacobian`` dP/dy0 or None, and what the map reports.

    ``jacobian_check`` is a second, less accurate ``dP/dy0`` when one was asked for (``"checked"``);
    ``info["jacobian"]`` may name how the map got its Jacobian (default ``"variational"``) and
    ``info["evaluations"]`` how many more evaluations of the map that took.
    """

    y: np.ndarray
    jacobian: np.ndarray | None = None
    info: dict = field(default_factory=dict)
    jacobian_check: np.ndarray | None = None


class MapFailure(RuntimeError):
    """The map cannot be evaluated at this point (e.g. the integration stopped early)."""


class ShootingError(RuntimeError):
    """Newton's method found no fixed point; the message says how far it got and what to try."""


@dataclass
class ShootingResult:
    """A fixed point ``y`` of the map and what it took.

    ``value`` is the map at ``y`` (``value.y`` = P(y)); ``jacobian`` dP/dy at ``y``,
    ``jacobian_method`` how it was obtained (``"variational"``: given by the map,
    ``"finite-difference"``) and ``jacobian_check`` a less accurate one (None: the Jacobian is
    exact); ``residual`` the scaled max norm of P(y) - y; ``iterations`` the Newton steps taken;
    ``history`` the residual before each step and at the end; ``jacobians`` how many Jacobians
    were computed, the final one included.
    """

    y: np.ndarray
    value: MapValue
    jacobian: np.ndarray
    jacobian_method: str
    residual: float
    iterations: int
    history: list
    evaluations: int
    jacobian_check: np.ndarray | None = None
    jacobians: int = 0


def _norm(v, scale):
    return float(np.max(np.abs(v / scale))) if v.size else 0.0


def finite_difference_jacobian(fmap, y, scale, step=None, central=True, value=None, check=False):
    """``dP/dy`` by finite differences of the map, steps ``step * scale`` per component.

    Parameters
    ----------
    fmap : callable
        The map, ``fmap(y, jacobian=False) -> MapValue``.
    y : ndarray, shape ``(n,)``
        Where.
    scale : ndarray, shape ``(n,)``
        Size of each component (the step is ``step * scale``).
    step : float, optional
        Relative step [-]. Default: :func:`difference_step` of the map's relative accuracy,
        ``fmap.accuracy`` (``1e-10`` for a map that does not say).
    central : bool
        Central differences (``2n`` evaluations, error ``O(step^2)``) or forward (``n``, using
        ``value`` = P(y) if given).
    check : bool
        Also central differences of step ``2 step`` (``2n`` more evaluations): their difference
        from the first is about 3 times the first's truncation error but only about its error
        from the map's own (half of it again, and not independent of it), so
        :data:`CHECK_SAFETY` times that difference is the check returned.

    Returns
    -------
    jacobian : ndarray, shape ``(n, n)``
    evaluations : int
    jacobian_check : ndarray or None
        ``J + CHECK_SAFETY (J_2 - J)``, ``J_2`` the Jacobian of step ``2 step`` (``check``).
    """
    if step is None:
        step = difference_step(getattr(fmap, "accuracy", 1e-10), central)
    n = y.size
    J = np.empty((n, n))
    J2 = np.empty((n, n)) if check else None
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
        if check:
            J2[:, j] = (fmap(y + 2.0 * e, False).y - fmap(y - 2.0 * e, False).y) / (4.0 * h)
            count += 2
    return J, count, (J + CHECK_SAFETY * (J2 - J) if check else None)


def jacobian_of(fmap, y, value, scale, fd_step=None, check=False):
    """``(dP/dy, method, evaluations, check)`` at ``y``: the map's own if ``value`` carries it, else by central
    differences (with the check of :func:`finite_difference_jacobian` when ``check``)."""
    if value.jacobian is not None:
        return (value.jacobian, value.info.get("jacobian", "variational"), value.info.get("evaluations", 0),
                value.jacobian_check)
    J, count, J2 = finite_difference_jacobian(fmap, y, scale, fd_step, central=True, check=check)
    return J, "finite-difference", count, J2


def shoot(fmap, y0, scale, *, tol=1e-9, max_iter=30, fd_step=None, min_damping=1.0 / 1024, what="the map"):
    """A fixed point ``P(y) = y`` by Newton's method on ``P(y) - y``, damped by step halving.

    Each step solves ``(B - I) dy = -(P(y) - y)``, ``B`` the Jacobian ``dP/dy`` at the first
    iterate or after a poor step, else its update by Broyden's formula, and takes the longest of
    ``dy, dy/2, dy/4, ...`` that reduces the scaled residual (Armijo: by at least the fraction
    ``lambda/4`` of it), down to ``min_damping``. At the fixed point the Jacobian is computed
    anew with its check (``fmap(y, "checked")``).

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
    fd_step : float, optional
        Relative step of the finite-difference Jacobian, when the map gives none (default
        :func:`difference_step` of the map's accuracy).
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
    jacobians = 0
    asked = True  # whether value was computed with the Jacobian asked for
    res = _norm(value.y - y, scale)
    history = [res]
    iterations = 0
    A = None  # the scaled D^-1 (B - I) D, D = diag(scale): None for a fresh Jacobian
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
        r = value.y - y
        if A is None:
            if not asked:
                value, asked = fmap(y, True), True
                evaluations += 1
            J, method, count, _ = jacobian_of(fmap, y, value, scale, fd_step)
            evaluations += count
            jacobians += 1
            A = (J - np.eye(n)) * scale[None, :] / scale[:, None]
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
        if trial_res > REFRESH * res:
            A = None  # a poor step: a fresh Jacobian for the next
        else:  # Broyden's update of D^-1 (B - I) D on the scaled step s and change of the scaled residual
            s = lam * dz
            dG = (trial.y - trial_y) / scale - r / scale
            A = A + np.outer(dG - A @ s, s) / float(s @ s)
        y, value, res, asked = trial_y, trial, trial_res, False
        iterations += 1
        history.append(res)
    value = fmap(y, "checked")
    evaluations += 1
    J, method, count, check = jacobian_of(fmap, y, value, scale, fd_step, check=True)
    evaluations += count
    return ShootingResult(y, value, J, method, res, iterations, history, evaluations, check, jacobians + 1)


def _history(history):
    return ", ".join(f"{h:.2g}" for h in history[-6:])

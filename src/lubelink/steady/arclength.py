"""Pseudo-arclength continuation of the fixed points of a map ``P(y, lam) = y`` in a parameter ``lam``.

A *family* is a callable ``family(lam) -> fmap`` giving the map at ``lam`` (``fmap(y, jacobian)
-> MapValue``, as in :mod:`.shooting`). The branch of fixed points ``G(y, lam) = P(y, lam) - y =
0`` is followed by Keller's pseudo-arclength method in scaled variables ``z = y / scale``,
``m = lam / lam_scale``:

* tangent ``t`` (unit): ``[G_z  G_m] t = 0``, oriented along the previous tangent;
* predictor ``u_p = u + ds t``;
* corrector: Newton on ``G(u) = 0`` and ``t . (u - u_p) = 0``, with ``G_z = D^-1 (dP/dy - I) D``
  (``D = diag(scale)``) from the map's Jacobian and ``G_m`` from a forward difference in
  ``lam``;
* step control: longer after an easy corrector, shorter after a hard one; a step whose tangent
  turns by more than ``max_angle`` is taken again at half length, so sharp resonance peaks are
  resolved; the parameter never moves by more than ``max_parameter_step`` in one step.

Along the branch, the Floquet multipliers (eigenvalues of ``dP/dy``) and their accuracy
estimates (:func:`.floquet.multiplier_errors`, from a second, less accurate ``dP/dy`` at each
orbit) mark each orbit stable or not, and :func:`.floquet.crossing` reports a multiplier leaving
or entering the unit circle when the number outside certainly changes: against the range that
every orbit since the last crossing allows, a multiplier within its accuracy of the circle
counting either way. A sign change of ``dlam/ds`` is a fold. Where the orbits are neutral (their
multipliers on the circle, an undamped linear link) and one passes +1, the response has a pole
that no corrector step crosses: the branch jumps over it and records the resonance. The branch ends exactly at ``lam_end``
(the last point is found by shooting at ``lam_end``), or earlier with a message saying why.
Nothing here knows the model.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from . import floquet
from .shooting import MapFailure, MapValue, ShootingError, jacobian_of, shoot

__all__ = ["Point", "Bifurcation", "Branch", "continue_branch"]


@dataclass
class Point:
    """One periodic orbit of the branch.

    ``y`` the fixed point, ``parameter`` the value of ``lam``, ``value`` the map there,
    ``jacobian`` ``dP/dy`` (the monodromy matrix) and how it was obtained, ``multipliers`` its
    eigenvalues and ``errors`` their accuracy estimates, ``tangent`` the unit tangent in scaled variables ``(y / scale, lam / lam_scale)``,
    ``arclength`` the scaled arclength from the first point, ``iterations`` the corrector's
    steps, ``residual`` the scaled max norm of ``P(y) - y``, ``scale`` the state scale of the
    tangent.
    """

    parameter: float
    y: np.ndarray
    value: MapValue
    jacobian: np.ndarray
    jacobian_method: str
    multipliers: np.ndarray
    tangent: np.ndarray
    arclength: float
    iterations: int
    residual: float
    scale: np.ndarray
    errors: np.ndarray = None

    @property
    def stable(self) -> bool:
        return floquet.is_stable(self.multipliers, self.errors)


@dataclass
class Bifurcation:
    """A fold or a Floquet multiplier crossing the unit circle between points ``index - 1`` and ``index``."""

    kind: str
    index: int
    parameter: float
    multiplier: complex


@dataclass
class Branch:
    """The points of a branch, its bifurcations, and how it ended (``status``: ``"complete"`` or ``"stopped"``).

    ``known``: the range of the number of multipliers outside the circle that every orbit since the
    last crossing allows (:func:`.floquet.outside_range`).
    """

    points: list
    bifurcations: list = field(default_factory=list)
    status: str = "complete"
    message: str = ""
    evaluations: int = 0
    wall_time: float = 0.0
    lam_scale: float = 1.0
    known: tuple = None


class _Stop(Exception):
    """The branch ends before ``lam_end``; the message says why."""


class _Land(Exception):
    """``lam_end`` lies within the next step."""


def continue_branch(family, y0, lam0, lam_end, scale_of, *, lam_scale=None, ds=0.02, ds_min=1e-5, ds_max=0.1,
                    max_parameter_step=None, max_points=2000, tol=1e-9, max_corrector=10, max_angle=15.0,
                    fd_step=None, lam_step=1e-6, on_point=None):
    """Follow the branch of fixed points of ``family(lam)`` from ``(y0, lam0)`` to ``lam = lam_end``.

    Parameters
    ----------
    family : callable
        ``family(lam) -> fmap``; may raise ValueError (or a subclass) for an invalid ``lam``.
    y0 : array_like
        A guess of the fixed point at ``lam0`` (refined by shooting).
    lam0, lam_end : float
        Start and end of the parameter.
    scale_of : callable
        ``scale_of(y, value) -> ndarray``: the size of each component of ``y`` at a point of the
        branch, ``value`` the map there (None at the initial guess); the scaling is renewed at
        every point.
    lam_scale : float, optional
        Size of the parameter in the arclength (default ``|lam_end - lam0|``).
    ds, ds_min, ds_max : float
        First, smallest and largest arclength step (scaled units).
    max_parameter_step : float, optional
        Largest change of ``lam`` in one step (default ``|lam_end - lam0| / 50``).
    max_points : int
        Most points.
    tol : float
        Scaled residual at which the corrector stops.
    max_corrector : int
        Most Newton steps of one corrector.
    max_angle : float
        Largest turn of the tangent in one step [degrees].
    fd_step, lam_step : float
        Relative finite-difference steps in ``y`` (when the map gives no Jacobian; default
        :func:`~.shooting.difference_step` of the map's accuracy) and ``lam``.
    on_point : callable, optional
        ``on_point(point)`` for each :class:`Point` as it joins the branch.

    Returns
    -------
    Branch
        With ``status = "stopped"`` and a ``message`` when the branch ended before ``lam_end``.

    Raises
    ------
    ShootingError
        If no fixed point is found at ``lam0``.
    """
    began = time.perf_counter()
    span = lam_end - lam0
    if span == 0:
        raise ValueError("lam_end must differ from lam0")
    direction = math.copysign(1.0, span)
    lam_scale = float(lam_scale or abs(span))
    max_dlam = float(max_parameter_step or abs(span) / 50.0)
    cos_max = math.cos(math.radians(max_angle))
    counter = {"evaluations": 0}

    def evaluate(y, lam, fmap=None, full=True, shot=None):
        """The map at (y, lam); with ``full``, also its Jacobian with its check and dP/dlam (``shot``: a
        :class:`~.shooting.ShootingResult` at ``y`` that has the map and its Jacobian already)."""
        fmap = fmap or family(lam)
        if not full:
            counter["evaluations"] += 1
            return fmap(y, False)
        if shot is not None:
            value, J, method, check, count = shot.value, shot.jacobian, shot.jacobian_method, shot.jacobian_check, 0
        else:
            value = fmap(y, "checked")
            J, method, count, check = jacobian_of(fmap, y, value, scale_of_current[0], fd_step, check=True)
            count += 1
        h = lam_step * max(abs(lam), lam_scale)
        P_lam = (family(lam + h)(y, False).y - value.y) / h
        counter["evaluations"] += 1 + count
        return value, (J, check), method, P_lam

    # --- the first point: shooting at lam0 ----------------------------------------------------------
    fmap0 = family(lam0)
    y0 = np.asarray(y0, dtype=float)
    first = shoot(fmap0, y0, scale_of(y0, None), tol=tol, fd_step=fd_step, what=f"the periodic response at {lam0:.6g}")
    counter["evaluations"] += first.evaluations
    scale_of_current = [scale_of(first.y, first.value)]
    value, (J, check), method, P_lam = evaluate(first.y, lam0, fmap0, shot=first)
    S = scale_of_current[0]
    t0 = np.zeros(first.y.size + 1)
    t0[-1] = direction
    tangent = _tangent(J, P_lam, S, lam_scale, t0)
    last_P_lam = [P_lam]
    points = [_point(lam0, first.y, value, J, check, method, tangent, 0.0, first.iterations, first.residual, S)]
    branch = Branch(points, lam_scale=lam_scale, known=floquet.outside_range(points[0].multipliers, points[0].errors))
    if on_point:
        on_point(points[0])

    # --- along the branch ----------------------------------------------------------------------------
    ds = ds0 = float(ds)
    try:
        while True:
            if len(points) >= max_points:
                raise _Stop(f"max_points = {max_points} reached at {points[-1].parameter:.6g}")
            last = points[-1]
            S = scale_of_current[0]
            t = _rescaled(last.tangent, last.scale, S)
            if abs(t[-1]) > 0:
                ds = min(ds, max_dlam / lam_scale / abs(t[-1]))
            u_last = np.concatenate([last.y / S, [last.parameter / lam_scale]])
            chord = _scaled(last.jacobian, last_P_lam[0], S, lam_scale)
            found = None
            while found is None:
                u_pred = u_last + ds * t
                lam_pred = u_pred[-1] * lam_scale
                if (lam_pred - lam_end) * direction > 0:  # the end is within this step: land on it
                    raise _Land()
                found, why = _correct(evaluate, u_pred, t, chord, S, lam_scale, tol, max_corrector)
                if found is not None:
                    u, value, (J, check), method, P_lam, iterations, res = found
                    new_t = _tangent(J, P_lam, S, lam_scale, t)
                    cos = float(new_t @ t)
                    if cos < cos_max and ds > ds_min:
                        found, why = None, f"the tangent turned by {math.degrees(math.acos(max(-1, cos))):.3g} deg"
                if found is None:
                    ds *= 0.5
                    if ds < ds_min:
                        jumped = _resonance_jump(branch, family, tol, fd_step, S, lam_scale, direction, evaluate)
                        if jumped is None:
                            raise _Stop(f"the corrector failed at {lam_pred:.6g} with the smallest step "
                                        f"(ds_min = {ds_min:g}): {why}")
                        found = jumped
            if isinstance(found, Point):  # across a resonance of a neutral orbit
                last_P_lam[0] = found.value.info.pop("P_lam")
                points.append(found)
                branch.known = floquet.outside_range(found.multipliers, found.errors)
                scale_of_current[0] = scale_of(found.y, found.value)
                if on_point:
                    on_point(found)
                ds = ds0
                continue
            lam = u[-1] * lam_scale
            y = u[:-1] * S
            arc = last.arclength + float(np.linalg.norm(u - u_last))
            point = _point(lam, y, value, J, check, method, new_t, arc, iterations, res, S)
            last_P_lam[0] = P_lam
            _detect(branch, point)
            points.append(point)
            scale_of_current[0] = scale_of(y, value)
            if on_point:
                on_point(point)
            if (lam - lam0) * direction < 0:
                raise _Stop(f"the branch turned back past the start ({lam0:.6g}) at {lam:.6g}")
            if iterations <= 4 and cos > math.sqrt(cos_max):
                ds = min(1.5 * ds, ds_max)
            elif iterations >= 7:
                ds = max(0.5 * ds, ds_min)
    except _Land:
        _land(branch, family, lam_end, tol, fd_step, scale_of_current[0], lam_scale, evaluate, counter)
        if on_point and branch.status == "complete":
            on_point(branch.points[-1])
    except _Stop as stop:
        branch.status, branch.message = "stopped", str(stop)
    branch.evaluations = counter["evaluations"]
    branch.wall_time = time.perf_counter() - began
    if branch.status == "complete":
        branch.message = f"reached {lam_end:.6g}"
    return branch


def _point(lam, y, value, J, check, method, tangent, arc, iterations, res, S):
    mu = floquet.multipliers(J)
    return Point(lam, y, value, J, method, mu, tangent, arc, iterations, res, S, floquet.multiplier_errors(mu, check))


def _rescaled(t, old, new):
    """The unit tangent ``t`` of scale ``old`` expressed in scale ``new``."""
    t = np.concatenate([t[:-1] * old / new, t[-1:]])
    return t / np.linalg.norm(t)


def _scaled(J, P_lam, S, lam_scale):
    """``[G_z  G_m]``: the Jacobian of ``D^-1 G`` in the scaled variables."""
    n = J.shape[0]
    Gz = (J - np.eye(n)) * S[None, :] / S[:, None]
    Gm = P_lam * lam_scale / S
    return np.column_stack([Gz, Gm])


def _tangent(J, P_lam, S, lam_scale, previous):
    """Unit tangent of the branch in scaled variables, on the side of ``previous``."""
    A = np.vstack([_scaled(J, P_lam, S, lam_scale), previous])
    b = np.zeros(A.shape[0])
    b[-1] = 1.0
    t = np.linalg.solve(A, b)
    return t / np.linalg.norm(t)


def _correct(evaluate, u_pred, t, chord, S, lam_scale, tol, max_corrector):
    """The corrector from ``u_pred``: ``(found, why)``.

    Quasi-Newton iterations on ``G = 0``, ``t . (u - u_pred) = 0``: the matrix starts as
    ``chord`` (the scaled ``[G_z G_m]`` of the previous point) and takes Broyden's rank-one
    update after each step, so an iteration costs one map evaluation; the full Jacobian is
    computed once, at the converged point (for its multipliers and the next tangent). ``found``
    is ``(u, value, J, method, P_lam, iterations, residual)``.
    """
    B = chord.copy()
    u = u_pred.copy()
    previous, G_old, step = math.inf, None, None
    for k in range(max_corrector + 1):
        try:
            value = evaluate(u[:-1] * S, u[-1] * lam_scale, full=False)
        except (MapFailure, ValueError) as exc:  # ConfigError is a ValueError: an invalid parameter
            return None, str(exc).replace("\n", "; ")
        G = (value.y - u[:-1] * S) / S
        res = float(np.max(np.abs(G)))
        if res < tol:
            break
        if k == max_corrector or res > 2.0 * previous or not np.isfinite(res):
            return None, f"scaled residual {res:.3g} after {k} corrector steps"
        if step is not None:  # Broyden: B step = G - G_old
            B += np.outer(G - G_old - B @ step, step) / float(step @ step)
        previous, G_old = res, G
        try:
            step = np.linalg.solve(np.vstack([B, t]), -np.concatenate([G, [float(t @ (u - u_pred))]]))
        except np.linalg.LinAlgError:
            return None, "singular corrector matrix"
        u = u + step
    try:
        value, J, method, P_lam = evaluate(u[:-1] * S, u[-1] * lam_scale, full=True)
    except (MapFailure, ValueError) as exc:
        return None, str(exc).replace("\n", "; ")
    return (u, value, J, method, P_lam, k, res), ""


def _detect(branch, point):
    """Record the fold or Floquet crossing between the last point of ``branch`` and ``point``."""
    last = branch.points[-1]
    index = len(branch.points)
    fold = last.tangent[-1] * point.tangent[-1] < 0
    if fold:
        branch.bifurcations.append(Bifurcation(floquet.KINDS[0], index,
                                               _fold_parameter(last, point, branch.lam_scale), complex(1.0, 0.0)))
    c = floquet.crossing(last.multipliers, point.multipliers, last.errors, margin_b=point.errors, known=branch.known)
    here = floquet.outside_range(point.multipliers, point.errors)
    if c is not None or branch.known is None:
        branch.known = here
    else:  # what every orbit since the last crossing allows
        branch.known = (max(branch.known[0], here[0]), min(branch.known[1], here[1]))
    if c is not None and not (fold and c.kind == floquet.KINDS[1]):
        lam = last.parameter + c.fraction * (point.parameter - last.parameter)
        branch.bifurcations.append(Bifurcation(c.kind, index, lam, c.multiplier))


def _resonance_jump(branch, family, tol, fd_step, S, lam_scale, direction, evaluate):
    """The orbit beyond a resonance of a neutral orbit, where the corrector failed, or None.

    A branch of orbits whose multipliers lie on the unit circle (an undamped linear link) has a
    pole where one of them passes +1 (``k omega0 = omega_n``: the response to the ``k``-th
    harmonic grows without bound), which no step of the corrector crosses. When the last orbit has
    a complex multiplier on the circle (within its accuracy) near +1, the parameter where its
    argument reaches 0 is extrapolated from an earlier orbit (the farthest of the last ten), the
    orbit as far beyond the pole as that one lay before it is found by shooting, and the branch
    goes on from it; the resonance is recorded (replacing any fold that
    the approach to the pole made the tangent report there).
    """
    pts = branch.points
    last = pts[-1]
    k = int(np.argmin(np.abs(last.multipliers - 1.0)))
    mu, err = last.multipliers[k], last.errors[k]
    if abs(abs(mu) - 1.0) > err or abs(mu - 1.0) > 0.05 or abs(mu.imag) <= err or len(pts) < 3:
        return None
    theta = abs(np.angle(mu))
    earlier = [p for p in pts[-10:-1] if abs(p.parameter - last.parameter) > 0]
    if not earlier:
        return None
    p = max(earlier, key=lambda p: abs(p.parameter - last.parameter))
    theta_p = float(np.min(np.abs(np.angle(p.multipliers[np.abs(p.multipliers - 1.0) < 0.5])), initial=np.inf))
    if not theta_p > theta:
        return None
    lam_k = last.parameter - theta * (p.parameter - last.parameter) / (theta_p - theta)
    if (lam_k - last.parameter) * direction < 0:
        return None
    d = max(abs(lam_k - p.parameter), 1e-9 * lam_scale)  # as far beyond as the earlier orbit lay before
    lam = lam_k + direction * d
    try:
        fmap = family(lam)
        r = shoot(fmap, last.y, S, tol=tol, fd_step=fd_step, what=f"the periodic response at {lam:.6g}")
        value, (J, check), method, P_lam = evaluate(r.y, lam, fmap, shot=r)
    except (ShootingError, MapFailure, ValueError):
        return None
    t0 = np.zeros(last.y.size + 1)
    t0[-1] = direction
    u_last = np.concatenate([last.y / S, [last.parameter / lam_scale]])
    u = np.concatenate([r.y / S, [lam / lam_scale]])
    point = _point(lam, r.y, value, J, check, method, _tangent(J, P_lam, S, lam_scale, t0),
                   last.arclength + float(np.linalg.norm(u - u_last)), r.iterations, r.residual, S)
    value.info["P_lam"] = P_lam
    near = 2.0 * max(abs(q.parameter - lam_k) for q in pts[-3:])
    branch.bifurcations = [b for b in branch.bifurcations
                           if not (b.kind == floquet.KINDS[0] and abs(b.parameter - lam_k) <= near)]
    branch.bifurcations.append(Bifurcation(floquet.KINDS[4], len(pts), float(lam_k), complex(1.0, 0.0)))
    return point


def _fold_parameter(a, b, lam_scale):
    """The turning value of the parameter between points ``a`` and ``b``: the extremum of the cubic
    Hermite interpolant of ``lam(s)``, with ``dlam/ds = t_m lam_scale`` from the tangents."""
    k = (b.arclength - a.arclength) * lam_scale
    lam_a, lam_b, d_a, d_b = a.parameter, b.parameter, a.tangent[-1] * k, b.tangent[-1] * k
    # p(x) = c0 + c1 x + c2 x^2 + c3 x^3 on [0, 1], p(0) = lam_a, p(1) = lam_b, p'(0) = d_a, p'(1) = d_b
    c0, c1 = lam_a, d_a
    c2 = 3.0 * (lam_b - lam_a) - 2.0 * d_a - d_b
    c3 = 2.0 * (lam_a - lam_b) + d_a + d_b
    roots = np.roots([3.0 * c3, 2.0 * c2, c1]) if abs(c3) + abs(c2) > 0 else np.array([])
    roots = [r.real for r in np.atleast_1d(roots) if abs(r.imag) < 1e-12 and 0.0 <= r.real <= 1.0]
    if not roots:
        return lam_a if abs(d_a) < abs(d_b) else lam_b
    x = roots[0]
    return float(((c3 * x + c2) * x + c1) * x + c0)


def _land(branch, family, lam_end, tol, fd_step, S, lam_scale, evaluate, counter):
    """The last point, at ``lam_end`` exactly, by shooting from the secant guess between the last points."""
    last = branch.points[-1]
    prev = branch.points[-2] if len(branch.points) > 1 else last
    span = last.parameter - prev.parameter
    w = (lam_end - prev.parameter) / span if span else 1.0
    guess = prev.y + w * (last.y - prev.y)
    fmap = family(lam_end)
    try:
        r = shoot(fmap, guess, S, tol=tol, fd_step=fd_step, what=f"the periodic response at {lam_end:.6g}")
    except (ShootingError, MapFailure, ValueError) as exc:
        branch.status, branch.message = "stopped", f"the last point, at {lam_end:.6g}, was not found: {exc}"
        return
    counter["evaluations"] += r.evaluations
    value, (J, check), method, P_lam = evaluate(r.y, lam_end, fmap, shot=r)
    tangent = _tangent(J, P_lam, S, lam_scale, _rescaled(last.tangent, last.scale, S))
    u_last = np.concatenate([last.y / S, [last.parameter / lam_scale]])
    u = np.concatenate([r.y / S, [lam_end / lam_scale]])
    point = _point(lam_end, r.y, value, J, check, method, tangent, last.arclength + float(np.linalg.norm(u - u_last)),
                   r.iterations, r.residual, S)
    _detect(branch, point)
    branch.points.append(point)

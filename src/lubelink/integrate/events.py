"""Locating the first zero of an event function inside a step, on the dense output.

The event is ``g(t) = sign * gap(t, y(t))``; the caller knows its rate ``g'(t)`` in closed form
and a bound ``D`` of ``|g'|`` valid over about a step: ``event(t, y, p)`` returns all three
(before ``sign``; ``D = inf`` if none is known). A zero counts when ``g`` falls from positive to
zero or below. Inside an accepted step ``[t_old, t_new]``:

* where the bound proves ``g > 0`` it is not sampled: on ``[a, b]``,
  ``g >= (g(a) + g(b) - D (b - a)) / 2`` and ``g(t) >= g(a) - D (t - a)``, with ``D`` twice the
  larger of the bounds at the step's ends (a margin for the amplitudes' change over the step);
* elsewhere ``g`` and ``g'`` are sampled on the dense output at sub-steps no longer than
  ``F_RES`` (the caller's bound: a fraction of the fastest period of the system);
* a sign change of ``g`` between samples is refined by Brent's method on ``g``;
* and so is every local minimum of ``g``: a change of ``g'`` from negative to positive between
  two samples is refined by Brent's method on ``g'`` and ``g`` is tested there. So a graze, ``g``
  dipping below zero and back between two samples, is found whatever its duration, by every
  method at every tolerance. (A minimum is refined only where a cubic Hermite estimate from the
  samples puts it below half the smaller sampled value; a shallow ripple costs nothing.)

The zero is returned as a bracket a few rounding units wide: the last located time with ``g > 0``
(``F_TBEFORE``, state in ``R_YBEFORE``) and the first with ``g <= 0`` (``F_TFINAL``, ``R_YFINAL``),
so that the caller can restart on either side without the event firing again at once.

References: R. P. Brent, *Algorithms for Minimization without Derivatives*, 1973, ch. 4 (the
root finder, as ``scipy.optimize.brentq``).
"""

import math

import numpy as np

from lubelink._jit import jitable
from ._layout import F_BOLD, F_DOLD, F_GOLD, F_RES, F_TBEFORE, F_TFINAL, R_BUF, R_Y, R_YBEFORE, R_YFINAL

__all__ = ["locate"]

EPS = np.finfo(float).eps
MAX_ITER = 200
MARGIN = 2.0  # the rate bound used is MARGIN times the larger of the bounds at the step's ends


@jitable
def _value(which, dense, rhs, event, p, sign, W, fst, ist, t):
    """``g(t)`` (``which = 0``) or ``g'(t)`` (1) on the dense output of the last step."""
    y = W[R_BUF]
    dense(rhs, p, W, fst, ist, t, y)
    return sign * event(t, y, p)[which]


@jitable
def _brent(which, dense, rhs, event, p, sign, W, fst, ist, a, b, fa, fb):
    """A zero of ``g`` or ``g'`` in ``[a, b]`` where ``fa``, ``fb`` differ in sign (Brent's method, ``4 eps`` relative)."""
    xtol = 4.0 * EPS * max(1.0, abs(b))
    c, fc = a, fa
    d = b - a
    e = d
    for _ in range(MAX_ITER):
        if (fb > 0.0) == (fc > 0.0):
            c, fc = a, fa
            d = b - a
            e = d
        if abs(fc) < abs(fb):
            a, b, c = b, c, b
            fa, fb, fc = fb, fc, fb
        tol = 0.5 * (xtol + 4.0 * EPS * abs(b))
        m = 0.5 * (c - b)
        if abs(m) <= tol or fb == 0.0:
            return b
        if abs(e) < tol or abs(fa) <= abs(fb):
            d = m
            e = m
        else:
            s = fb / fa
            if a == c:  # secant
                pp = 2.0 * m * s
                qq = 1.0 - s
            else:  # inverse quadratic interpolation
                qq = fa / fc
                r = fb / fc
                pp = s * (2.0 * m * qq * (qq - r) - (b - a) * (r - 1.0))
                qq = (qq - 1.0) * (r - 1.0) * (s - 1.0)
            if pp > 0.0:
                qq = -qq
            else:
                pp = -pp
            if 2.0 * pp < min(3.0 * m * qq - abs(tol * qq), abs(e * qq)):
                e = d
                d = pp / qq
            else:
                d = m
                e = m
        a, fa = b, fb
        if abs(d) > tol:
            b += d
        else:
            b += tol if m > 0.0 else -tol
        fb = _value(which, dense, rhs, event, p, sign, W, fst, ist, b)
    return b


@jitable
def _bracket(dense, rhs, event, p, sign, W, fst, ist, a, b, root):
    """Bracket the zero ``root`` of ``g`` (``g(a) > 0 >= g(b)``) by times a few rounding units apart.

    Writes ``F_TBEFORE``, ``R_YBEFORE`` (``g > 0``) and ``F_TFINAL``, ``R_YFINAL`` (``g <= 0``).
    """
    n = W.shape[1]
    g = _value(0, dense, rhs, event, p, sign, W, fst, ist, root)
    delta = 4.0 * EPS * max(1.0, abs(root))
    if g <= 0.0:
        hi, lo = root, root
        for m in range(n):
            W[R_YFINAL, m] = W[R_BUF, m]
        while True:
            lo = max(root - delta, a)
            if lo == a or _value(0, dense, rhs, event, p, sign, W, fst, ist, lo) > 0.0:
                break
            delta *= 2.0
        if lo == a:
            _value(0, dense, rhs, event, p, sign, W, fst, ist, a)
        for m in range(n):
            W[R_YBEFORE, m] = W[R_BUF, m]
    else:
        lo, hi = root, root
        for m in range(n):
            W[R_YBEFORE, m] = W[R_BUF, m]
        while True:
            hi = min(root + delta, b)
            if hi == b or _value(0, dense, rhs, event, p, sign, W, fst, ist, hi) <= 0.0:
                break
            delta *= 2.0
        if hi == b:
            _value(0, dense, rhs, event, p, sign, W, fst, ist, b)
        for m in range(n):
            W[R_YFINAL, m] = W[R_BUF, m]
    fst[F_TBEFORE] = lo
    fst[F_TFINAL] = hi


@jitable
def _hermite_minimum(a, b, ga, gb, da, db):
    """Smallest value on ``[a, b]`` of the cubic with values ``ga``, ``gb`` and slopes ``da``, ``db``."""
    h = b - a
    best = min(ga, gb)
    # p(s) = ga + da h s + c2 s^2 + c3 s^3, s in [0, 1]
    c2 = 3.0 * (gb - ga) - h * (2.0 * da + db)
    c3 = 2.0 * (ga - gb) + h * (da + db)
    # p'(s) = da h + 2 c2 s + 3 c3 s^2
    A, B, C = 3.0 * c3, 2.0 * c2, da * h
    if A == 0.0:
        roots = (-C / B if B != 0.0 else -1.0, -1.0)
    else:
        disc = B * B - 4.0 * A * C
        if disc < 0.0:
            return best
        r = math.sqrt(disc)
        roots = ((-B - r) / (2.0 * A), (-B + r) / (2.0 * A))
    for s in roots:
        if 0.0 < s < 1.0:
            best = min(best, ga + s * (C + s * (c2 + s * c3)))
    return best


@jitable
def locate(dense, rhs, event, p, sign, W, fst, ist, t_old, t_new):
    """Whether the event has a zero in ``(t_old, t_new]``; if so its bracket is written (see module docstring).

    ``fst[F_GOLD]``, ``fst[F_DOLD]``, ``fst[F_BOLD]``: ``g``, ``g'`` and the rate bound at ``t_old``;
    on return they hold the values at ``t_new``.
    """
    g_new, d_new, bound_new = event(t_new, W[R_Y], p)
    g_new *= sign
    d_new *= sign
    g_a = fst[F_GOLD]
    d_a = fst[F_DOLD]
    D = MARGIN * max(fst[F_BOLD], bound_new)
    fst[F_GOLD] = g_new
    fst[F_DOLD] = d_new
    fst[F_BOLD] = bound_new
    res = fst[F_RES]
    if res <= 0.0:
        res = t_new - t_old
    a = t_old
    while True:
        if g_a > 0.0 and g_new > 0.0 and g_a + g_new > D * (t_new - a):
            return False  # g > 0 on [a, t_new]
        b = a + (max(res, g_a / D) if D > 0.0 else res)  # g > 0 on [a, a + g_a / D) in any case
        if b >= t_new or t_new - b < 1e-3 * res:
            b, g_b, d_b = t_new, g_new, d_new
        else:
            dense(rhs, p, W, fst, ist, b, W[R_BUF])
            g_b, d_b, _ = event(b, W[R_BUF], p)
            g_b *= sign
            d_b *= sign
        if g_b <= 0.0:
            root = _brent(0, dense, rhs, event, p, sign, W, fst, ist, a, b, g_a, g_b)
            _bracket(dense, rhs, event, p, sign, W, fst, ist, a, b, root)
            return True
        proved = g_a > 0.0 and g_a + g_b > D * (b - a)
        if not proved and d_a < 0.0 and d_b > 0.0 and _hermite_minimum(a, b, g_a, g_b, d_a, d_b) < 0.5 * min(g_a, g_b):
            t_m = _brent(1, dense, rhs, event, p, sign, W, fst, ist, a, b, d_a, d_b)
            g_m = _value(0, dense, rhs, event, p, sign, W, fst, ist, t_m)
            if g_m <= 0.0:
                root = _brent(0, dense, rhs, event, p, sign, W, fst, ist, a, t_m, g_a, g_m)
                _bracket(dense, rhs, event, p, sign, W, fst, ist, a, t_m, root)
                return True
        if b == t_new:
            return False
        a, g_a, d_a = b, g_b, d_b

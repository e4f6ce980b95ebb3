"""Error norm, starting step and step-size control shared by the methods.

The norm and the controller are SciPy's (``scipy.integrate._ivp.common`` and ``rk``): the RMS of
the error scaled by ``atol + rtol max(|y_old|, |y_new|)``, a safety factor 0.9 and a step changed
by a factor within ``[0.2, 10]``.
"""

import math

import numpy as np

from lubelink._jit import jitable
from ._layout import F_DIR, F_H, F_HSTEP, F_MAXSTEP, F_T, F_TEND, F_TOLD, R_ATOL, R_F, R_RTOL, R_Y, S_NFEV

__all__ = ["scaled_rms", "step_factor", "initial_step", "min_step", "step_end", "accept_step", "SAFETY", "MIN_FACTOR",
           "MAX_FACTOR"]

EPS = np.finfo(float).eps
SAFETY, MIN_FACTOR, MAX_FACTOR = 0.9, 0.2, 10.0
TOO_SMALL_STEP = "Required step size is less than spacing between numbers."


@jitable
def scaled_rms(e, y_old, y_new, W):
    """``rms(e / (atol + rtol max(|y_old|, |y_new|)))`` with the tolerances of the rows of ``W``."""
    n = e.shape[0]
    acc = 0.0
    for m in range(n):
        sc = W[R_ATOL, m].real + W[R_RTOL, m].real * max(abs(y_old[m]), abs(y_new[m]))
        d = abs(e[m]) / sc
        acc += d * d
    return math.sqrt(acc / n)


@jitable
def step_factor(error_norm, order, rejected):
    """Factor for the next step of a method whose error estimate is ``O(h^(order + 1))``.

    After a rejection the step is not increased; a zero error allows the largest increase.
    """
    if error_norm == 0.0:
        factor = MAX_FACTOR
    else:
        factor = min(MAX_FACTOR, max(MIN_FACTOR, SAFETY * error_norm ** (-1.0 / (order + 1))))
    if rejected:
        factor = min(1.0, factor)
    return factor


@jitable
def min_step(t, direction):
    """The smallest step from ``t``: ten units in the last place of ``t`` (SciPy's)."""
    return 10.0 * abs(np.nextafter(t, direction * np.inf) - t)


@jitable
def step_end(fst, t, h_abs):
    """Where a step of size ``h_abs`` from ``t`` ends: in the direction of integration, not past ``t_end``."""
    t_new = t + fst[F_DIR] * h_abs
    if fst[F_DIR] * (t_new - fst[F_TEND]) > 0.0:
        t_new = fst[F_TEND]
    return t_new


@jitable
def accept_step(fst, t, t_new, h_abs):
    """Record an accepted step from ``t`` to ``t_new`` and the size ``h_abs`` of the next one to try."""
    fst[F_TOLD] = t
    fst[F_HSTEP] = t_new - t
    fst[F_T] = t_new
    fst[F_H] = h_abs


@jitable
def initial_step(rhs, p, W, fst, ist, order, buf, fbuf):
    """Hairer-Norsett-Wanner II.4 starting step for an error of order ``order + 1`` (SciPy's).

    ``W[R_F]`` must hold ``f(t, y)``; ``buf``, ``fbuf`` are scratch rows.
    """
    n = W.shape[1]
    t = fst[F_T]
    direction = fst[F_DIR]
    interval = abs(fst[F_TEND] - t)
    if interval == 0.0:
        return 0.0
    y = W[R_Y]
    f = W[R_F]
    d0 = scaled_rms(y, y, y, W)
    d1 = scaled_rms(f, y, y, W)
    h0 = 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1
    h0 = min(h0, interval)
    for m in range(n):
        buf[m] = y[m] + direction * h0 * f[m]
    rhs(t + direction * h0, buf, fbuf, p)
    ist[S_NFEV] += 1
    for m in range(n):
        buf[m] = fbuf[m] - f[m]
    d2 = scaled_rms(buf, y, y, W) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / (order + 1))
    return min(100 * h0, h1, interval, fst[F_MAXSTEP])

"""DOP853: Dormand & Prince's explicit Runge-Kutta pair of order 8(5,3) with dense output of order 7.

The algorithm of ``scipy.integrate.DOP853`` (Hairer, Norsett & Wanner, *Solving ODEs I*, 2nd ed.,
Section II.10), with SciPy's coefficients, error norm and step-size control, so it takes SciPy's
steps up to rounding; written as compiled kernels on the shared integration state (:mod:`._layout`)
so that the whole integration loop runs compiled. The dense output costs three more evaluations,
in the steps where it is used (samples, events), as in SciPy.
"""

import math
import os

import numpy as np

from lubelink._jit import jitable, kernel
from ._layout import (F_DIR, F_H, F_HSTEP, F_MAXSTEP, F_T, F_TOLD, FAIL_RHS, R_ATOL, R_F, R_FOLD, R_METHOD,
                      R_RTOL, R_Y, R_YOLD, S_DENSE, S_FAIL, S_NFEV, S_NREJ)
from .control import MAX_FACTOR, MIN_FACTOR, SAFETY, accept_step, initial_step, min_step, step_end

__all__ = ["init", "step", "dense", "rows", "ORDER"]

ORDER = 8


def _scipy_coefficients():
    """SciPy's DOP853 tables, read from their module without importing ``scipy.integrate`` (most of a second)."""
    import importlib.util

    import scipy

    path = os.path.join(scipy.__path__[0], "integrate", "_ivp", "dop853_coefficients.py")
    if not os.path.isfile(path):  # another layout: the ordinary import
        from scipy.integrate._ivp import dop853_coefficients

        return dop853_coefficients
    spec = importlib.util.spec_from_file_location("lubelink_scipy_dop853_coefficients", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


_dop = _scipy_coefficients()
_A = np.ascontiguousarray(_dop.A, dtype=float)  # row 12 holds the weights b
_C = np.ascontiguousarray(_dop.C, dtype=float)
_E = np.ascontiguousarray(np.vstack([_dop.E5, _dop.E3]), dtype=float)
_D = np.ascontiguousarray(_dop.D, dtype=float)

R_K = R_METHOD  # the 16 stages (13 of the step, 3 of the dense output)
R_YNEW = R_K + 16
R_TMP = R_YNEW + 1
R_E5 = R_TMP + 1
R_E3 = R_E5 + 1
R_COEF = R_E3 + 1  # the 7 rows of the interpolant


def rows(n):
    """Rows of ``W`` this method uses."""
    return R_COEF + 7


@jitable
def _combine(W, dst, coef, row, count):
    """``W[dst] = sum_{i < count} coef[row, i] K_i``, zero coefficients skipped (the tables are sparse)."""
    n = W.shape[1]
    for m in range(n):
        W[dst, m] = 0.0
    for i in range(count):
        a = coef[row, i]
        if a != 0.0:
            for m in range(n):
                W[dst, m] += W[R_K + i, m] * a


@jitable(inline=True)
def _stage(s, rhs, p, t, h, y, W, ist):
    """``K_s = f(t + c_s h, y + h sum_i a_si K_i)``."""
    n = W.shape[1]
    _combine(W, R_TMP, _A, s, s)
    for m in range(n):
        W[R_TMP, m] = y[m] + W[R_TMP, m] * h
    rhs(t + _C[s] * h, W[R_TMP], W[R_K + s], p)
    ist[S_NFEV] += 1


@kernel
def init(rhs, p, W, fst, ist):
    """``f(t0, y0)`` and the starting step."""
    rhs(fst[F_T], W[R_Y], W[R_F], p)
    ist[S_NFEV] += 1
    fst[F_H] = initial_step(rhs, p, W, fst, ist, ORDER - 1, W[R_TMP], W[R_YNEW])


@kernel
def step(rhs, p, W, fst, ist):
    """One accepted step (``scipy.integrate._ivp.rk.RungeKutta._step_impl``); False if the step underflows."""
    n = W.shape[1]
    t = fst[F_T]
    direction = fst[F_DIR]
    y = W[R_Y]
    f = W[R_F]
    smallest = min_step(t, direction)
    h_abs = fst[F_H]
    if h_abs > fst[F_MAXSTEP]:
        h_abs = fst[F_MAXSTEP]
    elif h_abs < smallest:
        h_abs = smallest
    rejected = False
    while True:
        if h_abs < smallest:
            return False
        t_new = step_end(fst, t, h_abs)
        h = t_new - t
        h_abs = abs(h)
        for m in range(n):
            W[R_K, m] = f[m]
        for s in range(1, 12):
            _stage(s, rhs, p, t, h, y, W, ist)
        _combine(W, R_YNEW, _A, 12, 12)
        for m in range(n):
            W[R_YNEW, m] = y[m] + h * W[R_YNEW, m]
        rhs(t + h, W[R_YNEW], W[R_K + 12], p)
        ist[S_NFEV] += 1
        _combine(W, R_E5, _E, 0, 13)
        _combine(W, R_E3, _E, 1, 13)
        e5 = 0.0
        e3 = 0.0
        for m in range(n):
            sc = W[R_ATOL, m].real + max(abs(y[m]), abs(W[R_YNEW, m])) * W[R_RTOL, m].real
            e5 += (abs(W[R_E5, m]) / sc) ** 2
            e3 += (abs(W[R_E3, m]) / sc) ** 2
        if e5 == 0.0 and e3 == 0.0:
            error_norm = 0.0
        else:
            error_norm = h_abs * e5 / math.sqrt((e5 + 0.01 * e3) * n)
        if not np.isfinite(error_norm):  # NaN or infinity in the stages: shrink, and say so if it underflows
            ist[S_FAIL] = FAIL_RHS
            error_norm = np.inf
        if error_norm < 1.0:
            ist[S_FAIL] = 0
            if error_norm == 0.0:
                factor = MAX_FACTOR
            else:
                factor = min(MAX_FACTOR, SAFETY * error_norm ** (-1.0 / ORDER))
            if rejected:
                factor = min(1.0, factor)
            h_abs *= factor
            break
        h_abs *= max(MIN_FACTOR, SAFETY * error_norm ** (-1.0 / ORDER)) if np.isfinite(error_norm) else MIN_FACTOR
        rejected = True
        ist[S_NREJ] += 1
    for m in range(n):
        W[R_YOLD, m] = y[m]
        W[R_FOLD, m] = f[m]
        y[m] = W[R_YNEW, m]
        f[m] = W[R_K + 12, m]
    accept_step(fst, t, t_new, h_abs)
    ist[S_DENSE] = 0
    return True


@jitable
def _coefficients(rhs, p, W, fst, ist):
    """Hairer's 7th-order interpolant of the last step (three more stages) into ``W[R_COEF:]``."""
    n = W.shape[1]
    h = fst[F_HSTEP]
    t_old = fst[F_TOLD]
    y_old = W[R_YOLD]
    for s in range(13, 16):
        _stage(s, rhs, p, t_old, h, y_old, W, ist)
    for r in range(4):
        _combine(W, R_COEF + 3 + r, _D, r, 16)
    for m in range(n):
        dy = W[R_Y, m] - y_old[m]
        W[R_COEF, m] = dy
        W[R_COEF + 1, m] = h * W[R_FOLD, m] - dy
        W[R_COEF + 2, m] = 2.0 * dy - h * (W[R_F, m] + W[R_FOLD, m])
        for r in range(4):
            W[R_COEF + 3 + r, m] *= h
    ist[S_DENSE] = 1


@kernel
def dense(rhs, p, W, fst, ist, t, out):
    """The dense output of the last step at ``t``, into ``out``."""
    if ist[S_DENSE] == 0:
        _coefficients(rhs, p, W, fst, ist)
    n = W.shape[1]
    x = (t - fst[F_TOLD]) / fst[F_HSTEP]
    for m in range(n):
        out[m] = 0.0
    for i in range(7):
        fac = x if i % 2 == 0 else 1.0 - x
        for m in range(n):
            out[m] = (out[m] + W[R_COEF + 6 - i, m]) * fac
    for m in range(n):
        out[m] += W[R_YOLD, m]


"""Compiled (Numba) segment integrators: the fast path of :func:`lubelink.simulate.run`.

What it does
------------
:func:`make_segment_integrator` returns, for a model it supports, a function
with the contract of :func:`lubelink.simulate.reference_segment_integrator`
(integrate from ``t0`` to ``t_end`` or the first zero of the gap function,
sample the dense output at ``t_eval``, report progress, stop at a deadline)
that runs

* ``solver.method = "bulirsch-stoer"`` and ``"DOP853"`` entirely in compiled
  code: stepping, dense output, sampling at ``t_eval``, event detection with
  sampling inside long steps and Brent's root refinement. The loop returns
  to Python every 1 % of the interval (or every :data:`STEPS_PER_CALL`
  steps) for the progress callback and the wall-clock deadline, then
  resumes where it stopped;
* the other SciPy methods (RK45, Radau, BDF, LSODA) by SciPy's own stepping
  (:func:`lubelink.integrate.driver.integrate_segment`) on the compiled
  right-hand side.

It returns None (the reference path) for a motion other than the
slider-crank and for ``film.cavitation = "reynolds"``.

The integrators are generic: :func:`solve` integrates any right-hand side
compiled with :data:`RHS_SIG` (``rhs(t, y, out, p)``, ``p`` a float64
parameter array), passed as a first-class function, so one compiled
integrator serves every right-hand side and is cached on disk
(``cache=True``) across processes.

Algorithms
----------
Bulirsch-Stoer: the same algorithm as
:class:`lubelink.integrate.bulirsch_stoer.BulirschStoer` (GBS extrapolation
with the ODEX order and step-size control of Hairer, Norsett & Wanner,
*Solving ODEs I*, 2nd ed., Section II.9, step sequence 2, 6, 10, ...,
dense output with interpolation-error control, the same tables), ported
statement by statement, so the two take the same steps up to rounding.

DOP853: Dormand & Prince's 8(5,3) pair with Hairer's dense output of order
7 (Hairer, Norsett & Wanner, Section II.10; the coefficients are read from
SciPy's ``dop853_coefficients`` at run time), with SciPy's error norm and
step-size control, so it takes the same steps as ``scipy.integrate.DOP853``
up to rounding. Its dense output costs three more evaluations in the steps
where it is needed (samples or event sub-sampling), as in SciPy.

Events: after every step the event function is evaluated at the step end
and, if the step is longer than ``event_resolution``, at equal sub-steps of
the dense output; the first sign change (positive to non-positive) is
refined by Brent's method (R. P. Brent, *Algorithms for Minimization
without Derivatives*, 1973, ch. 4) to ``4 eps`` relative, as the reference
driver does with ``scipy.optimize.brentq``. A graze shorter than the
sub-step spacing is found or not depending on where the samples fall, in
the reference driver as here: the compiled DOP853 samples where SciPy's does
(same steps), the compiled Bulirsch-Stoer where the Python one does only up
to rounding of the step sizes.

Implementation
--------------
One compiled function, :func:`_advance`, takes a segment as far as it can
(the state lives in a work array ``W`` of rows of length ``n`` and two small
state vectors, so a call can pause and resume); the right-hand side and the
event function are passed as first-class function objects whose Numba type
is computed once (:class:`_FirstClass`), and the method tables are module
constants frozen into the compiled code, so a return to Python costs about
15 us. Compilation takes about 30 s of CPU the first time (``compile_all``,
with a notice on a terminal after two seconds) and about 0.7 s from
Numba's on-disk cache afterwards.
"""

from __future__ import annotations

import contextlib
import logging
import math
import sys
import threading
import time

import numba
import numpy as np
from numba import types
from numba.extending import typeof_impl

from .bulirsch_stoer import (
    _DENSE_REJECT,
    _FAC1,
    _FAC2,
    _FAC3,
    _FAC4,
    _MU_DIFF,
    _SAFE1,
    _SAFE2,
    _SAFE3,
    _STAB_COLUMNS,
    DEFAULT_MAX_ORDER,
    EPS,
    TOO_SMALL_STEP,
    _tables,
)
from .driver import Segment, integrate_segment

__all__ = [
    "RHS_SIG",
    "EVENT_SIG",
    "COMPILED_METHODS",
    "SCIPY_METHODS",
    "make_segment_integrator",
    "solve",
    "compile_all",
]

log = logging.getLogger("lubelink")

#: ``rhs(t, y, out, p)``: writes ``dy/dt`` into ``out``; ``p`` is a float64 parameter array.
RHS_SIG = types.void(types.float64, types.float64[::1], types.float64[::1], types.float64[::1])
#: ``event(t, y, p) -> float``.
EVENT_SIG = types.float64(types.float64, types.float64[::1], types.float64[::1])

#: Methods run entirely in compiled code.
COMPILED_METHODS = ("bulirsch-stoer", "DOP853")
#: Methods run by SciPy's stepping on the compiled right-hand side.
SCIPY_METHODS = ("RK45", "Radau", "BDF", "LSODA")

#: Most steps taken in one call into compiled code before control returns to Python.
STEPS_PER_CALL = 500
#: Calls into compiled code per segment (progress and deadline checks), at least.
CALLS_PER_SEGMENT = 100

_BS, _DOP = 0, 1
_RUNNING, _FINISHED, _EVENT, _FAILED = 0, 1, 2, 3
_FAIL_SMALL_STEP, _FAIL_NONFINITE = 1, 2

KMAX = DEFAULT_MAX_ORDER  # extrapolation columns (ODEX's default)
_NSEQ = 4 * np.arange(1, KMAX + 1) - 2
_SEQ_ROWS = int(np.sum(_NSEQ + 1))

# rows of the work array W (each of length n)
R_Y, R_F, R_YOLD, R_FOLD, R_YNEW, R_FNEW, R_YA, R_YB, R_TMP, R_STAB, R_BUF, R_YFINAL = range(12)
R_T1 = 12  # GBS: T_j1, KMAX rows
R_YMID = R_T1 + KMAX  # GBS: midpoint values, KMAX rows
R_COEF = R_YMID + KMAX  # dense output coefficients, 2 KMAX + 5 rows
R_STORE = R_COEF + 2 * KMAX + 5  # GBS: f values of the midpoint sequences; DOP853: the 16 stages
ROWS = R_STORE + max(_SEQ_ROWS, 16)

# float state
F_T, F_H, F_HDENSE, F_GOLD, F_TOLD, F_HSTEP, F_TFINAL, F_ERROLD = range(8)
F_TEND, F_RTOL, F_ATOL, F_MAXSTEP, F_RES, F_TPAUSE, F_TSTOP = range(8, 15)
F_HH = 15  # GBS: step proposed by column j (1-based), KMAX + 2 entries
F_WW = F_HH + KMAX + 2  # GBS: work per unit step of column j
F_SIZE = F_WW + KMAX + 2

# integer state
(S_METHOD, S_K, S_NACC, S_NREJ, S_NFEV, S_NSTEPS, S_IEVAL, S_INIT, S_EVENT, S_DENSE, S_KC, S_FAIL,
 S_MAXSTEPS, S_MU) = range(14)
S_SIZE = 14

# SciPy's RK step-size control (scipy.integrate._ivp.rk)
_SAFETY, _MIN_FACTOR, _MAX_FACTOR = 0.9, 0.2, 10.0
_DOP_EXPONENT = -1.0 / 8.0  # error estimator of order 7


def _method_tables():
    """The GBS tables of :mod:`.bulirsch_stoer` and the DOP853 coefficients, as arrays."""
    from scipy.integrate._ivp import dop853_coefficients as dop

    tab = _tables(KMAX)
    nseq = np.asarray(tab.nseq, dtype=np.int64)
    seq_off = np.concatenate(([0], np.cumsum(nseq + 1)[:-1])).astype(np.int64)
    weights = np.zeros((KMAX, KMAX + 1, KMAX))
    for (a, b), w in tab.weights.items():
        weights[a, b, :b - a] = w
    diff = np.zeros((KMAX, 2 * KMAX, int(nseq[-1]) + 1))
    for j, op in enumerate(tab.diff_ops):
        diff[j, :op.shape[0], :op.shape[1]] = op
    hermite = np.ascontiguousarray(np.array(tab.hermite_inv))
    return (nseq, seq_off, np.asarray(tab.work, float), weights, diff, hermite,
            np.asarray(tab.taylor, float), np.asarray(tab.error_shape, float),
            np.ascontiguousarray(dop.A, dtype=float), np.ascontiguousarray(dop.C, dtype=float),
            np.ascontiguousarray(dop.E3, dtype=float), np.ascontiguousarray(dop.E5, dtype=float),
            np.ascontiguousarray(dop.D, dtype=float))


# The tables are module constants: Numba freezes global arrays into the compiled code.
(_T_NSEQ, _T_SEQ_OFF, _T_WORK, _T_WEIGHTS, _T_DIFF, _T_HERMITE, _T_TAYLOR, _T_ESHAPE,
 _T_DOP_A, _T_DOP_C, _T_DOP_E3, _T_DOP_E5, _T_DOP_D) = _method_tables()
_T_DOP_E = np.vstack([_T_DOP_E5, _T_DOP_E3])  # the 5th- and 3rd-order error estimators


# ------------------------------------------------------------------------------------------------
# shared helpers. Integer constants passed to helpers are wrapped in np.int64: Numba would compile
# a separate specialisation of the helper for every literal value otherwise.
@numba.njit(cache=True)
def _copy_row(W, row, src):
    """``W[row] = src`` (a loop: slice assignment compiles a costly shape check)."""
    for m in range(W.shape[1]):
        W[row, m] = src[m]


@numba.njit(cache=True)
def _rms_scaled(x, y, fst):
    """``rms(x / (atol + rtol |y|))``."""
    n = x.shape[0]
    acc = 0.0
    for m in range(n):
        d = x[m] / (fst[F_ATOL] + fst[F_RTOL] * abs(y[m]))
        acc += d * d
    return math.sqrt(acc / n)


@numba.njit(cache=True)
def _initial_step(rhs, p, W, fst, ist, order):
    """Hairer-Norsett-Wanner II.4 starting step for an error of order ``order + 1`` (SciPy's)."""
    n = W.shape[1]
    t = fst[F_T]
    interval = abs(fst[F_TEND] - t)
    if interval == 0.0:
        return 0.0
    y, f = W[R_Y], W[R_F]
    d0 = _rms_scaled(y, y, fst)
    d1 = _rms_scaled(f, y, fst)
    h0 = 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1
    h0 = min(h0, interval)
    y1, f1 = W[R_YA], W[R_YB]
    for m in range(n):
        y1[m] = y[m] + h0 * f[m]
    rhs(t + h0, y1, f1, p)
    ist[S_NFEV] += 1
    for m in range(n):
        y1[m] = f1[m] - f[m]
    d2 = _rms_scaled(y1, y, fst) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / (order + 1))
    return min(100 * h0, h1, interval, fst[F_MAXSTEP])


@numba.njit(cache=True)
def _init(rhs, p, W, fst, ist):
    """``f(t0, y0)``, the initial step and, for GBS, the initial number of columns."""
    rhs(fst[F_T], W[R_Y], W[R_F], p)
    ist[S_NFEV] += 1
    if ist[S_METHOD] == _BS:  # ODEX's k ~ 0.6 (-log10 rtol) + 1.5
        digits = -math.log10(fst[F_RTOL] + 1e-40)
        k = max(2, min(KMAX - 1, int(digits * 0.6 + 1.5)))
        ist[S_K] = k
        order = 2 * k
    else:
        order = 7
    fst[F_H] = _initial_step(rhs, p, W, fst, ist, order)
    fst[F_HDENSE] = np.inf


@numba.njit(cache=True)
def _dense_eval(W, fst, ist, t, y):
    """The dense output of the last step at ``t``, into ``y``."""
    n = W.shape[1]
    t0 = fst[F_TOLD]
    h = fst[F_HSTEP]
    if ist[S_METHOD] == _BS:  # polynomial in u = 2 (t - t0) / h - 1
        u = 2.0 * (t - t0) / h - 1.0
        rows = ist[S_MU] + 5
        top = W[R_COEF + rows - 1]
        for m in range(n):
            y[m] = top[m]
        for r in range(rows - 2, -1, -1):
            c = W[R_COEF + r]
            for m in range(n):
                y[m] = y[m] * u + c[m]
        return
    # DOP853: y_old + x (F0 + (1 - x) (F1 + x (F2 + (1 - x) (F3 + x (F4 + (1 - x) (F5 + x F6))))))
    x = (t - t0) / h
    for m in range(n):
        y[m] = 0.0
    for i in range(7):
        c = W[R_COEF + 6 - i]
        fac = x if i % 2 == 0 else 1.0 - x
        for m in range(n):
            y[m] = (y[m] + c[m]) * fac
    yo = W[R_YOLD]
    for m in range(n):
        y[m] += yo[m]


@numba.njit(cache=True)
def _event_at(event, p, W, fst, ist, t):
    buf = W[R_BUF]
    _dense_eval(W, fst, ist, t, buf)
    return event(t, buf, p)


@numba.njit(cache=True)
def _brent(event, p, W, fst, ist, a, b, fa, fb):
    """Zero of the event on the dense output in ``[a, b]`` (``fa > 0 >= fb``), Brent's method.

    Tolerance as the reference driver's ``brentq(xtol=4 eps max(1, |b|), rtol=4 eps)``.
    """
    xtol = 4.0 * EPS * max(1.0, abs(b))
    c, fc = a, fa
    d = b - a
    e = d
    for _ in range(200):
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
        fb = _event_at(event, p, W, fst, ist, b)
    return b


@numba.njit(cache=True)
def _first_crossing(event, p, W, fst, ist, t_old, g_old, t_new, g_new, n_sub):
    """``(found, t)``: the first time in ``(t_old, t_new]`` where the event falls to <= 0.

    As :func:`lubelink.integrate.driver._first_crossing`: ``n_sub`` equal
    sub-intervals of the step, then Brent's method on the first bracket.
    """
    if not g_old > 0.0:
        return True, t_old
    step = (t_new - t_old) / n_sub
    lo, g_lo = t_old, g_old
    for i in range(1, n_sub + 1):
        t = t_new if i == n_sub else i * step + t_old
        g_t = g_new if i == n_sub else _event_at(event, p, W, fst, ist, t)
        if not g_t > 0.0:
            if g_t == 0.0:
                return True, t
            return True, _brent(event, p, W, fst, ist, lo, t, g_lo, g_t)
        lo, g_lo = t, g_t
    return False, 0.0


# ------------------------------------------------------------------------------------------------
# Gragg-Bulirsch-Stoer (port of bulirsch_stoer.BulirschStoer)
@numba.njit(cache=True)
def _bs_column(col, rhs, p, t, h, W, fst, ist):
    """Column ``col`` (1-based) of the tableau: ``(err, diverged)``; ``err < 0`` for column 1.

    Gragg's midpoint rule with ``n_j`` substeps (``j = col - 1``; ODEX's
    stability check on the first substep of the first two sequences), then
    Aitken-Neville extrapolation to ``T_jj`` in ``W[R_YNEW]``, its error
    estimate, the step it proposes ``H_j`` and the work per unit step ``W_j``.
    """
    nseq, seq_off, work, weights = _T_NSEQ, _T_SEQ_OFF, _T_WORK, _T_WEIGHTS
    n = W.shape[1]
    j = col - 1
    nj = nseq[j]
    hj = h / nj
    off = R_STORE + seq_off[j]
    y, f = W[R_Y], W[R_F]
    _copy_row(W, off, f)
    a_row, b_row = R_YA, R_YB  # previous and current substep values
    ya, yb = W[a_row], W[b_row]
    for m in range(n):
        ya[m] = y[m]
        yb[m] = f[m] * hj + y[m]
    for i in range(1, nj):
        prev, cur = W[a_row], W[b_row]
        if 2 * i == nj:
            _copy_row(W, R_YMID + j, cur)
        fi = W[off + i]
        rhs(t + i * hj, cur, fi, p)
        ist[S_NFEV] += 1
        if i == 1 and col <= _STAB_COLUMNS:
            stab = W[R_STAB]
            base = 0.0
            change = 0.0
            for m in range(n):
                a = f[m] / stab[m]
                b = (fi[m] - f[m]) / stab[m]
                base += a * a
                change += b * b
            base /= n
            change /= n
            if change > 4.0 * max(base, EPS) or not np.isfinite(change):
                return 0.0, True
        for m in range(n):
            prev[m] += fi[m] * (2.0 * hj)
        a_row, b_row = b_row, a_row
    fn = W[off + nj]
    rhs(t + h, W[b_row], fn, p)
    ist[S_NFEV] += 1
    t1 = W[R_T1 + j]
    prev, cur = W[a_row], W[b_row]
    for m in range(n):
        t1[m] = ((fn[m] * hj + prev[m]) + cur[m]) * 0.5
    ynew = W[R_YNEW]
    for m in range(n):  # element-wise over the state (vectorised)
        ynew[m] = 0.0
        W[R_TMP, m] = 0.0
    for i in range(col):
        w0 = weights[0, col, i]
        for m in range(n):
            ynew[m] += w0 * W[R_T1 + i, m]
    if col == 1:
        return -1.0, False
    for i in range(1, col):  # T_j,j-1 for the error estimate
        w1 = weights[1, col, i - 1]
        for m in range(n):
            W[R_TMP, m] += w1 * W[R_T1 + i, m]
    acc2 = 0.0
    for m in range(n):
        sc = fst[F_ATOL] + fst[F_RTOL] * max(abs(y[m]), abs(ynew[m]))
        d = (ynew[m] - W[R_TMP, m]) / sc
        acc2 += d * d
    err = math.sqrt(acc2 / n)
    if not err * EPS < 1.0 or (col > 2 and err >= fst[F_ERROLD]):
        return err, True
    fst[F_ERROLD] = max(4.0 * err, 1.0)
    expo = 1.0 / (2 * col - 1)
    facmin = _FAC1**expo
    fac = min(_FAC2 / facmin, max(facmin, (err / _SAFE1) ** expo / _SAFE2))
    fst[F_HH + col] = min(abs(h) / fac, fst[F_MAXSTEP])
    fst[F_WW + col] = work[col] / fst[F_HH + col]
    return err, False


@numba.njit(cache=True)
def _bs_dense(t, t_new, kc, W, fst, ist):
    """Dense-output coefficients of the step into ``W[R_COEF:]``; ``(errint, mu)``."""
    nseq, seq_off, weights, diff, hermite, taylor, eshape = (_T_NSEQ, _T_SEQ_OFF, _T_WEIGHTS, _T_DIFF, _T_HERMITE,
                                                             _T_TAYLOR, _T_ESHAPE)
    n = W.shape[1]
    h = t_new - t
    mu = max(2 * kc - _MU_DIFF + 1, 0)
    # element-wise over the state (vectorised): d[0], the extrapolated midpoint value, and
    # d[kappa] ~ H^kappa y^(kappa)(t_mid), extrapolated central differences of the f values
    for kappa in range(mu + 1):
        for m in range(n):
            W[R_COEF + kappa, m] = 0.0
    for j in range(kc):
        w = weights[0, kc, j] * taylor[0]
        for m in range(n):
            W[R_COEF, m] += w * W[R_YMID + j, m]
    for kappa in range(1, mu + 1):
        j0 = (kappa + 1) // 2 - 1
        r = kappa - 1
        row = R_COEF + kappa
        for j in range(j0, kc):
            mid = nseq[j] // 2
            off = R_STORE + seq_off[j]
            wj = weights[j0, kc, j - j0] * h * taylor[kappa]
            for i in range(mid - r, mid + r + 1, 2):
                c = diff[j, r, i] * wj
                for m in range(n):
                    W[row, m] += c * W[off + i, m]
    y, ynew, fold, fnew = W[R_Y], W[R_YNEW], W[R_F], W[R_FNEW]
    hinv = hermite[mu]
    errint = 0.0
    for m in range(n):
        r0 = y[m]
        r1 = ynew[m]
        r2 = 0.5 * h * fold[m]
        r3 = 0.5 * h * fnew[m]
        s0 = 0.0
        s1 = 0.0
        s2 = 0.0
        s3 = 0.0
        for kk in range(mu + 1):
            c = W[R_COEF + kk, m]
            sg = 1.0 if kk % 2 == 0 else -1.0
            s0 += sg * c
            s1 += c
            s2 += (kk * -sg) * c
            s3 += kk * c
        r0 -= s0
        r1 -= s1
        r2 -= s2
        r3 -= s3
        for row in range(4):
            W[R_COEF + mu + 1 + row, m] = hinv[row, 0] * r0 + hinv[row, 1] * r1 + hinv[row, 2] * r2 + hinv[row, 3] * r3
        if mu > 0:
            top = W[R_COEF + mu, m]
            sgm = 1.0 if mu % 2 == 0 else -1.0
            q0 = r0 + sgm * top
            q1 = r1 + top
            q2 = r2 - mu * sgm * top
            q3 = r3 + mu * top
            hl = hermite[mu - 1]
            c = top - (hl[0, 0] * q0 + hl[0, 1] * q1 + hl[0, 2] * q2 + hl[0, 3] * q3)
            sc = fst[F_ATOL] + fst[F_RTOL] * max(abs(y[m]), abs(ynew[m]))
            errint += (c / sc) ** 2
    if mu == 0:
        return 0.0, mu
    return math.sqrt(errint / n) * eshape[mu], mu


@numba.njit(cache=True)
def _bs_next(kc, k, h_abs, reject, fst, work):
    """ODEX's choice of columns and step size after an accepted step."""
    ww = fst[F_WW:F_WW + KMAX + 2]
    hh = fst[F_HH:F_HH + KMAX + 2]
    top = KMAX - 1
    if kc == 2:
        kopt = 2 if reject else min(3, top)
    elif kc <= k:
        kopt = kc
        if ww[kc - 1] < ww[kc] * _FAC3:
            kopt = kc - 1
        if ww[kc] < ww[kc - 1] * _FAC4:
            kopt = min(kc + 1, top)
    else:
        kopt = kc - 1
        if kc > 3 and ww[kc - 2] < ww[kc - 1] * _FAC3:
            kopt = kc - 2
        if ww[kc] < ww[kopt] * _FAC4:
            kopt = min(kc, top)
    if reject:
        kopt = min(kopt, kc)
        return kopt, min(h_abs, hh[kopt])
    if kopt <= kc:
        return kopt, hh[kopt]
    if kc < k and ww[kc] < ww[kc - 1] * _FAC4:
        return kopt, hh[kc] * work[kopt + 1] / work[kc]
    return kopt, hh[kc] * work[kopt] / work[kc]


@numba.njit(cache=True)
def _bs_step(rhs, p, W, fst, ist):
    """One accepted GBS step (``BulirschStoer._step_impl``); False if the step size underflows."""
    nseq = _T_NSEQ
    n = W.shape[1]
    t = fst[F_T]
    h_abs = fst[F_H]
    k = ist[S_K]
    t_end = fst[F_TEND]
    min_step = 10.0 * abs(np.nextafter(t, np.inf) - t)
    remaining = abs(t_end - t)
    reject = False
    restart = True
    while True:
        if restart:
            h_abs = min(h_abs, fst[F_MAXSTEP], fst[F_HDENSE])
        last = 1.01 * h_abs >= remaining
        if last:
            h_abs = remaining
        if h_abs < min_step:
            return False
        full = restart and (ist[S_NACC] == 0 or last)
        h = h_abs
        # one attempt (BulirschStoer._attempt) as one loop over the columns: ``full`` computes
        # columns 1 ... k and accepts at the first converged one (first and last step); otherwise
        # the convergence monitor over the window k - 1, k, k + 1 decides
        for m in range(n):
            W[R_STAB, m] = fst[F_ATOL] + fst[F_RTOL] * abs(W[R_Y, m])
        col = 0
        kc = 0
        accepted = False
        diverged = False
        while True:
            col += 1
            err, diverged = _bs_column(col, rhs, p, t, h, W, fst, ist)
            kc = col
            if diverged:
                break
            if full:
                if col > 1 and err <= 1.0:
                    accepted = True
                    break
                if col == k:
                    accepted = err <= 1.0
                    break
            elif col == k - 1:
                if k > 2 and not reject:
                    if err <= 1.0:
                        accepted = True
                        break
                    if err > (nseq[k] * nseq[k - 1] / nseq[0] ** 2) ** 2:
                        break
            elif col == k:
                if err <= 1.0:
                    accepted = True
                    break
                if err > (nseq[k] / nseq[0]) ** 2:
                    break
            elif col == k + 1:
                accepted = err <= 1.0
                break
        if diverged:
            ist[S_NREJ] += 1
            h_abs *= _SAFE3
            reject = True
            restart = True
            continue
        if not accepted:  # fewer columns if they work better per unit step
            ist[S_NREJ] += 1
            k = min(k, kc, KMAX - 1)
            if k > 2 and fst[F_WW + k - 1] < fst[F_WW + k] * _FAC3:
                k -= 1
            h_abs = fst[F_HH + k]
            reject = True
            restart = False
            continue
        t_new = t_end if last else t + h
        rhs(t_new, W[R_YNEW], W[R_FNEW], p)
        ist[S_NFEV] += 1
        errint, mu = _bs_dense(t, t_new, kc, W, fst, ist)
        fst[F_HDENSE] = h_abs / max(errint ** (1.0 / (mu + 4)), 0.01)
        if errint > _DENSE_REJECT:
            ist[S_NREJ] += 1
            h_abs = fst[F_HDENSE]
            reject = True
            restart = True
            continue
        kopt, h_next = _bs_next(kc, k, h_abs, reject, fst, _T_WORK)
        ist[S_K] = kopt
        fst[F_H] = h_next
        for m in range(n):
            W[R_YOLD, m] = W[R_Y, m]
            W[R_FOLD, m] = W[R_F, m]
            W[R_Y, m] = W[R_YNEW, m]
            W[R_F, m] = W[R_FNEW, m]
        fst[F_TOLD] = t
        fst[F_HSTEP] = t_new - t
        fst[F_T] = t_new
        ist[S_KC] = kc
        ist[S_MU] = mu
        ist[S_NACC] += 1
        ist[S_DENSE] = 1
        return True


# ------------------------------------------------------------------------------------------------
# DOP853 (the algorithm of scipy.integrate.DOP853)
@numba.njit(cache=True)
def _combine(W, dst, coef, row, count):
    """``W[dst] = sum_{i < count} coef[row, i] K_i`` (the stages ``K_i = W[R_STORE + i]``).

    Element-wise over the state, zero coefficients skipped (DOP853's tables are sparse).
    """
    n = W.shape[1]
    for m in range(n):
        W[dst, m] = 0.0
    for i in range(count):
        a = coef[row, i]
        if a != 0.0:
            r = R_STORE + i
            for m in range(n):
                W[dst, m] += W[r, m] * a


@numba.njit(cache=True)
def _dop_stage(s, rhs, p, t, h, y, W, ist):
    """Stage ``s``: ``K_s = f(t + c_s h, y + h sum_i a_si K_i)``."""
    n = W.shape[1]
    _combine(W, np.int64(R_TMP), _T_DOP_A, s, s)
    for m in range(n):
        W[R_TMP, m] = y[m] + W[R_TMP, m] * h
    rhs(t + _T_DOP_C[s] * h, W[R_TMP], W[R_STORE + s], p)
    ist[S_NFEV] += 1


@numba.njit(cache=True)
def _dop_step(rhs, p, W, fst, ist):
    """One accepted DOP853 step (``scipy.integrate._ivp.rk.RungeKutta._step_impl``)."""
    n = W.shape[1]
    t = fst[F_T]
    y, f = W[R_Y], W[R_F]
    t_end = fst[F_TEND]
    min_step = 10.0 * abs(np.nextafter(t, np.inf) - t)
    h_abs = fst[F_H]
    if h_abs > fst[F_MAXSTEP]:
        h_abs = fst[F_MAXSTEP]
    elif h_abs < min_step:
        h_abs = min_step
    rejected = False
    while True:
        if h_abs < min_step:
            return False
        h = h_abs
        t_new = t + h
        if t_new - t_end > 0.0:
            t_new = t_end
        h = t_new - t
        h_abs = abs(h)
        _copy_row(W, np.int64(R_STORE), f)
        for s in range(1, 12):
            _dop_stage(s, rhs, p, t, h, y, W, ist)
        ynew = W[R_YNEW]
        _combine(W, np.int64(R_YNEW), _T_DOP_A, np.int64(12), np.int64(12))  # the weights b are row 12 of A
        for m in range(n):
            ynew[m] = y[m] + h * ynew[m]
        rhs(t + h, ynew, W[R_STORE + 12], p)
        ist[S_NFEV] += 1
        _combine(W, np.int64(R_YA), _T_DOP_E, np.int64(0), np.int64(13))  # the 5th- and 3rd-order error estimates
        _combine(W, np.int64(R_YB), _T_DOP_E, np.int64(1), np.int64(13))
        e5 = 0.0
        e3 = 0.0
        for m in range(n):
            sc = fst[F_ATOL] + max(abs(y[m]), abs(ynew[m])) * fst[F_RTOL]
            e5 += (W[R_YA, m] / sc) ** 2
            e3 += (W[R_YB, m] / sc) ** 2
        if e5 == 0.0 and e3 == 0.0:
            error_norm = 0.0
        else:
            error_norm = abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * n)
        if error_norm < 1.0:
            if error_norm == 0.0:
                factor = _MAX_FACTOR
            else:
                factor = min(_MAX_FACTOR, _SAFETY * error_norm**_DOP_EXPONENT)
            if rejected:
                factor = min(1.0, factor)
            h_abs *= factor
            break
        h_abs *= max(_MIN_FACTOR, _SAFETY * error_norm**_DOP_EXPONENT)
        rejected = True
    for m in range(n):
        W[R_YOLD, m] = y[m]
        W[R_FOLD, m] = f[m]
        y[m] = ynew[m]
        f[m] = W[R_STORE + 12, m]
    fst[F_TOLD] = t
    fst[F_HSTEP] = h
    fst[F_T] = t_new
    fst[F_H] = h_abs
    ist[S_NACC] += 1
    ist[S_DENSE] = 0
    return True


@numba.njit(cache=True)
def _dop_dense(rhs, p, W, fst, ist):
    """Hairer's 7th-order interpolant of the last step (three more stages) into ``W[R_COEF:]``."""
    n = W.shape[1]
    h = fst[F_HSTEP]
    t_old = fst[F_TOLD]
    y_old = W[R_YOLD]
    for s in range(13, 16):
        _dop_stage(s, rhs, p, t_old, h, y_old, W, ist)
    y, f, f_old = W[R_Y], W[R_F], W[R_STORE]
    for r in range(4):
        _combine(W, R_COEF + 3 + r, _T_DOP_D, r, np.int64(16))
    for m in range(n):
        dy = y[m] - y_old[m]
        W[R_COEF, m] = dy
        W[R_COEF + 1, m] = h * f_old[m] - dy
        W[R_COEF + 2, m] = 2.0 * dy - h * (f[m] + f_old[m])
        for r in range(4):
            W[R_COEF + 3 + r, m] *= h
    ist[S_DENSE] = 1


# ------------------------------------------------------------------------------------------------
@numba.njit(cache=True)
def _advance(rhs, event, p, t_eval, out, W, fst, ist):
    """Integrate until ``t_end``, an event, a failure, ``fst[F_TPAUSE]`` or ``ist[S_MAXSTEPS]`` steps.

    Returns ``_RUNNING`` (paused: call again), ``_FINISHED``, ``_EVENT`` or
    ``_FAILED``; the state, the samples written to ``out[:ist[S_IEVAL]]``
    and the statistics are in ``W``, ``fst`` and ``ist``.
    """
    n = W.shape[1]
    method = ist[S_METHOD]
    if ist[S_INIT] == 0:
        ist[S_INIT] = 1
        _init(rhs, p, W, fst, ist)
        if ist[S_EVENT] != 0:
            fst[F_GOLD] = event(fst[F_T], W[R_Y], p)
        if fst[F_T] >= fst[F_TEND]:
            fst[F_TFINAL] = fst[F_T]
            _copy_row(W, np.int64(R_YFINAL), W[R_Y])
            return _FINISHED
    steps = 0
    n_eval = t_eval.shape[0]
    while True:
        if fst[F_T] >= fst[F_TPAUSE] or steps >= ist[S_MAXSTEPS]:
            return _RUNNING
        t_old = fst[F_T]
        if method == _BS:
            ok = _bs_step(rhs, p, W, fst, ist)
        else:
            ok = _dop_step(rhs, p, W, fst, ist)
        steps += 1
        ist[S_NSTEPS] += 1
        if not ok:
            ist[S_FAIL] = _FAIL_SMALL_STEP
            fst[F_TFINAL] = t_old
            _copy_row(W, np.int64(R_YFINAL), W[R_Y])
            return _FAILED
        t_new = fst[F_T]
        y_new = W[R_Y]
        for m in range(n):
            if not np.isfinite(y_new[m]):
                ist[S_FAIL] = _FAIL_NONFINITE
                fst[F_TFINAL] = t_old
                _copy_row(W, np.int64(R_YFINAL), W[R_YOLD])
                return _FAILED
        t_stop = t_new
        hit = False
        sample_event = False
        g_new = 0.0
        n_sub = 1
        if ist[S_EVENT] != 0:
            g_new = event(t_new, y_new, p)
            res = fst[F_RES]
            if res > 0.0 and t_new - t_old > res:
                n_sub = int(math.ceil((t_new - t_old) / res))
            sample_event = n_sub > 1 or not g_new > 0.0
        i = ist[S_IEVAL]
        j = i
        while j < n_eval and t_eval[j] <= t_new:
            j += 1
        if (sample_event or j > i) and ist[S_DENSE] == 0:
            _dop_dense(rhs, p, W, fst, ist)
        if sample_event:
            hit, t_c = _first_crossing(event, p, W, fst, ist, t_old, fst[F_GOLD], t_new, g_new, max(n_sub, 2))
            if hit:
                t_stop = t_c
                while j > i and t_eval[j - 1] > t_stop:
                    j -= 1
        if ist[S_EVENT] != 0:
            fst[F_GOLD] = g_new
        for r in range(i, j):
            _dense_eval(W, fst, ist, t_eval[r], out[r])
        ist[S_IEVAL] = j
        fst[F_TSTOP] = t_stop
        if hit:
            fst[F_TFINAL] = t_stop
            if t_stop != t_new:
                _dense_eval(W, fst, ist, t_stop, W[R_YFINAL])
            else:
                _copy_row(W, np.int64(R_YFINAL), y_new)
            return _EVENT
        if t_new >= fst[F_TEND]:
            fst[F_TFINAL] = t_new
            _copy_row(W, np.int64(R_YFINAL), y_new)
            return _FINISHED


@numba.njit(cache=True)
def _no_event(t, y, p):
    return 1.0


# ------------------------------------------------------------------------------------------------
# compilation
_lock = threading.Lock()
_compiled = False
_FIRST_CLASS = {}  # the model kernels as first-class functions
NOTICE = "lubelink: compiling the fast path (first run only, cached)…"
#: Seconds of compiling (or loading from the cache) after which :data:`NOTICE` is shown.
NOTICE_DELAY = 2.0


@contextlib.contextmanager
def _compile_notice():
    """Announce a compilation that takes longer than :data:`NOTICE_DELAY` (a cold cache).

    The notice goes to the ``lubelink`` logger (INFO) and, when standard
    error is a terminal, straight to it, so that a CLI user sees why the
    first run pauses. Loading from a warm cache is faster and says nothing.
    """
    def announce():
        log.info(NOTICE)
        stream = sys.stderr
        if stream is not None and getattr(stream, "isatty", lambda: False)():
            print(NOTICE, file=stream, flush=True)

    timer = threading.Timer(NOTICE_DELAY, announce)
    timer.daemon = True
    timer.start()
    try:
        yield
    finally:
        timer.cancel()


class _FirstClass(types.CompileResultWAP):
    """A compiled function as a first-class function object, with its Numba type computed once.

    Passing a dispatcher makes Numba look up the function's address on every call into compiled
    code, and a plain :class:`numba.core.types.CompileResultWAP` rebuilds its type on every call
    (about 30 us each, paid at every return to Python for progress).
    """

    def __init__(self, dispatcher, sig):
        # by the argument types, as a call from Python compiles it: Numba's cache index keys a
        # full signature differently, and one process would not find what the other cached
        dispatcher.compile(sig.args)
        super().__init__(dispatcher.overloads[sig.args])
        self.dispatcher = dispatcher
        self.numba_type = types.FunctionType(self.cres.signature)


@typeof_impl.register(_FirstClass)
def _typeof_first_class(val, c):
    return val.numba_type


def _first_class(dispatcher, sig):
    """``dispatcher`` compiled for ``sig``, as a first-class function object."""
    return _FirstClass(dispatcher, sig)


def _advance_signature():
    return (types.FunctionType(RHS_SIG), types.FunctionType(EVENT_SIG), types.float64[::1], types.float64[::1],
            types.float64[:, ::1], types.float64[:, ::1], types.float64[::1], types.int64[::1])


def compile_all():
    """Compile (or load from Numba's on-disk cache) the integrators and the model kernels.

    Called by :func:`make_segment_integrator` and :func:`solve`; the first
    call in a process takes about a second from a warm cache, tens of
    seconds from a cold one (then :data:`NOTICE` is shown).
    """
    global _compiled
    if _compiled:
        return
    with _lock:
        if _compiled:
            return
        with _compile_notice():
            from .. import _kernels

            start = time.perf_counter()
            _FIRST_CLASS["rhs"] = _first_class(_kernels.rhs, RHS_SIG)
            _FIRST_CLASS["event"] = _first_class(_kernels.event, EVENT_SIG)
            _FIRST_CLASS["no_event"] = _first_class(_no_event, EVENT_SIG)
            _advance.compile(_advance_signature())
            # calls with dispatchers must convert them to the first-class function type of this
            # signature, not compile (and fail to cache) a specialisation on the dispatcher types
            _advance.disable_compile()
            log.debug("lubelink fast path ready in %.2f s", time.perf_counter() - start)
        _compiled = True


# ------------------------------------------------------------------------------------------------
def _run_compiled(method, rhs, event, p, t0, y0, t_end, t_eval, *, rtol, atol, max_step, event_resolution,
                  deadline, progress):
    """Integrate one segment in compiled code; returns a :class:`Segment`."""
    y0 = np.asarray(y0, dtype=float)
    n = y0.size
    t_eval = np.ascontiguousarray(t_eval, dtype=float)
    W = np.zeros((ROWS, n))
    W[R_Y] = y0
    fst = np.zeros(F_SIZE)
    fst[F_T] = t0
    fst[F_TEND] = t_end
    fst[F_RTOL] = max(float(rtol), 100 * EPS)
    fst[F_ATOL] = atol
    fst[F_MAXSTEP] = max_step
    fst[F_RES] = event_resolution if event_resolution is not None else 0.0
    fst[F_TSTOP] = t0
    ist = np.zeros(S_SIZE, dtype=np.int64)
    ist[S_METHOD] = _BS if method == "bulirsch-stoer" else _DOP
    ist[S_EVENT] = int(event is not None)
    ist[S_MAXSTEPS] = STEPS_PER_CALL
    out = np.empty((t_eval.size, n))
    chunk = (t_end - t0) / CALLS_PER_SEGMENT
    ev = _FIRST_CLASS["no_event"] if event is None else event
    status, message = "finished", "reached the end of the interval"
    while True:
        fst[F_TPAUSE] = min(fst[F_T] + chunk, t_end)
        code = _advance(rhs, ev, p, t_eval, out, W, fst, ist)
        if progress is not None:
            progress(float(fst[F_TSTOP]))
        if code == _RUNNING:
            if deadline is not None and time.perf_counter() > deadline:
                status = "timeout"
                message = f"the wall-time budget ran out at t = {fst[F_T]:.9g} s"
                fst[F_TFINAL] = fst[F_T]
                W[R_YFINAL] = W[R_Y]
                break
            continue
        if code == _EVENT:
            status, message = "event", f"event at t = {fst[F_TFINAL]:.12g} s"
        elif code == _FAILED:
            status = "failed"
            if ist[S_FAIL] == _FAIL_NONFINITE:
                message = f"the state became non-finite at t = {fst[F_T]:.9g} s"
            else:
                name = "BulirschStoer" if method == "bulirsch-stoer" else "DOP853"
                message = f"{name} failed at t = {fst[F_TFINAL]:.9g} s: {TOO_SMALL_STEP}"
        break
    m = int(ist[S_IEVAL])
    return Segment(
        t=t_eval[:m].copy(), y=out[:m], status=status, message=message, t_final=float(fst[F_TFINAL]),
        y_final=W[R_YFINAL].copy(), nfev=int(ist[S_NFEV]), njev=0, nsteps=int(ist[S_NSTEPS]),
        extra={"last_step": float(fst[F_HSTEP]), "n_rejected": int(ist[S_NREJ]), "compiled": True},
    )


def solve(rhs, t_span, y0, p=None, *, method="bulirsch-stoer", rtol=1e-3, atol=1e-6, max_step=np.inf,
          t_eval=None, event=None, event_resolution=None, deadline=None, progress=None):
    """Integrate ``dy/dt = rhs(t, y)`` in compiled code, from ``t_span[0]`` to ``t_span[1]``.

    Parameters
    ----------
    rhs : numba dispatcher
        ``@numba.njit`` function ``rhs(t, y, out, p)`` writing ``dy/dt`` into
        ``out``; compiled here with :data:`RHS_SIG`.
    t_span : (float, float)
        ``t0 < t_end``.
    y0 : array_like, shape (n,)
        Initial state.
    p : ndarray of float64, optional
        Parameters passed to ``rhs`` (and ``event``).
    method : {"bulirsch-stoer", "DOP853"}
        Integrator.
    rtol, atol, max_step : float
        As SciPy's (scalar tolerances).
    t_eval : array_like, optional
        Increasing times in ``(t0, t_end]`` at which to sample the solution.
    event : numba dispatcher, optional
        ``event(t, y, p) -> float``, compiled with :data:`EVENT_SIG`: the
        integration stops where it falls from positive to ``<= 0``.
    event_resolution : float, optional
        Longest interval between two samples of ``event`` [time units].
    deadline : float, optional
        ``time.perf_counter()`` value after which to stop (status ``"timeout"``).
    progress : callable, optional
        ``progress(t)``, called about every 1 % of the interval.

    Returns
    -------
    lubelink.integrate.Segment
    """
    if method not in COMPILED_METHODS:
        raise ValueError(f"method = {method!r}: the compiled integrators are {', '.join(COMPILED_METHODS)}")
    compile_all()
    rhs = _first_class(rhs, RHS_SIG)
    if event is not None:
        event = _first_class(event, EVENT_SIG)
    t0, t_end = (float(v) for v in t_span)
    if not t_end >= t0:
        raise ValueError("solve integrates forward in time: t_span[1] must be >= t_span[0]")
    p = np.zeros(1) if p is None else np.ascontiguousarray(p, dtype=float)
    t_eval = np.empty(0) if t_eval is None else np.asarray(t_eval, dtype=float)
    return _run_compiled(method, rhs, event, p, t0, y0, t_end, t_eval, rtol=rtol, atol=atol, max_step=max_step,
                         event_resolution=event_resolution, deadline=deadline, progress=progress)


def make_segment_integrator(model, *, stepping="auto"):
    """The fast segment integrator of ``model``, or None if the configuration is not supported.

    Parameters
    ----------
    model : lubelink.model.Model
        The model (slider-crank motion, cavitation ``"none"`` or
        ``"half-sommerfeld"``).
    stepping : {"auto", "scipy"}
        ``"auto"``: compiled stepping for :data:`COMPILED_METHODS`, SciPy's
        for :data:`SCIPY_METHODS`; ``"scipy"``: SciPy's stepping (the
        project's :class:`~lubelink.integrate.bulirsch_stoer.BulirschStoer`
        for ``"bulirsch-stoer"``) on the compiled right-hand side for every
        method (for benchmarks).

    Returns
    -------
    callable or None
        ``segment(t0, y0, t_end, t_eval, *, phase, event_sign,
        event_resolution, deadline, progress) -> Segment``, with the contract
        of :func:`lubelink.simulate.reference_segment_integrator`.
    """
    from .. import _kernels

    why = _kernels.supported(model)
    s = model.config.solver
    if why is not None or s.method not in COMPILED_METHODS + SCIPY_METHODS:
        log.debug("lubelink: reference path (%s)", why or f"solver.method = {s.method!r}")
        return None
    compile_all()
    base = _kernels.pack(model)
    rhs, event = _FIRST_CLASS["rhs"], _FIRST_CLASS["event"]
    compiled = stepping == "auto" and s.method in COMPILED_METHODS

    def segment(t0, y0, t_end, t_eval, *, phase, event_sign, event_resolution, deadline, progress):
        p = _kernels.set_segment(base, phase, event_sign)
        if compiled:
            return _run_compiled(s.method, rhs, None if event_sign is None else event, p, t0, y0, t_end, t_eval,
                                 rtol=s.rtol, atol=s.atol, max_step=s.max_step, event_resolution=event_resolution,
                                 deadline=deadline, progress=progress)
        n = np.size(y0)

        def fun(t, y):
            out = np.empty(n)
            _kernels.rhs(t, np.ascontiguousarray(y, dtype=float), out, p)
            return out

        ev = None if event_sign is None else (
            lambda t, y: _kernels.event(t, np.ascontiguousarray(y, dtype=float), p))
        return integrate_segment(fun, t0, y0, t_end, t_eval, method=s.method, rtol=s.rtol, atol=s.atol,
                                 max_step=s.max_step, event=ev, event_resolution=event_resolution,
                                 deadline=deadline, progress=progress)

    return segment

"""Gragg-Bulirsch-Stoer (GBS) extrapolation integrator with step-size and order control.

Why this module exists
----------------------
No maintained Python library offers a Bulirsch-Stoer integrator: SciPy's
``solve_ivp`` has explicit Runge-Kutta (RK23, RK45, DOP853), Radau, BDF and
LSODA only. It is therefore written here, once: the kernels :func:`init`,
:func:`step` and :func:`dense` on the shared integration state
(:mod:`._layout`) are what the compiled driver runs, and
:class:`BulirschStoer`, a :class:`scipy.integrate.OdeSolver` for
``solve_ivp(..., method=BulirschStoer)``, is a thin wrapper that runs the same
source as Python on the user's function. It knows nothing of the problem it
integrates.

Method
------
A step of size ``H`` from ``(t0, y0)`` runs the explicit midpoint rule with
``n_j`` substeps of size ``h_j = H / n_j`` (Gragg's method, ending with his
smoothing step) for ``j = 1, 2, ...``. The result ``T_j1`` has an error
expansion in even powers of ``h_j``, so Aitken-Neville extrapolation to
``h = 0`` gives ``T_jj`` of order ``2j``. The error of ``T_jj`` is estimated
by ``T_jj - T_j,j-1`` in SciPy's norm::

    err_j = rms((T_jj - T_j,j-1) / (atol + rtol * max(|y0|, |T_jj|)))

and the step is accepted when ``err_j <= 1``.

Order and step size follow the ODEX strategy of Hairer, Norsett & Wanner [1]_
(Section II.9), which refines Deuflhard's [2]_: every column ``j`` proposes a
step ``H_j`` from ``err_j``; the number of columns ``k`` for the next step is
the one with the least work per unit step ``W_j = A_j / H_j`` (``A_j`` is the
number of function evaluations for ``j`` columns), changed by at most one per
step; within a step a convergence monitor over the order window
``k - 1, k, k + 1`` accepts early, or rejects as soon as convergence by column
``k + 1`` is improbable. Divergence of the tableau and a stability check on
the first midpoint substeps halve the step.

Step-number sequence
--------------------
``n_j = 4j - 2 = 2, 6, 10, 14, ...`` instead of the harmonic ``2, 4, 6, 8``.
It grows linearly like the harmonic one, but all midpoint indices ``n_j / 2``
are odd. The dense output extrapolates values at the midpoint of the step,
and the GBS error expansion at grid point ``i`` depends on the parity of
``i``, so they must share a parity: ``2, 4, 6, 8`` mixes them. ODEX makes the
same choice whenever dense output is requested; ``solve_ivp`` needs the
dense output for events and ``t_eval``, so this class always uses it.

Dense output
------------
As in ODEX (Hairer-Norsett-Wanner II.9, "Dense output for the GBS method"):
the midpoint values ``y^(n_j/2)`` are extrapolated to ``y(t_mid)``, and
central differences (stride ``2 h_j``) of the stored ``f`` values around the
midpoint, extrapolated over the sequences that reach far enough, give
``H^kappa y^(kappa)(t_mid)`` for ``kappa = 1 ... mu`` with ``mu = 2k - 3``.
The interpolant is the polynomial of degree ``mu + 4`` that also matches
``y`` and ``H f`` at both ends of the step. Its local error is ``O(H^(2k))``,
one power of ``H`` less than the step's (the midpoint values, at odd grid
indices, carry an error term that does not vanish at ``t0``): measured
slopes 4.1 for ``k = 2`` and 6.0 for ``k = 3``, so the interpolant is of
order ``2k - 1 >= 5`` once ``k >= 3``. The difference to the interpolant of
one degree less estimates the interpolation error, and a step whose
estimate exceeds ten times the tolerance is rejected, as in ODEX; this
keeps the dense output within a small multiple of the tolerance at any
order. No function evaluations are added: the ``f`` values are those of the
midpoint sequences, and ``f(t1, y1)`` is reused as ``f0`` of the next step.

References
----------
.. [1] E. Hairer, S. P. Norsett, G. Wanner, "Solving Ordinary Differential
       Equations I: Nonstiff Problems", 2nd ed., Springer, 1993, Section II.9
       (the ODEX code).
.. [2] P. Deuflhard, "Order and stepsize control in extrapolation methods",
       Numer. Math. 41 (1983), 399-422.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from scipy.integrate import DenseOutput, OdeSolver

from .._jit import jitable, kernel
from ._layout import (F_DIR, F_H, F_HSTEP, F_MAXSTEP, F_METHOD, F_T, F_TEND, F_TOLD, FAIL_RHS, R_ATOL, R_F, R_FOLD,
                      R_METHOD, R_RTOL, R_Y, R_YOLD, S_DENSE, S_FAIL, S_METHOD, S_NFEV, S_NREJ)
from .control import EPS, TOO_SMALL_STEP, initial_step

__all__ = ["BulirschStoer", "GBSDenseOutput", "step_number_sequence", "init", "step", "dense", "rows", "setup"]

DEFAULT_MAX_ORDER = 9  # columns of the tableau, as ODEX's default KM = 9
KMAX = 12  # the most columns any configuration may use (the tables are built for it)

# ODEX defaults (Hairer-Norsett-Wanner II.9).
_FAC1 = 0.02  # H_j / H is kept within [fac1**e / fac2, fac1**-e], e = 1/(2j-1)
_FAC2 = 4.0
_FAC3 = 0.8  # fewer columns if W_{k-1} < fac3 * W_k
_FAC4 = 0.9  # more columns if W_k < fac4 * W_{k-1}
_SAFE1 = 0.65  # H_j = H * safe2 * (safe1 / err_j)**(1/(2j-1))
_SAFE2 = 0.94
_SAFE3 = 0.5  # step reduction after divergence or failed stability check
_STAB_COLUMNS = 2  # the stability check runs in the first two sequences
_MU_DIFF = 4  # interpolant uses midpoint derivatives up to mu = 2k - _MU_DIFF + 1
_DENSE_REJECT = 10.0  # reject a step whose interpolation error exceeds this


def step_number_sequence(max_order):
    """Substep numbers ``n_j = 4j - 2`` for ``j = 1 ... max_order``."""
    return 4 * np.arange(1, max_order + 1) - 2


def _extrapolation_weights(n):
    """Weights ``c`` such that ``sum_j c_j T_j`` is the value at ``h = 0``.

    ``T_j`` are samples at ``h_j = H / n_j`` of a polynomial in ``h**2``; ``c_j`` is the Lagrange
    basis polynomial ``L_j(0)`` in ``x = h**2``.
    """
    n2 = np.asarray(n, dtype=float) ** 2
    weights = np.empty(n2.size)
    for j, nj2 in enumerate(n2):
        others = np.delete(n2, j)
        weights[j] = np.prod(nj2 / (nj2 - others))
    return weights


def _difference_operator(n, rows):
    """Rows ``p = 0 ... rows-1``: ``(n/2)**p * delta**p f`` at the midpoint ``n/2``.

    ``delta g_i = g_(i+1) - g_(i-1)`` (stride two, so that only grid points of one parity enter).
    Times ``H`` this approximates ``H^(p+1) y^(p+1)`` at the midpoint of the step.
    """
    m = n // 2
    op = np.zeros((rows, n + 1))
    for p in range(rows):
        for l in range(p + 1):
            op[p, m + p - 2 * l] += (-1) ** l * math.comb(p, l)
        op[p] *= (n / 2) ** p
    return op


def _hermite_inverse(mu):
    """Inverse of the end conditions for ``u**(mu+1) * (a0 + a1 u + a2 u**2 + a3 u**3)``.

    Rows: value at ``u = -1``, value at ``u = +1``, derivative at ``-1``, at ``+1``.
    """
    powers = mu + 1 + np.arange(4)
    matrix = np.array([(-1.0) ** powers, np.ones(4), powers * (-1.0) ** (powers - 1), powers.astype(float)])
    return np.linalg.inv(matrix)


def _max_error_shape(mu):
    """``max |u**mu (1 - u**2)**2|`` on ``[-1, 1]``."""
    if mu == 0:
        return 1.0
    v = mu / (mu + 4.0)
    return v ** (mu / 2.0) * (1.0 - v) ** 2


def _method_tables():
    """The constants of the method for up to :data:`KMAX` columns, as arrays (frozen into compiled code)."""
    nseq = step_number_sequence(KMAX).astype(np.int64)
    seq_off = np.concatenate(([0], np.cumsum(nseq + 1)[:-1])).astype(np.int64)
    work = np.concatenate(([0.0], 1.0 + np.cumsum(nseq)))  # A_j, 1-based: f0 plus n_i per sequence i <= j
    weights = np.zeros((KMAX, KMAX + 1, KMAX))  # weights[a, b, :b - a]: extrapolation over sequences a..b-1
    for b in range(1, KMAX + 1):
        for a in range(b):
            weights[a, b, :b - a] = _extrapolation_weights(nseq[a:b])
    diff = np.zeros((KMAX, 2 * KMAX, int(nseq[-1]) + 1))
    for j, n in enumerate(nseq):
        op = _difference_operator(int(n), 2 * (j + 1))
        diff[j, :op.shape[0], :op.shape[1]] = op
    n_mu = 2 * KMAX + 1
    hermite = np.array([_hermite_inverse(mu) for mu in range(n_mu)])
    taylor = np.array([1.0 / (math.factorial(i) * 2.0 ** i) for i in range(n_mu)])
    eshape = np.array([_max_error_shape(mu) for mu in range(n_mu)])
    return nseq, seq_off, work, weights, diff, hermite, taylor, eshape


_NSEQ, _SEQ_OFF, _WORK, _WEIGHTS, _DIFF, _HERMITE, _TAYLOR, _ESHAPE = _method_tables()

# rows of W
R_YNEW = R_METHOD
R_FNEW = R_YNEW + 1
R_YA = R_FNEW + 1  # midpoint rule: previous and current substep values
R_YB = R_YA + 1
R_TMP = R_YB + 1
R_STAB = R_TMP + 1  # atol + rtol |y| for the stability check
R_T1 = R_STAB + 1  # T_j1, KMAX rows
R_YMID = R_T1 + KMAX  # midpoint values, KMAX rows
R_COEF = R_YMID + KMAX  # dense output coefficients, 2 KMAX + 5 rows
R_STORE = R_COEF + 2 * KMAX + 5  # f values of the midpoint sequences
# slots of fst and ist
F_ERROLD = F_METHOD
F_HDENSE = F_METHOD + 1
F_HH = F_METHOD + 2  # step proposed by column j (1-based), KMAX + 2 entries
F_WW = F_HH + KMAX + 2  # work per unit step of column j
FLOATS = F_WW + KMAX + 2
S_K, S_KC, S_MU, S_NACC, S_MAXORDER, S_FIXED, S_ADAPTIVE, S_DENSECONTROL = range(S_METHOD, S_METHOD + 8)
INTS = S_METHOD + 8


def rows(n):
    """Rows of ``W`` this method uses."""
    return R_STORE + int(np.sum(_NSEQ + 1))


def setup(W, fst, ist, options):
    """The method's options: ``max_order`` (3-12), ``fixed_order``, ``adaptive``, ``dense_error_control``, ``first_step``."""
    ist[S_MAXORDER] = options.get("max_order", DEFAULT_MAX_ORDER)
    ist[S_FIXED] = options.get("fixed_order") or 0
    ist[S_ADAPTIVE] = int(options.get("adaptive", True))
    ist[S_DENSECONTROL] = int(options.get("dense_error_control", True) and options.get("adaptive", True))
    if options.get("first_step") is not None:
        fst[F_H] = options["first_step"]


# --- one column of the tableau ---------------------------------------------------------------------
@jitable
def _column(col, rhs, p, t, h, W, fst, ist, checks):
    """Column ``col`` (1-based): ``(err, diverged)``; ``err < 0`` for column 1.

    Gragg's midpoint rule with ``n_j`` substeps (``j = col - 1``; ODEX's stability check on the
    first substep of the first two sequences), then Aitken-Neville extrapolation to ``T_jj`` in
    ``W[R_YNEW]``, its error estimate, the step it proposes ``H_j`` and the work per unit step
    ``W_j``.
    """
    n = W.shape[1]
    j = col - 1
    nj = _NSEQ[j]
    hj = h / nj
    off = R_STORE + _SEQ_OFF[j]
    for m in range(n):
        W[off, m] = W[R_F, m]
        W[R_YA, m] = W[R_Y, m]
        W[R_YB, m] = W[R_F, m] * hj + W[R_Y, m]
    a_row, b_row = R_YA, R_YB  # previous and current substep values
    for i in range(1, nj):
        if 2 * i == nj:
            for m in range(n):
                W[R_YMID + j, m] = W[b_row, m]
        rhs(t + i * hj, W[b_row], W[off + i], p)
        ist[S_NFEV] += 1
        if checks and i == 1 and col <= _STAB_COLUMNS:
            base = 0.0
            change = 0.0
            for m in range(n):
                base += abs(W[R_F, m] / W[R_STAB, m]) ** 2
                change += abs((W[off + 1, m] - W[R_F, m]) / W[R_STAB, m]) ** 2
            if change / n > 4.0 * max(base / n, EPS) or not np.isfinite(change):
                return 0.0, True
        for m in range(n):
            W[a_row, m] += W[off + i, m] * (2.0 * hj)
        a_row, b_row = b_row, a_row
    rhs(t + h, W[b_row], W[off + nj], p)
    ist[S_NFEV] += 1
    for m in range(n):
        W[R_T1 + j, m] = ((W[off + nj, m] * hj + W[a_row, m]) + W[b_row, m]) * 0.5
        W[R_YNEW, m] = 0.0
        W[R_TMP, m] = 0.0
    for i in range(col):
        w0 = _WEIGHTS[0, col, i]
        for m in range(n):
            W[R_YNEW, m] += w0 * W[R_T1 + i, m]
    if col == 1:
        return -1.0, False
    for i in range(1, col):  # T_j,j-1 for the error estimate
        w1 = _WEIGHTS[1, col, i - 1]
        for m in range(n):
            W[R_TMP, m] += w1 * W[R_T1 + i, m]
    acc = 0.0
    for m in range(n):
        sc = W[R_ATOL, m].real + W[R_RTOL, m].real * max(abs(W[R_Y, m]), abs(W[R_YNEW, m]))
        acc += abs((W[R_YNEW, m] - W[R_TMP, m]) / sc) ** 2
    err = math.sqrt(acc / n)
    if not np.isfinite(err):  # NaN or infinity in the tableau: shrink, and say so if it underflows
        ist[S_FAIL] = FAIL_RHS
        return err, True
    if checks:
        if not err * EPS < 1.0 or (col > 2 and err >= fst[F_ERROLD]):
            return err, True
        fst[F_ERROLD] = max(4.0 * err, 1.0)
    expo = 1.0 / (2 * col - 1)
    facmin = _FAC1**expo
    fac = min(_FAC2 / facmin, max(facmin, (err / _SAFE1) ** expo / _SAFE2))
    fst[F_HH + col] = min(abs(h) / fac, fst[F_MAXSTEP])
    fst[F_WW + col] = _WORK[col] / fst[F_HH + col]
    return err, False


@jitable
def _attempt(rhs, p, t, h, k, full, reject, W, fst, ist):
    """Try a step of signed size ``h`` aiming at ``k`` columns: ``(accepted, kc, diverged)``.

    ``full`` computes columns 1 ... k and accepts at the first converged one (ODEX's first and
    last step; always with a fixed order, which accepts at column k only); otherwise the
    convergence monitor over the window ``k - 1, k, k + 1`` decides.
    """
    n = W.shape[1]
    for m in range(n):
        W[R_STAB, m] = W[R_ATOL, m].real + W[R_RTOL, m].real * abs(W[R_Y, m])
    fixed = ist[S_FIXED] != 0
    if full:
        err = 0.0
        for col in range(1, k + 1):
            err, diverged = _column(col, rhs, p, t, h, W, fst, ist, True)
            if diverged:
                return False, col, True
            if col > 1 and err <= 1.0 and not fixed:
                return True, col, False
        return err <= 1.0, k, False
    err = 0.0
    for col in range(1, k):
        err, diverged = _column(col, rhs, p, t, h, W, fst, ist, True)
        if diverged:
            return False, col, True
    if k > 2 and not reject:
        if err <= 1.0:
            return True, k - 1, False
        if err > (_NSEQ[k] * _NSEQ[k - 1] / _NSEQ[0] ** 2) ** 2:
            return False, k - 1, False
    err, diverged = _column(k, rhs, p, t, h, W, fst, ist, True)
    if diverged:
        return False, k, True
    if err <= 1.0:
        return True, k, False
    if err > (_NSEQ[k] / _NSEQ[0]) ** 2:
        return False, k, False
    err, diverged = _column(k + 1, rhs, p, t, h, W, fst, ist, True)
    if diverged:
        return False, k + 1, True
    return err <= 1.0, k + 1, False


@jitable
def _order_after_rejection(k, kc, fst, ist):
    if ist[S_FIXED] != 0:
        return k
    k = min(k, kc, ist[S_MAXORDER] - 1)
    if k > 2 and fst[F_WW + k - 1] < fst[F_WW + k] * _FAC3:
        k -= 1
    return k


@jitable
def _next_order_and_step(kc, k, h_abs, reject, fst, ist):
    """ODEX's choice of columns and step size after an accepted step."""
    if ist[S_FIXED] != 0:
        return k, (min(h_abs, fst[F_HH + k]) if reject else fst[F_HH + k])
    top = ist[S_MAXORDER] - 1
    ww = F_WW
    if kc == 2:
        kopt = 2 if reject else min(3, top)
    elif kc <= k:
        kopt = kc
        if fst[ww + kc - 1] < fst[ww + kc] * _FAC3:
            kopt = kc - 1
        if fst[ww + kc] < fst[ww + kc - 1] * _FAC4:
            kopt = min(kc + 1, top)
    else:
        kopt = kc - 1
        if kc > 3 and fst[ww + kc - 2] < fst[ww + kc - 1] * _FAC3:
            kopt = kc - 2
        if fst[ww + kc] < fst[ww + kopt] * _FAC4:
            kopt = min(kc, top)
    if reject:
        kopt = min(kopt, kc)
        return kopt, min(h_abs, fst[F_HH + kopt])
    if kopt <= kc:
        return kopt, fst[F_HH + kopt]
    if kc < k and fst[ww + kc] < fst[ww + kc - 1] * _FAC4:
        return kopt, fst[F_HH + kc] * _WORK[kopt + 1] / _WORK[kc]
    return kopt, fst[F_HH + kc] * _WORK[kopt] / _WORK[kc]


# --- dense output ----------------------------------------------------------------------------------
@jitable
def _coefficients(W, ist, r_y0, r_y1, r_f0, r_f1, h, kc):
    """Dense-output coefficients of a step of size ``h`` with ``kc`` columns into ``W[R_COEF:]``; ``(errint, mu)``.

    ``r_y0``, ``r_y1``, ``r_f0``, ``r_f1``: the rows of ``W`` holding ``y`` and ``f`` at both ends.
    The coefficients are in powers of ``u = 2 (t - t_old) / H - 1``.

    The polynomial matches ``y`` and ``H f`` at ``u = -1, 1`` and, as coefficient of ``u^kappa``,
    ``d[kappa] / (kappa! 2^kappa)`` with ``d[kappa] ~ H^kappa y^(kappa)(t_mid)``, ``kappa <= mu``:
    the extrapolated midpoint value and extrapolated central differences of the ``f`` values
    (HNW II.9). The estimate is the largest scaled difference to the polynomial with ``mu - 1``,
    ``c u^mu (1 - u^2)^2``.
    """
    n = W.shape[1]
    mu = max(2 * kc - _MU_DIFF + 1, 0)
    ist[S_MU] = mu
    for kappa in range(mu + 1):
        for m in range(n):
            W[R_COEF + kappa, m] = 0.0
    for j in range(kc):
        w = _WEIGHTS[0, kc, j] * _TAYLOR[0]
        for m in range(n):
            W[R_COEF, m] += w * W[R_YMID + j, m]
    for kappa in range(1, mu + 1):
        j0 = (kappa + 1) // 2 - 1
        r = kappa - 1
        for j in range(j0, kc):
            mid = _NSEQ[j] // 2
            off = R_STORE + _SEQ_OFF[j]
            wj = _WEIGHTS[j0, kc, j - j0] * h * _TAYLOR[kappa]
            for i in range(mid - r, mid + r + 1, 2):
                c = _DIFF[j, r, i] * wj
                for m in range(n):
                    W[R_COEF + kappa, m] += c * W[off + i, m]
    hinv = _HERMITE[mu]
    errint = 0.0
    for m in range(n):
        r0 = W[r_y0, m]
        r1 = W[r_y1, m]
        r2 = 0.5 * h * W[r_f0, m]
        r3 = 0.5 * h * W[r_f1, m]
        for kk in range(mu + 1):
            c = W[R_COEF + kk, m]
            sg = 1.0 if kk % 2 == 0 else -1.0
            r0 -= sg * c
            r1 -= c
            r2 -= (kk * -sg) * c
            r3 -= kk * c
        for row in range(4):
            W[R_COEF + mu + 1 + row, m] = hinv[row, 0] * r0 + hinv[row, 1] * r1 + hinv[row, 2] * r2 + hinv[row, 3] * r3
        if mu > 0:
            top = W[R_COEF + mu, m]
            sgm = 1.0 if mu % 2 == 0 else -1.0
            hl = _HERMITE[mu - 1]
            c = top - (hl[0, 0] * (r0 + sgm * top) + hl[0, 1] * (r1 + top) + hl[0, 2] * (r2 - mu * sgm * top)
                       + hl[0, 3] * (r3 + mu * top))
            sc = W[R_ATOL, m].real + W[R_RTOL, m].real * max(abs(W[r_y0, m]), abs(W[r_y1, m]))
            errint += abs(c / sc) ** 2
    ist[S_DENSE] = 1
    if mu == 0:
        return 0.0, mu
    return math.sqrt(errint / n) * _ESHAPE[mu], mu


# --- the kernels -----------------------------------------------------------------------------------------
@kernel
def init(rhs, p, W, fst, ist):
    """``f(t0, y0)``, ODEX's first number of columns ``k ~ 0.6 (-log10 rtol) + 1.5`` and the starting step."""
    n = W.shape[1]
    rhs(fst[F_T], W[R_Y], W[R_F], p)
    ist[S_NFEV] += 1
    rtol = W[R_RTOL, 0].real
    for m in range(n):
        rtol = min(rtol, W[R_RTOL, m].real)
    if ist[S_FIXED] != 0:
        ist[S_K] = ist[S_FIXED]
    else:
        ist[S_K] = max(2, min(ist[S_MAXORDER] - 1, int(-math.log10(rtol + 1e-40) * 0.6 + 1.5)))
    ist[S_KC] = ist[S_K]
    fst[F_HDENSE] = np.inf
    if fst[F_H] == 0.0:
        fst[F_H] = initial_step(rhs, p, W, fst, ist, 2 * ist[S_K], W[R_TMP], W[R_FNEW])


@jitable
def _accept(t, t_new, kc, W, fst, ist):
    n = W.shape[1]
    for m in range(n):
        W[R_YOLD, m] = W[R_Y, m]
        W[R_FOLD, m] = W[R_F, m]
        W[R_Y, m] = W[R_YNEW, m]
        W[R_F, m] = W[R_FNEW, m]
    fst[F_TOLD] = t
    fst[F_HSTEP] = t_new - t
    fst[F_T] = t_new
    ist[S_KC] = kc
    ist[S_NACC] += 1


@kernel
def step(rhs, p, W, fst, ist):
    """One accepted GBS step; False if the step size underflows."""
    t = fst[F_T]
    direction = fst[F_DIR]
    h_abs = fst[F_H]
    k = ist[S_K]
    remaining = abs(fst[F_TEND] - t)
    ist[S_DENSE] = 0
    if ist[S_ADAPTIVE] == 0:  # fixed steps, fixed order, no error control
        last = 1.01 * h_abs >= remaining
        h = direction * (remaining if last else h_abs)
        for col in range(1, k + 1):
            _column(col, rhs, p, t, h, W, fst, ist, False)
        t_new = fst[F_TEND] if last else t + h
        rhs(t_new, W[R_YNEW], W[R_FNEW], p)
        ist[S_NFEV] += 1
        _accept(t, t_new, k, W, fst, ist)
        return True
    min_step = 10.0 * abs(np.nextafter(t, direction * np.inf) - t)
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
        full = ist[S_FIXED] != 0 or (restart and (ist[S_NACC] == 0 or last))
        h = direction * h_abs
        accepted, kc, diverged = _attempt(rhs, p, t, h, k, full, reject, W, fst, ist)
        if diverged:
            ist[S_NREJ] += 1
            h_abs *= _SAFE3
            reject = True
            restart = True
            continue
        if not accepted:
            ist[S_NREJ] += 1
            k = _order_after_rejection(k, kc, fst, ist)
            h_abs = fst[F_HH + k]
            reject = True
            restart = False
            continue
        t_new = fst[F_TEND] if last else t + h
        rhs(t_new, W[R_YNEW], W[R_FNEW], p)
        ist[S_NFEV] += 1
        if ist[S_DENSECONTROL] != 0:
            errint, mu = _coefficients(W, ist, R_Y, R_YNEW, R_F, R_FNEW, t_new - t, kc)
            fst[F_HDENSE] = h_abs / max(errint ** (1.0 / (mu + 4)), 0.01)
            if errint > _DENSE_REJECT:
                ist[S_NREJ] += 1
                ist[S_DENSE] = 0
                h_abs = fst[F_HDENSE]
                reject = True
                restart = True
                continue
        ist[S_FAIL] = 0
        k, h_next = _next_order_and_step(kc, k, h_abs, reject, fst, ist)
        fst[F_H] = h_next
        ist[S_K] = k
        _accept(t, t_new, kc, W, fst, ist)
        return True


@kernel
def dense(rhs, p, W, fst, ist, t, out):
    """The dense output of the last step at ``t`` (a polynomial in ``u = 2 (t - t_old) / H - 1``), into ``out``."""
    if ist[S_DENSE] == 0:
        _coefficients(W, ist, R_YOLD, R_Y, R_FOLD, R_F, fst[F_HSTEP], ist[S_KC])
    n = W.shape[1]
    u = 2.0 * (t - fst[F_TOLD]) / fst[F_HSTEP] - 1.0
    top = ist[S_MU] + 4
    for m in range(n):
        out[m] = W[R_COEF + top, m]
    for r in range(top - 1, -1, -1):
        for m in range(n):
            out[m] = out[m] * u + W[R_COEF + r, m]


# --- the SciPy face ---------------------------------------------------------------------------------
def _validate_tol(rtol, atol, n):
    """Check ``rtol`` and ``atol`` as SciPy does, raising ``ValueError`` on bad input.

    ``rtol`` below ``100 * eps`` is raised to it with a warning (as SciPy); negative or
    non-finite values and wrong shapes are errors.
    """
    checked = []
    for name, tol in (("rtol", rtol), ("atol", atol)):
        tol = np.asarray(tol, dtype=float)
        if tol.ndim > 0 and tol.shape != (n,):
            raise ValueError(f"`{name}` must be a scalar or have shape ({n},), got shape {tol.shape}.")
        if not np.all(np.isfinite(tol)) or np.any(tol < 0):
            raise ValueError(f"`{name}` must be finite and non-negative, got {tol!r}.")
        checked.append(tol)
    rtol, atol = checked
    if np.any(rtol < 100 * EPS):
        warnings.warn(f"At least one element of `rtol` is too small. Setting `rtol = "
                      f"np.maximum(rtol, {100 * EPS})`.", stacklevel=3)
        rtol = np.maximum(rtol, 100 * EPS)
    return rtol, atol


def _validate_order(value, name, low, high):
    if isinstance(value, bool) or int(value) != value or not low <= value <= high:
        raise ValueError(f"`{name}` must be an integer in [{low}, {high}], got {value!r}.")
    return int(value)


class GBSDenseOutput(DenseOutput):
    """Polynomial interpolant over one GBS step: coefficients in powers of ``u = 2 (t - t_old) / H - 1``."""

    def __init__(self, t_old, t, coeffs):
        super().__init__(t_old, t)
        self.h = t - t_old
        self.coeffs = coeffs

    def _call_impl(self, t):
        u = 2.0 * (np.asarray(t) - self.t_old) / self.h - 1.0
        y = np.multiply.outer(np.ones_like(u), self.coeffs[-1]).T if u.ndim else self.coeffs[-1].copy()
        for c in self.coeffs[-2::-1]:
            y = y * u + (c[:, None] if u.ndim else c)
        return y


class BulirschStoer(OdeSolver):
    """GBS extrapolation method with order and step-size control and dense output.

    See the module docstring for the method and references. Use it like the SciPy solvers, e.g.
    ``solve_ivp(fun, t_span, y0, method=BulirschStoer, rtol=1e-10, atol=1e-12, dense_output=True,
    events=...)``; integration in either time direction is supported. It runs the kernels that
    lubelink's compiled driver runs, as Python.

    At high order the steps are long (a few per oscillation period). Event detection by sign
    changes at step ends (``solve_ivp``'s way) then misses an event function that crosses zero
    twice within one step; bound ``max_step`` where that matters.

    Parameters
    ----------
    fun : callable
        Right-hand side ``fun(t, y) -> array_like, shape (n,)``.
    t0 : float
        Initial time.
    y0 : array_like, shape (n,)
        Initial state (real or complex).
    t_bound : float
        Boundary time; the integration does not go beyond it.
    rtol, atol : float or array_like, shape (n,), optional
        Tolerances: a step is accepted when the RMS norm of
        ``error / (atol + rtol * max(|y_old|, |y_new|))`` is at most 1.
    max_step : float, optional
        Largest allowed step size.
    first_step : float, optional
        Initial step size (the fixed step size if ``adaptive=False``). Chosen automatically if
        omitted.
    vectorized : bool, optional
        Whether ``fun`` is vectorized (only passed to the base class).
    max_order : int, optional
        Maximal number of extrapolation columns ``k`` (method order ``2k``), from 3 to 12.
        Default 9 (as ODEX).
    fixed_order : int, optional
        Use exactly ``k = fixed_order`` columns in every step (no order control; the step size is
        still controlled if ``adaptive``).
    adaptive : bool, optional
        If False, take fixed steps of size ``first_step`` with ``fixed_order`` columns and no
        error control (for convergence studies). Default True.
    dense_error_control : bool, optional
        Reject steps whose dense-output error estimate is too large (ODEX does this). Default True.
    **extraneous
        Ignored, with a warning.

    Attributes
    ----------
    order : int
        Number of extrapolation columns ``k`` used in the last accepted step (before the first
        step: the initial choice). The method order is ``2 * order``.
    max_order : int
        Maximal number of columns.
    h_abs : float
        Size of the next step to try.
    nfev, njev, nlu : int
        Function evaluations (counted by the base class); ``njev = nlu = 0``.
    n_accepted, n_rejected : int
        Accepted steps, and rejected step attempts.
    y_old : ndarray or None
        State at the start of the last step.
    """

    def __init__(self, fun, t0, y0, t_bound, rtol=1e-3, atol=1e-6, max_step=np.inf, first_step=None,
                 vectorized=False, max_order=DEFAULT_MAX_ORDER, fixed_order=None, adaptive=True,
                 dense_error_control=True, **extraneous):
        if extraneous:
            warnings.warn("The following arguments have no effect for BulirschStoer: "
                          + ", ".join(f"`{x}`" for x in extraneous) + ".", stacklevel=2)
        super().__init__(fun, t0, y0, t_bound, vectorized, support_complex=True)
        self.rtol, self.atol = _validate_tol(rtol, atol, self.n)
        if not max_step > 0:
            raise ValueError(f"`max_step` must be positive, got {max_step!r}.")
        self.max_step = max_step
        self.max_order = _validate_order(max_order, "max_order", 3, KMAX)
        self.adaptive = bool(adaptive)
        low = 2 if self.adaptive else 1
        self.fixed_order = None if fixed_order is None else _validate_order(fixed_order, "fixed_order", low,
                                                                           self.max_order)
        if not self.adaptive and (first_step is None or self.fixed_order is None):
            raise ValueError("`adaptive=False` needs `first_step` and `fixed_order`.")
        interval = abs(t_bound - t0)
        if first_step is not None and not 0 < first_step <= interval:
            raise ValueError(f"`first_step` must be in (0, |t_bound - t0|] = (0, {interval}], got {first_step!r}.")
        self.y_old = None
        self._W = np.zeros((rows(self.n), self.n), dtype=self.y.dtype)
        self._W[R_Y] = self.y
        self._W[R_ATOL] = np.broadcast_to(self.atol, (self.n,))
        self._W[R_RTOL] = np.broadcast_to(self.rtol, (self.n,))
        self._fst = np.zeros(FLOATS)
        self._fst[F_T], self._fst[F_TEND], self._fst[F_DIR] = t0, t_bound, self.direction
        self._fst[F_MAXSTEP] = max_step
        self._ist = np.zeros(INTS, dtype=np.int64)
        setup(self._W, self._fst, self._ist, {"max_order": self.max_order, "fixed_order": self.fixed_order,
                                              "adaptive": self.adaptive, "first_step": first_step,
                                              "dense_error_control": dense_error_control})
        self.dense_error_control = bool(self._ist[S_DENSECONTROL])

        def rhs(t, y, out, p):
            out[:] = self.fun(t, y)

        self._rhs = rhs
        init.py_func(rhs, None, self._W, self._fst, self._ist)
        self.f = self._W[R_F].copy()
        self.order = int(self._ist[S_K])

    @property
    def h_abs(self):
        return float(self._fst[F_H])

    @property
    def n_accepted(self):
        return int(self._ist[S_NACC])

    @property
    def n_rejected(self):
        return int(self._ist[S_NREJ])

    def _step_impl(self):
        if not step.py_func(self._rhs, None, self._W, self._fst, self._ist):
            return False, TOO_SMALL_STEP
        self.y_old = self._W[R_YOLD].copy()
        self.t = float(self._fst[F_T])
        self.y = self._W[R_Y].copy()
        self.f = self._W[R_F].copy()
        self.order = int(self._ist[S_KC])
        return True, None

    def _dense_output_impl(self):
        if self._ist[S_DENSE] == 0:
            _coefficients(self._W, self._ist, R_YOLD, R_Y, R_FOLD, R_F, self._fst[F_HSTEP], self._ist[S_KC])
        coeffs = self._W[R_COEF:R_COEF + self._ist[S_MU] + 5].copy()
        return GBSDenseOutput(float(self._fst[F_TOLD]), self.t, coeffs)

"""The Gragg-Bulirsch-Stoer method as kernels on the shared integration state.

:func:`init`, :func:`step` and :func:`dense` are what the compiled driver runs (and, as Python,
what :class:`~lubelink.integrate.bulirsch_stoer.BulirschStoer` runs); see the package docstring
for the method.
"""

from __future__ import annotations

import math

import numpy as np

from lubelink._jit import jitable, kernel

from lubelink.integrate._layout import (F_DIR, F_H, F_HSTEP, F_MAXSTEP, F_T, F_TEND, F_TOLD, FAIL_RHS, R_ATOL, R_F, R_FOLD, R_RTOL,
                       R_Y, R_YOLD, S_DENSE, S_FAIL, S_NFEV, S_NREJ)
from lubelink.integrate.control import EPS, initial_step, min_step
from .tables import (_DENSE_REJECT, _DIFF, _ESHAPE, _FAC1, _FAC2, _FAC3, _FAC4, _HERMITE, _MU_DIFF, _NSEQ, _SAFE1,
                     _SAFE2, _SAFE3, _SEQ_OFF, _STAB_COLUMNS, _TAYLOR, _WEIGHTS, _WORK, F_ERROLD, F_HDENSE, F_HH, F_WW,
                     R_COEF, R_FNEW, R_STAB, R_STORE, R_T1, R_TMP, R_YA, R_YB, R_YMID, R_YNEW, S_ADAPTIVE, S_DENSECONTROL,
                     S_FIXED, S_K, S_KC, S_MAXORDER, S_MU, S_NACC)

__all__ = ["init", "step", "dense"]


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
            # ODEX's test, which misfires where f is near zero (a state at rest, as a sustained contact
            # releases it): then any change is large against f; it only counts if the change moves
            # the first substep by more than the tolerance
            if (change / n > 4.0 * max(base / n, EPS) and hj * hj * change / n > 1.0) or not np.isfinite(change):
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
    smallest = min_step(t, direction)
    reject = False
    restart = True
    while True:
        if restart:
            h_abs = min(h_abs, fst[F_MAXSTEP], fst[F_HDENSE])
        last = 1.01 * h_abs >= remaining
        if last:
            h_abs = remaining
        if h_abs < smallest:
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

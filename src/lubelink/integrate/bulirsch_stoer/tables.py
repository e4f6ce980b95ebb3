"""Constants, tables and the integration-state layout of the Gragg-Bulirsch-Stoer method.

The step-number sequence, the extrapolation weights, the difference operators and Hermite
end-condition inverses of the dense output (Hairer-Norsett-Wanner II.9), built once for up to
:data:`KMAX` columns as arrays that compiled code freezes; and the rows and slots the method uses
in the shared integration state (:mod:`lubelink.integrate._layout`).
"""

from __future__ import annotations

import math

import numpy as np

from lubelink.integrate._layout import F_H, F_METHOD, R_METHOD, S_METHOD

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


"""RODAS4: a stiffly accurate, L-stable Rosenbrock method of order 4(3) with dense output of order 3.

Hairer & Wanner, *Solving ODEs II*, 2nd ed., Section IV.7 (the code ``RODAS``, its method 1): six
stages a step, each a solve with the one matrix ``E = I / (h gamma) - J``, ``J = df/dy`` at the
start of the step; the sixth stage's increment is the error estimate (the embedded solution is
the fifth). For ``y' = f(t, y)`` that depends on ``t``, ``df/dt`` enters every stage.

Why a Rosenbrock method: a stiff problem (here: a lubricant film of micrometres, whose squeeze
damping and stiffness couple all modes) holds an explicit or exponential method to steps of the
film's time constant; an implicit method is needed, and a Rosenbrock method is the implicit
method without Newton iterations, so its cost a step is known (one Jacobian, one LU, six
evaluations) and it runs as straight-line compiled code with no iteration to fail. RODAS4 is the
standard one of its order for mechanical problems with discontinuities (L-stable, stiffly accurate,
with a dense output that the driver's event location uses). Measured against the other methods and
SciPy's Radau: benchmarks/work_precision.py, docs/model.md section 7.

The Jacobian comes from the problem where it has one (``setup`` option ``jacobian``): then
``rhs(t, y, out, p)`` with an ``out`` of ``n + n^2`` entries writes ``f`` and ``J`` row by row.
Otherwise it is formed by forward differences of ``rhs`` (one evaluation a column, as RODAS
does), which also limits the accuracy at tight tolerances (an error of ``sqrt(eps)`` relative in
``J`` enters the step). ``df/dt`` is always a forward difference (one evaluation). The LU factorisation with
partial pivoting is written here because no LAPACK routine can be called from Numba code that is
cached on disk (``numpy.linalg.solve`` factors the matrix again at every solve; a step solves six
times with one matrix).
"""

import math

import numpy as np

from lubelink._jit import jitable, kernel
from ._layout import (F_DIR, F_H, F_HSTEP, F_MAXSTEP, F_T, F_TOLD, FAIL_RHS, R_ATOL, R_F, R_METHOD, R_RTOL, R_Y,
                      R_YOLD, S_DENSE, S_FAIL, S_METHOD, S_NFEV, S_NREJ)
from .control import EPS, MIN_FACTOR, accept_step, initial_step, min_step, step_end, step_factor

__all__ = ["init", "step", "dense", "rows", "setup", "lu_factor", "lu_solve", "ORDER", "INTS"]

#: Order of the error estimate's method (the step is of order four).
ORDER = 3
GAMMA = 0.25
#: Hairer's RODAS4 coefficients (``RODAS`` method 1, in its transformed form): stage times ``C``,
#: the ``df/dt`` weights ``D``, the state weights ``A`` and the stage couplings ``CC`` (divided by h).
C = np.array([0.0, 0.386, 0.21, 0.63, 1.0, 1.0])
D = np.array([0.25, -0.1043, 0.1035, -0.0362, 0.0, 0.0])
A = np.array([
    [0.0, 0.0, 0.0, 0.0, 0.0],
    [1.544, 0.0, 0.0, 0.0, 0.0],
    [0.9466785280815826, 0.2557011698983284, 0.0, 0.0, 0.0],
    [3.314825187068521, 2.896124015972201, 0.9986419139977817, 0.0, 0.0],
    [1.221224509226641, 6.019134481288629, 12.53708332932087, -0.687886036105895, 0.0],
    [1.221224509226641, 6.019134481288629, 12.53708332932087, -0.687886036105895, 1.0],
])
CC = np.array([
    [0.0, 0.0, 0.0, 0.0, 0.0],
    [-5.6688, 0.0, 0.0, 0.0, 0.0],
    [-2.430093356833875, -0.2063599157091915, 0.0, 0.0, 0.0],
    [-0.1073529058151375, -9.594562251023355, -20.47028614809616, 0.0, 0.0],
    [7.496443313967647, -10.24680431464352, -33.99990352819905, 11.7089089320616, 0.0],
    [8.083246795921522, -7.981132988064893, -31.52159432874371, 16.31930543123136, -6.058818238834054],
])
#: The dense output's two rows: ``y(s) = (1 - s) y_0 + s (y_1 + (1 - s) (H_0 + s H_1))``, ``H_r = sum_i DH[r, i] k_i``.
DH = np.array([
    [10.12623508344586, -7.487995877610167, -34.80091861555747, -7.992771707568823, 1.025137723295662],
    [-0.6762803392801253, 6.087714651680015, 16.43084320892478, 24.76722511418386, -6.594389125716872],
])

R_K = R_METHOD  # the six stages
R_YNEW = R_K + 6
R_TMP = R_YNEW + 1
R_FX = R_TMP + 1  # df/dt at the start of the step
R_H0 = R_FX + 1  # the dense output's two rows
R_H1 = R_H0 + 1
R_PIV = R_H1 + 1  # the pivots of the LU factorisation (as floats)
R_FJ = R_PIV + 1  # f with the analytic Jacobian: this row and the n of J are the problem's out
R_JAC = R_FJ + 1  # J: n rows
S_JAC = S_METHOD  # 1: the problem gives its Jacobian
S_SECOND = S_METHOD + 1  # 1: the Jacobian of this step has the second-order form (see _second_order)
INTS = S_METHOD + 2


def rows(n):
    """Rows of ``W`` this method uses: the stages and work rows, ``J`` and its LU factors (``n`` rows each)."""
    return R_JAC + 2 * n


@jitable
def lu_factor(M, piv):
    """LU factorisation of the square matrix ``M`` in place, with partial pivoting; False if singular.

    ``piv[k]``: the row swapped with row ``k`` at step ``k`` (as a float).
    """
    n = M.shape[0]
    for k in range(n):
        r = k
        big = abs(M[k, k])
        for i in range(k + 1, n):
            if abs(M[i, k]) > big:
                big = abs(M[i, k])
                r = i
        piv[k] = r
        if big == 0.0:
            return False
        if r != k:
            for j in range(n):
                M[k, j], M[r, j] = M[r, j], M[k, j]
        inv = 1.0 / M[k, k]
        for i in range(k + 1, n):
            M[i, k] *= inv
            m = M[i, k]
            if m != 0.0:
                for j in range(k + 1, n):
                    M[i, j] -= m * M[k, j]
    return True


@jitable
def lu_solve(M, piv, b):
    """Solve ``M x = b`` in place in ``b`` with the factors of :func:`lu_factor`."""
    n = M.shape[0]
    for k in range(n):
        r = int(piv[k])
        if r != k:
            b[k], b[r] = b[r], b[k]
    for i in range(n):
        acc = b[i]
        for j in range(i):
            acc -= M[i, j] * b[j]
        b[i] = acc
    for i in range(n - 1, -1, -1):
        acc = b[i]
        for j in range(i + 1, n):
            acc -= M[i, j] * b[j]
        b[i] = acc / M[i, i]


def setup(W, fst, ist, options):
    """``options["jacobian"]``: whether the problem gives its Jacobian (see the module docstring)."""
    ist[S_JAC] = 1 if options.get("jacobian") else 0


@jitable
def _jacobian(rhs, p, W, ist, t, y, f):
    """``J = df/dy`` into ``W[R_JAC:]``, from the problem or by forward differences (column ``j``:
    ``y_j`` moved by ``sqrt(eps max(1e-5, |y_j|))``, RODAS's increment), and ``df/dt`` into ``W[R_FX]``."""
    n = W.shape[1]
    if ist[S_JAC] != 0:
        rhs(t, y, W[R_FJ:R_JAC + n].reshape(n * (n + 1)), p)
        ist[S_NFEV] += 1
        for m in range(n):
            f[m] = W[R_FJ, m]
        _time_derivative(rhs, p, W, ist, t, y, f)
        return
    J = W[R_JAC:R_JAC + n]
    tmp = W[R_TMP]
    col = W[R_YNEW]
    for m in range(n):
        tmp[m] = y[m]
    for j in range(n):
        delta = math.sqrt(EPS * max(1e-5, abs(y[j])))
        tmp[j] = y[j] + delta
        rhs(t, tmp, col, p)
        tmp[j] = y[j]
        for i in range(n):
            J[i, j] = (col[i] - f[i]) / delta
    ist[S_NFEV] += n
    _time_derivative(rhs, p, W, ist, t, y, f)


@jitable
def _second_order(J):
    """Whether ``J = [[0, I], [A, B]]`` exactly (blocks of ``n/2``): the problem is ``y = [q, q']``, ``q' = y[n/2:]``.

    Then ``E = I/(h gamma) - J`` is solved through ``n/2`` unknowns: with ``c = 1/(h gamma)``,
    ``(c^2 I - c B - A) k_1 = r_2 + (c I - B) r_1`` and ``k_2 = c k_1 - r_1``, an LU factorisation of
    an eighth of the work. Only an exact Jacobian (from the problem) has those zeros and ones.
    """
    n = J.shape[0]
    if n % 2 != 0:
        return False
    N = n // 2
    for i in range(N):
        for j in range(n):
            if J[i, j] != (1.0 if j == N + i else 0.0):
                return False
    return True


@jitable
def _factor(W, ist, J, LU, c):
    """Factor ``E = c I - J`` into ``LU`` (its ``n/2`` block in the second-order form); False if singular."""
    n = J.shape[0]
    if ist[S_SECOND] != 0:
        N = n // 2
        for i in range(N):
            for j in range(N):
                LU[i, j] = -c * J[N + i, N + j] - J[N + i, j]
            LU[i, i] += c * c
        return lu_factor(LU[:N, :N], W[R_PIV])
    for i in range(n):
        for j in range(n):
            LU[i, j] = -J[i, j]
        LU[i, i] += c
    return lu_factor(LU, W[R_PIV])


@jitable
def _solve(W, ist, J, LU, c, r):
    """Solve ``E k = r`` in place in ``r`` with the factors of :func:`_factor`."""
    n = J.shape[0]
    if ist[S_SECOND] == 0:
        lu_solve(LU, W[R_PIV], r)
        return
    N = n // 2
    b = W[R_TMP]
    for i in range(N):
        acc = r[N + i] + c * r[i]
        for j in range(N):
            acc -= J[N + i, N + j] * r[j]
        b[i] = acc
    lu_solve(LU[:N, :N], W[R_PIV], b[:N])
    for i in range(N):
        r[N + i] = c * b[i] - r[i]
        r[i] = b[i]


@jitable
def _time_derivative(rhs, p, W, ist, t, y, f):
    """``df/dt`` into ``W[R_FX]`` by a forward difference."""
    n = W.shape[1]
    delta = math.sqrt(EPS * max(1e-5, abs(t)))
    rhs(t + delta, y, W[R_FX], p)
    ist[S_NFEV] += 1
    for m in range(n):
        W[R_FX, m] = (W[R_FX, m] - f[m]) / delta


@jitable
def _stage(s, rhs, p, W, ist, t, h, y, J, LU):
    """Stage ``s``: ``E k_s = f(t + c_s h, y + sum_j a_sj k_j) + h d_s df/dt + sum_j cc_sj / h k_j``."""
    n = W.shape[1]
    ks = W[R_K + s]
    tmp = W[R_TMP]
    if s == 0:
        for m in range(n):
            ks[m] = W[R_F, m] + h * D[0] * W[R_FX, m]
    else:
        for m in range(n):
            acc = y[m]
            for j in range(s):
                acc += A[s, j] * W[R_K + j, m]
            tmp[m] = acc
        if s == 5:  # the embedded solution (the stiffly accurate fifth stage plus its increment)
            for m in range(n):
                W[R_YNEW, m] = tmp[m]
        rhs(t + C[s] * h, tmp, ks, p)
        ist[S_NFEV] += 1
        for m in range(n):
            acc = ks[m] + h * D[s] * W[R_FX, m]
            for j in range(s):
                acc += CC[s, j] / h * W[R_K + j, m]
            ks[m] = acc
    _solve(W, ist, J, LU, 1.0 / (h * GAMMA), ks)


@kernel
def init(rhs, p, W, fst, ist):
    """``f(t0, y0)`` and the starting step."""
    rhs(fst[F_T], W[R_Y], W[R_F], p)
    ist[S_NFEV] += 1
    fst[F_H] = initial_step(rhs, p, W, fst, ist, ORDER, W[R_TMP], W[R_YNEW])


@kernel
def step(rhs, p, W, fst, ist):
    """One accepted step; False if the step size underflows."""
    n = W.shape[1]
    t = fst[F_T]
    direction = fst[F_DIR]
    y = W[R_Y]
    f = W[R_F]
    J = W[R_JAC:R_JAC + n]
    LU = W[R_JAC + n:R_JAC + 2 * n]
    smallest = min_step(t, direction)
    h_abs = min(fst[F_H], fst[F_MAXSTEP])
    if h_abs < smallest:
        h_abs = smallest
    _jacobian(rhs, p, W, ist, t, y, f)
    ist[S_SECOND] = 1 if ist[S_JAC] != 0 and _second_order(J) else 0
    rejected = False
    while True:
        if h_abs < smallest:
            return False
        t_new = step_end(fst, t, h_abs)
        h = t_new - t
        h_abs = abs(h)
        if not _factor(W, ist, J, LU, 1.0 / (h * GAMMA)):
            h_abs *= 0.5
            rejected = True
            ist[S_NREJ] += 1
            continue
        for s in range(6):
            _stage(s, rhs, p, W, ist, t, h, y, J, LU)
        acc = 0.0
        for m in range(n):
            y_new = W[R_YNEW, m] + W[R_K + 5, m]
            W[R_YNEW, m] = y_new
            sc = W[R_ATOL, m] + W[R_RTOL, m] * max(abs(y[m]), abs(y_new))
            d = W[R_K + 5, m] / sc
            acc += d * d
        error_norm = math.sqrt(acc / n)
        if not np.isfinite(error_norm):  # NaN or infinity in the stages: shrink, and say so if it underflows
            ist[S_FAIL] = FAIL_RHS
            h_abs *= MIN_FACTOR
            rejected = True
            ist[S_NREJ] += 1
            continue
        if error_norm < 1.0:
            ist[S_FAIL] = 0
            h_abs *= step_factor(error_norm, ORDER, rejected)
            break
        h_abs *= step_factor(error_norm, ORDER, True)
        rejected = True
        ist[S_NREJ] += 1
    for m in range(n):
        h0 = 0.0
        h1 = 0.0
        for j in range(5):
            h0 += DH[0, j] * W[R_K + j, m]
            h1 += DH[1, j] * W[R_K + j, m]
        W[R_H0, m] = h0
        W[R_H1, m] = h1
        W[R_YOLD, m] = y[m]
        y[m] = W[R_YNEW, m]
    if ist[S_JAC] == 0:  # the next step's first stage (with the problem's Jacobian, it comes with J)
        rhs(t_new, y, f, p)
        ist[S_NFEV] += 1
    accept_step(fst, t, t_new, h_abs)
    ist[S_DENSE] = 1
    return True


@kernel
def dense(rhs, p, W, fst, ist, t, out):
    """The dense output of the last step at ``t``, into ``out`` (order three)."""
    n = W.shape[1]
    s = (t - fst[F_TOLD]) / fst[F_HSTEP]
    for m in range(n):
        out[m] = (1.0 - s) * W[R_YOLD, m] + s * (W[R_Y, m] + (1.0 - s) * (W[R_H0, m] + s * W[R_H1, m]))

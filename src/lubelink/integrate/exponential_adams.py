"""Exponential Adams predictor-corrector for damped oscillators with a nonlinear load.

The problems of :mod:`.exponential`, ``y' = A y + G(t, y)`` with ``A`` block diagonal, by the
exponential Adams methods of Hochbruck & Ostermann (*Exponential integrators*, Acta Numerica 19
(2010) 209-286, Section 2.5): the load is replaced by the quintic ``G(t_n + sigma h) ~ sum_k Q_k
sigma^k`` through its values at six points, and the variation-of-constants formula integrated
exactly with it::

    y_(n+1) = phi_0(hA) y_n + h sum_k k! phi_(k+1)(hA) Q_k

(:func:`_shared`). The step is a PECE pair of order six on variable steps:

* predict with the quintic through the loads at ``t_n`` and the five steps before (extrapolated);
* evaluate the load there, correct with the quintic through ``t_(n+1)``, ``t_n`` and four steps before;
* the difference of the two is the error estimate (Milne's device: for constant steps the
  corrector's error is ``863/19950`` of it, :data:`MILNE`), evaluate the load at the corrected
  state: two evaluations a step against the Runge-Kutta method's seven.

Order six, not four: on the dry link (``paper-dry``, 1-15 modes, crank speed to 80 rad/s) it takes
half the steps of the order-four pair of version 0.1 at the same tolerances, with half its error;
its step costs more (the tables ``phi_0 .. phi_6``, fits of six loads), so a run takes 0.73-0.85x
the time (benchmarks/README.md). The corrector's quintic is the load over the step, so the dense
output is that of the Runge-Kutta method (:mod:`.exponential_dense`) with a quintic load. A
segment starts with five steps of the Runge-Kutta method (:func:`.exponential.rk_step`), which
leave the loads the first Adams step needs; so does every segment after an event. The multistep
method pays for its cheap steps with a smaller stability region: where the load depends strongly
on the state (a lubricant film, the spatial link's coupling) its steps are held short, and its
error at loose tolerances is less reliable than the Runge-Kutta method's (docs/model.md section 7.1).
"""

import numpy as np

from lubelink._jit import jitable, kernel
from ._layout import F_DIR, F_H, F_HSTEP, F_MAXSTEP, F_T, F_TOLD, FAIL_RHS, R_Y, S_FAIL, S_NFEV, S_NREJ
from . import exponential as E
from .control import MIN_FACTOR, min_step, scaled_rms, step_end, step_factor

__all__ = ["init", "step", "rows", "setup", "FLOATS"]

#: Order of the pair, and the number of loads its polynomials go through.
ORDER = 6
DEGREE = ORDER - 1
#: Corrector error over (corrector - predictor) for constant steps: ``C_c / (C_c - C_p)`` with the
#: error constants of the Adams-Moulton corrector and the Adams-Bashforth predictor of order six,
#: ``-863/60480`` and ``19087/60480`` (order four: ``-19/720``, ``251/720``, giving ``19/270``).
MILNE = 863.0 / 19950.0
#: Largest growth of the step from one step to the next: the variable-step coefficients stay
#: near the constant-step ones, whose stability the pair has.
MAX_GROWTH = 2.0

R_HIST = E.ROWS_END  # the loads at t_(n-1) .. t_(n-DEGREE): DEGREE rows
R_ATABLE = R_HIST + DEGREE  # phi_0 .. phi_ORDER of h A for the Adams step: ORDER + 1 rows
R_YPRED = R_ATABLE + ORDER + 1
R_GPREV = R_YPRED + 1  # the load at the start of a Runge-Kutta starting step
R_SP = R_GPREV + 1  # the shared polynomial S at the predictor's last node
R_SC = R_SP + 1  # ... and at sigma = 1, the corrector's
R_AP = R_SC + 1  # the leading coefficient of the predictor's polynomial
R_AC = R_AP + 1  # ... and of the corrector's
R_MPI = R_AC + 1  # h sum_k k! c_k phi_(k+1)(h A) of the node polynomial pi = sum_k c_k sigma^k, as a table row
ROWS_END = R_MPI + 1
F_THIST = E.FLOATS  # t_(n-1) .. t_(n-DEGREE)
F_NHIST = F_THIST + DEGREE  # loads in the history (DEGREE: the Adams steps run)
F_AHOLD = F_NHIST + 1  # the step R_ATABLE was made for
F_NODES = F_AHOLD + 1  # the nodes of the fit in sigma: 0, then the DEGREE steps before
F_PI = F_NODES + DEGREE + 1  # the monomial coefficients of pi: DEGREE + 1 slots
FLOATS = F_PI + DEGREE + 1

setup = E.setup


def rows(n):
    """Rows of ``W`` this method uses."""
    return ROWS_END


@kernel
def init(rhs, p, W, fst, ist):
    """The Runge-Kutta method's start (``G`` at ``t0``, the starting step), an empty history."""
    E.rk_init(rhs, p, W, fst, ist)
    fst[F_NHIST] = 0.0
    fst[F_AHOLD] = np.nan


@jitable
def _shared(W, fst, h):
    """The polynomial the predictor and the corrector share, and what each adds to it.

    The predictor's quintic goes through the loads at the nodes ``x_0 = 0, x_1 .. x_5`` (``t_n``
    and the five steps before, in ``sigma``), the corrector's through ``x_0 .. x_4`` and
    ``sigma = 1``. Both are ``S + a pi`` with ``S`` the quartic through ``x_0 .. x_4`` and
    ``pi(sigma) = prod_(k<5) (sigma - x_k)``, so ``a = (G(x) - S(x)) / pi(x)`` at the extra node
    ``x`` (Newton's form, appended last), and the variation-of-constants formula is linear in
    the load: ``y = Y_S + M_pi a`` with ``Y_S = phi_0 y_n + h sum_k k! phi_(k+1) S_k`` and the
    block matrices ``M_pi = h sum_k k! pi_k phi_(k+1)``. One fit and one sum over the tables a
    step instead of two of each (0.3 us a fit of six loads). This sets ``R_Q`` to ``S``'s monomial
    coefficients, ``R_SC`` to ``S(1)``, ``R_AP`` to the predictor's ``a``, ``R_MPI``, ``F_PI``, and
    ``R_U`` to ``Y_S``.
    """
    n = W.shape[1]
    D = DEGREE
    Q = E.R_Q
    for m in range(n):  # Newton's divided differences of the loads at x_0 .. x_(D-1), in place
        W[Q, m] = W[E.R_G, m]
    for i in range(1, D):
        for m in range(n):
            W[Q + i, m] = W[R_HIST + i - 1, m]
    for order in range(1, D):
        for i in range(D - 1, order - 1, -1):
            c = 1.0 / (fst[F_NODES + i] - fst[F_NODES + i - order])
            for m in range(n):
                W[Q + i, m] = (W[Q + i, m] - W[Q + i - 1, m]) * c
    xp = fst[F_NODES + D]
    for m in range(n):  # S at the predictor's last node and at 1 (Horner in Newton's form)
        W[R_SP, m] = W[Q + D - 1, m]
        W[R_SC, m] = W[Q + D - 1, m]
    for k in range(D - 2, -1, -1):
        x = fst[F_NODES + k]
        for m in range(n):
            W[R_SP, m] = W[R_SP, m] * (xp - x) + W[Q + k, m]
            W[R_SC, m] = W[R_SC, m] * (1.0 - x) + W[Q + k, m]
    for k in range(D - 2, -1, -1):  # Newton's form to monomials: P_k = a_k + (s - x_k) P_(k+1)
        x = fst[F_NODES + k]
        for i in range(k, D - 1):
            for m in range(n):
                W[Q + i, m] -= x * W[Q + i + 1, m]
    for k in range(D + 1):  # pi's monomial coefficients
        fst[F_PI + k] = 0.0
    fst[F_PI] = 1.0
    for k in range(D):
        x = fst[F_NODES + k]
        for i in range(k + 1, 0, -1):
            fst[F_PI + i] = fst[F_PI + i - 1] - x * fst[F_PI + i]
        fst[F_PI] = -x * fst[F_PI]
    inv = 1.0 / _pi(fst, xp)
    for m in range(n):
        W[R_AP, m] = (W[R_HIST + D - 1, m] - W[R_SP, m]) * inv
    T = R_ATABLE
    E._phi_sum(W, E.R_U, (T, T + 1, T + 2, T + 3, T + 4, T + 5), (R_Y, Q, Q + 1, Q + 2, Q + 3, Q + 4),
               (1.0, h, h, 2.0 * h, 6.0 * h, 24.0 * h))
    N = n // 2
    for i in range(N):
        a = 0.0
        b = 0.0
        factorial = h
        for k in range(D + 1):
            c = factorial * fst[F_PI + k]
            a += c * W[T + k + 1, i]
            b += c * W[T + k + 1, N + i]
            factorial *= k + 1
        W[R_MPI, i] = a
        W[R_MPI, N + i] = b


@jitable
def _pi(fst, x):
    """The node polynomial ``pi(x) = prod_(k < DEGREE) (x - x_k)`` at ``x``, by its factors."""
    value = 1.0
    for k in range(DEGREE):
        value *= x - fst[F_NODES + k]
    return value


@jitable
def _corrector_coefficient(W, fst):
    """``R_AC``: the corrector's ``a = (G(1) - S(1)) / pi(1)``, ``G(1)`` the predicted load in ``R_GNEW``."""
    inv = 1.0 / _pi(fst, 1.0)
    for m in range(W.shape[1]):
        W[R_AC, m] = (W[E.R_GNEW, m] - W[R_SC, m]) * inv


@jitable
def _corrector_polynomial(W, fst):
    """``R_Q``: the monomial coefficients of the corrector's polynomial ``S + a pi`` (the dense output's load)."""
    n = W.shape[1]
    for k in range(DEGREE):
        c = fst[F_PI + k]
        for m in range(n):
            W[E.R_Q + k, m] += c * W[R_AC, m]
    for m in range(n):
        W[E.R_Q + DEGREE, m] = W[R_AC, m]  # (pi is monic)


@jitable
def _plus_m_pi(W, r_base, r_a, scale, r_out):
    """``W[r_out] = W[r_base] + scale M_pi W[r_a]``, block by block (``M_pi`` the table row ``R_MPI``)."""
    N = W.shape[1] // 2
    for i in range(N):
        W[r_out, i] = W[r_base, i]
        W[r_out, N + i] = W[r_base, N + i]
        E._apply_block(W, R_MPI, r_a, r_out, scale, i)


@jitable
def _push(W, fst, row, t):
    """The load in ``row`` at ``t`` becomes the newest of the history."""
    for m in range(W.shape[1]):
        for i in range(DEGREE - 1, 0, -1):
            W[R_HIST + i, m] = W[R_HIST + i - 1, m]
        W[R_HIST, m] = W[row, m]
    for i in range(DEGREE - 1, 0, -1):
        fst[F_THIST + i] = fst[F_THIST + i - 1]
    fst[F_THIST] = t
    fst[F_NHIST] = min(fst[F_NHIST] + 1.0, float(DEGREE))


@kernel
def step(rhs, p, W, fst, ist):
    """One accepted step: the Runge-Kutta method's while the history fills, then the PECE pair."""
    n = W.shape[1]
    if fst[F_NHIST] < DEGREE:
        for m in range(n):
            W[R_GPREV, m] = W[E.R_G, m]
        if not E.rk_step(rhs, p, W, fst, ist):
            return False
        _push(W, fst, R_GPREV, fst[F_TOLD])
        return True
    t = fst[F_T]
    smallest = min_step(t, fst[F_DIR])
    h_abs = min(fst[F_H], fst[F_MAXSTEP], MAX_GROWTH * abs(fst[F_HSTEP]))
    rejected = False
    while True:
        if h_abs < smallest:
            return False
        t_new = step_end(fst, t, h_abs)
        h = t_new - t
        if h != fst[F_AHOLD]:
            E._tables(W, h, 1.0, R_ATABLE, ORDER + 1)
            fst[F_AHOLD] = h
        fst[F_NODES] = 0.0  # t_n and the DEGREE steps before, in sigma
        for i in range(DEGREE):
            fst[F_NODES + 1 + i] = (fst[F_THIST + i] - t) / h
        _shared(W, fst, h)
        _plus_m_pi(W, E.R_U, R_AP, 1.0, R_YPRED)  # predictor
        rhs(t_new, W[R_YPRED], W[E.R_FU], p)
        ist[S_NFEV] += 1
        E._load(W, R_YPRED, E.R_FU, E.R_GNEW)
        _corrector_coefficient(W, fst)
        _plus_m_pi(W, E.R_U, R_AC, 1.0, E.R_YNEW)  # corrector
        for m in range(n):
            W[E.R_ERR, m] = 0.0
            W[R_SP, m] = W[R_AC, m] - W[R_AP, m]
        for i in range(n // 2):  # Milne's estimate: MILNE (y_corrector - y_predictor) = MILNE M_pi (a_c - a_p)
            E._apply_block(W, R_MPI, R_SP, E.R_ERR, MILNE, i)
        err = scaled_rms(W[E.R_ERR], W[R_Y], W[E.R_YNEW], W)
        if not np.isfinite(err):
            ist[S_FAIL] = FAIL_RHS
            err = 1.0 / MIN_FACTOR ** (ORDER + 1)
        factor = step_factor(err, ORDER, rejected)
        if E.KEEP_LOW <= factor <= E.KEEP_HIGH:
            factor = 1.0  # the tables serve the next step too
        h_abs = abs(h) * factor
        if err < 1.0:
            ist[S_FAIL] = 0
            break
        rejected = True
        ist[S_NREJ] += 1
    _corrector_polynomial(W, fst)
    rhs(t_new, W[E.R_YNEW], W[E.R_FU], p)  # the load at the corrected state: the next step's G_n
    ist[S_NFEV] += 1
    E._load(W, E.R_YNEW, E.R_FU, E.R_GNEW)
    _push(W, fst, E.R_G, t)
    fst[E.F_DEGREE] = float(DEGREE)  # the dense output's load: the corrector's polynomial
    E.accept(W, fst, ist, t, t_new, h_abs)
    return True

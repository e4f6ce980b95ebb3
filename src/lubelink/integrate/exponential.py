"""Exponential Runge-Kutta integrator for damped oscillators with a nonlinear load.

Problems of the form, with the state ``y = (x_1..x_N, v_1..v_N)``::

    x_i' = v_i,    v_i' = -omega_i^2 x_i - 2 zeta_i omega_i v_i + g_i(t, y),

i.e. ``y' = A y + G(t, y)`` with ``A`` block diagonal (one 2x2 block per oscillator). The linear
part is integrated exactly, through the functions ``phi_k(z) = sum_j z^j / (j + k)!`` of the
2x2 blocks (closed forms below), and the load ``G = f - A y`` explicitly, so the step is set by how
fast ``G`` varies along the solution, not by the largest ``omega_i``. The right-hand side is the
usual ``f(t, y)``; the method subtracts ``A y`` itself (``omega``, ``zeta`` are given at set-up), so
it knows nothing else of the problem.

Method
------
The five-stage exponential Runge-Kutta method of order four of Hochbruck & Ostermann
(*Explicit exponential Runge-Kutta methods for semilinear parabolic problems*, SIAM J. Numer.
Anal. 43 (2005) 1069-1090; also *Exponential integrators*, Acta Numerica 19 (2010) 209-286,
Section 2.3), with nodes ``c = (0, 1/2, 1/2, 1, 1/2)`` and ``phi_{k,i} = phi_k(c_i h A)``::

    U_i     = exp(c_i h A) y_n + h sum_j a_ij(hA) G_j,        G_j = G(t_n + c_j h, U_j)
    y_{n+1} = exp(h A) y_n + h [(phi_1 - 3 phi_2 + 4 phi_3) G_1 + (4 phi_3 - phi_2) G_4
                                + (4 phi_2 - 8 phi_3) G_5]

(the stage coefficients in :func:`_stages`). Stages 2 and 3 are each accurate to first order
only, but their errors cancel in ``G_2 + G_3``.

Error estimate and dense output. Two estimates, the larger of which controls the step (as in
SciPy, exponent ``-1/4``):

* the stages': Krogstad's third-order weights, ``(2 phi_2 - 4 phi_3)`` on ``G_2`` and on
  ``G_3``, differ from the step's by ``h (2 phi_2 - 4 phi_3)(hA) (2 G_5 - G_2 - G_3)``. It sees
  the error of the internal stages through the load's dependence on the state only: for a load
  that depends on time only (here the rigid-body inertia, the dominant load) it is exactly zero;
* the quadrature's: the load is interpolated by a cubic in time through ``G`` at the start, at
  ``1/4`` and ``1/2`` of the step (on the third-order continuous extension) and at the new state,
  and the variation-of-constants formula integrated exactly with it; its difference to the step
  is ``O(h^5)``, like the step's error. This cubic is also the dense output, of order four
  (:mod:`.exponential_dense`, which evaluates it through the particular solution of each block).

``G_1`` of a step is the load at the end of the previous one, so an accepted step costs seven
evaluations: four stages, the new state, and the two interpolation points.

The phi-functions of the 2x2 blocks are those of :mod:`.phi`.
"""

import numpy as np

from lubelink._jit import jitable, kernel
from ._layout import (F_DIR, F_H, F_MAXSTEP, F_METHOD, F_T, FAIL_RHS, R_F, R_METHOD, R_Y,
                      R_YOLD, S_DENSE, S_FAIL, S_NFEV, S_NREJ)
from .control import MIN_FACTOR, accept_step, initial_step, min_step, scaled_rms, step_end, step_factor
from .phi import phi_block

__all__ = ["init", "step", "rows", "setup"]

ORDER = 4

R_LIN = R_METHOD  # [omega_1..omega_N, zeta_1..zeta_N]
R_G = R_LIN + 1  # G_1 ... G_5 (G_1 also of the last accepted step, for the dense output)
R_U = R_G + 5  # a stage state
R_FU = R_U + 1  # f at a stage
R_YNEW = R_FU + 1
R_ERR = R_YNEW + 1
R_GNEW = R_ERR + 1  # G at the new state of an attempted step
#: Largest degree of the polynomial load of a step (the dense output's): 3 here, 5 in the Adams method.
MAX_DEGREE = 5
R_Q = R_GNEW + 1  # the polynomial G over the last step, in powers of sigma = (t - t_n) / h: MAX_DEGREE + 1 rows
R_HALF = R_Q + MAX_DEGREE + 1  # phi_0..phi_4 of (h/2) A: rows [a_1..a_N, b_1..b_N]
R_ONE = R_HALF + 5  # phi_0..phi_4 of h A
R_THETA = R_ONE + 5  # phi_0..phi_(degree + 1) of theta h A (dense output): MAX_DEGREE + 2 rows
R_QUARTER = R_THETA + MAX_DEGREE + 2  # phi_0..phi_4 of (h/4) A
R_PART = R_QUARTER + 5  # the dense output's polynomial particular solution over the last step (powers of tau)
R_FREE = R_PART + MAX_DEGREE + 1  # its free part at tau = 0, y_n - P(0)
R_TURN = R_FREE + 1  # (A + zeta omega I) R_FREE / omega_d
R_LAST = R_TURN + 1  # exp(lambda tau) of each block at the last sample, [Re_1..Re_N, Im_1..Im_N]
R_ROT = R_LAST + 1  # exp(lambda F_DTAU) of each block, the same layout
#: Terms of the Taylor series in ``tau`` of a step's solution that the dense output sums for a block
#: of small ``h omega`` (:mod:`.exponential_dense`).
TAYLOR_TERMS = 17
R_TAYLOR = R_ROT + 1  # those terms: TAYLOR_TERMS rows
ROWS_END = R_TAYLOR + TAYLOR_TERMS
FLOATS = F_METHOD + 6
F_HOLD = F_METHOD  # the step the R_HALF, R_ONE, R_QUARTER tables were made for
F_PART = F_METHOD + 1  # 1: R_PART, R_FREE, R_TURN hold the last accepted step's; 0: not yet
F_TAU = F_METHOD + 2  # tau of the last sample of this step (R_LAST); NaN: none yet
F_DTAU = F_METHOD + 3  # the spacing of the samples R_ROT was made for (0: none)
F_CHAIN = F_METHOD + 4  # samples since the last one computed directly
F_DEGREE = F_METHOD + 5  # the degree of the load polynomial R_Q (3: this method's cubic)
#: A step accepted with a proposed change of its size by a factor in ``[KEEP_LOW, KEEP_HIGH]`` is
#: kept, and so are its tables of phi-functions (the rule of Hairer & Wanner's RADAU5 for its LU
#: factors; *Solving ODEs II*, IV.8): the tables cost about 40 % of the seven evaluations
#: (1.3 against 3.2 us on ``paper-dry``, 5 modes).
KEEP_LOW, KEEP_HIGH = 1.0, 1.2
def rows(n):
    """Rows of ``W`` this method uses."""
    return ROWS_END


def setup(W, fst, ist, options):
    """The linear part: ``options["omega"]`` [rad/s] and ``options["zeta"]`` [-], one per oscillator."""
    n = W.shape[1]
    omega = np.asarray(options["omega"], dtype=float)
    zeta = np.broadcast_to(np.asarray(options.get("zeta", 0.0), dtype=float), omega.shape)
    if n != 2 * omega.size:
        raise ValueError(f"the exponential method needs a state of 2 N = {2 * omega.size} components, got {n}")
    W[R_LIN, :omega.size] = omega
    W[R_LIN, omega.size:] = zeta


@jitable
def _tables(W, h, c, row, K):
    """Rows ``row .. row + K - 1``: ``phi_k(c h A)`` of every block, as ``[a_1..a_N, b_1..b_N]``."""
    N = W.shape[1] // 2
    for i in range(N):
        _table_block(W, c * h, row, K, i)


@jitable
def _step_tables(W, h):
    """The tables of a step: ``phi_0..phi_4`` of ``(h/4) A`` (:func:`_tables`), then of ``(h/2) A``
    and ``h A`` by doubling (:func:`_double`): one evaluation of the phi-functions per block instead
    of three (the tables cost 3.1 of the 8.5 us of a step on ``paper-dry``, 5 modes, where the step changes)."""
    _tables(W, h, 0.25, R_QUARTER, 5)
    _double(W, R_QUARTER, R_HALF)
    _double(W, R_HALF, R_ONE)


#: ``1 / j!``, j = 0..4.
_INV_FACTORIAL = (1.0, 1.0, 0.5, 1.0 / 6.0, 1.0 / 24.0)


@jitable
def _double(W, src, dst):
    """Rows ``dst ..``: ``phi_k(2 Z)``, k = 0..4, from ``phi_k(Z)`` in rows ``src ..`` (``Z = c h A``).

    ``phi_k(2 Z) = 2^-k [phi_0(Z) phi_k(Z) + sum_(j=1..k) phi_j(Z) / (k - j)!]`` (the doubling of
    scaling and squaring; Skaflestad & Wright, *The scaling and modified squaring method for matrix
    functions related to the exponential*, Appl. Numer. Math. 59 (2009) 783-799). Every table is
    ``a I + b A`` of the block's ``A``, and ``A^2 = -2 zeta omega A - omega^2 I``, so a product is
    ``(a1 a2 - omega^2 b1 b2) I + (a1 b2 + a2 b1 - 2 zeta omega b1 b2) A``.
    """
    N = W.shape[1] // 2
    for i in range(N):
        om = W[R_LIN, i]
        two_zo = 2.0 * W[R_LIN, N + i] * om
        om2 = om * om
        a0 = W[src, i]
        b0 = W[src, N + i]
        scale = 1.0
        for k in range(5):
            ak = W[src + k, i]
            bk = W[src + k, N + i]
            a = a0 * ak - om2 * b0 * bk
            b = a0 * bk + ak * b0 - two_zo * b0 * bk
            for j in range(1, k + 1):
                a += W[src + j, i] * _INV_FACTORIAL[k - j]
                b += W[src + j, N + i] * _INV_FACTORIAL[k - j]
            W[dst + k, i] = a * scale
            W[dst + k, N + i] = b * scale
            scale *= 0.5


@jitable
def _table_block(W, ch, row, K, i):
    """Column ``i`` (and ``N + i``) of :func:`_tables` for the step ``ch``."""
    N = W.shape[1] // 2
    phi_block(W[R_LIN, i], W[R_LIN, N + i], ch, W[row:row + K, i], W[row:row + K, N + i])
    for k in range(K):
        W[row + k, N + i] *= ch  # absorb c h: phi_k = a I + b' A


# The helpers below take rows of ``W``, not views of them: a view costs two atomic reference-count
# updates in compiled code, which cost more than a block's arithmetic (30 products of 5 blocks:
# 1.6 us through views, 0.4 us through rows).


@jitable
def _combine(W, dst, c1, r1, c2, r2, c3, r3):
    """``W[dst] = c1 W[r1] + c2 W[r2] + c3 W[r3]``."""
    for m in range(W.shape[1]):
        W[dst, m] = c1 * W[r1, m] + c2 * W[r2, m] + c3 * W[r3, m]


@jitable
def _phi_sum(W, dst, rows, srcs, scales):
    """``W[dst] = sum_k scales[k] phi_k W[srcs[k]]`` with ``phi_k`` the table in row ``rows[k]`` (tuples).

    Every table is ``a I + b A`` of the block's ``A``, so per block the sum is
    ``sum_k a_k g_k + A sum_k b_k g_k``: one product with ``A`` for all the terms.
    """
    N = W.shape[1] // 2
    for i in range(N):
        rx = 0.0
        rv = 0.0
        sx = 0.0
        sv = 0.0
        for k in range(len(rows)):
            a = scales[k] * W[rows[k], i]
            b = scales[k] * W[rows[k], N + i]
            gx = W[srcs[k], i]
            gv = W[srcs[k], N + i]
            rx += a * gx
            rv += a * gv
            sx += b * gx
            sv += b * gv
        om = W[R_LIN, i]
        W[dst, i] = rx + sv
        W[dst, N + i] = rv - om * om * sx - 2.0 * W[R_LIN, N + i] * om * sv


@jitable
def _apply_block(W, row, src, dst, scale, i):
    """Block ``i`` of :func:`_apply`."""
    N = W.shape[1] // 2
    om = W[R_LIN, i]
    x = W[src, i]
    v = W[src, N + i]
    a = W[row, i]
    b = W[row, N + i]
    W[dst, i] += scale * (a * x + b * v)
    W[dst, N + i] += scale * (a * v + b * (-om * om * x - 2.0 * W[R_LIN, N + i] * om * v))


@jitable
def _load(W, r_y, r_f, r_out):
    """``G = f - A y`` of rows ``r_y``, ``r_f`` into row ``r_out``."""
    N = W.shape[1] // 2
    for i in range(N):
        om = W[R_LIN, i]
        W[r_out, i] = W[r_f, i] - W[r_y, N + i]
        W[r_out, N + i] = W[r_f, N + i] + om * om * W[r_y, i] + 2.0 * W[R_LIN, N + i] * om * W[r_y, N + i]


@jitable
def _stage(rhs, p, W, ist, t, row_g):
    """``G = G(t, U)`` of the stage state ``W[R_U]`` into row ``row_g``."""
    rhs(t, W[R_U], W[R_FU], p)
    ist[S_NFEV] += 1
    _load(W, R_U, R_FU, row_g)


@jitable
def _stages(rhs, p, W, ist, t, h):
    """Stages 2 to 5 of the Hochbruck-Ostermann method, ``y_{n+1}`` into ``R_YNEW``, the error estimate into ``R_ERR``."""
    G1, G2, G3, G4, G5 = R_G, R_G + 1, R_G + 2, R_G + 3, R_G + 4
    H0, H1, H2, H3 = R_HALF, R_HALF + 1, R_HALF + 2, R_HALF + 3
    O0, O1, O2, O3 = R_ONE, R_ONE + 1, R_ONE + 2, R_ONE + 3
    U, E, S = R_U, R_ERR, R_GNEW  # (R_GNEW: scratch until the new state's load)
    # U_2 = phi_0(h/2) y + h/2 phi_1(h/2) G_1
    _phi_sum(W, U, (H0, H1), (R_Y, G1), (1.0, 0.5 * h))
    _stage(rhs, p, W, ist, t + 0.5 * h, G2)
    # U_3 = phi_0(h/2) y + h [(phi_1(h/2)/2 - phi_2(h/2)) G_1 + phi_2(h/2) G_2]
    _combine(W, E, 1.0, G2, -1.0, G1, 0.0, G1)
    _phi_sum(W, U, (H0, H1, H2), (R_Y, G1, E), (1.0, 0.5 * h, h))
    _stage(rhs, p, W, ist, t + 0.5 * h, G3)
    # U_4 = phi_0(h) y + h [(phi_1(h) - 2 phi_2(h)) G_1 + phi_2(h) (G_2 + G_3)]
    _combine(W, E, 1.0, G2, 1.0, G3, -2.0, G1)
    _phi_sum(W, U, (O0, O1, O2), (R_Y, G1, E), (1.0, h, h))
    _stage(rhs, p, W, ist, t + h, G4)
    # U_5 = phi_0(h/2) y + h [phi_1(h/2)/2 G_1 + phi_2(h/2)/4 (G_4 - G_1) + a_52 D],
    # D = G_2 + G_3 - G_1 - G_4, a_52 = phi_2(h/2)/2 - phi_3(h/2)/2 + phi_2(h)/4 - phi_3(h)
    for m in range(W.shape[1]):
        d = W[G2, m] + W[G3, m] - W[G1, m] - W[G4, m]
        W[E, m] = d
        W[S, m] = 0.25 * (W[G4, m] - W[G1, m]) + 0.5 * d  # the phi_2(h/2) terms
    _phi_sum(W, U, (H0, H1, H2, H3, O2, O3), (R_Y, G1, S, E, E, E), (1.0, 0.5 * h, h, -0.5 * h, 0.25 * h, -h))
    _stage(rhs, p, W, ist, t + 0.5 * h, G5)
    # y_new = phi_0(h) y + h [(phi_1 - 3 phi_2 + 4 phi_3) G_1 + (4 phi_3 - phi_2) G_4 + (4 phi_2 - 8 phi_3) G_5]
    _combine(W, E, -3.0, G1, -1.0, G4, 4.0, G5)
    _combine(W, S, 4.0, G1, 4.0, G4, -8.0, G5)
    _phi_sum(W, R_YNEW, (O0, O1, O2, O3), (R_Y, G1, E, S), (1.0, h, h, h))
    # error estimate h (2 phi_2 - 4 phi_3)(h) (2 G_5 - G_2 - G_3), into R_ERR
    _combine(W, U, 2.0, G5, -1.0, G2, -1.0, G3)
    _phi_sum(W, E, (O2, O3), (U, U), (2.0 * h, -4.0 * h))


@jitable
def _extension3(W, h, theta, row_phi, r_y, r_g1, r_g4, r_g5, r_out):
    """Third-order continuous extension of a step at ``theta``, into row ``r_out``.

    ``y(t_n + theta h) = phi_0(theta h A) y_n + h [b_1(theta) G_1 + b_4(theta) G_4 + b_5(theta) G_5]``
    with ``b_5 = 4 theta^2 phi_2 - 8 theta^3 phi_3``, ``b_4 = 4 theta^3 phi_3 - theta^2 phi_2``,
    ``b_1 = theta phi_1 - b_4 - b_5`` (``phi_k = phi_k(theta h A)``): the conditions of order
    three at ``theta``, and the step's weights at ``theta = 1``. Rows ``r_*`` hold ``y_n`` and
    the stage loads; rows ``row_phi ..`` the tables of ``phi_0 .. phi_3`` of ``theta h A``.
    """
    _combine(W, R_U, -3.0, r_g1, -1.0, r_g4, 4.0, r_g5)  # the phi_2 terms: theta^2 (-3 G_1 - G_4 + 4 G_5)
    _combine(W, R_FU, 4.0, r_g1, 4.0, r_g4, -8.0, r_g5)  # the phi_3 terms: theta^3 (4 G_1 + 4 G_4 - 8 G_5)
    _phi_sum(W, r_out, (row_phi, row_phi + 1, row_phi + 2, row_phi + 3), (r_y, r_g1, R_U, R_FU),
             (1.0, theta * h, theta * theta * h, theta**3 * h))


#: Monomial coefficients of the cubic through ``sigma = 1/4, 1/2, 1`` (values minus the one at 0).
_CUBIC = np.linalg.inv(np.array([[s, s * s, s**3] for s in (0.25, 0.5, 1.0)]))


@jitable
def _load_cubic(rhs, p, W, ist, t, h):
    """The cubic ``G(t_n + sigma h) ~ sum_k Q_k sigma^k`` of the attempted step, into ``R_Q``.

    Through ``G`` at ``sigma = 0`` (``G_1``), ``1`` (``G`` of the new state, the next step's
    ``G_1``, left in ``R_GNEW``) and at ``1/4`` and ``1/2`` on the third-order extension: three
    evaluations. Its interpolation error is ``O(h^4)``.
    """
    n = W.shape[1]
    rhs(t + h, W[R_YNEW], W[R_FU], p)
    ist[S_NFEV] += 1
    _load(W, R_YNEW, R_FU, R_GNEW)
    for j in range(2):
        sigma = 0.25 * (j + 1)
        _extension3(W, h, sigma, R_QUARTER if j == 0 else R_HALF, R_Y, R_G, R_G + 3, R_G + 4, R_ERR)
        rhs(t + sigma * h, W[R_ERR], W[R_FU], p)
        ist[S_NFEV] += 1
        _load(W, R_ERR, R_FU, R_Q + 1 + j)
    for m in range(n):
        g0 = W[R_G, m]
        d1 = W[R_Q + 1, m] - g0
        d2 = W[R_Q + 2, m] - g0
        d3 = W[R_GNEW, m] - g0
        W[R_Q, m] = g0
        W[R_Q + 1, m] = _CUBIC[0, 0] * d1 + _CUBIC[0, 1] * d2 + _CUBIC[0, 2] * d3
        W[R_Q + 2, m] = _CUBIC[1, 0] * d1 + _CUBIC[1, 1] * d2 + _CUBIC[1, 2] * d3
        W[R_Q + 3, m] = _CUBIC[2, 0] * d1 + _CUBIC[2, 1] * d2 + _CUBIC[2, 2] * d3


@jitable
def _cubic_solution(W, h, row_phi, r_y, theta, r_out):
    """``phi_0(theta h A) y + h sum_k k! theta^(k+1) phi_(k+1)(theta h A) Q_k`` into row ``r_out``.

    The variation-of-constants formula with the load replaced by its cubic ``R_Q``, integrated
    exactly (``int_0^tau exp((tau - s) A) s^k ds = k! tau^(k+1) phi_(k+1)(tau A)``); ``row_phi``
    holds ``phi_0 .. phi_4`` of ``theta h A``.
    """
    _phi_sum(W, r_out, (row_phi, row_phi + 1, row_phi + 2, row_phi + 3, row_phi + 4), (r_y, R_Q, R_Q + 1, R_Q + 2, R_Q + 3),
             (1.0, theta * h, theta**2 * h, 2.0 * theta**3 * h, 6.0 * theta**4 * h))


@kernel
def init(rhs, p, W, fst, ist):
    """``f(t0, y0)``, ``G_1`` and the starting step."""
    rk_init(rhs, p, W, fst, ist)


@kernel
def step(rhs, p, W, fst, ist):
    """One accepted step (seven evaluations); False if the step size underflows (:func:`rk_step`)."""
    return rk_step(rhs, p, W, fst, ist)


@jitable
def rk_init(rhs, p, W, fst, ist):
    """:func:`init`'s work, also the start of :mod:`.exponential_adams`."""
    rhs(fst[F_T], W[R_Y], W[R_F], p)
    ist[S_NFEV] += 1
    _load(W, R_Y, R_F, R_G)
    fst[F_HOLD] = np.nan
    fst[F_PART] = 0.0
    fst[F_DEGREE] = 3.0
    fst[F_H] = initial_step(rhs, p, W, fst, ist, ORDER, W[R_U], W[R_FU])


@jitable
def rk_step(rhs, p, W, fst, ist):
    """One accepted step (seven evaluations); False if the step size underflows.

    The error is estimated twice: the stages' (``h (2 phi_2 - 4 phi_3)(hA) (2 G_5 - G_2 - G_3)``,
    the difference to Krogstad's third-order weights, blind to a load that depends on time only)
    and the quadrature's (the difference to the step integrated with the cubic interpolant of the
    load, :func:`_load_cubic`, which is also the dense output); the larger decides.
    """
    n = W.shape[1]
    t = fst[F_T]
    smallest = min_step(t, fst[F_DIR])
    h_abs = min(fst[F_H], fst[F_MAXSTEP])
    rejected = False
    while True:
        if h_abs < smallest:
            return False
        t_new = step_end(fst, t, h_abs)
        h = t_new - t
        if h != fst[F_HOLD]:
            _step_tables(W, h)
            fst[F_HOLD] = h
        _stages(rhs, p, W, ist, t, h)
        err = scaled_rms(W[R_ERR], W[R_Y], W[R_YNEW], W)
        _load_cubic(rhs, p, W, ist, t, h)
        _cubic_solution(W, h, R_ONE, R_Y, 1.0, R_ERR)
        for m in range(n):
            W[R_ERR, m] -= W[R_YNEW, m]
        err = max(err, scaled_rms(W[R_ERR], W[R_Y], W[R_YNEW], W))
        if not np.isfinite(err):  # NaN or infinity in the stages: shrink, and say so if it underflows
            ist[S_FAIL] = FAIL_RHS
            err = 1.0 / MIN_FACTOR ** ORDER
        factor = step_factor(err, ORDER - 1, rejected)
        if KEEP_LOW <= factor <= KEEP_HIGH and h == fst[F_HOLD]:
            factor = 1.0  # the tables serve the next step too
        h_abs = abs(h) * factor
        if err < 1.0:
            ist[S_FAIL] = 0
            break
        rejected = True
        ist[S_NREJ] += 1
    fst[F_DEGREE] = 3.0  # the dense output's load: the cubic of _load_cubic
    accept(W, fst, ist, t, t_new, h_abs)
    return True


@jitable
def accept(W, fst, ist, t, t_new, h_abs):
    """The step from ``t`` to ``t_new`` becomes the last one: ``y`` from ``R_YNEW``, the load ``G_1``
    of the next step from ``R_GNEW``, the next step's size ``h_abs``; its dense output is to be made."""
    for m in range(W.shape[1]):
        W[R_YOLD, m] = W[R_Y, m]
        W[R_Y, m] = W[R_YNEW, m]
        W[R_G, m] = W[R_GNEW, m]
    accept_step(fst, t, t_new, h_abs)
    fst[F_PART] = 0.0
    ist[S_DENSE] = 1

"""Dense output of the exponential methods (:mod:`.exponential`, :mod:`.exponential_adams`): a step's solution at any time inside it.

The step's solution with its load replaced by a polynomial (the Runge-Kutta method's cubic
interpolant of its error estimate, :func:`.exponential._load_cubic`; the Adams method's corrector
quintic), integrated exactly: of the step's order. At a sample the dense output evaluates
``exp(tau A) (y_n - P(0)) + P(tau)``, with ``P`` the polynomial particular solution of the block
(:func:`_particular`): one real ``exp``, ``cos``, ``sin`` per block, against the complex
phi-functions (2.6x cheaper a sample); along the samples of ``t_eval``, ``exp(lambda tau)``
follows from the previous sample's by one rotation (:data:`CHAIN_LENGTH`). Where ``h omega`` is
small (``P`` would cancel) it sums the Taylor series of the step's solution (:func:`_taylor`);
where the block is not underdamped it falls back to the variation-of-constants sum over the
phi-functions (:func:`.exponential._cubic_solution`'s formula, to the load's degree). The three
agree to rounding.

This is the methods' ``dense`` (:class:`lubelink.integrate.Method`); the rows and floats it uses
are laid out in :mod:`.exponential`.
"""

import math

import numpy as np

from lubelink._jit import jitable, kernel
from ._layout import F_HSTEP, F_TOLD, R_YOLD, S_SAMPLE
from .exponential import (F_CHAIN, F_DEGREE, F_DTAU, F_PART, F_TAU, R_FREE, R_LAST, R_LIN, R_PART, R_Q, R_ROT,
                          R_TAYLOR, R_THETA, R_TURN, R_U, TAYLOR_TERMS, _apply_block, _table_block)

__all__ = ["dense"]

#: Smallest ``h omega`` at which the dense output of a block uses its particular solution (below,
#: the Taylor series of the solution), by the degree of the load polynomial (3: the Runge-Kutta method's cubic, 5:
#: the Adams method's quintic): the particular solution's terms grow like ``d! / (h omega)^(d + 1)``
#: against the solution, and so does their rounding error; these keep that growth below about 2000
#: (rounding about 1e-13 of the state).
DENSE_H_OMEGA = (0.0, 0.0, 0.0, 0.25, 0.0, 0.63)
#: Largest damping ratio at which the dense output of a block uses its particular solution.
DENSE_ZETA = 0.999
#: Samples of ``t_eval`` in a row whose ``exp(lambda tau)`` follows from the previous sample's
#: by one rotation ``exp(lambda dtau)`` (a complex product instead of an ``exp``, ``cos`` and
#: ``sin``), before one is computed directly again: the rounding of the products, a few units of
#: the last place each, stays below 1e-14 of the free oscillation.
CHAIN_LENGTH = 32
#: Relative difference of two spacings of samples within which the rotation of one serves the
#: other, with the first-order correction ``1 + lambda (d - dtau)`` (its error ``(lambda (d - dtau))^2 / 2``
#: is below 1e-18 for ``|lambda dtau| < 1e3``); sample times differ from a uniform grid by rounding only.
CHAIN_MATCH = 1e-9




@jitable
def _particular(W, h, degree):
    """Per block, the polynomial solution ``P`` of ``y' = A y + G(tau)`` for the last step's polynomial load.

    With the load ``G(t_n + tau) = sum_k c_k tau^k`` (``c_k = Q_k / h^k``, ``k <= d = degree``),
    matching powers of ``tau`` in ``P' = A P + G`` gives ``P_d = -A^-1 c_d``, ``P_k = A^-1 ((k + 1) P_(k+1) - c_k)``;
    the solution of the step is then ``exp(tau A) (y_n - P(0)) + P(tau)``, and ``exp(tau A)`` of an
    underdamped block is ``e^(-zeta omega tau) (cos(omega_d tau) I + sin(omega_d tau) (A + zeta
    omega I) / omega_d)``. Rows ``R_PART`` hold ``P_0 .. P_d``, ``R_FREE`` ``y_n - P(0)``, ``R_TURN``
    ``(A + zeta omega I) (y_n - P(0)) / omega_d``. An underdamped block below :data:`DENSE_H_OMEGA`
    gets the Taylor series of the step's solution instead (:func:`_taylor`; ``R_TURN`` is -inf); one
    above :data:`DENSE_ZETA` is left to the phi-functions (``R_TURN`` is NaN).
    """
    N = W.shape[1] // 2
    smallest = DENSE_H_OMEGA[degree]
    for i in range(N):
        om = W[R_LIN, i]
        zeta = W[R_LIN, N + i]
        if not zeta < DENSE_ZETA:
            W[R_TURN, i] = np.nan
            continue
        if abs(h) * om < smallest:
            _taylor(W, h, degree, i)
            W[R_TURN, i] = -np.inf
            continue
        inv_om2 = 1.0 / (om * om)
        two_zo = 2.0 * zeta * om
        px = 0.0
        pv = 0.0
        for k in range(degree, -1, -1):  # A^-1 (a, b) = ((-2 zeta omega a - b) / omega^2, a)
            scale = 1.0 / h**k
            a = (k + 1) * px - W[R_Q + k, i] * scale
            b = (k + 1) * pv - W[R_Q + k, N + i] * scale
            px = (-two_zo * a - b) * inv_om2
            pv = a
            W[R_PART + k, i] = px
            W[R_PART + k, N + i] = pv
        zx = W[R_YOLD, i] - px
        zv = W[R_YOLD, N + i] - pv
        sigma = zeta * om
        inv_od = 1.0 / (om * math.sqrt(1.0 - zeta * zeta))
        W[R_FREE, i] = zx
        W[R_FREE, N + i] = zv
        W[R_TURN, i] = (sigma * zx + zv) * inv_od
        W[R_TURN, N + i] = (-om * om * zx - sigma * zv) * inv_od


@jitable
def _taylor(W, h, degree, i):
    """Rows ``R_TAYLOR ..`` of block ``i``: the Taylor coefficients in ``tau`` of the step's solution.

    ``y(tau) = sum_j Y_j tau^j`` with ``Y_0 = y_n``, ``Y_(j+1) = (A Y_j + c_j) / (j + 1)`` (``c_j = Q_j / h^j``
    for ``j <= degree``, 0 beyond): the exact solution under the polynomial load. For
    ``|h omega| <`` :data:`DENSE_H_OMEGA` (< 1) the terms fall like ``(h omega)^j / j!``, so
    :data:`~.exponential.TAYLOR_TERMS` of them reach rounding (``0.63^17 / 17! ~ 1e-18``) where the
    particular solution would cancel; a sample is then one Horner sum per component instead of
    the phi-functions of the block.
    """
    N = W.shape[1] // 2
    om = W[R_LIN, i]
    two_zo = 2.0 * W[R_LIN, N + i] * om
    x = W[R_YOLD, i]
    v = W[R_YOLD, N + i]
    W[R_TAYLOR, i] = x
    W[R_TAYLOR, N + i] = v
    for j in range(TAYLOR_TERMS - 1):
        cx = 0.0
        cv = 0.0
        if j <= degree:
            scale = 1.0 / h**j
            cx = W[R_Q + j, i] * scale
            cv = W[R_Q + j, N + i] * scale
        inv = 1.0 / (j + 1)
        x, v = (v + cx) * inv, (-om * om * x - two_zo * v + cv) * inv
        W[R_TAYLOR + j + 1, i] = x
        W[R_TAYLOR + j + 1, N + i] = v


@jitable
def _rotations(W, d):
    """``exp(lambda d)`` of every underdamped block into ``R_ROT`` (``lambda = -zeta omega + i omega_d``).

    All of them, not only those of this step's particular solution: the rotations serve later steps,
    whose blocks may switch from the phi-functions to the particular solution (``h omega`` grows).
    """
    N = W.shape[1] // 2
    for i in range(N):
        if W[R_LIN, N + i] < DENSE_ZETA:
            W[R_ROT, i], W[R_ROT, N + i] = _exp_lambda(W[R_LIN, i], W[R_LIN, N + i], d)


@jitable
def _exp_lambda(om, zeta, tau):
    """``exp(lambda tau)`` of an underdamped block as ``(Re, Im)``, ``lambda = -zeta omega + i omega_d``."""
    decay = math.exp(-zeta * om * tau)
    angle = om * math.sqrt(1.0 - zeta * zeta) * tau
    return decay * math.cos(angle), decay * math.sin(angle)


@kernel
def dense(rhs, p, W, fst, ist, t, out):
    """Dense output of the last step at ``t``, into ``out``, of the step's order.

    The step's solution with its load replaced by the polynomial ``R_Q`` of degree
    ``fst[F_DEGREE]``, integrated exactly: for an underdamped block with ``h omega >=``
    :data:`DENSE_H_OMEGA` through the particular solution of :func:`_particular`
    (``exp(lambda tau)``: a real ``exp``, ``cos`` and ``sin`` per block; along the samples of
    ``t_eval`` the previous sample's times one rotation, :data:`CHAIN_LENGTH`), below it through
    the Taylor series of :func:`_taylor`, for a block near or above critical damping through the
    phi-functions; the three agree to rounding.
    """
    h = fst[F_HSTEP]
    theta = (t - fst[F_TOLD]) / h
    if theta == 0.0:
        for m in range(W.shape[1]):
            out[m] = W[R_YOLD, m]
        return
    degree = int(fst[F_DEGREE])
    if fst[F_PART] == 0.0:
        _particular(W, h, degree)
        fst[F_PART] = 1.0
        fst[F_TAU] = np.nan
    N = W.shape[1] // 2
    tau = theta * h
    sample = ist[S_SAMPLE] != 0
    chained = False
    delta = 0.0
    if sample:
        d = tau - fst[F_TAU]  # NaN at the first sample of the step
        dtau = fst[F_DTAU]
        if d == d and d != 0.0:
            if abs(d - dtau) <= CHAIN_MATCH * abs(dtau):
                chained = fst[F_CHAIN] < CHAIN_LENGTH
                delta = d - dtau
            else:  # a new spacing: its rotations, for the samples that follow
                _rotations(W, d)
                fst[F_DTAU] = d
        fst[F_CHAIN] = fst[F_CHAIN] + 1.0 if chained else 0.0
        fst[F_TAU] = tau
    for i in range(N):
        if W[R_TURN, i] == -np.inf:  # small h omega: the Taylor series of the step's solution
            x = W[R_TAYLOR + TAYLOR_TERMS - 1, i]
            v = W[R_TAYLOR + TAYLOR_TERMS - 1, N + i]
            for j in range(TAYLOR_TERMS - 2, -1, -1):
                x = x * tau + W[R_TAYLOR + j, i]
                v = v * tau + W[R_TAYLOR + j, N + i]
            out[i] = x
            out[N + i] = v
            continue
        if np.isnan(W[R_TURN, i]):  # through the phi-functions, in the scratch row R_U
            _table_block(W, tau, R_THETA, degree + 2, i)
            W[R_U, i] = 0.0
            W[R_U, N + i] = 0.0
            _apply_block(W, R_THETA, R_YOLD, R_U, 1.0, i)
            factorial = 1.0
            for k in range(degree + 1):
                _apply_block(W, R_THETA + k + 1, R_Q + k, R_U, factorial * theta ** (k + 1) * h, i)
                factorial *= k + 1
            out[i] = W[R_U, i]
            out[N + i] = W[R_U, N + i]
            continue
        om = W[R_LIN, i]
        zeta = W[R_LIN, N + i]
        if chained:  # exp(lambda tau) = exp(lambda tau_last) exp(lambda dtau) (1 + lambda delta)
            sigma = zeta * om
            omega_d = om * math.sqrt(1.0 - zeta * zeta)
            cr = 1.0 - sigma * delta
            ci = omega_d * delta
            rr = W[R_ROT, i] * cr - W[R_ROT, N + i] * ci
            ri = W[R_ROT, i] * ci + W[R_ROT, N + i] * cr
            c = W[R_LAST, i] * rr - W[R_LAST, N + i] * ri
            s = W[R_LAST, i] * ri + W[R_LAST, N + i] * rr
        else:
            c, s = _exp_lambda(om, zeta, tau)
        if sample:
            W[R_LAST, i] = c
            W[R_LAST, N + i] = s
        x = W[R_PART + degree, i]
        v = W[R_PART + degree, N + i]
        for k in range(degree - 1, -1, -1):
            x = x * tau + W[R_PART + k, i]
            v = v * tau + W[R_PART + k, N + i]
        out[i] = c * W[R_FREE, i] + s * W[R_TURN, i] + x
        out[N + i] = c * W[R_FREE, N + i] + s * W[R_TURN, N + i] + v

"""The axial force in the link from its rigid motion, and its geometric stiffness (docs/model.md §1.5).

The link's rigid motion loads it along its chord ``i``: per unit length, the d'Alembert force of the axial
rigid acceleration ``a_1(x) = A_O1 - omega^2 x`` and gravity, ``p_1(x) = rho A (g_1 - A_O1 + omega^2 x)``.
With the force the slider C exerts along ``i``, ``N_C``, the axial force (tension positive) is

    N(x) = N_C + int_x^L p_1 ds = N_C - rho A (A_O1 - g_1) (L - x) + rho A omega^2 (L^2 - x^2) / 2,

a quadratic ``c0 + c1 x + c2 x^2`` (:func:`axial_force_terms`). The massless frictionless slider pushes
only normal to its guide (the +X line of the slider-crank), so it does load the link axially:
``N_C = F_C2 tan(angle)``, with ``F_C2`` its force along ``j``, from the link's moment balance about O
(:func:`slider_end_force`; the collar pushes along ``j`` only and adds its moment).

``N`` works on the bending slope: the term ``(N u2')'`` of the transverse equation becomes, in the sine
modes ``phi_n = sin(beta_n x)``, the modal force ``-sum_n K_mn q_n`` with
``K_mn = int_0^L N phi_m' phi_n' dx = c0 P0_mn + c1 P1_mn + c2 P2_mn`` (tension stiffens), the ``P_k`` the
slope moments ``int_0^L x^k phi_m' phi_n' dx`` in closed form (:func:`slope_moments`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .._jit import jitable
from ..beam import wavenumber

__all__ = ["GeometricTable", "slope_moments", "slider_end_force", "axial_force_terms", "rigid_axial_force",
           "axial_force", "geometric_stiffness", "geometric_load", "geometric_table"]


class GeometricTable(NamedTuple):
    """What compiled code reads for the geometric stiffness: ``moments`` ``(3, N, N)`` the slope moments
    :func:`slope_moments` [m^-1, 1, m], ``mass_per_length`` ``rho A`` [kg/m]."""

    moments: np.ndarray
    mass_per_length: float


def _cosine_moment(k, j, rod_length):
    """``int_0^L x^k cos(j pi x / L) dx`` for ``k`` in 0, 1, 2 and an integer ``j >= 0`` (closed form)."""
    L = rod_length
    if j == 0:
        return L ** (k + 1) / (k + 1)
    s = wavenumber(j, L)
    sign = -1.0 if j % 2 else 1.0  # cos(j pi)
    return (0.0, (sign - 1.0) / s**2, 2.0 * L * sign / s**2)[k]


def slope_moments(modes, rod_length):
    """``P[k, m, n] = int_0^L x^k phi_m'(x) phi_n'(x) dx`` for ``k = 0, 1, 2``, ``phi_n = sin(n pi x / L)``
    [m^(k-1)], shape ``(3, modes, modes)``.

    ``phi_m' phi_n' = beta_m beta_n [cos((beta_m - beta_n) x) + cos((beta_m + beta_n) x)] / 2``, and each
    cosine moment is closed (:func:`_cosine_moment`).
    """
    P = np.zeros((3, modes, modes))
    for k in range(3):
        for m in range(1, modes + 1):
            for n in range(1, modes + 1):
                bm, bn = wavenumber(m, rod_length), wavenumber(n, rod_length)
                P[k, m - 1, n - 1] = 0.5 * bm * bn * (_cosine_moment(k, abs(m - n), rod_length)
                                                      + _cosine_moment(k, m + n, rod_length))
    return P


def geometric_table(modes, rod_length, mass_per_length):
    """The :class:`GeometricTable` of a uniform link of ``modes`` sine modes, length [m], ``rho A`` [kg/m]."""
    return GeometricTable(np.ascontiguousarray(slope_moments(modes, rod_length)), float(mass_per_length))


@jitable
def slider_end_force(A_t, alpha, reaction, x_star, mass_per_length, rod_length):
    """The force of the slider on the link end C along ``j`` [N], from the rigid link's moment balance about O.

    ``F_C2 L + int_0^L x p_2 dx + R x_star = 0`` with the transverse d'Alembert load
    ``p_2 = -rho A (A_t + alpha x)`` and the collar's force ``R`` along ``j`` at ``x_star``:
    ``F_C2 = rho A (A_t L / 2 + alpha L^2 / 3) - R x_star / L``.

    Parameters
    ----------
    A_t : float
        Transverse acceleration of O less gravity along ``j``, ``A_O2 - g_2`` [m/s^2].
    alpha : float
        Angular acceleration of the link [rad/s^2].
    reaction, x_star : float
        The collar's force along ``j`` [N] and its position from O [m].
    mass_per_length, rod_length : float
        ``rho A`` [kg/m], ``L`` [m].
    """
    L = rod_length
    return mass_per_length * (0.5 * A_t * L + alpha * L * L / 3.0) - reaction * x_star / L


@jitable
def axial_force_terms(A_a, omega, N_C, mass_per_length, rod_length):
    """``(c0 [N], c1 [N/m], c2 [N/m^2])`` of the axial force ``N(x) = c0 + c1 x + c2 x^2`` (tension positive).

    ``N(x) = N_C - rho A A_a (L - x) + rho A omega^2 (L^2 - x^2) / 2``: the force ``N_C`` [N] the slider puts
    on the end C along ``i``, plus the axial loads beyond ``x``, with ``A_a = A_O1 - g_1`` [m/s^2] the axial
    acceleration of O less gravity along ``i`` and ``omega`` [rad/s] the link's rate (the centripetal
    acceleration ``-omega^2 x``).
    """
    m, L = mass_per_length, rod_length
    return N_C - m * A_a * L + 0.5 * m * omega * omega * L * L, m * A_a, -0.5 * m * omega * omega


@jitable
def rigid_axial_force(A_O1, A_O2, omega, alpha, angle, reaction, x_star, gravity, mass_per_length, rod_length):
    """``(c0, c1, c2)`` of :func:`axial_force_terms` for the slider-crank's rigid motion (units there).

    ``A_O1``, ``A_O2`` [m/s^2] the acceleration of O along ``i`` and ``j``; ``angle`` [rad] that of ``i``
    from +X; ``gravity`` ``(g_X, g_Y)`` [m/s^2]. The slider's force is along +Y (normal to its guide, the
    +X line): its ``j`` part :func:`slider_end_force`, its ``i`` part that times ``tan(angle)``.
    """
    gX, gY = gravity
    c, s = np.cos(angle), np.sin(angle)
    g1 = gX * c + gY * s
    g2 = -gX * s + gY * c
    F_C2 = slider_end_force(A_O2 - g2, alpha, reaction, x_star, mass_per_length, rod_length)
    return axial_force_terms(A_O1 - g1, omega, F_C2 * s / c, mass_per_length, rod_length)


def axial_force(x, terms):
    """``N(x)`` [N] of the terms ``(c0, c1, c2)`` of :func:`axial_force_terms` at ``x`` [m] (elementwise)."""
    c0, c1, c2 = (np.asarray(c, dtype=float) for c in terms)
    x = np.asarray(x, dtype=float)
    return c0 + c1 * x + c2 * x * x


def geometric_stiffness(moments, terms):
    """``K_mn = int_0^L N phi_m' phi_n' dx`` [N/m] of the terms ``(c0, c1, c2)``, from the slope ``moments``."""
    c0, c1, c2 = terms
    return c0 * moments[0] + c1 * moments[1] + c2 * moments[2]


@jitable
def geometric_load(moments, c0, c1, c2, q, F):
    """Add the geometric stiffness's modal forces ``-K q`` [N] to ``F`` (``q`` [m], the sine modes)."""
    N = q.shape[0]
    for m in range(N):
        f = 0.0
        for n in range(N):
            f += (c0 * moments[0, m, n] + c1 * moments[1, m, n] + c2 * moments[2, m, n]) * q[n]
        F[m] -= f

"""The forces of the joints on the planar link: Newton's and Euler's laws for the whole link.

The link (mass per length ``rho A(x)``) is pinned to the crank at O and to the slider at C, and carries the
collar's loads. With the elastic deflection ``u2`` the point at ``x`` is at ``x i + u2 j`` from O and has the
acceleration ``a_O + alpha k x r - omega^2 r + 2 omega k x u2_dot j + u2_ddot j``. Its integrals over the link,
to first order in ``u2`` as the modal equations are,

    P = int rho A a dx:   P_i = m a_O1 - alpha U - omega^2 S1 - 2 omega U_dot,   P_j = m a_O2 + alpha S1 - omega^2 U + U_ddot
    M_O = int (r x rho A a) . k dx = S1 a_O2 + alpha J_O + sum_n b_n q_ddot_n - U a_O1

(``m``, ``S1``, ``J_O`` the mass and its first and second moments about O, ``U = sum_n a_n q_n``, ``a_n``, ``b_n``
the first two moments of ``rho A sin(beta_n x)``: :func:`link_inertia`) equal the forces on the link and their
moment about O. The massless, frictionless slider on the guide along X pushes the link along Y only, so the
moment balance about O gives the slider pin's force and the force balance the crank pin's (:func:`joint_reactions`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..beam import wavenumbers
from .section import quadrature, sampled

__all__ = ["LinkInertia", "link_inertia", "crank_pin_acceleration", "joint_reactions"]


class LinkInertia(NamedTuple):
    """Moments of the link's mass per length ``rho A(x)`` about O.

    Attributes
    ----------
    mass : float
        ``m = int rho A dx`` [kg].
    first : float
        ``S1 = int rho A x dx`` [kg m].
    second : float
        ``J_O = int rho A x^2 dx`` [kg m^2].
    modal : ndarray, shape (N,)
        ``a_n = int rho A sin(beta_n x) dx`` [kg].
    modal_first : ndarray, shape (N,)
        ``b_n = int rho A x sin(beta_n x) dx`` [kg m].
    """

    mass: float
    first: float
    second: float
    modal: np.ndarray
    modal_first: np.ndarray


def link_inertia(section, density, rod_length, modes) -> LinkInertia:
    """:class:`LinkInertia` of a link of ``section`` (:class:`~lubelink.link.section.Section`), ``density``
    [kg/m^3] and length ``rod_length`` [m], for ``modes`` sine modes, by composite Gauss-Legendre quadrature."""
    x, w = quadrature(rod_length, modes)
    mass = w * density * sampled(section, "area", x, rod_length)
    shapes = np.sin(np.outer(x, wavenumbers(modes, rod_length)))
    return LinkInertia(float(mass.sum()), float(mass @ x), float(mass @ (x * x)), mass @ shapes, (mass * x) @ shapes)


def crank_pin_acceleration(t, crank_length, crank_speed):
    """Acceleration of the crank pin O in the fixed frame, ``-omega0^2 OA (cos phi, sin phi)`` with ``phi = omega0 t``
    [m/s^2] (the crank turning at constant speed, docs/model.md section 3): ``(a_X, a_Y)``."""
    phi = crank_speed * np.asarray(t, dtype=float)
    scale = -crank_speed * crank_speed * crank_length
    return scale * np.cos(phi), scale * np.sin(phi)


def joint_reactions(inertia: LinkInertia, rod_length, angle, a_O, omega, alpha, q, q_dot, q_ddot, collar, gravity):
    """Forces of the crank pin and of the slider pin on the link [N], in the fixed frame.

    Parameters
    ----------
    inertia : LinkInertia
    rod_length : float
        ``L`` [m]; the slider pin at ``x = L``.
    angle : ndarray, shape (T,)
        Angle of the link axis ``i`` from +X [rad].
    a_O : tuple of ndarray
        ``(a_X, a_Y)``: acceleration of O in the fixed frame [m/s^2].
    omega, alpha : ndarray, shape (T,)
        Angular velocity [rad/s] and acceleration [rad/s^2] of the link about +k.
    q, q_dot, q_ddot : ndarray, shape (T, N)
        Sine-mode coordinates [m] and their rates [m/s], [m/s^2].
    collar : tuple of ndarray
        ``(F_i, F_j, M)``: resultant of the collar's loads on the link along +i and +j [N] and their moment about O
        (+k) [N m].
    gravity : tuple of float
        ``(g_X, g_Y)`` [m/s^2].

    Returns
    -------
    tuple of ndarray
        ``(R_OX, R_OY, R_C)``: the crank pin's force on the link along +X and +Y, the slider pin's along +Y [N].
    """
    c, s = np.cos(angle), np.sin(angle)
    a_i = a_O[0] * c + a_O[1] * s
    a_j = -a_O[0] * s + a_O[1] * c
    g_i = gravity[0] * c + gravity[1] * s
    g_j = -gravity[0] * s + gravity[1] * c
    m, S1 = inertia.mass, inertia.first
    U, U_dot, U_ddot = q @ inertia.modal, q_dot @ inertia.modal, q_ddot @ inertia.modal
    P_i = m * a_i - alpha * U - omega * omega * S1 - 2.0 * omega * U_dot
    P_j = m * a_j + alpha * S1 - omega * omega * U + U_ddot
    M_O = S1 * a_j + alpha * inertia.second + q_ddot @ inertia.modal_first - U * a_i
    F_i, F_j, M_collar = collar
    # the moment about O of the forces: the slider pin's (L i x R_C Y = L cos(angle) R_C k), the collar's, gravity's
    R_C = (M_O - M_collar - (S1 * g_j - U * g_i)) / (rod_length * c)
    R_i = P_i - R_C * s - F_i - m * g_i
    R_j = P_j - R_C * c - F_j - m * g_j
    return R_i * c - R_j * s, R_i * s + R_j * c, R_C

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

The same slider turns the chord: a bent link is shorter between its ends by ``delta = int_0^L u2'^2 / 2 dx``,
and with O held on the crank and C on the ``X`` axis its chord turns by ``dpsi = tan(angle) delta / L``
(second order in the deflection). The points of the link move across it by ``x dpsi``: their inertia couples
the modes through a mass that depends on the deflection (:func:`chord_rotation`, docs/model.md §1.5), the
second half of the slider's second-order work (the first is ``N_C``'s stiffness).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .._jit import jitable
from ..beam import wavenumber

__all__ = ["GeometricTable", "slope_moments", "slider_end_force", "axial_force_terms", "rigid_axial_force",
           "frame_axial_force", "axial_force", "geometric_stiffness", "geometric_load",
           "geometric_jacobian", "geometric_table", "chord_levers",
           "chord_rotation", "chord_rotation_force", "chord_rotation_jacobian"]


class GeometricTable(NamedTuple):
    """What compiled code reads for the geometric stiffness: ``moments`` ``(3, N, N)`` the slope moments
    :func:`slope_moments` [m^-1, 1, m], ``mass_per_length`` ``rho A`` [kg/m]; for the chord's rotation
    (:func:`chord_rotation`) ``lever`` ``b_n = int_0^L x phi_n dx`` [m^2] and ``slopes`` ``D_n = int_0^L phi_n'^2 dx``
    [1/m] (:func:`chord_levers`)."""

    moments: np.ndarray
    mass_per_length: float
    lever: np.ndarray
    slopes: np.ndarray


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


def chord_levers(modes, rod_length):
    """``(b, D)``: ``b_n = int_0^L x sin(beta_n x) dx = (-1)^(n+1) L / beta_n`` [m^2] (the moment about O of the
    sine mode) and ``D_n = int_0^L phi_n'^2 dx = beta_n^2 L / 2`` [1/m] (so the chord shortens by
    ``delta = sum_n D_n q_n^2 / 2``; the sine modes' slopes are orthogonal), each of shape ``(modes,)``."""
    beta = np.array([wavenumber(n, rod_length) for n in range(1, modes + 1)])
    sign = np.where(np.arange(1, modes + 1) % 2 == 1, 1.0, -1.0)
    return sign * rod_length / beta, 0.5 * beta * beta * rod_length


def geometric_table(modes, rod_length, mass_per_length):
    """The :class:`GeometricTable` of a uniform link of ``modes`` sine modes, length [m], ``rho A`` [kg/m]."""
    b, D = chord_levers(modes, rod_length)
    return GeometricTable(np.ascontiguousarray(slope_moments(modes, rod_length)), float(mass_per_length),
                          np.ascontiguousarray(b), np.ascontiguousarray(D))


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
    return frame_axial_force((A_O1 - g1, A_O2 - g2, 0.0), (-omega * omega, alpha, 0.0), (c, -s, 0.0), reaction,
                             x_star, mass_per_length, rod_length)


@jitable
def frame_axial_force(A, axis, d, reaction, x_star, mass_per_length, rod_length):
    """``(c0, c1, c2)`` of :func:`axial_force_terms` for a rigid link whose frame moves in space (units there).

    ``A`` [m/s^2] the acceleration of O less gravity, ``axis = alpha x e1 + w x (w x e1)`` [1/s^2] the
    acceleration of the point ``x e1`` per unit ``x`` (:func:`lubelink.link.spatial.axis_acceleration`:
    ``axis_1 = -(w2^2 + w3^2)``, the centripetal one), ``d`` [-] the slider's guide direction, all 3-tuples of
    link-frame components; the collar's force ``reaction`` [N] along ``e2`` at ``x_star`` [m]. The slider's
    force on C, ``(R1, R2, R3)``, has ``R2``, ``R3`` from the rigid link's moments about O in the ``e1 e2`` and
    ``e1 e3`` planes (:func:`slider_end_force` each) and is normal to its guide, ``R . d = 0``:
    ``R1 = -(R2 d2 + R3 d3) / d1``. The planar link is ``axis = (-omega^2, alpha, 0)``,
    ``d = (cos angle, -sin angle, 0)``: ``R1 = R2 tan(angle)``.
    """
    R2 = slider_end_force(A[1], axis[1], reaction, x_star, mass_per_length, rod_length)
    R3 = slider_end_force(A[2], axis[2], 0.0, x_star, mass_per_length, rod_length)
    return axial_force_terms(A[0], np.sqrt(-axis[0]), -(R2 * d[1] + R3 * d[2]) / d[0], mass_per_length, rod_length)


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


@jitable
def geometric_jacobian(moments, c0, c1, c2, Jq):
    """Subtract the geometric stiffness ``K`` [N/m] of the terms ``c0, c1, c2`` from ``Jq`` (a block ``dF/dq`` of the
    modal forces of one bending direction, the sine modes)."""
    N = Jq.shape[0]
    for m in range(N):
        for n in range(N):
            Jq[m, n] -= c0 * moments[0, m, n] + c1 * moments[1, m, n] + c2 * moments[2, m, n]


@jitable
def _chord_sums(lever, slopes, q, q_dot):
    """``(delta [m], delta_dot [m/s], q_dot D q_dot [m/s^2], b.q [m^2], b.D q [m], (D q).(D q) [1], b.b [m^4])``."""
    delta = delta_dot = vDv = bq = vb = vv = bb = 0.0
    for n in range(q.shape[0]):
        v = slopes[n] * q[n]
        delta += 0.5 * v * q[n]
        delta_dot += v * q_dot[n]
        vDv += slopes[n] * q_dot[n] * q_dot[n]
        bq += lever[n] * q[n]
        vb += v * lever[n]
        vv += v * v
        bb += lever[n] * lever[n]
    return delta, delta_dot, vDv, bq, vb, vv, bb


@jitable
def _chord_load(m, lever, slopes, mass_per_length, rod_length, angle, omega, alpha, q, sums):
    """The chord rotation's modal force on mode ``m`` that does not hold the accelerations [N] (see
    :func:`chord_rotation`): ``x_m = -(rho A / L) b_m (tau'' delta + 2 tau' delta' + tau q'.D q')
    + (rho A omega^2 tau / L) (b_m delta + D_m q_m b.q)``."""
    delta, delta_dot, vDv, bq = sums[0], sums[1], sums[2], sums[3]
    tau = np.tan(angle)
    sec2 = 1.0 + tau * tau
    tau_dot = omega * sec2
    tau_ddot = (alpha + 2.0 * omega * omega * tau) * sec2
    r = mass_per_length / rod_length
    return (-r * lever[m] * (tau_ddot * delta + 2.0 * tau_dot * delta_dot + tau * vDv)
            + r * omega * omega * tau * (lever[m] * delta + slopes[m] * q[m] * bq))


@jitable
def chord_rotation(lever, slopes, mass_per_length, rod_length, modal_mass, angle, omega, alpha, q, q_dot, acc):
    """Correct the modal accelerations ``acc`` [m/s^2] (in place) for the rotation of the link's chord.

    ``acc`` holds the accelerations with the chord on the rigid link's (all forces over the modal mass
    ``m`` [kg]). The chord turns by ``dpsi = tau delta / L`` (``tau = tan(angle)``, ``angle`` [rad] the link's
    from +X, the slider's guide; ``delta = sum D_n q_n^2 / 2`` [m] the chord's shortening), so the link's
    points move across it by ``x dpsi``; Lagrange's equations of ``T = rho A / 2 int (u2_dot + x dpsi_dot)^2``
    (first order in ``dpsi``) and of the frame's ``-omega^2`` softening of it give

        (m I + c (b v^T + v b^T)) q_ddot = m acc + x,    c = rho A tau / L,  v = D q,

    with ``x`` of :func:`_chord_load`, ``omega`` [rad/s] and ``alpha`` [rad/s^2] the link's rate and angular
    acceleration (``tau' = omega sec^2``, ``tau'' = (alpha + 2 omega^2 tau) sec^2``), ``lever``, ``slopes``
    the :class:`GeometricTable`'s ``b`` [m^2], ``D`` [1/m], ``rho A`` [kg/m], ``L`` [m], ``q`` [m], ``q_dot``
    [m/s]. The mass is the identity plus a rank-two term: solved exactly (Sherman-Morrison-Woodbury).
    """
    sums = _chord_sums(lever, slopes, q, q_dot)
    vb, vv, bb = sums[4], sums[5], sums[6]
    N = q.shape[0]
    for n in range(N):
        acc[n] += _chord_load(n, lever, slopes, mass_per_length, rod_length, angle, omega, alpha, q, sums) / modal_mass
    _chord_solve(mass_per_length * np.tan(angle) / rod_length / modal_mass, lever, slopes, q, vb, vv, bb, acc)


@jitable
def chord_rotation_force(lever, slopes, mass_per_length, rod_length, angle, omega, alpha, q, q_dot, acc, F):
    """The chord rotation's modal forces [N] into ``F`` given the final accelerations ``acc`` [m/s^2] (those
    :func:`chord_rotation` returns): ``F = x - c (b (v.acc) + v (b.acc))``, what it adds to ``m q_ddot``
    (its power closes the energy budget). Arguments as :func:`chord_rotation`."""
    sums = _chord_sums(lever, slopes, q, q_dot)
    c = mass_per_length * np.tan(angle) / rod_length
    va = ba = 0.0
    for n in range(q.shape[0]):
        va += slopes[n] * q[n] * acc[n]
        ba += lever[n] * acc[n]
    for n in range(q.shape[0]):
        F[n] = (_chord_load(n, lever, slopes, mass_per_length, rod_length, angle, omega, alpha, q, sums)
                - c * (lever[n] * va + slopes[n] * q[n] * ba))


@jitable
def _chord_solve(k, lever, slopes, q, vb, vv, bb, col):
    """``col <- (I + k (b v^T + v b^T))^-1 col`` (``v = D q``), in place (Sherman-Morrison-Woodbury)."""
    vr = br = 0.0
    for n in range(q.shape[0]):
        vr += slopes[n] * q[n] * col[n]
        br += lever[n] * col[n]
    s00, s01, s10, s11 = 1.0 + k * vb, k * vv, k * bb, 1.0 + k * vb
    det = s00 * s11 - s01 * s10
    z0 = (s11 * vr - s01 * br) / det
    z1 = (s00 * br - s10 * vr) / det
    for n in range(q.shape[0]):
        col[n] -= k * (lever[n] * z0 + slopes[n] * q[n] * z1)


@jitable
def chord_rotation_jacobian(lever, slopes, mass_per_length, rod_length, modal_mass, angle, omega, alpha, q, q_dot,
                            acc, Jq, Jv):
    """Turn ``Jq``, ``Jv`` (``d acc0/dq``, ``d acc0/dq_dot`` of the accelerations without the chord's rotation)
    into those of :func:`chord_rotation`'s, in place, given its final accelerations ``acc``:
    ``(I + k B)^-1 [J0 + dx/dy / m - k d(B acc)/dq]`` with ``B = b v^T + v b^T``, ``k = c / m``."""
    delta, delta_dot, vDv, bq, vb, vv, bb = _chord_sums(lever, slopes, q, q_dot)
    tau = np.tan(angle)
    sec2 = 1.0 + tau * tau
    tau_dot = omega * sec2
    tau_ddot = (alpha + 2.0 * omega * omega * tau) * sec2
    r = mass_per_length / rod_length / modal_mass
    k = mass_per_length * tau / rod_length / modal_mass
    w2 = omega * omega * tau
    N = q.shape[0]
    ba = 0.0
    for n in range(N):
        ba += lever[n] * acc[n]
    for m in range(N):
        for n in range(N):
            vn = slopes[n] * q[n]
            Jq[m, n] += (-r * lever[m] * (tau_ddot * vn + 2.0 * tau_dot * slopes[n] * q_dot[n])
                         + r * w2 * (lever[m] * vn + slopes[m] * q[m] * lever[n])
                         - k * lever[m] * slopes[n] * acc[n])
            Jv[m, n] += -r * lever[m] * 2.0 * (tau_dot * vn + tau * slopes[n] * q_dot[n])
        Jq[m, m] += slopes[m] * (r * w2 * bq - k * ba)
    _chord_solve_columns(k, lever, slopes, q, vb, vv, bb, Jq)
    _chord_solve_columns(k, lever, slopes, q, vb, vv, bb, Jv)


@jitable
def _chord_solve_columns(k, lever, slopes, q, vb, vv, bb, J):
    """:func:`_chord_solve` on every column of ``J``, in place."""
    N = q.shape[0]
    col = np.empty(N)
    for n in range(N):
        for m in range(N):
            col[m] = J[m, n]
        _chord_solve(k, lever, slopes, q, vb, vv, bb, col)
        for m in range(N):
            J[m, n] = col[m]

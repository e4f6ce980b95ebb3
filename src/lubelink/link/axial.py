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
second half of the slider's second-order work (the first is ``N_C``'s stiffness). Written once for a frame that
turns in space (:func:`frame_chord_rotation`: the spatial link, ``delta = int (u2'^2 + u3'^2) / 2``, the chord
turning about ``e2`` and ``e3`` with the guide's direction, :func:`chord_coefficients`); the planar functions are
its restriction to the ``u2`` block and the planar motion (:func:`planar_chord_coefficients`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .._jit import jitable
from ..beam import wavenumber
from .spatial import _cross, _dot, _lin, _lin3

__all__ = ["GeometricTable", "slope_moments", "slider_end_force", "axial_force_terms", "rigid_axial_force",
           "frame_axial_force", "axial_force", "geometric_stiffness", "geometric_load",
           "geometric_jacobian", "geometric_table", "chord_levers", "ChordCoefficients", "chord_coefficients",
           "planar_chord_coefficients", "frame_chord_rotation", "frame_chord_rotation_force",
           "frame_chord_rotation_jacobian", "chord_rotation", "chord_rotation_force", "chord_rotation_jacobian",
           "chord_mass"]


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


class ChordCoefficients(NamedTuple):
    """The coefficients of the chord's rotation for the two bending directions ``k = 2, 3`` (each a 2-tuple,
    :func:`chord_coefficients`): ``c`` [1/m] the chord's turn per unit shortening, ``accel`` [1/(m s^2)] and
    ``rate`` [1/(m s)] what ``delta`` and ``delta_dot`` add to the acceleration of ``sigma = c delta``, ``gyro``
    [1/(m s)] and ``frame`` [1/(m s^2)] the frame's terms of the deflection that the turn reads."""

    c: tuple
    accel: tuple
    rate: tuple
    gyro: tuple
    frame: tuple


@jitable
def chord_coefficients(d, w, al, rod_length):
    """The :class:`ChordCoefficients` of the link frame's motion [SI]: ``d`` [-] the slider's guide direction,
    ``w`` [rad/s], ``al`` [rad/s^2] the frame's angular velocity and acceleration, 3-tuples of link-frame components.

    C stays on its guide: the chord of the link shortened by ``delta`` turns by ``sigma = c delta`` (``c_k =
    -d_k / (d_1 L)``, the components of ``sigma`` across ``e1``, ``k = 2, 3``). The guide is fixed, so its
    components turn against the frame, ``d' = -w x d``, ``d'' = -al x d + w x (w x d)``, and those of ``c``
    follow by the quotient rule. The acceleration of ``sigma`` (the frame's ``2 w x sigma' + al x sigma + w x
    (w x sigma)`` with it) is ``accel delta + rate delta' + c delta''``, ``accel = c'' + 2 w x c' + al x c +
    w x (w x c)``, ``rate = 2 (c' + w x c)``; the frame's terms of the deflection ``U`` that ``c`` reads are
    ``c . (2 w x U' + al x U + w x (w x U)) = gyro . U' + frame . U``, ``gyro = 2 c x w``,
    ``frame = c x al + (w . c) w - |w|^2 c`` (docs/model.md §1.5).
    """
    dt = _cross(d, w)  # -w x d
    dtt = _lin(-1.0, _cross(al, d), 1.0, _cross(w, _cross(w, d)))
    c2, c2_t, c2_tt = _turn(d, dt, dtt, 1, rod_length)
    c3, c3_t, c3_tt = _turn(d, dt, dtt, 2, rod_length)
    cv, ctv, cttv = (0.0, c2, c3), (0.0, c2_t, c3_t), (0.0, c2_tt, c3_tt)
    wc = _cross(w, cv)
    accel = _lin3(1.0, cttv, 2.0, _cross(w, ctv), 1.0, _lin(1.0, _cross(al, cv), 1.0, _cross(w, wc)))
    rate = _lin(2.0, ctv, 2.0, wc)
    gyro = _cross(cv, w)
    frame = _lin3(1.0, _cross(cv, al), _dot(w, cv), w, -_dot(w, w), cv)
    return ChordCoefficients((c2, c3), (accel[1], accel[2]), (rate[1], rate[2]), (2.0 * gyro[1], 2.0 * gyro[2]),
                             (frame[1], frame[2]))


@jitable
def _turn(d, dt, dtt, k, rod_length):
    """``c_k = -d_k / (d_1 L)`` [1/m] and its first two rates (the quotient rule on ``d`` and its rates ``dt``, ``dtt``)."""
    f = d[k] / d[0]
    f_t = (dt[k] - f * dt[0]) / d[0]
    f_tt = (dtt[k] - 2.0 * f_t * dt[0] - f * dtt[0]) / d[0]
    return -f / rod_length, -f_t / rod_length, -f_tt / rod_length


@jitable
def planar_chord_coefficients(angle, omega, alpha, rod_length):
    """:func:`chord_coefficients` of the planar link: angle [rad] from its guide (+X), rate [rad/s], angular
    acceleration [rad/s^2]: ``d = (cos angle, -sin angle, 0)``, ``w = (0, 0, omega)``, ``al = (0, 0, alpha)``
    (``c_2 = tan(angle) / L``)."""
    return chord_coefficients((np.cos(angle), -np.sin(angle), 0.0), (0.0, 0.0, omega), (0.0, 0.0, alpha), rod_length)


@jitable
def _chord_sums(lever, slopes, coef, q, q_dot):
    """``(delta [m], delta_dot [m/s], q_dot.D q_dot [m/s^2], gyro.U' + frame.U [1/s^2] (the deflection's frame terms
    along c, per unit lever), u.v [m], v.v [1], u.u [m^2])`` of the ``K = q.size / N`` bending blocks ``q``, ``q_dot``
    (``K = 1``: ``u2``; ``K = 2``: ``u2`` then ``u3``); ``u_kn = c_k b_n``, ``v = D q``."""
    N = lever.shape[0]
    delta = delta_dot = vDv = H = uv = vv = uu = 0.0
    for k in range(q.shape[0] // N):
        bv = bb = 0.0
        for n in range(N):
            i = k * N + n
            v = slopes[n] * q[i]
            delta += 0.5 * v * q[i]
            delta_dot += v * q_dot[i]
            vDv += slopes[n] * q_dot[i] * q_dot[i]
            H += lever[n] * (coef.gyro[k] * q_dot[i] + coef.frame[k] * q[i])
            bv += lever[n] * v
            vv += v * v
            bb += lever[n] * lever[n]
        uv += coef.c[k] * bv
        uu += coef.c[k] * coef.c[k] * bb
    return delta, delta_dot, vDv, H, uv, vv, uu


@jitable(inline=True)
def _chord_weight(coef, k, sums):
    """``accel_k delta + rate_k delta' + c_k q'.D q'`` [m/s^2]: the acceleration of the chord's turn ``sigma_k`` per
    unit ``x`` without ``delta''`` (``sums`` of :func:`_chord_sums`)."""
    return coef.accel[k] * sums[0] + coef.rate[k] * sums[1] + coef.c[k] * sums[2]


@jitable(inline=True)
def _chord_load(lever_n, slope_n, q_kn, G, H, mass_per_length):
    """The chord's rotation's modal force on mode ``n`` of block ``k`` that does not hold the accelerations [N]
    (:func:`frame_chord_rotation`): ``x_kn = -rho A (b_n G_k + D_n q_kn H)``, ``G_k`` of :func:`_chord_weight`, ``H``
    the deflection's frame terms of :func:`_chord_sums`."""
    return -mass_per_length * (lever_n * G + slope_n * q_kn * H)


@jitable
def frame_chord_rotation(lever, slopes, mass_per_length, modal_mass, coef, q, q_dot, acc):
    """Correct the bending accelerations ``acc`` [m/s^2] (in place) for the rotation of the link's chord.

    ``q`` [m], ``q_dot`` [m/s], ``acc``: the ``K`` bending blocks (``u2``, then ``u3`` when ``K = 2``) of the sine
    modes, ``acc`` the accelerations with the chord on the rigid link's (all forces over the modal mass ``m``
    [kg]); ``coef`` the :class:`ChordCoefficients` of the frame's motion; ``lever``, ``slopes`` the
    :class:`GeometricTable`'s ``b`` [m^2], ``D`` [1/m]; ``rho A`` [kg/m]. The chord turns by
    ``sigma = c delta`` (``delta = sum D_n q_kn^2 / 2``), the link's points move across it by ``x sigma``, and the
    kinetic energy gains ``rho A (U' + w x U) . (sigma' + w x sigma)`` (``U_k = b . q_k``): Lagrange's equations
    add the cross accelerations ``rho A [B^T a(sigma) + v c . a(U)]``,

        (m I + rho A (u v^T + v u^T)) q_ddot = m acc + x,    u_kn = c_k b_n,  v = D q,

    ``x`` of :func:`_chord_load` (docs/model.md §1.5). The mass is the identity plus a rank-two term (one
    ``delta`` turns the chord about both axes): solved exactly (Sherman-Morrison-Woodbury).
    """
    sums = _chord_sums(lever, slopes, coef, q, q_dot)
    N = lever.shape[0]
    vr = ur = 0.0
    for k in range(q.shape[0] // N):
        G = _chord_weight(coef, k, sums)
        br = 0.0
        for n in range(N):
            i = k * N + n
            acc[i] += _chord_load(lever[n], slopes[n], q[i], G, sums[3], mass_per_length) / modal_mass
            vr += slopes[n] * q[i] * acc[i]
            br += lever[n] * acc[i]
        ur += coef.c[k] * br
    _chord_apply(mass_per_length / modal_mass, lever, slopes, coef, q, sums[4], sums[5], sums[6], vr, ur, acc)


@jitable
def frame_chord_rotation_force(lever, slopes, mass_per_length, coef, q, q_dot, acc, F):
    """The chord's rotation's modal forces [N] into ``F`` given the final accelerations ``acc`` [m/s^2] (those
    :func:`frame_chord_rotation` returns): ``F = x - rho A (u (v.acc) + v (u.acc))``, what it adds to ``m q_ddot``
    (its power closes the energy budget). Arguments as :func:`frame_chord_rotation`."""
    sums = _chord_sums(lever, slopes, coef, q, q_dot)
    va, ua = _chord_products(lever, slopes, coef, q, acc)
    N = lever.shape[0]
    for k in range(q.shape[0] // N):
        G = _chord_weight(coef, k, sums)
        for n in range(N):
            i = k * N + n
            F[i] = (_chord_load(lever[n], slopes[n], q[i], G, sums[3], mass_per_length)
                    - mass_per_length * (coef.c[k] * lever[n] * va + slopes[n] * q[i] * ua))


@jitable
def _chord_products(lever, slopes, coef, q, col):
    """``(v . col, u . col)`` (``v = D q``, ``u_kn = c_k b_n``)."""
    N = lever.shape[0]
    vr = ur = 0.0
    for k in range(q.shape[0] // N):
        br = 0.0
        for n in range(N):
            vr += slopes[n] * q[k * N + n] * col[k * N + n]
            br += lever[n] * col[k * N + n]
        ur += coef.c[k] * br
    return vr, ur


@jitable
def _chord_apply(k, lever, slopes, coef, q, uv, vv, uu, vr, ur, col):
    """``col <- (I + k (u v^T + v u^T))^-1 col`` (``v = D q``, ``u_kn = c_k b_n``) in place, given ``vr = v . col``,
    ``ur = u . col`` (Sherman-Morrison-Woodbury)."""
    s00, s01, s10, s11 = 1.0 + k * uv, k * vv, k * uu, 1.0 + k * uv
    det = s00 * s11 - s01 * s10
    z0 = (s11 * vr - s01 * ur) / det
    z1 = (s00 * ur - s10 * vr) / det
    N = lever.shape[0]
    for b in range(q.shape[0] // N):
        u = k * coef.c[b] * z0
        for n in range(N):
            col[b * N + n] -= u * lever[n] + k * slopes[n] * q[b * N + n] * z1


@jitable
def frame_chord_rotation_jacobian(lever, slopes, mass_per_length, modal_mass, coef, q, q_dot, acc, Jq, Jv, rows):
    """Turn the Jacobian of the accelerations without the chord's rotation into that of
    :func:`frame_chord_rotation`'s, in place, given its final accelerations ``acc``: ``Jq``, ``Jv`` the blocks
    ``d acc/dq``, ``d acc/dq_dot`` of the bending coordinates among themselves (``K N x K N``), ``rows`` all the
    columns of their rows (``Jq`` and ``Jv`` views into it): ``(I + k B)^-1 [J0 + dx/dy / m - k d(B acc)/dq]``
    with ``B = u v^T + v u^T``, ``k = rho A / m``."""
    delta, delta_dot, vDv, H, uv, vv, uu = _chord_sums(lever, slopes, coef, q, q_dot)
    r = mass_per_length / modal_mass
    ua = _chord_products(lever, slopes, coef, q, acc)[1]
    N = lever.shape[0]
    M = q.shape[0]
    for i in range(M):
        j, m = i // N, i % N
        Dq = slopes[m] * q[i]
        for l in range(M):
            k, n = l // N, l % N
            vn = slopes[n] * q[l]
            Jq[i, l] -= r * (lever[m] * (coef.accel[j] * vn + coef.rate[j] * slopes[n] * q_dot[l])
                             + Dq * coef.frame[k] * lever[n] + coef.c[j] * lever[m] * slopes[n] * acc[l])
            Jv[i, l] -= r * (lever[m] * (coef.rate[j] * vn + 2.0 * coef.c[j] * slopes[n] * q_dot[l])
                             + Dq * coef.gyro[k] * lever[n])
        Jq[i, i] -= r * slopes[m] * (H + ua)
    col = np.empty(M)
    for c in range(rows.shape[1]):
        for i in range(M):
            col[i] = rows[i, c]
        vr, ur = _chord_products(lever, slopes, coef, q, col)
        _chord_apply(r, lever, slopes, coef, q, uv, vv, uu, vr, ur, col)
        for i in range(M):
            rows[i, c] = col[i]


@jitable
def chord_rotation(lever, slopes, mass_per_length, rod_length, modal_mass, angle, omega, alpha, q, q_dot, acc):
    """:func:`frame_chord_rotation` of the planar link (its ``u2`` block; :func:`planar_chord_coefficients` of its
    ``angle`` [rad] from the guide, rate ``omega`` [rad/s], ``alpha`` [rad/s^2], ``L`` [m]):

        (m I + c (b v^T + v b^T)) q_ddot = m acc - (rho A / L) b (tau'' delta + 2 tau' delta' + tau q'.D q')
                                           + (rho A omega^2 tau / L) (b delta + v b.q),    c = rho A tau / L,

    ``tau = tan(angle)``, ``tau' = omega sec^2``, ``tau'' = (alpha + 2 omega^2 tau) sec^2``."""
    frame_chord_rotation(lever, slopes, mass_per_length, modal_mass,
                         planar_chord_coefficients(angle, omega, alpha, rod_length), q, q_dot, acc)


@jitable
def chord_rotation_force(lever, slopes, mass_per_length, rod_length, angle, omega, alpha, q, q_dot, acc, F):
    """:func:`frame_chord_rotation_force` of the planar link (arguments as :func:`chord_rotation`)."""
    frame_chord_rotation_force(lever, slopes, mass_per_length, planar_chord_coefficients(angle, omega, alpha,
                                                                                         rod_length), q, q_dot, acc, F)


@jitable
def chord_rotation_jacobian(lever, slopes, mass_per_length, rod_length, modal_mass, angle, omega, alpha, q, q_dot,
                            acc, Jq, Jv, rows):
    """:func:`frame_chord_rotation_jacobian` of the planar link (arguments as :func:`chord_rotation`)."""
    frame_chord_rotation_jacobian(lever, slopes, mass_per_length, modal_mass,
                                  planar_chord_coefficients(angle, omega, alpha, rod_length), q, q_dot, acc, Jq, Jv,
                                  rows)


def chord_mass(q, guide, rod_length, mass_per_length):
    """The generalised mass ``M(q)`` [kg] that :func:`frame_chord_rotation` solves with, ``(K N, K N)``: its
    columns from unit accelerations at rest (``q_dot = 0``, no rotation: no other term).

    ``q`` [m] shape ``(N,)`` (the planar link's ``u2``) or ``(K, N)`` (``K = 2``: ``u2``, ``u3``), ``guide`` [-] the
    slider's guide direction in the link frame (3 components; the planar link at ``angle`` from it:
    ``(cos angle, -sin angle, 0)``), ``L`` [m], ``rho A`` [kg/m] of the uniform link."""
    q = np.atleast_2d(np.asarray(q, dtype=float))
    K, N = q.shape
    lever, slopes = chord_levers(N, rod_length)
    m = mass_per_length * rod_length / 2
    coef = chord_coefficients(tuple(float(g) for g in guide), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), rod_length)
    flat = q.ravel()
    Minv = np.empty((K * N, K * N))
    for j in range(K * N):
        acc = np.eye(K * N)[j].copy()
        frame_chord_rotation(lever, slopes, mass_per_length, m, coef, flat, np.zeros(K * N), acc)
        Minv[:, j] = acc
    return m * np.linalg.inv(Minv)

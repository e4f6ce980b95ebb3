"""The rotation of the bent link's chord under the slider and the frame terms, against independent references
(lubelink.link.axial.chord_rotation, docs/model.md §1.5).

References: the kinetic energy of the link from its exact geometry (the chord's angle solved from the slider's
constraint, the points' positions differentiated numerically, integrated by Gauss quadrature); the mode-1
frequency shifts of the paper's rod measured in Exudyn 1.13.6 (8 ANCF cable elements, ``h = 1e-4 s``, shifts
against the unloaded rod's; ``benchmarks/exudyn_frequency.py``, whose printed figures these are; they scatter by
0.3-0.5 1/s^2 with the way C is guided and carry the static deflection's second-order share, +-0.7 1/s^2 at
``g = 30``: the tolerance is 1.5 1/s^2): the rod pinned at a fixed O with C on a guide,
inclined at ``psi`` under gravity, and spinning about O.
"""

from __future__ import annotations

import numpy as np
import pytest
from numpy.polynomial.legendre import leggauss
from scipy.linalg import eigh

from lubelink.link import axial

# the paper's rod, written out (a changed default cannot move the reference)
E, RHO, B, HH, L = 207e9, 7650.0, 0.01, 0.01, 1.0
RHO_A, EI = RHO * B * HH, E * B * HH**3 / 12.0
M_MODAL = RHO_A * L / 2


def model_mass(q, angle, modes):
    """The generalised mass ``M(q)`` [kg] the model's :func:`~lubelink.link.axial.chord_rotation` solves with
    (:func:`~lubelink.link.axial.chord_mass`: from unit accelerations at rest)."""
    assert q.size == modes
    return axial.chord_mass(q, (np.cos(angle), -np.sin(angle), 0.0), L, RHO_A)


def geometric_mass(q, angle, points=40):
    """``M(q) = int rho A (dr/dq)^T (dr/dq) dx`` from the positions ``r(x; q)`` of the link's points: O fixed, C on
    the horizontal line through its rest position, the deflection ``w = sum q_n sin(n pi x / L)`` from the chord,
    the points drawn in by ``int_0^x w'^2 / 2``, the chord's angle solved exactly from C's constraint."""
    xg, wg = leggauss(points)
    x, wts = 0.5 * L * (xg + 1.0), 0.5 * L * wg
    n = np.arange(1, q.size + 1)
    beta = n * np.pi / L

    def positions(qq):
        def shortening(upto):  # int_0^upto w'^2 / 2, by its own Gauss rule
            s, ws = 0.5 * upto * (xg + 1.0), 0.5 * upto * wg
            slope = np.cos(np.outer(s, beta)) @ (beta * qq)
            return np.sum(ws * slope**2) / 2
        u1 = -np.array([shortening(xi) for xi in x])
        chord = L - shortening(L)
        psi = np.arcsin(L * np.sin(angle) / chord)  # C stays on its guide: chord sin(psi) = L sin(angle)
        e1, e2 = np.array([np.cos(psi), np.sin(psi)]), np.array([-np.sin(psi), np.cos(psi)])
        w = np.sin(np.outer(x, beta)) @ qq
        return (x + u1)[:, None] * e1 + w[:, None] * e2

    h = 1e-7
    J = np.stack([(positions(q + h * e) - positions(q - h * e)) / (2 * h) for e in np.eye(q.size)], axis=-1)
    return RHO_A * np.einsum("k,kdi,kdj->ij", wts, J, J)


@pytest.mark.parametrize("angle", [0.3, -0.12])
def test_the_mass_is_that_of_the_geometry(angle):
    """``M(q) - m I`` of the model against the exact geometry's, at a deflection of about 2 mm in three modes.
    The geometry's mass less that of the same link with its chord level (``angle = 0``: the chord does not turn;
    what remains there, the points' axial motion, is second order in ``q``) is first order in ``q``; the two agree
    to its second-order terms (relative ~q/L)."""
    q = np.array([2e-3, -4e-4, 3e-4])
    extra_model = model_mass(q, angle, 3) - M_MODAL * np.eye(3)
    extra_geometry = geometric_mass(q, angle) - geometric_mass(q, 0.0)
    scale = np.abs(extra_geometry).max()
    assert scale > 1e-3 * M_MODAL * abs(np.tan(angle)) / 0.3  # the coupling is there, and first order in q
    np.testing.assert_allclose(extra_model, extra_geometry, rtol=0, atol=1e-2 * scale)


def inclined_shift(psi, g, modes=10, rotation=True):
    """The mode-1 ``omega^2`` shift [1/s^2] of the rod pinned at a fixed O, inclined at ``psi`` [rad], C on a
    horizontal guide, under gravity ``(0, -g)``: about its static deflection, with the slider's axial force and
    the chord's rotation (``rotation``)."""
    n = np.arange(1, modes + 1)
    beta = n * np.pi / L
    terms = axial.rigid_axial_force(0.0, 0.0, 0.0, 0.0, psi, 0.0, L, (0.0, -g), RHO_A, L)
    K = np.diag(M_MODAL * EI / RHO_A * beta**4) + axial.geometric_stiffness(axial.slope_moments(modes, L), terms)
    load = RHO_A * (-g * np.cos(psi)) * (1 - np.cos(n * np.pi)) / beta  # int rho A g_j sin(beta_n x) dx
    q_static = np.linalg.solve(K, load)
    M = model_mass(q_static, psi, modes) if rotation else M_MODAL * np.eye(modes)
    return eigh(K, M, eigvals_only=True)[0] - EI / RHO_A * beta[0]**4


@pytest.mark.parametrize("psi, g, exudyn", [(0.4, 30.0, 92.85), (0.4, 15.0, 45.93), (0.2, 30.0, 47.26),
                                            (-0.4, 30.0, -94.26)])
def test_an_inclined_link_on_the_slider_against_exudyn(psi, g, exudyn):
    """The inclined rod with C on a horizontal guide: the mode-1 shift against Exudyn's (the same rod with the
    guide along its chord, where nothing turns the chord, matches the axial force alone to 0.3). Without the
    chord's rotation the model finds no shift at all."""
    assert abs(inclined_shift(psi, g) - exudyn) < 1.5
    assert abs(inclined_shift(psi, g, rotation=False)) < 0.1


@pytest.mark.parametrize("omega, exudyn", [(5.0, 50.64), (10.0, 203.34), (20.0, 812.43)])
def test_a_link_spinning_about_a_fixed_end_against_exudyn(omega, exudyn):
    """The rod pinned at a fixed O and spun about it at ``omega``, C sliding freely on an arm along the chord:
    the centrifugal tension stiffens and the frame softens, ``omega_1^2 - omega_10^2 = omega^2 (c_1 - 1)``,
    ``c_1 = pi^2 / 3 - 1 / 4`` for the one-mode Galerkin model; 10 modes against Exudyn's (without the frame's
    softening the model would be 25, 100, 400 1/s^2 higher)."""
    modes = 10
    beta = np.arange(1, modes + 1) * np.pi / L
    terms = axial.axial_force_terms(0.0, omega, 0.0, RHO_A, L)
    K = (np.diag(M_MODAL * (EI / RHO_A * beta**4 - omega**2))
         + axial.geometric_stiffness(axial.slope_moments(modes, L), terms))
    shift = eigh(K, M_MODAL * np.eye(modes), eigvals_only=True)[0] - EI / RHO_A * beta[0]**4
    assert abs(shift - exudyn) < 1.5
    # the one-mode closed form, which the coupling of the modes lowers by (omega^2 / omega_1)^2-small terms
    assert abs(shift - omega**2 * (np.pi**2 / 3 - 1.25)) < 4e-3 * shift


def test_the_moving_chord_keeps_lagranges_energy_balance():
    """With the link's angle changing in time, the equations of :func:`~lubelink.link.axial.chord_rotation` are
    Lagrange's of ``T = m |q_dot|^2 / 2 + rho A (b.q_dot) dpsi_dot + m omega^2 |q|^2 / 2
    + rho A omega^2 (b.q) dpsi``, ``dpsi = tan(angle) delta / L`` (the cross terms of the points' velocity
    across the chord and of the frame's rotation, first order in ``dpsi``), with ``V = m sum W_n^2 q_n^2 / 2``:
    then ``h = q_dot . dL/dq_dot - L`` changes by ``-int dL/dt dt`` (``dL/dt`` at fixed ``q``, ``q_dot``, by
    differences), which holds only if every term of the equations has the right coefficient. A large deflection
    (5 cm) and a link swinging by 0.3 rad make the chord's terms a few per cent of the energy."""
    from scipy.integrate import solve_ivp

    modes = 3
    W = np.array([10.0, 40.0, 90.0])  # soft modes: a cheap integration, the chord's terms unchanged
    b, D = axial.chord_levers(modes, L)

    def angle(t):  # the link's angle and its two derivatives
        return 0.1 + 0.3 * np.sin(2.0 * t), 0.6 * np.cos(2.0 * t), -1.2 * np.sin(2.0 * t)

    def lagrangian(t, q, v):
        a, w, _ = angle(t)
        tau, sec2 = np.tan(a), 1.0 / np.cos(a) ** 2
        delta, delta_dot = 0.5 * q @ (D * q), (D * q) @ v
        dpsi, dpsi_dot = tau * delta / L, (w * sec2 * delta + tau * delta_dot) / L
        T = (0.5 * M_MODAL * v @ v + RHO_A * (b @ v) * dpsi_dot + 0.5 * M_MODAL * w * w * q @ q
             + RHO_A * w * w * (b @ q) * dpsi)
        return T - 0.5 * M_MODAL * (W * W) @ (q * q)

    def h(t, q, v):  # q_dot . dL/dq_dot - L, dL/dq_dot by differences (L is quadratic in q_dot: exact)
        e = 1e-3
        p = np.array([(lagrangian(t, q, v + e * u) - lagrangian(t, q, v - e * u)) / (2 * e) for u in np.eye(modes)])
        return v @ p - lagrangian(t, q, v)

    def f(t, y):
        q, v = y[:modes], y[modes:2 * modes]
        a, w, al = angle(t)
        acc = -(W * W - w * w) * q
        axial.chord_rotation(b, D, RHO_A, L, M_MODAL, a, w, al, q, v, acc)
        return np.r_[v, acc, -(lagrangian(t + 1e-5, q, v) - lagrangian(t - 1e-5, q, v)) / 2e-5]

    y0 = np.r_[0.05, -0.01, 0.004, 0.0, 0.3, -0.2, 0.0]
    s = solve_ivp(f, (0.0, 3.0), y0, method="DOP853", rtol=1e-11, atol=1e-13, dense_output=True)
    h0 = h(0.0, y0[:modes], y0[modes:2 * modes])
    for t in (1.0, 2.0, 3.0):
        y = s.sol(t)
        balance = h(t, y[:modes], y[modes:2 * modes]) - h0 - y[-1]
        assert abs(balance) < 1e-7 * abs(h0), (t, balance / h0)
    # the chord's terms are not small here: without them the same balance misses by about a per cent
    assert abs(y[-1]) > 1e-3 * abs(h0)


def rodrigues(a, b):
    """The rotation that takes the unit vector ``a`` to the unit vector ``b`` about ``a x b`` (no spin about them)."""
    k = np.cross(a, b)
    s, c = np.linalg.norm(k), a @ b
    if s == 0.0:
        return np.eye(3)
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]]) / s
    return np.eye(3) + s * K + (1.0 - c) * K @ K


def spatial_geometric_mass(q, guide, points=40):
    """``M(q)`` ``(2 N, 2 N)`` of the link bent in both directions, ``q = (q2, q3)``, from the positions of its points:
    O fixed, the rigid chord along ``X``, C on the line through its rest position along ``guide``; the deflections
    ``w2``, ``w3`` from the chord, the points drawn in by ``int_0^x (w2'^2 + w3'^2) / 2``, the chord's direction
    solved exactly from C's constraint (``|L e_X + s guide| = L - shortening``), its frame turned without spin."""
    xg, wg = leggauss(points)
    x, wts = 0.5 * L * (xg + 1.0), 0.5 * L * wg
    N = q.shape[1]
    beta = np.arange(1, N + 1) * np.pi / L
    d = np.asarray(guide, dtype=float) / np.linalg.norm(guide)
    eX = np.array([1.0, 0.0, 0.0])

    def positions(qq):
        def shortening(upto):
            s, ws = 0.5 * upto * (xg + 1.0), 0.5 * upto * wg
            C = np.cos(np.outer(s, beta))
            return np.sum(ws * ((C @ (beta * qq[0])) ** 2 + (C @ (beta * qq[1])) ** 2)) / 2
        u1 = -np.array([shortening(xi) for xi in x])
        chord = L - shortening(L)
        s = -L * d[0] + np.sqrt((L * d[0]) ** 2 - L**2 + chord**2)  # the root near 0
        e1 = (L * eX + s * d) / chord
        R = rodrigues(eX, e1)
        S = np.sin(np.outer(x, beta))
        return (x + u1)[:, None] * e1 + (S @ qq[0])[:, None] * R[:, 1] + (S @ qq[1])[:, None] * R[:, 2]

    h = 1e-7
    J = np.stack([(positions(q + h * e.reshape(q.shape)) - positions(q - h * e.reshape(q.shape))) / (2 * h)
                  for e in np.eye(q.size)], axis=-1)
    return RHO_A * np.einsum("k,kdi,kdj->ij", wts, J, J)


@pytest.mark.parametrize("guide", [(0.95, -0.2, 0.25), (0.9, 0.15, -0.4)])
def test_the_spatial_mass_is_that_of_the_geometry(guide):
    """The link bent in both directions with a guide out of its plane: the chord turns about ``e2`` and ``e3`` with
    the one shortening. ``M(q) - m I`` of :func:`~lubelink.link.axial.chord_mass` against the exact geometry's less
    that of a guide along the chord (which turns nothing), to its second-order terms."""
    q = np.array([[2e-3, -4e-4, 3e-4], [-1.5e-3, 5e-4, 2e-4]])
    d = np.asarray(guide) / np.linalg.norm(guide)
    extra_model = axial.chord_mass(q, d, L, RHO_A) - M_MODAL * np.eye(6)
    extra_geometry = spatial_geometric_mass(q, d) - spatial_geometric_mass(q, (1.0, 0.0, 0.0))
    scale = np.abs(extra_geometry).max()
    assert scale > 1e-3 * M_MODAL  # the coupling is there
    assert np.abs(extra_geometry[:3, 3:]).max() > 0.1 * scale  # and couples the two directions
    np.testing.assert_allclose(extra_model, extra_geometry, rtol=0, atol=1e-2 * scale)


def frame_motion(t):
    """A link frame turning in space, ``R = Rz(a) Ry(b) Rx(c)`` (a spin ``c`` about the link too): its angular
    velocity in link-frame components ``w = c' e1 + Rx^T (b' e2 + a' Ry^T e3)``, complex-safe (the derivatives that
    follow are complex steps)."""
    a, a_t = 0.2 + 0.3 * np.sin(2.0 * t), 0.6 * np.cos(2.0 * t)
    b, b_t = -0.1 + 0.25 * np.sin(1.3 * t + 0.4), 0.325 * np.cos(1.3 * t + 0.4)
    c, c_t = 0.4 * np.sin(1.7 * t), 0.68 * np.cos(1.7 * t)

    def rz(u):
        return np.array([[np.cos(u), -np.sin(u), 0 * u], [np.sin(u), np.cos(u), 0 * u], [0 * u, 0 * u, 1 + 0 * u]])

    def ry(u):
        return np.array([[np.cos(u), 0 * u, np.sin(u)], [0 * u, 1 + 0 * u, 0 * u], [-np.sin(u), 0 * u, np.cos(u)]])

    def rx(u):
        return np.array([[1 + 0 * u, 0 * u, 0 * u], [0 * u, np.cos(u), -np.sin(u)], [0 * u, np.sin(u), np.cos(u)]])

    R = rz(a) @ ry(b) @ rx(c)
    w = c_t * np.array([1.0, 0.0, 0.0]) + rx(c).T @ (b_t * np.array([0.0, 1.0, 0.0]) + a_t * ry(b).T[:, 2])
    return R, w


GUIDE = np.array([1.0, 0.3, -0.4]) / np.linalg.norm([1.0, 0.3, -0.4])  # fixed-frame components


def frame_at(t):
    """``(d, w, alpha)`` in link-frame components at real ``t``: the guide, ``w``, and ``alpha = w'`` by a complex step."""
    R, w = frame_motion(t)
    return R.T @ GUIDE, w, frame_motion(t + 1e-30j)[1].imag / 1e-30


def test_the_chord_in_a_frame_turning_in_space_keeps_lagranges_energy_balance():
    """The bent link in a frame turning about all three axes, C on a fixed guide out of the link's plane: the
    equations of :func:`~lubelink.link.axial.frame_chord_rotation` on top of the frame's terms of the deflection are
    Lagrange's of ``T = m/2 sum_n |Q_n' + w x Q_n|^2 + rho A (U' + w x U) . (sigma' + w x sigma)``
    (``Q_n = (0, q2_n, q3_n)``, ``U = (0, b.q2, b.q3)``, ``sigma = (0, c2, c3) delta``, ``c_k = -d_k / (d_1 L)`` from
    the guide's link-frame components ``d = R^T d_fixed``, its rate by a complex step, not the code's quotient
    rule) with ``V = m sum W^2 q^2 / 2``: ``h = q_dot . dL/dq_dot - L`` changes by ``-int dL/dt dt``. A large
    deflection (5 cm) makes the chord's terms a per cent of the energy; without them the balance misses by 10 times
    the tolerance and more."""
    from scipy.integrate import solve_ivp

    from lubelink.link.spatial import frame_terms

    N = 3
    W = np.array([10.0, 40.0, 90.0, 12.0, 45.0, 95.0])
    b, D = axial.chord_levers(N, L)

    def lagrangian(t, q, v):
        def c_of(tt):  # c in link-frame components
            d = frame_motion(tt)[0].T @ GUIDE
            return np.array([0.0 * d[0], -d[1] / (d[0] * L), -d[2] / (d[0] * L)])

        w = frame_motion(t)[1]
        c, c_t = c_of(t), c_of(t + 1e-30j).imag / 1e-30
        Q, V = np.zeros((N, 3)), np.zeros((N, 3))
        Q[:, 1], Q[:, 2], V[:, 1], V[:, 2] = q[:N], q[N:], v[:N], v[N:]
        T = 0.5 * M_MODAL * np.sum((V + np.cross(w, Q)) ** 2)
        delta, delta_dot = 0.5 * np.sum(D * (q[:N] ** 2 + q[N:] ** 2)), np.sum(D * (q[:N] * v[:N] + q[N:] * v[N:]))
        U, U_t = np.array([0.0, b @ q[:N], b @ q[N:]]), np.array([0.0, b @ v[:N], b @ v[N:]])
        sigma, sigma_t = c * delta, c_t * delta + c * delta_dot
        T = T + RHO_A * (U_t + np.cross(w, U)) @ (sigma_t + np.cross(w, sigma))
        return T - 0.5 * M_MODAL * (W * W) @ (q * q)

    def dldt(t, q, v):  # dL/dt at fixed q, q_dot by central differences (the complex step is taken inside)
        e = 1e-5
        return (lagrangian(t + e, q, v) - lagrangian(t - e, q, v)) / (2 * e)

    def h(t, q, v):
        e = 1e-3
        p = np.array([(lagrangian(t, q, v + e * u) - lagrangian(t, q, v - e * u)) / (2 * e) for u in np.eye(2 * N)])
        return v @ p - lagrangian(t, q, v)

    def f(t, y, chord=True):
        q, v = y[:2 * N], y[2 * N:4 * N]
        d, w, al = frame_at(t)
        acc = -(W * W) * q
        for n in range(N):
            fr = frame_terms(w, al, (0.0, q[n], q[N + n]), (0.0, v[n], v[N + n]))
            acc[n] -= fr[1]
            acc[N + n] -= fr[2]
        if chord:
            axial.frame_chord_rotation(b, D, RHO_A, M_MODAL, axial.chord_coefficients(tuple(d), tuple(w), tuple(al), L),
                                       q, v, acc)
        return np.r_[v, acc, -dldt(t, q, v)]

    y0 = np.r_[0.05, -0.01, 0.004, -0.03, 0.008, 0.002, 0.0, 0.3, -0.2, 0.1, -0.25, 0.15, 0.0]
    h0 = h(0.0, y0[:2 * N], y0[2 * N:4 * N])
    misses = []
    for chord in (True, False):
        s = solve_ivp(f, (0.0, 2.0), y0, method="DOP853", rtol=1e-11, atol=1e-13, args=(chord,))
        y = s.y[:, -1]
        misses.append(abs(h(2.0, y[:2 * N], y[2 * N:4 * N]) - h0 - y[-1]) / abs(h0))
    assert misses[0] < 1e-7, misses
    assert misses[1] > 10 * 1e-7, misses


def test_the_chord_rotations_jacobian_is_its_differences():
    """:func:`~lubelink.link.axial.frame_chord_rotation_jacobian` against central differences of
    :func:`~lubelink.link.axial.frame_chord_rotation` applied to random linear accelerations of the bending blocks
    and of an extra (axial) block, in a frame turning in space, at a large deflection."""
    N = 3
    K = 2 * N
    rng = np.random.default_rng(5)
    A = rng.standard_normal((K, 3 * N + 3 * N)) * 50.0  # d acc0 / d(q1, q2, q3, and their rates)
    b, D = axial.chord_levers(N, L)
    d, w, al = frame_at(0.7)
    coef = axial.chord_coefficients(tuple(d), tuple(w), tuple(al), L)

    def acc(y):
        a = A @ y + 3.0
        axial.frame_chord_rotation(b, D, RHO_A, M_MODAL, coef, y[N:3 * N], y[4 * N:], a)
        return a

    y = np.r_[rng.standard_normal(N) * 1e-3, rng.standard_normal(K) * 0.03, rng.standard_normal(3 * N) * 0.5]
    rows = A.copy()
    axial.frame_chord_rotation_jacobian(b, D, RHO_A, M_MODAL, coef, y[N:3 * N], y[4 * N:], acc(y),
                                        rows[:, N:3 * N], rows[:, 4 * N:], rows)
    fd = np.column_stack([(acc(y + 1e-6 * e) - acc(y - 1e-6 * e)) / 2e-6 for e in np.eye(y.size)])
    assert np.abs(fd - A).max() > 1e-2 * np.abs(A).max()  # the chord's terms are there
    np.testing.assert_allclose(rows, fd, rtol=0, atol=1e-7 * np.abs(fd).max())

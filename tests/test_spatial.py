"""The spatial link's modal equations (lubelink.link.spatial) against closed forms and the planar model.

References: the gyroscopic whirl of a link spinning about its own axis (characteristic quartic),
the fixed-fixed and fixed-free bars (finite differences, closed forms), the quasi-static axial
stretch of a spinning link (closed forms of ``E u1'' + rho W^2 u1 = rho (a1 - W^2 x)`` with either end
condition at ``L``), the Galerkin projection of the frame's accelerations between the free-end axial
modes and the bending sines (quadrature, written here), and the planar model (lubelink.beam) for a
planar motion.
"""

import numpy as np
import pytest

from lubelink import beam

from lubelink.link import spatial

E, RHO, L = 207e9, 7650.0, 1.0


def frequencies(N, b=0.01, h=0.01, end="fixed"):
    A = b * h
    return spatial.frequencies(N, L, E, RHO, A, b * h**3 / 12, h * b**3 / 12, end), RHO * A * L / 2


def axial_basis(N, end, b=0.01, h=0.01):
    """The :class:`~lubelink.link.spatial.AxialBasis` of the end condition (None: fixed)."""
    return None if end == "fixed" else spatial.free_axial_basis(N, L, RHO * b * h)


def jacobian(N, W, w, al, a_O=(0.0, 0.0, 0.0), zeta=0.0, m=1.0, axial=None):
    """``(J, f0)``: the right-hand side is ``J y + f0`` (it is linear in the state)."""
    n = 6 * N

    def f(y):
        out = np.empty(n)
        spatial.accelerations(y, W, zeta, np.array(a_O, float), np.array(w, float), np.array(al, float),
                              np.zeros(3 * N), m, L, out, axial)
        return out

    f0 = f(np.zeros(n))
    return np.column_stack([f(e) - f0 for e in np.eye(n)]), f0


def test_planar_motion_reduces_to_the_planar_model():
    """For ``w = (0, 0, omega)``: u3 is not forced, and the u2 equation is the planar model's plus
    the axial-bending terms ``-(2 omega q1_t + alpha q1)``."""
    N = 4
    W, m = frequencies(N)
    rng = np.random.default_rng(0)
    omega, alpha, A1, A2 = 3.1, -40.0, 12.0, -55.0
    y = rng.normal(size=6 * N)
    y[2 * N:3 * N] = 0.0
    y[5 * N:] = 0.0
    F = rng.normal(size=3 * N)
    F[2 * N:] = 0.0
    out = np.empty(6 * N)
    spatial.accelerations(y, W, 0.02, np.array([A1, A2, 0.0]), np.array([0.0, 0.0, omega]),
                          np.array([0.0, 0.0, alpha]), F, m, L, out)
    n = np.arange(1, N + 1)
    q1, q2, v1, v2 = y[:N], y[N:2 * N], y[3 * N:4 * N], y[4 * N:5 * N]
    planar = beam.modal_acceleration(q2, v2, W[N:2 * N], 0.02, omega,
                                     beam.rigid_load(A2, alpha, n, L) + F[N:2 * N] / m)
    assert np.allclose(out[4 * N:5 * N], planar - 2 * omega * v1 - alpha * q1, rtol=1e-13, atol=1e-9)
    assert np.all(out[5 * N:] == 0.0) and np.all(out[2 * N:3 * N] == 0.0)
    # axial: the bar softened by the spin, driven by A1 - omega^2 x, coupled by 2 omega q2_t + alpha q2
    axial = (-(W[:N] ** 2 - omega**2) * q1 - 2 * 0.02 * W[:N] * v1 + beam.rigid_load(A1, -omega**2, n, L)
             + F[:N] / m + 2 * omega * v2 + alpha * q2)
    assert np.allclose(out[3 * N:4 * N], axial, rtol=1e-13, atol=1e-9)


@pytest.mark.parametrize("b,h", [(0.01, 0.01), (0.01, 0.014)])
def test_spinning_link_whirl_against_the_gyroscopic_quartic(b, h):
    """Spin ``Omega`` about ``e1``: per mode ``x'' - 2 Omega y' + (a - Omega^2) x = 0``,
    ``y'' + 2 Omega x' + (b - Omega^2) y = 0``, characteristic
    ``s^4 + (a + b + 2 Omega^2) s^2 + (a - Omega^2)(b - Omega^2) = 0``; symmetric: ``|s| = w_n +- Omega``."""
    N = 2
    W, _ = frequencies(N, b, h)
    for Omega in (0.3 * W[N], 1.7 * W[N], 0.5 * (W[N] + W[2 * N])):
        J, _ = jacobian(N, W, (Omega, 0.0, 0.0), (0.0, 0.0, 0.0))
        s = np.linalg.eigvals(J)
        for n in range(N):
            a, c = W[N + n] ** 2, W[2 * N + n] ** 2
            roots = np.roots([1, 0, a + c + 2 * Omega**2, 0, (a - Omega**2) * (c - Omega**2)])
            for r in roots:
                assert np.min(np.abs(s - r)) < 1e-7 * max(abs(r), Omega)  # (a double zero at Omega = w_n)
            if b == h:
                assert np.allclose(np.sort(np.abs(roots.imag)), np.sort([abs(W[N + n] - Omega)] * 2
                                                                         + [W[N + n] + Omega] * 2), rtol=1e-9)
        unstable = any(min(W[N + n], W[2 * N + n]) < Omega < max(W[N + n], W[2 * N + n]) for n in range(N))
        assert (np.max(s.real) > 1e-6 * Omega) == unstable


def test_asymmetric_section_unstable_between_the_bending_frequencies():
    N = 1
    W, _ = frequencies(N, 0.01, 0.012)
    lo, hi = sorted((W[1], W[2]))
    growth = []
    for Omega in np.linspace(0.8 * lo, 1.2 * hi, 41):
        s = np.linalg.eigvals(jacobian(N, W, (Omega, 0.0, 0.0), (0, 0, 0))[0])
        growth.append((Omega, np.max(s.real)))
    for Omega, g in growth:
        inside = lo * (1 + 1e-9) < Omega < hi * (1 - 1e-9)
        assert (g > 1e-3) == inside, (Omega, g)


def _fd_bar(N, n, end):
    """The lowest ``N`` eigenvalues ``w^2`` of the bar ``E u'' = rho u_tt``, ``u(0) = 0``, on ``n`` intervals:
    ``u(L) = 0`` (fixed) or ``u'(L) = 0`` (free: a mirror node beyond ``L``, second order)."""
    hh = L / n
    k = n - 1 if end == "fixed" else n
    D2 = (np.diag(-2.0 * np.ones(k)) + np.diag(np.ones(k - 1), 1) + np.diag(np.ones(k - 1), -1)) / hh**2
    if end == "free":
        D2[-1, -2] = 2.0 / hh**2
    return np.sort(np.linalg.eigvals(-E / RHO * D2).real)[:N]


@pytest.mark.parametrize("end, first", [("fixed", np.pi), ("free", np.pi / 2)])
def test_axial_modes_against_finite_difference_bar(end, first):
    """The axial frequencies of the model's equations against the finite-difference bar (Richardson, 2 grids) and
    the closed forms: fixed-fixed ``n pi / L sqrt(E / rho)`` (16.3 krad/s first), fixed-free
    ``(2 n - 1) pi / (2 L) sqrt(E / rho)`` (8.2 krad/s)."""
    N = 4
    W, m = frequencies(N, end=end)
    J, _ = jacobian(N, W, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), m=m, axial=axial_basis(N, end))
    s = np.linalg.eigvals(J)
    model = np.sort(np.abs(s.imag))[::2]  # conjugate pairs
    lam = [_fd_bar(N, n, end) for n in (400, 800)]
    fd = np.sqrt((4 * lam[1] - lam[0]) / 3)
    for k, wk in enumerate(fd):
        assert np.min(np.abs(model - wk)) < 1e-6 * wk
    c = np.sqrt(E / RHO)  # 5.2 km/s
    assert fd[0] == pytest.approx(first / L * c, rel=1e-6)
    step = 2.0 if end == "free" else 1.0  # the next modes: (2n - 1) pi / 2 or n pi
    np.testing.assert_allclose(W[:N], first / L * c * (1.0 + step * np.arange(N)), rtol=1e-14)


def _stretch(x, Omega, a1, end):
    """Closed form of ``E u1'' + rho Omega^2 u1 = rho (a1 - Omega^2 x)``, ``u1(0) = 0`` and ``u1(L) = 0`` (fixed) or
    ``u1'(L) = 0`` (free): ``u1 = (a1 - Omega^2 x) / Omega^2 + C cos(k x) + D sin(k x)``,
    ``k = Omega sqrt(rho / E)``."""
    k = Omega * np.sqrt(RHO / E)
    up = lambda x: (a1 - Omega**2 * x) / Omega**2  # noqa: E731
    C = -up(0.0)
    if end == "fixed":
        D = -(up(L) + C * np.cos(k * L)) / np.sin(k * L)
    else:  # up' = -1: -1 - C k sin(k L) + D k cos(k L) = 0
        D = (1.0 + C * k * np.sin(k * L)) / (k * np.cos(k * L))
    return up(x) + C * np.cos(k * x) + D * np.sin(k * x)


@pytest.mark.parametrize("end", ["fixed", "free"])
def test_quasi_static_axial_stretch_of_a_spinning_link(end):
    """Constant spin ``Omega`` about ``e3`` and ``a_O1``: the equilibrium of the model's equations against the closed
    form of each end condition (:func:`_stretch`); converges with the modes."""
    Omega, a1 = 400.0, 3.0e4
    x = np.linspace(0.0, L, 101)
    exact = _stretch(x, Omega, a1, end)
    assert np.max(np.abs(exact)) > 1e-6  # micrometres of stretch
    errors = []
    for N in (4, 16, 64):
        W, m = frequencies(N, end=end)
        J, f0 = jacobian(N, W, (0.0, 0.0, Omega), (0.0, 0.0, 0.0), a_O=(a1, 0.0, 0.0), m=m, axial=axial_basis(N, end))
        y = np.linalg.solve(J, -f0)
        u1, u2, u3 = spatial.deflections(y, x, L, end)
        assert np.max(np.abs(u2)) == 0.0 and np.max(np.abs(u3)) == 0.0
        errors.append(np.max(np.abs(u1 - exact)) / np.max(np.abs(exact)))
    assert errors[0] > errors[1] > errors[2]
    assert errors[2] < 1e-4


@pytest.mark.parametrize("end, mid", [("fixed", 1.0 / 8.0), ("free", 3.0 / 8.0)])
def test_quasi_static_stretch_under_a_uniform_axial_load(end, mid):
    """No spin, ``a_O1 = a``: ``E u1'' = rho a``, ``u1(0) = 0``; at mid-length ``u1 = -rho a L^2 / (8 E)`` with
    ``u1(L) = 0`` and ``-3 rho a L^2 / (8 E)`` with ``u1'(L) = 0``: the free end stretches three times as far (the
    paper's rod under ``OA omega0^2 = 69 m/s^2``: 0.32 um against 0.96 um)."""
    a = 0.07 * (10 * np.pi) ** 2
    N = 64
    W, m = frequencies(N, end=end)
    J, f0 = jacobian(N, W, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), a_O=(a, 0.0, 0.0), m=m, axial=axial_basis(N, end))
    u1 = spatial.deflections(np.linalg.solve(J, -f0), [0.5 * L], L, end)[0][0]
    assert u1 == pytest.approx(-mid * RHO * a * L**2 / E, rel=1e-4)


def test_free_end_couplings_are_the_galerkin_projection():
    """The frame's accelerations and the rigid load with the free-end axial modes ``psi_m = sin(gamma_m x)``, against
    the Galerkin projection assembled here by Gauss quadrature: a direction's rows are ``M_dd^-1 M_de`` times the
    ``(d, e)`` entry of the frame's matrices (``[alpha x] + w w^T - |w|^2 I`` on displacements, ``2 [w x]`` on
    velocities), ``M_de = int psi or s . psi or s``; the axial rigid load ``-(int psi (a1 + g1 x)) / (L / 2)``.
    Both :func:`accelerations` (linear in the state: its columns) and :func:`oscillator_jacobian`."""
    def cross(a):
        return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])

    N, zeta = 3, 0.01
    w, al, a_O = np.array([0.7, -2.0, 5.0]), np.array([30.0, 4.0, -11.0]), np.array([40.0, -3.0, 7.0])
    W, m = frequencies(N, end="free")
    axial = axial_basis(N, "free")
    xg, wg = np.polynomial.legendre.leggauss(200)
    x, wq = 0.5 * L * (xg + 1.0), 0.5 * L * wg
    psi = np.sin(np.outer((2 * np.arange(1, N + 1) - 1) * np.pi / (2 * L), x))
    sin = np.sin(np.outer(np.arange(1, N + 1) * np.pi / L, x))
    basis = [psi, sin, sin]
    Mb = [[(bd * wq) @ be.T for be in basis] for bd in basis]
    Cx = cross(al) + np.outer(w, w) - w @ w * np.eye(3)
    Cv = 2.0 * cross(w)
    Jq_ref, Jv_ref = -np.diag(W**2), -np.diag(2.0 * zeta * W)
    for d in range(3):
        for e in range(3):
            P = np.linalg.solve(Mb[d][d], Mb[d][e])
            Jq_ref[d * N:(d + 1) * N, e * N:(e + 1) * N] -= Cx[d, e] * P
            Jv_ref[d * N:(d + 1) * N, e * N:(e + 1) * N] -= Cv[d, e] * P
    assert np.abs(Jq_ref[:N, N:2 * N]).max() > 0.1 * np.abs(Cx[0, 1])  # a full block: the bases differ
    J, f0 = jacobian(N, W, w, al, a_O=a_O, zeta=zeta, m=m, axial=axial)
    M = 3 * N
    np.testing.assert_allclose(J[M:, :M], Jq_ref, rtol=0, atol=1e-12 * np.abs(Jq_ref).max())
    np.testing.assert_allclose(J[M:, M:], Jv_ref, rtol=0, atol=1e-12 * np.abs(Jv_ref).max())
    Jq, Jv = np.zeros((M, M)), np.zeros((M, M))
    spatial.oscillator_jacobian(W, zeta, tuple(w), tuple(al), Jq, Jv, axial)
    np.testing.assert_allclose(Jq, Jq_ref, rtol=0, atol=1e-12 * np.abs(Jq_ref).max())
    np.testing.assert_allclose(Jv, Jv_ref, rtol=0, atol=1e-12 * np.abs(Jv_ref).max())
    g1 = -(w[1] ** 2 + w[2] ** 2)
    load = -(psi * wq) @ (a_O[0] + g1 * x) / (L / 2)
    np.testing.assert_allclose(f0[M:M + N], load, rtol=1e-12)


def _rssp(t, axis=(0.25, 0.2, 1.0), ref=(1.0, 0.0, 0.0), P=(0.0, 0.0, 0.05), d=(1.0, 0.0, 0.0), r=0.07,
          w0=10 * np.pi, guide=0.4):
    k = np.array(axis) / np.linalg.norm(axis)
    a = np.array(ref) - np.dot(ref, k) * k
    a /= np.linalg.norm(a)
    dd = np.array(d) / np.linalg.norm(d)
    return spatial.slider_crank_rssp(t, r, L, w0, guide, k, a, np.array(P, float), dd)


def test_rssp_kinematics_against_finite_differences_of_positions():
    """Crank axis 14 deg off the normal of the slider line (not perpendicular to it), slider line offset 5 cm."""
    h = 1e-5
    spin, outof, tilt = [], [], []
    for t in (0.0, 0.0123, 0.071, 0.15):
        k = _rssp(t)
        A_O, w, al, v_O, x_star, V_r, O, e1, e2, e3 = k.A_O, k.omega, k.alpha, k.v_O, k.x_star, k.V_r, k.O, k.e1, \
            k.e2, k.e3
        R = np.array([e1, e2, e3])  # rows: fixed -> link components
        assert np.allclose(R @ R.T, np.eye(3), atol=1e-14)
        pos = [_rssp(t + j * h) for j in (-2, -1, 1, 2)]

        def d1(name):
            a, b, c, d = (np.asarray(getattr(k, name)) for k in pos)
            return (a - 8 * b + 8 * c - d) / (12 * h)

        O_t = d1("O")
        O_tt = (pos[1].O - 2 * O + pos[2].O) / h**2
        assert np.allclose(v_O, R @ O_t, rtol=1e-8, atol=1e-9)
        assert np.allclose(A_O, R @ O_tt, rtol=1e-5, atol=1e-4)
        # C = O + L e1 stays on the slider line and the link length is kept
        C = O + L * e1
        assert abs(C[1]) < 1e-14 and abs(C[2] - 0.05) < 1e-14
        # w from e_i_t = w x e_i, alpha from differences of w
        e_t = [d1("e1"), d1("e2"), d1("e3")]
        w_fd = np.array([e_t[1] @ e3, e_t[2] @ e1, e_t[0] @ e2])
        assert np.allclose(w, w_fd, rtol=1e-8, atol=1e-8)
        for i in range(3):
            assert np.allclose(R.T @ np.cross(w, R @ e_t[i] * 0 + np.eye(3)[i]), e_t[i], atol=1e-7)
        al_fd = d1("omega")
        assert np.allclose(al, al_fd, rtol=1e-6, atol=1e-5)
        assert V_r == pytest.approx(d1("x_star"), rel=1e-8, abs=1e-10)
        # the collar point lies on the guide plane X = 0.4
        assert (O + x_star * e1)[0] == pytest.approx(0.4, abs=1e-14)
        spin.append(abs(w[0]))
        tilt.append(abs(w[1]))
        outof.append(abs(A_O[2]))
    assert max(spin) > 1e-2 and max(outof) > 1.0 and max(tilt) > 1e-2  # a genuinely spatial motion


def test_rssp_planar_case_is_the_paper_slider_crank():
    """Crank axis normal to the slider line through the crank centre: the planar closed forms."""
    from lubelink.link.kinematics import slider_crank

    for t in (0.0123, 0.05, 0.13):
        k_ = _rssp(t, axis=(0, 0, 1), P=(0, 0, 0))
        A_O, w, al, v_O, x_star, V_r = k_.A_O, k_.omega, k_.alpha, k_.v_O, k_.x_star, k_.V_r
        k = slider_crank(t, 0.07, L, 10 * np.pi, 0.4)
        assert A_O[1] == pytest.approx(k["A_O2"], rel=1e-12)
        assert w[2] == pytest.approx(k["omega"], rel=1e-12) and al[2] == pytest.approx(k["alpha"], rel=1e-10)
        assert abs(w[0]) + abs(w[1]) + abs(al[0]) + abs(al[1]) + abs(A_O[2]) < 1e-12
        assert x_star == pytest.approx(k["x_star"], rel=1e-12) and V_r == pytest.approx(k["V_r"], rel=1e-10)
        assert v_O[0] == pytest.approx(k["v_O1"], rel=1e-12)


def test_oscillator_jacobian_is_the_frame_acceleration_matrices():
    """``spatial.oscillator_jacobian`` against the matrices of ``2 w x v + alpha x x + w x (w x x)`` written by hand:
    ``d/dx = [alpha x] + w w^T - |w|^2 I``, ``d/dv = 2 [w x]``, on every mode's three coordinates, with the
    oscillators' ``-W^2`` and ``-2 zeta W`` on the diagonals; and the accelerations' change from the rest state is
    that Jacobian times the state (the equations are affine in the state without loads)."""
    def cross(a):
        return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])

    N, zeta = 3, 0.03
    w, al = np.array([0.7, -2.0, 5.0]), np.array([30.0, 4.0, -11.0])
    W = np.linspace(100.0, 900.0, 3 * N)
    Jq, Jv = np.zeros((3 * N, 3 * N)), np.zeros((3 * N, 3 * N))
    spatial.oscillator_jacobian(W, zeta, tuple(w), tuple(al), Jq, Jv)
    Cx = cross(al) + np.outer(w, w) - w @ w * np.eye(3)
    Cv = 2.0 * cross(w)
    Jq_ref, Jv_ref = -np.diag(W**2), -np.diag(2.0 * zeta * W)
    for n in range(N):
        idx = np.array([n, N + n, 2 * N + n])
        Jq_ref[np.ix_(idx, idx)] -= Cx
        Jv_ref[np.ix_(idx, idx)] -= Cv
    np.testing.assert_allclose(Jq, Jq_ref, rtol=0, atol=1e-12 * np.abs(Jq_ref).max())
    np.testing.assert_allclose(Jv, Jv_ref, rtol=0, atol=1e-14)
    y = np.random.default_rng(0).standard_normal(6 * N)
    out, rest = np.empty(6 * N), np.empty(6 * N)
    for state, acc in ((y, out), (np.zeros(6 * N), rest)):  # the rigid motion's load: the affine part
        spatial.accelerations(state, W, zeta, (0.0, 0.0, 0.0), tuple(w), tuple(al), np.zeros(3 * N), 1.0, 1.0, acc)
    np.testing.assert_allclose(out[3 * N:] - rest[3 * N:], Jq @ y[:3 * N] + Jv @ y[3 * N:], rtol=1e-12, atol=1e-9)

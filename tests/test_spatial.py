"""The spatial link's modal equations (lubelink.link.spatial) against closed forms and the planar model.

References: the gyroscopic whirl of a link spinning about its own axis (characteristic quartic),
the fixed-fixed bar (finite differences), the quasi-static axial stretch of a spinning link (closed
form of ``E u1'' + rho W^2 u1 = rho (W^2 x - a1)``), and the planar model (lubelink.beam) for a
planar motion.
"""

import numpy as np
import pytest

from lubelink import beam

from lubelink.link import spatial

E, RHO, L = 207e9, 7650.0, 1.0


def frequencies(N, b=0.01, h=0.01):
    A = b * h
    return spatial.frequencies(N, L, E, RHO, A, b * h**3 / 12, h * b**3 / 12), RHO * A * L / 2


def jacobian(N, W, w, al, a_O=(0.0, 0.0, 0.0), zeta=0.0, m=1.0):
    """``(J, f0)``: the right-hand side is ``J y + f0`` (it is linear in the state)."""
    n = 6 * N

    def f(y):
        out = np.empty(n)
        spatial.accelerations(y, W, zeta, np.array(a_O, float), np.array(w, float), np.array(al, float),
                              np.zeros(3 * N), m, L, out)
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


def test_axial_modes_against_finite_difference_bar():
    N = 4
    W, _ = frequencies(N)
    J, _ = jacobian(N, W, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    s = np.linalg.eigvals(J)
    model = np.sort(np.abs(s.imag))[::2]  # conjugate pairs
    # the bar E u'' = rho u_tt, u(0) = u(L) = 0, by finite differences (Richardson, 2 grids)
    lam = []
    for n in (400, 800):
        hh = L / n
        D2 = (np.diag(-2.0 * np.ones(n - 1)) + np.diag(np.ones(n - 2), 1) + np.diag(np.ones(n - 2), -1)) / hh**2
        lam.append(np.sort(np.linalg.eigvalsh(-E / RHO * D2))[:N])
    fd = np.sqrt((4 * lam[1] - lam[0]) / 3)
    for k, wk in enumerate(fd):
        assert np.min(np.abs(model - wk)) < 1e-6 * wk
    assert fd[0] == pytest.approx(np.pi / L * np.sqrt(E / RHO), rel=1e-6)  # 16.3 krad/s, 5.2 km/s bar


def test_quasi_static_axial_stretch_of_a_spinning_link():
    """Constant spin ``Omega`` about ``e3`` and ``a_O1``: equilibrium ``E u1'' + rho Omega^2 u1 =
    rho (a1 - Omega^2 x)``, ``u1(0) = u1(L) = 0``, in closed form; converges with the modes."""
    Omega, a1 = 400.0, 3.0e4
    k = Omega * np.sqrt(RHO / E)
    x = np.linspace(0.0, L, 101)
    up = lambda x: (a1 - Omega**2 * x) / Omega**2  # noqa: E731  (E/rho)/Omega^2 * rho/E * (...)
    C = -up(0.0)
    D = -(up(L) + C * np.cos(k * L)) / np.sin(k * L)
    exact = up(x) + C * np.cos(k * x) + D * np.sin(k * x)
    assert np.max(np.abs(exact)) > 1e-6  # micrometres of stretch
    errors = []
    for N in (4, 16, 64):
        W, m = frequencies(N)
        J, f0 = jacobian(N, W, (0.0, 0.0, Omega), (0.0, 0.0, 0.0), a_O=(a1, 0.0, 0.0))
        y = np.linalg.solve(J, -f0)
        u1, u2, u3 = spatial.deflections(y, x, L)
        assert np.max(np.abs(u2)) == 0.0 and np.max(np.abs(u3)) == 0.0
        errors.append(np.max(np.abs(u1 - exact)) / np.max(np.abs(exact)))
    assert errors[0] > errors[1] > errors[2]
    assert errors[2] < 1e-4


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

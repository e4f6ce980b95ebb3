"""Variable section (lubelink.link.section): Galerkin matrices, eigenbasis, and the model built on them.

References are independent of the sine-mode Galerkin code: closed forms for the uniform link, a
finite-difference eigen and static solution of ``(E I w'')'' = ...`` for the tapered one.
"""

import numpy as np
import pytest

from lubelink import beam, config

from lubelink.link import section
from lubelink.config import ConfigError
from lubelink.link.kinematics import PrescribedMotion
from lubelink.build import build_model
from lubelink.params import Beam

E, RHO, B, H, L = 207e9, 7650.0, 0.01, 0.01, 1.0


def tapered(rb=0.6, rh=1.4):
    return section.taper(Beam(width=B, height=H, width_ratio=rb, height_ratio=rh), L)


def fd_operators(sec, n):
    """``(x, K, M)`` of ``(E I w'')'' = lambda rho A w``, pinned ends, on ``n`` intervals (second order).

    ``m = E I w''`` vanishes at pinned ends like ``w``, so ``K = D2 diag(E I) D2`` on the interior nodes.
    """
    h = L / n
    x = np.linspace(0.0, L, n + 1)[1:-1]
    A, I = (np.asarray(f(x), dtype=float) * np.ones_like(x) for f in sec.functions())
    D2 = (np.diag(-2.0 * np.ones(n - 1)) + np.diag(np.ones(n - 2), 1) + np.diag(np.ones(n - 2), -1)) / h**2
    return x, D2 @ np.diag(E * I) @ D2, RHO * A


def fd_frequencies(sec, n, count):
    """Lowest ``count`` circular frequencies [rad/s] by finite differences.

    The largest eigenvalues of the inverse problem, with ``K^-1 = G diag(1 / E I) G`` from the
    discrete Green's function of the second difference, ``G_ij = -h x_i (L - x_j) / L`` for
    ``x_i <= x_j`` (exact): no ill-conditioned inversion (``cond K ~ n^4``; inverting ``K`` by LU
    left errors of 1e-8 in the reference on some machines).
    """
    x, K, m = fd_operators(sec, n)
    h = L / n
    G = -h * np.minimum.outer(x, x) * (L - np.maximum.outer(x, x)) / L
    EI = E * np.asarray(sec.functions()[1](x), dtype=float) * np.ones_like(x)
    s = np.sqrt(m)
    K_inv = (G / EI[None, :]) @ G
    mu = np.linalg.eigvalsh(s[:, None] * K_inv * s[None, :])[::-1][:count]
    return 1.0 / np.sqrt(mu)


def fd_reference(sec, count):
    """Finite-difference frequencies [rad/s] on 200, 400 and 800 intervals, Richardson-extrapolated
    twice on the eigenvalues (errors ``O(h^2)``, ``O(h^4)``)."""
    lam = [fd_frequencies(sec, n, count) ** 2 for n in (200, 400, 800)]
    r1 = [(4.0 * lam[i + 1] - lam[i]) / 3.0 for i in range(2)]
    return np.sqrt((16.0 * r1[1] - r1[0]) / 15.0)


def test_uniform_matrices_are_the_closed_form():
    N = 12
    A, I = B * H, B * H**3 / 12
    sec = section.Section(area=lambda x: A + 0 * x, second_moment=lambda x: I + 0 * x)
    M, K, r0, r1 = section.galerkin_matrices(sec, E, RHO, N, L)
    m = RHO * A * L / 2
    w = beam.natural_frequencies(N, L, E, I, RHO, A)
    assert np.allclose(M, m * np.eye(N), rtol=0, atol=1e-13 * m)
    assert np.allclose(K, np.diag(m * w**2), rtol=0, atol=1e-12 * m * w[-1] ** 2)
    # rigid loads: the uniform model's closed form (beam.rigid_load is per unit modal mass)
    n = np.arange(1, N + 1)
    assert np.allclose(-(r0 * 1.0) / m, beam.rigid_load(1.0, 0.0, n, L), rtol=1e-12, atol=1e-12)
    assert np.allclose(-(r1 * 1.0) / m, beam.rigid_load(0.0, 1.0, n, L), rtol=1e-12, atol=1e-12)


def test_sampled_table_equals_callable():
    xs = np.linspace(0.0, L, 2001)
    sec = tapered()
    A, I = sec.functions()
    table = section.Section(area=(xs, A(xs)), second_moment=(xs, I(xs)))
    w1 = section.galerkin_table(sec, E, RHO, 6, L)[0]
    w2 = section.galerkin_table(table, E, RHO, 6, L)[0]
    assert np.allclose(w1, w2, rtol=1e-6)  # the table interpolates a quadratic/quartic linearly


def test_eigenbasis_is_mass_normalised():
    N = 8
    M, K, *_ = section.galerkin_matrices(tapered(), E, RHO, N, L)
    w, Phi = section.eigenbasis(M, K, 0.37)
    assert np.allclose(Phi.T @ M @ Phi, 0.37 * np.eye(N), atol=1e-12)
    assert np.allclose(Phi.T @ K @ Phi, 0.37 * np.diag(w**2), rtol=1e-10, atol=1e-9 * w[-1] ** 2)
    assert np.all(np.diff(w) > 0)


def test_tapered_frequencies_against_finite_differences_converging_with_modes():
    sec = tapered()
    ref = fd_reference(sec, 3)
    errors = []
    for N in (3, 6, 12, 24):
        w = section.galerkin_table(sec, E, RHO, N, L)[0][:3]
        assert np.all(w >= ref * (1 - 1e-9))  # Rayleigh-Ritz bounds from above
        errors.append(np.max(np.abs(w / ref - 1.0)))
    assert errors == sorted(errors, reverse=True)
    assert errors[-1] < 5e-8 and errors[0] > 1e5 * errors[-1]
    # the taper matters: the uniform link's frequencies are far off
    w_uniform = beam.natural_frequencies(3, L, E, B * H**3 / 12, RHO, B * H, )
    assert np.max(np.abs(w_uniform / ref - 1.0)) > 0.05


def test_config_taper_validation():
    with pytest.raises(ConfigError, match=r"beam.width_ratio = 0.0: must be a number in \[0.01, 100\]"):
        config.resolve("paper", {"beam.width_ratio": 0.0})
    with pytest.raises(ConfigError, match="beam.height"):
        config.resolve("paper", {"beam.height_ratio": 100.0, "beam.height": 0.02})


def test_bad_section_named():
    with pytest.raises(ValueError, match="section area: must be positive"):
        section.galerkin_table(section.Section(area=lambda x: 1e-4 - 2e-4 * x, second_moment=lambda x: 1e-9 + 0 * x),
                               E, RHO, 3, L)
    with pytest.raises(ValueError, match="section second_moment: a table"):
        section.Section(area=lambda x: x, second_moment=([0, 1], [1.0])).functions()


def _dry(set_=None, modes=6):
    return config.resolve("paper-dry", {"beam.modes": modes, "solver.backend": "numpy", **(set_ or {})})


def test_uniform_section_object_gives_the_uniform_model():
    cfg = _dry()
    A, I = B * H, B * H**3 / 12
    sec = section.Section(area=lambda x: A + 0 * x, second_moment=lambda x: I + 0 * x)
    m0, m1 = build_model(cfg), build_model(cfg, section=sec)
    assert m0.uniform and not m1.uniform
    assert np.allclose(m1.params.galerkin.phi, np.eye(6), atol=1e-12)
    rng = np.random.default_rng(1)
    for t in (0.0, 0.0123, 0.31):
        y = rng.normal(scale=1e-3, size=12)
        a = m0.rhs(t, y)
        b = m1.to_physical(m1.rhs(t, m1.to_state(y)))
        assert np.allclose(a, b, rtol=1e-10, atol=1e-10 * np.max(np.abs(a)))


def test_static_deflection_of_tapered_link_against_finite_differences():
    """Constant transverse acceleration and angular acceleration, no spin: the model's equilibrium
    against the finite-difference solution of ``(E I w'')'' = -rho A (a + alpha x)``."""
    sec = tapered(0.5, 1.5)
    a, alpha = 40.0, -25.0
    motion = PrescribedMotion(A_O2=lambda t: a + 0 * t, omega=lambda t: 0 * t, alpha=lambda t: alpha + 0 * t,
                              x_star=lambda t: 0.3 + 0 * t, V_r=lambda t: 0 * t)
    N = 24
    model = build_model(_dry(modes=N), motion, section=sec)
    # the equilibrium of the linear rhs: accelerations = J eta + f
    z = np.zeros(2 * N)
    f = model.rhs(0.0, z)[N:]
    J = np.column_stack([model.rhs(0.0, np.eye(2 * N)[k])[N:] - f for k in range(N)])
    eta = np.linalg.solve(J, -f)
    q = model.to_physical(np.concatenate([eta, z[:N]]))[:N]
    x, K, m = fd_operators(sec, 800)
    w_fd = np.linalg.solve(K, -m * (a + alpha * x))
    w_model = beam.deflection(q, x, L)
    assert np.max(np.abs(w_model - w_fd)) < 1e-5 * np.max(np.abs(w_fd))  # 1.6e-6 measured
    # the uniform link's static deflection differs by far more
    qu = np.linalg.solve(np.diag(beam.natural_frequencies(N, L, E, B * H**3 / 12, RHO, B * H) ** 2),
                         beam.rigid_forcing(a, alpha, N, L))
    assert np.max(np.abs(beam.deflection(qu, x, L) - w_fd)) > 0.1 * np.max(np.abs(w_fd))


def test_restitution_jump_variable_section():
    sec = tapered()
    N = 5
    model = build_model(_dry(modes=N), section=sec)
    g = model.params.galerkin
    rng = np.random.default_rng(3)
    q_dot = rng.normal(size=N)
    x_c, e = 0.37, 0.6
    s = np.sin(np.arange(1, N + 1) * np.pi / L * x_c)
    v = s @ q_dot
    after = section.eigen_restitution_jump(g, q_dot, x_c, v, e, L)
    assert s @ after == pytest.approx(-e * v, rel=1e-12)  # Newton's law at the contact point
    M = section.galerkin_matrices(sec, E, RHO, N, L)[0]
    impulse = M @ (after - q_dot)  # an impulse at x_c: its sine transform is proportional to s
    assert np.allclose(impulse, (impulse @ s) / (s @ s) * s, atol=1e-10 * np.max(np.abs(impulse)))


def test_rate_bound_of_eigenmodes_bounds_the_film_rate():
    sec = tapered()
    N = 6
    model = build_model(config.resolve("paper", {"beam.modes": N, "solver.backend": "numpy"}), section=sec)
    g = model.params.galerkin
    rng = np.random.default_rng(5)
    t_grid = np.linspace(0, 0.02, 400)
    for _ in range(5):
        y0 = rng.normal(scale=1e-4, size=2 * N) * np.r_[np.ones(N), model.omega_n]
        bound = section.eigen_rate_bound(g, y0, model.omega_n, 0.0, 0.7)
        # free oscillation of the eigenmodes, u2 and slope sampled over the pad points
        eta = y0[:N, None] * np.cos(np.outer(model.omega_n, t_grid)) + \
            (y0[N:] / model.omega_n)[:, None] * np.sin(np.outer(model.omega_n, t_grid))
        q = (g.phi @ eta).T
        x = np.linspace(0, L, 201)
        u = beam.deflection(q, x, L)
        rate = np.diff(u, axis=0) / np.diff(t_grid)[:, None]
        slope = np.abs(beam.slope(q, x, L)).max()
        assert np.abs(rate).max() + 0.7 * slope <= bound * (1 + 1e-9)


def fd_modal_response(sec, t_eval, n=400, modes=8):
    """Deflection at L/2 [m] of the tapered link under the paper's slider-crank, from the lowest
    ``modes`` eigenmodes of the finite-difference operators (no sine basis), by ``solve_ivp``."""
    from scipy.integrate import solve_ivp

    from lubelink.link.kinematics import slider_crank

    x, K, m = fd_operators(sec, n)
    s = np.sqrt(m)
    lam, V = np.linalg.eigh(K / s[:, None] / s[None, :])
    W2, Phi = lam[:modes], V[:, :modes] / s[:, None]  # Phi^T diag(m) Phi = I
    load0, load1 = Phi.T @ m, Phi.T @ (m * x)

    def f(t, z):
        k = slider_crank(t, 0.07, L, 10 * np.pi, 0.4)
        eta, eta_dot = z[:modes], z[modes:]
        return np.r_[eta_dot, -(W2 - k["omega"] ** 2) * eta - k["A_O2"] * load0 - k["alpha"] * load1]

    sol = solve_ivp(f, (0, t_eval[-1]), np.zeros(2 * modes), t_eval=t_eval, rtol=1e-10, atol=1e-14, method="DOP853")
    mid = np.argmin(np.abs(x - 0.5 * L))
    assert x[mid] == pytest.approx(0.5 * L)
    return Phi[mid] @ sol.y[:modes]


@pytest.mark.parametrize("method,backend", [("exponential", "numpy"), ("DOP853", "numpy"), ("exponential", "numba")])
def test_tapered_slider_crank_against_finite_difference_modes(method, backend):
    """The whole run (eigen-coordinate state, exponential or DOP853) against the FD link's modes."""
    if backend == "numba":
        pytest.importorskip("numba")
    rb, rh = 0.6, 1.4
    cfg = config.resolve("paper-dry", {"beam.modes": 8, "beam.width_ratio": rb, "beam.height_ratio": rh,
                                       "solver.t_end": 0.25, "solver.rtol": 1e-10, "solver.atol": 1e-14,
                                       "solver.method": method, "solver.backend": backend,
                                       "output.x_points": 3})
    from lubelink.simulate import run
    from lubelink.results import collect

    r = collect(run(cfg))
    assert r.attrs["status"] == "complete" and r.attrs["backend"] == backend
    ref = fd_modal_response(tapered(rb, rh), r["time"])
    u_mid = r["u2_mid"]
    peak = np.max(np.abs(ref))
    assert peak > 1e-3
    assert np.max(np.abs(u_mid - ref)) < 2e-4 * peak


def test_periodic_monodromy_of_tapered_link_in_sine_modes():
    """The variational monodromy matrix (integrated in eigen-coordinates) is returned in the sine
    modes of the map: it equals finite differences of the map itself."""
    from lubelink.steady.problem import PeriodMap

    cfg = config.resolve("paper-dry", {"beam.modes": 2, "beam.width_ratio": 0.7, "beam.damping_ratio": 0.05,
                                       "solver.backend": "numpy", "solver.method": "DOP853"})
    pm = PeriodMap(cfg, jacobian="variational")
    y0 = np.array([1e-4, -2e-5, 0.01, 0.003])
    J = pm(y0, jacobian=True).jacobian
    h = 1e-7
    J_fd = np.column_stack([(pm(y0 + h * e).y - pm(y0 - h * e).y) / (2 * h) for e in np.eye(4)])
    assert np.allclose(J, J_fd, rtol=1e-4, atol=1e-5 * np.max(np.abs(J)))

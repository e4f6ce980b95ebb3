"""The spatial link of variable section (lubelink.link.spatial_section, wired in lubelink.link.spatial_model).

References, independent of the sine-mode Galerkin code:

* finite-difference eigen solutions of the tapered bar ``-(E A u')' = lambda rho A u`` (fixed ends, or
  fixed at 0 and free at L) and of the tapered beams ``(E I w'')'' = lambda rho A w`` with ``I_z`` and
  ``I_y`` (pinned ends);
* the equations in the coordinates of the trial functions (sines; a free axial end: ``sin((2n - 1) pi
  x / (2 L))`` for ``u1``) solved with the block mass matrix (no eigenbasis), their matrices by a
  quadrature of this file, their frame terms by NumPy cross products: the right-hand side at a
  general 3-D motion, and a whole run under the spatial slider-crank by SciPy;
* the rotating-frame whirl of a square-section taper spinning about its axis, ``w_n +- Omega``;
* the planar model with the same taper (planar motion), and the uniform sine-mode path.
"""

import subprocess
import sys

import numpy as np
import pytest

import lubelink
from lubelink.link import section, spatial, spatial_section
from lubelink.config import resolve
from lubelink.build import build_model
from lubelink.params import Beam

E, RHO, B, H, L = 207e9, 7650.0, 0.01, 0.01, 1.0
EPS = np.finfo(float).eps
TIGHT = {"solver.rtol": 1e-10, "solver.atol": 1e-14}
TAPER = {"beam.width_ratio": 0.6, "beam.height_ratio": 1.4}


def tapered(rb=0.6, rh=1.4, b=B, h=H):
    return section.taper(Beam(width=b, height=h, width_ratio=rb, height_ratio=rh), L)


# --- independent references --------------------------------------------------------------------------------
def fd_bar(sec, n, end="fixed"):
    """Lowest eigenvalues ``w^2`` [rad^2/s^2] of ``-(E A u')' = w^2 rho A u``, ``u(0) = 0`` and ``u(L) = 0`` (fixed) or
    ``E A u'(L) = 0`` (free), on ``n`` intervals (conservative three-point scheme, ``E A`` at the midpoints; the
    free end's node carries half a cell: second order)."""
    h = L / n
    x = np.linspace(0.0, L, n + 1)
    A = sec.profile("area")
    ea = E * A(0.5 * (x[:-1] + x[1:]))  # at the n midpoints
    if end == "fixed":
        K = (np.diag(ea[:-1] + ea[1:]) - np.diag(ea[1:-1], 1) - np.diag(ea[1:-1], -1)) / h**2
        mass = RHO * A(x[1:-1])
    else:  # nodes 1..n
        K = (np.diag(np.r_[ea[:-1] + ea[1:], ea[-1]]) - np.diag(ea[1:], 1) - np.diag(ea[1:], -1)) / h**2
        mass = RHO * A(x[1:]) * np.r_[np.ones(n - 1), 0.5]
    s = np.sqrt(mass)
    return np.linalg.eigvalsh(K / s[:, None] / s[None, :])


def fd_beam(sec, moment, n):
    """Lowest eigenvalues ``w^2`` of ``(E I w'')'' = w^2 rho A w``, pinned ends, ``I`` the field ``moment``
    (``m = E I w''`` vanishes at the pins like ``w``: ``K = D2 diag(E I) D2`` on the interior nodes), through
    ``K^-1 = D2^-1 diag(1/(E I)) D2^-1``: its largest eigenvalues are accurate to ``eps n^2`` (those of ``K``
    itself to ``eps n^4``)."""
    h = L / n
    x = np.linspace(0.0, L, n + 1)[1:-1]
    G = np.linalg.inv((np.diag(-2.0 * np.ones(n - 1)) + np.diag(np.ones(n - 2), 1)
                       + np.diag(np.ones(n - 2), -1)) / h**2)
    s = np.sqrt(RHO * sec.profile("area")(x))
    mu = np.linalg.eigvalsh((s[:, None] * G) @ np.diag(1.0 / (E * sec.profile(moment)(x))) @ (G * s[None, :]))
    return 1.0 / mu[::-1]


def fd_reference(fd, count):
    """Frequencies [rad/s] on 200, 400, 800 intervals, Richardson-extrapolated twice (errors h^2, h^4)."""
    lam = [fd(n)[:count] for n in (200, 400, 800)]
    r1 = [(4.0 * lam[i + 1] - lam[i]) / 3.0 for i in range(2)]
    return np.sqrt((16.0 * r1[1] - r1[0]) / 15.0)


def trial_matrices(sec, N, end="fixed"):
    """``(M, [K1, K2, K3], r0, r1)`` of the trial functions by 400-point Gauss-Legendre on ``[0, L]`` (not the
    library's composite rule): the sines ``s_n = sin(n pi x / L)`` for the bending directions and, for the axial
    one, the sines (``end`` fixed) or ``psi_n = sin((2 n - 1) pi x / (2 L))`` (free). ``M[d][e]`` the mass blocks
    ``int rho A phi_d phi_e`` between the directions' functions; ``r0[d]``, ``r1[d]`` ``int rho A phi_d``,
    ``int rho A x phi_d``."""
    s, wq = np.polynomial.legendre.leggauss(400)
    x, wq = 0.5 * L * (s + 1.0), 0.5 * L * wq
    beta = np.arange(1, N + 1) * np.pi / L
    gamma = beta if end == "fixed" else (2 * np.arange(1, N + 1) - 1) * np.pi / (2 * L)
    S, C = np.sin(np.outer(x, beta)), np.cos(np.outer(x, gamma))
    P = np.sin(np.outer(x, gamma))  # the axial functions
    A, Iz, Iy = (sec.profile(k)(x) for k in ("area", "second_moment", "second_moment_y"))

    def gram(U, weight, V=None):
        return U.T @ ((weight * wq)[:, None] * (U if V is None else V))

    funcs = [P, S, S]
    M = [[gram(funcs[d], RHO * A, funcs[e]) for e in range(3)] for d in range(3)]
    Ks = [gram(C * gamma, E * A), gram(S * beta**2, E * Iz), gram(S * beta**2, E * Iy)]
    return (M, Ks, np.array([U.T @ (RHO * A * wq) for U in funcs]),
            np.array([U.T @ (RHO * A * x * wq) for U in funcs]))


class MassMatrixForm:
    """``Q_tt`` ``(3, N)`` of ``sum_e M_de [delta_de Q_e_tt + (2 w x Q_t + al x Q + w x (w x Q))_(d, e)] + K_d Q_d
    + C_d Q_d_t = F_d - r0_d a_d - r1_d g_d`` in the coordinates of the trial functions (``g = al x e1 + w x (w x
    e1)``; the matrices of :func:`trial_matrices`), solved with ``M_dd`` (its inverse, once)."""

    def __init__(self, mats, damping=None):
        M, Ks, r0, r1 = mats
        self.Mi = [np.linalg.inv(M[d][d]) for d in range(3)]
        self.P = [[self.Mi[d] @ M[d][e] for e in range(3)] for d in range(3)]
        self.MiK = [self.Mi[d] @ Ks[d] for d in range(3)]
        self.MiC = None if damping is None else [self.Mi[d] @ damping[d] for d in range(3)]
        self.Mi_r0 = [self.Mi[d] @ r0[d] for d in range(3)]
        self.Mi_r1 = [self.Mi[d] @ r1[d] for d in range(3)]

    def __call__(self, Q, Q_t, a_O, w, al, F):
        Wx, Ax = skew(w), skew(al)  # Wx @ v = w x v
        G = Ax + Wx @ Wx
        g = G[:, 0]  # al x e1 + w x (w x e1)
        out = np.empty((3, Q.shape[1]))
        for d in range(3):
            out[d] = self.Mi[d] @ F[d] - a_O[d] * self.Mi_r0[d] - g[d] * self.Mi_r1[d] - self.MiK[d] @ Q[d]
            if self.MiC is not None:
                out[d] -= self.MiC[d] @ Q_t[d]
            for e in range(3):
                out[d] -= self.P[d][e] @ (2.0 * Wx[d, e] * Q_t[e] + G[d, e] * Q[e])
        return out


def skew(v):
    """The matrix of ``v x``."""
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


# --- the matrices and frequencies ----------------------------------------------------------------------------
@pytest.mark.parametrize("end", ["fixed", "free"])
def test_tapered_frequencies_of_the_three_directions_against_finite_differences(end):
    """Width 0.6 and height 1.4 times at x = L: A(x), I_z(x) = B h^3/12, I_y(x) = h B^3/12 all differ. The
    Galerkin eigenvalues bound the FD references from above (Rayleigh-Ritz) and converge with the modes; the
    axial ones with either end condition at L."""
    sec = tapered()
    refs = [fd_reference(lambda n: fd_bar(sec, n, end), 3), fd_reference(lambda n: fd_beam(sec, "second_moment", n), 3),
            fd_reference(lambda n: fd_beam(sec, "second_moment_y", n), 3)]
    assert abs(refs[1][0] / refs[2][0] - 1.0) > 0.3  # I_z and I_y differ
    errors = []
    for N in (3, 6, 12, 24):
        W = spatial_section.spatial_galerkin(sec, E, RHO, N, L, axial_end=end)[0].reshape(3, N)[:, :3]
        for d in range(3):
            assert np.all(W[d] >= refs[d] * (1 - 1e-9)), (N, d)
        errors.append([np.max(np.abs(W[d] / refs[d] - 1.0)) for d in range(3)])
    errors = np.array(errors)
    assert np.all(np.diff(errors, axis=0) < 0)
    # 24 modes: 7.1e-8, 1.6e-8, 9.7e-8; axial ~N^-3 (u1'' != 0 at the fixed ends), bending ~N^-5
    assert np.all(errors[-1] < [1e-7, 3e-8, 2e-7]), errors[-1]
    assert np.all(errors[0] > 1e2 * errors[-1])
    # the taper matters: the uniform link's frequencies are off by 0.9 % (axial: A(x) enters through its
    # relative variation only), 16 % and 27 %
    uniform = spatial.frequencies(3, L, E, RHO, B * H, B * H**3 / 12, H * B**3 / 12, end).reshape(3, 3)
    assert np.all(np.max(np.abs(uniform / np.array(refs) - 1.0), axis=1) > [5e-3, 0.1, 0.2])


@pytest.mark.parametrize("end", ["fixed", "free"])
def test_model_frequencies_and_results(end):
    """The configuration's taper reaches the model: ``state_frequencies`` are the three directions'
    Galerkin eigenvalues, ``omega_n`` the in-plane ones; the eigenbases are M-orthonormal (the axial one in the
    mass matrix of its end's functions), the free end's couplings the projections ``M_dd^-1 M_de``."""
    N = 4
    model = build_model(resolve("spatial-slider-crank", {**TAPER, "beam.modes": N, "solver.backend": "numpy",
                                                         "beam.axial_end": end}))
    W, m_ref, g, axial = spatial_section.spatial_galerkin(tapered(), E, RHO, N, L, axial_end=end)
    np.testing.assert_allclose(model.state_frequencies, W, rtol=1e-14)
    np.testing.assert_allclose(model.omega_n, W[N:2 * N], rtol=1e-14)
    assert not model.uniform and model.params.galerkin is not None
    assert (model.params.spatial.axial is None) == (axial is None) == (end == "fixed")
    M, Ks, r0, r1 = trial_matrices(tapered(), N, end)
    a, b = 0.6 - 1.0, 1.4 - 1.0  # A = B H (1 + a x/L)(1 + b x/L)
    assert m_ref == pytest.approx(0.5 * RHO * B * H * L * (1 + (a + b) / 2 + a * b / 3), rel=1e-13)
    for d in range(3):
        phi = g.phi[d]
        np.testing.assert_allclose(phi.T @ M[d][d] @ phi, m_ref * np.eye(N), atol=1e-12 * m_ref)
        np.testing.assert_allclose(phi.T @ Ks[d] @ phi, m_ref * np.diag(W[d * N:(d + 1) * N] ** 2),
                                   atol=1e-11 * m_ref * W[(d + 1) * N - 1] ** 2)
        np.testing.assert_allclose(g.phi_inv[d] @ phi, np.eye(N), atol=1e-12)
    np.testing.assert_allclose(g.r0, r0[1], rtol=1e-12)
    np.testing.assert_allclose(g.r1, r1[1], rtol=1e-12)
    if axial is not None:
        np.testing.assert_allclose(axial.rigid[0], r0[0], rtol=0, atol=1e-12 * np.abs(r0[0]).max())
        np.testing.assert_allclose(axial.rigid[1], r1[0], rtol=0, atol=1e-12 * np.abs(r1[0]).max())
        np.testing.assert_allclose(axial.projection[0], np.linalg.solve(M[0][0], M[0][1]), rtol=0, atol=1e-12)
        np.testing.assert_allclose(axial.projection[1], np.linalg.solve(M[1][1], M[1][0]), rtol=0, atol=1e-12)


# --- the right-hand side -----------------------------------------------------------------------------------------
@pytest.mark.parametrize("seed, end", [(0, "fixed"), (1, "fixed"), (2, "fixed"), (0, "free"), (1, "free")])
def test_eigen_right_hand_side_equals_the_mass_matrix_form(seed, end):
    """At a general motion (all components of w, alpha, A_O), forces on all three directions and damping:
    the eigen-coordinate accelerations, taken back to the trial functions' coordinates, solve their equations
    with the block mass matrix (the cross-direction blocks Phi_d^T M_dj Phi_j included; a free axial end's
    functions differ from the bending sines, so its blocks are full)."""
    N, zeta = 5, 0.03
    sec = tapered(0.7, 1.3)
    W, m_ref, g, axial = spatial_section.spatial_galerkin(sec, E, RHO, N, L, axial_end=end)
    mats = trial_matrices(sec, N, end)
    # modal damping of each eigenmode: C_d = M_dd Phi_d diag(2 zeta W_d) Phi_d^-1
    damping = [mats[0][d][d] @ g.phi[d] @ np.diag(2 * zeta * W[d * N:(d + 1) * N]) @ g.phi_inv[d] for d in range(3)]
    rng = np.random.default_rng(seed)
    scale = np.array([[1e-7], [1e-3], [1e-3]]) / np.arange(1, N + 1) ** 2
    Q, Q_t = rng.uniform(-1, 1, (3, N)) * scale, rng.uniform(-1, 1, (3, N)) * scale * 500
    a_O, w, al = rng.normal(size=3) * 100, rng.normal(size=3) * 30, rng.normal(size=3) * 1e3
    F = rng.normal(size=(3, N)) * 10
    yq = np.concatenate([Q.ravel(), Q_t.ravel()])
    y = spatial_section.state(g, yq)
    np.testing.assert_allclose(spatial_section.physical(g, y), yq, rtol=1e-12, atol=1e-14 * np.abs(yq).max())
    out = np.empty(6 * N)
    spatial_section.eigen_accelerations(g, y, yq, W, zeta, tuple(a_O), tuple(w), tuple(al), F.ravel(), m_ref, out,
                                        axial)
    got = spatial_section.physical(g, out)
    np.testing.assert_allclose(got[:3 * N], Q_t.ravel(), rtol=1e-12, atol=1e-14 * np.abs(Q_t).max())
    ref = MassMatrixForm(mats, damping)(Q, Q_t, a_O, w, al, F)
    for d in range(3):
        terms = np.abs(np.linalg.solve(mats[0][d][d], mats[1][d] @ Q[d])).max() + np.abs(ref[d]).max()
        np.testing.assert_allclose(got[3 * N + d * N:3 * N + (d + 1) * N], ref[d], rtol=0, atol=1e-12 * terms)  # 4e-14


def test_square_taper_spinning_about_its_axis_whirls_at_w_n_plus_minus_omega():
    """I_y(x) = I_z(x): with z = q2 + i q3, ``M z_tt + 2 i Omega M z_t - Omega^2 M z + K z = 0`` gives
    ``K phi = (lambda + Omega)^2 M phi``: the link-frame whirl frequencies are ``|w_n +- Omega|`` with the
    Galerkin ``w_n``; the axial direction keeps its own (no centrifugal term along the spin axis)."""
    N = 4
    sec = tapered(0.6, 0.6)
    W, m_ref, g, _ = spatial_section.spatial_galerkin(sec, E, RHO, N, L)
    np.testing.assert_allclose(W[N:2 * N], W[2 * N:], rtol=1e-13)

    def f(y, Omega):
        out = np.empty(6 * N)
        spatial_section.eigen_accelerations(g, y, spatial_section.physical(g, y), W, 0.0, (0.0, 0.0, 0.0),
                                            (Omega, 0.0, 0.0), (0.0, 0.0, 0.0), np.zeros(3 * N), m_ref, out)
        return out

    for Omega in (0.3 * W[N], 1.7 * W[N], 2.5 * W[N + 1]):
        J = np.column_stack([f(e, Omega) for e in np.eye(6 * N)])
        s = np.linalg.eigvals(J)
        assert np.max(np.abs(s.real)) < 1e-6 * Omega
        expected = np.concatenate([W[:N], W[N:2 * N] + Omega, np.abs(W[N:2 * N] - Omega)])
        np.testing.assert_allclose(np.sort(np.abs(s.imag)), np.sort(np.repeat(expected, 2)), rtol=1e-11)  # 3e-15


@pytest.mark.parametrize("end", ["fixed", "free"])
def test_uniform_section_through_the_eigen_path_equals_the_uniform_path(end):
    """A constant Section goes through the eigenbases; it agrees with the uniform sine-mode kernels to round-off
    (with a free axial end: the quadrature's couplings and rigid loads against the closed forms of
    :func:`lubelink.link.spatial.free_axial_basis`)."""
    N = 3
    # the axial force is modelled on the uniform link only ("auto" leaves it out with a section): off in both
    cfg = resolve("spatial-slider-crank", {"beam.modes": N, "solver.backend": "numpy", "film.clearance": 5e-3,
                                           "beam.axial_end": end, "beam.axial_force": "none"})
    const = section.Section(area=lambda x: B * H + 0 * x, second_moment=lambda x: B * H**3 / 12 + 0 * x,
                            second_moment_y=lambda x: H * B**3 / 12 + 0 * x)
    m0, m1 = build_model(cfg), build_model(cfg, section=const)
    assert m0.uniform and not m1.uniform
    np.testing.assert_allclose(m1.state_frequencies, m0.state_frequencies, rtol=1e-13)
    for d in range(3):
        np.testing.assert_allclose(np.abs(m1.params.spatial.galerkin.phi[d]), np.eye(N), atol=1e-13)
    rng = np.random.default_rng(4)
    for t in (0.0, 0.0123, 0.31):
        y = np.concatenate([rng.normal(size=3 * N) * np.repeat([1e-7, 1e-3, 1e-3], N),
                            rng.normal(size=3 * N) * np.repeat([1e-4, 0.3, 0.3], N)])
        a = m0.rhs(t, y)
        b = m1.to_physical(m1.rhs(t, m1.to_state(y)))
        scale = np.max(np.abs(a)) + np.max(m0.state_frequencies) ** 2 * 1e-7
        np.testing.assert_allclose(b, a, rtol=0, atol=20 * EPS * scale)  # 2 eps measured
        assert m1.gap(t, m1.to_state(y)) == pytest.approx(m0.gap(t, y), abs=1e-15)


# --- whole runs ----------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("scenario", ["paper-dry", "paper"])
def test_planar_case_with_a_taper_matches_the_planar_model(scenario):
    """Planar motion, same taper: u3 stays exactly zero and u2_mid is the planar tapered model's within 0.1 um
    (the axial-bending Coriolis and Euler terms)."""
    over = {"beam.modes": 3, "solver.t_end": 0.3, **TAPER, **TIGHT}
    pl = lubelink.simulate(scenario, set=over)
    sp = lubelink.simulate(scenario, set={**over, "beam.model": "spatial"})
    assert sp.attrs["status"] == pl.attrs["status"] == "complete"
    assert np.max(np.abs(sp.u3.values)) == 0.0 and np.max(np.abs(sp.u3_mid.values)) == 0.0
    diff = np.max(np.abs(sp.u2_mid.values - pl.u2_mid.values))
    assert np.max(np.abs(pl.u2_mid.values)) > 1e-3
    assert 1e-9 < diff < 1e-7, diff  # the coupling is there, and small
    np.testing.assert_allclose(sp.omega_n.values, pl.omega_n.values, rtol=1e-13)  # the in-plane Galerkin ones
    assert sp.omega_spatial.dims == ("direction", "mode") and sp.omega_spatial.attrs["units"] == "rad s-1"
    np.testing.assert_allclose(sp.omega_spatial.values[1], pl.omega_n.values, rtol=1e-13)


def _scipy_mass_matrix_run(cfg, sec, t_eval):
    """The spatial slider-crank, dry, in the trial functions' coordinates with the mass matrix (:class:`MassMatrixForm`)
    under :func:`lubelink.link.spatial.slider_crank_rssp`, by SciPy's DOP853."""
    from scipy.integrate import solve_ivp

    from lubelink.link.spatial_motion import geometry

    N, m = cfg.beam.modes, cfg.mechanism
    form = MassMatrixForm(trial_matrices(sec, N, cfg.beam.axial_end))
    geo = geometry(m)
    F = np.zeros((3, N))

    def f(t, y):
        A_O, w, al, *_ = spatial.slider_crank_rssp(t, m.crank_length, L, m.crank_speed, m.guide_distance,
                                                   geo.crank_axis, geo.crank_ref, geo.slider_point, geo.slider_dir)
        Q, Q_t = y[:3 * N].reshape(3, N), y[3 * N:].reshape(3, N)
        return np.concatenate([y[3 * N:], form(Q, Q_t, A_O, w, al, F).ravel()])

    return solve_ivp(f, (0.0, t_eval[-1]), np.zeros(6 * N), method="DOP853", t_eval=t_eval, rtol=1e-9,
                     atol=1e-15).y.T


@pytest.mark.parametrize("end", ["fixed", "free"])
def test_tapered_spatial_slider_crank_against_the_mass_matrix_form(end):
    """The whole run (eigen-coordinate state, exponential integrator exact on the 3N frequencies) against SciPy on
    the trial functions' equations with the mass matrix; both bending directions and the axial one."""
    over = {**TAPER, "film.model": "none", "solver.t_end": 0.05, "beam.axial_end": end, **TIGHT}
    ds = lubelink.simulate("spatial-slider-crank", set=over)
    assert ds.attrs["status"] == "complete" and ds.attrs["solver_method"] == "exponential"
    cfg = resolve("spatial-slider-crank", over)
    ref = _scipy_mass_matrix_run(cfg, tapered(), ds.time.values[1:])
    for k, name in enumerate(("u1", "u2", "u3")):
        u_ref = spatial.deflections(ref, [0.5], L, end)[k][:, 0]
        u = ds[name].sel(x=0.5, method="nearest").values[1:]
        peak = np.max(np.abs(u_ref))
        assert peak > (1e-7 if name == "u1" else 1e-4)
        np.testing.assert_allclose(u, u_ref, rtol=0, atol=1e-5 * peak)


def test_impacts_of_a_tapered_link_on_the_u2_faces_match_the_planar_model():
    """A dry tapered link in a 4.6 mm clearance, restitution law, 3 modes: the planar case of the spatial model
    hits at the planar tapered model's times with its velocities (the in-plane eigenbasis' restitution jump)."""
    over = {"solver.t_end": 0.45, "beam.modes": 3, "beam.width_ratio": 0.9, "beam.height_ratio": 1.05,
            "film.clearance": 4.6e-3, "contact.law": "restitution", **TIGHT}  # two models, not two integration errors
    pl = lubelink.simulate("paper-dry", set=over)
    sp = lubelink.simulate("paper-dry", set={**over, "beam.model": "spatial"})
    assert sp.attrs["status"] == pl.attrs["status"] == "complete"
    assert sp.sizes["impact"] == pl.sizes["impact"] >= 2
    np.testing.assert_allclose(sp.impact_time.values, pl.impact_time.values, rtol=0, atol=1e-5)
    np.testing.assert_allclose(sp.impact_velocity.values, pl.impact_velocity.values, rtol=2e-3)
    np.testing.assert_allclose(sp.impact_velocity_after.values, -0.7 * sp.impact_velocity.values, rtol=1e-9)
    assert np.max(np.abs(sp.u3.values)) == 0.0


# --- bad input ---------------------------------------------------------------------------------------------------
def test_a_section_without_I_y_or_not_positive_is_refused():
    cfg = resolve("spatial-slider-crank", {"solver.backend": "numpy"})
    planar_only = section.Section(area=lambda x: B * H + 0 * x, second_moment=lambda x: B * H**3 / 12 + 0 * x)
    with pytest.raises(lubelink.ConfigError, match="section second_moment_y: not given.*I_y"):
        build_model(cfg, section=planar_only)
    bad = section.Section(area=planar_only.area, second_moment=planar_only.second_moment,
                          second_moment_y=lambda x: 1e-10 - 2e-10 * x)
    with pytest.raises(lubelink.ConfigError, match=r"section second_moment_y: must be positive and finite on "
                                                   r"\[0, 1.0\] m; at x = 0.5"):
        build_model(cfg, section=bad)
    with pytest.raises(lubelink.ConfigError, match="section area: must be a callable"):
        build_model(cfg, section=section.Section(area=3.0, second_moment=planar_only.second_moment,
                                                 second_moment_y=planar_only.second_moment))
    # the planar model never needs I_y
    build_model(resolve("paper", {"solver.backend": "numpy"}), section=planar_only)


def test_the_command_line_runs_a_tapered_spatial_link_and_refuses_a_bad_ratio(tmp_path):
    out = tmp_path / "taper.nc"
    r = subprocess.run([sys.executable, "-m", "lubelink", "run", "--scenario", "spatial-slider-crank", "--set",
                        "beam.width_ratio=0.6", "--set", "beam.height_ratio=1.4", "--set", "solver.t_end=0.02",
                        "--set", "output.x_points=11", "-o", str(out)], capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    ds = lubelink.load(out)
    assert ds.attrs["status"] == "complete" and np.max(np.abs(ds.u3_mid.values)) > 0.0
    np.testing.assert_allclose(ds.omega_spatial.values.ravel(),
                               spatial_section.spatial_galerkin(tapered(), E, RHO, 3, L, axial_end="free")[0],
                               rtol=1e-13)  # the scenario's (default) free axial end
    bad = subprocess.run([sys.executable, "-m", "lubelink", "run", "--scenario", "spatial-slider-crank", "--set",
                          "beam.height_ratio=0.001", "-o", str(tmp_path / "x.nc")], capture_output=True, text=True,
                         timeout=300)
    assert bad.returncode == 2 and "beam.height_ratio = 0.001: must be a number in [0.01, 100]" in bad.stderr
    assert "Traceback" not in bad.stderr

"""The axial force of the spatial link's rigid motion and its geometric stiffness (``beam.model = "spatial"``,
``beam.axial_force = "inertial"``; lubelink.link.spatial_model, docs/model.md §1.5).

References, none of them the spatial code's: Newton-Euler on the RSSP slider-crank's rigid link in the fixed frame,
with positions from the mechanism's geometry alone and accelerations from their finite differences; the planar
model's axial force (itself tested against the planar Newton-Euler, tests/test_axial.py) on the planar case; a
link spinning about a fixed end out of its plane: the centrifugal tension and, by finite differences of
``EI u'''' - (N u')' = rho A w^2 u``, the flapwise (no frame softening) and lagwise (softened by ``Omega^2``)
frequencies of a rotating beam; the right-hand side's Jacobian against its central differences.
"""

from __future__ import annotations

import numpy as np
import pytest

import lubelink
from lubelink import energy
from conftest import central_differences
from lubelink.build import build_model
from lubelink.config import resolve
from lubelink.link import axial
from lubelink.link.spatial import SpatialRigidMotion
from lubelink.link.spatial_model import spatial_axial_terms, spatial_jacobian_given, spatial_rhs
from lubelink.link.spatial_motion import sampled_spatial_motion
from lubelink.validation import ConfigError
from test_axial import EI, RHO_A, fd_lowest_frequency

L = 1.0
ON = {"beam.axial_force": "inertial", "solver.backend": "numpy"}


def rssp_positions(t, m):
    """O, C of the RSSP slider-crank from its geometry alone: the crank pin on its tilted circle, C on the slider line
    ``(s, 0, z_P)`` at the link's length from it (the branch of larger ``s``)."""
    phi, tau = m.crank_speed * t, m.crank_tilt
    O = m.crank_length * np.array([np.cos(phi), np.sin(phi) * np.cos(tau), np.sin(phi) * np.sin(tau)])
    s = O[0] + np.sqrt(m.rod_length**2 - O[1] ** 2 - (O[2] - m.slider_offset) ** 2)
    return O, np.array([s, 0.0, m.slider_offset])


def newton_euler_axial_force(t, x, m, gravity):
    """N(x) [N] of the rigid RSSP link at ``t`` from Newton-Euler in the fixed frame.

    The acceleration of the link point at ``s`` is the 4th-order second difference (h = 2e-4 s) of ``O + s i``,
    ``i = (C - O) / L``. The slider pushes normal to its guide (``X``): ``V = (0, V_Y, V_Z)`` from the moments about
    O of it and of the d'Alembert load ``rho A (g - a)`` (24-point Gauss-Legendre; least squares over the three
    components, whose ``i`` component is 0 = 0); the segment ``[x, L]`` gives ``N(x) = (V + int_x^L ...) . i``.
    """
    h = 2e-4
    g = np.array([gravity[0], gravity[1], 0.0])

    def point(s, tt):
        O, C = rssp_positions(tt, m)
        return O + s * (C - O) / m.rod_length

    def acc(s):
        return (-point(s, t - 2 * h) + 16 * point(s, t - h) - 30 * point(s, t) + 16 * point(s, t + h)
                - point(s, t + 2 * h)) / (12 * h * h)

    O, C = rssp_positions(t, m)
    i = (C - O) / m.rod_length
    nodes, weights = np.polynomial.legendre.leggauss(24)

    def load(a, b):  # (force, moment about O) of the distributed load on [a, b]
        s = 0.5 * (b - a) * nodes + 0.5 * (b + a)
        f = np.array([RHO_A * (g - acc(si)) for si in s])
        r = np.array([si * i for si in s])
        return 0.5 * (b - a) * weights @ f, 0.5 * (b - a) * weights @ np.cross(r, f)

    moment = load(0.0, m.rod_length)[1]
    A = np.column_stack([np.cross(C - O, [0.0, 1.0, 0.0]), np.cross(C - O, [0.0, 0.0, 1.0])])
    VY, VZ = np.linalg.lstsq(A, -moment, rcond=None)[0]
    return (np.array([0.0, VY, VZ]) + load(x, m.rod_length)[0]) @ i


@pytest.mark.parametrize("sets", [
    {"mechanism.crank_tilt": 0.3},
    {"mechanism.crank_tilt": -0.5, "mechanism.slider_offset": 0.03, "mechanism.gravity": [3.0, -9.81]},
])
def test_the_spatial_axial_force_is_the_rigid_links_newton_euler(sets):
    """The RSSP slider-crank's N(x, t) against :func:`newton_euler_axial_force` over a turn (a tilted crank, and one
    with the slider line offset and gravity out of line): the finite differences err by ~1e-8 of N's ~50 N."""
    cfg = resolve("spatial-slider-crank", {**sets, **ON})
    model = build_model(cfg)
    p = model.params
    for t in np.linspace(0.0, 0.2, 9) + 0.0071:
        terms = spatial_axial_terms(p.geometric, model.motion.at(t), p)
        for x in (0.0, 0.37, 0.8, L):
            ref = newton_euler_axial_force(t, x, cfg.mechanism, cfg.mechanism.gravity)
            assert abs(axial.axial_force(x, terms) - ref) < 1e-6, (t, x, ref)


def test_the_planar_case_is_the_planar_link():
    """Planar geometry and motion, ``u1 = u3 = 0``: the axial force's change of the spatial right-hand side (its
    geometric stiffness and the chord's rotation) is, on the u2 rows, the planar model's, to round-off; nothing on
    the axial and u3 rows (the planar chord's rotation is tested on its own in tests/test_chord_rotation.py)."""
    N = 4
    over = {"beam.modes": N, "mechanism.gravity": [2.0, -9.81], **ON}
    pl_on, pl_off = (build_model(resolve("paper-dry", {**over, "beam.axial_force": a})) for a in ("inertial", "none"))
    sp_on, sp_off = (build_model(resolve("paper-dry", {**over, "beam.model": "spatial", "beam.axial_force": a}))
                     for a in ("inertial", "none"))
    assert sp_off.params.geometric is None
    rng = np.random.default_rng(7)
    zero = np.zeros(N)
    for t in rng.uniform(0.0, 0.2, 6):
        q2, v2 = rng.standard_normal(N) * 1e-3, rng.standard_normal(N) * 0.1
        y = np.r_[zero, q2, zero, zero, v2, zero]
        acc = pl_on.rhs(t, np.r_[q2, v2])[N:]
        planar = acc - pl_off.rhs(t, np.r_[q2, v2])[N:]
        got = sp_on.rhs(t, y) - sp_off.rhs(t, y)
        assert np.abs(planar).max() > 1e-4 * np.abs(acc).max()  # the term is there (the modes' own stiffness dominates)
        np.testing.assert_allclose(got[4 * N:5 * N], planar, rtol=0, atol=1e-12 * np.abs(acc).max())
        np.testing.assert_array_equal(got[:4 * N], 0.0)
        np.testing.assert_array_equal(got[5 * N:], 0.0)


def spinning(w):
    """A rigid motion spinning at ``w`` [rad/s] (link-frame components) about a fixed O, the frame on the fixed
    axes (the slider's guide along the link: it bears no axial share)."""
    nan3 = (np.nan, np.nan, np.nan)
    return SpatialRigidMotion((0.0, 0.0, 0.0), w, (0.0, 0.0, 0.0), 0.4, 0.0, (1.0, 0.0, 0.0), (0.0, 1.0, 0.0),
                              (0.0, 0.0, 1.0), nan3, nan3)


@pytest.mark.parametrize("spin", [40.0, 100.0])
def test_a_link_spinning_out_of_its_plane(spin):
    """Spun about ``e2`` at ``Omega``: the centrifugal tension ``rho A Omega^2 (L^2 - x^2) / 2``; its stiffness makes
    the lowest frequencies (of the right-hand side's Jacobian, 12 modes) those of the finite-difference rotating
    beam: ``u2`` (flapwise: out of the plane of rotation, no softening) ``omega_fd``, ``u3`` (lagwise: in it)
    ``omega_fd^2 - Omega^2``; sine modes to 2e-5 (test_axial's tolerance of the same comparison)."""
    N = 12
    model = build_model(resolve("paper-dry", {"beam.modes": N, "beam.model": "spatial", **ON}))
    p = model.params
    kin = spinning((0.0, spin, 0.0))
    terms = spatial_axial_terms(p.geometric, kin, p)
    x = np.linspace(0.0, L, 11)
    np.testing.assert_allclose(axial.axial_force(x, terms), RHO_A * spin**2 * (L**2 - x**2) / 2, rtol=1e-14,
                               atol=1e-12 * RHO_A * spin**2)
    J = np.empty((6 * N, 6 * N))
    spatial_jacobian_given(kin, np.zeros(6 * N), J, p)
    Jq = J[3 * N:, :3 * N]
    w_fd = fd_lowest_frequency(lambda s: RHO_A * spin**2 * (L**2 - s**2) / 2)
    flap = np.sqrt(np.linalg.eigvalsh(-Jq[N:2 * N, N:2 * N]).min())
    lag2 = np.linalg.eigvalsh(-Jq[2 * N:, 2 * N:]).min()
    assert abs(flap - w_fd) < 2e-5 * w_fd
    assert abs(lag2 - (w_fd**2 - spin**2)) < 4e-5 * w_fd**2
    assert w_fd > 1.05 * np.pi**2 * np.sqrt(EI / RHO_A)  # the tension does matter


@pytest.mark.parametrize("sets", [{"mechanism.crank_tilt": 0.3, "mechanism.gravity": [1.0, -9.81]},
                                  {"mechanism.crank_tilt": 0.3, "beam.axial_end": "fixed"}])
def test_the_jacobian_holds_the_geometric_stiffness_of_both_directions(sets):
    """The spatial right-hand side's Jacobian (an ``out`` of ``n + n^2``) with the axial force, against its central
    differences; the stiffness is there on both bending blocks."""
    cfg = resolve("spatial-slider-crank", {**sets, **ON})
    p = build_model(cfg).params
    N = cfg.beam.modes
    n = 6 * N
    rng = np.random.default_rng(11)
    y = np.concatenate([rng.standard_normal(3 * N) * 2e-7, rng.standard_normal(3 * N) * 1e-4])
    t = 0.137

    def f(x):
        d = np.empty(n)
        spatial_rhs.py_func(t, x, d, p)
        return d

    out = np.empty(n + n * n)
    spatial_rhs.py_func(t, y, out, p)
    J = out[n:].reshape(n, n)
    J_fd = central_differences(f, y, np.r_[np.full(3 * N, 1e-10), np.full(3 * N, 1e-7)])
    np.testing.assert_allclose(J, J_fd, rtol=0, atol=1e-6 * np.abs(J_fd).max())
    off = np.empty(n + n * n)
    without = build_model(resolve("spatial-slider-crank", {**sets, "beam.axial_force": "none"}))
    spatial_rhs.py_func(t, y, off, without.params)
    dJ = J - off[n:].reshape(n, n)
    M = 3 * N
    for b in (slice(M + N, M + 2 * N), slice(M + 2 * N, n)):
        assert np.abs(dJ[b, b.start - M:b.stop - M]).max() > 1e-3 * abs(J[b.start, b.start - M])  # of mode 1's


def test_the_energy_budget_closes_with_the_axial_force(monkeypatch):
    """The geometric stiffness's power on both directions is among the rigid motion's loads: the budget closes (on
    20 us samples, as tests/test_energy.py's spatial budgets: the axial modes vibrate), and without that power it
    does not."""
    sets = {"mechanism.crank_tilt": 0.3, "solver.t_end": 0.05, "solver.output_step": 2e-5, **ON}
    ds = lubelink.simulate("spatial-slider-crank", sets)
    assert ds.attrs["status"] == "complete"
    assert np.abs(ds.u3_mid.values).max() > 1e-6
    assert ds.attrs["energy_residual_relative"] < 2e-4, ds.attrs["energy_residual_relative"]
    monkeypatch.setattr(energy, "_spatial_geometric_power", lambda g, kin, yq, p: 0.0)
    missing = lubelink.simulate("spatial-slider-crank", sets).attrs["energy_residual_relative"]
    assert missing > 10 * ds.attrs["energy_residual_relative"], missing


@pytest.mark.slow  # compiles the spatial kernels with the geometric table (~17 s; the warm-up does not)
def test_the_compiled_kernels_equal_their_python_source():
    """spatial_rhs with the axial force, compiled and as Python, on random states (a tilted crank)."""
    cfg = resolve("spatial-slider-crank", {"mechanism.crank_tilt": 0.3, "beam.axial_force": "inertial"})
    model = build_model(cfg)
    assert model.compiled
    p, n = model.params, 6 * cfg.beam.modes
    rng = np.random.default_rng(2)
    for t in rng.uniform(0.0, 0.3, 4):
        y = np.concatenate([rng.standard_normal(n // 2) * 1e-6, rng.standard_normal(n // 2) * 1e-3])
        a, b = np.empty(n + n * n), np.empty(n + n * n)
        spatial_rhs(t, y, a, p)
        spatial_rhs.py_func(t, y, b, p)
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12 * np.abs(b).max())


def test_a_motion_of_the_users_and_a_taper_are_refused():
    """The slider's axial share needs its guide, which a motion from samples does not give; the P_k are the uniform
    link's."""
    cfg = resolve("spatial-slider-crank", {"beam.axial_force": "inertial"})
    model = build_model(resolve("spatial-slider-crank"))
    t = np.linspace(-0.01, cfg.solver.t_end + 0.01, 400)
    k = model.motion(t)
    motion = sampled_spatial_motion(t, k.A_O, k.omega, k.x_star, e1=k.e1, e2=k.e2)
    with pytest.raises(ConfigError, match="slider-crank's motion"):
        build_model(cfg, motion)
    with pytest.raises(ConfigError, match="uniform link only"):
        resolve("spatial-slider-crank", {"beam.axial_force": "inertial", "beam.width_ratio": 0.7})

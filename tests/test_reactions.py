"""The joint reactions of the planar link (lubelink.link.reactions) against rigid-body mechanics by finite
differences, beam theory's end shear, closed-form moments of the mass, and through a whole run."""

import numpy as np
import pytest
from scipy.integrate import quad

import lubelink
from lubelink.link.reactions import crank_pin_acceleration, joint_reactions, link_inertia
from lubelink.link.section import taper
from lubelink.params import Beam

OA, L, W0 = 0.07, 1.0, 10 * np.pi
BEAM = Beam()
RHO_A = BEAM.density * BEAM.area


def test_the_moments_of_the_mass_are_the_closed_forms_of_a_uniform_link_and_quadratures_of_a_taper():
    N = 5
    got = link_inertia(taper(BEAM, L), BEAM.density, L, N)
    n = np.arange(1, N + 1)
    beta = n * np.pi / L
    assert got.mass == pytest.approx(RHO_A * L, rel=1e-14)
    assert got.first == pytest.approx(RHO_A * L**2 / 2, rel=1e-14)
    assert got.second == pytest.approx(RHO_A * L**3 / 3, rel=1e-14)
    np.testing.assert_allclose(got.modal, RHO_A * (1 - np.cos(n * np.pi)) / beta, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(got.modal_first, -RHO_A * L * np.cos(n * np.pi) / beta, rtol=1e-12)
    tapered = Beam(width_ratio=0.5, height_ratio=0.7)
    got = link_inertia(taper(tapered, L), tapered.density, L, N)
    rho_A = lambda x: tapered.density * tapered.area * (1 - 0.5 * x / L) * (1 - 0.3 * x / L)
    assert got.second == pytest.approx(quad(lambda x: rho_A(x) * x * x, 0, L)[0], rel=1e-12)
    for k in range(N):
        assert got.modal_first[k] == pytest.approx(quad(lambda x: rho_A(x) * x * np.sin(beta[k] * x), 0, L,
                                                        limit=200)[0], rel=1e-10)


def rigid_slider_crank(t, h=1e-5):
    """Positions of O and C from the geometry, differentiated numerically: the link's motion as a rigid body."""
    def pose(t):
        phi = W0 * t
        O = OA * np.array([np.cos(phi), np.sin(phi)])
        C = np.array([OA * np.cos(phi) + np.sqrt(L**2 - (OA * np.sin(phi)) ** 2), 0.0])
        return O, C, np.arctan2(*(C - O)[::-1])

    poses = [pose(t + k * h) for k in (-1, 0, 1)]
    G = [(O + C) / 2 for O, C, _ in poses]
    a_G = (G[2] - 2 * G[1] + G[0]) / h**2
    angles = np.unwrap([a for _, _, a in poses])
    alpha = (angles[2] - 2 * angles[1] + angles[0]) / h**2
    omega = (angles[2] - angles[0]) / (2 * h)
    return poses[1], a_G, omega, alpha


@pytest.mark.parametrize("t", [0.0, 0.013, 0.041, 0.077])
@pytest.mark.parametrize("gravity", [(0.0, 0.0), (0.0, -9.81)])
def test_a_rigid_link_obeys_newton_and_euler_about_its_centre_of_mass(t, gravity):
    (O, C, angle), a_G, omega, alpha = rigid_slider_crank(t)
    m, I_G = RHO_A * L, RHO_A * L**3 / 12
    # unknowns R_OX, R_OY, R_C: m a_G = R_O + R_C Y + m g;  I_G alpha = (O - G) x R_O + (C - G) x R_C Y
    G = (O + C) / 2
    rO, rC = O - G, C - G
    A = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 1.0], [-rO[1], rO[0], rC[0]]])
    b = np.array([m * (a_G[0] - gravity[0]), m * (a_G[1] - gravity[1]), I_G * alpha])
    expected = np.linalg.solve(A, b)
    inertia = link_inertia(taper(BEAM, L), BEAM.density, L, 1)
    zero = np.zeros((1, 1))
    got = joint_reactions(inertia, L, np.array([angle]), crank_pin_acceleration(np.array([t]), OA, W0),
                          np.array([omega]), np.array([alpha]), zero, zero, zero,
                          (np.zeros(1), np.zeros(1), np.zeros(1)), gravity)
    np.testing.assert_allclose(np.ravel(got), expected, rtol=2e-5, atol=1e-6 * m * OA * W0**2)


def test_a_collar_load_on_a_link_at_rest_is_shared_by_the_lever_rule():
    inertia = link_inertia(taper(BEAM, L), BEAM.density, L, 1)
    one, zero = np.ones(1), np.zeros((1, 1))
    P, x = 3.0, 0.3  # along +j = +Y at angle 0, at x from O
    got = joint_reactions(inertia, L, 0 * one, (0 * one, 0 * one), 0 * one, 0 * one, zero, zero, zero,
                          (0 * one, P * one, P * x * one), (0.0, 0.0))
    np.testing.assert_allclose(np.ravel(got), [0.0, -P * (1 - x / L), -P * x / L], atol=1e-15)


@pytest.mark.parametrize("n", [1, 2, 3])
def test_the_pins_of_a_link_in_free_vibration_carry_the_end_shear_of_beam_theory(n):
    """One mode in free vibration is an exact solution of the beam equation: the pins carry its end shear,
    ``EI u'''(0)`` at O and ``-EI u'''(L)`` at C."""
    N, q = 3, 1e-3
    inertia = link_inertia(taper(BEAM, L), BEAM.density, L, N)
    beta = n * np.pi / L
    EI = BEAM.youngs_modulus * BEAM.second_moment
    omega_n2 = EI * beta**4 / RHO_A
    Q = np.zeros((1, N))
    Q[0, n - 1] = q
    one = np.ones(1)
    _, R_O, R_C = joint_reactions(inertia, L, 0 * one, (0 * one, 0 * one), 0 * one, 0 * one, Q, 0 * Q,
                                  -omega_n2 * Q, (0 * one, 0 * one, 0 * one), (0.0, 0.0))
    u3 = lambda x: -q * beta**3 * np.cos(beta * x)
    assert R_O[0] == pytest.approx(EI * u3(0.0), rel=1e-10)
    assert R_C[0] == pytest.approx(-EI * u3(L), rel=1e-10)


def test_a_run_reports_the_reactions_of_the_rigid_mechanism_when_the_link_is_stiff(short):
    ds = lubelink.simulate("paper", {**short, "beam.youngs_modulus": 1e13, "beam.damping_ratio": 0.3,
                                     "film.model": "none",
                                     "mechanism.gravity": [0.0, -9.81]})
    m = RHO_A * L
    for name in ("crank_pin_force_X", "crank_pin_force_Y", "slider_pin_force", "collar_force", "guide_force"):
        assert ds[name].attrs["units"] == "N"
    for k in (77, 150, 220, 299):  # (the free vibration from rest has died out, damped)
        t = float(ds.time[k])
        (O, C, angle), a_G, omega, alpha = rigid_slider_crank(t)
        G = (O + C) / 2
        rO, rC = O - G, C - G
        A = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 1.0], [-rO[1], rO[0], rC[0]]])
        expected = np.linalg.solve(A, [m * a_G[0], m * (a_G[1] + 9.81), m * L**2 / 12 * alpha])
        got = [float(ds[name][k]) for name in ("crank_pin_force_X", "crank_pin_force_Y", "slider_pin_force")]
        np.testing.assert_allclose(got, expected, rtol=1e-3, atol=1e-3 * m * OA * W0**2)


def test_the_collar_loads_enter_the_reactions_and_the_guide_force_is_their_component_along_X(short):
    mc, a = 0.2, 0.4
    ds = lubelink.simulate("paper", {**short, "film.sides": 2, "collar.mass": mc})
    t = ds.time.values
    angle = -np.arcsin(OA / L * np.sin(W0 * t))
    along, normal = ds["film_friction"].values, ds["collar_force"].values
    np.testing.assert_allclose(ds["guide_force"].values, along * np.cos(angle) - normal * np.sin(angle), rtol=1e-12,
                               atol=1e-12)

    def Y(t):  # height of the link under the guide X = a, from the geometry
        phi = W0 * t
        return OA * np.sin(phi) * (1 - (a - OA * np.cos(phi)) / np.sqrt(L**2 - (OA * np.sin(phi)) ** 2))

    h = 1e-5
    Y_ddot = (Y(t + h) - 2 * Y(t) + Y(t - h)) / h**2
    # beside the film, the collar's mass pushes the link by the joint reaction -m_c Y_ddot / cos(theta) along +j
    np.testing.assert_allclose(normal - ds["film_force"].values, -mc * Y_ddot / np.cos(angle), rtol=1e-4,
                               atol=1e-6 * mc * OA * W0**2)


def test_the_spatial_link_and_a_finite_width_film_store_no_reactions(short):
    ds = lubelink.simulate("paper", {**short, "film.reynolds": "short"})
    assert "crank_pin_force_X" not in ds and "film_friction" not in ds

"""The axial force of the rigid motion and its geometric stiffness (lubelink.link.axial, docs/model.md §1.4).

References, none of them lubelink's closed forms: SciPy quadrature of the slope moments; the centrifugal
tension of a link spinning about one end, ``rho A omega^2 (L^2 - x^2) / 2``; Newton-Euler on the slider-crank's
rigid link in the fixed frame, with accelerations from finite differences of the mechanism's positions; the
pinned-pinned beam under a constant axial force, ``omega_1^2 = beta^2 (EI beta^2 + P) / (rho A)`` (and buckling at
``P = -EI pi^2 / L^2``); a finite-difference eigen-solution of ``EI u'''' - (N u')' = rho A w^2 u`` for an
``N`` that varies along the link; the model's right-hand side and Jacobian against these and its own differences.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.linalg import eigh

import lubelink
from lubelink.build import build_model
from lubelink.config import resolve
from lubelink.link import axial
from lubelink.link.kinematics import PrescribedMotion, SliderCrank, pin_axial_acceleration, sampled_motion, slider_crank
from lubelink.link.model import rhs
from lubelink.params import Mechanism
from lubelink.validation import ConfigError

# the paper's rod, written out (a changed default cannot move the reference)
E, RHO, B, HH, L = 207e9, 7650.0, 0.01, 0.01, 1.0
RHO_A, EI = RHO * B * HH, E * B * HH**3 / 12.0
P_CR = EI * np.pi**2 / L**2  # Euler load [N]


# ------------------------------------------------------------------ slope moments
@pytest.mark.parametrize("rod_length", [1.0, 1.7])
def test_slope_moments_are_the_integrals(rod_length):
    """``P[k, m, n] = int_0^L x^k phi_m' phi_n' dx`` against quad, k = 0, 1, 2, modes 1..5 (quad to 1e-12)."""
    P = axial.slope_moments(5, rod_length)
    for k in range(3):
        for m in range(1, 6):
            for n in range(1, 6):
                bm, bn = m * np.pi / rod_length, n * np.pi / rod_length
                ref = quad(lambda x: x**k * bm * np.cos(bm * x) * bn * np.cos(bn * x), 0.0, rod_length,
                           epsabs=1e-12, epsrel=1e-12, limit=200)[0]
                assert abs(P[k, m - 1, n - 1] - ref) < 1e-11 * max(1.0, bm * bn * rod_length**(k + 1))


# ------------------------------------------------------------------ the axial force
def test_a_link_spinning_about_its_end_is_in_centrifugal_tension():
    """O at rest, the link turning uniformly, no slider force: ``N = rho A omega^2 (L^2 - x^2) / 2`` at every angle
    (the slider's share, ``F_C2 tan(angle)``, vanishes with no transverse load)."""
    x = np.linspace(0.0, L, 11)
    for omega, angle in ((3.0, 0.0), (-7.0, 0.6), (12.0, -1.1)):
        terms = axial.rigid_axial_force(0.0, 0.0, omega, 0.0, angle, 0.0, 0.4, (0.0, 0.0), RHO_A, L)
        np.testing.assert_allclose(axial.axial_force(x, terms), RHO_A * omega**2 * (L**2 - x**2) / 2,
                                   rtol=1e-14, atol=1e-14 * RHO_A * omega**2)


def positions(t, m):
    """O, C and ``i`` of the slider-crank from its geometry alone (crank pin on the circle, C on the +X axis)."""
    phi = m.crank_speed * np.asarray(t, dtype=float)
    O = m.crank_length * np.stack([np.cos(phi), np.sin(phi)])
    C = np.stack([O[0] + np.sqrt(m.rod_length**2 - O[1] ** 2), np.zeros_like(phi)])
    return O, C, (C - O) / m.rod_length


def newton_euler_axial_force(t, x, m, rho_A, gravity, collar_mass):
    """N(x) [N] at one time from the rigid link's Newton-Euler equations in the fixed frame.

    The acceleration of the link point at ``s`` is the second difference (4th order, h = 2e-4 s) of
    ``O + s i``. The slider's force is ``V e_Y``; ``V`` from the moments about O of it, of the distributed
    d'Alembert load ``rho A (g - a(s))`` (Gauss-Legendre) and of the collar's force ``R j`` at ``x_star``. The
    segment ``[x, L]`` then gives the tension ``N(x) = (V e_Y + int_x^L rho A (g - a) ds) . i``.
    """
    h = 2e-4
    g = np.asarray(gravity, dtype=float)

    def point(s, tt):
        O, _, i = positions(tt, m)
        return O + s * i

    def acc(s):
        return (-point(s, t - 2 * h) + 16 * point(s, t - h) - 30 * point(s, t) + 16 * point(s, t + h)
                - point(s, t + 2 * h)) / (12 * h * h)

    O, C, i = positions(t, m)
    j = np.array([-i[1], i[0]])
    k = slider_crank(t, m.crank_length, m.rod_length, m.crank_speed, m.guide_distance)
    R = SliderCrank(m).joint_reaction(t, collar_mass)
    nodes, weights = np.polynomial.legendre.leggauss(24)

    def load(a, b):  # (force, moment about O) of the distributed load on [a, b]
        s = 0.5 * (b - a) * nodes + 0.5 * (b + a)
        f = np.array([rho_A * (g - acc(si)) for si in s])
        r = np.array([si * i for si in s])
        return 0.5 * (b - a) * weights @ f, 0.5 * (b - a) * weights @ (r[:, 0] * f[:, 1] - r[:, 1] * f[:, 0])

    moment_load = load(0.0, m.rod_length)[1] + k["x_star"] * R  # (x_star i) x (R j) = x_star R k
    V = -moment_load / (C - O)[0]  # (C - O) x (V e_Y) = (C - O)_X V k
    return (V * np.array([0.0, 1.0]) + load(x, m.rod_length)[0]) @ i


@pytest.mark.parametrize("gravity, collar_mass", [((0.0, 0.0), 0.0), ((3.0, -9.81), 0.8)])
def test_the_axial_force_is_the_rigid_links_newton_euler(gravity, collar_mass):
    """The slider-crank's N(x, t) against :func:`newton_euler_axial_force` over a turn (the paper's mechanism,
    and one with gravity out of line and a collar mass). The finite differences err by ~1e-8 of ``N``'s
    ~50 N, the 24-point quadrature of a smooth load by less: 1e-6 N."""
    m = Mechanism()
    R_mass = collar_mass
    for t in np.linspace(0.0, 0.2, 9) + 0.0071:
        k = slider_crank(t, m.crank_length, m.rod_length, m.crank_speed, m.guide_distance)
        angle = -k["theta"]
        A_O1 = pin_axial_acceleration(t, angle, m.crank_length, m.crank_speed)
        R = SliderCrank(m).joint_reaction(t, R_mass)
        terms = axial.rigid_axial_force(A_O1, k["A_O2"], k["omega"], k["alpha"], angle, R, k["x_star"], gravity,
                                        RHO_A, L)
        for x in (0.0, 0.37, 0.8, L):
            ref = newton_euler_axial_force(t, x, m, RHO_A, gravity, collar_mass)
            assert abs(axial.axial_force(x, terms) - ref) < 1e-6, (t, x)


# ------------------------------------------------------------------ geometric stiffness
def lowest_frequency(terms, modes=1):
    """The lowest circular frequency [rad/s] of the sine-mode link with the axial force ``terms``."""
    beta = np.arange(1, modes + 1) * np.pi / L
    m = RHO_A * L / 2
    K = np.diag(m * EI / RHO_A * beta**4) + axial.geometric_stiffness(axial.slope_moments(modes, L), terms)
    w2 = eigh(K, m * np.eye(modes), eigvals_only=True)[0]
    return np.sign(w2) * np.sqrt(abs(w2))


@pytest.mark.parametrize("P", [0.0, 500.0, 3000.0, -800.0, -P_CR])
def test_a_constant_axial_force_shifts_the_first_frequency(P):
    """Pinned-pinned beam under a constant ``P`` (tension positive): ``omega_1^2 = beta^2 (EI beta^2 + P) / (rho A)``
    with ``beta = pi / L``; zero at the Euler load ``P = -EI pi^2 / L^2``."""
    beta = np.pi / L
    exact = beta**2 * (EI * beta**2 + P) / RHO_A
    w = lowest_frequency((P, 0.0, 0.0), modes=4)
    assert abs(w**2 - exact) < 1e-10 * beta**4 * EI / RHO_A


def fd_lowest_frequency(N_of_x, points=600):
    """The lowest frequency of ``EI u'''' - (N u')' = rho A w^2 u``, pinned-pinned, by central differences on
    ``points`` intervals (``u = u'' = 0``: the fourth difference is the square of the Dirichlet second one)."""
    h = L / points
    n = points - 1
    D2 = (np.diag(np.full(n, -2.0)) + np.diag(np.ones(n - 1), 1) + np.diag(np.ones(n - 1), -1)) / h**2
    Nh = N_of_x((np.arange(points) + 0.5) * h)  # at the half points x_{i+1/2}, i = 0..points-1
    G = (np.diag(Nh[:-1] + Nh[1:]) - np.diag(Nh[1:-1], 1) - np.diag(Nh[1:-1], -1)) / h**2  # -(N u')'
    return np.sqrt(eigh(EI * D2 @ D2 + G, RHO_A * np.eye(n), eigvals_only=True)[0])


@pytest.mark.parametrize("terms", [(-600.0, 900.0, 0.0), (200.0, -300.0, -400.0), (50.0, 0.0, -1500.0)])
def test_a_varying_axial_force_against_finite_differences(terms):
    """``N = c0 + c1 x + c2 x^2`` varying along the link (compression at one end, tension at the other): the
    lowest frequency of 12 sine modes against 600 finite-difference intervals (error O(h^2) ~ 1e-6 relative;
    the sine modes converge as the Rayleigh-Ritz bound from above, to better than 1e-6 here)."""
    w_fd = fd_lowest_frequency(lambda x: axial.axial_force(x, terms))
    w = lowest_frequency(terms, modes=12)
    assert abs(w - w_fd) < 2e-5 * w_fd
    assert abs(w - lowest_frequency((0.0, 0.0, 0.0))) > 1e-3 * w_fd  # the axial force does matter here


# ------------------------------------------------------------------ in the model
SETS = {"beam.modes": 4, "beam.axial_force": "inertial", "mechanism.gravity": (2.0, -9.81), "collar.mass": 0.6,
        "solver.backend": "numpy"}


def test_the_right_hand_side_adds_minus_k_q_over_the_modal_mass():
    """``dq_dot/dt`` with the axial force minus without it is ``(-K q + F_c) / m``, ``K`` the quadrature of the
    Newton-Euler ``N(x)`` (cubic fit of 9 samples, exact for the quadratic) times ``phi_m' phi_n'``, ``F_c`` the
    chord rotation's forces at the resulting accelerations (tests/test_chord_rotation.py tests them)."""
    on, off = build_model(resolve("paper-dry", SETS)), build_model(resolve("paper-dry", {**SETS, "beam.axial_force": "none"}))
    assert off.params.geometric is None
    rng = np.random.default_rng(5)
    y = np.r_[rng.standard_normal(4) * 1e-3, rng.standard_normal(4) * 0.1]
    t = 0.0437
    xs = np.linspace(0.0, L, 9)
    coef = np.polyfit(xs, [newton_euler_axial_force(t, x, Mechanism(), RHO_A, (2.0, -9.81), 0.6) for x in xs], 3)
    K = np.empty((4, 4))
    for m in range(4):
        for n in range(4):
            bm, bn = (m + 1) * np.pi / L, (n + 1) * np.pi / L
            K[m, n] = quad(lambda x: np.polyval(coef, x) * bm * np.cos(bm * x) * bn * np.cos(bn * x), 0.0, L,
                           epsabs=1e-12, limit=200)[0]
    acc = on.rhs(t, y)[4:]
    got = acc - off.rhs(t, y)[4:]
    g, k = on.params.geometric, slider_crank(t, 0.07, L, 10 * np.pi, 0.4)
    F_c = np.empty(4)
    axial.chord_rotation_force(g.lever, g.slopes, RHO_A, L, -k["theta"], k["omega"], k["alpha"], y[:4], y[4:], acc,
                               F_c)
    assert np.abs(F_c).max() > 1e-3 * np.abs(K @ y[:4]).max()  # the chord's rotation is there
    np.testing.assert_allclose(got, (-K @ y[:4] + F_c) / (RHO_A * L / 2), rtol=0,
                               atol=1e-6 * np.abs(K @ y[:4]).max())


def test_the_jacobian_holds_the_geometric_stiffness():
    """The right-hand side's Jacobian (an ``out`` of ``n + n^2``) with the axial force on, against its differences."""
    model = build_model(resolve("paper-dry", SETS))
    p, n = model.params, 8
    y = np.r_[np.full(4, 1e-4), np.full(4, 1e-2)]
    out = np.empty(n + n * n)
    rhs.py_func(0.2, y, out, p)

    def f(x):
        d = np.empty(n)
        rhs.py_func(0.2, x, d, p)
        return d

    J_fd = np.column_stack([(f(y + e) - f(y - e)) / (2 * e[k]) for k, e in enumerate(np.eye(n) * 1e-6)])
    np.testing.assert_allclose(out[n:].reshape(n, n), J_fd, rtol=0, atol=1e-7 * np.abs(J_fd).max())
    off = np.empty(n + n * n)
    rhs.py_func(0.2, y, off, build_model(resolve("paper-dry", {**SETS, "beam.axial_force": "none"})).params)
    assert np.abs(out[n:] - off[n:]).max() > 1e-3 * np.abs(J_fd).max()  # the term is there


@pytest.mark.parametrize("drive", [{}, {"drive.law": "torque", "drive.torque": 2.0, "drive.flywheel_inertia": 0.05}])
def test_the_energy_budget_closes_with_the_axial_force(drive):
    """The geometric stiffness's power is among the rigid motion's loads: the budget still closes (0.1 s), with the
    prescribed crank speed and with the driven crank (its motion from samples, ``A_O1`` among them)."""
    ds = lubelink.simulate("paper-dry", {**SETS, **drive, "solver.t_end": 0.1, "solver.output_step": 1e-3})
    assert ds.attrs["status"] == "complete"
    assert ds.attrs["energy_residual_relative"] < 2e-4, ds.attrs["energy_residual_relative"]


@pytest.mark.parametrize("sets, words", [
    ({"beam.axial_force": "elastic"}, "beam.axial_force = 'elastic': must be one of \"auto\", \"none\", \"inertial\""),
    ({"beam.axial_force": "inertial", "beam.width_ratio": 0.7}, "uniform link only"),
])
def test_bad_settings_are_named(sets, words):
    with pytest.raises(ConfigError, match=words.replace("(", r"\(")):
        resolve("paper-dry", sets)


def test_a_motion_without_the_pins_axial_acceleration_is_refused():
    """A motion from samples or callables without ``A_O1`` cannot give the axial force: refused, in one line."""
    t = np.linspace(0.0, 0.3, 50)
    k = slider_crank(t, 0.07, 1.0, 10 * np.pi, 0.4)
    config = resolve("paper-dry", {"beam.axial_force": "inertial"})
    for motion in (sampled_motion(t, k["A_O2"], k["omega"], k["x_star"]),
                   PrescribedMotion(*(lambda s, v=v: np.interp(s, t, k[v]) for v in
                                      ("A_O2", "omega", "alpha", "x_star", "V_r")))):
        with pytest.raises(ConfigError, match="needs the axial acceleration of O") as info:
            build_model(config, motion)
        assert all("\n" not in line for line in info.value.problems)
    build_model(resolve("paper-dry", {"beam.axial_force": "none"}), motion)  # without the axial force it runs


def test_a_sampled_slider_crank_with_its_axial_acceleration_runs_as_the_closed_form():
    """The slider-crank given as samples every 0.5 ms (with ``A_O1``, the link angle and the collar's reaction)
    runs, compiled, the closed form's run with the axial force: the splines err by ~(omega0 dt)^4 / 77 ~ 1e-8 of
    each quantity, the runs by 1e-5 of the peak deflection (the tolerances, 1e-9, below that)."""
    sets = {**SETS, "solver.backend": "numba", "solver.t_end": 0.3, "solver.rtol": 1e-9, "solver.atol": 1e-12}
    config = resolve("paper-dry", sets)
    m = config.mechanism
    t = np.arange(0.0, 0.4, 5e-4)
    k = slider_crank(t, m.crank_length, m.rod_length, m.crank_speed, m.guide_distance)
    reaction = SliderCrank(m).joint_reaction(t, config.collar.mass)
    motion = sampled_motion(t, k["A_O2"], k["omega"], k["x_star"], alpha=k["alpha"], V_r=k["V_r"], reaction=reaction,
                            angle=-k["theta"], A_O1=k["A_O1"])
    ref = lubelink.simulate("paper-dry", sets)
    ds = lubelink.simulate(config, motion=motion)
    assert ds.attrs["status"] == ref.attrs["status"] == "complete"
    peak = float(np.abs(ref["u2_mid"].values).max())
    np.testing.assert_allclose(ds["u2_mid"].values, ref["u2_mid"].values, rtol=0, atol=1e-5 * peak)
    off = lubelink.simulate("paper-dry", {**sets, "beam.axial_force": "none"})
    assert np.abs(off["u2_mid"].values - ref["u2_mid"].values).max() > 1e-3 * peak  # the force is there


def test_auto_runs_the_axial_force_where_the_model_has_it():
    """``"auto"`` (the default; the paper's scenarios set ``"none"``) is ``"inertial"`` on the uniform link under the
    slider-crank, at constant speed or driven, and under a motion that gives ``A_O1``; ``"none"`` on a taper, a
    given section, a motion without ``A_O1`` and a driven crank whose slider has a mass or a load. The model's
    configuration holds what it ran with."""
    from lubelink.build import axial_force_of
    from lubelink.link.section import taper
    from lubelink.params import Config

    assert Config().beam.axial_force == "auto"
    assert {resolve(s).beam.axial_force for s in ("paper", "paper-dry", "paper-impact")} == {"none"}
    assert resolve("lubricated").beam.axial_force == "auto"
    auto = resolve("paper-dry", {"beam.axial_force": "auto", "beam.modes": 2})
    t = np.linspace(0.0, 2.1, 400)
    k = slider_crank(t, 0.07, 1.0, 10 * np.pi, 0.4)
    driven = {"drive.law": "torque", "drive.torque": 1.0}
    cases = [
        (auto, None, None, "inertial"),
        (resolve(auto, driven), None, None, "inertial"),
        (auto, sampled_motion(t, k["A_O2"], k["omega"], k["x_star"], A_O1=k["A_O1"]), None, "inertial"),
        (auto, sampled_motion(t, k["A_O2"], k["omega"], k["x_star"]), None, "none"),
        (resolve(auto, {"beam.width_ratio": 0.7}), None, None, "none"),
        (auto, None, taper(auto.beam, 1.0), "none"),
        (resolve(auto, {**driven, "drive.slider_force": 5.0}), None, None, "none"),
        (resolve(auto, {"beam.axial_force": "none"}), None, None, "none"),
    ]
    for config, motion, section, expected in cases:
        assert axial_force_of(config, motion, section) == expected, (config.beam, config.drive, motion, section)
    model = build_model(auto)
    assert model.config.beam.axial_force == "inertial" and model.params.geometric is not None
    model = build_model(resolve(auto, {"beam.width_ratio": 0.7}))
    assert model.config.beam.axial_force == "none" and model.params.geometric is None

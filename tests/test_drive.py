"""The crank driven through a flywheel (lubelink.link.drive): against the mechanism's geometry typed here
independently, energy conservation, closed forms from energy, the infinite-flywheel limit and Newton-Euler."""

import numpy as np
import pytest
from scipy.optimize import brentq

from lubelink import ConfigError, simulate
from lubelink.config import from_dict, parse_toml, resolve
from lubelink.link import drive
from lubelink.link.reactions import joint_reactions, link_inertia
from lubelink.link.section import taper
from lubelink.params import Drive


def _config(**drive_keys):
    sets = {f"drive.{k}": v for k, v in drive_keys.items()}
    return resolve("paper-dry", {"drive.law": "torque", **sets})


# ------------------------------------------------------------ the mechanism's geometry, typed here
def _positions(phi, m):
    """``(O, C, psi, Y)``: crank pin and slider [m], link angle [rad], height of the link under the guide [m]."""
    OA, L, a = m.crank_length, m.rod_length, m.guide_distance
    O = np.array([OA * np.cos(phi), OA * np.sin(phi)])
    C = np.array([OA * np.cos(phi) + np.sqrt(L * L - (OA * np.sin(phi)) ** 2), 0.0 * phi])
    psi = np.arctan2(C[1] - O[1], C[0] - O[0])
    return O, C, psi, O[1] + (a - O[0]) * np.tan(psi)


def _inertia_and_potential(phi, m, masses, force=0.0, h=1e-5):
    """``M(phi)`` from central differences of the positions (uniform link: centre at L/2, ``I_G = m L^2/12``) and
    the potential of gravity and of a constant slider force ``V(phi)`` [J]."""
    def coefficients(f):
        return [(p - q) / (2 * h) for p, q in zip(f(phi + h), f(phi - h))]

    gO, gC, gpsi, gY = coefficients(lambda p: _positions(p, m))
    gG = 0.5 * (gO + gC)
    L, mass = m.rod_length, masses.link_mass
    M = (masses.flywheel + mass * (gG ** 2).sum(axis=0) + mass * L * L / 12 * gpsi ** 2
         + masses.slider * gC[0] ** 2 + masses.collar * gY ** 2)
    O, C, _, Y = _positions(phi, m)
    g = np.array(masses.gravity)
    V = -(mass * (g @ (0.5 * (O + C))) + masses.slider * g[0] * C[0] + masses.collar * g[1] * Y) - force * C[0]
    return M, V


def _slider_x(phi, m):
    return _positions(phi, m)[1][0]


MASSES = dict(flywheel_inertia=0.02, slider_mass=0.4)


def test_inertia_velocity_term_and_gravity_match_the_geometry():
    c = resolve("paper-dry", {"drive.law": "torque", "drive.flywheel_inertia": 0.02, "drive.slider_mass": 0.4,
                              "collar.mass": 0.3, "mechanism.gravity": [3.0, -9.81]})
    m, ms = c.mechanism, drive.rigid_masses(c)
    phi = np.linspace(0.0, 2 * np.pi, 97)
    M, V = _inertia_and_potential(phi, m, ms)
    # central differences of smooth functions at h = 1e-5: about 1e-10 relative
    assert np.allclose(drive.generalised_inertia(phi, m, ms), M, rtol=1e-8, atol=0)
    h = 1e-3  # truncation ~1e-7 of M', the inner differences' noise ~1e-12 J / h: 5e-7 measured
    dM = (_inertia_and_potential(phi + h, m, ms)[0] - _inertia_and_potential(phi - h, m, ms)[0]) / (2 * h)
    assert np.allclose(drive.velocity_torque(phi, 2.0, m, ms), 0.5 * dM * 4.0, rtol=0, atol=3e-6 * np.abs(dM).max())
    dV = (_inertia_and_potential(phi + h, m, ms)[1] - _inertia_and_potential(phi - h, m, ms)[1]) / (2 * h)
    assert np.allclose(drive.gravity_torque(phi, m, ms), -dV, rtol=0, atol=3e-6 * np.abs(dV).max())
    # the slider stays on its guide: crank_state's accelerations at C have no vertical part
    from lubelink.link.kinematics import crank_state

    theta, _, A1, A2, w, al, *_ = crank_state(phi, 3.0, -7.0, m.crank_length, m.rod_length, m.guide_distance)
    L = m.rod_length
    assert np.allclose(-np.sin(theta) * (A1 - w * w * L) + np.cos(theta) * (A2 + al * L), 0.0, atol=1e-12)


def test_free_crank_conserves_energy_and_follows_the_energy_closed_form():
    """(a) No motor torque, no losses: ``M phi_dot^2 / 2 + V`` constant, ``phi_dot(phi)`` from it."""
    c = resolve("paper-dry", {"drive.law": "torque", "drive.flywheel_inertia": 0.005, "drive.slider_mass": 0.4,
                              "drive.slider_force": 15.0, "mechanism.gravity": [0.0, -9.81]})
    m, ms = c.mechanism, drive.rigid_masses(c)
    sol = drive.integrate_crank(c, 0.6, ms)
    t = np.linspace(0.0, 0.6, 1201)
    phi, phi_dot, _, torque = sol(t)
    M, V = _inertia_and_potential(phi, m, ms, force=15.0)
    E = 0.5 * M * phi_dot ** 2 + V
    assert np.ptp(0.5 * M * phi_dot ** 2) > 0.05 * E[0]  # a real exchange of kinetic and potential energy
    assert np.ptp(E) < 1e-9 * abs(E[0]) + 1e-10 * np.ptp(V)  # tolerances 1e-11: drift of a few 1e-10
    closed = np.sqrt(2.0 * (E[0] - V) / M)
    assert np.allclose(phi_dot, closed, rtol=1e-8, atol=0)
    assert np.all(torque == 0.0)


def _crank(c, t_end):
    return drive.integrate_crank(c, t_end)


def test_speed_fluctuation_against_energy_closed_form():
    """(c) Constant torque balancing the slider's Coulomb friction: the energy, hence ``phi_dot(phi)``, is periodic
    in ``phi`` and known in closed form; the fluctuation coefficient follows."""
    F_f = 40.0
    c0 = resolve("paper-dry", {"drive.law": "torque", "drive.flywheel_inertia": 0.02, "drive.slider_mass": 0.4,
                               "drive.slider_friction": F_f})
    m = c0.mechanism
    OA = m.crank_length
    T = 2.0 * F_f * OA / np.pi  # the friction's work in a turn, 4 F_f OA (stroke 2 OA), over 2 pi
    c = resolve(c0, {"drive.torque": T})
    ms = drive.rigid_masses(c)
    period = 2 * np.pi / m.crank_speed
    sol = drive.integrate_crank(c, 3.2 * period, ms)
    X0, Xpi = _slider_x(0.0, m), _slider_x(np.pi, m)

    def omega_closed(phi):
        p = np.mod(phi, 2 * np.pi)
        travel = np.where(p <= np.pi, X0 - _slider_x(p, m), (X0 - Xpi) + _slider_x(p, m) - Xpi)
        work = T * p - F_f * travel
        M0 = _inertia_and_potential(np.array([0.0]), m, ms)[0][0]
        return np.sqrt((M0 * m.crank_speed ** 2 + 2.0 * work) / _inertia_and_potential(p, m, ms)[0])

    t = np.linspace(0.0, 3.2 * period, 4001)
    phi, phi_dot, _, _ = sol(t)
    assert np.allclose(phi_dot, omega_closed(phi), rtol=1e-8, atol=0)
    # the fluctuation coefficient (omega_max - omega_min) / omega_mean over a turn, omega_mean = 2 pi / period
    grid = np.linspace(0.0, 2 * np.pi, 20001)
    w = omega_closed(grid)
    f = 1.0 / w
    period_closed = np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(grid))
    delta_closed = (w.max() - w.min()) * period_closed / (2 * np.pi)
    t_turns = [brentq(lambda s, k=k: sol.solution(s)[0] - 2 * np.pi * k, (k - 0.5) * period, (k + 0.5) * period,
                      xtol=1e-14) for k in (1, 2, 3)]
    tt = np.linspace(t_turns[1], t_turns[2], 20001)
    w_run = sol(tt)[1]
    delta_run = (w_run.max() - w_run.min()) * (t_turns[2] - t_turns[1]) / (2 * np.pi)
    assert 0.005 < delta_closed < 0.2
    assert abs(t_turns[2] - t_turns[1] - period_closed) < 1e-7 * period_closed  # the trapezoidal rule's error
    assert abs(delta_run - delta_closed) < 1e-6 * delta_closed


def test_torque_speed_line_reaches_its_steady_mean_speed():
    """(d) Mean motor torque = mean load torque: ``T_s (1 - <phi_dot>_phi / omega_nl) = 2 F_f OA / pi`` exactly, the
    mean over the crank angle of a periodic motion (a constant slider force does no work in a turn)."""
    F_f, T_s, w_nl = 30.0, 50.0, 40.0
    c = resolve("paper-dry", {"drive.law": "torque-speed", "drive.flywheel_inertia": 0.02, "drive.slider_mass": 0.4,
                              "drive.slider_friction": F_f, "drive.slider_force": -20.0, "drive.stall_torque": T_s,
                              "drive.no_load_speed": w_nl})
    m = c.mechanism
    tau = 0.02 * w_nl / T_s  # the speed's time constant, 16 ms
    sol = drive.integrate_crank(c, 80 * tau)
    expected = w_nl * (1.0 - 2.0 * F_f * m.crank_length / (np.pi * T_s))
    phi_end = sol.solution(80 * tau)[0]
    k = np.floor(phi_end / (2 * np.pi))
    t1, t2 = (brentq(lambda s, j=j: sol.solution(s)[0] - 2 * np.pi * j, 0.0, 80 * tau, xtol=1e-14) for j in (k - 1, k))
    x, wq = np.polynomial.legendre.leggauss(40)
    mean = 0.0  # int phi_dot dphi = int phi_dot^2 dt over the turn, by Gauss-Legendre on 200 panels
    edges = np.linspace(t1, t2, 201)
    for a, b in zip(edges[:-1], edges[1:]):
        mean += 0.5 * (b - a) * np.sum(wq * sol(0.5 * (b - a) * x + 0.5 * (a + b))[1] ** 2)
    mean /= 2 * np.pi
    assert t1 > 50 * tau  # the transient has decayed as exp(-50)
    assert abs(mean - expected) < 1e-8 * expected
    assert abs(expected - m.crank_speed) > 0.1 * expected  # not the initial speed


def test_elastic_torque_matches_newton_euler_pin_force():
    """The torque of the elastic motion on the crank (virtual power) against the crank pin's force of
    :func:`lubelink.link.reactions.joint_reactions` (Newton-Euler on the link), for arbitrary modal states."""
    c = _config()
    m, N = c.mechanism, 3
    rng = np.random.default_rng(3)
    phi = rng.uniform(0, 2 * np.pi, 50)
    phi_dot, phi_ddot = rng.uniform(20, 40, 50), rng.uniform(-300, 300, 50)
    q, q_dot, q_ddot = (rng.normal(0, s, (50, N)) for s in (1e-3, 0.05, 5.0))
    inertia = link_inertia(taper(c.beam, m.rod_length), c.beam.density, m.rod_length, N)
    from lubelink.link.kinematics import crank_state

    theta, _, _, _, w, al, *_ = crank_state(phi, phi_dot, phi_ddot, m.crank_length, m.rod_length, m.guide_distance)
    OA = m.crank_length
    a_O = (OA * (-phi_ddot * np.sin(phi) - phi_dot ** 2 * np.cos(phi)),
           OA * (phi_ddot * np.cos(phi) - phi_dot ** 2 * np.sin(phi)))

    def crank_torque(qq, qd, qdd):  # of the link on the crank about its axis: r_O x (-R_O)
        X, Y, _ = joint_reactions(inertia, m.rod_length, -theta, a_O, w, al, qq, qd, qdd, (0.0, 0.0, 0.0), (0.0, 0.0))
        return -(OA * np.cos(phi) * Y - OA * np.sin(phi) * X)

    zero = np.zeros_like(q)
    expected = crank_torque(q, q_dot, q_ddot) - crank_torque(zero, zero, zero)
    got = drive.elastic_torque(phi, phi_dot, phi_ddot, q, q_dot, q_ddot, m, inertia)
    assert np.allclose(got, expected, rtol=1e-10, atol=1e-12 * np.abs(expected).max())
    # and the rigid part: the pin's torque on the crank is minus the link's generalised inertia force
    rigid = drive.inertia_torque(phi, phi_dot, phi_ddot, m, drive.rigid_masses(c)._replace(flywheel=0.0))
    assert np.allclose(crank_torque(zero, zero, zero), -rigid, rtol=1e-10, atol=1e-12 * np.abs(rigid).max())


@pytest.mark.parametrize("axial_force", ["none", "inertial"])
def test_large_flywheel_converges_to_the_prescribed_speed_as_one_over_J(axial_force):
    """(b) The prescribed speed is the infinite flywheel's limit: the elastic link's response converges as
    ``1/J_f``, without and with the axial force (which reads the pin's axial acceleration from the driven
    motion's samples, the prescribed run from the closed form)."""
    base = {"solver.t_end": 0.3, "solver.backend": "numpy", "solver.rtol": 1e-10, "solver.atol": 1e-13,
            "solver.method": "DOP853", "beam.axial_force": axial_force}
    prescribed = simulate("paper-dry", base)
    errors = []
    inertias = np.array([0.5, 2.0, 8.0])
    for J in inertias:
        ds = simulate("paper-dry", {**base, "drive.law": "torque", "drive.flywheel_inertia": float(J)})
        errors.append(float(np.max(np.abs(ds["u2_mid"].values - prescribed["u2_mid"].values))))
        assert ds.attrs["status"] == "complete"
        assert ds["crank_speed"].attrs["units"] == "rad s-1" and "crank_angle" in ds.coords
    rate = np.polyfit(np.log(inertias), np.log(errors), 1)[0]
    assert -1.1 < rate < -0.9, (errors, rate)
    assert errors[-1] < 1e-3 * float(np.max(np.abs(prescribed["u2_mid"].values)))


def test_the_driven_pin_accelerates_along_the_link_as_its_positions_say():
    """The driven motion's ``A_O1`` channel (what the axial force reads) against central differences of the crank
    pin's position ``O = OA (cos phi, sin phi)`` along the link's ``i`` from the positions typed here, at the
    integrated crank angle (a torque that speeds the crank up by 10 rad/s in 0.3 s). The splines through 512
    samples a turn err by ~(2 pi / 512)^4 / 77 ~ 3e-10 of the ~120 m/s^2; the second differences (h = 1e-4 s) of
    the crank's dense output by more, 2e-4 m/s^2 (their truncation ~h^2 OA omega^4 / 12 ~ 5e-5 and the dense
    output's error over h^2): the tolerance, 1e-5 of the peak, is 6 times that."""
    config = resolve("paper-dry", {"drive.law": "torque", "drive.torque": 2.0, "drive.flywheel_inertia": 0.05,
                                   "solver.t_end": 0.3})
    motion = drive.driven_motion(config)
    m = config.mechanism
    t, h = np.linspace(0.01, 0.29, 57), 1e-4

    def pin(s):
        phi = motion.crank.solution(s)[0]
        return m.crank_length * np.array([np.cos(phi), np.sin(phi)])

    a_O = (pin(t + h) - 2.0 * pin(t) + pin(t - h)) / (h * h)
    psi = _positions(motion.crank.solution(t)[0], m)[2]
    expected = a_O[0] * np.cos(psi) + a_O[1] * np.sin(psi)
    assert np.ptp(motion.crank.solution(t)[1]) > 1.0  # the crank speed does change
    np.testing.assert_allclose(motion(t).A_O1, expected, rtol=0, atol=1e-5 * np.abs(expected).max())
    assert motion.gives_axial_acceleration


def test_speed_law_is_the_prescribed_motion():
    """The default ``drive.law = "speed"`` builds the slider-crank's closed-form motion (today's results)."""
    from lubelink.build import build_model
    from lubelink.link.kinematics import SliderCrank

    assert resolve("paper").drive == Drive()
    assert type(build_model(resolve("paper")).motion) is SliderCrank


def test_drive_keys_from_toml_and_overrides():
    c = from_dict(parse_toml('[drive]\nlaw = "torque-speed"\nflywheel_inertia = 2\nno_load_speed = 40.0\n', "t.toml"))
    assert (c.drive.law, c.drive.flywheel_inertia, c.drive.no_load_speed) == ("torque-speed", 2.0, 40.0)
    assert resolve("paper", {"drive.slider_mass": 1.5}).drive.slider_mass == 1.5


@pytest.mark.parametrize("sets, needle", [
    ({"drive.law": "motor"}, "drive.law = 'motor': must be one of \"speed\", \"torque\""),
    ({"drive.flywheel_inertia": 0.0}, "drive.flywheel_inertia = 0.0: must be a number in (0, 1e6]"),
    ({"drive.slider_mass": -1.0}, "drive.slider_mass = -1.0: must be a number in [0, 1e6]"),
    ({"drive.slider_friction": -2.0}, "drive.slider_friction = -2.0: must be a number in [0, 1e9]"),
    ({"drive.law": "torque-speed", "drive.no_load_speed": -5.0}, "drive.no_load_speed = -5.0: must be non-zero and "
                                                                  "of the sign of mechanism.crank_speed"),
    ({"drive.law": "torque", "beam.model": "spatial"}, "drive.law = 'torque': a driven crank is not supported with "
                                                       "beam.model = 'spatial'"),
    ({"drive.flywheel": 1.0}, "unknown key drive.flywheel"),
    ({"drive.law": "torque", "beam.axial_force": "inertial", "drive.slider_mass": 0.4},
     "beam.axial_force = 'inertial' with drive.slider_mass = 0.4: the slider's own loads on the link's axial force"),
])
def test_validation_names_key_value_and_range(sets, needle):
    with pytest.raises(ConfigError) as info:
        resolve("paper", sets)
    assert any(needle in line and "\n" not in line for line in info.value.problems), info.value.problems


def test_controller_holds_the_set_speed():
    """A PI controller against a constant load torque: the integral action removes the steady error (the speed
    returns to ``mechanism.crank_speed`` on average over a turn)."""
    c = _config(law="controller", flywheel_inertia=0.05, slider_friction=30.0, proportional_gain=2.0,
                integral_gain=20.0)
    sol = drive.integrate_crank(c, 3.0)
    w0 = c.mechanism.crank_speed
    t_turn = 2 * np.pi / w0
    t = np.linspace(3.0 - t_turn, 3.0, 4001)
    phi, phi_dot, _, torque = sol(t)
    assert abs(np.mean(phi_dot) - w0) < 2e-3 * w0
    assert abs(np.mean(torque) - 2 * 30.0 * c.mechanism.crank_length / np.pi) < 0.02 * np.mean(torque)


def test_tabulated_rates_match_the_crank_equation():
    """:class:`drive.TabulatedRates` (the integrator's right-hand side) against :func:`drive.crank_rates` at random
    states, with gravity, a collar, the slider's force and friction (whose torque has kinks at the dead centres)
    and a further torque: to 1e-11 of the acceleration's scale (the splines' error, ~1e-14 of each term)."""
    c = resolve("paper-dry", {"drive.law": "controller", "drive.slider_mass": 0.4, "drive.slider_friction": 20.0,
                              "drive.slider_force": 15.0, "mechanism.gravity": [3.0, -9.81], "collar.mass": 0.3})
    ms = drive.rigid_masses(c)

    def torque(t):
        return 0.3 * np.sin(150.0 * t)

    tab = drive.TabulatedRates(c, ms, torque)
    rng = np.random.default_rng(2)
    states = [(rng.uniform(0, 2), [rng.uniform(-20, 20), rng.choice([-1, 1]) * rng.uniform(5, 40), rng.normal()])
              for _ in range(500)]
    exact = np.array([drive.crank_rates(t, y, c, ms, torque) for t, y in states])
    got = np.array([tab(t, y) for t, y in states])
    scale = np.abs(exact[:, 1]).max()
    assert np.allclose(got[:, 1], exact[:, 1], rtol=0, atol=1e-11 * scale)
    assert np.array_equal(got[:, [0, 2]], exact[:, [0, 2]])


def test_compiled_crank_integration_matches_scipy_dop853_at_a_tight_tolerance():
    """The crank integrated by the project's compiled DOP853 (integrate.dense_steps) against SciPy's ``solve_ivp``
    on the same right-hand side at 1e-13, with the slider's friction (kinks at the dead centres), a controller and
    a further torque as a piecewise cubic (the coupling's elastic torque, zero after its last knot): at the
    default 1e-11 as close to it as SciPy's own run at 1e-11, within 1e-8 of the speed; the interpolant
    continuous across steps."""
    from scipy.interpolate import CubicSpline

    c = resolve("paper-dry", {"drive.law": "controller", "drive.slider_mass": 0.4, "drive.slider_friction": 20.0,
                              "drive.slider_force": 15.0, "mechanism.gravity": [3.0, -9.81], "drive.proportional_gain": 2.0,
                              "drive.integral_gain": 20.0})
    knots = np.linspace(0.0, 0.5, 2001)
    torque = CubicSpline(knots, 0.3 * np.sin(150.0 * knots) + 0.1 * np.cos(900.0 * knots))
    ref = drive.integrate_crank(c, 0.8, rtol=1e-13, atol=1e-14, torque=torque, method="scipy")
    t = np.linspace(0.0, 0.8, 4001)
    scale = c.mechanism.crank_speed
    sol = drive.integrate_crank(c, 0.8, torque=torque)  # at the default 1e-11: as accurate as SciPy's at 1e-11
    same = drive.integrate_crank(c, 0.8, torque=torque, method="scipy")
    for k in (0, 1):
        error, scipy_error = (np.abs(s.solution(t)[k] - ref.solution(t)[k]).max() for s in (sol, same))
        assert error < 2.0 * scipy_error + 1e-12 * scale and error < 1e-8 * scale, (k, error, scipy_error)
    steps = sol.solution
    inner = steps.ts[1:-1]
    left, right = steps(np.nextafter(inner, -np.inf)), steps(inner)  # the end of a step, the start of the next
    assert np.allclose(left, right, rtol=1e-12, atol=1e-12)
    assert steps(0.3).shape == (3,) and steps(t).shape == (3, t.size)
    without = drive.integrate_crank(c, 0.8)  # the torque matters (the test can fail)
    assert np.abs(without.solution(t)[1] - ref.solution(t)[1]).max() > 1e-6 * scale

"""Slider-crank kinematics against docs/model.md §3 and independent geometry.

Everything here is checked against something computed without
``lubelink.link.kinematics``' closed forms: the independently computed reference
table of docs/model.md §3, and positions built from the mechanism's
geometry (crank pin on a circle, slider on the X axis, collar under a
vertical guide) differentiated by 4th-order central finite differences.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from lubelink.link.kinematics import (
    PrescribedMotion,
    SliderCrank,
    collar_many,
    collar_travel,
    motion_at,
    sampled_motion,
    slider_crank,
)
from lubelink.params import Mechanism

PAPER = Mechanism()  # OA = 0.07 m, L = 1 m, omega0 = 10 pi rad/s, a = 0.4 m


def kin(t, m=PAPER):
    return slider_crank(t, m.crank_length, m.rod_length, m.crank_speed, m.guide_distance)


# ----------------------------------------------------------- independent geometry
def geometry(t, m=PAPER):
    """Positions of the mechanism from first principles (no closed-form rates).

    Crank pin O on the circle of radius OA about the fixed pivot; slider C on
    the +X axis at distance L from O; the rod point under the guide is where
    the segment O->C crosses X = a.
    """
    t = np.asarray(t, dtype=float)
    phi = m.crank_speed * t
    O = m.crank_length * np.stack([np.cos(phi), np.sin(phi)])
    C = np.stack([O[0] + np.sqrt(m.rod_length**2 - O[1] ** 2), np.zeros_like(t)])
    i = (C - O) / m.rod_length  # unit vector O -> C
    j = np.stack([-i[1], i[0]])  # k x i
    x_star = (m.guide_distance - O[0]) / i[0]  # distance from O along the rod to X = a
    P = O + x_star * i  # the rod point under the guide
    psi = np.arctan2(i[1], i[0])  # rod angle about +k (= -theta)
    return {"O": O, "C": C, "i": i, "j": j, "x_star": x_star, "P": P, "psi": psi}


def d1(f, t, h):
    """4th-order central first derivative."""
    return (f(t - 2 * h) - 8 * f(t - h) + 8 * f(t + h) - f(t + 2 * h)) / (12 * h)


def d2(f, t, h):
    """4th-order central second derivative."""
    return (-f(t - 2 * h) + 16 * f(t - h) - 30 * f(t) + 16 * f(t + h) - f(t + 2 * h)) / (12 * h**2)


# Times spread over more than one crank turn, avoiding special angles.
T = np.linspace(0.0, 0.25, 41) + 0.0123
# Step sizes (paper crank, omega0 = 31.4 rad/s): the n-th time derivative of
# a quantity of amplitude |f| is ~ |f| omega0^n. For d1 with h = 1e-4 s the
# truncation error h^4 f^(5)/30 and the round-off eps |f|/h are both
# ~ 1e-12 |f'|; for d2 with h = 3e-4 s the truncation h^4 f^(6)/90 and the
# round-off 5 eps |f|/h^2 are both ~ 1e-10 |f''| (observed: 1e-11 and 2e-8
# m/s^2 on amplitudes of 2 m/s and 70 m/s^2). Tolerances are a fraction of
# the amplitude of the checked quantity, ~10-100x above the observed errors.
H1, H2 = 1e-4, 3e-4
RTOL1, RTOL2 = 1e-10, 2e-9


def test_reference_table_section3():
    """docs/model.md §10.4 reference values at t = 0.0123 s (computed independently).

    The table is printed to 9 significant figures, so rel 5e-9 is half a unit
    in the last printed digit (plus margin).
    """
    k = kin(0.0123)
    expected = {
        "v_O1": -0.882231298,
        "A_O2": -27.7161137,
        "omega": -2.03767396,
        "alpha": 25.9364645,
        "x_star": 0.33527809,
        "V_r": 0.847100609,
    }
    for name, value in expected.items():
        assert float(k[name]) == pytest.approx(value, rel=1e-8, abs=0), name


def test_geometry_matches_closed_forms():
    """theta, cos(theta) and x_star agree with the positions (pure trigonometry, round-off)."""
    k, g = kin(T), geometry(T)
    np.testing.assert_allclose(-k["theta"], g["psi"], rtol=0, atol=1e-14)
    np.testing.assert_allclose(k["cos_theta"], g["i"][0], rtol=1e-14)
    np.testing.assert_allclose(k["x_star"], g["x_star"], rtol=1e-13)
    # the collar point really is under the guide and inside the rod
    np.testing.assert_allclose(g["P"][0], PAPER.guide_distance, rtol=1e-14)
    assert np.all((g["x_star"] > 0) & (g["x_star"] < PAPER.rod_length))


def test_rates_by_finite_differences():
    """omega = d(-theta)/dt, alpha = d omega/dt, V_r = dx*/dt, A_r = dV_r/dt (all from positions)."""
    k = kin(T)
    geo = lambda name: (lambda s: geometry(s)[name])  # noqa: E731
    np.testing.assert_allclose(k["omega"], d1(geo("psi"), T, H1), rtol=0, atol=RTOL1 * 2.2)
    np.testing.assert_allclose(k["alpha"], d2(geo("psi"), T, H2), rtol=0, atol=RTOL2 * 70)
    # and alpha is also the derivative of the module's own omega (consistency of the pair)
    np.testing.assert_allclose(k["alpha"], d1(lambda s: kin(s)["omega"], T, H1), rtol=0, atol=RTOL1 * 70)
    np.testing.assert_allclose(k["V_r"], d1(geo("x_star"), T, H1), rtol=0, atol=RTOL1 * 2.2)
    np.testing.assert_allclose(k["A_r"], d2(geo("x_star"), T, H2), rtol=0, atol=RTOL2 * 70)
    np.testing.assert_allclose(k["A_r"], d1(lambda s: kin(s)["V_r"], T, H1), rtol=0, atol=RTOL1 * 70)


def test_crank_pin_velocity_and_acceleration_in_rod_frame():
    """v_O1 = dO/dt . i, A_O1 = d2O/dt2 . i and A_O2 = d2O/dt2 . j, i and j from the positions; the motion the
    compiled code reads (:func:`motion_at` of the slider-crank's table) gives the same A_O1."""
    k, g = kin(T), geometry(T)
    vO = d1(lambda s: geometry(s)["O"], T, H1)
    aO = d2(lambda s: geometry(s)["O"], T, H2)
    np.testing.assert_allclose(k["v_O1"], np.sum(vO * g["i"], axis=0), rtol=0, atol=RTOL1 * 2.2)
    np.testing.assert_allclose(k["A_O1"], np.sum(aO * g["i"], axis=0), rtol=0, atol=RTOL2 * 70)
    np.testing.assert_allclose(k["A_O2"], np.sum(aO * g["j"], axis=0), rtol=0, atol=RTOL2 * 70)
    table = SliderCrank(PAPER).table()
    A_O1 = np.array([motion_at(s, table).A_O1 for s in T])
    np.testing.assert_allclose(A_O1, np.sum(aO * g["i"], axis=0), rtol=0, atol=RTOL2 * 70)
    np.testing.assert_array_equal(SliderCrank(PAPER)(T).A_O1, k["A_O1"])


def test_collar_vertical_acceleration():
    """Y_ddot is the second derivative of the Y coordinate of the rod point under the guide."""
    k = kin(T)
    Y_dd = d2(lambda s: geometry(s)["P"][1], T, H2)
    np.testing.assert_allclose(k["Y_ddot"], Y_dd, rtol=0, atol=RTOL2 * 70)


def test_chord_point_transverse_acceleration():
    """docs/model.md §1.3: the chord point at x has transverse acceleration A_O2 + alpha x.

    Checked at x = 0.3 and x = L on the rigid rod by differentiating its
    position twice and projecting on j.
    """
    k, g = kin(T), geometry(T)
    for x in (0.3, PAPER.rod_length):
        acc = d2(lambda s: (lambda gg: gg["O"] + x * gg["i"])(geometry(s)), T, H2)
        np.testing.assert_allclose(k["A_O2"] + k["alpha"] * x, np.sum(acc * g["j"], axis=0),
                                   rtol=0, atol=RTOL2 * 100)


def test_joint_reaction_force_balance():
    """D7: the collar (mass m) moves vertically with Y_ddot; the guide pushes horizontally
    only and the rod pushes it along j. The force of the collar on the rod along +j is
    then -m Y_ddot / cos(theta) (vertical balance N j_Y = m Y_ddot, j_Y = cos theta)."""
    m = 0.8
    g = geometry(T)
    Y_dd = d2(lambda s: geometry(s)["P"][1], T, H2)
    N_on_collar = m * Y_dd / g["j"][1]
    R = SliderCrank(PAPER).joint_reaction(T, m)
    np.testing.assert_allclose(R, -N_on_collar, rtol=0, atol=RTOL2 * 70 * m)
    assert np.all(SliderCrank(PAPER).joint_reaction(T, 0.0) == 0.0)


def test_collar_travel_paper():
    """docs/model.md §3: x_star in [0.330, 0.470] m and max |V_r| = 2.2054 m/s.

    The extremes are also checked against a dense scan of the independent
    geometry (2e5 samples per turn: sampling error of an extreme ~ x''dt^2/8
    ~ 1e-10 m).
    """
    lo, hi = collar_travel(PAPER)
    assert lo == pytest.approx(0.330, abs=5e-4)  # MODEL prints 3 decimals
    assert hi == pytest.approx(0.470, abs=5e-4)
    ts = np.linspace(0.0, 2 * np.pi / PAPER.crank_speed, 200_001)
    xs = geometry(ts)["x_star"]
    assert lo == pytest.approx(xs.min(), abs=1e-9)
    assert hi == pytest.approx(xs.max(), abs=1e-9)
    assert lo <= xs.min() + 1e-12 and hi >= xs.max() - 1e-12  # polished, not just sampled
    vmax = np.abs(kin(ts)["V_r"]).max()
    assert vmax == pytest.approx(2.2054, abs=5e-5)  # MODEL prints 5 significant figures


def test_slider_crank_motion_provider():
    """SliderCrank returns the slider_crank values in RigidMotion order."""
    k = kin(T)
    mo = SliderCrank(PAPER)(T)
    for name in ("A_O2", "omega", "alpha", "x_star", "V_r"):
        np.testing.assert_array_equal(getattr(mo, name), k[name])
    assert SliderCrank(PAPER).period == pytest.approx(0.2)


def test_prescribed_motion_broadcasts_constants():
    mo = PrescribedMotion(lambda t: 3.0, lambda t: 0.0 * t, lambda t: 0.0, lambda t: 0.4, lambda t: 0.0)
    out = mo(np.linspace(0, 1, 5))
    assert all(np.shape(v) == (5,) for v in out)
    assert np.all(out.A_O2 == 3.0) and np.all(out.x_star == 0.4)
    assert np.all(mo.joint_reaction(np.linspace(0, 1, 5), 1.0) == 0.0)


def test_sampled_motion_reproduces_slider_crank():
    """Cubic splines through samples every 1 ms (omega0 dt = 0.031 rad).

    Spline interpolation error ~ (5/384) (omega0 dt)^4 |f| = 1.3e-8 |f| and
    the error of its derivative ~ (omega0 dt)^3 / 24 |f'| = 1.3e-6 |f'|
    (observed 3e-9 and 2.5e-7). Values are checked to 2e-8 and the derived
    rates (alpha from omega, V_r from x_star) to 2e-6 of their amplitude, on
    a dense grid that skips 10 samples at each end, where the not-a-knot end
    conditions are less accurate (5e-6 there).
    """
    ts = np.arange(0.0, 0.4 + 1e-12, 1e-3)
    k = kin(ts)
    mo = sampled_motion(ts, k["A_O2"], k["omega"], k["x_star"])
    tm = np.linspace(ts[10], ts[-11], 20_001)
    ref, got = SliderCrank(PAPER)(tm), mo(tm)
    for name, rel in (("A_O2", 2e-8), ("omega", 2e-8), ("x_star", 2e-8), ("alpha", 2e-6), ("V_r", 2e-6)):
        r, g = getattr(ref, name), getattr(got, name)
        np.testing.assert_allclose(g, r, rtol=0, atol=rel * np.abs(r).max(), err_msg=name)
    # explicit alpha and V_r samples are interpolated, not differentiated
    mo2 = sampled_motion(ts, k["A_O2"], k["omega"], k["x_star"], alpha=k["alpha"], V_r=k["V_r"], A_O1=k["A_O1"])
    np.testing.assert_allclose(mo2(tm).alpha, ref.alpha, rtol=0, atol=2e-8 * np.abs(ref.alpha).max())
    np.testing.assert_allclose(mo2(ts).V_r, k["V_r"], rtol=1e-12, atol=1e-14)
    # A_O1 is a channel of its own: interpolated in Python and in the compiled table alike; absent, NaN
    np.testing.assert_allclose(mo2(tm).A_O1, ref.A_O1, rtol=0, atol=2e-8 * np.abs(ref.A_O1).max())
    table = mo2.table()
    np.testing.assert_allclose([motion_at(s, table).A_O1 for s in tm[::500]], ref.A_O1[::500], rtol=0,
                               atol=2e-8 * np.abs(ref.A_O1).max())
    assert mo2.gives_axial_acceleration and not mo.gives_axial_acceleration and np.all(np.isnan(mo(tm).A_O1))


def test_collar_samples_of_the_compiled_motion_are_the_geometry():
    """``collar_many`` (the results' x_star, V_r, through the compiled motion table) against the
    first-principles geometry and its finite-difference rate, for the slider-crank and a sampled motion."""
    t = np.linspace(0.0, 0.4, 401)
    h = 1e-5
    x_geo = geometry(t)["x_star"]
    v_geo = d1(lambda s: geometry(s)["x_star"], t, h)
    x_star, V_r = collar_many(t, SliderCrank(PAPER).table())
    np.testing.assert_allclose(x_star, x_geo, rtol=0, atol=1e-13)
    np.testing.assert_allclose(V_r, v_geo, rtol=0, atol=1e-8)
    knots = np.linspace(0.0, 0.4, 801)
    k = kin(knots)
    motion = sampled_motion(knots, k["A_O2"], k["omega"], k["x_star"], alpha=k["alpha"], V_r=k["V_r"])
    x_star, V_r = collar_many(t, motion.table())
    np.testing.assert_allclose(x_star, x_geo, rtol=0, atol=1e-9)
    np.testing.assert_allclose(V_r, v_geo, rtol=0, atol=1e-6)


@pytest.mark.parametrize("bad_t", [[0.0, 1.0, 2.0], [0.0, 2.0, 1.0, 3.0], [[0.0, 1.0], [2.0, 3.0]]])
def test_sampled_motion_rejects_bad_times(bad_t):
    n = np.size(bad_t)
    with pytest.raises(ValueError):
        sampled_motion(bad_t, np.zeros(n), np.zeros(n), np.zeros(n))


def test_sampled_motion_rejects_nonfinite():
    t = np.linspace(0, 1, 6)
    with pytest.raises(ValueError):
        sampled_motion(t, np.r_[np.nan, np.zeros(5)], np.zeros(6), np.zeros(6))


# ----------------------------------------------------------------- random mechanisms
@st.composite
def mechanisms(draw):
    """Valid mechanisms: crank shorter than half the rod, guide strictly between the
    extreme crank-pin abscissa (OA) and the closest slider position (L - OA)."""
    L = draw(st.floats(0.2, 5.0))
    lam = draw(st.floats(0.01, 0.45))
    OA = lam * L
    frac = draw(st.floats(0.02, 0.98))
    a = OA + frac * (L - 2 * OA)
    w0 = draw(st.floats(0.5, 200.0)) * draw(st.sampled_from([1.0, -1.0]))
    return Mechanism(crank_length=OA, rod_length=L, crank_speed=w0, guide_distance=a)


@settings(deadline=None, suppress_health_check=[HealthCheck.too_slow])  # examples: the profile (conftest)
@given(m=mechanisms(), phase=st.floats(0.0, 2 * math.pi))
def test_collar_point_is_under_guide_random_mechanisms(m, phase):
    """For any valid mechanism the rod point at x_star (module) has X = a, lies on the rod,
    and V_r, omega are the time derivatives of x_star and of the rod angle."""
    t = (phase + np.linspace(0.0, 2 * math.pi, 25)) / abs(m.crank_speed)
    k = kin(t, m)
    phi = m.crank_speed * t
    O = m.crank_length * np.stack([np.cos(phi), np.sin(phi)])
    C_x = O[0] + np.sqrt(m.rod_length**2 - O[1] ** 2)
    i = np.stack([C_x - O[0], -O[1]]) / m.rod_length
    P = O + k["x_star"] * i
    np.testing.assert_allclose(P[0], m.guide_distance, rtol=1e-12, atol=1e-12 * m.rod_length)
    assert np.all((k["x_star"] > 0) & (k["x_star"] < m.rod_length))
    # derivatives: time scaled by the crank speed, so the FD accuracy argument
    # of H1/RTOL1 above carries over (h omega0 = 3e-3 rad)
    h = 3e-3 / abs(m.crank_speed)
    x_of = lambda s: (m.guide_distance - m.crank_length * np.cos(m.crank_speed * s)) / np.sqrt(  # noqa: E731
        1 - (m.crank_length * np.sin(m.crank_speed * s) / m.rod_length) ** 2)
    scale_v = m.crank_length * abs(m.crank_speed) * 10  # |V_r| <~ OA w0 (1 + a/L ...)
    np.testing.assert_allclose(k["V_r"], d1(x_of, t, h), rtol=0, atol=1e-8 * scale_v)
    psi_of = lambda s: -np.arcsin(m.crank_length / m.rod_length * np.sin(m.crank_speed * s))  # noqa: E731
    np.testing.assert_allclose(k["omega"], d1(psi_of, t, h), rtol=0, atol=1e-8 * abs(m.crank_speed))

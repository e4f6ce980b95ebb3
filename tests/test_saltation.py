"""Saltation matrices: the monodromy through impacts from the variational equations.

References: a closed form (the half-period map of an undamped oscillator bouncing on a wall is
``e I``), Liouville's formula with the determinant ``e^2`` of a restitution impact's saltation
matrix, central differences of the period map (and of the model's own impact and gap for the
written-out reset Jacobian), and a graze made to be one.
"""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from lubelink.build import build_model
from lubelink.config import resolve
from lubelink.jumps import approach_jacobian, restitution_terms, restitution_terms_by_differences, unsupported
from lubelink.steady import ShootingError, find_periodic
from lubelink.steady import saltation
from lubelink.steady.saltation import Grazing, compose, saltation_matrix

#: The impacting orbit of tests/test_periodic.py: three impacts a period, e = 0.7, the film off.
IMPACT = {"beam.damping_ratio": 0.05, "film.model": "none", "film.clearance": 3.6e-3, "contact.restitution": 0.7}


def rotation(t, w=1.0):
    """The flow's Jacobian of ``x'' = -w^2 x`` over ``t`` [s] (state ``[x, v]``)."""
    return np.array([[math.cos(w * t), math.sin(w * t) / w], [-w * math.sin(w * t), math.cos(w * t)]])


@pytest.mark.parametrize("e", [0.0, 0.5, 1.0])
def test_oscillator_bouncing_on_a_wall_has_the_closed_form_monodromy(e):
    # x'' = -x from (1, 0): the wall x = 0 at t = pi/2 (v = -1), v+ = -e v-, then x = e sin(t - pi/2) to t = pi.
    # The motion is homogeneous of degree 1 in the start (and a start shifted along the orbit is the
    # same orbit shifted in time), so the map (1, 0) -> (e, 0) has the Jacobian e I.
    f_minus, f_plus = np.array([-1.0, 0.0]), np.array([e, 0.0])
    S = saltation_matrix(np.diag([1.0, -e]), np.zeros(2), np.array([1.0, 0.0]), -1.0, f_minus, f_plus,
                         rate_scale=np.ones(2))
    np.testing.assert_allclose(S, -e * np.eye(2), atol=1e-15)
    M = compose([rotation(math.pi / 2), rotation(math.pi / 2)], [S])
    np.testing.assert_allclose(M, e * np.eye(2), atol=1e-15)


def test_a_graze_is_reported_not_divided_by():
    # a trajectory touching the wall: its rate along the flow is 1e-6 of the velocities' size
    args = (np.diag([1.0, -0.7]), np.zeros(2), np.array([1.0, 0.0]), -1e-6, np.array([-1e-6, -1.0]),
            np.array([0.7e-6, -1.0]))
    with pytest.raises(Grazing, match="graze.*1e-06"):
        saltation_matrix(*args, rate_scale=np.ones(2))
    assert np.isfinite(saltation_matrix(*args, rate_scale=np.ones(2), grazing=1e-7)).all()
    with pytest.raises(Grazing):  # a rate that is not a number is no crossing either
        saltation_matrix(*args[:3], np.nan, *args[4:], rate_scale=np.ones(2))


@pytest.mark.parametrize("where", ["interior", "edge"])
def test_written_out_reset_jacobian_matches_differences_of_the_impact(where):
    config = resolve("paper-impact", {**IMPACT, "beam.modes": 3})
    model = build_model(config)
    y = np.array([1.6e-3, 2e-4, -1e-4, 0.05, -0.02, 0.01])
    # a time when the thinnest film is inside the pad, or at an edge with the collar sliding fastest (the
    # reset's slope term V_r u2' is then largest)
    ts = np.linspace(0.0, 0.06, 601)
    edge = np.array([model.thinnest_film(t, y)[2] for t in ts])
    speed = np.array([abs(model.kinematics(t).V_r) for t in ts])
    t = float(ts[np.argmax(~edge if where == "interior" else np.where(edge, speed, 0.0))])
    assert model.thinnest_film(t, y)[2] == (where == "edge")
    assert model.approach(t, y)[0] > 0.0  # closing: the restitution law jumps
    y_plus = model.impact(t, y)[0]
    scale = np.array([2e-3] * 3 + [0.05] * 3)
    exact = restitution_terms(model, t, y, y_plus, scale, 0.01)
    approx = restitution_terms_by_differences(model, t, y, y_plus, scale, 0.01)
    for name in ("reset_jacobian", "reset_rate", "gradient"):
        a, b = getattr(exact, name), getattr(approx, name)
        assert np.max(np.abs(a - b)) <= 1e-6 * max(np.max(np.abs(b)), 1e-300), name
    if where == "edge":  # the collar's slope term makes the reset depend on the displacements and on time
        assert np.max(np.abs(exact.reset_jacobian[3:, :3])) > 1.0 and np.max(np.abs(exact.reset_rate)) > 0.0
    # the event's rate is grad g . f_- plus its explicit time derivative (zero inside the pad)
    if where == "interior":
        assert exact.rate == pytest.approx(exact.gradient @ exact.f_minus, rel=1e-9)
    # the thinnest film's point, which a sustained contact holds (lubelink.phases): written out against
    # central differences of the film's own search, inside the pad (at an edge it moves with the collar)
    N, L = 3, config.mechanism.rod_length
    _, x_c, at_edge, side = model.thinnest_film(t, y)
    _, _, _, _, dx_dq, dx_dt = approach_jacobian(y[:N], y[N:], x_c, at_edge, side, model.kinematics(t).V_r, 0.0, L)
    h = 1e-7 * scale[:N]
    found = [(model.thinnest_film(t, y + np.r_[h[n] * np.eye(N)[n], np.zeros(N)])[1]
              - model.thinnest_film(t, y - np.r_[h[n] * np.eye(N)[n], np.zeros(N)])[1]) / (2 * h[n]) for n in range(N)]
    if where == "interior":
        np.testing.assert_allclose(dx_dq, found, rtol=1e-5, atol=1e-5 * np.max(np.abs(found)))
        assert np.max(np.abs(found)) > 1e-3  # the point moves with the state
    else:
        assert np.all(dx_dq == 0.0) and np.all(np.asarray(found) == 0.0) and dx_dt == model.kinematics(t).V_r


@pytest.fixture(scope="module")
def impact_orbit():
    return find_periodic(resolve("paper-impact", IMPACT))


def test_monodromy_through_impacts_matches_differences_of_the_map(impact_orbit):
    orbit = impact_orbit
    assert orbit.jacobian == "variational+saltation" and orbit.jacobian_note == ""
    pmap = orbit.period_map
    assert len(pmap.run(orbit.y0).impacts) == 3
    M_fd, _, check = pmap.differences(orbit.y0, check=True)
    scale = pmap.scale()
    D = lambda A: (A * scale[None, :] / scale[:, None])  # noqa: E731 (the scaled matrix)
    # the two monodromies agree within the accuracy estimate of the differences (their check's distance)
    assert np.max(np.abs(D(orbit.monodromy - M_fd))) <= np.max(np.abs(D(check - M_fd)))
    mu_fd = np.sort_complex(np.linalg.eigvals(M_fd))
    err_fd = np.max(np.abs(np.sort_complex(np.linalg.eigvals(check)) - mu_fd))
    np.testing.assert_allclose(np.sort_complex(orbit.multipliers), mu_fd, rtol=0, atol=err_fd)


def test_impacting_orbit_determinant_is_liouville_times_e_squared_per_impact(impact_orbit):
    # det of each impact's saltation matrix: e * (v+ / v-) = e^2 (one mode); Liouville between the impacts
    orbit = impact_orbit
    zeta, e, w1 = IMPACT["beam.damping_ratio"], IMPACT["contact.restitution"], orbit.period_map.model.omega_n[0]
    expected = math.exp(-2 * zeta * w1 * orbit.period) * e ** (2 * 3)
    assert np.prod(np.abs(orbit.multipliers)) == pytest.approx(expected, rel=1e-8)
    # the estimate holds the events' own error (the period run again at 100x rtol): 2.6e-9 measured
    assert np.max(orbit.multiplier_errors) < 1e-8


def test_a_graze_falls_back_to_differences_and_says_why(monkeypatch, impact_orbit):
    monkeypatch.setattr(saltation, "GRAZING", 1e3)  # every impact a graze
    config = resolve("paper-impact", IMPACT)
    y0 = impact_orbit.y0
    orbit = find_periodic(config, y0=y0)
    assert orbit.jacobian == "finite-difference"
    assert "graze" in orbit.jacobian_note and "impact at t =" in orbit.jacobian_note
    with pytest.raises(ShootingError, match="jacobian = 'variational'.*graze"):
        find_periodic(config, y0=y0, jacobian="variational")


def test_events_without_a_saltation_matrix_are_named():
    planar = SimpleNamespace(contact=SimpleNamespace(law="compliant"), beam=SimpleNamespace(model="planar"))
    model = SimpleNamespace(config=planar)
    assert unsupported(model, SimpleNamespace(contacts=[[0.1, 0.2, 1.0]], impacts=[])) == ""
    assert "still on" in unsupported(model, SimpleNamespace(contacts=[[0.1, np.nan, 1.0]], impacts=[]))
    model.config.beam.model = "spatial"
    assert "spatial" in unsupported(model, SimpleNamespace(contacts=[[0.1, 0.2, 1.0]], impacts=[]))
    model.config.beam.model = "planar"
    model.config.contact.law = "restitution"
    assert unsupported(model, SimpleNamespace(contacts=[[0.1, 0.2, 1.0]], impacts=[])) == ""
    impact = SimpleNamespace(t=0.1, v_minus=0.0)
    assert "without a jump" in unsupported(model, SimpleNamespace(contacts=[], impacts=[impact]))
    assert unsupported(model, SimpleNamespace(contacts=[], impacts=[SimpleNamespace(t=0.1, v_minus=0.3)])) == ""

"""Impact law and gap function (docs/model.md §5.3) against independent references."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from lubelink import contact

L = 1.0


def modal_kinetic(q_dot, mass=1.0):
    return 0.5 * mass * np.sum(q_dot**2)


# docs/model.md §5.3, table: only mode 1 moving at 1 m/s, x_c = 0.43 L, e = 0.7.
TABLE = [(1, -1.700, -0.700), (3, -0.921, -0.667), (5, -0.633, -0.440), (20, -0.154, 1.345), (100, -0.032, 1.000)]


@pytest.mark.parametrize("N, dq1, v_mid", TABLE)
def test_jump_matches_reference_table(N, dq1, v_mid):
    q_dot = np.zeros(N)
    q_dot[0] = 1.0
    v_minus = np.sin(np.pi * 0.43)  # approach velocity at x_c from mode 1
    after = contact.restitution_jump(q_dot, 0.43, v_minus, 0.7, L)
    mid = np.sin(np.arange(1, N + 1) * np.pi * 0.5)
    # the table is printed to 3 decimals
    assert after[0] - 1.0 == pytest.approx(dq1, abs=6e-4)
    assert after @ mid == pytest.approx(v_mid, abs=6e-4)


@given(N=st.integers(1, 30), x_c=st.floats(0.01, 0.99), e=st.floats(0.0, 1.0),
       seed=st.integers(0, 2**32 - 1))
def test_newton_law_energy_and_minimum_norm(N, x_c, e, seed):
    rng = np.random.default_rng(seed)
    q_dot = rng.normal(size=N)
    s = np.sin(np.arange(1, N + 1) * np.pi * x_c)
    v_minus = s @ q_dot
    after = contact.restitution_jump(q_dot, x_c, v_minus, e, L)
    # Newton's law at the contact point (paper Eq. 21 with a collar at rest)
    assert s @ after == pytest.approx(-e * v_minus, abs=1e-12 * (1 + abs(v_minus)))
    # energy lost equals the closed form of section 5 (modal mass 1)
    lost = modal_kinetic(q_dot) - modal_kinetic(after)
    assert lost == pytest.approx(contact.impact_energy_loss(v_minus, x_c, e, N, 1.0, L), rel=1e-9, abs=1e-12)
    # the impulse-consistent jump is the minimum-norm one (equal modal masses)
    jump = np.linalg.lstsq(s[None, :], [-(1 + e) * v_minus], rcond=None)[0]
    np.testing.assert_allclose(after - q_dot, jump, atol=1e-10 * (1 + abs(v_minus)))


@given(N=st.integers(1, 12), x0=st.floats(0.05, 0.9), seed=st.integers(0, 2**32 - 1))
def test_thinnest_film_against_dense_sampling(N, x0, seed):
    rng = np.random.default_rng(seed)
    q = rng.normal(size=N) * 1e-3 / np.arange(1, N + 1) ** 2
    l, H = 0.05, 6e-3
    xi_min, x_c, _ = contact.thinnest_film(q, x0, l, H, L)
    xs = np.linspace(x0, x0 + l, 200001)
    xi = H / 2 - np.sin(np.outer(xs, np.arange(1, N + 1) * np.pi / L)) @ q
    # dense sampling at 2.5e-7 m spacing resolves the minimum to ~(spacing)^2 * curvature
    assert xi_min <= xi.min() + 1e-15
    assert xi_min == pytest.approx(xi.min(), abs=1e-12)
    assert x0 - 1e-12 <= x_c <= x0 + l + 1e-12


@pytest.mark.parametrize("edge", [True, False])
def test_approach_velocity_is_minus_gap_rate(edge):
    # gap(t) = thinnest film with q(t) = q + q_dot t and the pad moving at V
    N, H, l, V = 3, 6e-3, 0.05, 1.7
    q_dot = np.array([0.3, -0.05, 0.02])
    if edge:  # monotone deflection on the pad: the thinnest film is at an edge
        q, x0 = np.array([2e-3, 1e-4, 0.0]), 0.2
    else:  # an interior maximum of u2 on the pad
        q, x0 = np.array([2e-3, 0.0, 0.0]), 0.48
    xi0, x_c, at_edge = contact.thinnest_film(q, x0, l, H, L)
    assert at_edge == edge
    dt = 1e-7
    gaps = [contact.thinnest_film(q + q_dot * s, x0 + V * s, l, H, L)[0] for s in (-dt, dt)]
    rate = (gaps[1] - gaps[0]) / (2 * dt)
    v = contact.approach_velocity(q, q_dot, x_c, V if at_edge else 0.0, L)
    assert v == pytest.approx(-rate, rel=1e-5)


@pytest.mark.parametrize("N", [1, 3, 6])
@pytest.mark.parametrize("e", [0.0, 0.7, 1.0])
def test_energy_change_of_an_edge_impact_is_the_loss_plus_the_collar_work(N, e):
    # the kinetic energy before and after the jump, computed directly, against the closed form;
    # an edge contact (V_c = V_r) and an interior one (V_c = 0: the classical loss)
    rng = np.random.default_rng(N)
    q = 1e-3 * rng.standard_normal(N)
    x_c, V_r, mass = 0.37, 2.5, 0.38
    beta = np.arange(1, N + 1) * np.pi / L
    s = np.sin(beta * x_c)
    slope = np.sum(beta * np.cos(beta * x_c) * q)
    for V_c in (V_r, 0.0):
        q_dot = rng.standard_normal(N) * 0.01
        v = contact.approach_velocity(q, q_dot, x_c, V_c, L)
        assert v == pytest.approx(s @ q_dot + slope * V_c, rel=1e-12)
        if v <= 0:
            q_dot = -q_dot
            v = contact.approach_velocity(q, q_dot, x_c, V_c, L)
        after = contact.restitution_jump(q_dot, x_c, v, e, L)
        direct = modal_kinetic(after, mass) - modal_kinetic(q_dot, mass)
        change = contact.impact_energy_change(v, slope * V_c, x_c, e, N, mass, L)
        assert change == pytest.approx(direct, rel=1e-10, abs=1e-18)
        if V_c == 0.0:
            assert change == pytest.approx(-contact.impact_energy_loss(v, x_c, e, N, mass, L), rel=1e-12)


def test_an_edge_impact_can_give_the_link_energy():
    # the collar corner slides over the sloped link: approach driven by u2' V_r, link at rest
    N, x_c, mass, e = 1, 0.3, 0.38, 0.7
    q, q_dot = np.array([2e-3]), np.array([0.0])
    V_r = 1.0
    v = contact.approach_velocity(q, q_dot, x_c, V_r, L)
    assert v > 0
    after = contact.restitution_jump(q_dot, x_c, v, e, L)
    gain = modal_kinetic(after, mass) - modal_kinetic(q_dot, mass)
    assert gain > 0 > -contact.impact_energy_loss(v, x_c, e, N, mass, L)
    assert contact.impact_energy_change(v, v, x_c, e, N, mass, L) == pytest.approx(gain, rel=1e-12)


def test_the_penetration_message_says_where_and_when():
    from lubelink.contact import penetration

    t = np.arange(5.0)
    ok = np.array([9e-6, 5e-6, 4.6e-6, 6e-6, 7e-6])  # 4.6 um: within 10 % of min_film = 5 um
    assert penetration(t, ok, np.zeros(5), 5e-6) == ""
    held = np.array([9e-6, 4e-6, -2e-6, 6e-6, 7e-6])
    side = np.array([0, 1, 1, 0, 0])
    text = penetration(t, held, side, 5e-6)
    assert "to -2e-06 m at t = 2 s (first at t = 1 s, 2 samples), during a sustained contact" in text
    assert "partly in free flight" in penetration(t, held, np.zeros(5), 5e-6)


class _StrikingModel:
    """A model whose every impact leaves the link on the face with a negative holding force:
    what several points of the pad striking the face at the same instant look like to the logic."""

    modes = 1
    params = type("P", (), {"galerkin": None})()

    def __init__(self, config):
        self.config = config

    @staticmethod
    def planar_state(y):
        return y

    def impact(self, t, y, restitution=None):
        return y.copy(), 0.5, 1e-3, 1  # y_plus, x_c [m], v_minus [m/s], side

    def contact_point(self, t, y):
        return 0.5

    def sustained_force(self, t, y, side, point):
        return (-1.0,)  # [N]: the collar would pull the link


def test_impacts_repeated_at_one_instant_end_in_chatter_at_stuck_impacts():
    """Repeated impacts within one chatter interval and no holding force: chatter at the 100th, not
    at max_impacts (before, paper-impact with 7 modes on DOP853 made 100,000 of them, 2 min)."""
    from lubelink.config import resolve

    logic = contact.ContactLogic(_StrikingModel(resolve("paper-impact")))
    y = np.zeros(2)
    t = 1.0
    for k in range(1, logic.stuck_impacts):
        status = logic.on_event(t, y, t, y, None)[0]
        assert status is None, k
        t += 1e-9  # [s], well within contact.chatter_interval = 1e-6 s
    status, message = logic.on_event(t, y, t, y, None)[:2]
    assert status == "chatter" and len(logic.impacts) == logic.stuck_impacts
    assert "100 impacts within contact.chatter_interval = 1e-06 s" in message and "compliant" in message
    spaced = contact.ContactLogic(_StrikingModel(resolve("paper-impact")))
    for k in range(2 * spaced.stuck_impacts):  # the same number of impacts, each 2 chatter intervals apart
        assert spaced.on_event(2e-6 * k, y, 2e-6 * k, y, None)[0] is None


def test_the_restitution_law_with_several_modes_says_it_does_not_converge():
    """The paper's restitution law with N > 1: its velocity jump scales like 2/N (docs/model.md 5.3); the run
    says so, and with one mode it does not."""
    import warnings

    import lubelink

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = lubelink.simulate("paper-impact", {"beam.modes": 2, "solver.t_end": 0.05})
    assert "2/N" in ds.attrs["contact_warning"] and any("2/N" in str(w.message) for w in caught)
    assert ds.attrs["status"] == "complete"
    assert lubelink.simulate("paper-impact", {"solver.t_end": 0.05}).attrs["contact_warning"] == ""

"""Model assembly: two-sided film symmetry, gravity sag, cavitation in the model, compliant contact."""

import numpy as np
import pytest

import lubelink
from lubelink.config import resolve
from lubelink.link.kinematics import PrescribedMotion
from lubelink.link.faces import ContactPhase
from lubelink.build import build_model
from lubelink.simulate import run


def state(N=3):
    rng = np.random.default_rng(4)
    q = rng.normal(size=N) * 1e-3 / np.arange(1, N + 1) ** 2
    return np.concatenate([q, rng.normal(size=N) * 0.02])


@pytest.mark.parametrize("model", ["wedge", "wedge+squeeze"])
@pytest.mark.parametrize("cavitation", ["none", "half-sommerfeld", "reynolds"])
def test_two_sided_film_mirror_symmetry(model, cavitation):
    """Mirroring the deflection about the link axis mirrors the film force (sides = 2)."""
    cfg = resolve("paper", {"beam.modes": 3, "film.sides": 2, "film.model": model,
                            "film.cavitation": cavitation, "film.clearance": 4e-3})
    m = build_model(cfg)
    y = state()
    F, total = m.film_loads(0.03, y)
    F_m, total_m = m.film_loads(0.03, -y)
    np.testing.assert_allclose(F_m, -F, rtol=1e-12, atol=1e-12 * np.abs(F).max())
    assert total_m == pytest.approx(-total, rel=1e-12)
    # and the two films are the one-sided film of each mirrored state
    one = build_model(resolve("paper", {"beam.modes": 3, "film.model": model, "film.cavitation": cavitation,
                                        "film.clearance": 4e-3}))
    F_up, _ = one.film_loads(0.03, y)
    F_down, _ = one.film_loads(0.03, -y)
    np.testing.assert_allclose(F, F_up - F_down, rtol=1e-12, atol=1e-12 * np.abs(F).max())


def test_two_sided_gap_and_impact_on_the_lower_side():
    cfg = resolve("paper", {"beam.modes": 1, "film.sides": 2, "film.model": "none",
                            "contact.law": "restitution", "film.clearance": 4e-3})
    m = build_model(cfg)
    y = np.array([-1.9e-3, -0.05])  # deflected towards the lower face, moving further down
    xi, x_c, edge, side = m.thinnest_film(0.0, y)
    assert side == -1 and xi == pytest.approx(2e-3 - 1.9e-3 * np.sin(np.pi * x_c), rel=1e-12)
    y_plus, x_c, v_minus, side = m.impact(0.0, y)
    assert v_minus > 0 and side == -1
    v_after, _, _ = m.approach(0.0, y_plus)
    assert v_after == pytest.approx(-0.7 * v_minus, rel=1e-12)


def test_gravity_sag_of_a_horizontal_link_at_rest():
    """Static sag 5 rho A g L^4 / (384 E I) at midspan (docs/model.md §1.3)."""
    zero = lambda t: 0.0 * np.asarray(t)  # noqa: E731
    at_rest = PrescribedMotion(A_O2=zero, omega=zero, alpha=zero, x_star=lambda t: 0.4 + zero(t), V_r=zero)
    ds = lubelink.simulate("paper-dry", set={"mechanism.gravity": [0.0, -9.81], "beam.modes": 9,
                                             "beam.damping_ratio": 0.9, "solver.t_end": 0.5,
                                             "solver.output_step": 0.01}, motion=at_rest)
    b = resolve("paper").beam
    sag = 5 * b.density * b.area * 9.81 / (384 * b.youngs_modulus * b.second_moment)
    assert sag == pytest.approx(0.567e-3, rel=2e-3)  # docs/model.md §6: 0.567 mm
    # 9 modes truncate the series of the uniform load at ~1e-5 relative; damping has settled the transient
    assert float(ds.u2_mid[-1]) == pytest.approx(-sag, rel=1e-4)


def test_gravity_is_resolved_on_the_link_axis():
    """A vertical link (angle 90 deg) feels no transverse gravity; a horizontal one feels all of it."""
    zero = lambda t: 0.0 * np.asarray(t)  # noqa: E731
    for angle, expected in [(np.pi / 2, 0.0), (0.0, -9.81), (np.pi, 9.81)]:
        motion = PrescribedMotion(A_O2=zero, omega=zero, alpha=zero, x_star=lambda t: 0.4 + zero(t), V_r=zero,
                                  angle=lambda t, a=angle: a + zero(t))
        m = build_model(resolve("paper-dry", {"mechanism.gravity": [0.0, -9.81]}), motion)
        assert m.gravity_j(0.0) == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize("cavitation", ["half-sommerfeld", "reynolds"])
def test_cavitation_bounds_the_film_pressure_in_a_run(cavitation):
    # The paper's crank sense keeps the wedge converging (p > 0, measured min -0.1 Pa over a turn); a
    # crank turning the other way makes it diverging, with sub-ambient pressure (-411 Pa gauge at t = 0.19 s, -1.7e5 Pa later as the film thins).
    ds = lubelink.simulate("paper", set={"mechanism.crank_speed": -10 * np.pi, "film.cavitation": cavitation, "film.cavitation_pressure": 101000.0,
                                         "solver.t_end": 0.2, "output.pad_points": 21, "film.clearance": 5e-3, "film.grid_points": 101})
    p_cav = 101000.0 - 101325.0
    assert float(ds.pressure.min()) >= p_cav - 1e-6
    assert float(ds.pressure.min()) < p_cav + 1.0  # the bound is reached: the film does cavitate


def test_compliant_contact_restitution_for_one_mode():
    """With e near 1 the Lankarani-Nikravesh law returns the approach velocity times e.

    LN is derived for e close to 1 (energy loss small against the elastic
    energy); at e = 0.95 its effective restitution is e to within 1 %.
    """
    cfg = {"film.model": "none", "film.clearance": 5e-3, "contact.law": "compliant",
           "contact.restitution": 0.95, "solver.t_end": 0.3}
    r = run(resolve("paper", cfg))
    assert len(r.impacts) >= 1
    t, x_c, v_in, v_out = r.impacts[0][:4]
    assert -v_out / v_in == pytest.approx(0.95, rel=0.01)
    # and with the same first contact as the instantaneous law
    r2 = run(resolve("paper", {**cfg, "contact.law": "restitution"}))
    assert r2.impacts[0][0] == pytest.approx(t, abs=1e-9)


def test_compliant_contact_converges_with_modes_where_restitution_does_not():
    """docs/model.md §5.3: the point restitution law depends on N; a compliant contact converges.

    A short transverse acceleration pulse throws a dry link at the collar
    (half-clearance 0.5 mm). The change of mode 1's velocity over the first
    contact converges with N for the compliant law (the link's point
    receptance converges, its modal terms falling like 1/n^4), while the
    restitution jump spreads over all modes and shrinks like 1/sum s_n^2 ~ 2/N.
    The contact is soft (linear, 1e5 N/m) so that 16 modes resolve it.
    """
    const = lambda v: (lambda t: v + 0.0 * np.asarray(t))  # noqa: E731
    pulse = PrescribedMotion(A_O2=lambda t: -2000.0 * np.exp(-((np.asarray(t) - 1e-3) / 4e-4) ** 2),
                             omega=const(0.0), alpha=const(0.0), x_star=const(0.45), V_r=const(0.0))
    base = {"film.model": "none", "film.clearance": 1e-3, "contact.stiffness": 1e5, "contact.exponent": 1.0,
            "solver.t_end": 0.008, "solver.output_step": 1e-3}
    jump = {}
    for law in ("compliant", "restitution"):
        for N in (4, 8, 16):
            r = run(resolve("paper", {**base, "contact.law": law, "beam.modes": N}), motion=pulse)
            first = r.impacts[0]
            jump[law, N] = first.y_after[N] - first.y_before[N]  # mode 1's velocity
    c, r_ = (np.array([jump[law, N] for N in (4, 8, 16)]) for law in ("compliant", "restitution"))
    # compliant: measured -3.106, -3.071, -3.0705 m/s; doubling N changes it 50x less each time
    assert abs(c[2] - c[1]) < 0.1 * abs(c[1] - c[0])
    assert c[2] == pytest.approx(-3.0705, rel=1e-3)
    # restitution: -0.92, -0.52, -0.26 m/s, halving with every doubling of N (no limit but 0)
    assert r_[2] / r_[1] == pytest.approx(0.5, abs=0.05) and r_[1] / r_[0] < 0.6


def test_contact_force_is_zero_outside_contact_and_never_adhesive():
    m = build_model(resolve("paper", {"film.model": "none", "contact.law": "compliant", "film.clearance": 5e-3}))
    y = np.array([1e-3, 0.0])
    F, f = m.contact_force(0.0, y, ContactPhase(side=1, v_minus=0.1))
    assert f == 0.0 and not F.any()
    # deep penetration but separating fast: the LN damping term would go negative; clipped at 0
    x_edge = 0.33  # pad start at t = 0
    q = (2.5e-3 - 5e-6 + 1e-6) / np.sin(np.pi * x_edge)
    F, f = m.contact_force(0.0, np.array([q, -10.0]), ContactPhase(side=1, v_minus=0.01))
    assert f == 0.0


def test_the_remembered_parameter_type_is_numbas_type_of_the_parameters():
    """``assembly.params_type`` (keyed by the layout of the parameters) gives ``numba.typeof`` of them, also
    where only an array's flags differ (read-only, Fortran order): the layout key tells those apart."""
    numba = pytest.importorskip("numba")
    from lubelink import assembly

    cases = [("paper", None), ("paper-dry", {"beam.modes": 3}), ("lubricated", None),
             ("paper", {"film.cavitation": "reynolds", "film.model": "wedge+squeeze"}),
             ("paper", {"beam.width_ratio": 0.5})]
    for scenario, overrides in cases:
        p = build_model(resolve(scenario, overrides)).params
        assert assembly.params_type(p) == numba.typeof(p), scenario
        frozen = p.basis.omega_n.copy()
        frozen.flags.writeable = False
        variants = [p._replace(basis=p.basis._replace(omega_n=frozen)),
                    p._replace(pad=p.pad._replace(trig=np.asfortranarray(p.pad.trig)))]
        for q in variants:
            assert assembly.params_type(q) == numba.typeof(q) != numba.typeof(p), scenario

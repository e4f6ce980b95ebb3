"""The energy budget (lubelink.energy) against closed forms, a physical law of the squeeze film, and impacts.

Tiers: analytic (a free link keeps its energy; a damped mode loses it as exp(-2 zeta omega t));
physical law (a squeeze film without sliding only dissipates); convergence (the residual falls with
the sampling like Simpson's rule); cross-method (each impact's energy change against
:func:`lubelink.contact.impact_energy_change`, its dissipation from the states); every scenario closes.
"""

import numpy as np
import pytest

import lubelink
from lubelink import contact
from lubelink.beam import wavenumbers
from lubelink.config import resolve
from lubelink.link.kinematics import sampled_motion
from lubelink.link.spatial_motion import sampled_spatial_motion
from lubelink.results import collect, dataset
from lubelink.simulate import run

X_STAR = 0.4


def _at_rest(t_end, x_star=X_STAR):
    t = np.linspace(0.0, t_end + 0.01, 8)
    zero = np.zeros_like(t)
    return sampled_motion(t, A_O2=zero, omega=zero, x_star=zero + x_star)


def _free(overrides, y0):
    config = resolve("paper-dry", {"solver.method": "DOP853", "solver.rtol": 1e-11, "solver.atol": 1e-14,
                                   "solver.t_end": 0.2, "solver.output_step": 1e-4, **overrides})
    return dataset(collect(run(config, motion=_at_rest(0.2), y0=y0))), config


def test_a_free_undamped_link_keeps_its_energy():
    """No load on a link at rest: E = m/2 sum omega_n^2 q_n(0)^2 at every sample, every work zero."""
    q0 = np.array([2e-4, -1e-4, 5e-5])
    ds, cfg = _free({"beam.modes": 3}, np.r_[q0, 0.0, 0.0, 0.0])
    b = cfg.beam
    m = b.density * b.width * b.height * cfg.mechanism.rod_length / 2
    omega = ds.omega_n.values
    E0 = 0.5 * m * np.sum(omega**2 * q0**2)
    assert np.abs(ds.energy.values / E0 - 1.0).max() < 1e-9
    for name in ("work_rigid", "work_damping", "work_film", "work_contact", "work_impacts"):
        assert np.all(ds[name].values == 0.0), name
    assert ds.attrs["energy_residual_max"] < 1e-9 * E0


def test_damping_takes_what_the_closed_form_says():
    """One mode, damping ratio zeta, released from q0: E(t) from the damped oscillator's closed form, and the
    damping's work is all the change."""
    zeta, q0 = 0.02, 3e-4
    ds, cfg = _free({"beam.modes": 1, "beam.damping_ratio": zeta}, np.array([q0, 0.0]))
    t = ds.time.values
    w = float(ds.omega_n[0])
    wd = w * np.sqrt(1 - zeta**2)
    q = q0 * np.exp(-zeta * w * t) * (np.cos(wd * t) + zeta * w / wd * np.sin(wd * t))
    q_dot = -q0 * w**2 / wd * np.exp(-zeta * w * t) * np.sin(wd * t)
    b = cfg.beam
    m = b.density * b.width * b.height * cfg.mechanism.rod_length / 2
    E = 0.5 * m * (q_dot**2 + w**2 * q**2)
    assert np.abs(ds.energy.values - E).max() < 1e-8 * E[0]
    lost = E - E[0]
    assert lost[-1] < -0.5 * E[0]
    assert np.abs(ds.work_damping.values - lost).max() < 1e-6 * E[0]  # Simpson on 0.1 ms samples


def test_a_squeeze_film_without_sliding_only_dissipates():
    """The collar at rest on a vibrating link: Reynolds' squeeze film turns the link's energy into heat
    (int p dh/dt dX = -int h^3 p'^2 / 12 mu <= 0), so its work never increases, and it takes it all."""
    overrides = {"beam.modes": 3, "film.clearance": 2e-4, "film.cavitation": "none",
                 "film.viscosity": 0.5, "solver.method": "Radau", "solver.rtol": 1e-9, "solver.atol": 1e-13,
                 "solver.t_end": 0.1, "solver.output_step": 5e-5}
    config = resolve("lubricated", overrides)
    res = dataset(collect(run(config, motion=_at_rest(0.1), y0=np.r_[5e-5, 0.0, 2e-5, 0.0, 0.0, 0.0])))
    assert res.attrs["status"] == "complete"
    W = res.work_film.values
    E = res.energy.values
    assert np.all(np.diff(W) <= 1e-12 * E[0])
    assert W[-1] < -0.5 * E[0]
    assert np.abs(E - E[0] - W).max() < 2e-4 * E[0]  # the first 50 us: the fastest squeeze, coarsest quadrature


@pytest.fixture(scope="module")
def impacts():
    """``paper-impact`` to 1.3 s (its first impacts, a Zeno sequence and a sustained contact) on 20 us samples."""
    return lubelink.simulate("paper-impact", {"solver.t_end": 1.3, "solver.output_step": 2e-5})


def test_every_impact_dissipates_in_the_frame_of_the_collar_face(impacts):
    """Each impact's energy change is :func:`contact.impact_energy_change` of its approach velocity and point
    (a closed form of the restitution law); the approach velocity after it, from the states, is minus e times
    the one before (0 in a Zeno sequence), and the loss in the contact frame is >= 0 at every impact."""
    ds = impacts
    cfg = resolve("paper-impact")
    L = cfg.mechanism.rod_length
    N = ds.mode.size
    b = cfg.beam
    m = b.density * b.width * b.height * L / 2
    assert ds.impact.size >= 10
    for k in range(ds.impact.size):
        t_k, x_c = float(ds.impact_time[k]), float(ds.impact_position[k])
        v, v_after = float(ds.impact_velocity[k]), float(ds.impact_velocity_after[k])
        e = -v_after / v
        assert e == pytest.approx(cfg.contact.restitution) or e == 0.0
        s = np.sin(wavenumbers(N, L) * x_c)
        change = float(ds.impact_energy_change[k])
        # the slope term of an impact at a pad edge, sliding at V_r (0 inside the pad)
        i = int(np.searchsorted(ds.time.values, t_k))
        q, V_r = ds.q.values[i], float(ds.V_r[i])
        x0 = float(ds.x_star[i])
        at_edge = min(abs(x_c - x0), abs(x_c - x0 - cfg.film.pad_length)) < 1e-3
        slope = float(np.sum(q * wavenumbers(N, L) * np.cos(wavenumbers(N, L) * x_c))) * V_r if at_edge else 0.0
        expected = contact.impact_energy_change(v, int(ds.impact_side[k]) * slope, x_c, e, N, m, L)
        assert change == pytest.approx(expected, rel=1e-3, abs=1e-3 * abs(v) ** 2 * m / np.sum(s * s))
        assert float(ds.impact_dissipation[k]) >= 0.0
        assert float(ds.impact_collar_work[k]) == pytest.approx(change + float(ds.impact_dissipation[k]))


def test_the_balance_closes_through_impacts_and_a_sustained_contact(impacts):
    ds = impacts
    assert ds.attrs["status"] == "complete" and ds.contact_phase.values.any()
    assert abs(float(ds.work_impacts[-1])) > 0.01 * float(ds.energy.max())
    assert ds.attrs["energy_residual_relative"] < 3e-4


def test_the_residual_falls_with_the_sampling_like_simpsons_rule():
    """Before its first impact ``paper-impact``'s residual is the quadrature error of the powers: 1 ms -> 0.1 ms
    samples cut it by more than 1000 (fourth order: 10^4; the trapezoid would give 100)."""
    worst = []
    for dt in (1e-3, 1e-4):
        ds = lubelink.simulate("paper-impact", {"solver.t_end": 1.2, "solver.output_step": dt})
        worst.append(ds.attrs["energy_residual_max"])
    assert worst[0] > 1000 * worst[1]


@pytest.mark.parametrize("scenario, overrides", [
    ("paper", {}), ("paper-dry", {"beam.modes": 5}), ("lubricated", {"solver.t_end": 0.5}),
    ("guide", {"solver.t_end": 0.1, "solver.output_step": 1e-5}),
    ("paper", {"model.equations": "printed"}), ("paper", {"mechanism.gravity": [0.0, -9.81]}),
    ("paper", {"film.model": "none", "film.clearance": 1e-4, "contact.law": "compliant", "contact.min_film": 1e-6,
               "contact.extent": "pad", "beam.modes": 7, "solver.t_end": 0.02, "solver.output_step": 2e-6}),
])
def test_every_scenario_closes_its_energy_balance(scenario, overrides):
    ds = lubelink.simulate(scenario, overrides)
    assert ds.attrs["status"] == "complete"
    assert ds.attrs["energy_residual_relative"] < 2e-4, ds.attrs["energy_residual_relative"]
    assert float(np.abs(ds.work_rigid).max()) > 0.0


# --- the spatial link and the variable section -------------------------------------------------------------
def _spatial_at_rest(t_end, omega=(0.0, 0.0, 0.0)):
    t = np.linspace(0.0, t_end + 0.01, 8)
    n = t.size
    return sampled_spatial_motion(t, A_O=np.zeros((n, 3)), omega=np.tile(omega, (n, 1)), x_star=np.full(n, X_STAR))


SPATIAL_FREE = {"film.model": "none", "contact.law": "none", "beam.damping_ratio": 0.0, "beam.modes": 2,
                "solver.method": "DOP853", "solver.rtol": 1e-11, "solver.atol": 1e-14, "solver.t_end": 0.05,
                "solver.output_step": 2e-5}
#: A spatial state: axial, in-plane and out-of-plane coordinates [m] (velocities zero).
Q0 = np.array([1e-7, -5e-8, 2e-4, -1e-4, 1.5e-4, 5e-5])


@pytest.mark.parametrize("end", ["fixed", "free"])
def test_a_free_undamped_spatial_link_keeps_its_energy(end):
    """No load on a spatial link at rest: E = m/2 sum W_i^2 q_i(0)^2 over the axial, in-plane and out-of-plane modes
    (frequencies by hand: n pi / L sqrt(E / rho) with a fixed axial end, (2 n - 1) pi / (2 L) sqrt(E / rho) with a
    free one, beta^2 sqrt(E I / rho A)) at every sample, every work zero."""
    cfg = resolve("spatial-slider-crank", {**SPATIAL_FREE, "beam.axial_end": end})
    r = run(cfg, motion=_spatial_at_rest(0.05), y0=np.r_[Q0, np.zeros(6)])
    ds = dataset(collect(r))
    b, L = cfg.beam, cfg.mechanism.rod_length
    beta = np.arange(1, 3) * np.pi / L
    k = beta if end == "fixed" else np.array([1.0, 3.0]) * np.pi / (2 * L)
    W = np.r_[k * np.sqrt(b.youngs_modulus / b.density),
              beta**2 * np.sqrt(b.youngs_modulus * b.width * b.height**3 / 12 / (b.density * b.width * b.height)),
              beta**2 * np.sqrt(b.youngs_modulus * b.height * b.width**3 / 12 / (b.density * b.width * b.height))]
    m = b.density * b.width * b.height * L / 2
    E0 = 0.5 * m * np.sum(W**2 * Q0**2)
    assert np.abs(ds.energy.values / E0 - 1.0).max() < 1e-9
    for name in ("work_rigid", "work_damping", "work_film", "work_contact", "work_impacts"):
        assert np.all(ds[name].values == 0.0), name


def _spinning(frame_terms=True, end="free"):
    """A spatial link at rest in translation, its frame spinning at a constant w = (3, 20, 40) rad/s, released from
    Q0: the centrifugal and Coriolis accelerations exchange energy with it. Returns the largest relative residual
    of the budget, with the frame's accelerations in the powers or (``frame_terms`` False) left out; ``end`` the
    axial end condition."""
    from lubelink import energy

    cfg = resolve("spatial-slider-crank", {**SPATIAL_FREE, "solver.backend": "numpy", "solver.t_end": 0.02,
                                           "solver.output_step": 5e-6, "beam.axial_end": end})
    r = run(cfg, motion=_spatial_at_rest(0.02, (3.0, 20.0, 40.0)), y0=np.r_[Q0, np.zeros(6)])
    assert r.status == "complete"
    original = energy.spatial
    if not frame_terms:
        class NoFrame:
            rigid_loads = staticmethod(original.rigid_loads)
            axis_acceleration = staticmethod(original.axis_acceleration)
            axial_rigid_load = staticmethod(original.axial_rigid_load)

            @staticmethod
            def frame_terms(w, al, x, v):
                return 0.0, 0.0, 0.0

            @staticmethod
            def coupled_frame_terms(projection, w, al, y, n):
                return 0.0, 0.0, 0.0
        energy.spatial = NoFrame
    try:
        series, _, residual = energy.of_run(r, r.t, r.y, np.zeros(r.t.size))
    finally:
        energy.spatial = original
    scale = max(np.abs(series["energy"]).max(), np.abs(series["work_rigid"]).max())
    return residual / scale, series


@pytest.mark.parametrize("end", ["fixed", "free"])
def test_a_spinning_frame_works_on_the_spatial_link_and_the_budget_closes(end):
    """The frame's centrifugal load does work (its power is of the order of the energy), the budget closes to
    the quadrature error; without the frame's accelerations in the powers it misses by orders of magnitude. With
    either axial end (a free one couples the axial modes with all the bending sines)."""
    relative, series = _spinning(end=end)
    assert np.abs(series["work_rigid"]).max() > 0.01 * series["energy"].max()
    assert relative < 1e-6
    assert _spinning(frame_terms=False, end=end)[0] > 1e3 * relative


@pytest.mark.parametrize("overrides", [
    {},
    {"film.faces": "u2+u3", "mechanism.crank_tilt": 0.2, "mechanism.slider_offset": 0.02, "beam.modes": 3},
    {"beam.width_ratio": 0.6, "beam.modes": 3},
    {"film.model": "none", "film.sides": 2, "film.faces": "u2+u3", "film.clearance": 1e-4, "contact.law": "compliant",
     "contact.min_film": 5e-6, "solver.t_end": 0.012, "solver.output_step": 2e-6},
    {"beam.axial_end": "fixed"},
    {"beam.axial_end": "fixed", "beam.width_ratio": 0.6, "beam.modes": 3},
])
def test_the_spatial_link_closes_its_budget(overrides):
    """The spatial slider-crank: its film, a tilted crank with films on both pairs, a tapered link (eigenbases),
    and compliant contacts on both pairs of faces, with the free axial end (the default) and the fixed one. On 20 us
    samples: the axial modes (8,200 rad/s for the first, free; 16,300 fixed) vibrate, and on the default 1 ms
    samples Simpson's rule misses 1 % of the energy (measured with the free end: 1.3e-2, 5.7e-4, 6.9e-6, 3.7e-6 at
    1000, 200, 50, 10 us, the last two the integration's error; fixed: 1.0e-2, 9.1e-3, 6.5e-5, 6.2e-5)."""
    ds = lubelink.simulate("spatial-slider-crank", {"solver.t_end": 0.1, "solver.output_step": 2e-5, **overrides})
    assert ds.attrs["status"] == "complete"
    assert ds.attrs["energy_residual_relative"] < 2e-4, ds.attrs["energy_residual_relative"]
    assert float(np.abs(ds.work_rigid).max()) > 0.0
    if overrides.get("contact.law") == "compliant":
        assert float(np.abs(ds.work_contact).max()) > 0.01 * float(ds.energy.max())


def test_impacts_on_both_pairs_of_faces_close_the_spatial_budget():
    """Restitution impacts on the u2 and on the u3 faces (spatial-slider-crank, dry, 0.1 mm clearance, to 11.6 ms,
    before the Zeno sequence): each impact's loss in the contact frame is >= 0, the collar's work is the change plus
    the loss, and the balance closes through the jumps."""
    over = {"film.model": "none", "film.sides": 2, "film.faces": "u2+u3", "film.clearance": 1e-4,
            "contact.law": "restitution", "solver.t_end": 0.0116, "solver.output_step": 2e-6}
    ds = lubelink.simulate("spatial-slider-crank", over)
    assert set(ds.impact_face.values) == {2, 3}
    assert np.all(ds.impact_dissipation.values >= 0.0)
    np.testing.assert_allclose(ds.impact_collar_work, ds.impact_energy_change + ds.impact_dissipation)
    assert abs(float(ds.work_impacts[-1])) > 0.01 * float(ds.energy.max())
    assert ds.attrs["energy_residual_relative"] < 5e-4, ds.attrs["energy_residual_relative"]  # measured 3.7e-4


def test_a_tapered_link_stores_the_energy_of_its_mass_and_stiffness_matrices():
    """A variable section (planar, taper 0.5): the energy in the results is q_dot^T M q_dot / 2 + q^T K q / 2 of the
    Galerkin matrices of the sine modes (computed here without the eigenbasis), and the budget closes (on 20 us
    samples; measured 0.12, 1.8e-4, 4.3e-6 at 1000, 100, 20 us: its higher modes vibrate more than a uniform link's)."""
    from lubelink.link.section import galerkin_matrices, taper

    cfg = resolve("paper", {"beam.width_ratio": 0.5, "beam.height_ratio": 0.8, "beam.modes": 3,
                            "solver.output_step": 2e-5, "solver.t_end": 0.5})
    ds = lubelink.simulate(cfg)
    b, L = cfg.beam, cfg.mechanism.rod_length
    M, K, _, _ = galerkin_matrices(taper(b, L), b.youngs_modulus, b.density, b.modes, L)
    q, v = ds.q.values, ds.q_dot.values
    E = 0.5 * np.einsum("ti,ij,tj->t", v, M, v) + 0.5 * np.einsum("ti,ij,tj->t", q, K, q)
    np.testing.assert_allclose(ds.energy.values, E, rtol=1e-9, atol=1e-12 * E.max())
    assert ds.attrs["energy_residual_relative"] < 2e-5

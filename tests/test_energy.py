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
from lubelink.kinematics import sampled_motion
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


def test_the_spatial_model_says_it_has_no_budget():
    ds = lubelink.simulate("spatial-slider-crank", {"solver.t_end": 0.05})
    assert "energy" not in ds and "spatial model" in ds.attrs["energy_note"]

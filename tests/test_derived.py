"""Series derived beside the state (lubelink.derived): statistics per revolution of the crank, the crank angle,
the stress against the yield strength, and the film's loss over a revolution against an independent quadrature."""

import numpy as np
import pytest
from scipy.integrate import quad

import lubelink
from lubelink.derived import revolutions
from lubelink.summary import summary


def test_the_statistics_of_each_revolution_of_synthetic_series():
    t = np.linspace(0.0, 1.03, 1031)
    T = 0.25
    u = np.sin(2 * np.pi * t / T) * (1 + t)  # peaks grow with t: the peak of revolution k is near (k - 3/4) T
    data = {"u2_mid": (("time",), u, {}), "film_power_loss": (("time",), 2.0 + 0 * t, {}),
            "film_min": (("time",), 1e-3 + t, {}), "work_damping": (("time",), -0.1 * t, {}),
            "bending_stress": (("time", "x"), np.outer(1 + t, [1.0, 3.0]), {})}
    out = revolutions(t, T, data, ([0.3, 0.31, 0.9], [0.5, 0.25, 1.0]))
    assert out["revolution_start"].tolist() == [0.0, 0.25, 0.5, 0.75]
    k = np.arange(4)
    np.testing.assert_allclose(out["revolution_peak_u2_mid"], [np.abs(u[(t >= a - 1e-12) & (t < a + T - 1e-12)]).max()
                                                               for a in k * T])
    np.testing.assert_allclose(out["revolution_film_min"], 1e-3 + k * T)
    np.testing.assert_allclose(out["revolution_peak_stress"], 3 * (1 + (k + 1) * T - 0.001), rtol=1e-12)
    np.testing.assert_allclose(out["revolution_film_loss"], 2.0 * T, rtol=1e-12)
    np.testing.assert_allclose(out["revolution_energy_lost"], 2.0 * T + 0.1 * T + np.array([0, 0.75, 0, 1.0]),
                               rtol=1e-12)


def test_samples_sparser_than_a_revolution_give_no_statistics():
    out = revolutions(np.array([0.0, 0.3, 0.6]), 0.25, {"film_min": (("time",), np.ones(3), {})}, ((), ()))
    assert set(out) == {"revolution_start"}


def test_a_run_has_the_crank_angle_beside_time_in_the_dataset_and_in_its_file(short, tmp_path):
    ds = lubelink.simulate("paper", short)
    assert "crank_angle" in ds.coords and ds["crank_angle"].dims == ("time",)
    np.testing.assert_allclose(ds["crank_angle"].values, 10 * np.pi * ds.time.values, rtol=1e-15)
    lubelink.save(ds, tmp_path / "r.nc")
    back = lubelink.load(tmp_path / "r.nc")
    assert "crank_angle" in back.coords and "crank_angle" not in back.data_vars
    assert back["revolution"].values.tolist() == [1]  # 0.3 s: one whole turn of 0.2 s


def test_a_revolution_of_a_thick_film_loses_what_couette_flow_loses_at_the_collar_speed():
    """A rigid link (stiff, damped) in a film far thicker than its deflection: each revolution dissipates
    ``mu B l / h int V_r^2 dt``, ``V_r`` from the geometry (finite differences of ``x_star``), by quad."""
    OA, L, w0, a = 0.07, 1.0, 10 * np.pi, 0.4
    ds = lubelink.simulate("paper", {"solver.t_end": 0.4, "beam.youngs_modulus": 1e13, "beam.damping_ratio": 0.3,
                                     "film.clearance": 0.2, "output.x_points": 11})
    x_star = lambda t: (a - OA * np.cos(w0 * t)) / np.sqrt(1 - (OA / L * np.sin(w0 * t)) ** 2)
    V_r = lambda t: (x_star(t + 1e-6) - x_star(t - 1e-6)) / 2e-6
    mu, B, l, h = 0.1, 0.01, 0.05, 0.1
    per_turn = mu * B * l / h * quad(lambda t: V_r(t) ** 2, 0.0, 0.2, limit=200)[0]
    np.testing.assert_allclose(ds["revolution_film_loss"].values, per_turn, rtol=2e-3)
    assert ds["revolution_energy_lost"].values[1] > ds["revolution_film_loss"].values[1]  # damping too


def test_the_peak_stress_is_read_against_the_yield_strength(short):
    ds = lubelink.simulate("paper", {**short, "beam.yield_strength": 20e6})
    peak = float(ds["bending_stress"].max())
    assert ds.attrs["stress_utilisation"] == pytest.approx(peak / 20e6, rel=1e-12)
    text = summary(ds, "paper", None, None)
    assert f"{100 * peak / 20e6:.3g} % of the yield strength" in text and "the link yields" in text
    assert np.isnan(lubelink.simulate("paper", short).attrs["stress_utilisation"])

"""Periodic steady state: shooting against transients and closed forms, Floquet multipliers, the CLI.

References are independent of the shooting code: long transients of :func:`lubelink.simulate.run`,
the harmonic balance (Hill's method) of the one-mode modal equation written from docs/model.md §2.3, the
exact Floquet moduli of a damped linear oscillator (Liouville: ``det M = exp(-2 zeta omega_n T)``
per decoupled mode, a complex pair on the circle of radius ``exp(-zeta omega_n T)``), and the
determinant of the saltation of a restitution impact (``e^2`` per impact).
"""

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import lubelink
from lubelink.cli import main
from lubelink.config import resolve
from lubelink.link.kinematics import PrescribedMotion, slider_crank
from lubelink.simulate import run
from lubelink.steady import ShootingError, find_periodic, periodic

DRY = {"beam.damping_ratio": 0.05}


def crank_period(config):
    return 2 * math.pi / abs(config.mechanism.crank_speed)


def harmonic_balance(config, zeta, t, harmonics=40, samples=512):
    """``q_1(t)`` of the exact periodic response of the one-mode dry link (Hill's method).

    The modal equation of docs/model.md §2, ``q'' + 2 zeta w q' + (w^2 - omega(t)^2) q =
    -2/(L beta) (2 A_O2 + alpha L)``, in Fourier series: the forcing and ``omega^2`` from the
    slider-crank's closed-form kinematics, the harmonics ``c_k`` from the linear system
    ``(w^2 - (k w0)^2 + 2i zeta w k w0) c_k - sum_m W_(k-m) c_m = F_k``.
    """
    m, b = config.mechanism, config.beam
    w0, L = m.crank_speed, m.rod_length
    beta = math.pi / L
    w = beta**2 * math.sqrt(b.youngs_modulus * b.width * b.height**3 / 12 / (b.density * b.width * b.height))
    T = 2 * math.pi / abs(w0)
    ts = np.arange(samples) * T / samples
    k = slider_crank(ts, m.crank_length, L, w0, m.guide_distance)
    F = np.fft.fft(-2 / (L * beta) * (2 * k["A_O2"] + k["alpha"] * L)) / samples
    W = np.fft.fft(k["omega"] ** 2) / samples
    ks = np.arange(-harmonics, harmonics + 1)
    A = -W[(ks[:, None] - ks[None, :]) % samples]
    A[np.diag_indices_from(A)] += w**2 - (ks * w0) ** 2 + 2j * zeta * w * ks * w0
    c = np.linalg.solve(A, F[ks % samples])
    return np.real(np.exp(1j * np.outer(t, ks * w0)) @ c), w


# ----------------------------------------------------------------------------- the linear dry link
def test_linear_orbit_is_the_last_turn_of_a_long_transient():
    config = resolve("paper-dry", {**DRY, "solver.rtol": 1e-10, "solver.atol": 1e-13})
    T = crank_period(config)
    config = config.replace(solver=replace(config.solver, output_step=T / 100, t_end=12 * T))
    ds = periodic(config)
    assert ds.attrs["iterations"] <= 2 and ds.attrs["jacobian"] == "variational"
    assert ds.time.size == 101 and ds.time.values[-1] == pytest.approx(T, rel=1e-12)
    transient = run(config)  # from rest: the free vibration decays by exp(-zeta w1 11 T) ~ 1e-7
    last = transient.y[-101:, 0]
    # 0.1 um, the criterion; the free vibration left after 12 turns is ~ 1e-10 m
    assert np.max(np.abs(ds.q.values[:, 0] - last)) < 1e-7
    assert np.max(np.abs(ds.q.values[:, 0] - last)) < 1e-9


@pytest.mark.parametrize("modes, jacobian", [(1, "auto"), (3, "auto"), (3, "finite-difference")])
def test_floquet_moduli_of_the_damped_linear_link(modes, jacobian):
    zeta = 0.02
    config = resolve("paper-dry", {"beam.damping_ratio": zeta, "beam.modes": modes})
    orbit = find_periodic(config, jacobian=jacobian)
    assert orbit.jacobian == ("variational" if jacobian == "auto" else "finite-difference")
    w = orbit.period_map.model.omega_n
    expected = np.sort(np.repeat(np.exp(-zeta * w * orbit.period), 2))[::-1]
    np.testing.assert_allclose(np.abs(orbit.multipliers), expected, rtol=0, atol=1e-7)
    # each multiplier's accuracy estimate bounds its error, and is not uselessly large
    assert np.all(np.abs(np.abs(orbit.multipliers) - expected) <= orbit.multiplier_errors)
    assert np.all(orbit.multiplier_errors < 1e-6)
    assert orbit.stable


def test_exact_periodic_response_as_damping_goes_to_zero():
    base = resolve("paper-dry")
    T = crank_period(base)
    fine = np.linspace(0, T, 20001)
    peaks = {}
    for zeta in (1e-2, 1e-3, 0.0):
        config = resolve("paper-dry", {"beam.damping_ratio": zeta})
        ds = periodic(config)
        exact, w = harmonic_balance(config, zeta, ds.time.values)
        # the shooting orbit is the exact periodic response to integration accuracy (rtol 1e-10)
        assert np.max(np.abs(ds.q.values[:, 0] - exact)) < 1e-10
        peaks[zeta] = np.max(np.abs(harmonic_balance(config, zeta, fine)[0]))
        if zeta == 0.0:  # undamped: neutral, on the unit circle (det M = 1)
            np.testing.assert_allclose(ds.floquet_modulus.values, 1.0, atol=1e-7)
            assert ds.attrs["stable"] == 0
    # docs/model.md §10.3: the exact periodic response of the 1-mode model peaks at 2.1055 mm
    assert peaks[0.0] == pytest.approx(2.1055e-3, abs=1e-7)
    assert abs(peaks[1e-3] - peaks[0.0]) < abs(peaks[1e-2] - peaks[0.0]) < 1e-6


@pytest.mark.parametrize("jacobian, bound", [("variational", 1e-7), ("finite-difference", 1e-6)])
def test_undamped_multipliers_are_on_the_circle_within_their_accuracy(jacobian, bound):
    """Issue 36: at 5.04 rad/s (a period of 1.25 s) differences of fixed step 1e-5 on the map at rtol 1e-10
    gave moduli 8.4e-6 from 1. The undamped linear link's one pair is on the circle exactly (``det M
    = 1``: ``tr J = 0``, Liouville; a complex pair): its moduli's distance from 1 is their error, which
    the estimate must bound; the differences' step and tolerance now follow an error balance."""
    ds = periodic("paper-dry", {"beam.damping_ratio": 0.0, "mechanism.crank_speed": 5.04}, jacobian=jacobian)
    assert ds.attrs["jacobian"] == jacobian
    mu = ds.floquet_modulus.values * np.exp(1j * ds.floquet_argument.values)
    assert abs(mu[0].imag) > 0.1 and mu[0] == pytest.approx(np.conj(mu[1]), abs=1e-12)  # a complex pair
    error = np.abs(ds.floquet_modulus.values - 1.0)
    assert np.all(error <= ds.floquet_error.values) and np.all(ds.floquet_error.values < bound)
    assert np.max(error) < 0.1 * bound
    assert ds.attrs["stable"] == 0 and ds.attrs["floquet_undecided"] == 2


def test_no_periodic_response_is_reported_not_hidden():
    # the README's film-breakdown case: every period ends early, so no map, so no orbit
    with pytest.raises(ShootingError, match="film_breakdown.*contact.law"):
        periodic("paper", {"film.viscosity": 1e-3, "film.clearance": 4.6e-3})


# ----------------------------------------------------------------------------- films and impacts
@pytest.mark.parametrize("film", ["wedge", "wedge+squeeze"])
def test_film_orbit_closes_and_wedge_film_is_volume_preserving(film):
    ds = periodic("paper", {"film.model": film})
    assert ds.attrs["residual"] < 1e-9 and ds.attrs["residual_q"] < 1e-11  # [m]
    mu = ds.floquet_modulus.values
    if film == "wedge":  # a force of q alone (no q_dot): det M = 1, no asymptotic stability possible
        assert np.prod(mu) == pytest.approx(1.0, abs=1e-7) and ds.attrs["stable"] == 0
    else:  # the squeeze film damps
        assert np.max(mu) < 0.01 and ds.attrs["stable"] == 1


def test_impacting_orbit_matches_the_transient_and_the_saltation_determinant():
    zeta, e = 0.05, 0.7
    settings = {"beam.damping_ratio": zeta, "film.model": "none", "film.clearance": 3.6e-3,
                "contact.restitution": e}
    config = resolve("paper-impact", settings)
    ds = periodic(config)
    assert ds.attrs["jacobian"] == "variational+saltation" and ds.attrs["jacobian_note"] == ""
    n_impacts = ds.attrs["impact_count"]
    assert n_impacts == 3
    T = ds.attrs["period"]
    # Liouville between impacts, e^2 for each impact's saltation matrix (one mode)
    w1 = float(ds.omega_n.values[0])
    expected = math.exp(-2 * zeta * w1 * T) * e ** (2 * n_impacts)
    assert np.prod(ds.floquet_modulus.values) == pytest.approx(expected, rel=1e-8)
    # by differences of the map (tests/test_saltation.py compares the matrices)
    fd = periodic(config, jacobian="finite-difference")
    assert np.prod(fd.floquet_modulus.values) == pytest.approx(expected, rel=1e-4)
    # the transient from rest settles on the same impacts
    transient = lubelink.simulate(config, {"solver.t_end": 10 * T})
    late = transient.impact_time.values[-n_impacts:] - 9 * T
    np.testing.assert_allclose(late, ds.impact_time.values, atol=1e-7)


def test_user_motion_needs_its_period_and_is_exact_for_harmonic_forcing():
    Omega, a, zeta = 20.0, 5.0, 0.1
    motion = PrescribedMotion(A_O2=lambda t: a * np.sin(Omega * t), omega=lambda t: 0.0 * t,
                              alpha=lambda t: 0.0 * t, x_star=lambda t: 0.4 + 0.0 * t, V_r=lambda t: 0.0 * t)
    with pytest.raises(ValueError, match="period"):
        periodic("paper-dry", {"beam.damping_ratio": zeta}, motion=motion)
    ds = periodic("paper-dry", {"beam.damping_ratio": zeta, "solver.output_step": 0.01}, motion=motion,
                  period=2 * math.pi / Omega)
    w = float(ds.omega_n.values[0])
    L = 1.0
    F = -2 / (L * math.pi) * 2 * a  # the modal load of A_O2 = a sin(Omega t) on mode 1
    exact = np.imag(F * np.exp(1j * Omega * ds.time.values) / (w**2 - Omega**2 + 2j * zeta * w * Omega))
    np.testing.assert_allclose(ds.q.values[:, 0], exact, rtol=0, atol=1e-12)


def test_simulate_run_from_a_given_state():
    config = resolve("paper-dry", {"solver.t_end": 0.05})
    a, b = run(config), run(config, y0=np.zeros(2))
    np.testing.assert_array_equal(a.y, b.y)
    c = run(config, y0=[1e-3, 0.0])
    assert c.y[0, 0] == 1e-3 and c.t[0] == 0.0


# ----------------------------------------------------------------------------- command line
def test_cli_periodic_writes_a_loadable_file(tmp_path, capsys):
    out = tmp_path / "dry.nc"
    assert main(["periodic", "--scenario", "paper-dry", "--set", "beam.damping_ratio=0.05", "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "stable" in text and "variational" in text
    ds = lubelink.load(out)
    assert {"floquet_modulus", "floquet_argument", "q", "u2_mid"} <= set(ds.variables)
    assert ds.attrs["stable"] == 1 and ds.attrs["period"] == pytest.approx(0.2)
    assert main(["periodic", "--scenario", "paper-dry", "-o", str(out)]) == 2  # exists: never replaced
    assert "--overwrite" in capsys.readouterr().err


def test_a_failed_final_write_keeps_the_orbit_in_a_fallback_file(tmp_path, monkeypatch, capsys):
    """Issue 37 item 3: a write that failed at the end (a full disk, a folder turned read-only) lost the work
    with a traceback. As ``run`` does, the results go beside the target (or here, or the temporary folder),
    the error line says where, and the status is 1."""
    from lubelink import netcdf

    out = tmp_path / "dry.nc"
    real = netcdf.write

    def full_disk(results, path, overwrite=False):
        if Path(path) == out:
            raise OSError(28, "No space left on device")
        return real(results, path, overwrite=overwrite)

    monkeypatch.setattr(netcdf, "write", full_disk)
    assert main(["periodic", "--scenario", "paper-dry", "--set", "beam.damping_ratio=0.05", "-o", str(out)]) == 1
    captured = capsys.readouterr()
    assert "No space left on device" in captured.err and "instead" in captured.err
    assert "Traceback" not in captured.err and not out.exists()
    kept = [p for p in tmp_path.iterdir() if p.suffix == ".nc"]
    assert len(kept) == 1 and lubelink.load(kept[0]).attrs["period"] == pytest.approx(0.2)
    assert str(kept[0]) in captured.out  # the summary names the file written


def test_the_monodromy_from_the_models_jacobian_equals_the_differences():
    """The variational equations with the right-hand side's own Jacobian (one evaluation) and with
    central differences (2n + 1): the same flow and monodromy matrix over a crank period, squeeze
    film with half-Sommerfeld cavitation and asperities, 2 modes."""
    from lubelink.build import build_model
    from lubelink.steady.variational import flow_with_jacobian

    cfg = resolve("lubricated", {"beam.modes": 2, "film.clearance": 1e-3})
    model = build_model(cfg)
    assert model.jacobian_missing(None) == ""
    T = crank_period(cfg)
    y0 = np.array([1e-4, -2e-5, 0.01, 0.0])
    scale = np.array([1e-3, 1e-3, 0.1, 0.1])
    out = {}
    for jacobian in (True, False):
        out[jacobian] = flow_with_jacobian(model.functions()[0], model.params, 0.0, y0, T, scale, rtol=1e-10,
                                           atol=1e-13, jacobian=jacobian, p_type=model.params_type)
    np.testing.assert_allclose(out[True][0], out[False][0], rtol=0, atol=1e-11)
    M, M_fd = out[True][1], out[False][1]
    assert np.abs(M).max() > 0.1
    np.testing.assert_allclose(M, M_fd, rtol=0, atol=1e-6 * np.abs(M).max())

"""Periodic orbits, Floquet multipliers and continuation of the spatial model (``beam.model = "spatial"``).

The shooting code (lubelink.steady) runs on the whole spatial state ``[q1, q2, q3, q1_t, q2_t, q3_t]``.
References, independent of it:

* the planar model's periodic orbit and multipliers (its planar case differs only by the
  axial-bending terms ``alpha q1 + 2 omega q1_t`` of the ``u2`` equation, docs/spatial.md), and
  the closed-form multipliers of the ``u3`` block, which planar motion leaves decoupled and
  autonomous;
* the monodromy matrix of the dry link's linear time-periodic equations, written in this file from
  the vector form of docs/spatial.md ("Modal equations") with cross-product matrices and integrated
  by SciPy's ``solve_ivp``;
* long direct simulations (the orbit returns to itself; a transient from rest settles on it at the
  rate of the largest Floquet multiplier);
* linearity of the out-of-plane response in a small offset of the slider line (continuation).
"""

import math

import numpy as np
import pytest

import lubelink
from lubelink.link import spatial
from lubelink.cli import main
from lubelink.config import resolve
from lubelink.link.kinematics import slider_crank
from lubelink.link.spatial_motion import geometry
from lubelink.steady import find_periodic
from lubelink.steady.orbit import orbit_run

ZETA = {"beam.damping_ratio": 0.02}
# one mode per direction: the 6-state spatial link, seconds per orbit; the references (the linear time-periodic
# monodromy, the multipliers exp(-zeta W T)) leave the axial force out, so the runs do too
ONE = {**ZETA, "beam.modes": 1, "beam.axial_force": "none"}


def blocks(y, N):
    """``(q1, q2, q3, q1_t, q2_t, q3_t)`` of spatial states ``(..., 6 N)``."""
    return tuple(y[..., k * N:(k + 1) * N] for k in range(6))


@pytest.mark.parametrize("scenario", ["paper-dry", "paper"])
def test_planar_case_orbit_is_the_planar_orbit_with_u3_zero(scenario):
    """Planar motion: u2 of the spatial orbit equals the planar model's orbit within the axial coupling, u3 = 0.

    The ``u2`` equation of the spatial model is the planar one plus ``-c (alpha q1 + 2 omega q1_t)``
    (docs/spatial.md; ``c = 8 / (3 pi)`` projects the free axial end's mode on the sine, 1 for the fixed
    end). Its effect on ``q2`` is bounded by the quasi-static response to the largest such load,
    ``max |alpha q1 + 2 omega q1_t| / (W^2 - max omega^2)``, times a dynamic factor of 2 (the harmonics of
    the crank, 31.4 and 62.8 rad/s, lie well below ``W = 148 rad/s``: factors 1.05 and 1.2). Measured with
    the free end (the default): 7.2 nm (dry) and 7.6 nm (wedge film) on a 2.1 mm peak (2.1 and 2.2 nm with the
    fixed end, whose ``u1`` is a third as large).
    """
    planar = find_periodic(resolve(scenario, ONE))
    sp = find_periodic(resolve(scenario, {**ONE, "beam.model": "spatial"}))
    N = 1
    assert sp.y0.size == 6 * N and sp.residual < 1e-9
    run_sp, _ = orbit_run(sp)
    run_pl, _ = orbit_run(planar)
    np.testing.assert_allclose(run_sp.t, run_pl.t)
    q1, q2, q3, q1_t, _, q3_t = blocks(run_sp.y, N)
    assert np.max(np.abs(q3)) == 0.0 and np.max(np.abs(q3_t)) == 0.0  # u3 stays zero: decoupled, unforced
    m, b = sp.config.mechanism, sp.config.beam
    k = slider_crank(run_sp.t, m.crank_length, m.rod_length, m.crank_speed, m.guide_distance)
    omega, alpha = k["omega"], k["alpha"]
    W = math.pi**2 / m.rod_length**2 * math.sqrt(b.youngs_modulus * b.second_moment / (b.density * b.area))
    coupling = np.max(np.abs(alpha * q1[:, 0] + 2 * omega * q1_t[:, 0]))
    bound = 2.0 * coupling / (W**2 - np.max(omega**2))
    diff = np.max(np.abs(q2 - run_pl.y[:, :N]))
    assert 0.0 < diff < bound, (diff, bound)
    assert diff < 5e-6 * np.max(np.abs(q2))  # 7.2 nm on 2.1 mm measured
    # the multipliers: the planar pair (to the coupling's and the differences' accuracy) ...
    mu = sp.multipliers
    for m_pl in planar.multipliers:
        assert np.min(np.abs(mu - m_pl)) < 1e-5, (m_pl, mu)
    # ... the u3 pair exp(lambda T), lambda = W (-zeta +- i sqrt(1 - zeta^2)): u3_tt + 2 zeta W u3_t + W^2 u3 = 0
    # (rotation about e3 leaves no centrifugal term on u3: w x (w x e3) = 0) ...
    z = ZETA["beam.damping_ratio"]
    lam = W * complex(-z, math.sqrt(1 - z * z))
    for m_u3 in (np.exp(lam * sp.period), np.exp(np.conj(lam) * sp.period)):
        assert np.min(np.abs(mu - m_u3)) < 1e-7, (m_u3, mu)
    # ... and the axial pair, exp(-zeta W1 T) ~ 6e-15: zero to the differences' accuracy
    assert np.sort(np.abs(mu))[:2].max() < 1e-6
    # the directions of the eigenvectors say which pair is which
    ds = lubelink.periodic(scenario, set={**ONE, "beam.model": "spatial"})
    direction = dict(zip(np.round(ds.floquet_modulus.values, 12), ds.floquet_direction.values))
    assert ds.floquet_direction.attrs["flag_meanings"] == "axial in_plane out_of_plane"
    assert direction[round(abs(np.exp(lam * sp.period)), 12)] == 3
    assert sorted(ds.floquet_direction.values.tolist()) == [1, 1, 2, 2, 3, 3]


def _ltp_monodromy(config, period):
    """Monodromy of the dry link's homogeneous equations (one mode), from docs/spatial.md by solve_ivp.

    ``Q_tt + 2 w x Q_t + alpha x Q + w x (w x Q) + diag(W^2) Q + 2 zeta diag(W) Q_t = 0`` with
    ``w``, ``alpha`` of the RSSP slider-crank, written with cross-product matrices. With a free axial end
    the axial mode ``sin(pi x / (2 L))`` and the bending sine ``sin(pi x / L)`` differ: the entries between
    the axial and the bending directions carry the projection ``(2/L) int_0^L sin(pi x / (2 L)) sin(pi x / L) dx
    = 8 / (3 pi)``.
    """
    from scipy.integrate import solve_ivp

    m, b = config.mechanism, config.beam
    g = geometry(m)
    W = spatial.frequencies(1, m.rod_length, b.youngs_modulus, b.density, b.area, b.second_moment,
                            b.height * b.width**3 / 12, b.axial_end)
    zeta = b.damping_ratio
    c = 1.0 if b.axial_end == "fixed" else 8.0 / (3.0 * np.pi)
    P = np.array([[1.0, c, c], [c, 1.0, 1.0], [c, 1.0, 1.0]])

    def cross(a):
        return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])

    def f(t, z):
        _, w, al, *_ = spatial.slider_crank_rssp(t, m.crank_length, m.rod_length, m.crank_speed, m.guide_distance,
                                                 g.crank_axis, g.crank_ref, g.slider_point, g.slider_dir)
        Wx = cross(w)
        K = -P * (cross(al) + Wx @ Wx) - np.diag(W**2)
        C = -2.0 * P * Wx - 2.0 * zeta * np.diag(W)
        A = np.block([[np.zeros((3, 3)), np.eye(3)], [K, C]])
        return (A @ z.reshape(6, 6)).ravel()

    sol = solve_ivp(f, (0.0, period), np.eye(6).ravel(), method="DOP853", rtol=1e-11, atol=1e-12)
    assert sol.success
    return sol.y[:, -1].reshape(6, 6)


def test_dry_spatial_slider_crank_monodromy_matches_an_independent_one():
    """Tilted crank: the spin ``w1`` about the link (0.11 rad/s) and ``alpha1`` (3.4 rad/s^2) couple u2 and u3,
    ``w3``, ``alpha3`` (2.2 rad/s, 69 rad/s^2) u1 and u2, with coefficients periodic in time. (``w2``,
    ``alpha2`` vanish for this mechanism: ``k . e1`` is constant, the crank pin moving in the plane normal
    to ``k``.) The whole scaled monodromy matrix of the shooting (the compiled variational equations;
    before, central differences of the compiled map, DOP853 for one mode) equals the reference to 1e-7
    (measured 2.3e-9 by differences), the coupling entries included."""
    cfg = resolve("spatial-slider-crank", {**ONE, "film.model": "none"})
    orbit = find_periodic(cfg)
    assert orbit.jacobian == "variational"
    M = _ltp_monodromy(orbit.config, orbit.period)
    S = orbit.scale
    scaled = lambda A: A * S[None, :] / S[:, None]  # noqa: E731
    err = np.max(np.abs(scaled(orbit.monodromy) - scaled(M)))
    assert err < 1e-7, err
    # the coupling is there: u3 rows (2, 5) respond to u2 columns (1, 4) well above that error
    assert np.max(np.abs(scaled(M)[np.ix_([2, 5], [1, 4])])) > 1e3 * err
    ref = lubelink.steady.floquet.multipliers(M)
    big = np.abs(ref) > 1e-6  # the bending multipliers; the axial ones (exp(-zeta W1 T) ~ 6e-15) are noise
    assert big.sum() == 4
    for m_ref in ref[big]:
        assert np.min(np.abs(orbit.multipliers - m_ref)) < 1e-7, (m_ref, orbit.multipliers)
    assert np.all(np.abs(orbit.multipliers[4:]) < 1e-6)
    # both bending pairs have the damping's modulus exp(-zeta W T) (square section; the gyroscopic terms
    # conserve energy), their arguments differ (the in-plane pair is softened by omega^2)
    assert orbit.stable and abs(abs(ref[0]) - abs(ref[2])) < 1e-6 and abs(np.angle(ref[0]) - np.angle(ref[2])) > 1e-4
    # the exponential method steps over the free axial vibration that an axial difference starts: the in-plane
    # response to it is off by 2.5e-5 (scaled; measured), the multipliers still within 1e-7
    fast = find_periodic(resolve("spatial-slider-crank", {**ONE, "film.model": "none", "solver.method": "exponential"}),
                         jacobian="finite-difference")
    off = np.abs(scaled(fast.monodromy) - scaled(M))
    axial = [0, 3]
    assert np.max(np.delete(off, axial, axis=1)) < 1e-7 and np.max(off[:, axial]) < 1e-4
    for m_ref in ref[big]:
        assert np.min(np.abs(fast.multipliers - m_ref)) < 1e-7


def test_spatial_orbit_is_periodic_and_attracts_the_transient():
    """``spatial-slider-crank`` (wedge film, 2 % damping, one mode per direction).

    From the orbit's state a long simulation (10 periods) returns to it after every period. From rest
    the transient settles on it: written in the eigenvectors of the monodromy matrix, each component of
    its distance to the orbit shrinks per period by the modulus of its multiplier, which for the bending
    pairs is the damping's ``exp(-zeta W T)`` (the film's wedge force depends on the deflection only and
    the gyroscopic terms conserve energy: neither damps); periods 6-12, to 2e-3 (measured: 1e-5 for the
    out-of-plane pair, 7e-4 for the in-plane pair, which the film's nonlinearity still bends).
    """
    import scipy.linalg

    cfg = resolve("spatial-slider-crank", ONE)
    orbit = find_periodic(cfg)
    assert orbit.stable
    pmap = orbit.period_map
    per = round(orbit.period / pmap.config.solver.output_step)
    long = pmap.run(orbit.y0, t_end=10 * orbit.period)
    at_periods = long.y[::per]
    assert at_periods.shape[0] == 11
    drift = np.max(np.abs(at_periods - orbit.y0) / orbit.scale, axis=1)
    assert np.max(drift) < 1e-7, drift  # scaled (the shooting's residual 1e-9; the flow contracts)
    assert np.max(np.abs(long.y[:, 1])) > 1e-3 and np.max(np.abs(long.y[:, 2])) > 1e-4  # u2 ~ 2.1 mm, u3 ~ 0.2 mm
    S = orbit.scale
    rest = pmap.run(np.zeros(pmap.n), t_end=12 * orbit.period).y[::per]
    dist = np.max(np.abs(rest - orbit.y0) / S, axis=1)
    assert dist[12] < 1e-2 * dist[0], dist  # reached: 0.55^12 = 8e-4
    mu, V = scipy.linalg.eig(orbit.monodromy * S[None, :] / S[:, None])
    c = np.linalg.solve(V, ((rest - orbit.y0) / S).T).T  # the distance in the eigenvectors, per period
    b = cfg.beam
    W = math.pi**2 * math.sqrt(b.youngs_modulus * b.second_moment / (b.density * b.area))  # u2 and u3 (square)
    expected = math.exp(-b.damping_ratio * W * orbit.period)
    bending = np.argsort(-np.abs(mu))[:4]
    np.testing.assert_allclose(np.abs(mu[bending]), expected, rtol=1e-6)
    for i in bending:
        np.testing.assert_allclose(np.abs(c[7:, i] / c[6:-1, i]), expected, rtol=2e-3)


def test_continuation_over_the_slider_offset_from_the_planar_case():
    """From the planar case (offset 0: u3 = 0) to a slider line 4 cm out of the plane: the out-of-plane
    response grows linearly with the small offset (measured: peak u3_mid / offset constant to 3e-5), u2
    hardly changes, the last orbit equals direct shooting at 4 cm, every orbit stable (2 % damping).

    (Tilting the crank axis alone, slider line through the crank centre, only turns the planar
    mechanism into the plane normal to the axis: u3 stays zero, gravity aside.)
    """
    br = lubelink.continuation("paper", set={**ONE, "beam.model": "spatial"}, parameter="mechanism.slider_offset",
                               stop=0.04, max_parameter_step=0.01)
    assert br.attrs["status"] == "complete" and br.sizes["point"] >= 5
    offset = br.parameter.values
    assert offset[0] == 0.0 and offset[-1] == pytest.approx(0.04, abs=1e-12)
    assert br.peak_u3_mid.values[0] == 0.0 and br.peak_u3_mid.attrs["units"] == "m"
    ratio = br.peak_u3_mid.values[1:] / offset[1:]
    assert ratio.min() > 1e-3 and np.ptp(ratio) < 1e-3 * ratio.mean(), ratio  # linear in the offset
    assert np.ptp(br.peak_u2_mid.values) < 1e-4 * br.peak_u2_mid.values[0]
    assert br.stable.values.all() and br.q3_0.dims == ("point", "mode")
    assert br.peak_u1_mid.values.min() > 1e-7  # the axial stretch, about 1 um (the free end)
    direct = find_periodic(resolve("paper", {**ONE, "beam.model": "spatial", "mechanism.slider_offset": 0.04}))
    last = np.concatenate([br[v].values[-1] for v in ("q1_0", "q0", "q3_0", "q1_dot0", "q_dot0", "q3_dot0")])
    np.testing.assert_allclose(last, direct.y0, rtol=0, atol=1e-7 * np.max(np.abs(direct.y0)))


def test_cli_periodic_and_continue_for_the_spatial_model(tmp_path, capsys):
    out = tmp_path / "sp.nc"
    assert main(["periodic", "--scenario", "spatial-slider-crank", "--set", "beam.modes=1", "--set",
                 "beam.damping_ratio=0.02", "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "peak |u3_mid|" in text and "stable" in text and "variational" in text
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sp.nc"]  # written under a temporary name, renamed
    ds = lubelink.load(out)
    assert ds.attrs["stable"] == 1 and ds.sizes["multiplier"] == 6
    for name, units in (("u3_mid", "m"), ("u1", "m"), ("q3", "m"), ("q1_dot", "m s-1"), ("floquet_modulus", "1")):
        assert ds[name].attrs["units"] == units
    assert np.max(np.abs(ds.u3_mid.values)) > 1e-4
    size = out.stat().st_size
    assert main(["periodic", "--scenario", "spatial-slider-crank", "-o", str(out)]) == 2  # exists: never replaced
    assert out.stat().st_size == size
    branch = tmp_path / "b.nc"
    assert main(["continue", "--scenario", "spatial-slider-crank", "--set", "beam.modes=1", "--set",
                 "beam.damping_ratio=0.02", "--to", "32.4", "--max-step", "0.5", "-o", str(branch)]) == 0
    assert "complete" in capsys.readouterr().out
    import xarray as xr

    with xr.open_dataset(branch) as b:
        b.load()
    assert b.sizes["point"] >= 3 and b.peak_u3_mid.attrs["units"] == "m" and b.parameter.values[-1] == 32.4


@pytest.mark.parametrize("args, words", [
    (["--parameter", "mechanism.crank_tilt", "--to", "2.0"], ["mechanism.crank_tilt = 2.0", "[-1.2, 1.2]"]),
    (["--parameter", "mechanism.slider_offset", "--to", "1.5"], ["mechanism.slider_offset = 1.5"]),
])
def test_cli_continue_refuses_an_end_out_of_range(tmp_path, capsys, args, words):
    code = main(["continue", "--scenario", "spatial-slider-crank", "-o", str(tmp_path / "b.nc"), *args])
    err = capsys.readouterr().err
    assert code == 2 and all(w in err for w in words), err
    assert not list(tmp_path.iterdir())


def test_bad_inputs_are_refused_clearly():
    cfg = resolve("spatial-slider-crank", ONE)
    with pytest.raises(ValueError, match=r"y0: 2 values; .*\[q1, q2, q3, q1_t, q2_t, q3_t\], 6 values"):
        find_periodic(cfg, y0=[0.0, 0.0])
    with pytest.raises(lubelink.ConfigError, match="beam.model = 'spatial'"):  # tilting the planar model
        lubelink.continuation("paper-dry", set=ZETA, parameter="mechanism.crank_tilt", stop=0.1)
    with pytest.raises(ValueError, match="jacobian = 'exact'"):
        find_periodic(cfg, jacobian="exact")

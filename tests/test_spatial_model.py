"""The spatial model wired into the library (``beam.model = "spatial"``, lubelink.spatial_model).

* its planar case against the planar model, the film included: the right-hand side differs only
  by the axial-bending terms ``2 omega q1_t + alpha q1`` (to round-off), a whole run by less than
  0.1 um on u2_mid while u3 stays exactly zero;
* the compiled kernels equal their Python source on random states;
* the spatial slider-crank scenario: complete on both backends, exponential and DOP853 agree, and
  the run equals a direct SciPy integration of ``spatial.accelerations`` under
  ``spatial.slider_crank_rssp`` (the wiring of frequencies, motion and frame);
* impacts and compliant contact on the u2 faces: the planar case against the planar model;
* bad keys and unsupported combinations are refused with the key, value and valid range;
* the command line writes u1, u3, u3_mid with units.
"""

import subprocess
import sys

import numpy as np
import pytest

import lubelink
from lubelink import spatial
from lubelink.config import resolve
from lubelink.model import build_model, rhs
from lubelink.spatial_model import SpatialModel, spatial_gap, spatial_rhs
from lubelink.spatial_motion import geometry, spatial_motion_at

EPS = np.finfo(float).eps
TIGHT = {"solver.rtol": 1e-10, "solver.atol": 1e-14}


def _random_state(rng, N, omega, amplitude=1.5e-3):
    amp = amplitude / np.arange(1, N + 1) ** 2
    q = rng.uniform(-1, 1, (3, N)) * amp * np.array([[1e-3], [1.0], [1.0]])
    return np.concatenate([q.ravel(), (rng.uniform(-1, 1, (3, N)) * amp * omega).ravel()])


@pytest.mark.parametrize("film", ["none", "wedge+squeeze"])
def test_planar_case_right_hand_side_is_the_planar_one_plus_the_axial_terms(film):
    """Planar motion: u2 rows = planar model's rhs - (2 omega q1_t + alpha q1); u3 rows unforced."""
    N = 3
    over = {"beam.modes": N, "film.model": film, "film.clearance": 5e-3}
    planar = build_model(resolve("paper", over))
    sp = build_model(resolve("paper", {**over, "beam.model": "spatial"}))
    assert isinstance(sp, SpatialModel) and sp.state_frequencies.size == 3 * N
    rng = np.random.default_rng(3)
    for _ in range(10):
        t = rng.uniform(0.0, 0.2)
        y = _random_state(rng, N, planar.omega_n[0])
        y[2 * N:3 * N] = y[5 * N:] = 0.0  # u3 = 0
        d_sp = sp.rhs(t, y)
        d_pl = planar.rhs(t, sp.planar_state(y))
        _, omega, alpha, *_ = planar.kinematics(t)
        expected = d_pl[N:] - (2.0 * omega * y[3 * N:4 * N] + alpha * y[:N])
        scale = np.max(np.abs(d_pl)) + planar.omega_n[-1] ** 2 * np.max(np.abs(y[N:2 * N]))
        np.testing.assert_allclose(d_sp[4 * N:5 * N], expected, rtol=0, atol=1e2 * EPS * scale)
        np.testing.assert_array_equal(d_sp[5 * N:], 0.0)
        np.testing.assert_array_equal(d_sp[:3 * N], y[3 * N:])
        assert sp.gap(t, y) == pytest.approx(planar.gap(t, sp.planar_state(y)), abs=1e-12)


@pytest.mark.parametrize("scenario", ["paper-dry", "paper"])
def test_planar_case_through_simulate_matches_the_planar_model(scenario):
    """u3 stays zero; u2_mid within 0.1 um of the planar model (the axial Coriolis/Euler terms, ~10 nm)."""
    over = {"beam.modes": 3, "solver.t_end": 0.3, **TIGHT}
    pl = lubelink.simulate(scenario, set=over)
    sp = lubelink.simulate(scenario, set={**over, "beam.model": "spatial"})
    assert sp.attrs["status"] == pl.attrs["status"] == "complete"
    assert np.max(np.abs(sp.u3.values)) == 0.0 and np.max(np.abs(sp.u3_mid.values)) == 0.0
    diff = np.max(np.abs(sp.u2_mid.values - pl.u2_mid.values))
    peak = np.max(np.abs(pl.u2_mid.values))
    assert peak > 1e-3
    assert 1e-9 < diff < 1e-7, diff  # the coupling is there, and small
    assert 1e-8 < np.max(np.abs(sp.u1.values)) < 1e-5  # the axial stretch, sub-micrometre
    if scenario == "paper":
        np.testing.assert_allclose(sp.film_force.values, pl.film_force.values, rtol=0,
                                   atol=1e-3 * np.max(np.abs(pl.film_force.values)))


@pytest.mark.parametrize("over", [{}, {"film.model": "wedge+squeeze", "film.sides": 2},
                                  {"film.roughness": 1e-6, "mechanism.gravity": [0.0, -9.81]}])
def test_compiled_spatial_kernels_equal_their_python_source(over):
    model = build_model(resolve("spatial-slider-crank", {"film.clearance": 5e-3, **over}))
    assert model.compiled
    p, N = model.params, model.modes
    rng = np.random.default_rng(11)
    for _ in range(10):
        t = rng.uniform(0.0, 0.5)
        y = _random_state(rng, N, model.omega_n[0])
        a, b = np.empty(6 * N), np.empty(6 * N)
        spatial_rhs(t, y, a, p)
        spatial_rhs.py_func(t, y, b, p)
        scale = np.max(np.abs(a)) + np.max(model.state_frequencies) ** 2 * np.max(np.abs(y[:3 * N]))
        np.testing.assert_allclose(a, b, rtol=0, atol=1e3 * EPS * scale)
        np.testing.assert_allclose(spatial_gap(t, y, p), spatial_gap.py_func(t, y, p), rtol=1e-10, atol=1e-15)


def _scipy_reference(config, t_eval):
    """``spatial.accelerations`` under ``spatial.slider_crank_rssp`` of the scenario's geometry, dry, by SciPy."""
    from scipy.integrate import solve_ivp

    b, m = config.beam, config.mechanism
    N, L = b.modes, m.rod_length
    W = spatial.frequencies(N, L, b.youngs_modulus, b.density, b.area, b.second_moment, b.height * b.width**3 / 12)
    g = geometry(m)
    F = np.zeros(3 * N)
    mass = b.density * b.area * L / 2

    def f(t, y):
        A_O, w, al, *_ = spatial.slider_crank_rssp(t, m.crank_length, L, m.crank_speed, m.guide_distance,
                                                   g.crank_axis, g.crank_ref, g.slider_point, g.slider_dir)
        out = np.empty(6 * N)
        spatial.accelerations(y, W, b.damping_ratio, A_O, w, al, F, mass, L, out)
        return out

    return solve_ivp(f, (0.0, t_eval[-1]), np.zeros(6 * N), method="DOP853", t_eval=t_eval, rtol=1e-11,
                     atol=1e-15).y.T


def test_spatial_scenario_runs_on_both_backends_and_methods():
    """Complete; numba/numpy equal; exponential and DOP853 within 1e-7 of the peak of each direction;
    the dry run equals a direct SciPy integration of the equations within 1e-5 of the peaks."""
    over = {"solver.t_end": 0.1, **TIGHT}  # u1 (0.6 um) lies far below the default atol
    runs = {(method, backend): lubelink.simulate("spatial-slider-crank", set={
        **over, "solver.method": method, "solver.backend": backend})
        for method, backend in [("exponential", "numba"), ("DOP853", "numba"), ("exponential", "numpy")]}
    for ds in runs.values():
        assert ds.attrs["status"] == "complete", ds.attrs["message"]
    ex, dop, ex_np = runs["exponential", "numba"], runs["DOP853", "numba"], runs["exponential", "numpy"]
    assert ex.attrs["backend"] == "numba" and ex_np.attrs["backend"] == "numpy"
    for name in ("u1", "u2", "u3"):
        peak = np.max(np.abs(ex[name].values))
        assert peak > 0.0
        np.testing.assert_allclose(ex_np[name].values, ex[name].values, rtol=0, atol=1e-9 * peak)
        np.testing.assert_allclose(dop[name].values, ex[name].values, rtol=0, atol=1e-7 * peak)  # measured 7e-9
    assert np.max(np.abs(ex.u3_mid.values)) > 1e-4  # out of the plane indeed
    # dry, against SciPy on the equations themselves
    dry = lubelink.simulate("spatial-slider-crank", set={**over, "film.model": "none"})
    cfg = resolve("spatial-slider-crank", {**over, "film.model": "none"})
    ref = _scipy_reference(cfg, dry.time.values[1:])
    N = cfg.beam.modes
    for k, name in enumerate(("u1", "u2", "u3")):
        u_ref = spatial.deflections(ref, [0.5], 1.0)[k][:, 0]
        u = dry[name].sel(x=0.5, method="nearest").values[1:]
        np.testing.assert_allclose(u, u_ref, rtol=0, atol=1e-5 * np.max(np.abs(u_ref)))
    assert ref.shape[1] == 6 * N


def test_spatial_motion_of_the_planar_geometry_is_the_planar_slider_crank():
    from lubelink.kinematics import slider_crank

    cfg = resolve("paper", {"beam.model": "spatial"})
    m = geometry(cfg.mechanism)
    for t in np.linspace(0.0, 0.2, 7):
        A_O, w, al, v_O, x_star, V_r = spatial_motion_at(t, m)[:6]
        k = slider_crank(t, 0.07, 1.0, 10 * np.pi, 0.4)
        np.testing.assert_allclose([A_O[1], w[2], al[2], x_star, V_r],
                                   [k["A_O2"], k["omega"], k["alpha"], k["x_star"], k["V_r"]], rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("over, words", [
    ({"beam.model": "3d"}, ["beam.model = '3d'", '"planar", "spatial"']),
    ({"beam.model": "spatial", "mechanism.crank_tilt": 2.0}, ["mechanism.crank_tilt = 2.0", "[-1.2, 1.2]"]),
    ({"beam.model": "spatial", "model.equations": "printed"}, ["model.equations = 'printed'", "beam.model = 'spatial'"]),
    ({"beam.model": "spatial", "beam.width_ratio": 0.005}, ["beam.width_ratio = 0.005", "[0.01, 100]"]),
    ({"beam.model": "spatial", "collar.mass": 0.3}, ["collar.mass = 0.3"]),
    ({"mechanism.crank_tilt": 0.2}, ["mechanism.crank_tilt = 0.2", "beam.model = 'spatial'"]),
    ({"beam.model": "spatial", "mechanism.slider_offset": 1.2}, ["mechanism.slider_offset = 1.2", "cannot reach"]),
    ({"beam.model": "spatial", "mechanism.guide_distance": 0.05}, ["guide_distance = 0.05", "pad"]),
])
def test_bad_spatial_configurations_are_refused(over, words):
    with pytest.raises(lubelink.ConfigError) as e:
        resolve("paper", over)
    for w in words:
        assert w in str(e.value), (w, str(e.value))


@pytest.mark.parametrize("law", ["restitution", "compliant"])
def test_impacts_on_the_u2_faces_match_the_planar_model(law):
    """paper-impact's first impacts (1 mode, 1.273-1.2744 s): the planar case of the spatial model hits at the
    planar model's times (2e-6 s later: the axial coupling, 0.25 um on u2 by then) with its velocities; a Zeno
    sequence stops the restitution run with status chatter (no sustained contact for the spatial model)."""
    over = {"solver.t_end": 1.2744, "contact.law": law}
    pl = lubelink.simulate("paper-impact", set=over)
    sp = lubelink.simulate("paper-impact", set={**over, "beam.model": "spatial"})
    assert sp.attrs["status"] == pl.attrs["status"] == "complete"
    assert sp.sizes["impact"] == pl.sizes["impact"] >= (8 if law == "restitution" else 1)
    np.testing.assert_allclose(sp.impact_time.values, pl.impact_time.values, rtol=0, atol=1e-5)
    np.testing.assert_allclose(sp.impact_velocity.values, pl.impact_velocity.values, rtol=2e-3)
    assert np.max(np.abs(sp.u3.values)) == 0.0
    if law == "compliant":
        np.testing.assert_allclose(np.max(sp.contact_force.values), np.max(pl.contact_force.values), rtol=1e-3)
    else:
        later = lubelink.simulate("paper-impact", set={"solver.t_end": 1.28, "beam.model": "spatial"})
        assert later.attrs["status"] == "chatter" and "spatial model" in later.attrs["message"]


def test_a_user_motion_is_refused_by_the_spatial_model():
    from lubelink.kinematics import SliderCrank

    cfg = resolve("spatial-slider-crank")
    with pytest.raises(lubelink.ConfigError, match="beam.model = 'spatial'"):
        build_model(cfg, SliderCrank(cfg.mechanism))


def test_periodic_orbits_refuse_the_spatial_model():
    with pytest.raises(lubelink.ConfigError, match="periodic orbits"):
        lubelink.periodic("spatial-slider-crank")


def test_the_command_line_writes_u1_u3(tmp_path):
    out = tmp_path / "spatial.nc"
    r = subprocess.run([sys.executable, "-m", "lubelink", "run", "--scenario", "spatial-slider-crank", "--set",
                        "solver.t_end=0.05", "--set", "output.x_points=11", "-o", str(out)],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    ds = lubelink.load(out)
    assert ds.attrs["status"] == "complete"
    for name, dims in (("u1", ("time", "x")), ("u3", ("time", "x")), ("u3_mid", ("time",))):
        assert ds[name].dims == dims and ds[name].attrs["units"] == "m"
    assert np.max(np.abs(ds.u3_mid.values)) > 0.0
    bad = subprocess.run([sys.executable, "-m", "lubelink", "run", "--scenario", "spatial-slider-crank", "--set",
                          "collar.mass=0.3", "-o", str(tmp_path / "x.nc")], capture_output=True, text=True,
                         timeout=300)
    assert bad.returncode == 2 and "collar.mass = 0.3" in bad.stderr

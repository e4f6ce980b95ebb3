"""The spatial model wired into the library (``beam.model = "spatial"``, lubelink.link.spatial_model).

* its planar case against the planar model, the film included: the right-hand side differs only
  by the axial-bending terms ``2 omega q1_t + alpha q1`` (to round-off), a whole run by less than
  0.1 um on u2_mid while u3 stays exactly zero;
* the compiled kernels equal their Python source on random states;
* the spatial slider-crank scenario: complete on both backends, exponential and DOP853 agree, and
  the run equals a direct SciPy integration of ``spatial.accelerations`` under
  ``spatial.slider_crank_rssp`` (the wiring of frequencies, motion and frame);
* impacts and compliant contact on the u2 faces: the planar case against the planar model;
* the axial stretch under the slider-crank's inertial load, once the free axial vibration has
  decayed: the quasi-static closed forms of both end conditions (``beam.axial_end``);
* bad keys and unsupported combinations are refused with the key, value and valid range;
* the command line writes u1, u3, u3_mid with units.
"""

import subprocess
import sys

import numpy as np
import pytest

import lubelink
from conftest import central_differences
from lubelink.link import spatial
from lubelink.config import resolve
from lubelink.link.model import rhs, rhs_given
from lubelink.build import build_model
from lubelink.results import to_dataset
from lubelink.simulate import run as simulate_run
from lubelink.spatial_assembly import SpatialModel
from lubelink.link.spatial_model import spatial_gap, spatial_rhs
from lubelink.link.spatial_motion import geometry, spatial_motion_at

EPS = np.finfo(float).eps
TIGHT = {"solver.rtol": 1e-10, "solver.atol": 1e-14}


def _random_state(rng, N, omega, amplitude=1.5e-3):
    amp = amplitude / np.arange(1, N + 1) ** 2
    q = rng.uniform(-1, 1, (3, N)) * amp * np.array([[1e-3], [1.0], [1.0]])
    return np.concatenate([q.ravel(), (rng.uniform(-1, 1, (3, N)) * amp * omega).ravel()])


def _axial_to_sine(N, L, end):
    """The sine coordinates of the projection of an axial field given in the axial modes of ``end``: the identity
    (fixed: the same sines) or ``(2/L) int sin(beta_n x) psi_m dx`` (free, ``psi_m = sin((2m - 1) pi x / (2 L))``), by
    Gauss quadrature."""
    if end == "fixed":
        return np.eye(N)
    s, w = np.polynomial.legendre.leggauss(200)
    x, w = 0.5 * L * (s + 1.0), 0.5 * L * w
    n = np.arange(1, N + 1)
    return 2.0 / L * (np.sin(np.outer(n * np.pi / L, x)) * w) @ np.sin(np.outer((2 * n - 1) * np.pi / (2 * L), x)).T


@pytest.mark.parametrize("film, end", [("none", "free"), ("wedge+squeeze", "free"), ("wedge+squeeze", "fixed")])
def test_planar_case_right_hand_side_is_the_planar_one_plus_the_axial_terms(film, end):
    """Planar motion: u2 rows = planar model's rhs - (2 omega u1_t + alpha u1) projected on the sines; u3 rows
    unforced."""
    N = 3
    over = {"beam.modes": N, "film.model": film, "film.clearance": 5e-3}
    planar = build_model(resolve("paper", over))
    sp = build_model(resolve("paper", {**over, "beam.model": "spatial", "beam.axial_end": end}))
    assert isinstance(sp, SpatialModel) and sp.state_frequencies.size == 3 * N
    C = _axial_to_sine(N, 1.0, end)
    rng = np.random.default_rng(3)
    for _ in range(10):
        t = rng.uniform(0.0, 0.2)
        y = _random_state(rng, N, planar.omega_n[0])
        y[2 * N:3 * N] = y[5 * N:] = 0.0  # u3 = 0
        d_sp = sp.rhs(t, y)
        d_pl = planar.rhs(t, sp.planar_state(y))
        _, omega, alpha, *_ = planar.kinematics(t)
        expected = d_pl[N:] - C @ (2.0 * omega * y[3 * N:4 * N] + alpha * y[:N])
        scale = np.max(np.abs(d_pl)) + planar.omega_n[-1] ** 2 * np.max(np.abs(y[N:2 * N]))
        np.testing.assert_allclose(d_sp[4 * N:5 * N], expected, rtol=0, atol=1e2 * EPS * scale)
        np.testing.assert_array_equal(d_sp[5 * N:], 0.0)
        np.testing.assert_array_equal(d_sp[:3 * N], y[3 * N:])
        assert sp.gap(t, y) == pytest.approx(planar.gap(t, sp.planar_state(y)), abs=1e-12)


@pytest.mark.parametrize("scenario", ["paper-dry", "paper"])
def test_planar_case_through_simulate_matches_the_planar_model(scenario):
    """u3 stays zero; u2_mid within 0.1 um of the planar model (the axial Coriolis/Euler terms: 46 nm dry, 61 nm with
    the film, the free axial end; 13-17 nm fixed)."""
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
                                  {"film.roughness": 1e-6, "mechanism.gravity": [0.0, -9.81]},
                                  {"film.faces": "u2+u3", "film.model": "wedge+squeeze", "film.sides": 2,
                                   "film.roughness": 1e-6, "film.clearance": 3.1e-3},
                                  {"beam.width_ratio": 0.6, "beam.height_ratio": 1.4},  # a taper: eigen-coordinates
                                  {"beam.width_ratio": 0.6, "beam.height_ratio": 1.4, "film.model": "wedge+squeeze",
                                   "film.sides": 2},
                                  {"beam.axial_end": "fixed"},
                                  {"beam.axial_end": "fixed", "beam.width_ratio": 0.6, "beam.height_ratio": 1.4}])
def test_compiled_spatial_kernels_equal_their_python_source(over):
    model = build_model(resolve("spatial-slider-crank", {"film.clearance": 5e-3, **over}))
    assert model.compiled and (model.params.spatial.galerkin is not None) == ("beam.width_ratio" in over)
    assert (model.params.spatial.axial is None) == (over.get("beam.axial_end") == "fixed")
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
    """``spatial.accelerations`` under ``spatial.slider_crank_rssp`` of the scenario's geometry, dry, by SciPy
    (``t_eval`` None: the solution object with its dense output)."""
    from scipy.integrate import solve_ivp

    b, m = config.beam, config.mechanism
    N, L = b.modes, m.rod_length
    W = spatial.frequencies(N, L, b.youngs_modulus, b.density, b.area, b.second_moment, b.height * b.width**3 / 12,
                            b.axial_end)
    axial = None if b.axial_end == "fixed" else spatial.free_axial_basis(N, L, b.density * b.area)
    g = geometry(m)
    F = np.zeros(3 * N)
    mass = b.density * b.area * L / 2

    def f(t, y):
        A_O, w, al, *_ = spatial.slider_crank_rssp(t, m.crank_length, L, m.crank_speed, m.guide_distance,
                                                   g.crank_axis, g.crank_ref, g.slider_point, g.slider_dir)
        out = np.empty(6 * N)
        spatial.accelerations(y, W, b.damping_ratio, A_O, w, al, F, mass, L, out, axial)
        return out

    if t_eval is None:  # the solution with its dense output, to solver.t_end
        return solve_ivp(f, (0.0, config.solver.t_end), np.zeros(6 * N), method="DOP853", dense_output=True,
                         rtol=1e-11, atol=1e-15)
    return solve_ivp(f, (0.0, t_eval[-1]), np.zeros(6 * N), method="DOP853", t_eval=t_eval, rtol=1e-11,
                     atol=1e-15).y.T


def test_spatial_scenario_runs_on_both_backends_and_methods():
    """Complete; numba/numpy equal; exponential and DOP853 within 1e-7 of the peak of each direction;
    the dry run equals a direct SciPy integration of the equations within 1e-5 of the peaks."""
    # u1 (0.6 um) lies far below the default atol; the SciPy reference's equations have no axial force
    over = {"solver.t_end": 0.1, "beam.axial_force": "none", **TIGHT}
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
        u_ref = spatial.deflections(ref, [0.5], 1.0, cfg.beam.axial_end)[k][:, 0]
        u = dry[name].sel(x=0.5, method="nearest").values[1:]
        np.testing.assert_allclose(u, u_ref, rtol=0, atol=1e-5 * np.max(np.abs(u_ref)))
    assert ref.shape[1] == 6 * N


@pytest.mark.parametrize("end", ["fixed", "free"])
def test_axial_stretch_follows_the_quasi_static_closed_form(end):
    """The slider-crank's axial inertial load ``rho A (A1 + g1 x)`` (``g1 = -(w2^2 + w3^2)``) stretches the link
    quasi-statically, its first axial mode (8-16 krad/s) 260-520 times faster than the crank:
    ``E u1'' = rho (A1 + g1 x)``, ``u1(0) = 0`` and ``u1(L) = 0`` (fixed) or ``u1'(L) = 0`` (free), so
    ``u1 = rho / E [A1 (x^2 - L x) / 2 + g1 (x^3 - L^2 x) / 6]`` or
    ``u1 = rho / E [A1 (x^2 / 2 - L x) + g1 (x^3 / 6 - L^2 x / 2)]``.
    Damping (10 %) removes the free axial vibration that the start from rest excites; after 0.05 s ``u1`` along the
    link is that closed form to 2 % of its peak (measured 1.3 % fixed, 0.6 % free: the tail of the 3-mode series
    and the axial terms of the deflection ``alpha u2 + 2 omega u2_t``, 0.2 % of the load), which is 0.33 um (fixed)
    and 1.00 um (free) on the paper's rod."""
    cfg = resolve("paper-dry", {"beam.model": "spatial", "beam.axial_end": end, "beam.modes": 3,
                                "beam.damping_ratio": 0.1, "solver.t_end": 0.25, **TIGHT})
    ds = lubelink.simulate(cfg)
    model = build_model(cfg)
    b, L = cfg.beam, cfg.mechanism.rod_length
    x = ds.x.values
    late = ds.time.values >= 0.05
    exact = []
    for t in ds.time.values[late]:
        k = model.motion.at(t)
        A1, g1 = k.A_O[0], -(k.omega[1] ** 2 + k.omega[2] ** 2)
        if end == "fixed":
            u = A1 * (x**2 - L * x) / 2 + g1 * (x**3 - L**2 * x) / 6
        else:
            u = A1 * (x**2 / 2 - L * x) + g1 * (x**3 / 6 - L**2 * x / 2)
        exact.append(b.density / b.youngs_modulus * u)
    exact = np.array(exact)
    peak = np.max(np.abs(exact[:, np.argmin(np.abs(x - 0.5 * L))]))
    assert peak == pytest.approx(0.33e-6 if end == "fixed" else 1.00e-6, rel=0.01)
    np.testing.assert_allclose(ds.u1.values[late], exact, rtol=0, atol=2e-2 * np.max(np.abs(exact)))


def test_spatial_motion_of_the_planar_geometry_is_the_planar_slider_crank():
    from lubelink.link.kinematics import slider_crank

    cfg = resolve("paper", {"beam.model": "spatial"})
    m = geometry(cfg.mechanism)
    for t in np.linspace(0.0, 0.2, 7):
        A_O, w, al, x_star, V_r = spatial_motion_at(t, m)[:5]
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
    ({"beam.model": "spatial", "film.faces": "u3"}, ["film.faces = 'u3'", '"u2", "u2+u3"']),
    ({"film.faces": "u2+u3"}, ["film.faces = 'u2+u3'", "beam.model = 'spatial'"]),
    ({"beam.model": "spatial", "beam.axial_end": "pinned"}, ["beam.axial_end = 'pinned'", '"fixed", "free"']),
    ({"beam.axial_end": "fixed"}, ["beam.axial_end = 'fixed'", "beam.model = 'spatial'"]),
])
def test_bad_spatial_configurations_are_refused(over, words):
    with pytest.raises(lubelink.ConfigError) as e:
        resolve("paper", over)
    for w in words:
        assert w in str(e.value), (w, str(e.value))


def test_compliant_impacts_on_the_u2_faces_match_the_planar_model():
    """paper-impact's first compliant contact (1 mode, to 1.2744 s): the planar case of the spatial model makes
    contact at the planar model's time (6.7e-6 s later: the axial coupling, 0.87 um on u2 by then, with the free
    axial end; 2e-6 s and 0.25 um with the fixed one) with its velocity and force."""
    over = {"solver.t_end": 1.2744, "contact.law": "compliant"}
    pl = lubelink.simulate("paper-impact", set=over)
    sp = lubelink.simulate("paper-impact", set={**over, "beam.model": "spatial"})
    assert sp.attrs["status"] == pl.attrs["status"] == "complete"
    assert sp.sizes["impact"] == pl.sizes["impact"] >= 1
    np.testing.assert_allclose(sp.impact_time.values, pl.impact_time.values, rtol=0, atol=1e-5)
    np.testing.assert_allclose(sp.impact_velocity.values, pl.impact_velocity.values, rtol=2e-3)
    assert np.max(np.abs(sp.u3.values)) == 0.0
    np.testing.assert_allclose(np.max(sp.contact_force.values), np.max(pl.contact_force.values), rtol=1e-3)


def test_the_zeno_sequence_and_sustained_contact_match_the_planar_model():
    """paper-impact to its end (2 s, restitution, 1 mode): the planar case of the spatial model has the planar
    model's 21 impacts (the Zeno sequence at 1.2732-1.2745 s, then three single ones; times within 6.7e-6 s, the
    axial coupling's shift), the same sustained contact (1.27447-1.29971 s; start within 5.5e-6 s, end within
    2e-7 s measured), the same contact phase at every sample, its force within 2e-5 of its 771 N peak, and u2_mid
    within 0.87 um of a 4.79 mm peak (the axial-bending terms alpha u1 + 2 omega u1_t; u1 is 2.8 um with the free
    axial end; 0.43 um, 0.68 um and 2e-6 s with the fixed one); u3 stays 0."""
    runs = [simulate_run(resolve("paper-impact", over)) for over in ({}, {"beam.model": "spatial"})]
    pl, sp = (to_dataset(r) for r in runs)
    assert sp.attrs["status"] == pl.attrs["status"] == "complete"
    assert sp.sizes["impact"] == pl.sizes["impact"] == 21
    np.testing.assert_array_equal(sp.impact_side.values, pl.impact_side.values)
    np.testing.assert_allclose(sp.impact_time.values, pl.impact_time.values, rtol=0, atol=1e-5)  # 6.7e-6
    v = pl.impact_velocity.values
    np.testing.assert_allclose(sp.impact_velocity.values, v, rtol=0, atol=1e-3 * np.max(np.abs(v)))  # 1.8e-4
    (c_pl,), (c_sp,) = runs[0].contacts, runs[1].contacts
    assert c_pl[2] == c_sp[2] == 1 and 1.274 < c_pl[0] < 1.275 and 1.29 < c_pl[1] < 1.31
    np.testing.assert_allclose(c_sp[:2], c_pl[:2], rtol=0, atol=1e-5)
    np.testing.assert_array_equal(sp.contact_phase.values, pl.contact_phase.values)
    inside = pl.contact_phase.values == 1
    assert inside.sum() >= 20
    peak = np.max(pl.contact_force.values)
    assert peak > 100.0
    np.testing.assert_allclose(sp.contact_force.values, pl.contact_force.values, rtol=0, atol=1e-4 * peak)
    diff = np.max(np.abs(sp.u2_mid.values - pl.u2_mid.values))
    assert 1e-8 < diff < 1e-6, diff
    assert np.max(np.abs(sp.u3.values)) == 0.0


# --- the film pair on the u3 faces (film.faces = "u2+u3") ---------------------------------------------------------
def _mirrored_state(rng, N, omega):
    """A random state whose u3 block equals its u2 block (``q3 = q2``, ``q3_t = q2_t``)."""
    y = _random_state(rng, N, omega)
    y[2 * N:3 * N], y[5 * N:] = y[N:2 * N], y[4 * N:5 * N]
    return y


@pytest.mark.parametrize("over", [{}, {"film.model": "wedge+squeeze", "film.sides": 2,
                                       "film.cavitation": "half-sommerfeld", "beam.height": 0.012}])
def test_the_u3_pair_is_the_u2_film_on_the_q3_block(over):
    """With q3 = q2 and q3_t = q2_t, the u3 pair adds to the u3 rows what the u2 film adds to the u2 rows, scaled by
    the pad widths h / B (the film force is proportional to the pad width); it changes no other row."""
    N = 3
    base = {"beam.model": "spatial", "beam.modes": N, "film.clearance": 5e-3, **over}
    on = build_model(resolve("paper", {**base, "film.faces": "u2+u3"}))
    off = build_model(resolve("paper", base))
    dry = build_model(resolve("paper", {**base, "film.model": "none"}))
    ratio = on.config.beam.height / on.config.beam.width
    rng = np.random.default_rng(5)
    for _ in range(10):
        t = rng.uniform(0.0, 0.2)
        y = _mirrored_state(rng, N, on.omega_n[0])
        d_on, d_off, d_dry = on.rhs(t, y), off.rhs(t, y), dry.rhs(t, y)
        f2 = d_off[4 * N:5 * N] - d_dry[4 * N:5 * N]
        f3 = d_on[5 * N:] - d_off[5 * N:]
        scale = np.max(np.abs(d_on)) + np.max(on.state_frequencies) ** 2 * np.max(np.abs(y[:3 * N]))
        assert np.max(np.abs(f2)) > 1e4 * EPS * scale  # the film is felt
        np.testing.assert_allclose(f3, ratio * f2, rtol=0, atol=1e2 * EPS * scale)
        np.testing.assert_array_equal(d_on[:5 * N], d_off[:5 * N])


def _thinnest_by_sampling(model, t, y, k, points=20001):
    """Thinnest film [m] of the pair on block ``k`` by brute force: ``H/2 -+ u`` on a fine grid of the pad."""
    f, N, L = model.config.film, model.modes, model.config.mechanism.rod_length
    x0 = model.motion.at(t).x_star - (0.5 * f.pad_length if f.pad_reference == "centre" else 0.0)
    X = x0 + np.linspace(0.0, f.pad_length, points)
    u = np.sin(np.outer(X, np.arange(1, N + 1) * np.pi / L)) @ y[k * N:(k + 1) * N]
    return 0.5 * f.clearance - (np.max(np.abs(u)) if f.sides == 2 else np.max(u))


def test_the_gap_is_the_thinner_of_the_two_pairs():
    """The event and the thinnest film: the smaller of the two pairs' films (sampled on a fine grid of the pad), and
    the side code names the pair (+-2: the u3 faces)."""
    model = build_model(resolve("spatial-slider-crank", {"film.faces": "u2+u3", "film.sides": 2,
                                                         "film.clearance": 5e-3}))
    rng = np.random.default_rng(8)
    seen = set()
    for _ in range(40):
        t = rng.uniform(0.0, 0.5)
        y = _random_state(rng, model.modes, model.omega_n[0])
        films = {k: _thinnest_by_sampling(model, t, y, k) for k in (1, 2)}
        k = min(films, key=films.get)
        assert model.gap(t, y) == pytest.approx(films[k] - model.config.contact.min_film, abs=1e-10)
        xi, _, _, code = model.thinnest_film(t, y)
        assert xi == pytest.approx(films[k], abs=1e-10) and abs(code) == k
        seen.add(k)
    assert seen == {1, 2}


@pytest.mark.parametrize("sides", [1, 2])
def test_with_the_u3_pair_an_unforced_u3_stays_zero(sides):
    """Planar motion, u3 = 0 at the start: the u3 films are uniform, H/2 over the pad, so their wedge pressure
    vanishes. A two-sided collar's two films cancel exactly: u3 stays exactly 0 and u2 is bitwise that of the
    default film.faces = 'u2'. One-sided, the uniform film's pressure is zero to rounding only (the Reynolds
    constant I1/I2 equals the film to an ulp): u3 stays below 1e-16 of the u2 peak (5e-20 m measured)."""
    over = {"beam.model": "spatial", "beam.modes": 3, "solver.t_end": 0.3, "film.sides": sides}
    a = lubelink.simulate("paper", set=over)
    b = lubelink.simulate("paper", set={**over, "film.faces": "u2+u3"})
    assert a.attrs["status"] == b.attrs["status"] == "complete"
    peak = np.max(np.abs(a.u2.values))
    if sides == 2:
        assert np.max(np.abs(b.u3.values)) == 0.0 and np.max(np.abs(b.film_force_u3.values)) == 0.0
        np.testing.assert_array_equal(b.u2.values, a.u2.values)
    else:
        assert np.max(np.abs(b.u3.values)) < 1e-16 * peak
        assert np.max(np.abs(b.film_force_u3.values)) < 1e-12 * np.max(np.abs(b.film_force.values))
        np.testing.assert_allclose(b.u2.values, a.u2.values, rtol=0, atol=1e-12 * peak)
    np.testing.assert_allclose(b.film_min_u3.values, 0.5 * 6e-3, rtol=1e-12)  # H/2: the u3 films stay uniform
    assert b.film_force_u3.attrs["units"] == "N" and b.film_min_u3.attrs["units"] == "m"
    assert "film_force_u3" not in a


def test_a_one_sided_u3_pair_drives_u3_as_the_planar_film_drives_u2():
    """A translation of the link (no rotation: the crank-driven terms removed) that drives e2 and e3 alike,
    A_O = -(0, a, a) (1 - cos(Omega t)), with the collar sliding: on a square section with one-sided films on both
    pairs, u3(t) equals u2(t) bit for bit, and u2 equals the planar model's (model.rhs_given with omega = alpha = 0)
    integrated on its own (within 1e-9 of the peak; 2e-12 between the planar runs at rtol 1e-10 and 1e-12); the film
    (0.93 mm at its thinnest) changes the deflection by 3.6 % of the dry link's."""
    from scipy.integrate import solve_ivp

    from lubelink.link.kinematics import RigidMotion
    from lubelink.link.spatial import SpatialRigidMotion
    from lubelink.link.spatial_model import spatial_rhs_given

    N = 2
    common = {"beam.modes": N, "film.clearance": 3e-3, "film.viscosity": 0.3}
    sp = build_model(resolve("paper", {**common, "beam.model": "spatial", "film.faces": "u2+u3"}))
    pl = build_model(resolve("paper", common))
    dry = build_model(resolve("paper", {**common, "film.model": "none"}))
    a, Om, x0, d = 5.0, 31.4, 0.35, 0.03
    zero, e = (0.0, 0.0, 0.0), ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))

    def f_sp(t, y):
        A = -a * (1.0 - np.cos(Om * t))
        kin = SpatialRigidMotion((0.0, A, A), zero, zero, x0 + d * np.sin(Om * t), d * Om * np.cos(Om * t), *e,
                                 zero, zero)
        out = np.empty(6 * N)
        spatial_rhs_given(kin, y, out, sp.params)
        return out

    def planar(model):
        def f(t, y):
            out = np.empty(2 * N)
            rhs_given(t, RigidMotion(-a * (1.0 - np.cos(Om * t)), 0.0, 0.0, x0 + d * np.sin(Om * t),
                                     d * Om * np.cos(Om * t)), y, out, model.params)
            return out
        return f

    t = np.linspace(0.0, 0.2, 201)
    opts = {"method": "DOP853", "t_eval": t, "rtol": 1e-11, "atol": 1e-15}
    ys = solve_ivp(f_sp, (0.0, t[-1]), np.zeros(6 * N), **opts).y
    yp = solve_ivp(planar(pl), (0.0, t[-1]), np.zeros(2 * N), **opts).y
    yd = solve_ivp(planar(dry), (0.0, t[-1]), np.zeros(2 * N), **opts).y
    np.testing.assert_array_equal(ys[2 * N:3 * N], ys[N:2 * N])
    np.testing.assert_array_equal(ys[:N], 0.0)
    peak = np.max(np.abs(yp[:N]))
    assert np.max(np.abs(yp[:N] - yd[:N])) > 0.02 * peak
    np.testing.assert_allclose(ys[N:2 * N], yp[:N], rtol=0, atol=1e-9 * peak)


def test_a_u3_breakdown_is_found_at_the_root_of_the_u3_film():
    """spatial-slider-crank, dry, a two-sided collar on both pairs with 0.1 mm clearance: the u3 films break down
    first (4.77 ms, before the u2 films). The first impact is on the u3 faces at the root of H/2 - max|u3| - min_film
    over the pad, found on the dense output of an independent SciPy integration of the equations (the pad sampled)."""
    from scipy.optimize import brentq

    over = {"film.model": "none", "film.sides": 2, "film.faces": "u2+u3", "film.clearance": 1e-4,
            "contact.law": "restitution", "solver.t_end": 0.006, "beam.axial_force": "none",  # (as the SciPy's)
            **TIGHT}
    ds = lubelink.simulate("spatial-slider-crank", set=over)
    cfg = resolve("spatial-slider-crank", over)
    assert ds.attrs["status"] == "complete" and ds.sizes["impact"] >= 1
    assert int(ds.impact_face[0]) == 3 and int(ds.impact_side[0]) == -1
    assert ds.impact_face.attrs["flag_meanings"] == "u2_faces u3_faces"
    model = build_model(cfg)
    sol = _scipy_reference(cfg, None)
    gap = {k: (lambda t, k=k: _thinnest_by_sampling(model, t, sol.sol(t), k, 4001) - cfg.contact.min_film)
           for k in (1, 2)}
    grid = np.linspace(1e-4, 0.006, 600)
    g3 = np.array([gap[2](t) for t in grid])
    i = int(np.argmax(g3 <= 0.0))
    assert i > 0
    t_root = brentq(gap[2], grid[i - 1], grid[i], xtol=1e-13)
    assert min(gap[1](t) for t in grid[:i + 1]) > 0.0  # the u2 films are still open
    assert float(ds.impact_time[0]) == pytest.approx(t_root, abs=1e-8)
    before = ds.time.values < t_root
    assert np.all(ds.film_min_u3.values[before] > cfg.contact.min_film)
    assert ds.film_min_u3.values[before][-1] < ds.film_min.values[before][-1]  # the results say the same


def test_impacts_and_sustained_contact_on_both_pairs_are_the_same_on_both_backends():
    """spatial-slider-crank, dry, two-sided collar on both pairs, 0.1 mm clearance, to 15 ms: impacts on both pairs
    (u3, u2, u3, u2, u2, u3, then a Zeno sequence on the u2 faces and a sustained contact from about 11.9 ms, ended
    by a second point of the pad reaching a face at 12.14 ms: status penetration); the
    numpy backend gives the compiled run's impacts, faces and states up to the Zeno sequence (equal to the last bit
    measured but for one dense-output sample, 2e-19 m/s apart). Within the sequence the two part: the backends' math
    libraries differ in the last bit here and there (measured: the 13th impact 9e-16 s apart), and a Zeno sequence
    amplifies any difference."""
    over = {"film.model": "none", "film.sides": 2, "film.faces": "u2+u3", "film.clearance": 1e-4,
            "contact.law": "restitution", "solver.t_end": 0.015}
    runs = {b: simulate_run(resolve("spatial-slider-crank", {**over, "solver.backend": b})) for b in ("numba", "numpy")}
    a, b = (to_dataset(runs[k]) for k in ("numba", "numpy"))
    assert a.attrs["backend"] == "numba" and b.attrs["backend"] == "numpy"
    # the sustained contact holds one point of the u2 faces while the pad reaches a face elsewhere: the event
    # watches the films of both pairs over the whole pad and ends the run where the thinnest reaches 0.9
    # min_film (12.14 ms; it used to go on to 15 ms, the u2 film 3.2 um and the u3 film -7.5 um there)
    assert a.attrs["status"] == b.attrs["status"] == "penetration"
    assert "reached the collar face at a second point" in a.attrs["message"]
    end = runs["numba"].contacts[0][1]
    assert 0.0119 < end < 0.0125 and runs["numpy"].contacts[0][1] == pytest.approx(end, abs=1e-9)
    assert a.film_min.values[-1] >= 0.9 * 5e-6 * (1 - 1e-9) and float(a.time[-1]) <= end
    assert set(a.impact_face.values[:6]) == {2, 3} and a.sizes["impact"] > 10
    assert len(runs["numba"].contacts) == 1 and runs["numba"].contacts[0][2] == 1
    assert np.any(a.contact_phase.values == 1) and np.all(a.contact_force.values[a.contact_phase.values == 1] > 0.0)
    before = 0.0116  # [s] the Zeno sequence begins
    first = int(np.count_nonzero(a.impact_time.values < before))
    assert first >= 10 and first == int(np.count_nonzero(b.impact_time.values < before))
    np.testing.assert_array_equal(b.impact_face.values[:first], a.impact_face.values[:first])
    np.testing.assert_allclose(b.impact_time.values[:first], a.impact_time.values[:first], rtol=0, atol=1e-12)
    a, b = a.sel(time=slice(0.0, before)), b.sel(time=slice(0.0, before))
    for name in ("u1", "u2", "u3", "contact_force"):
        np.testing.assert_allclose(b[name].values, a[name].values, rtol=0, atol=1e-9 * np.max(np.abs(a[name].values)))


def test_the_spatial_collar_acceleration_is_the_derivative_of_its_velocity():
    """collar_acceleration_at: central differences of V_r (Richardson-extrapolated) on the RSSP, and the planar
    closed form when the mechanism is planar."""
    from lubelink.link.kinematics import slider_crank_state
    from lubelink.link.spatial_motion import collar_acceleration_at

    m = geometry(resolve("spatial-slider-crank").mechanism)
    V = lambda t: spatial_motion_at(t, m).V_r  # noqa: E731
    for t in np.linspace(0.0, 0.2, 9):
        d = lambda h: (V(t + h) - V(t - h)) / (2 * h)  # noqa: E731
        fd = (4 * d(1e-4) - d(2e-4)) / 3
        assert collar_acceleration_at(t, m) == pytest.approx(fd, rel=1e-8, abs=1e-8)
    planar = geometry(resolve("paper", {"beam.model": "spatial"}).mechanism)
    for t in np.linspace(0.0, 0.2, 5):
        assert collar_acceleration_at(t, planar) == pytest.approx(slider_crank_state(t, 0.07, 1.0, 10 * np.pi, 0.4)[7],
                                                                   rel=1e-12, abs=1e-10)


@pytest.mark.parametrize("code", [1.0, -1.0, 2.0, -2.0])
def test_a_sustained_contact_acts_on_its_faces_block_by_baumgartes_law(code):
    """A sustained contact of side code +-1 (u2 faces) or +-2 (u3 faces) at a material point: only its block's
    accelerations change, and there the gap at the point obeys g_tt + 2 a g_t + a^2 g = 0 (a: the block's highest
    frequency); compiled and Python agree."""
    from lubelink.link.spatial_model import face_of, spatial_gap

    model = build_model(resolve("spatial-slider-crank", {"film.faces": "u2+u3", "film.sides": 2,
                                                         "film.clearance": 5e-3, "contact.law": "restitution"}))
    N, L, H, xi_min = model.modes, 1.0, 5e-3, model.config.contact.min_film
    k, side = face_of(code)
    rng = np.random.default_rng(int(10 + code))
    for _ in range(5):
        t = rng.uniform(0.0, 0.5)
        y = _random_state(rng, N, model.omega_n[0])
        x_c = model.motion.at(t).x_star + rng.uniform(0.0, 0.05)
        free, held = model.rhs(t, y), model.rhs(t, y, (code, 0.0, x_c))
        other = [j for j in range(3) if j != k]
        for j in other:
            np.testing.assert_array_equal(held[(3 + j) * N:(4 + j) * N], free[(3 + j) * N:(4 + j) * N])
        s = np.sin(np.arange(1, N + 1) * np.pi / L * x_c)
        g = H / 2 - side * (s @ y[k * N:(k + 1) * N]) - xi_min
        g_t = -side * (s @ y[(3 + k) * N:(4 + k) * N])
        g_tt = -side * (s @ held[(3 + k) * N:(4 + k) * N])
        a = model.state_frequencies[(k + 1) * N - 1]
        scale = np.max(np.abs(free)) * np.sum(np.abs(s)) + a * a * abs(g)
        assert abs(g_tt + 2 * a * g_t + a * a * g) < 1e-12 * scale
        p = model.with_phase((code, 0.0, x_c))
        out = np.empty(6 * N)
        spatial_rhs.py_func(t, y, out, p)
        np.testing.assert_allclose(out, held, rtol=0, atol=1e3 * EPS * np.max(np.abs(held)))
        force = spatial_gap(t, y, p)[0]
        assert force == pytest.approx(spatial_gap.py_func(t, y, p)[0], rel=1e-9)
        assert force == pytest.approx(model.sustained_force(t, y, code, x_c)[0], rel=1e-12)


@pytest.mark.parametrize("code", [1.0, -2.0])
def test_a_compliant_contact_acts_on_its_faces_block(code):
    """The compliant force of a contact on the u2 (+-1) or u3 (+-2) faces loads only its block, as the planar force
    of that block's state (Model.contact_force on it); compiled and Python agree."""
    from lubelink.link.spatial_model import face_of

    # without the axial force: the chord's rotation couples the blocks' accelerations through its mass
    model = build_model(resolve("spatial-slider-crank", {"film.faces": "u2+u3", "film.sides": 2, "film.model": "none",
                                                         "film.clearance": 2e-4, "contact.law": "compliant",
                                                         "beam.axial_force": "none"}))
    N = model.modes
    k, side = face_of(code)
    rng = np.random.default_rng(4)
    t = 0.1
    y = _random_state(rng, N, model.omega_n[0], amplitude=1e-6)
    x_c = model.motion.at(t).x_star + 0.025
    y[k * N] += side * 1e-4 / np.sin(np.pi * x_c)  # the film at the pad centre closes, 5 um below min_film
    free, pushed = model.rhs(t, y), model.rhs(t, y, (code, 0.2))
    F, magnitude = model.contact_force(t, y, (code, 0.2))
    assert magnitude > 0.0
    for j in range(3):
        expected = F / model.modal_mass if j == k else 0.0
        np.testing.assert_allclose(pushed[(3 + j) * N:(4 + j) * N] - free[(3 + j) * N:(4 + j) * N], expected,
                                   rtol=1e-9, atol=1e3 * EPS * np.max(np.abs(free)))
    out = np.empty(6 * N)
    spatial_rhs.py_func(t, y, out, model.with_phase((code, 0.2)))
    np.testing.assert_allclose(out, pushed, rtol=0, atol=1e3 * EPS * np.max(np.abs(pushed)))


def test_a_planar_motion_is_refused_by_the_spatial_model():
    from lubelink.link.kinematics import SliderCrank

    cfg = resolve("spatial-slider-crank")
    with pytest.raises(lubelink.ConfigError, match="beam.model = 'spatial'"):
        build_model(cfg, SliderCrank(cfg.mechanism))


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


def test_the_domain_of_the_linear_theory_is_checked_out_of_plane():
    """Issue 37 item 1: a thin link (1 x 20 mm) driven out of plane (crank tilt 1.2 rad) ended ``complete`` with
    max |u3| = 0.235 m, the domain check reading the in-plane block only. It stops now where the stretching
    strain of both directions reaches solver.max_axial_strain; the strain from the sampled u3 itself (finite
    differences over x, trapezoidal rule) agrees, and the CLI's summary shows the out-of-plane peak."""
    over = {"beam.width": 0.001, "beam.height": 0.02, "mechanism.crank_tilt": 1.2, "film.model": "none",
            "mechanism.crank_speed": 14.8, "solver.t_end": 5.0, "output.x_points": 401}
    ds = lubelink.simulate("spatial-slider-crank", set=over)
    assert ds.attrs["status"] == "out_of_domain", ds.attrs["message"]
    assert "stretching strain" in ds.attrs["message"] and float(ds.time[-1]) < 5.0
    x, L = ds.x.values, 1.0
    limit = resolve("spatial-slider-crank", over).solver.max_axial_strain

    def strain(k):  # 1/(2L) int (u2'^2 + u3'^2) dx of sample k, from the sampled deflections
        return sum(np.trapezoid(np.gradient(ds[u].values[k], x) ** 2, x) for u in ("u2", "u3")) / (2 * L)

    assert strain(-1) == pytest.approx(limit, rel=0.03) and strain(-2) < limit
    assert np.max(np.abs(ds.u3_mid.values)) > 100 * np.max(np.abs(ds.u2_mid.values))  # the out-of-plane direction
    r = subprocess.run([sys.executable, "-m", "lubelink", "run", "--scenario", "spatial-slider-crank", "--no-output",
                        *[a for k, v in over.items() for a in ("--set", f"{k}={v!r}" if isinstance(v, str) else f"{k}={v}")]],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 1 and "peak |u3_mid|" in r.stdout and "out_of_domain" in r.stdout



@pytest.mark.parametrize("sets, phase", [
    ({"film.model": "wedge+squeeze", "film.clearance": 1e-4, "film.faces": "u2+u3", "film.sides": 2,
      "mechanism.crank_tilt": 0.3, "beam.damping_ratio": 0.02}, None),
    ({"film.model": "wedge+squeeze", "film.clearance": 6e-6, "film.roughness": 1e-6, "film.thickness_floor": 0.0,
      "contact.min_film": 5e-7,
      "film.faces": "u2+u3", "beam.modes": 2}, None),
    ({"film.model": "none", "film.clearance": 1e-4, "film.faces": "u2+u3", "contact.law": "compliant"}, (2.0, 0.05)),
    ({"film.model": "wedge+squeeze", "film.clearance": 1e-4, "film.faces": "u2+u3", "film.sides": 2,
      "mechanism.crank_tilt": 0.3, "beam.damping_ratio": 0.02, "beam.axial_end": "fixed"}, None),
], ids=["squeeze-both-pairs", "asperity", "compliant-u3", "fixed-axial-end"])
def test_spatial_jacobian_against_finite_differences(sets, phase):
    """The spatial right-hand side's Jacobian (an ``out`` of ``n + n^2``) against its own central differences:
    films and asperities on both pairs of faces, the frame's accelerations of a tilted crank (between the free
    axial end's modes and the bending sines: full blocks; the fixed end's: diagonal), and a compliant contact on
    the u3 faces pressed 1 um in; the frame terms matter (the Coriolis and centrifugal entries are checked to be
    there)."""
    cfg = resolve("spatial-slider-crank", sets)
    model = build_model(cfg)
    assert model.jacobian_missing(phase) == ""
    p = model.with_phase(phase)
    N = cfg.beam.modes
    n = 6 * N
    rng = np.random.default_rng(3)
    y = np.concatenate([rng.standard_normal(3 * N) * 2e-7, rng.standard_normal(3 * N) * 1e-4])
    t = 0.137
    if phase is not None:  # the u3 faces' film H/2 - u3 1 um below min_film at the thinnest point
        x_star = model.kinematics(t).x_star
        x = np.linspace(x_star, x_star + cfg.film.pad_length, 201)
        u3 = np.sin(np.outer(x, np.arange(1, N + 1)) * np.pi / cfg.mechanism.rod_length) @ y[2 * N:3 * N]
        y[2 * N:3 * N] *= (0.5 * cfg.film.clearance - cfg.contact.min_film + 1e-6) / u3[np.argmax(np.abs(u3))]
        assert model.thinnest_film(t, y)[3] == 2
    out = np.empty(n + n * n)
    spatial_rhs(t, y, out, p)
    f = np.empty(n)
    spatial_rhs(t, y, f, p)
    np.testing.assert_array_equal(out[:n], f)

    def g(x):
        d = np.empty(n)
        spatial_rhs(t, x, d, p)
        return d

    J = out[n:].reshape(n, n)
    J_fd = central_differences(g, y, np.r_[np.full(3 * N, 1e-10), np.full(3 * N, 1e-7)])
    np.testing.assert_allclose(J, J_fd, rtol=0, atol=1e-6 * np.abs(J_fd).max())
    M = 3 * N
    assert np.abs(J[M:M + N, M + N:M + 2 * N]).max() > 0.0  # Coriolis: axial <- in-plane velocity
    assert np.abs(J[M + 2 * N:, N:2 * N]).max() > 0.0  # the frame's centrifugal/Euler: out-of-plane <- in-plane
    off = J[M:M + N, M + N:M + 2 * N] - np.diag(np.diag(J[M:M + N, M + N:M + 2 * N]))
    assert (np.abs(off).max() > 0.0) == (cfg.beam.axial_end == "free")  # the bases differ: a full block


def test_a_stiff_squeeze_film_on_the_spatial_link_runs_rodas_with_its_jacobian():
    """At 40 um the squeeze film damps at 2e7 1/s: "auto" takes rodas with the analytic Jacobian, and its result
    is SciPy's Radau's (a second method) to 1e-7 of the peak (measured 9e-9); with films on both pairs the stiffer pair decides
    (the u3 faces of a link twice as high as wide: pads twice as wide, twice the rate)."""
    from lubelink.choice import film_squeeze_rate, method_name

    base = {"film.model": "wedge+squeeze", "film.clearance": 4e-5, "film.viscosity": 0.05, "solver.t_end": 0.02,
            "contact.law": "none", "beam.modes": 2}
    cfg = resolve("spatial-slider-crank", base)
    assert method_name(cfg) == "rodas"
    both = resolve("spatial-slider-crank", {**base, "film.faces": "u2+u3", "beam.height": 2.0 * cfg.beam.width})
    assert film_squeeze_rate(both) == pytest.approx(2.0 * film_squeeze_rate(
        resolve("spatial-slider-crank", {**base, "beam.height": 2.0 * cfg.beam.width})))
    rodas = lubelink.simulate(cfg)
    assert rodas.attrs["solver_method"] == "rodas" and "Jacobian analytic" in rodas.attrs["solver_note"]
    radau = lubelink.simulate(cfg, set={"solver.method": "Radau"})
    for name in ("u2_mid", "u3_mid"):
        peak = float(np.abs(radau[name]).max())
        assert peak > 0.0
        np.testing.assert_allclose(rodas[name], radau[name], rtol=0, atol=1e-7 * peak)

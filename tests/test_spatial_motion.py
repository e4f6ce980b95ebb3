"""A spatial motion of the user's (lubelink.link.spatial_motion): callables and samples against independent results.

* the built-in RSSP slider-crank's own kinematics fed back as callables gives the built-in run
  (the same equations, evaluated from Python); fed as samples every ``h``, the run converges to
  the built-in one at the splines' order, 4 (measured: 3.9-4.0);
* a constant spin about ``e3`` with a constant acceleration of O and gravity through a tilted frame:
  the quasi-static axial stretch, the spin-softened in-plane bending and the out-of-plane bending
  against their closed forms (the sine modes are exact eigenfunctions of these constant-coefficient
  problems, so the modal coordinates equal the closed forms' sine coefficients);
* the sampled motion compiled against the ``numpy`` backend;
* bad inputs: clear errors naming the argument, its value and the valid range.
"""

import numpy as np
import pytest

import lubelink
from lubelink.build import build_model
from lubelink.config import resolve
from lubelink.errors import BackendError
from lubelink.simulate import run
from lubelink.link.spatial_motion import (CHANNELS, SampledSpatialMotion, SpatialPrescribedMotion, SpatialSliderCrank,
                                     sampled_spatial_motion, spatial_motion_at)

# a motion of the user's runs the spatial link without the axial force ("auto"): so does the built-in one it is
# compared with
SHORT = {"solver.t_end": 0.02, "beam.modes": 2, "output.x_points": 11, "beam.axial_force": "none"}


def rssp_callables(mechanism):
    """The built-in slider-crank's kinematics as the callables a user would write."""
    ssc = SpatialSliderCrank(mechanism)
    names = ("A_O", "omega", "alpha", "x_star", "V_r", "e1", "e2")
    return SpatialPrescribedMotion(**{name: (lambda t, name=name: getattr(ssc.at(t), name)) for name in names})


def rssp_samples(mechanism, h, t_end, derived=False):
    """The built-in slider-crank's kinematics sampled every ``h`` [s] over ``[-2h, t_end + 2h]``."""
    ssc = SpatialSliderCrank(mechanism)
    t = np.arange(-2 * h, t_end + 2.5 * h, h)
    rows = [ssc.at(ti) for ti in t]
    col = lambda name: np.array([getattr(r, name) for r in rows])  # noqa: E731
    extra = {} if derived else {"alpha": col("alpha"), "V_r": col("V_r")}
    return sampled_spatial_motion(t, A_O=col("A_O"), omega=col("omega"), x_star=col("x_star"), e1=col("e1"),
                                  e2=col("e2"), **extra)


def test_builtin_kinematics_as_callables_give_the_builtin_run():
    """Same numbers into the same equations: equal to the built-in run on the numpy backend to the last bit,
    and to the compiled built-in run within the integration tolerance."""
    cfg = resolve("spatial-slider-crank", SHORT)
    ref_numpy = lubelink.simulate(cfg, set={"solver.backend": "numpy"})
    ref = lubelink.simulate(cfg)
    user = lubelink.simulate(cfg, motion=rssp_callables(cfg.mechanism))
    assert user.attrs["backend"] == "numpy" and "sampled_spatial_motion" in user.attrs["backend_note"]
    assert user.attrs["status"] == "complete" and user.attrs["nfev"] == ref_numpy.attrs["nfev"]
    for name in ("u1", "u2", "u3", "u3_mid", "film_force", "x_star", "V_r"):
        scale = float(np.abs(ref[name]).max())
        assert scale > 0.0
        np.testing.assert_array_equal(user[name].values, ref_numpy[name].values)
        assert float(np.abs(user[name] - ref[name]).max()) < 1e-6 * scale  # solver.rtol = 1e-8


@pytest.mark.parametrize("derived", [False, True], ids=["all-channels", "alpha-V_r-from-splines"])
def test_sampled_builtin_kinematics_converge_at_fourth_order(derived):
    """Samples every 2, 1, 0.5 ms: the run's error against the built-in run falls 16-fold per halving.

    ``rtol = 1e-12`` keeps the integration error (8e-12 of the ``u2_mid`` peak against DOP853 at
    1e-13) well below the smallest interpolation error measured (2.4e-10 of the peaks at 0.5 ms,
    6e-8 at 2 ms). At ``rtol = 1e-10`` the integration error is 6e-10 to 9e-10 of the peak: the test
    then passed only while the sampled and built-in runs took nearly the same steps, and failed
    (rate 3.2) once the exponential method began keeping its step size. With ``alpha``,
    ``V_r`` taken from the spline derivatives (O(h^3) pointwise) the run still converges at order 4:
    their error oscillates from piece to piece and averages out in the response.
    """
    cfg = resolve("spatial-slider-crank", {"solver.t_end": 0.1, "solver.rtol": 1e-12, "solver.atol": 1e-16,
                                           "beam.axial_force": "none"})
    ref = lubelink.simulate(cfg)
    errors = []
    for h in (2e-3, 1e-3, 5e-4):
        ds = lubelink.simulate(cfg, motion=rssp_samples(cfg.mechanism, h, 0.1, derived))
        assert ds.attrs["backend"] == ref.attrs["backend"]
        errors.append([float(np.abs(ds[v] - ref[v]).max() / np.abs(ref[v]).max()) for v in ("u2_mid", "u3_mid")])
    rates = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all((rates > 3.6) & (rates < 4.4)), rates
    assert max(errors[0]) < 2e-6


@pytest.mark.parametrize("given, end", [("callables", "fixed"), ("samples", "fixed"), ("samples", "free")])
def test_constant_spin_and_acceleration_against_the_closed_forms(given, end):
    """Spin ``Omega`` about ``e3``, constant ``A_O``, gravity resolved through a tilted constant frame, heavy
    damping: after the transient the link rests in the quasi-static shape of the closed forms

    * ``E u1'' + rho Omega^2 u1 = rho (A1 - Omega^2 x)``, ``u1(0) = 0`` and ``u1(L) = 0`` (fixed-fixed bar) or
      ``u1'(L) = 0`` (fixed-free, ``beam.axial_end = "free"``: its modes ``sin((2 n - 1) pi x / (2 L))``);
    * ``E I u2'''' - rho A Omega^2 u2 = -rho A A2``, pinned (the spin softens the in-plane bending);
    * ``E I u3'''' = -rho A A3``, pinned (no spin across ``e3``: the uniformly loaded beam),

    with ``A = A_O - g`` in link-frame components. The sine modes are the exact eigenfunctions of
    these problems, so the modal coordinates must equal the closed forms' sine coefficients: to the
    transient left at 0.15 s, ``exp(-zeta omega_1 t) = 2e-7``.
    """
    Omega, A_O = 80.0, np.array([2.0e3, 50.0, -30.0])
    gravity = (3.0, -9.81)
    e1 = np.array([1.0, 1.0, 1.0]) / np.sqrt(3.0)
    e2 = np.array([1.0, -1.0, 0.0]) / np.sqrt(2.0)
    e3 = np.cross(e1, e2)
    g = np.array([gravity[0], gravity[1], 0.0])
    A1, A2, A3 = A_O - np.array([g @ e1, g @ e2, g @ e3])
    N = 3
    cfg = resolve("paper-dry", {"beam.model": "spatial", "beam.modes": N, "beam.damping_ratio": 0.7,
                                "mechanism.gravity": list(gravity), "solver.t_end": 0.15, "solver.rtol": 1e-9,
                                "solver.atol": 1e-13, "output.x_points": 11, "beam.axial_end": end})
    if given == "callables":
        motion = SpatialPrescribedMotion(A_O=A_O, omega=lambda t: (0.0, 0.0, Omega), alpha=(0.0, 0.0, 0.0),
                                         x_star=0.5, V_r=lambda t: 0.0, e1=e1, e2=e2)
    else:
        t = np.linspace(0.0, 0.15, 7)
        ones = np.ones((t.size, 1))
        motion = sampled_spatial_motion(t, A_O=A_O * ones, omega=[0.0, 0.0, Omega] * ones, x_star=0.5 * ones[:, 0],
                                        e1=e1, e2=e2)
    result = run(cfg, motion)
    assert result.status == "complete" and result.model.compiled == (given == "samples")
    b, L = cfg.beam, cfg.mechanism.rod_length
    E, rho, EI = b.youngs_modulus, b.density, b.youngs_modulus * b.second_moment
    EI_y = b.youngs_modulus * b.height * b.width**3 / 12.0
    rho_A = rho * b.area

    k = Omega * np.sqrt(rho / E)
    up = lambda x: (A1 - Omega**2 * x) / Omega**2  # noqa: E731
    C = -up(0.0)
    if end == "fixed":
        D = -(up(L) + C * np.cos(k * L)) / np.sin(k * L)
    else:  # u1'(L) = up' - C k sin(k L) + D k cos(k L) = 0, up' = -1
        D = (1.0 + C * k * np.sin(k * L)) / (k * np.cos(k * L))
    u1 = lambda x: up(x) + C * np.cos(k * x) + D * np.sin(k * x)  # noqa: E731
    kap = (rho_A * Omega**2 / EI) ** 0.25
    u2p = A2 / Omega**2
    u2 = lambda x: u2p * (1.0 - 0.5 * (np.cosh(kap * x) + (1 - np.cosh(kap * L)) / np.sinh(kap * L) * np.sinh(kap * x))  # noqa: E731
                          - 0.5 * (np.cos(kap * x) + (1 - np.cos(kap * L)) / np.sin(kap * L) * np.sin(kap * x)))
    u3 = lambda x: -rho_A * A3 / (24.0 * EI_y) * x * (L**3 - 2 * L * x**2 + x**3)  # noqa: E731

    nodes, weights = np.polynomial.legendre.leggauss(64)
    x, w = 0.5 * L * (nodes + 1.0), 0.5 * L * weights
    S = np.sin(np.outer(np.arange(1, N + 1) * np.pi / L, x))
    S1 = S if end == "fixed" else np.sin(np.outer((2 * np.arange(1, N + 1) - 1) * np.pi / (2 * L), x))
    y = result.y[-1]
    for direction, u in enumerate((u1, u2, u3)):
        exact = (2.0 / L) * (S1 if direction == 0 else S) @ (w * u(x))
        q = y[direction * N:(direction + 1) * N]
        assert np.abs(q - exact).max() < 1e-6 * np.abs(exact).max(), (direction, q, exact)
    assert abs(u2(0.5 * L)) > 1.3 * abs(5 * rho_A * A2 * L**4 / (384 * EI))  # the spin softens u2 by 40 %
    ds = lubelink.results.to_dataset(result)  # the stored midpoint: the truncated series, next term 5^-5
    assert float(ds.u3_mid[-1]) == pytest.approx(u3(0.5 * L), rel=5e-4)
    assert float(ds.u2_mid[-1]) == pytest.approx(u2(0.5 * L), rel=5e-4)


def test_sampled_motion_runs_compiled_as_its_python_source():
    cfg = resolve("spatial-slider-crank", SHORT)
    motion = rssp_samples(cfg.mechanism, 1e-3, 0.02)
    compiled = lubelink.simulate(cfg, motion=motion)
    plain = lubelink.simulate(cfg, set={"solver.backend": "numpy"}, motion=motion)
    assert compiled.attrs["backend"] == "numba" and plain.attrs["backend"] == "numpy"
    for name in ("u1", "u2", "u3", "film_force"):
        scale = float(np.abs(plain[name]).max())
        assert float(np.abs(compiled[name] - plain[name]).max()) < 1e-9 * scale


def test_spline_table_reproduces_the_samples_and_the_frame():
    """At the knots the table gives the samples back (interpolation), ``e3 = e1 x e2``, NaN for ``v_O``, ``O``."""
    cfg = resolve("spatial-slider-crank")
    motion = rssp_samples(cfg.mechanism, 1e-3, 0.01)
    ssc = SpatialSliderCrank(cfg.mechanism)
    assert isinstance(motion, SampledSpatialMotion) and motion.coef.shape[0] == len(CHANNELS)
    for t in motion.knots[::3]:
        got, want = spatial_motion_at(t, motion.table()), ssc.at(t)
        for name in ("A_O", "omega", "alpha", "x_star", "V_r", "e1", "e2", "e3"):
            a, b = getattr(got, name), getattr(want, name)
            np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12 * np.max(np.abs(b)))
        assert np.all(np.isnan(got.v_O)) and np.all(np.isnan(got.O))


T = np.linspace(0.0, 0.1, 11)
Z3 = np.zeros((11, 3))
X = np.full(11, 0.4)


@pytest.mark.parametrize("call, words", [
    (lambda: sampled_spatial_motion(T[::-1], Z3, Z3, X), ["t must be", "strictly increasing"]),
    (lambda: sampled_spatial_motion(np.r_[0.0, 0.1, 0.1, 0.2, 0.3], np.zeros((5, 3)), np.zeros((5, 3)),
                                    np.zeros(5)), ["not increasing after t = 0.1 s"]),
    (lambda: sampled_spatial_motion(T[:3], Z3[:3], Z3[:3], X[:3]), ["at least 4"]),
    (lambda: sampled_spatial_motion(T, Z3[:, :2], Z3, X), ["A_O must have shape (11, 3)", "got (11, 2)"]),
    (lambda: sampled_spatial_motion(T, Z3, Z3, X[:5]), ["x_star must have shape (11,)", "got (5,)"]),
    (lambda: sampled_spatial_motion(T, Z3, np.where(T[:, None] > 0.05, np.nan, Z3), X),
     ["omega must be finite", "t = 0.06 s"]),
    (lambda: sampled_spatial_motion(T, Z3, Z3, X, e1=(1.0, 0.0, 0.0), e2=(1.0, 0.0, 0.0)),
     ["orthonormal", "e1 . e2 = 1"]),
    (lambda: SpatialPrescribedMotion(A_O=lambda t: (0.0, 0.0), omega=Z3[0], alpha=Z3[0], x_star=0.4, V_r=0.0),
     ["A_O", "t = 0 s", "3 finite numbers", "shape (2,)"]),
    (lambda: SpatialPrescribedMotion(A_O=Z3[0], omega=Z3[0], alpha=Z3[0], x_star=lambda t: np.nan, V_r=0.0),
     ["x_star", "finite"]),
])
def test_bad_motions_are_refused_naming_the_argument(call, words):
    with pytest.raises(ValueError) as info:
        call()
    for w in words:
        assert w in str(info.value)


def test_a_run_outside_the_samples_or_a_pad_off_the_link_is_refused():
    cfg = resolve("spatial-slider-crank", {"solver.t_end": 0.2})
    with pytest.raises(lubelink.ConfigError, match=r"samples span \[0, 0.1\] s.*solver.t_end = 0.2"):
        lubelink.simulate(cfg, motion=sampled_spatial_motion(T, Z3, Z3, X))
    late = sampled_spatial_motion(T + 0.01, Z3, Z3, X)
    with pytest.raises(lubelink.ConfigError, match=r"samples span \[0.01, 0.11\] s"):
        lubelink.simulate(cfg, set={"solver.t_end": 0.1}, motion=late)
    off = SpatialPrescribedMotion(A_O=Z3[0], omega=Z3[0], alpha=Z3[0], x_star=lambda t: 0.9 + t, V_r=1.0)
    with pytest.raises(lubelink.ConfigError, match=r"x_star spans \[0.9, 1.1\] m.*inside \(0, 1.0\)"):
        lubelink.simulate(cfg, motion=off)


def test_planar_and_spatial_motions_are_refused_by_the_other_model():
    from lubelink.link.kinematics import SliderCrank

    spatial_cfg, planar_cfg = resolve("spatial-slider-crank"), resolve("paper")
    with pytest.raises(lubelink.ConfigError, match="motion = SliderCrank: beam.model = 'spatial' needs a spatial"):
        build_model(spatial_cfg, SliderCrank(spatial_cfg.mechanism))
    with pytest.raises(lubelink.ConfigError, match="motion = SampledSpatialMotion: a spatial motion drives"):
        build_model(planar_cfg, sampled_spatial_motion(T, Z3, Z3, X))
    with pytest.raises(BackendError, match="solver.backend = 'numba'.*sampled_spatial_motion"):
        build_model(resolve("spatial-slider-crank", {"solver.backend": "numba"}), rssp_callables(spatial_cfg.mechanism))



def test_simulate_validates_the_spatial_mechanism_once(monkeypatch):
    """``simulate(name, set=...)`` turns the crank over a turn (the validation of the spatial mechanism) once:
    not for the scenario and again after the overrides; a mechanism seen before is remembered."""
    from lubelink import config
    from lubelink.link import spatial_motion

    cached = spatial_motion.collar_travel
    cached.cache_clear()
    for _ in range(2):
        config._named.cache_clear()  # (else the second resolve returns the first's configuration unvalidated)
        lubelink.simulate("spatial-slider-crank", set={"mechanism.crank_tilt": 0.25, "solver.t_end": 0.01})
    info = cached.cache_info()
    assert (info.misses, info.hits) == (1, 1)
    calls = []
    monkeypatch.setattr(spatial_motion, "collar_travel", lambda m, samples=721: calls.append(m) or cached(m, samples))
    config._named.cache_clear()
    lubelink.simulate("spatial-slider-crank", set={"solver.t_end": 0.01})
    assert [m.crank_tilt for m in calls] == [0.2]


def test_collar_acceleration_of_a_sampled_motion_converges_to_the_slider_crank():
    """The sustained contact reads the collar's acceleration: for samples, the derivative of the
    ``V_r`` spline. Against the slider-crank's closed form (checked against differences of ``V_r``
    in tests/test_spatial_model.py) between the knots, at order >= 2 as the step halves."""
    from lubelink.link.spatial_motion import collar_acceleration_at

    cfg = resolve("spatial-slider-crank", SHORT)
    exact = SpatialSliderCrank(cfg.mechanism).table()
    t = np.linspace(0.001, 0.019, 37) + 1.234e-4  # off the knots
    a_ref = np.array([collar_acceleration_at(ti, exact) for ti in t])
    errors = []
    for h in (2e-3, 1e-3, 5e-4):
        table = rssp_samples(cfg.mechanism, h, 0.02).table()
        errors.append(np.abs(np.array([collar_acceleration_at(ti, table) for ti in t]) - a_ref).max())
    assert errors[-1] < 1e-3 * np.abs(a_ref).max()
    assert np.log2(errors[0] / errors[1]) > 1.8 and np.log2(errors[1] / errors[2]) > 1.8


def test_restitution_with_a_motion_of_callables_is_refused():
    cfg = resolve("spatial-slider-crank", {**SHORT, "contact.law": "restitution"})
    with pytest.raises(lubelink.ConfigError, match="contact.law = 'restitution' with a spatial motion of callables"):
        lubelink.simulate(cfg, motion=rssp_callables(cfg.mechanism))

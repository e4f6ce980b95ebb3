"""Results: the registry of variables, their contents and units, the series of a run, its warnings."""

import numpy as np
import pytest

import lubelink
from lubelink.netcdf import config_of


@pytest.fixture(scope="module")
def ds():
    from conftest import SHORT

    return lubelink.simulate("paper", set=SHORT)


def test_layout_units_and_provenance(ds):
    for name in ["q", "q_dot", "u2", "u2_mid", "x_star", "V_r", "pressure", "film_force", "film_min",
                 "impact_time", "impact_velocity", "time", "x", "mode", "x_pad"]:
        assert name in ds.variables, name
        assert ds[name].attrs["units"] and ds[name].attrs["long_name"]
    assert ds.u2.dims == ("time", "x") and ds.pressure.dims == ("time", "x_pad")
    assert ds.attrs["status"] == "complete"
    assert "[beam]" in ds.attrs["config"] and ds.attrs["lubelink_format"]
    assert config_of(ds) == lubelink.resolve_config("paper", {k: v for k, v in
                                                              __import__("conftest").SHORT.items()})
    # u2 is the modal sum: its midpoint column equals u2_mid (independent path: 21 points, x = L/2 at index 10)
    np.testing.assert_allclose(ds.u2.isel(x=10), ds.u2_mid, atol=1e-15)


def test_collect_computes_only_the_variables_asked_for():
    from lubelink.results import collect
    from lubelink.simulate import run

    r = run(lubelink.config.resolve("paper", {"solver.t_end": 0.05}))
    full, lean = collect(r), collect(r, variables={"u2_mid", "film_min"})
    assert {"u2", "pressure", "pressure_lower", "film_force"}.isdisjoint(lean.data_vars)
    for name in ("u2_mid", "film_min", "q", "impact_time"):
        np.testing.assert_array_equal(lean[name], full[name])
    assert list(lean.data_vars) == [n for n in full.data_vars if n in lean.data_vars]  # same order


@pytest.mark.parametrize("scenario, overrides", [
    ("paper", {"solver.t_end": 0.05}),  # no impact: an empty impact dimension
    ("paper-impact", {}),  # impacts (the first at 1.27 s), contact phases
    ("spatial-slider-crank", {"solver.t_end": 0.02}),  # the direction coordinate, u1, u3
])
def test_the_dataset_assembled_directly_is_the_one_of_xarrays_constructor(scenario, overrides):
    """:func:`results.dataset` (xarray's shortcut, no alignment) gives the Dataset that
    ``xarray.Dataset(data_vars, coords, attrs)`` builds from the same results: values, dims,
    indexes, attributes and coordinate names."""
    import xarray as xr

    from lubelink.results import collect, dataset
    from lubelink.simulate import run

    r = collect(run(lubelink.config.resolve(scenario, overrides)))
    direct = dataset(r)
    built = xr.Dataset(r.data_vars, coords=r.coords, attrs=r.attrs)
    xr.testing.assert_identical(direct, built)
    assert list(direct.data_vars) == list(built.data_vars) and set(direct.xindexes) == set(built.xindexes)
    assert dict(direct.sizes) == dict(built.sizes)
    if scenario == "paper-impact":
        assert direct.sizes["impact"] > 0
    direct.isel(time=slice(0, 3)).sel(x=0.5, method="nearest")  # the indexes work


# ====================================================================== issue 16 item 9: NetCDF conventions
def test_units_of_the_registry_are_dimensionally_right():
    """Each unit string of VARIABLES has the dimension its name implies (cf-units)."""
    cf_units = pytest.importorskip("cf_units")
    from lubelink.results import VARIABLES

    kinds = {"m": "metre", "m s-1": "metre/second", "Pa": "kg m-1 s-2", "N": "kg m s-2", "s": "second",
             "rad s-1": "1/second", "1": "1", "J": "kg m2 s-2", "W": "kg m2 s-3", "rad": "1",
             "N m": "kg m2 s-2"}
    for name, v in VARIABLES.items():
        assert v.units in kinds, (name, v.units)
        assert cf_units.Unit(v.units).is_convertible(cf_units.Unit(kinds[v.units])), name


def _pressure_peak(_):
    return float(lubelink.simulate("paper", set={"solver.t_end": 0.05}).pressure.max())


def test_pressure_beside_the_other_series_equals_it_computed_in_line(monkeypatch):
    """The pad pressure, computed in a worker thread beside the other series, is the same array
    as computed in the calling thread; a forked child (which inherits the parent's executor but
    not its thread) gets its own thread instead of waiting for ever."""
    import multiprocessing
    import os

    from lubelink import results

    threaded = lubelink.simulate("paper", set={"solver.t_end": 0.05})
    assert results._POOL.get(os.getpid()) is not None or len(os.sched_getaffinity(0)) < 2
    monkeypatch.setattr(results, "_pool", lambda: None)
    inline = lubelink.simulate("paper", set={"solver.t_end": 0.05})
    np.testing.assert_array_equal(threaded.pressure.values, inline.pressure.values)
    monkeypatch.undo()
    with multiprocessing.get_context("fork").Pool(1) as pool:
        peaks = pool.map_async(_pressure_peak, [0]).get(timeout=120)
    assert peaks == [float(threaded.pressure.max())]


def test_one_thread_computes_the_pressure_here_and_a_sweep_point_asks_for_it(monkeypatch):
    """``collect(..., threads=1)`` (a sweep's worker, given one thread by its cluster) computes the
    pad pressure in the calling thread, the same array; a sweep point never starts the thread."""
    import importlib

    from lubelink import results
    from lubelink.config import resolve
    from lubelink.sweep.compute import _TaskOptions, _compute_point

    config = resolve("paper", {"solver.t_end": 0.05})
    run = importlib.import_module("lubelink.simulate").run(config)
    threaded = results.collect(run)

    def no_thread():
        raise AssertionError("the second thread was asked for")

    monkeypatch.setattr(results, "_pool", no_thread)
    np.testing.assert_array_equal(results.collect(run, threads=1)["pressure"], threaded["pressure"])
    record, _ = _compute_point(0, config, _TaskOptions(("peak_pressure",), (), 10, 0, 1e-3, "test"))
    assert record["status"] == "complete", record["message"]
    assert record["peak_pressure"] == float(np.abs(threaded["pressure"]).max())


# ---------------------------------------------------------------- penetration of the collar (restitution law)
def test_a_second_point_reaching_the_face_in_a_sustained_contact_stops_the_run():
    """``paper-impact`` with 3 modes (issue 34's audit case): a Zeno sequence ends in a sustained contact
    held at one point while another point of the pad reaches the collar face. The run used to go on,
    the link passing 101.8 um through the face at 1.07329 s, and end ``complete``; it now stops there
    with status ``penetration``. The film computed here from the modal sum on a fine pad grid confirms
    a second thin point away from the held one, and no sample is through the face."""
    ds = lubelink.simulate("paper-impact", {"beam.modes": 3, "solver.t_end": 1.1, "solver.output_step": 1e-5})
    assert ds.attrs["status"] == "penetration" and ds.attrs["complete"] == 0
    message = ds.attrs["message"]
    assert "second point" in message and "t = 1.0728" in message
    cfg = config_of(ds)
    m, f = cfg.mechanism, cfg.film
    # the last sample is the event itself, where the film elsewhere on the pad is 0.9 min_film (to round-off)
    assert float(ds["film_min"][-1]) == pytest.approx(0.9 * cfg.contact.min_film, rel=1e-9)
    assert float(ds["film_min"][:-1].min()) > 0.9 * cfg.contact.min_film
    held = float(message.split("held it at x = ")[1].split(" m")[0])
    i = ds.time.size - 1
    x0 = float(ds.x_star[i]) - (0.5 * f.pad_length if f.pad_reference == "centre" else 0.0)
    x = np.linspace(x0, x0 + f.pad_length, 2001)
    n = np.arange(1, cfg.beam.modes + 1)
    film = f.clearance / 2 - np.sin(np.outer(x, n) * np.pi / m.rod_length) @ ds["q"].values[i]
    k = int(np.argmin(film))
    assert film[k] < cfg.contact.min_film and abs(x[k] - held) > 0.002  # the second point, 4.4 mm away
    assert film[np.argmin(abs(x - held))] == pytest.approx(cfg.contact.min_film, rel=1e-3)  # the held one


def test_a_link_through_the_face_between_samples_of_free_flight_is_not_complete():
    """The samples' check (:func:`lubelink.contact.penetration`) still catches what the events cannot: it
    turns a would-be complete run into ``penetration`` (here the check is fed a link through the face)."""
    from lubelink import results
    from lubelink.config import resolve
    from lubelink.simulate import run

    r = run(resolve("paper-impact", {"solver.t_end": 0.05}))
    assert r.status == "complete"
    r.y = r.y.copy()
    r.y[-3:, 0] = 0.01  # u2 of 1 cm: through the face of 1 mm clearance
    ds = results.dataset(results.collect(r))
    assert ds.attrs["status"] == "penetration" and ds.attrs["complete"] == 0
    assert "went through the collar face" in ds.attrs["message"]


def test_no_warning_when_the_film_stays_above_the_contact_threshold():
    ds = lubelink.simulate("paper-impact")
    assert ds.attrs["impact_count"] > 0 and ds.attrs["contact_warning"] == ""
    assert float(ds["film_min"].min()) >= 0.9 * config_of(ds).contact.min_film


def test_a_sweep_point_records_the_penetration_even_without_storing_the_film():
    """A sweep point computes only what it stores; the penetration is its status and message regardless."""
    from lubelink.config import resolve
    from lubelink.results import collect
    from lubelink.simulate import run
    from lubelink.sweep.compute import summarise

    r = run(resolve("paper-impact", {"solver.t_end": 0.05}))
    r.y = r.y.copy()
    r.y[-3:, 0] = 0.01  # through the face, as in the test above
    r = collect(r, variables={"u2_mid"})
    assert "film_min" not in r.data_vars
    record = summarise(r, ("peak_u2_mid",))
    assert record["status"] == "penetration" and "went through the collar face" in record["message"]


def test_the_direct_dataset_of_an_orbit_and_of_a_branch_is_the_constructors():
    """``lubelink.periodic`` and ``lubelink.continuation`` build their Datasets through
    :func:`results.dataset` too: the same Dataset as xarray's constructor, for their own
    dimensions (harmonics, points, bifurcations)."""
    import xarray as xr

    from lubelink.results import dataset
    from lubelink.steady.branch import branch_results, find_branch
    from lubelink.steady.orbit import find_periodic, orbit_results

    config = lubelink.config.resolve("paper-dry", {"beam.damping_ratio": 0.02})
    orbit = orbit_results(find_periodic(config))
    branch = branch_results(*find_branch(config, 46.5, start=46.0, max_points=3))
    for r in (orbit, branch):
        direct = dataset(r)
        xr.testing.assert_identical(direct, xr.Dataset(r.data_vars, coords=r.coords, attrs=r.attrs))
        assert set(direct.xindexes) == set(xr.Dataset(r.data_vars, coords=r.coords).xindexes)


def test_a_sweep_point_skips_the_configuration_text(monkeypatch):
    """A sweep point's results carry no TOML text of their configuration (its store records the sweep):
    ``to_toml`` is never called, and its summary is the one of the full results."""
    import importlib

    from lubelink import config as config_module
    from lubelink import results
    from lubelink.config import resolve
    from lubelink.sweep.compute import _TaskOptions, _compute_point

    config = resolve("paper", {"solver.t_end": 0.05, "film.viscosity": 0.1234})
    full = results.collect(importlib.import_module("lubelink.simulate").run(config))
    assert "viscosity = 0.1234" in full.attrs["config"]

    def no_text(_):
        raise AssertionError("the configuration's text was asked for")

    monkeypatch.setattr(config_module, "to_toml", no_text)
    record, _ = _compute_point(0, config, _TaskOptions(("peak_film_force", "min_film"), (), 10, 0, 1e-3, "test"))
    assert record["status"] == "complete", record["message"]
    assert record["peak_film_force"] == float(np.abs(full["film_force"]).max())
    assert record["min_film"] == float(np.min(full["film_min"]))


def test_a_link_sagging_under_its_weight_has_the_static_beams_bending_stress():
    """A pinned-pinned link at rest under gravity, damped to rest (zeta 0.9): at mid-span the bending stress is
    (w (h/2) / I) (4 L^2 / pi^3) sum over odd n <= N of (-1)^((n-1)/2) / n^3, the static sine series of the uniform
    load w = rho A g, which tends to the beam's w L^2 / 8 (h/2) / I (7 modes: 0.08 % above it); along the link the
    stress is that series' (to 1e-9) and the static moment w x (L - x) / 2 times (h/2) / I (to 0.3 %: the series
    converges slowest near the pins), and it is largest at mid-span."""
    from lubelink.config import resolve
    from lubelink.link.kinematics import sampled_motion
    from lubelink.results import collect, dataset
    from lubelink.simulate import run

    N, g = 7, 9.81
    cfg = resolve("paper-dry", {"beam.modes": N, "beam.damping_ratio": 0.9, "mechanism.gravity": [0.0, -g],
                                "solver.t_end": 0.5, "output.x_points": 41})
    t = np.linspace(0.0, 0.6, 8)
    zero = np.zeros_like(t)
    ds = dataset(collect(run(cfg, motion=sampled_motion(t, A_O2=zero, omega=zero, x_star=zero + 0.4))))
    b, L = cfg.beam, cfg.mechanism.rod_length
    w, c, I = b.density * b.width * b.height * g, b.height / 2, b.width * b.height**3 / 12
    odd = np.arange(1, N + 1, 2)
    series = 4 * L**2 / np.pi**3 * np.sum((-1.0) ** ((odd - 1) // 2) / odd**3)
    stress = ds.bending_stress.values[-1]
    x = ds.x.values
    mid = int(np.argmin(np.abs(x - L / 2)))
    assert stress[mid] == pytest.approx(w * c / I * series, rel=1e-9)
    assert stress[mid] == pytest.approx(w * L**2 / 8 * c / I, rel=1e-3)
    truncated = w * c / I * np.abs(4 * L**2 / np.pi**3 * np.sin(np.outer(x, odd) * np.pi / L) @ (1.0 / odd**3))
    np.testing.assert_allclose(stress, truncated, rtol=1e-9, atol=1e-9 * stress[mid])
    np.testing.assert_allclose(stress, w * x * (L - x) / 2 * c / I, rtol=0, atol=5e-3 * stress[mid])
    assert int(np.argmax(stress)) == mid


def test_a_spatial_link_sagging_out_of_its_plane_has_the_static_beams_bending_stress():
    """The spatial link at rest with its e3 axis vertical (e2 horizontal): gravity bends it out of plane (u3), about
    the section's other axis: at mid-span the stress is w (B/2) / I_y times the same truncated static series."""
    from lubelink.config import resolve
    from lubelink.link.spatial_motion import sampled_spatial_motion
    from lubelink.results import collect, dataset
    from lubelink.simulate import run

    N, g = 5, 9.81
    cfg = resolve("spatial-slider-crank", {"beam.modes": N, "beam.damping_ratio": 0.9, "mechanism.gravity": [0.0, -g],
                                           "film.model": "none", "solver.t_end": 0.5, "output.x_points": 41})
    t = np.linspace(0.0, 0.6, 8)
    n = t.size
    motion = sampled_spatial_motion(t, A_O=np.zeros((n, 3)), omega=np.zeros((n, 3)), x_star=np.full(n, 0.4),
                                    e1=np.array([1.0, 0.0, 0.0]), e2=np.array([0.0, 0.0, 1.0]))
    ds = dataset(collect(run(cfg, motion=motion)))
    b, L = cfg.beam, cfg.mechanism.rod_length
    w, c, I_y = b.density * b.width * b.height * g, b.width / 2, b.height * b.width**3 / 12
    odd = np.arange(1, N + 1, 2)
    series = 4 * L**2 / np.pi**3 * np.sum((-1.0) ** ((odd - 1) // 2) / odd**3)
    mid = int(np.argmin(np.abs(ds.x.values - L / 2)))
    assert float(np.abs(ds.u2_mid[-1])) < 1e-12 * float(np.abs(ds.u3_mid[-1]))
    assert float(ds.bending_stress[-1, mid]) == pytest.approx(w * c / I_y * series, rel=1e-9)

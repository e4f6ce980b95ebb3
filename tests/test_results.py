"""Results dataset: contents, units, provenance, atomic save, versioned load."""

import numpy as np
import pytest
import xarray as xr

import lubelink
from lubelink.results import ResultsFileError, config_of


@pytest.fixture(scope="module")
def ds():
    from conftest import SHORT

    return lubelink.simulate("paper", set=SHORT)


def test_layout_units_and_provenance(ds):
    for name in ["q", "q_dot", "u2", "u2_mid", "x_star", "V_r", "pressure", "film_force", "film_min",
                 "impact_time", "impact_velocity", "time", "x", "mode", "X"]:
        assert name in ds.variables, name
        assert ds[name].attrs["units"] and ds[name].attrs["long_name"]
    assert ds.u2.dims == ("time", "x") and ds.pressure.dims == ("time", "X")
    assert ds.attrs["status"] == "complete"
    assert "[beam]" in ds.attrs["config"] and ds.attrs["lubelink_format"]
    assert config_of(ds) == lubelink.resolve_config("paper", {k: v for k, v in
                                                              __import__("conftest").SHORT.items()})
    # u2 is the modal sum: its midpoint column equals u2_mid (independent path: 21 points, x = L/2 at index 10)
    np.testing.assert_allclose(ds.u2.isel(x=10), ds.u2_mid, atol=1e-15)


def test_save_load_round_trip(ds, tmp_path):
    path = lubelink.save(ds, tmp_path / "r.nc")
    back = lubelink.load(path)
    # the file names the netCDF-C and HDF5 libraries that wrote it, after the packages of the run
    assert back.attrs["versions"].startswith(ds.attrs["versions"] + ", netCDF-C ")
    back.attrs["versions"] = ds.attrs["versions"]
    xr.testing.assert_identical(back, ds)
    with pytest.raises(ResultsFileError, match="exists"):
        lubelink.save(ds, path)
    lubelink.save(ds, path, overwrite=True)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.nc"]


def test_failed_write_leaves_nothing(ds, tmp_path, monkeypatch):
    def boom(self, *a, **k):
        raise OSError("disk full")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", boom)
    with pytest.raises(OSError):
        lubelink.save(ds, tmp_path / "r.nc")
    assert list(tmp_path.iterdir()) == []


def test_load_rejects_foreign_files(tmp_path):
    other = tmp_path / "other.nc"
    xr.Dataset({"a": ("t", [1.0])}).to_netcdf(other)
    with pytest.raises(ResultsFileError, match="format missing"):
        lubelink.load(other)
    junk = tmp_path / "junk.nc"
    junk.write_text("not netcdf")
    with pytest.raises(ResultsFileError, match="not a readable"):
        lubelink.load(junk)
    with pytest.raises(ResultsFileError, match="no such"):
        lubelink.load(tmp_path / "none.nc")


def test_config_of_a_foreign_dataset_is_a_clear_error(ds):
    with pytest.raises(ResultsFileError, match="no 'config' attribute"):
        config_of(xr.Dataset({"a": ("t", [1.0])}))
    with pytest.raises(ResultsFileError, match="not valid TOML"):
        config_of(xr.Dataset(attrs={"config": "[beam\nmodes"}))


def test_save_refuses_other_suffixes_and_special_files(ds, tmp_path):
    import os

    with pytest.raises(ResultsFileError, match=r"name the file \*.nc"):
        lubelink.save(ds, tmp_path / "r.zarr")
    (tmp_path / "d.nc").mkdir()
    os.mkfifo(tmp_path / "p.nc")
    for name in ("d.nc", "p.nc"):
        with pytest.raises(ResultsFileError, match="only a regular file"):
            lubelink.save(ds, tmp_path / name, overwrite=True)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.nc", "p.nc"]


def test_collect_computes_only_the_variables_asked_for():
    from lubelink.results import collect
    from lubelink.simulate import run

    r = run(lubelink.config.resolve("paper", {"solver.t_end": 0.05}))
    full, lean = collect(r), collect(r, variables={"u2_mid", "film_min"})
    assert {"u2", "pressure", "pressure_lower", "film_force"}.isdisjoint(lean.data_vars)
    for name in ("u2_mid", "film_min", "q", "impact_time"):
        np.testing.assert_array_equal(lean[name], full[name])
    assert list(lean.data_vars) == [n for n in full.data_vars if n in lean.data_vars]  # same order


# ====================================================================== issue 16 item 9: NetCDF conventions
@pytest.fixture(scope="module")
def impact_results():
    """Results of a run with impacts (two-sided collar), before they become a Dataset."""
    from lubelink.results import collect
    from lubelink.simulate import run

    config = lubelink.resolve_config("paper-impact", {"solver.t_end": 1.3, "film.sides": 2})
    r = collect(run(config))
    assert r.attrs["impact_count"] > 0
    return r


def _both_writers(results, folder):
    """The same results written by the CLI's netCDF4 writer and by :func:`lubelink.save` (xarray)."""
    from lubelink.results import write

    a = write(results, folder / "netcdf4.nc")
    b = lubelink.save(xr.Dataset(results.data_vars, coords=results.coords, attrs=results.attrs), folder / "xarray.nc")
    return a, b


def test_both_writers_write_the_same_file(impact_results, tmp_path):
    """Variables, dtypes, attributes, compression and global attributes agree, read with netCDF4."""
    import netCDF4

    a, b = _both_writers(impact_results, tmp_path)
    with netCDF4.Dataset(a) as fa, netCDF4.Dataset(b) as fb:
        assert list(fa.dimensions) and {d: len(v) for d, v in fa.dimensions.items()} == \
            {d: len(v) for d, v in fb.dimensions.items()}
        assert set(fa.variables) == set(fb.variables)
        for name, va in fa.variables.items():
            vb = fb.variables[name]
            assert va.dimensions == vb.dimensions and va.dtype == vb.dtype, name
            assert set(va.ncattrs()) == set(vb.ncattrs()), name
            for attr in va.ncattrs():
                np.testing.assert_array_equal(va.getncattr(attr), vb.getncattr(attr), err_msg=f"{name}.{attr}")
            fa_, fb_ = va.filters(), vb.filters()
            assert fa_ == fb_, name
            if va.size:
                assert fa_["zlib"] and 1 <= fa_["complevel"] <= 4, name
                np.testing.assert_array_equal(va[...], vb[...], err_msg=name)
        assert fa.ncattrs() == fb.ncattrs()
        for attr in fa.ncattrs():
            assert fa.getncattr(attr) == fb.getncattr(attr), attr


def test_compression_shrinks_the_file(impact_results, tmp_path):
    """Lossless zlib (level 2, with the shuffle filter) shrinks a results file: by 10 % here, by
    20 % on the paper scenario's 2 s (float64 samples do not compress to half without losing digits)."""
    import netCDF4

    from lubelink.results import file_attrs

    a, _ = _both_writers(impact_results, tmp_path)
    plain = tmp_path / "plain.nc"
    with netCDF4.Dataset(plain, "w") as nc:
        for dims, data, _ in list(impact_results.coords.values()) + list(impact_results.data_vars.values()):
            for dim, n in zip(dims, np.shape(data)):
                if dim not in nc.dimensions:
                    nc.createDimension(dim, n)
        for name, (dims, data, attrs) in list(impact_results.coords.items()) + list(impact_results.data_vars.items()):
            var = nc.createVariable(name, np.asarray(data).dtype, dims)
            var.setncatts(attrs)
            if np.size(data):
                var[...] = data
        nc.setncatts(file_attrs(impact_results.attrs))
    assert a.stat().st_size < 0.95 * plain.stat().st_size


#: A CF variable name (CF 2.3) and a flag meaning (CF 3.5: blank-separated words of these characters).
CF_NAME = r"[A-Za-z][A-Za-z0-9_]*"
CF_FLAG_WORD = r"[A-Za-z0-9_.+@-]+"


def test_files_follow_the_cf_conventions(impact_results, tmp_path):
    """The CF attributes that matter here, checked on both writers' files: Conventions, units that
    UDUNITS-2 parses (cf-units, which bundles it), long names, flag variables whose values are
    unique, of the variable's type, one per meaning and cover the data, and the run's provenance
    (wall time with its units, the versions of the numerical and NetCDF libraries)."""
    import re

    import netCDF4

    cf_units = pytest.importorskip("cf_units")
    for path in _both_writers(impact_results, tmp_path):
        with netCDF4.Dataset(path) as nc:
            assert nc.Conventions == "CF-1.10"
            for attr in ("title", "source", "references"):
                assert getattr(nc, attr)
            assert isinstance(nc.wall_time, float) and nc.wall_time > 0
            assert cf_units.Unit(nc.wall_time_units) == cf_units.Unit("second")
            versions = nc.versions
            for package in ("numpy", "scipy", "numba", "netCDF4", "netCDF-C", "HDF5"):
                assert re.search(rf"\b{re.escape(package)} \d", versions), (package, versions)
            flags = 0
            for name, var in nc.variables.items():
                assert re.fullmatch(CF_NAME, name), name
                assert var.long_name, name
                unit = cf_units.Unit(var.units)  # raises for a string UDUNITS-2 cannot parse
                assert not unit.is_unknown(), (name, var.units)
                assert "standard_name" not in var.ncattrs()  # none used: no table to check them against
                if "flag_values" in var.ncattrs() or "flag_meanings" in var.ncattrs():
                    flags += 1
                    values = np.atleast_1d(var.flag_values)
                    words = var.flag_meanings.split(" ")
                    assert all(re.fullmatch(CF_FLAG_WORD, w) for w in words), words
                    assert values.dtype == var.dtype and len(set(values.tolist())) == values.size == len(words)
                    data = np.asarray(var[...])
                    assert set(data.tolist()) <= set(values.tolist()), name
            assert flags == 2  # impact_side, contact_phase
            assert nc["impact_side"].size > 0  # the flags were checked against data


def test_units_of_the_registry_are_dimensionally_right():
    """Each unit string of VARIABLES has the dimension its name implies (cf-units)."""
    cf_units = pytest.importorskip("cf_units")
    from lubelink.results import VARIABLES

    kinds = {"m": "metre", "m s-1": "metre/second", "Pa": "kg m-1 s-2", "N": "kg m s-2", "s": "second",
             "rad s-1": "1/second", "1": "1"}
    for name, v in VARIABLES.items():
        assert v.units in kinds, (name, v.units)
        assert cf_units.Unit(v.units).is_convertible(cf_units.Unit(kinds[v.units])), name


@pytest.mark.parametrize("umask", [0o022, 0o077])
def test_both_writers_honour_the_umask(impact_results, tmp_path, umask):
    """Issue 16 item 4: the mode of a new results file is what the umask asks, whichever writer."""
    import os
    import stat

    old = os.umask(umask)
    try:
        paths = _both_writers(impact_results, tmp_path)
    finally:
        os.umask(old)
    for path in paths:
        assert stat.S_IMODE(path.stat().st_mode) == 0o666 & ~umask, path
    assert sorted(p.name for p in tmp_path.iterdir()) == ["netcdf4.nc", "xarray.nc"]  # no temporary left


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


# ---------------------------------------------------------------- penetration of the collar (restitution law)
def test_a_penetration_in_a_sustained_contact_is_reported_and_is_real():
    """``paper-impact`` with 3 modes: a Zeno sequence ends in a sustained contact held at one point
    while the link goes through the collar face elsewhere on the pad. The warning must name it,
    and the film computed here from the modal sum on a fine pad grid must confirm it."""
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = lubelink.simulate("paper-impact", {"beam.modes": 3, "solver.t_end": 1.1})
    message = ds.attrs["contact_warning"]
    assert "sustained contact" in message and any(message in str(w.message) for w in caught)
    cfg = config_of(ds)
    m, f = cfg.mechanism, cfg.film
    i = int(np.argmin(ds["film_min"].values))
    assert f"t = {float(ds.time[i]):.6g} s" in message
    x0 = float(ds.x_star[i]) - (0.5 * f.pad_length if f.pad_reference == "centre" else 0.0)
    x = np.linspace(x0, x0 + f.pad_length, 2001)
    n = np.arange(1, cfg.beam.modes + 1)
    u2 = np.sin(np.outer(x, n) * np.pi / m.rod_length) @ ds["q"].values[i]
    film = f.clearance / 2 - u2  # the film H/2 - u2 of the watched face
    assert film.min() < 0.9 * cfg.contact.min_film
    assert film.min() == pytest.approx(float(ds["film_min"][i]), abs=1e-8)


def test_no_warning_when_the_film_stays_above_the_contact_threshold():
    ds = lubelink.simulate("paper-impact")
    assert ds.attrs["impact_count"] > 0 and ds.attrs["contact_warning"] == ""
    assert float(ds["film_min"].min()) >= 0.9 * config_of(ds).contact.min_film


def test_the_penetration_message_says_where_and_when():
    from lubelink.results import penetration

    t = np.arange(5.0)
    ok = np.array([9e-6, 5e-6, 4.6e-6, 6e-6, 7e-6])  # 4.6 um: within 10 % of min_film = 5 um
    assert penetration(t, ok, np.zeros(5), 5e-6) == ""
    held = np.array([9e-6, 4e-6, -2e-6, 6e-6, 7e-6])
    side = np.array([0, 1, 1, 0, 0])
    text = penetration(t, held, side, 5e-6)
    assert "to -2e-06 m at t = 2 s (first at t = 1 s, 2 samples), during a sustained contact" in text
    assert "partly in free flight" in penetration(t, held, np.zeros(5), 5e-6)


def test_a_sweep_point_records_the_penetration_even_without_storing_the_film():
    """A sweep point computes only what it stores; the penetration check runs regardless, and the
    point's record carries it as its message."""
    from lubelink.config import resolve
    from lubelink.results import collect
    from lubelink.simulate import run
    from lubelink.sweep.compute import summarise

    r = collect(run(resolve("paper-impact", {"beam.modes": 3, "solver.t_end": 1.1})), variables={"u2_mid"})
    assert "film_min" not in r.data_vars
    record = summarise(r, ("peak_u2_mid",))
    assert record["status"] == "complete" and "went through the collar face" in record["message"]

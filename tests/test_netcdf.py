"""Results files (lubelink.netcdf): atomic save and write, the two writers agree, compression, CF
conventions, the umask, versioned load, the configuration read back."""

import numpy as np
import pytest
import xarray as xr

import lubelink
from lubelink.netcdf import ResultsFileError, config_of


@pytest.fixture(scope="module")
def ds():
    from conftest import SHORT

    return lubelink.simulate("paper", set=SHORT)


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


def test_a_file_of_format_1_0_reads_its_pad_coordinate_X_as_x_pad(ds, tmp_path):
    """Format 1.0 named the pad's coordinate ``X``, which differs from the link's ``x`` only by case
    (CF 2.3 warns of such names); such a file loads with the name of format 1.1."""
    import netCDF4

    assert ds.pressure.dims == ("time", "x_pad") and "X" not in ds.variables
    path = tmp_path / "old.nc"  # the layout of format 1.0, written by xarray (netCDF4's renaming in place
    old = ds.rename({"x_pad": "X"})  # of a coordinate variable loses its values in HDF5)
    old.attrs["lubelink_format"] = "1.0"
    old.to_netcdf(path)
    with netCDF4.Dataset(path) as nc:
        assert "X" in nc.variables and nc["pressure"].dimensions == ("time", "X")
    back = lubelink.load(path)
    assert "X" not in back.variables and back.pressure.dims == ("time", "x_pad")
    np.testing.assert_array_equal(back.x_pad.values, ds.x_pad.values)
    np.testing.assert_array_equal(back.pressure.values, ds.pressure.values)


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
    from lubelink.netcdf import write

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
            np.testing.assert_array_equal(fa.getncattr(attr), fb.getncattr(attr), err_msg=attr)  # (NaN == NaN here)


def test_compression_shrinks_the_file(impact_results, tmp_path):
    """Lossless zlib (level 2, with the shuffle filter) shrinks a results file: by 10 % here, by
    20 % on the paper scenario's 2 s (float64 samples do not compress to half without losing digits)."""
    import netCDF4

    from lubelink.netcdf import file_attrs

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
            names = list(nc.variables) + list(nc.dimensions)
            assert len({n.lower() for n in names}) == len(set(names)), names  # CF 2.3: none differ only by case
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

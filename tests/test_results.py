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

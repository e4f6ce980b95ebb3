"""The sweep store's two writers, and the command's choice of where the points run.

:func:`lubelink.sweep.layout.write_empty` (Zarr alone) against ``Dataset.to_zarr`` of
:func:`lubelink.sweep.layout._template` (xarray's encoding, an independent writer): the same files,
the same metadata and the same chunks, for grids, explicit points, strings, impacts and time series.
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest

from lubelink.sweep import read_sweep
from lubelink.sweep.layout import _template, write_empty

SWEEPS = {
    "grid": {"base": "paper", "vary": {"film.viscosity": {"start": 0.1, "stop": 0.2, "num": 3},
                                       "film.clearance": [2e-3, 3e-3]},
             "store": {"quantities": ["peak_u2_mid", "min_film", "impact_times", "regime", "impact_count"]}},
    "strings and integers": {"base": "paper", "vary": {"film.model": ["wedge", "wedge+squeeze"], "beam.modes": [1, 2],
                                                       "film.viscosity": {"start": 0.1, "stop": 0.2, "num": 5000,
                                                                          "scale": "log"}},
                             "store": {"quantities": ["nfev", "regime", "impact_times"]}},
    "points and series": {"base": "paper", "points": [{"film.viscosity": 0.1, "film.model": "wedge"},
                                                      {"film.viscosity": 0.2, "film.model": "wedge+squeeze"}],
                          "store": {"quantities": ["peak_u2_mid", "regime"], "time_series": ["u2_mid", "u2", "q"]}},
}


def _reference(sp, folder):
    """The store as ``Dataset.to_zarr`` writes it: metadata (the Dask time series unwritten), then the values."""
    import zarr

    ds, encoding = _template(sp)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds.to_zarr(str(folder), mode="w-", compute=False, consolidated=False, encoding=encoding)
    g = zarr.open_group(str(folder), mode="r+")
    for name, var in ds.variables.items():
        if not hasattr(var.data, "dask"):
            g[name][...] = var.values


def _files(folder):
    return {str(p.relative_to(folder)): p for p in Path(folder).rglob("*") if p.is_file()}


@pytest.mark.parametrize("name", list(SWEEPS))
def test_the_zarr_writer_makes_the_store_xarray_makes(tmp_path, name):
    pytest.importorskip("dask")
    sp = read_sweep(SWEEPS[name])
    _reference(sp, tmp_path / "a.zarr")
    write_empty(sp, tmp_path / "b.zarr")
    a, b = _files(tmp_path / "a.zarr"), _files(tmp_path / "b.zarr")
    assert sorted(a) == sorted(b)
    for rel, path in a.items():
        if rel.endswith(".json"):
            ma, mb = json.loads(path.read_text()), json.loads(b[rel].read_text())
            ma.get("attributes", {}).pop("created", None)
            mb.get("attributes", {}).pop("created", None)
            assert ma == mb, rel
        else:
            assert path.read_bytes() == b[rel].read_bytes(), rel


def test_a_new_store_reads_back_with_its_no_data_values(tmp_path):
    from lubelink.sweep.store import _Store, load_sweep, outcome

    sp = read_sweep(SWEEPS["points and series"])
    _Store.open(tmp_path / "s.zarr", sp).close()
    ds = load_sweep(tmp_path / "s.zarr")
    assert not ds.done.values.any() and np.isnan(ds.u2.values).all() and list(ds.regime.values) == ["", ""]
    assert ds.u2.dims == ("point", "time", "x") and ds["film.model"].values.tolist() == ["wedge", "wedge+squeeze"]
    done, status, message, attrs = outcome(tmp_path / "s.zarr")
    assert not done.any() and status.tolist() == ["", ""] and attrs["sweep_hash"] == sp.hash


def test_auto_counts_the_cores_other_processes_leave_free(monkeypatch):
    from lubelink.sweep import execute

    sp = read_sweep({"base": "paper", "vary": {"film.viscosity": [0.05, 0.1]}})
    monkeypatch.setattr(execute, "_cpu_count", lambda: 2)
    monkeypatch.setattr(execute, "SERIAL_SECONDS", 0.0)
    monkeypatch.setattr(execute, "free_cores", lambda: (1.2, 0.8))
    kind, n, line = execute.choose_executor(sp, 1000)
    assert (kind, n) == ("serial", 1) and "one core free; other processes keep 0.8 of 2 cores busy" in line
    monkeypatch.setattr(execute, "free_cores", lambda: (1.6, 0.4))
    assert execute.choose_executor(sp, 1000)[:2] == ("processes", 2)
    monkeypatch.setattr(execute, "free_cores", lambda: (0.0, 2.0))
    assert execute.choose_executor(sp, 1000, workers=2)[:2] == ("processes", 2)  # asked for: as asked


def test_free_cores_sees_a_busy_process(monkeypatch):
    """A child spinning on one core for the whole window is seen as about one busy core."""
    import subprocess
    import sys
    import time

    from lubelink.sweep import local

    if local._cpu_sample() is None:
        pytest.skip("no /proc/stat")
    spin = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    try:
        time.sleep(0.2)
        monkeypatch.setattr(local, "_MARK", local._cpu_sample())
        time.sleep(0.6)
        busy = local.free_cores()[1]
    finally:
        spin.kill()
        spin.wait()
    # idle, the child alone: about 1; loaded by others too: up to every core
    assert 0.7 <= busy <= local._cpu_count() + 0.05

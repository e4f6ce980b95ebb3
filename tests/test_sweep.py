"""Parameter sweeps on Dask: the sweep file, a real LocalCluster, failing points, kill and resume.

The cluster tests share one ``LocalCluster(n_workers=2, processes=True, threads_per_worker=1)``
and one reference sweep of 48 tiny simulations (0.1 s of motion, 5 output points); with a
water-like viscosity the film breaks down at the higher crank speeds.
"""

import contextlib
import json
import math
import os
import signal
import subprocess
import sys
import threading
import time
import tomllib
from pathlib import Path

import numpy as np
import pytest

import lubelink
from lubelink import ConfigError
from lubelink.cli import main as cli_main
from lubelink.sweep import (SweepError, _compute_point, _empty_record, _Store, _TaskOptions, load_sweep,
                            point_config, read_sweep, run_sweep, summarise)

distributed = pytest.importorskip("distributed")
pytest.importorskip("zarr")
xr = pytest.importorskip("xarray")

#: Tests on the shared cluster; ``pytest -n 2 --dist loadgroup`` keeps them in one process (one cluster).
on_cluster = pytest.mark.xdist_group("sweep-cluster")
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
TINY = {"solver.t_end": 0.1, "output.x_points": 5, "output.pad_points": 5}
QUANTITIES = ["peak_u2_mid", "impact_count", "first_impact_time", "peak_pressure", "min_film",
              "peak_film_force", "end_time", "regime"]

#: 2 x 6 x 4 = 48 points; with 1 mPa s the film breaks down from 25-30 rad/s on (failing points).
SWEEP_TOML = """
base = "paper"
description = "test sweep"

[set]
"solver.t_end" = 0.1
"output.x_points" = 5
"output.pad_points" = 5

[vary]
"film.viscosity" = [0.001, 0.1]
mechanism.crank_speed = { start = 20.0, stop = 45.0, num = 6 }
"film.clearance" = { start = 1e-3, stop = 3e-3, num = 4, scale = "log" }

[store]
quantities = ["peak_u2_mid", "impact_count", "first_impact_time", "peak_pressure", "min_film",
              "peak_film_force", "end_time", "regime"]
time_series = ["u2_mid"]
"""


def sweep_dict(**vary):
    return {"base": "paper", "set": dict(TINY), "vary": vary}


N = 48  # points of SWEEP_TOML


def stored(store):
    """Points committed to a store being written: journal lines plus the folded ``done`` mask."""
    import zarr

    journal = store / "journal.jsonl"
    n = journal.read_bytes().count(b"\n") if journal.exists() else 0
    try:
        return n + int(np.asarray(zarr.open_array(str(store / "done"), mode="r")[...]).sum())
    except Exception:  # not created yet
        return n


def ends(trace):
    """Flat indices of the points whose computation ended, in the order of the trace file."""
    if not Path(trace).exists():
        return []
    return [int(line.split()[4]) for line in Path(trace).read_text().splitlines() if line.split()[2] == "end"]


def same_results(a, b):
    """Equal stored results (wall_time and run history excepted) of the same sweep."""
    assert a.attrs["sweep_hash"] == b.attrs["sweep_hash"]
    xr.testing.assert_equal(a.drop_vars("wall_time"), b.drop_vars("wall_time"))


# ====================================================================== the sweep file
def test_lists_ranges_and_points_make_a_labelled_grid():
    sp = read_sweep({
        "base": "paper-impact",
        "set": {"solver": {"t_end": 0.5}},
        "vary": {"mechanism.crank_speed": {"start": 10, "stop": 60, "num": 6},
                 "film": {"viscosity": {"start": 1e-3, "stop": 1e-1, "num": 3, "scale": "log"}},
                 "beam.modes": [1, 3.0]},
        "points": [{"contact.restitution": 0.5, "film.model": "wedge"},
                   {"contact.restitution": 0.9, "film.model": "wedge+squeeze"}],
    })
    assert sp.dims == ("mechanism.crank_speed", "film.viscosity", "beam.modes", "point")
    assert sp.shape == (6, 3, 2, 2) and sp.size == 72
    assert sp.axes[0].values == (10.0, 20.0, 30.0, 40.0, 50.0, 60.0)
    assert sp.axes[1].values[0] == 1e-3 and sp.axes[1].values[2] == 1e-1
    assert sp.axes[1].values[1] == pytest.approx(1e-2, rel=1e-12) and sp.axes[1].scale == "log"
    assert sp.axes[2].values == (1, 3) and all(type(v) is int for v in sp.axes[2].values)
    assert sp.base_config.solver.t_end == 0.5 and sp.base_config.contact.law == "restitution"
    last = sp.overrides(sp.size - 1)
    assert last == {"mechanism.crank_speed": 60.0, "film.viscosity": 0.1, "beam.modes": 3,
                    "contact.restitution": 0.9, "film.model": "wedge+squeeze"}
    columns = read_sweep({"base": "paper-impact", "set": {"solver.t_end": 0.5},
                          "vary": {"mechanism.crank_speed": {"start": 10, "stop": 60, "num": 6},
                                   "film.viscosity": {"start": 1e-3, "stop": 1e-1, "num": 3, "scale": "log"},
                                   "beam.modes": [1, 3]},
                          "points": {"contact.restitution": [0.5, 0.9], "film.model": ["wedge", "wedge+squeeze"]}})
    assert columns.hash == sp.hash  # the same grid written as columns
    assert read_sweep({**sweep_dict(**{"film.viscosity": [0.1, 0.2]}), "description": "x"}).hash \
        == read_sweep(sweep_dict(**{"film.viscosity": [0.1, 0.2]})).hash
    assert read_sweep(sweep_dict(**{"film.viscosity": [0.1, 0.3]})).hash \
        != read_sweep(sweep_dict(**{"film.viscosity": [0.1, 0.2]})).hash


@pytest.mark.parametrize("data, needle", [
    ({"vary": {"film.viscositty": [0.1]}}, "did you mean 'film.viscosity'"),
    ({"vary": {"film.viscosity": {"start": 0.1, "stop": 1.0}}}, "vary.\"film.viscosity\": a range needs num"),
    ({"vary": {"film.viscosity": {"start": 0.0, "stop": 1.0, "num": 3, "scale": "log"}}}, "needs start > 0"),
    ({"vary": {"film.viscosity": {"start": 0.1, "stop": 1.0, "num": 3, "scale": "logarithmic"}}},
     "vary.\"film.viscosity\".scale = 'logarithmic'"),
    ({"vary": {"film.viscosity": [0.1, 0.1]}}, "appears twice"),
    ({"vary": {"film.viscosity": []}}, "empty list"),
    ({"vary": {"film.viscosity": ["thick"]}}, "vary.\"film.viscosity\"[0] = 'thick': must be a number"),
    ({"vary": {"beam.modes": {"start": 1, "stop": 2, "num": 3}}}, "beam.modes is an integer"),
    ({"vary": {"mechanism.gravity": [[0, -9.81]]}}, "cannot be swept"),
    ({"vary": {"film.viscosity": [0.1]}, "set": {"film.viscosity": 0.2}}, "also given in [set]"),
    ({"vary": {"film.viscosity": [0.1]}, "store": {"quantities": ["peak_u2"]}}, "did you mean 'peak_u2_mid'"),
    ({"vary": {"solver.t_end": [0.1, 0.2]}, "store": {"time_series": ["u2_mid"]}}, "no common time axis"),
    ({"vary": {"beam.modes": [1, 2]}, "store": {"time_series": ["q"]}}, "q needs beam.modes fixed"),
    ({"vary": {"film.viscosity": [0.1]}, "stor": {}}, "unknown key 'stor' (did you mean 'store'?)"),
    ({"base": "papper", "vary": {"film.viscosity": [0.1]}}, "did you mean 'paper'"),
    ({"vary": {"film.viscosity": [0.1]}, "set": {"beam.modes": 0}}, "beam.modes = 0"),
    ({"points": [{"film.viscosity": 0.1}, {"film.clearance": 1e-3}]}, "every point must set the same"),
    ({}, "nothing to sweep"),
])
def test_bad_sweep_files_are_refused_naming_the_key(data, needle):
    with pytest.raises(ConfigError) as err:
        read_sweep(data)
    assert any(needle in p for p in err.value.problems), err.value.problems


def test_every_invalid_point_is_reported_before_anything_runs(tmp_path):
    # contact.min_film must stay below film.clearance / 2: 2 of the 6 points break that rule.
    data = sweep_dict(**{"contact.min_film": [1e-6, 4e-3], "film.clearance": [3e-3, 6e-3, 1e-2]})
    with pytest.raises(ConfigError) as err:
        run_sweep(data, tmp_path / "r.zarr")
    text = "\n".join(err.value.problems)
    assert "contact.min_film=0.004, film.clearance=0.003" in text and "2 of 6 points are invalid" in text
    assert not (tmp_path / "r.zarr").exists()


def test_summary_quantities_of_one_run():
    ds = lubelink.simulate("paper-impact", set={"solver.t_end": 0.7, "output.x_points": 5,
                                                "film.clearance": 5e-3, "film.viscosity": 1e-3})
    s = summarise(ds, ("peak_u2_mid", "impact_count", "first_impact_time", "peak_pressure", "min_film",
                       "peak_film_force", "end_time", "nfev", "impact_times"), max_impacts=4)
    assert s["status"] == "complete" and s["impact_count"] == ds.attrs["impact_count"] >= 2
    assert s["peak_u2_mid"] == float(np.abs(ds.u2_mid).max())
    assert s["first_impact_time"] == float(ds.impact_time[0])
    assert s["impact_times"][:2] == [float(t) for t in ds.impact_time[:2]]
    assert len(s["impact_times"]) == 4
    assert s["peak_pressure"] == float(np.abs(ds.pressure).max())
    assert s["min_film"] == float(ds.film_min.min()) and s["end_time"] == float(ds.time[-1]) > 0.69
    dry = summarise(lubelink.simulate("paper-dry", set={"solver.t_end": 0.05, "output.x_points": 5}))
    assert math.isnan(dry["peak_pressure"]) and math.isnan(dry["first_impact_time"])


def test_the_regime_reads_contact_then_the_asperities_share_of_the_film_force():
    """``regime``: contact before anything else (an impact, a contact force, a breakdown), ``dry``
    without a film, ``mixed`` only above :data:`MIXED_SHARE` of the film's peak force."""
    import xarray as xr

    from lubelink.sweep.compute import MIXED_SHARE, regime

    def run(status="complete", impacts=0, **series):
        return xr.Dataset({k: ("time", np.asarray(v, float)) for k, v in series.items()},
                          attrs={"status": status, "impact_count": impacts})

    assert regime(run()) == "dry"
    assert regime(run(film_force=[0.0, -10.0])) == "full film"
    assert regime(run(film_force=[0.0, -10.0], asperity_force=[0.0, 10 * MIXED_SHARE])) == "full film"
    assert regime(run(film_force=[0.0, -10.0], asperity_force=[0.0, 10.5 * MIXED_SHARE])) == "mixed"
    assert regime(run(film_force=[0.0, 0.0], asperity_force=[0.0, 1e-9])) == "mixed"
    assert regime(run(film_force=[1.0, 1.0], contact_force=[0.0, 1e-6])) == "contact"
    assert regime(run(impacts=1)) == "contact"
    assert regime(run("film_breakdown", film_force=[1.0])) == "contact"


@pytest.mark.parametrize("base, overrides", [
    ("paper", {}),                                                        # full film
    ("paper", {"film.viscosity": 0.001, "mechanism.crank_speed": 40.0}),  # ends at a film breakdown
    ("guide-mixed", {"beam.modes": 3}),                                   # rough surfaces (a compiled kind)
    ("paper", {"film.cavitation": "reynolds", "beam.modes": 3}),          # Swift-Stieber, 3 modes
    ("paper-dry", {"contact.law": "compliant"}),                          # no film, compliant contact
    ("paper-impact", {"contact.law": "compliant"}),                       # impacts (compliant contact)
])
def test_the_fast_reductions_equal_the_results_path(base, overrides):
    """Second method: each quantity a sweep reduces from the run's arrays (``reduce_run``) equals the
    summary of the run's results (``collect`` then ``summarise``), for every quantity it covers."""
    from lubelink.config import resolve
    from lubelink.results import collect
    from lubelink.simulate import run
    from lubelink.sweep.compute import FAST, fast_reducible, reduce_run

    config = resolve(base, {**TINY, "solver.t_end": 0.3, **overrides})
    result = run(config)
    opts = _TaskOptions(tuple(sorted(FAST)), (), 4, 0, config.solver.output_step, "t")
    assert fast_reducible(result.model, opts)
    fast = reduce_run(result, opts.quantities, opts.max_impacts)
    slow = summarise(collect(result), opts.quantities, opts.max_impacts)
    assert fast.keys() == slow.keys()
    for name, want in slow.items():
        got = fast[name]
        if isinstance(want, float) and math.isnan(want):
            assert math.isnan(got), name
        elif isinstance(want, list):
            np.testing.assert_array_equal(got, want, err_msg=name)
        else:
            assert got == want, name
    if base == "paper-impact":
        assert fast["impact_count"] > 0 or fast["peak_film_force"] > 0  # (a case with contact)


def test_points_that_store_series_or_other_quantities_keep_the_results_path():
    from lubelink.config import resolve
    from lubelink.simulate import run
    from lubelink.sweep.compute import fast_reducible

    model = run(resolve("paper", TINY)).model
    opts = _TaskOptions(("peak_u2_mid",), (), 4, 0, 1e-3, "t")
    assert fast_reducible(model, opts)
    assert not fast_reducible(model, opts._replace(time_series=("u2_mid",)) if hasattr(opts, "_replace")
                              else _TaskOptions(("peak_u2_mid",), ("u2_mid",), 4, 101, 1e-3, "t"))
    assert not fast_reducible(model, _TaskOptions(("peak_u2_mid", "regime"), (), 4, 0, 1e-3, "t"))
    assert not fast_reducible(run(resolve("paper-impact", TINY)).model, opts)  # restitution: penetration check

def test_a_point_that_raises_is_a_failed_record():
    opts = _TaskOptions(("peak_u2_mid", "impact_count"), (), 3, 0, 1e-3, "x")
    record, series = _compute_point(0, None, opts)  # no configuration: the simulation raises
    assert record["status"] == "error" and "AttributeError" in record["message"] and series == {}
    assert math.isnan(record["peak_u2_mid"]) and record["impact_count"] == -1


def test_journal_commits_points_and_a_torn_line_is_ignored(tmp_path):
    sp = read_sweep(sweep_dict(**{"film.viscosity": [0.1, 0.2, 0.3]}))
    st = _Store.open(tmp_path / "j.zarr", sp)
    record = _empty_record(sp.quantities, sp.max_impacts, "complete", "ok", 1.0)
    st.write([(2, {**record, "peak_u2_mid": 1.5e-3, "impact_count": 4}, {})])
    with pytest.raises(SweepError, match="being written by another sweep"):
        _Store.open(tmp_path / "j.zarr", sp)
    with open(tmp_path / "j.zarr" / "journal.jsonl", "a") as f:
        f.write('{"i": 0, "status": "compl')  # a kill in the middle of a line
    ds = load_sweep(tmp_path / "j.zarr")  # reads the journal without folding it
    assert ds.done.values.tolist() == [False, False, True]
    assert ds.peak_u2_mid.values[2] == 1.5e-3 and ds.impact_count.values.tolist() == [-1, -1, 4]
    st.close()
    other = read_sweep(sweep_dict(**{"film.viscosity": [0.1, 0.2, 0.4]}))
    with pytest.raises(SweepError, match="holds a different sweep"):
        _Store.open(tmp_path / "j.zarr", other)
    again = _Store.open(tmp_path / "j.zarr", sp)  # the lock of a closed writer is free
    assert again.state()[0].tolist() == [False, False, True]
    again.close()


SPATIAL_SWEEP = {"base": "spatial-slider-crank", "set": {"solver.t_end": 0.02, "output.x_points": 5, "beam.modes": 2},
                 "vary": {"mechanism.crank_tilt": [0.0, 0.1, 0.2]}}


def test_a_spatial_sweep_stores_the_out_of_plane_twins():
    """With spatial points, peak_u2_mid brings peak_u3_mid and peak_axial, the series u2_mid u3_mid; a planar
    sweep stores what it stored before; a sweep over beam.model counts as spatial."""
    sp = read_sweep(SPATIAL_SWEEP)
    assert sp.quantities[:3] == ("peak_u2_mid", "peak_u3_mid", "peak_axial")
    asked = read_sweep({**SPATIAL_SWEEP, "store": {"quantities": ["min_film", "peak_u2_mid"],
                                                   "time_series": ["u2_mid", "u2", "x_star"]}})
    assert asked.quantities == ("min_film", "peak_u2_mid", "peak_u3_mid", "peak_axial")
    assert asked.time_series == ("u2_mid", "u3_mid", "u2", "u3", "x_star")
    assert read_sweep(tomllib.loads(asked.to_toml())).hash == asked.hash  # the stored definition reads back alike
    planar = read_sweep(sweep_dict(**{"film.viscosity": [0.1, 0.2]}))
    assert "peak_u3_mid" not in planar.quantities and planar.quantities == lubelink.sweep.DEFAULT_QUANTITIES
    both = read_sweep({"base": "paper", "set": dict(TINY), "vary": {"beam.model": ["planar", "spatial"]}})
    assert "peak_u3_mid" in both.quantities
    with pytest.raises(ConfigError, match="store.time_series: u3 needs mechanism.rod_length fixed"):
        read_sweep({**SPATIAL_SWEEP, "vary": {"mechanism.rod_length": [1.0, 1.1]}, "store": {"time_series": ["u3"]}})


def test_a_point_summarises_the_engineering_outputs_as_the_results_hold_them():
    ds = lubelink.simulate("paper", set={"solver.t_end": 0.05, "output.x_points": 5})
    names = ("peak_stress", "peak_film_friction", "mean_film_power_loss", "peak_crank_pin_force",
             "peak_slider_pin_force")
    s = summarise(ds, names)
    assert s["peak_stress"] == float(ds["bending_stress"].max())
    assert s["peak_film_friction"] == float(np.abs(ds["film_friction"]).max())
    assert s["mean_film_power_loss"] == pytest.approx(float(ds["film_power_loss"].mean()), rel=1e-12)
    assert s["peak_crank_pin_force"] == float(np.hypot(ds["crank_pin_force_X"], ds["crank_pin_force_Y"]).max())
    assert s["peak_slider_pin_force"] == float(np.abs(ds["slider_pin_force"]).max())
    dry = summarise(lubelink.simulate("paper-dry", set={"solver.t_end": 0.05, "output.x_points": 5}), names)
    assert np.isnan(dry["peak_film_friction"]) and np.isfinite(dry["peak_crank_pin_force"])


def test_a_spatial_point_summarises_u3_and_u1():
    sp = read_sweep({**SPATIAL_SWEEP, "store": {"time_series": ["u2_mid", "u1"]}})
    config = sp.point_config(2)
    opts = _TaskOptions(sp.quantities, sp.time_series, sp.max_impacts, 21, 1e-3, "s")
    record, series = _compute_point(2, config, opts)
    one = lubelink.simulate(config)
    assert record["status"] == "complete" and record["peak_u2_mid"] == float(np.abs(one.u2_mid).max())
    assert record["peak_u3_mid"] == float(np.abs(one.u3_mid).max()) > 1e-5  # the tilted crank's u3
    assert record["peak_axial"] == float(np.abs(one.u1).max()) > 0.0
    np.testing.assert_array_equal(series["u3_mid"], one.u3_mid.values)
    np.testing.assert_array_equal(series["u1"], one.u1.values)
    planar = summarise(lubelink.simulate("paper-dry", set={"solver.t_end": 0.01, "output.x_points": 5}),
                       ("peak_u2_mid", "peak_u3_mid", "peak_axial"))
    assert planar["peak_u2_mid"] > 0.0 and math.isnan(planar["peak_u3_mid"]) and math.isnan(planar["peak_axial"])


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("sweep*.toml")), ids=lambda p: p.name)
def test_examples_are_valid_sweeps(path):
    sp = read_sweep(path)
    configs, invalid = sp.point_configs()
    assert not invalid and len(configs) == sp.size


# ====================================================================== on a real LocalCluster
@pytest.fixture(scope="module")
def client():
    import dask
    from distributed import Client, LocalCluster

    from lubelink.sweep import LOCAL_CLUSTER_CONFIG

    with dask.config.set(LOCAL_CLUSTER_CONFIG), \
            LocalCluster(n_workers=2, processes=True, threads_per_worker=1, dashboard_address=":0") as cluster, \
            Client(cluster) as c:
        yield c


_ENV_PROBE = """
import logging, os, dask
from distributed import Client, LocalCluster
from lubelink.sweep import LOCAL_CLUSTER_CONFIG
if __name__ == "__main__":
    with dask.config.set(LOCAL_CLUSTER_CONFIG), LocalCluster(n_workers=1, processes=True, threads_per_worker=1,
                                                          dashboard_address=":0", silence_logs=logging.ERROR) as cl, \\
            Client(cl) as c:
        print(list(c.run(os.environ.get, "MALLOC_TRIM_THRESHOLD_").values()),
              list(c.run(os.environ.get, "OMP_NUM_THREADS").values()))
"""


@on_cluster
def test_the_sweeps_workers_keep_glibcs_malloc_thresholds(tmp_path):
    """Dask's nanny starts workers with ``MALLOC_TRIM_THRESHOLD_=65536``, which made a point 5-10 %
    slower (glibc maps every array above 128 KiB afresh); the sweep's local cluster unsets it and
    keeps Dask's other variables (a fresh process: an earlier cluster leaves it in this one's
    environment, which workers inherit)."""
    probe = tmp_path / "probe.py"
    probe.write_text(_ENV_PROBE)
    env = {k: v for k, v in os.environ.items() if k != "MALLOC_TRIM_THRESHOLD_"}
    out = subprocess.run([sys.executable, str(probe)], capture_output=True, text=True, env=env, timeout=120)
    assert out.stdout.split("\n")[-2] == "[None] ['1']", out.stdout + out.stderr


_PLAIN_SCRIPT = """
import os

import lubelink

with open("ran.log", "a") as f:  # once per run of this file
    f.write(f"{os.getpid()}\\n")
ds = lubelink.run_sweep({"base": "paper", "set": {"solver.t_end": 0.05, "output.x_points": 5, "output.pad_points": 5},
                         "vary": {"film.viscosity": [0.05, 0.1]}}, "s.zarr", workers=2, progress=False,
                        executor=EXECUTOR)
print("stored", int(ds.done.sum()), "of", ds.done.size)
"""


@pytest.mark.parametrize("how, executor", [("script", "dask"), ("module", "dask"), ("script", "processes")])
def test_run_sweep_from_a_script_without_a_main_guard_runs_the_script_once(tmp_path, how, executor):
    """Issue 35: a script (or a module run with -m) calling run_sweep at its top level, without
    ``if __name__ == "__main__":``, ran again in each worker that multiprocessing spawned (there
    its sweep found the store in use, and the workers failed to start). The workers now leave the
    script alone: it runs once, and the sweep completes on its two workers (of a local Dask
    cluster, or of the process pool)."""
    (tmp_path / "plain.py").write_text(_PLAIN_SCRIPT.replace("EXECUTOR", repr(executor)))
    package = str(Path(lubelink.__file__).resolve().parents[1])  # this lubelink, wherever the test runs
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([package, str(tmp_path)])}
    command = [sys.executable, "plain.py"] if how == "script" else [sys.executable, "-m", "plain"]
    out = subprocess.run(command, cwd=tmp_path, capture_output=True, text=True, env=env, timeout=300)
    assert out.returncode == 0, out.stderr[-3000:]
    assert out.stdout.strip() == "stored 2 of 2"
    assert len((tmp_path / "ran.log").read_text().split()) == 1


@pytest.fixture(scope="module")
def reference(client, tmp_path_factory):
    """The 48-point sweep, uninterrupted, on the shared cluster."""
    folder = tmp_path_factory.mktemp("reference")
    (folder / "sweep.toml").write_text(SWEEP_TOML)
    trace = folder / "trace.log"
    ds = run_sweep(folder / "sweep.toml", folder / "ref.zarr", client=client, progress=False, trace=trace)
    return folder, ds, trace


@on_cluster
def test_sweep_on_a_local_cluster_stores_every_point_once(reference):
    folder, ds, trace = reference
    assert ds.sizes == {"film.viscosity": 2, "mechanism.crank_speed": 6, "film.clearance": 4, "time": 101}
    assert bool(ds.done.all())
    assert sorted(ends(trace)) == list(range(N))  # each point computed exactly once
    assert ds["mechanism.crank_speed"].attrs["units"] == "rad s-1" and ds.peak_pressure.attrs["units"] == "Pa"
    assert ds["film.clearance"].attrs["scale"] == "log"
    again = run_sweep(folder / "sweep.toml", folder / "ref.zarr", progress=False, trace=trace)  # resume: nothing left
    assert sorted(ends(trace)) == list(range(N))
    same_results(again, ds)


@on_cluster
def test_results_match_the_same_points_run_in_process(reference):
    _, ds, _ = reference
    for mu, w, H in [(0.001, 20.0, 1e-3), (0.001, 40.0, 3e-3), (0.1, 30.0, 1e-3), (0.1, 45.0, 3e-3)]:
        one = lubelink.simulate("paper", set={**TINY, "film.viscosity": mu, "mechanism.crank_speed": w,
                                              "film.clearance": H})
        expected = summarise(one, QUANTITIES)
        point = ds.sel({"film.viscosity": mu, "mechanism.crank_speed": w, "film.clearance": H})
        for name in QUANTITIES + ["status", "message"]:
            got, want = point[name].item(), expected[name]
            assert got == want or (isinstance(want, float) and math.isnan(want) and math.isnan(got)), name
        np.testing.assert_array_equal(point.u2_mid.values[: one.sizes["time"]], one.u2_mid.values)
        assert point_config(ds, {"film.viscosity": mu, "mechanism.crank_speed": w, "film.clearance": H}) \
            == lubelink.config.resolve(lubelink.results.config_of(one))


@on_cluster
def test_failing_points_are_recorded_and_the_others_complete(reference):
    _, ds, _ = reference
    water, oil = ds.sel({"film.viscosity": 0.001}), ds.sel({"film.viscosity": 0.1})
    assert (oil.status == "complete").all() and (water.status.sel({"mechanism.crank_speed": 20.0}) == "complete").all()
    fast = water.sel({"mechanism.crank_speed": [30.0, 35.0, 40.0, 45.0]})
    assert (fast.status == "film_breakdown").all()
    assert all("contact.min_film" in m for m in fast.message.values.reshape(-1))
    broken = fast.sel({"mechanism.crank_speed": 40.0, "film.clearance": 1e-3})
    assert broken.end_time.item() < 0.1 and np.isnan(broken.u2_mid.values[-1])  # partial series kept
    assert np.isfinite(broken.u2_mid.values[0]) and np.isfinite(broken.peak_u2_mid.item())
    assert (fast.regime == "contact").all() and (oil.regime == "full film").all()


@on_cluster
def test_a_spatial_sweep_over_the_crank_tilt_on_the_cluster(client, tmp_path):
    ds = run_sweep({**SPATIAL_SWEEP, "store": {"time_series": ["u2_mid"]}}, tmp_path / "spatial.zarr", client=client,
                   progress=False)
    assert (ds.status == "complete").all() and ds.u3_mid.attrs["units"] == "m"
    assert ds.peak_u3_mid.attrs["units"] == "m" and ds.peak_axial.attrs["units"] == "m"
    for tilt in (0.0, 0.2):
        one = lubelink.simulate("spatial-slider-crank", set={**SPATIAL_SWEEP["set"], "mechanism.crank_tilt": tilt})
        point = ds.sel({"mechanism.crank_tilt": tilt})
        assert point.peak_u3_mid.item() == float(np.abs(one.u3_mid).max())
        np.testing.assert_array_equal(point.u3_mid.values, one.u3_mid.values)
    assert np.ptp(ds.peak_u3_mid.values) > 0.01 * ds.peak_u3_mid.values.max()  # the tilt changes u3


@on_cluster
def test_timeouts_netcdf_output_resume_and_retry(client, tmp_path):
    data = {"base": "paper", "set": dict(TINY),
            # max_step: more steps than the driver's first call takes, after which the budget is checked
            "points": [{"solver.max_wall_time": 1e-6, "solver.max_step": 1e-4},
                       {"solver.max_wall_time": 100.0, "solver.max_step": 1e-4}]}
    out, trace = tmp_path / "points.nc", tmp_path / "trace.log"
    ds = run_sweep(data, out, client=client, progress=False, trace=trace)
    assert out.is_file() and not (tmp_path / "points.nc.partial.zarr").exists()
    assert ds.status.values.tolist() == ["timeout", "complete"] and "max_wall_time" in ds.message.values[0]
    assert ds["solver.max_wall_time"].dims == ("point",)
    same_results(load_sweep(out), ds)
    assert sorted(ends(trace)) == [0, 1]
    run_sweep(data, out, client=client, progress=False, trace=trace)  # resumes from the NetCDF file
    assert sorted(ends(trace)) == [0, 1]
    retried = run_sweep(data, out, client=client, progress=False, trace=trace, retry_failed=True)
    assert sorted(ends(trace)) == [0, 0, 1]  # only the failed point again
    assert retried.status.values[1] == "complete"


#: The command-line options of each execution path: (the killed run's, the resumed run's).
PATHS = {"serial": (["--executor", "serial"], ["--executor", "serial"]),
         "processes": (["--executor", "processes", "--workers", "2"], ["--executor", "processes", "--workers", "2"]),
         "auto": (["--workers", "2"], ["--workers", "2"]),  # pilot points here, then here or on a pool
         "dask": (["--workers", "2", "--executor", "dask"], None)}  # resumed on the shared cluster (--scheduler)


#: The sweep the kill test interrupts: SWEEP_TOML's points 10x longer. With 0.1 s a point (a few ms of work) the
#: batches of about ``task_seconds`` stored the whole sweep between two polls of the store on a quiet machine.
KILL_TOML = SWEEP_TOML.replace('"solver.t_end" = 0.1', '"solver.t_end" = 1.0')


@pytest.fixture(scope="module")
def kill_reference(tmp_path_factory):
    """KILL_TOML's sweep, uninterrupted, in this process."""
    folder = tmp_path_factory.mktemp("kill-reference")
    (folder / "sweep.toml").write_text(KILL_TOML)
    return run_sweep(folder / "sweep.toml", folder / "ref.zarr", executor="serial", progress=False)


@on_cluster
@pytest.mark.parametrize("path", list(PATHS))
def test_kill_mid_sweep_then_resume_equals_an_uninterrupted_sweep(kill_reference, client, tmp_path, path):
    """SIGKILL the whole CLI process group (the sweep's process and its workers, or its Dask scheduler
    and workers) once points are stored, then resume with the CLI: on the same path, and for Dask on
    the shared cluster (--scheduler). Nothing is lost and no stored point is computed again."""
    ref = kill_reference
    (tmp_path / "sweep.toml").write_text(KILL_TOML)
    store, first, second = tmp_path / "k.zarr", tmp_path / "first.log", tmp_path / "second.log"
    stored(store)  # (imports zarr now, not while the sweep runs)
    cmd = [sys.executable, "-m", "lubelink", "sweep", "sweep.toml", "-o", "k.zarr", "-q"]
    killed_args, resumed_args = PATHS[path]
    proc = subprocess.Popen(cmd + killed_args + ["--trace", str(first)], cwd=tmp_path, start_new_session=True,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 180
    while proc.poll() is None and time.monotonic() < deadline and stored(store) < 3:
        time.sleep(0.005)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    before = load_sweep(store)
    done_before = set(np.flatnonzero(before.done.values.reshape(-1)).tolist())
    assert 3 <= len(done_before) < N, "the sweep was not interrupted midway"
    assert set(ends(first)) >= done_before

    address = client.scheduler.address
    r = subprocess.run(cmd + (resumed_args or ["--scheduler", address]) + ["--trace", str(second)], cwd=tmp_path,
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    resumed = load_sweep(store)
    same_results(resumed, ref)
    again = ends(second)
    assert len(again) == len(set(again))  # nothing computed twice in the resumed run
    assert not set(again) & done_before  # no stored point computed again
    assert set(again) | done_before == set(range(N))  # none lost
    # Points computed in the killed run but not stored (their task was still running, or its result
    # on its way to the client) are computed once more; no point more than that.
    assert max((ends(first) + again).count(i) for i in range(N)) <= 2
    runs = json.loads(resumed.attrs["runs"])
    assert runs[-1]["computed"] == N - len(done_before) and runs[-1]["resumed"] == len(done_before)
    assert runs[-1]["executor"] == path or path == "auto" and runs[-1]["executor"] in ("serial", "processes")
    if path == "dask":
        assert runs[-1]["scheduler"] == f"Dask scheduler {address}"


@pytest.mark.parametrize("path", list(PATHS))
def test_ctrl_c_to_the_process_group_is_one_line_from_the_client(tmp_path, path):
    """Ctrl-C at a terminal reaches every process of the group: the workers of the sweep's own pool or
    local cluster leave it to the client (no traceback of theirs), which says one line and exits 130."""
    (tmp_path / "slow.toml").write_text('base = "paper-dry"\n[set]\n"solver.t_end" = 1.0\n'
                                        '[vary]\n"solver.max_step" = [1e-6, 1.1e-6, 1.2e-6, 1.3e-6]\n')
    proc = subprocess.Popen([sys.executable, "-m", "lubelink", "sweep", "slow.toml", "-o", "s.zarr", *PATHS[path][0]],
                            cwd=tmp_path, start_new_session=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    end = time.monotonic() + 120
    while proc.poll() is None and not (tmp_path / "s.zarr").exists() and time.monotonic() < end:
        time.sleep(0.05)
    time.sleep(1.0)  # the workers are computing the first points
    os.killpg(proc.pid, signal.SIGINT)
    try:
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 130, err
    assert "Traceback" not in err and err.strip().splitlines()[-1].startswith("lubelink: interrupted"), err


@on_cluster
def test_a_worker_killed_mid_point_is_rescheduled_and_nothing_is_lost(client, tmp_path):
    # points of about a second each (7 modes at a tight tolerance), so that the kill, polled every
    # 10 ms, lands while the point computes
    data = sweep_dict(**{"mechanism.crank_speed": [20.0, 25.0, 30.0, 35.0]})
    data["set"].update({"beam.modes": 7, "solver.method": "DOP853", "solver.rtol": 1e-12, "solver.atol": 1e-16,
                        "solver.t_end": 0.5})
    trace = tmp_path / "trace.log"
    workers = set(client.run(os.getpid).values())
    killed = []

    def kill_first_worker_that_starts_a_point():
        deadline = time.monotonic() + 120
        while not killed and time.monotonic() < deadline:
            lines = trace.read_text().splitlines() if trace.exists() else []
            for line in lines:
                _, pid, event, _, flat = line.split()
                if event == "start" and int(pid) in workers:
                    os.kill(int(pid), signal.SIGKILL)  # its nanny starts a new worker process
                    killed.append(int(flat))
                    break
            time.sleep(0.01)

    killer = threading.Thread(target=kill_first_worker_that_starts_a_point)
    killer.start()
    ds = run_sweep(data, tmp_path / "w.zarr", client=client, progress=False, trace=trace)
    killer.join()
    assert killed and bool(ds.done.all()) and (ds.status == "complete").all()
    assert sorted(ends(trace)) == [0, 1, 2, 3]  # every point stored once, the killed one included
    starts = [line for line in trace.read_text().splitlines() if line.split()[2] == "start"]
    assert len(starts) > 4  # the killed computation was started again elsewhere




def test_a_pool_worker_killed_mid_point_is_computed_again_and_nothing_is_lost(tmp_path):
    """The process pool's counterpart of Dask's rescheduling: a worker killed while it computes breaks
    the pool; the points in flight are computed again on a new pool, every point stored once."""
    data = sweep_dict(**{"mechanism.crank_speed": [20.0, 25.0, 30.0, 35.0]})
    data["set"].update({"beam.modes": 7, "solver.method": "DOP853", "solver.rtol": 1e-12, "solver.atol": 1e-16,
                        "solver.t_end": 0.5})
    trace = tmp_path / "trace.log"
    killed = []

    def kill_first_worker_that_starts_a_point():
        deadline = time.monotonic() + 120
        while not killed and time.monotonic() < deadline:
            for line in (trace.read_text().splitlines() if trace.exists() else []):
                _, pid, event, _, flat = line.split()
                if event == "start" and int(pid) != os.getpid():
                    os.kill(int(pid), signal.SIGKILL)
                    killed.append(int(flat))
                    break
            time.sleep(0.01)

    killer = threading.Thread(target=kill_first_worker_that_starts_a_point)
    killer.start()
    ds = run_sweep(data, tmp_path / "w.zarr", executor="processes", workers=2, progress=False, trace=trace)
    killer.join()
    assert killed and bool(ds.done.all()) and (ds.status == "complete").all()
    assert sorted(ends(trace)) == [0, 1, 2, 3]  # every point stored once, the killed one included
    starts = [line for line in trace.read_text().splitlines() if line.split()[2] == "start"]
    assert len(starts) > 4 and json.loads(ds.attrs["runs"])[-1]["executor"] == "processes"


def test_a_point_that_kills_its_worker_every_time_is_stored_as_worker_died(tmp_path, monkeypatch):
    """A point that kills the pool's worker 3 times alone is stored as ``worker_died``; the others complete."""
    from lubelink.sweep import local

    calls = []

    class Dying:  # a pool whose worker dies on point 1 (no process is harmed)
        def __init__(self, workers):
            from concurrent.futures import ThreadPoolExecutor

            self.threads = ThreadPoolExecutor(1)

        def submit(self, fn, flats, *args):
            from concurrent.futures import Future
            from concurrent.futures.process import BrokenProcessPool

            calls.append(list(flats))
            if 1 in flats:
                fut = Future()
                fut.set_exception(BrokenProcessPool("a worker died"))
                return fut
            return self.threads.submit(fn, flats, *args)

        def shutdown(self, wait=True, cancel_futures=False):
            self.threads.shutdown(wait=wait)

    monkeypatch.setattr(local, "_new_pool", Dying)
    ds = run_sweep(sweep_dict(**{"film.viscosity": [0.05, 0.1, 0.2]}), tmp_path / "d.zarr", executor="processes",
                   workers=2, progress=False, task_seconds=0)
    assert ds.status.values.tolist() == ["complete", "worker_died", "complete"]
    assert "3 times" in ds.message.values[1]
    # once beside other tasks (which break with it, then complete alone), then alone DEATHS times
    assert sum(c == [1] for c in calls) == 1 + local.DEATHS


def test_auto_runs_a_short_sweep_here_a_longer_on_a_pool_and_dask_where_given(monkeypatch):
    from lubelink.sweep import execute

    sp = read_sweep(sweep_dict(**{"film.viscosity": [0.05, 0.1]}))
    one = execute.serial_seconds(sp, 1)
    assert 0 < one < 1 and execute.serial_seconds(sp, 100) == pytest.approx(100 * one)
    monkeypatch.setattr(execute, "SERIAL_SECONDS", 10 * one)
    assert execute.choose_executor(sp, 9, workers=2)[:2] == ("serial", 1)
    assert execute.choose_executor(sp, 11, workers=2)[:2] == ("processes", 2)
    assert execute.choose_executor(sp, 11, workers=1)[:2] == ("serial", 1)
    assert execute.choose_executor(sp, 11, workers=2, dask_given=True)[0] == "dask"
    monkeypatch.setattr(execute, "DASK_SECONDS", 20 * one)
    kind, n, line = execute.choose_executor(sp, 21, workers=2)
    assert (kind, n) == ("dask", 2) and line.startswith("21 point(s) on a Dask LocalCluster of 2 workers")
    assert execute.choose_executor(sp, 1000, "serial")[:2] == ("serial", 1)
    for bad, needle in [({"executor": "threads"}, "must be one of auto, serial, processes, dask"),
                        ({"executor": "serial", "workers": 2}, "needs 'processes' or 'dask'"),
                        ({"executor": "processes", "scheduler": "tcp://127.0.0.1:9"}, "needs executor 'dask'")]:
        with pytest.raises(SweepError, match=needle):
            run_sweep(sp, "never.zarr", progress=False, **bad)


def test_auto_times_pilot_points_here_then_runs_the_rest_where_they_end_sooner(monkeypatch, tmp_path, capsys):
    """The pilot's points are stored as they end (done work), and its timing chooses: a pool that would take
    forever to start leaves the rest here, one that starts at once takes them; the same results either way."""
    from lubelink.sweep import execute

    sp = read_sweep(sweep_dict(**{"film.viscosity": [0.05, 0.1, 0.15, 0.2],
                                  "mechanism.crank_speed": [20.0, 30.0, 40.0]}))
    assert execute.wants_pilot(sp, sp.size, workers=2)  # kernels cached by the test session's warm-up
    assert not execute.wants_pilot(sp, sp.size, workers=1) and not execute.wants_pilot(sp, sp.size, "serial", 2)
    assert not execute.wants_pilot(sp, execute.PILOT_POINTS + 1, workers=2)
    monkeypatch.setattr(execute, "PILOT_POINTS", 3)
    monkeypatch.setattr(execute, "PILOT_SECONDS", math.inf)
    reference = run_sweep(sp, tmp_path / "ref.zarr", executor="serial", progress=False)
    capsys.readouterr()
    for pool_start, kind in [(math.inf, "serial"), (-math.inf, "processes")]:
        monkeypatch.setattr(execute, "POOL_START", pool_start)
        ds = run_sweep(sp, tmp_path / f"{kind}.zarr", workers=2, progress=True)
        line = [x for x in capsys.readouterr().err.splitlines() if x.startswith("lubelink sweep: ")]
        assert len(line) == 1 and "3 point(s) here took" in line[0], line
        assert line[0].startswith(f"lubelink sweep: {sp.size - 4} point(s) "), line  # after the first and 3 timed
        runs = json.loads(ds.attrs["runs"])
        assert runs[-1]["executor"] == kind and runs[-1]["computed"] == sp.size and runs[-1]["resumed"] == 0
        same_results(ds, reference)


def test_a_timed_pilot_chooses_by_the_time_each_side_would_take(monkeypatch):
    from lubelink.sweep import execute

    sp = read_sweep(sweep_dict(**{"film.viscosity": [0.05, 0.1]}))
    monkeypatch.setattr(execute, "free_cores", lambda: (2.0, 0.0))
    assert execute.choose_executor(sp, 400, workers=2, timed=(8, 0.01, 1.0))[:2] == ("processes", 2)  # 4 s, 3 s
    kind, n, line = execute.choose_executor(sp, 100, workers=2, timed=(8, 0.01, 1.0))  # 1 s here, 1.5 s on 2
    assert (kind, n) == ("serial", 1)
    assert line == ("100 point(s) in this process (8 point(s) here took 10 ms each: about 1 s in this process, "
                    "1.5 s on 2 workers)")
    assert execute.choose_executor(sp, 400, workers=1, timed=(8, 0.01, 0.0))[:2] == ("serial", 1)
    monkeypatch.setattr(execute, "free_cores", lambda: (1.2, 0.8))  # 2 workers asked for, 1.2 cores free
    kind, n, line = execute.choose_executor(sp, 400, workers=2, timed=(8, 0.01, 1.0))  # 4 s here, 4.3 s there
    assert (kind, n) == ("serial", 1) and line.endswith("4.3 s on 2 workers (1.2 cores free))")
    assert execute.choose_executor(sp, 400, "processes", workers=2, timed=(8, 1.0, 99.0))[:2] == ("processes", 2)


def test_the_serial_path_stores_what_the_pool_stores(tmp_path, capsys):
    """The same sweep in this process and on a pool of 2 processes: the same results, the choice printed
    (one line) and recorded in the store's runs."""
    data = {**sweep_dict(**{"film.viscosity": [0.001, 0.1], "mechanism.crank_speed": [20.0, 40.0]}),
            "store": {"quantities": QUANTITIES, "time_series": ["u2_mid"]}}
    a = run_sweep(data, tmp_path / "a.zarr", executor="serial", progress=True)
    err = capsys.readouterr().err
    assert "lubelink sweep: 4 point(s) in this process (asked for)" in err
    b = run_sweep(data, tmp_path / "b.zarr", executor="processes", workers=2, progress=False)
    same_results(a, b)
    assert set(a.status.values.reshape(-1)) == {"complete", "film_breakdown"}
    assert [json.loads(x.attrs["runs"])[-1]["executor"] for x in (a, b)] == ["serial", "processes"]

# ====================================================================== interrupted, then called again in-process
@contextlib.contextmanager
def deadline(seconds, what):
    """Fail the test if the block takes longer than ``seconds`` (a hang fails instead of blocking CI):
    SIGALRM's handler raises in the main thread, where pytest runs the tests."""
    assert threading.current_thread() is threading.main_thread()

    def alarm(signum, frame):
        pytest.fail(f"{what}: still waiting after {seconds} s")

    previous = signal.signal(signal.SIGALRM, alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def left_on_scheduler(client, sp, wait=10.0):
    """Tasks of sweep ``sp`` that the scheduler still means to run (waiting, queued, processing),
    polled until there are none or ``wait`` [s] has passed."""
    prefix = f"lubelink-sweep-{sp.hash[:8]}-"

    def running(dask_scheduler, prefix=prefix):
        return sorted(str(k) for k, ts in dask_scheduler.tasks.items()
                      if str(k).startswith(prefix) and ts.state in ("waiting", "queued", "processing", "no-worker"))

    end = time.monotonic() + wait
    while (left := client.run_on_scheduler(running)) and time.monotonic() < end:
        time.sleep(0.05)
    return left


#: 12 points (more than the first window of tasks on 2 workers, so that it is refilled), 1 mode, dry.
RECALL = {"base": "paper-dry", "set": {**TINY, "beam.modes": 1},
          "vary": {"mechanism.crank_speed": [10.0 + 2.5 * i for i in range(12)]}}


@on_cluster
@pytest.mark.parametrize("reach, moment", [(reach, moment) for reach in ("scheduler", "client")
                                           for moment in ("first submit", "refill", "store write", "waiting")]
                         + [("workers", "store write"), ("serial", "store write"), ("processes", "store write")])
def test_a_sweep_interrupted_then_called_again_in_the_same_process(client, tmp_path, monkeypatch, reach, moment):
    """Ctrl-C in a notebook, then the same call again: it finishes, computes only the missing points,
    and the interrupted call leaves no task and no process behind. The sweep reaches Dask with a
    client of its own (``scheduler=``, as the CLI's --scheduler does), the user's ``client=``, or
    a LocalCluster of its own (``workers=``); the interruption comes while the first tasks are
    submitted, while the window is refilled, while a result is stored, or as SIGINT while the
    client waits for results."""
    import multiprocessing

    import distributed

    sp = read_sweep(RECALL)
    store, first, second = tmp_path / "r.zarr", tmp_path / "first.log", tmp_path / "second.log"
    reach_dask = {"scheduler": {"scheduler": client.scheduler.address}, "client": {"client": client},
                  "workers": {"workers": 1, "executor": "dask"}, "serial": {"executor": "serial"},
                  "processes": {"executor": "processes", "workers": 2}}[reach]
    processes = set(multiprocessing.active_children())
    interrupt = {"on": False}

    if moment in ("first submit", "refill"):
        calls, real_map = [], distributed.Client.map

        def map_(self, *args, **kwargs):  # the Ctrl-C comes while the graph of the tasks is made
            calls.append(1)
            if interrupt["on"] and len(calls) == (1 if moment == "first submit" else 2):
                raise KeyboardInterrupt
            return real_map(self, *args, **kwargs)

        monkeypatch.setattr(distributed.Client, "map", map_)
    elif moment == "store write":
        writes, real_write = [], _Store.write

        def write(self, results):  # the Ctrl-C comes just after the second point is stored
            real_write(self, results)
            writes.extend(results)
            if interrupt["on"] and len(writes) >= 2:
                raise KeyboardInterrupt

        monkeypatch.setattr(_Store, "write", write)
    else:
        # points that sleep 0.2 s on the workers (no CPU): the client is waiting when SIGINT comes
        def slow_points(seconds):
            from lubelink.sweep import compute

            fast = compute.__dict__.setdefault("_unslowed_simulate_point", compute._simulate_point)

            def slow(config, opts):
                time.sleep(seconds)
                return fast(config, opts)

            compute._simulate_point = slow if seconds else fast

        client.run(slow_points, 0.2)

        def ctrl_c(signum, frame):  # Python's SIGINT handler, but a late signal (sweep over) is ignored
            if interrupt["on"]:
                raise KeyboardInterrupt

        previous = signal.signal(signal.SIGINT, ctrl_c)

        def press_ctrl_c_after_two_points():
            end = time.monotonic() + 60
            while stored(store) < 2 and time.monotonic() < end:
                time.sleep(0.01)
            os.kill(os.getpid(), signal.SIGINT)

        presser = threading.Thread(target=press_ctrl_c_after_two_points)
        presser.start()
    try:
        with pytest.raises(KeyboardInterrupt), deadline(120, "the interrupted sweep"):
            interrupt["on"] = True
            try:
                run_sweep(RECALL, store, progress=False, trace=first, **reach_dask)
            finally:
                interrupt["on"] = False
    finally:
        if moment == "waiting":
            presser.join()
            signal.signal(signal.SIGINT, previous)
            client.run(slow_points, 0.0)
    assert not left_on_scheduler(client, sp)  # cancelled (user's client) or released with its client
    assert set(multiprocessing.active_children()) <= processes  # a LocalCluster of its own is closed
    done_before = set(np.flatnonzero(load_sweep(store).done.values.reshape(-1))) if store.exists() else set()
    if moment == "first submit":
        assert not done_before and not store.exists()  # nothing computed: nothing left behind
    else:  # the first refill follows the first result; the other interruptions come after two stored points
        assert (1 if moment == "refill" else 2) <= len(done_before) < sp.size, done_before

    with deadline(120, "the sweep called again"):
        ds = run_sweep(RECALL, store, progress=False, trace=second, **reach_dask)
    assert bool(ds.done.all()) and (ds.status == "complete").all()
    again = ends(second)
    assert len(again) == len(set(again)) and not set(again) & done_before  # stored points not computed again
    assert set(again) | done_before == set(range(sp.size))
    runs = json.loads(ds.attrs["runs"])
    assert runs[-1]["resumed"] == len(done_before) and runs[-1]["computed"] == sp.size - len(done_before)


@on_cluster
def test_a_sweep_gathers_its_results_on_its_own_clients_event_loop(client, tmp_path):
    """Another client made current in the process (``with Client(...)``), its event loop held up:
    the sweep, on a client of its own, still finishes. (It used to track and gather its futures on
    the current client's loop: one CI run waited for ever there, the result held by the scheduler.)"""
    from distributed import Client

    data = {**RECALL, "vary": {"mechanism.crank_speed": [20.0, 30.0, 40.0]}}
    gate = threading.Event()
    with Client(client.scheduler.address) as other:
        other.loop.add_callback(gate.wait)  # its event loop does nothing until the gate opens
        try:
            with deadline(60, "a sweep beside a held-up client"):
                ds = run_sweep(data, tmp_path / "s.zarr", scheduler=client.scheduler.address, progress=False)
        finally:
            gate.set()
    assert bool(ds.done.all()) and (ds.status == "complete").all()

# ====================================================================== command line
@on_cluster
def test_plot_sweep_draws_maps_curves_and_status(reference, tmp_path, capsys):
    folder, _, _ = reference
    store = str(folder / "ref.zarr")
    for k, args in enumerate((["--quantity", "peak_u2_mid"],
                 ["--quantity", "status", "--select", "film.clearance=3"],  # mm, the axis's unit
                 ["--quantity", "regime", "--select", "film.clearance=0.003 m"],
                 ["--quantity", "peak_pressure", "--select", "film.viscosity=100", "--select", "film.clearance=1"])):
        png = tmp_path / f"{k}.png"
        assert cli_main(["plot-sweep", store, *args, "-o", str(png)]) == 0
        assert png.stat().st_size > 5000
    assert cli_main(["plot-sweep", store, "--quantity", "peak_u2"]) == 2
    assert "did you mean 'peak_u2_mid'" in capsys.readouterr().err


@pytest.mark.parametrize("args, needle", [
    (["sweep", "missing.toml"], "no such file"),
    (["sweep", "s.toml", "--workers", "two"], "--workers two"),
    (["sweep", "s.toml", "--workers", "2", "--scheduler", "tcp://127.0.0.1:1"], "not both"),
    (["sweep", "s.toml", "--executor", "serial", "--workers", "2"], "--workers 2 needs --executor processes or dask"),
    (["sweep", "s.toml", "--executor", "processes", "--scheduler", "tcp://127.0.0.1:1"], "needs --executor dask"),
    (["sweep", "bad.toml"], "did you mean 'film.viscosity'"),
    (["sweep", "s.toml", "-o", "/nonexistent-dir/r.zarr"], "does not exist"),
    (["plot-sweep", "nothing.zarr"], "no such sweep store"),
])
def test_bad_command_lines_exit_2_with_clear_lines(args, needle, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    Path("s.toml").write_text('[set]\n"solver.t_end" = 0.05\n[vary]\n"film.viscosity" = [0.1]\n')
    Path("bad.toml").write_text('[vary]\n"film.viscositty" = [0.1]\n')
    assert cli_main(args) == 2
    err = capsys.readouterr().err
    assert needle in err and "Traceback" not in err
    assert all(line.startswith("lubelink: error: ") for line in err.strip().splitlines())


def test_an_unreachable_scheduler_is_one_clear_line(tmp_path, monkeypatch, capsys):
    import dask

    monkeypatch.chdir(tmp_path)
    Path("s.toml").write_text('[set]\n"solver.t_end" = 0.05\n[vary]\n"film.viscosity" = [0.1]\n')
    with dask.config.set({"distributed.comm.timeouts.connect": "1s"}):
        assert cli_main(["sweep", "s.toml", "--scheduler", "tcp://127.0.0.1:9"]) == 2
    err = capsys.readouterr().err
    assert "lubelink: error: scheduler tcp://127.0.0.1:9: cannot connect" in err and "Traceback" not in err


def test_check_prints_the_plan_without_computing(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    Path("s.toml").write_text(SWEEP_TOML)
    assert cli_main(["sweep", "s.toml", "--check"]) == 0
    out = capsys.readouterr().out
    assert "points            48\n" in out and "validated         48 points, all valid" in out
    assert "film.clearance: 4 (log" in out and "estimate          about" in out
    assert not Path("s.zarr").exists()


# ====================================================================== issue 15: reliability II
def test_two_sweeps_creating_the_same_store_at_once_one_is_told_it_is_in_use(tmp_path, monkeypatch):
    """Item 6: the loser of the race gets the documented "store in use", not OSError."""
    sp = read_sweep(sweep_dict(**{"film.viscosity": [0.1, 0.2]}))
    path = tmp_path / "r.zarr"
    real = _Store._build_and_publish
    winner = []

    def another_sweep_publishes_first(self):
        if not winner:
            winner.append(None)
            winner[0] = _Store.open(path, sp)  # created, published, locked by the other sweep
        real(self)

    monkeypatch.setattr(_Store, "_build_and_publish", another_sweep_publishes_first)
    with pytest.raises(SweepError, match="being written by another sweep"):
        _Store.open(path, sp)
    assert winner[0].created and sorted(p.name for p in tmp_path.iterdir()) == ["r.zarr"]
    winner[0].close()


def test_two_threads_creating_the_same_store(tmp_path):
    sp = read_sweep(sweep_dict(**{"film.viscosity": [0.1, 0.2]}))
    for round_ in range(3):
        path = tmp_path / f"r{round_}.zarr"
        barrier, outcomes = threading.Barrier(2), []

        def open_store():
            barrier.wait()
            try:
                outcomes.append(_Store.open(path, sp))
            except Exception as exc:  # noqa: BLE001 - the outcome is what is checked
                outcomes.append(exc)

        threads = [threading.Thread(target=open_store) for _ in range(2)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        stores = [o for o in outcomes if isinstance(o, _Store)]
        errors = [o for o in outcomes if not isinstance(o, _Store)]
        assert len(stores) == 1 and len(errors) == 1, outcomes
        assert isinstance(errors[0], SweepError) and "being written by another sweep" in str(errors[0])
        stores[0].close()
    assert not [p for p in tmp_path.iterdir() if ".part" in p.name]


@pytest.mark.parametrize("name", ["lock", "journal.jsonl"])
def test_a_store_never_writes_through_a_symbolic_link_inside_it(tmp_path, name):
    """Issue 37 (security): the store's ``lock`` was opened through a link and truncated before any check, its
    ``journal.jsonl`` appended to through a link and later emptied. A link in their place is refused, naming it,
    and the file it points to is left as it was."""
    sp = read_sweep(sweep_dict(**{"film.viscosity": [0.1, 0.2]}))
    path = tmp_path / "r.zarr"
    _Store.open(path, sp).close()
    outside = tmp_path / "precious.txt"
    outside.write_text("keep me\n")
    (path / name).unlink()
    (path / name).symlink_to(outside)
    with pytest.raises(SweepError, match=f"{name} is a symbolic link: a sweep store never writes through one"):
        _Store.open(path, sp)
    assert outside.read_text() == "keep me\n" and (path / name).is_symlink()


@pytest.mark.parametrize("output", ["s.zarr", "s.nc"])
def test_an_unreachable_scheduler_leaves_no_store(tmp_path, monkeypatch, capsys, output):
    """Item 8."""
    import dask

    monkeypatch.chdir(tmp_path)
    Path("s.toml").write_text('[set]\n"solver.t_end" = 0.05\n[vary]\n"film.viscosity" = [0.1]\n')
    with dask.config.set({"distributed.comm.timeouts.connect": "1s"}):
        assert cli_main(["sweep", "s.toml", "-o", output, "--scheduler", "tcp://127.0.0.1:9"]) == 2
    assert "cannot connect" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]


def test_a_store_this_run_created_is_removed_if_nothing_was_computed(tmp_path, monkeypatch):
    import lubelink.sweep.execute as execute

    def no_cluster(*a, **k):
        raise SweepError("no cluster today")

    monkeypatch.setattr(execute, "_dask_client", no_cluster)
    with pytest.raises(SweepError, match="no cluster today"):
        run_sweep(sweep_dict(**{"film.viscosity": [0.1]}), tmp_path / "r.zarr", progress=False, executor="dask")
    assert list(tmp_path.iterdir()) == []


HUGE_SWEEP = """
[vary]
"film.viscosity" = { start = 0.01, stop = 1.0, num = 10000 }
"mechanism.crank_speed" = { start = 10.0, stop = 40.0, num = 1000 }
"""


def test_a_huge_sweep_is_refused_up_front_with_its_cost(tmp_path, monkeypatch, capsys):
    """Item 9: 10^7 points: the plan at once, no point validated, refused above the cap."""
    from lubelink.sweep import Sweep

    def never(*a, **k):
        raise AssertionError("a refused sweep must not be validated point by point")

    monkeypatch.setattr(Sweep, "invalid_points_of", never)
    monkeypatch.setattr(Sweep, "point_configs", never)
    monkeypatch.chdir(tmp_path)
    Path("huge.toml").write_text(HUGE_SWEEP)
    assert cli_main(["sweep", "huge.toml", "--check"]) == 2
    out, err = capsys.readouterr()
    assert "points            10,000,000" in out and "estimate          about" in out
    assert "client memory about" in out and "store about" in out
    assert "10,000,000 points, more than the limit of 100,000" in err and "--max-points 10000000" in err
    assert cli_main(["sweep", "huge.toml"]) == 2
    assert "more than the limit of 100,000" in capsys.readouterr().err
    with pytest.raises(SweepError, match="more than the limit"):
        run_sweep("huge.toml", "huge.zarr", progress=False)
    assert cli_main(["sweep", "huge.toml", "--max-points", "0"]) == 2
    assert "--max-points 0: must be a whole number in [1, 1000000000]" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["huge.toml"]


def test_a_large_sweep_is_validated_without_holding_configurations(tmp_path, monkeypatch, capsys):
    from lubelink.sweep import Sweep

    def never(*a, **k):
        raise AssertionError("run_sweep and --check keep no configuration per point")

    monkeypatch.setattr(Sweep, "point_configs", never)
    monkeypatch.chdir(tmp_path)
    Path("big.toml").write_text('[vary]\n"film.viscosity" = { start = 0.01, stop = 1.0, num = 300 }\n'
                                '"mechanism.crank_speed" = { start = 10.0, stop = 40.0, num = 1000 }\n')
    assert cli_main(["sweep", "big.toml", "--check", "--max-points", "300000"]) == 0
    assert "validated         300,000 points, all valid" in capsys.readouterr().out


def test_sweep_estimates_scale_with_the_points_and_what_is_stored():
    small = read_sweep(sweep_dict(**{"film.viscosity": [0.1, 0.2]}))
    big = read_sweep(sweep_dict(**{"film.viscosity": {"start": 0.1, "stop": 0.2, "num": 2000}}))
    a, b = small.estimate(workers=2), big.estimate(workers=2)
    assert b.cpu_seconds == pytest.approx(1000 * a.cpu_seconds, rel=0.05)
    assert b.wall_seconds == pytest.approx(b.cpu_seconds / 2)
    series = read_sweep({**sweep_dict(**{"film.viscosity": [0.1, 0.2]}), "store": {"time_series": ["u2"]}})
    assert series.estimate().store_bytes > 2 * 101 * 5 * 8  # 101 samples x 5 points along the link, per point


@pytest.mark.parametrize("data, needle", [
    ({"points": [{}]}, "points[0]: an empty point"),
    ({"points": [{"film.viscosity": 0.1}, {}]}, "points[1]: an empty point"),
    ({"vary": {"film.viscosity": [10**400]}}, "vary.\"film.viscosity\"[0] = <an integer of about 401 digits>"),
    ({"vary": {"film.viscosity": {"start": 10**400, "stop": 1.0, "num": 3}}},
     "vary.\"film.viscosity\".start = <an integer of about 401 digits>: must be a finite number"),
    ({"vary": {"beam.modes": [10**400]}}, "[0] = <an integer of about 401 digits>: must be an integer"),
    ({"vary": {"film.viscosity": [0.1]}, "set": {"mechanism.gravity": [10**400, 0]}},
     "mechanism.gravity = (<an integer of about 401 digits>, 0)"),
    ({"vary": {"film.viscosity": [0.1]}, "set": {"film.viscosity": 10**400}}, "must be a number within"),
])
def test_sweep_files_of_issue_15_are_refused_naming_the_key(data, needle):
    with pytest.raises(ConfigError) as err:
        read_sweep(data)
    assert any(needle in p for p in err.value.problems), err.value.problems


def test_a_sweep_base_is_relative_to_the_sweep_file_and_a_foreign_base_is_not_quoted(tmp_path, monkeypatch, capsys):
    """Item 13."""
    (tmp_path / "studies").mkdir()
    (tmp_path / "studies" / "base.toml").write_text('scenario = "paper-dry"\n[beam]\nmodes = 2\n')
    (tmp_path / "studies" / "s.toml").write_text('base = "base.toml"\n[vary]\n"film.viscosity" = [0.1]\n')
    (tmp_path / "secrets.toml").write_text('[DB_PASSWORD]\nvalue = "hunter2"\n[film]\nmodel = "s3cr3t-token"\n')
    (tmp_path / "studies" / "evil.toml").write_text('base = "../secrets.toml"\n[vary]\n"film.viscosity" = [0.1]\n')
    (tmp_path / "studies" / "bytes.toml").write_text('base = "/proc/self/environ"\n[vary]\n"film.viscosity" = [0.1]\n')
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    sp = read_sweep("../studies/s.toml")
    assert sp.base_config.beam.modes == 2 and sp.base_config.film.model == "none"
    for name in ("evil.toml", "bytes.toml"):
        assert cli_main(["sweep", f"../studies/{name}", "--check"]) == 2
        err = capsys.readouterr().err
        assert "is not a valid lubelink configuration file" in err and "lubelink config" in err
        for secret in ("DB_PASSWORD", "hunter2", "s3cr3t", "PATH="):
            assert secret not in err


@pytest.mark.parametrize("args, needle", [
    (["sweep", "random.toml", "--check"], "random.toml: not UTF-8 text"),
    (["sweep", "folder"], "is a folder, not a sweep file"),
    (["sweep", "s.toml", "-o", "/proc/r.zarr"], "cannot create files in folder /proc"),
    (["sweep", "s.toml", "-o", "file.zarr"], "exists and is a file, not a folder"),
    (["sweep", "s.toml", "-o", "folder.nc"], "is a folder; only a regular file is ever replaced"),
    (["sweep", "s.toml", "--check", "-o", "/proc/r.nc"], "cannot create files in folder /proc"),
])
def test_bad_sweep_command_lines_of_issue_15(args, needle, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    Path("s.toml").write_text('[set]\n"solver.t_end" = 0.05\n[vary]\n"film.viscosity" = [0.1]\n')
    Path("random.toml").write_bytes(bytes(range(128, 256)))
    Path("folder").mkdir()
    Path("folder.nc").mkdir()
    Path("file.zarr").write_text("")
    assert cli_main(args) == 2
    err = capsys.readouterr().err
    assert needle in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


@on_cluster
def test_plot_sweep_checks_its_output_before_drawing(reference, tmp_path, capsys):
    """Item 1, plot-sweep -o."""
    store = str(reference[0] / "ref.zarr")
    (tmp_path / "d.png").mkdir()
    for out, needle in (("/proc/x.png", "cannot create files in folder /proc"),
                        (str(tmp_path / "d.png"), "is a folder"),
                        (str(tmp_path / "x.zarr"), "name an image file")):
        assert cli_main(["plot-sweep", store, "-o", out]) == 2
        err = capsys.readouterr().err
        assert needle in err and "Traceback" not in err


@on_cluster
def test_sweep_outputs_honour_the_umask(client, tmp_path):
    """Item 11: every file and folder of a Zarr store, a NetCDF export and a plot."""
    import stat

    data = sweep_dict(**{"film.viscosity": [0.1, 0.2]})
    old = os.umask(0o002)
    try:
        run_sweep(data, tmp_path / "u.zarr", client=client, progress=False, trace=tmp_path / "trace.log")
        run_sweep(data, tmp_path / "u.nc", client=client, progress=False)
        assert cli_main(["plot-sweep", str(tmp_path / "u.zarr"), "-o", str(tmp_path / "u.png")]) == 0
    finally:
        os.umask(old)
    # (the trace file is created by the workers, with their own umask)
    paths = [tmp_path / "u.zarr", *(tmp_path / "u.zarr").rglob("*"), tmp_path / "u.nc", tmp_path / "u.png"]
    for p in paths:
        want = 0o775 if p.is_dir() else 0o664
        assert stat.S_IMODE(p.stat().st_mode) == want, p


@on_cluster
def test_sigterm_stops_a_sweep_like_ctrl_c(client, tmp_path, monkeypatch, capsys):
    """Item 10: SIGTERM to the sweep client: stored points kept, one line, status 143, resumable."""
    monkeypatch.chdir(tmp_path)
    # points slow enough (2 s of motion, tight tolerance) that the sweep is still running when the signal comes
    Path("s.toml").write_text(SWEEP_TOML.replace('"solver.t_end" = 0.1', '"solver.t_end" = 2.0\n"solver.rtol" = 1e-10'))
    trace = tmp_path / "trace.log"

    def terminate_after_the_first_points():
        deadline = time.monotonic() + 120
        while stored(tmp_path / "s.zarr") < 2 and time.monotonic() < deadline:
            time.sleep(0.01)
        os.kill(os.getpid(), signal.SIGTERM)

    killer = threading.Thread(target=terminate_after_the_first_points)
    killer.start()
    status = cli_main(["sweep", "s.toml", "-q", "--scheduler", client.scheduler.address, "--trace", str(trace)])
    killer.join()
    err = capsys.readouterr().err
    assert status == 143, err
    assert "lubelink: terminated by SIGTERM;" in err and "run the same command again to resume" in err
    assert not [p for p in tmp_path.iterdir() if ".part" in p.name]
    # resumed as a CLI user resumes it: a new process (resuming in the same process is
    # test_a_sweep_interrupted_then_called_again_in_the_same_process)
    resumed = subprocess.run([sys.executable, "-m", "lubelink", "sweep", "s.toml", "-q", "--scheduler",
                              client.scheduler.address], cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert resumed.returncode == 0, resumed.stderr
    assert bool(load_sweep("s.zarr").done.all())


@pytest.mark.parametrize("overrides, asperities, contact", [
    ({"film.clearance": 160e-6, "film.viscosity": 0.0275}, False, False),    # full film
    ({"film.clearance": 20e-6, "film.viscosity": 0.00275}, True, False),     # mixed lubrication
    ({"film.clearance": 20e-6, "film.viscosity": 0.275, "mechanism.crank_speed": 62.8319}, True, True),  # contact
])
def test_the_regime_quantities_tell_the_regimes_of_examples_sweep_regimes(overrides, asperities, contact):
    """Three points of examples/sweep-regimes.toml (``guide``, 3 modes, 0.5 s): the summaries
    ``peak_asperity_force`` and ``peak_contact_force`` are the series' peaks, and they say full film, mixed
    lubrication (the asperities carry load, the film stays above contact.min_film) or contact."""
    import lubelink
    from lubelink.sweep.compute import summarise

    ds = lubelink.simulate("guide", {"beam.modes": 3, "solver.t_end": 0.5, **overrides})
    record = summarise(ds, ("peak_asperity_force", "peak_contact_force", "min_film", "regime"))
    assert record["regime"] == ("contact" if contact else "mixed" if asperities else "full film")
    assert record["peak_asperity_force"] == float(np.abs(ds.asperity_force).max())
    assert record["peak_contact_force"] == float(np.abs(ds.contact_force).max())
    assert (record["peak_asperity_force"] > 1.0) == asperities
    assert (record["peak_contact_force"] > 0.0) == contact
    assert (record["min_film"] < lubelink.results.config_of(ds).contact.min_film) == contact


def test_a_crafted_zarr_v2_store_with_a_pickle_codec_runs_no_code(tmp_path, capsys):
    """Issue 37 (security): a sweep store is data from elsewhere. A Zarr v2 store that claims to be a sweep and
    holds an object array with the pickle codec, whose payload would create a file when unpickled, is refused
    in one line and runs nothing (Zarr >= 3 has no pickle codec: pyproject.toml keeps that bound)."""
    import json
    import pickle

    store = tmp_path / "s.zarr"
    (store / "status").mkdir(parents=True)
    (store / ".zgroup").write_text(json.dumps({"zarr_format": 2}))
    (store / ".zattrs").write_text(json.dumps({"lubelink_sweep_format": "1.0", "swept_dims": "film.viscosity",
                                               "quantities": ""}))
    (store / "status" / ".zarray").write_text(json.dumps({
        "zarr_format": 2, "shape": [1], "chunks": [1], "dtype": "|O", "compressor": None, "fill_value": None,
        "filters": [{"id": "pickle"}], "order": "C", "dimension_separator": "."}))
    (store / "status" / ".zattrs").write_text(json.dumps({"_ARRAY_DIMENSIONS": ["film.viscosity"]}))
    marker = tmp_path / "PWNED"

    class Payload:
        def __reduce__(self):
            return (Path.touch, (marker,))

    payload = np.empty(1, dtype=object)
    payload[0] = Payload()
    (store / "status" / "0").write_bytes(pickle.dumps(payload))
    assert cli_main(["plot-sweep", str(store), "-o", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err
    assert "not a readable Zarr store" in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
    with pytest.raises(SweepError):
        load_sweep(store)
    assert not marker.exists()

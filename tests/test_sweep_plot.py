"""``plot_sweep`` and ``lubelink plot-sweep`` (issue 16 item 7): time series can be drawn, values
in display units, points that did not complete masked, the --overwrite rule.

The stores are written through the sweep's own store class with made-up records (no simulation,
no Dask cluster), so that every drawn value is known here.
"""

import os
import stat

import numpy as np
import pytest

pytest.importorskip("zarr")
pytest.importorskip("matplotlib")
xr = pytest.importorskip("xarray")

import matplotlib  # noqa: E402

matplotlib.use("Agg")

from lubelink.cli import main  # noqa: E402
from lubelink.sweep import load_sweep, plot_sweep, read_sweep  # noqa: E402
from lubelink.sweep.store import _Store  # noqa: E402

CLEARANCES = [2e-3, 3e-3, 4e-3, 5e-3]
VISCOSITIES = [1e-3, 1e-1]
#: Made-up peak deflections [m] over (viscosity, clearance); the point (1e-3, 2e-3) did not
#: complete and holds the huge value of its partial run.
PEAK = np.array([[0.5, 2.1e-3, 2.2e-3, 2.3e-3], [2.6e-3, 2.65e-3, 2.7e-3, 2.75e-3]])
PEAK[0, 0] = 0.5
STATUS = np.array([["film_breakdown", "complete", "complete", "complete"], ["complete"] * 4])
T_END, STEP = 0.05, 0.01


def _make_store(path, n_visc=2):
    sp = read_sweep({"base": "paper", "set": {"solver.t_end": T_END, "solver.output_step": STEP},
                     "vary": {"film.viscosity": VISCOSITIES[:n_visc], "film.clearance": CLEARANCES},
                     "store": {"quantities": ["peak_u2_mid", "peak_pressure", "end_time"],
                               "time_series": ["u2_mid", "q"]}})
    t = np.arange(round(T_END / STEP) + 1) * STEP
    st = _Store.open(path, sp)
    rows = []
    for i in range(n_visc):
        for j in range(len(CLEARANCES)):
            status = STATUS[i, j]
            record = {"status": status, "message": "", "wall_time": 0.25 + 0.01 * j,
                      "peak_u2_mid": PEAK[i, j], "peak_pressure": 1.5e3 * (j + 1),
                      "end_time": T_END if status == "complete" else 0.02}
            series = {"u2_mid": PEAK[i, j] * np.sin(np.pi * t / T_END) ** 2, "q": np.zeros((t.size, 1))}
            rows.append((i * len(CLEARANCES) + j, record, series))
    st.write(rows)
    st.close()
    return path


@pytest.fixture(scope="module")
def store(tmp_path_factory):
    return _make_store(tmp_path_factory.mktemp("plot") / "s.zarr")


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    import matplotlib.pyplot as plt

    plt.close("all")


def _mesh(fig):
    from matplotlib.collections import QuadMesh

    return next(c for ax in fig.axes for c in ax.collections if isinstance(c, QuadMesh))


def test_a_stored_time_series_can_be_drawn(store):
    ds = load_sweep(store)
    fig = plot_sweep(ds, "u2_mid", select={"film.viscosity": 0.1})  # time x clearance map
    z = _mesh(fig).get_array().reshape(len(CLEARANCES), -1)  # rows: clearance, columns: time
    t = ds.time.values
    expect = PEAK[1][:, None] * np.sin(np.pi * t / T_END)[None, :] ** 2 * 1e3  # in mm
    np.testing.assert_allclose(z, expect, rtol=1e-12, atol=1e-15)
    assert fig.axes[0].get_xlabel() == "time [ms]"
    fig = plot_sweep(ds, "u2_mid", select={"film.viscosity": 0.1, "film.clearance": 3e-3})  # one curve
    line = fig.axes[0].lines[0]
    np.testing.assert_allclose(line.get_xdata(), t * 1e3)
    np.testing.assert_allclose(line.get_ydata(), expect[1])
    with pytest.raises(Exception, match="dimension mode besides time: pick one value with --select mode="):
        plot_sweep(ds, "q", select={"film.viscosity": 0.1})


def test_the_command_draws_a_series_it_used_to_call_not_stored(store, tmp_path, capsys):
    out = tmp_path / "u.png"
    assert main(["plot-sweep", str(store), "--quantity", "u2_mid", "--select", "film.viscosity=100",
                 "-o", str(out)]) == 0
    assert out.stat().st_size > 5000
    assert main(["plot-sweep", str(store), "--quantity", "u2"]) == 2
    err = capsys.readouterr().err
    assert "choose from peak_u2_mid, peak_pressure, end_time, u2_mid, q, status, wall_time" in err


def test_values_are_drawn_in_display_units_with_plain_ticks(store):
    fig = plot_sweep(load_sweep(store), "peak_u2_mid")
    ax = fig.axes[0]
    assert ax.get_xlabel() == "film.viscosity [mPa s]"
    assert [t.get_text() for t in ax.get_xticklabels()] == ["1", "100"]  # a list: one column per value
    assert ax.get_ylabel() == "film.clearance [mm]"
    assert [t.get_text() for t in ax.get_yticklabels()] == ["2", "3", "4", "5"]
    cbar = fig.axes[-1]
    assert cbar.get_ylabel().startswith("peak_u2_mid [mm]")
    fig.canvas.draw()
    ticks = [t.get_text() for t in cbar.get_yticklabels()]
    assert ticks and all("e" not in s and "×" not in s and "10^" not in s for s in ticks), ticks
    assert all(2.0 <= float(s.replace("−", "-")) <= 3.0 for s in ticks), ticks  # mm, not metres
    fig = plot_sweep(load_sweep(store), "peak_pressure", select={"film.viscosity": 0.1})
    assert fig.axes[0].get_ylabel() == "peak_pressure [kPa]  (film.viscosity = 100 mPa s)"
    np.testing.assert_allclose(fig.axes[0].lines[0].get_ydata(), [1.5, 3.0, 4.5, 6.0])


def test_select_takes_values_in_the_units_of_the_axis(store):
    """``--select`` (strings) reads a value in the unit the axis is drawn in (mPa s, mm), or with a
    unit of its own; the curve drawn is the row of made-up values of that grid point."""
    ds = load_sweep(store)
    row = {0: [np.nan, 2.1, 2.2, 2.3], 1: [2.6, 2.65, 2.7, 2.75]}  # PEAK in mm, masked where not complete
    for text, i in (("100", 1), ("1", 0), ("0.1 Pa s", 1), ("1 mPa s", 0), ("1e2", 1), (" 100.0 ", 1)):
        fig = plot_sweep(ds, "peak_u2_mid", select={"film.viscosity": text})
        np.testing.assert_allclose(fig.axes[0].lines[0].get_ydata(), row[i], err_msg=text)
        assert fig.axes[0].get_ylabel().endswith(f"(film.viscosity = {[1, 100][i]} mPa s)"), text
    fig = plot_sweep(ds, "peak_u2_mid", select={"film.clearance": "3"})  # mm: a curve over the viscosity
    np.testing.assert_allclose(fig.axes[0].lines[0].get_ydata(), [2.1, 2.65])
    fig = plot_sweep(ds, "peak_u2_mid", select={"film.clearance": "3.0004"})  # as the axis shows it (4 digits)
    np.testing.assert_allclose(fig.axes[0].lines[0].get_ydata(), [2.1, 2.65])
    fig = plot_sweep(ds, "peak_u2_mid", select={"film.viscosity": 0.1})  # a number (Python): SI, as stored
    np.testing.assert_allclose(fig.axes[0].lines[0].get_ydata(), row[1])
    with pytest.raises(Exception, match=r"select film.viscosity=None: must be a number \(in Pa s\)"):
        plot_sweep(ds, "peak_u2_mid", select={"film.viscosity": None})


@pytest.mark.parametrize("select, needle", [
    ("film.viscosity=50", "select film.viscosity='50': 50 mPa s is not a value of the sweep; its values are "
                          "1, 100 mPa s"),
    ("film.viscosity=0.1", "select film.viscosity='0.1': 0.1 mPa s is not a value of the sweep; its values are "
                           "1, 100 mPa s (0.1 is a value in Pa s: write 100, or '0.1 Pa s')"),
    ("film.viscosity=0.2 Pa s", "0.2 Pa s is not a value of the sweep; its values are 1, 100 mPa s"),
    ("film.viscosity=100 cP", "unknown unit 'cP'; write the number in mPa s, or follow it with one of mPa s, Pa s"),
    ("film.viscosity=fast", "select film.viscosity='fast': must be a number in mPa s"),
    ("film.clearance=3.5", "3.5 mm is not a value of the sweep; its values are 2, 3, 4, 5 mm"),
])
def test_an_off_grid_select_is_refused_naming_the_grid_in_the_axis_units(store, tmp_path, capsys, select, needle):
    out = tmp_path / "p.png"
    assert main(["plot-sweep", str(store), "--select", select, "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert needle in err and len(err.strip().splitlines()) == 1, err
    assert not out.exists()
    with pytest.raises(Exception, match="0.05 Pa s is not a value of the sweep; its values are 1, 100 mPa s"):
        plot_sweep(load_sweep(store), "peak_u2_mid", select={"film.viscosity": 0.05})


def test_the_time_of_a_series_is_selected_in_the_units_of_its_axis(store):
    ds = load_sweep(store)
    fig = plot_sweep(ds, "u2_mid", select={"time": "20"})  # ms: a map over the swept parameters at t = 20 ms
    z = _mesh(fig).get_array().reshape(len(CLEARANCES), len(VISCOSITIES))
    expect = PEAK.T * np.sin(np.pi * 0.02 / T_END) ** 2 * 1e3
    np.testing.assert_allclose(np.ma.filled(z, np.nan)[1:], expect[1:])  # (the failed point is masked)
    with pytest.raises(Exception, match=r"15 ms is not a value of the sweep; its values are 0, 10, 20, 30, 40, 50 ms$"):
        plot_sweep(ds, "u2_mid", select={"film.viscosity": "100", "time": "15"})


def test_a_long_grid_is_listed_by_its_ends():
    from lubelink.sweep.plot import _grid_text

    assert _grid_text(np.arange(2001.0), "ms") == "0, 1, 2, 3, ..., 1999, 2000 ms (2001 values)"
    assert _grid_text(np.array([0.5, 1.0]), "") == "0.5, 1"


def test_points_that_did_not_complete_are_masked_and_marked(store):
    ds = load_sweep(store)
    fig = plot_sweep(ds, "peak_u2_mid")
    mesh = _mesh(fig)
    z = np.ma.masked_invalid(mesh.get_array()).reshape(len(CLEARANCES), len(VISCOSITIES))
    assert z.mask[0, 0] and z.count() == 7  # the partial run's 0.5 m is not drawn
    assert mesh.norm.vmax == pytest.approx(2.75)  # ... nor does it set the colour scale (mm)
    crosses = [line for line in fig.axes[0].lines if line.get_marker() == "x"]
    assert len(crosses) == 1 and (crosses[0].get_xdata().tolist(), crosses[0].get_ydata().tolist()) == ([0.0], [0.0])
    assert "did not complete (masked)" in fig.axes[-1].get_ylabel()
    # curves: the failed point is left out of the curve and marked on the axis
    fig = plot_sweep(ds, "peak_u2_mid", select={"film.viscosity": 1e-3})
    y = fig.axes[0].lines[0].get_ydata()
    assert np.isnan(y[0]) and np.allclose(y[1:], [2.1, 2.2, 2.3])
    # run statistics are drawn for every point: how long a failed point ran is no partial result
    fig = plot_sweep(ds, "end_time", select={"film.viscosity": 1e-3})
    np.testing.assert_allclose(fig.axes[0].lines[0].get_ydata(), [20, 50, 50, 50])  # ms
    # a failed point's own series: its partial run is shown apart, dashed
    fig = plot_sweep(ds, "u2_mid", select={"film.viscosity": 1e-3, "film.clearance": 2e-3})
    solid, dashed = fig.axes[0].lines[:2]
    assert np.isnan(solid.get_ydata()).all() and dashed.get_linestyle() == "--"
    assert "partial run (status film_breakdown" in dashed.get_label()


def test_the_output_is_replaced_only_with_overwrite(store, tmp_path, capsys):
    out = tmp_path / "map.png"
    out.write_bytes(b"mine")
    assert main(["plot-sweep", str(store), "-o", str(out)]) == 2
    assert capsys.readouterr().err.strip() == (f"lubelink: error: -o {out}: the file exists; add --overwrite "
                                               "to replace it")
    assert out.read_bytes() == b"mine"
    assert main(["plot-sweep", str(store), "-o", str(out), "--overwrite"]) == 0
    assert out.read_bytes()[:4] == b"\x89PNG"
    # the default name follows the same rule
    os.chdir(tmp_path)
    assert main(["plot-sweep", str(store)]) == 0
    assert main(["plot-sweep", str(store)]) == 2
    assert "s-peak_u2_mid.png: the file exists" in capsys.readouterr().err


@pytest.mark.parametrize("umask", [0o022, 0o077])
def test_figures_and_stores_honour_the_umask(tmp_path, umask):
    old = os.umask(umask)
    try:
        path = _make_store(tmp_path / "u.zarr", n_visc=1)
        assert main(["plot-sweep", str(path), "-o", str(tmp_path / "u.png")]) == 0
    finally:
        os.umask(old)
    for p in [path, *path.rglob("*"), tmp_path / "u.png"]:
        want = (0o777 if p.is_dir() else 0o666) & ~umask
        assert stat.S_IMODE(p.stat().st_mode) == want, p

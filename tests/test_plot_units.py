"""Display units of the figures (lubelink.plots.units): the unit in which the values read 1-1000."""

import math

import numpy as np
import pytest

from lubelink.plots.units import DISPLAY, display_unit, to_display
from lubelink.results import VARIABLES


@pytest.mark.parametrize("units, values, expect", [
    ("m", [0.002675, -0.001], ("mm", 1e-3)),       # the 0.002675 m: 2.675 mm
    ("m", [4e-6, 2e-5], ("µm", 1e-6)),
    ("m", [0.3, 1.0], ("m", 1.0)),
    ("m", [2e-9], ("µm", 1e-6)),                     # below the smallest unit: the smallest
    ("Pa", [6995.0], ("kPa", 1e3)),
    ("Pa", [-2.5e6, 1e3], ("MPa", 1e6)),             # the magnitude decides, whatever the sign
    ("Pa", [12.0], ("Pa", 1.0)),
    ("Pa s", [1e-3, 0.1], ("mPa s", 1e-3)),
    ("s", [0.0, 0.05], ("ms", 1e-3)),
    ("s", [1.273], ("s", 1.0)),
    ("N", [2.318], ("N", 1.0)),
    ("m s-1", [0.05], ("mm/s", 1e-3)),
    ("m", [np.nan, 0.0], ("m", 1.0)),                # nothing finite and non-zero: the SI unit
    ("m", None, ("m", 1.0)),
    ("1", [5.0], ("", 1.0)),
    ("furlong", [5.0], ("furlong", 1.0)),           # unknown units are shown as they are
])
def test_the_display_unit_reads_between_1_and_1000(units, values, expect):
    assert display_unit(units, values) == expect


@pytest.mark.parametrize("top", np.geomspace(1.1e-6, 900.0, 40))
def test_lengths_read_between_1_and_1000(top):
    shown, label = to_display("m", [top, -0.5 * top])
    assert 1.0 <= np.max(np.abs(shown)) < 1000.0 or label == "km"
    size = dict(DISPLAY["m"])[label]
    np.testing.assert_allclose(shown * size, [top, -0.5 * top], rtol=1e-15)


def test_every_dimensional_unit_of_the_results_has_display_units():
    for name, v in VARIABLES.items():
        if v.units != "1":
            assert v.units in DISPLAY, (name, v.units)
            assert any(size == 1.0 for _, size in DISPLAY[v.units])  # the SI unit is among them
            sizes = [size for _, size in DISPLAY[v.units]]
            assert sizes == sorted(sizes) and all(math.log10(s).is_integer() for s in sizes)


@pytest.mark.parametrize("values, log", [
    ([2.0e-3, 3.0e-3], False),                 # the 2-3 mm response curve: a linear axis
    ([1.0e-3, 9.99e-3], False),                # just under a decade
    ([1.0e-3, 1.0e-2], True),                  # a decade: log
    ([5e-6, 2e-4, 4e-4], True),                # a film thinning to breakdown
    ([0.05, 0.1, 0.2], False),                 # three viscosities within a factor 4
    ([1e-3, 1e-1], True),
    ([0.0, 1e-3, 1.0], False),                 # a zero cannot be drawn on a log axis
    ([-1e-4, 2e-4, 3e-1], False),              # nor a negative film (penetration)
    ([np.nan, 1e-3, np.inf, 5e-2], True),      # non-finite values are not drawn
    ([3e-3], False),
    ([], False),
])
def test_log_axes_only_where_the_values_span_a_decade(values, log):
    from lubelink.plots.units import log_scale

    assert log_scale(values) is log


def _branch(peaks):
    """A made-up branch Dataset (the variables figure_branch reads), stable throughout."""
    import xarray as xr

    n = len(peaks)
    return xr.Dataset(
        {"parameter": ("point", np.linspace(30.0, 31.0, n), {"units": "rad s-1"}),
         "peak_u2_mid": ("point", np.asarray(peaks, dtype=float), {"units": "m"}),
         "max_modulus": ("point", np.full(n, 0.5)),
         "omega_n": (("point", "mode"), np.full((n, 1), 300.0)),
         "bifurcation_type": ("bifurcation", np.zeros(0, dtype=np.int8)),
         "bifurcation_parameter": ("bifurcation", np.zeros(0)),
         "bifurcation_point": ("bifurcation", np.zeros(0, dtype=np.int32))},
        coords={"point": np.arange(n), "mode": [1], "bifurcation": np.arange(0)},
        attrs={"parameter": "mechanism.crank_speed"})


@pytest.mark.parametrize("peaks, scale", [(np.linspace(2e-3, 3e-3, 11), "linear"),
                                          (np.geomspace(1e-4, 3e-3, 11), "log")])
def test_response_curves_choose_their_deflection_axis(peaks, scale, tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    from lubelink.cli import main
    from lubelink.steady.plot import figure_branch

    ds = _branch(peaks)
    fig = figure_branch(ds)
    assert fig.axes[0].get_yscale() == scale
    assert figure_branch(ds, log=True).axes[0].get_yscale() == "log"
    assert figure_branch(ds, log=False).axes[0].get_yscale() == "linear"
    ds.to_netcdf(tmp_path / "b.nc")  # and plot-branch, which draws it with --log, --linear or neither
    for flag in ("--log", "--linear"):
        assert main(["plot-branch", str(tmp_path / "b.nc"), "-o", str(tmp_path / f"b{flag}.png"), flag]) == 0
    with pytest.raises(SystemExit) as exc:  # argparse: one or the other
        main(["plot-branch", str(tmp_path / "b.nc"), "-o", str(tmp_path / "b.png"), "--log", "--linear"])
    assert exc.value.code == 2
    import matplotlib.pyplot as plt

    plt.close("all")


def test_the_thinnest_film_axis_is_log_only_when_it_spans_a_decade():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import xarray as xr

    from lubelink.plots.response import plot_film_min

    t = np.linspace(0.0, 1.0, 21)
    for film, min_film, scale in ((2e-4 + 1e-4 * np.sin(t), None, "linear"),
                                  (2e-4 + 1e-4 * np.sin(t), 5e-6, "log"),  # the threshold drawn too
                                  (np.geomspace(3e-4, 6e-6, t.size), None, "log")):
        ds = xr.Dataset({"film_min": ("time", film), "impact_time": ("impact", np.zeros(0))}, coords={"time": t})
        fig, ax = plt.subplots()
        plot_film_min(ds, ax, min_film=min_film)
        assert ax.get_yscale() == scale
        plt.close(fig)

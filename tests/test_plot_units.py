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

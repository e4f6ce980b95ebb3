"""Display units: values stored in SI, drawn in the units people read (mm, µm, kPa, mPa s).

:func:`display_unit` picks, for the SI unit of a variable (its ``units`` attribute, as
:data:`lubelink.results.VARIABLES` and :data:`lubelink.fields.FIELDS` write it), the unit of
:data:`DISPLAY` in which the largest magnitude drawn reads between 1 and 1000, so that axes show
``2.7 mm`` rather than ``0.0027`` or ticks with a ``1e-3`` offset. :func:`log_scale` says whether
values are drawn on a logarithmic axis (they span a decade or more) or a linear one.
"""

from __future__ import annotations

import numpy as np

__all__ = ["DISPLAY", "LOG_RATIO", "display_unit", "to_display", "label", "log_scale", "plain_ticks"]

#: Display units of each SI unit, smallest first: ``(label, size in the SI unit)``.
DISPLAY = {
    "m": (("µm", 1e-6), ("mm", 1e-3), ("m", 1.0), ("km", 1e3)),
    "m s-1": (("µm/s", 1e-6), ("mm/s", 1e-3), ("m/s", 1.0)),
    "m s-2": (("mm/s²", 1e-3), ("m/s²", 1.0)),
    "Pa": (("Pa", 1.0), ("kPa", 1e3), ("MPa", 1e6), ("GPa", 1e9)),
    "Pa s": (("mPa s", 1e-3), ("Pa s", 1.0)),
    "N": (("mN", 1e-3), ("N", 1.0), ("kN", 1e3), ("MN", 1e6)),
    "N m": (("mN m", 1e-3), ("N m", 1.0), ("kN m", 1e3)),
    "s": (("µs", 1e-6), ("ms", 1e-3), ("s", 1.0)),
    "kg": (("g", 1e-3), ("kg", 1.0)),
    "kg m-3": (("kg/m³", 1.0),),
    "rad s-1": (("rad/s", 1.0),),
    "J": (("µJ", 1e-6), ("mJ", 1e-3), ("J", 1.0), ("kJ", 1e3)),
    "W": (("µW", 1e-6), ("mW", 1e-3), ("W", 1.0), ("kW", 1e3)),
    "rad": (("rad", 1.0),),
}


def display_unit(units, values=None):
    """``(label, size)``: the display unit of SI ``units`` for ``values``; divide by ``size`` to draw.

    The largest display unit not larger than the largest finite magnitude of ``values`` (so it
    reads at least 1); the smallest one when all magnitudes are below it; the SI unit itself when
    there is no value. A unit not in :data:`DISPLAY` is drawn as it is (``"1"``: no label).
    """
    units = (units or "").strip()
    choices = DISPLAY.get(units)
    if choices is None:
        return ("" if units in ("", "1") else units), 1.0
    top = 0.0
    if values is not None:
        v = np.abs(np.asarray(values, dtype=float))
        v = v[np.isfinite(v) & (v > 0)]
        top = float(v.max()) if v.size else 0.0
    if top == 0.0:
        return next((label, size) for label, size in choices if size == 1.0)
    best = choices[0]
    for label, size in choices:
        if size <= top * (1 + 1e-12):
            best = (label, size)
    return best


def to_display(units, values):
    """``(values in the display unit, its label)``."""
    label, size = display_unit(units, values)
    return np.asarray(values, dtype=float) / size, label


#: The ratio of the largest to the smallest value from which an axis is drawn logarithmic: a
#: narrower range (2-3 mm of deflection) reads better on a linear axis, a decade or more on a log one.
LOG_RATIO = 10.0


def log_scale(values, ratio=LOG_RATIO) -> bool:
    """Whether ``values`` are drawn on a logarithmic axis: their finite values are all positive
    and the largest is at least ``ratio`` times the smallest (a linear axis otherwise, and for
    zero or negative values, which a log axis cannot show)."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if v.size < 2 or np.any(v <= 0.0):
        return False
    return bool(v.max() >= ratio * v.min())


def label(name, unit_label):
    """Axis label ``name [unit]`` (just ``name`` for a dimensionless quantity)."""
    return f"{name} [{unit_label}]" if unit_label else name


def plain_ticks(axis):
    """Ticks of a linear axis as plain numbers: no offset, no ``×10^n`` factor."""
    from matplotlib.ticker import ScalarFormatter

    formatter = axis.get_major_formatter()
    if isinstance(formatter, ScalarFormatter):
        formatter.set_useOffset(False)
        formatter.set_scientific(False)


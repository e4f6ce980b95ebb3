"""Shared helpers of the plotting functions: the figure style, units, axes and legends.

Matplotlib is imported inside the functions only.
"""

from __future__ import annotations

import numpy as np

__all__ = ["STYLE", "MM", "UM", "KPA"]

#: Matplotlib settings of every figure (readable at column width).
STYLE = {
    "font.size": 10,
    "axes.titlesize": 11,
    "axes.labelsize": 10,
    "legend.fontsize": 9,
    "xtick.labelsize": 9,
    "ytick.labelsize": 9,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "figure.constrained_layout.use": True,
    "savefig.bbox": "tight",
}

#: Drawing units: m -> mm, m -> µm, Pa -> kPa.
MM, UM, KPA = 1e3, 1e6, 1e-3


def _ax(ax, projection=None):
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt

    if projection is None:
        return plt.gca()
    return plt.gcf().add_subplot(projection=projection)


def _figure(width=7.0, height=4.2):
    import matplotlib
    from matplotlib.figure import Figure

    with matplotlib.rc_context(STYLE):
        return Figure(figsize=(width, height), layout="constrained")


def _levels(data, n):
    """Round, symmetric contour levels covering ``data``."""
    from matplotlib.ticker import MaxNLocator

    top = float(np.nanmax(np.abs(data))) or 1.0
    return MaxNLocator(nbins=n, symmetric=True).tick_values(-top, top)


def _style():
    import matplotlib

    return matplotlib.rc_context(STYLE)


def _legend(ax, n):
    """Legend above the axes, in columns, so that it never hides the curves."""
    longest = max((len(t) for t in ax.get_legend_handles_labels()[1]), default=0)
    ncols = min(n, 4 if longest <= 20 else 3 if longest <= 28 else 2)
    ax.legend(loc="lower left", bbox_to_anchor=(0.0, 1.0), ncols=max(ncols, 1), fontsize=8, frameon=False,
              borderaxespad=0.2, handlelength=1.8, columnspacing=1.2)

"""Figures of lubelink results (paper Figs. 6-9 and beyond), drawn with Matplotlib.

Every function here is pure: it takes results :class:`xarray.Dataset` objects
(see :func:`lubelink.simulate`) and draws on the axes it is given, or, when
``ax`` is omitted, on the current pyplot axes; it returns what it drew on.
The ``figure_*`` functions compose whole figures on a new
:class:`matplotlib.figure.Figure` (no pyplot state), ready for ``savefig``.
Nothing here computes a simulation: :mod:`lubelink.paper` does that.

Lengths are drawn in mm, deflection differences in µm, pressures in kPa,
times in s. Matplotlib is imported inside the functions only, so importing
this package is cheap.

=================  ===========================================================
module             job
=================  ===========================================================
``_style``         shared style (:data:`STYLE`), units, axes, legend helpers
``response``       one run: deflection, midpoint, pressure, impacts, film
                   (paper Figs. 6-9)
``studies``        several runs: modal convergence, errata, lubrication
                   effect, first-impact map
``mechanism``      drawing and animating the slider-crank
=================  ===========================================================

Every public name is importable from ``lubelink.plots`` itself.
"""

from __future__ import annotations

from ._style import KPA, MM, STYLE, UM  # noqa: F401  (MM, UM, KPA: unit factors, public as before)
from .response import (
    figure_deflection,
    figure_impact,
    figure_lubrication,
    figure_pressure,
    plot_deflection_3d,
    plot_deflection_surface,
    plot_film_min,
    plot_impacts,
    plot_midpoint,
    plot_midpoint_difference,
    plot_pressure_surface,
)
from .studies import figure_errata, figure_first_impact_map, figure_lubrication_effect, figure_modal_convergence
from .mechanism import animate_mechanism, draw_link_view, draw_mechanism

__all__ = [
    "STYLE",
    "plot_deflection_surface",
    "plot_deflection_3d",
    "plot_midpoint",
    "plot_midpoint_difference",
    "plot_pressure_surface",
    "plot_impacts",
    "plot_film_min",
    "figure_deflection",
    "figure_lubrication",
    "figure_pressure",
    "figure_impact",
    "figure_modal_convergence",
    "figure_errata",
    "figure_lubrication_effect",
    "figure_first_impact_map",
    "draw_mechanism",
    "draw_link_view",
    "animate_mechanism",
]

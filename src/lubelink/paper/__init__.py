"""Reproduction of the paper's Section 6 results (Figs. 6-9), modal convergence and errata.

Orchestration only: this package runs the simulations (each configuration
once, see :class:`Study`), calibrates the clearance of the impact scenario
(:func:`calibrate_clearance`), and hands the results to the pure plotting
functions of :mod:`lubelink.plots`. It also holds the "as printed" variants
of the equations used to show what the errata change (:func:`simulate_variant`)
and the ``lubelink figures`` / ``lubelink animate`` commands.

Heavy libraries (Matplotlib, xarray, SciPy) are imported inside functions so
that importing this package (which ``lubelink --help`` does) stays cheap.

=================  ===========================================================
module             job
=================  ===========================================================
``calibration``    first-impact time, Fig. 9's clearance calibration (root
                   finding) and its cache, the first-impact map
``branches``       the windows of clearance where the first impact is at
                   1.273 s, and the map over pad length and clearance
``variants``       the equations as printed (errata): ``simulate_variant``
``study``          every configuration simulated once; lubrication effect
``figures``        the figure builders and ``make_figures``
``animation``      ``animate``: the mechanism as a GIF or MP4
``cli``            the ``figures`` and ``animate`` subcommands
=================  ===========================================================

Every public name is importable from ``lubelink.paper`` itself. Only
``calibration`` and ``variants`` call the simulation core directly
(``branches`` runs it through ``calibration``).

Paper: Marghitu & Guran, "The Dynamics of a Flexible Beam With a Lubricated
Prismatic Kinematic Pair", J. Vibration and Acoustics, Section 6.
"""

from __future__ import annotations

# Re-exported beyond __all__: RESOLUTIONS, BUILDERS and the in-memory calibration
# cache _CALIBRATIONS, which the tests and earlier code reach as lubelink.paper.NAME.
from .calibration import (  # noqa: F401
    _CALIBRATIONS,
    PAPER_IMPACT_TIME,
    Calibration,
    calibrate_clearance,
    calibrate_impact,
    first_impact_map,
    first_impact_time,
)
from .branches import Window, branch_map, find_windows, phase_refine, widest_window
from .variants import VARIANTS, simulate_variant  # noqa: F401
from .study import Study, lubrication_effect, lubrication_table
from .figures import BUILDERS, FIGURES, RESOLUTIONS, FigureSet, make_figures  # noqa: F401
from .animation import animate
from .cli import register_cli

__all__ = [
    "PAPER_IMPACT_TIME",
    "FIGURES",
    "VARIANTS",
    "Calibration",
    "Study",
    "first_impact_time",
    "calibrate_clearance",
    "calibrate_impact",
    "first_impact_map",
    "Window",
    "find_windows",
    "phase_refine",
    "branch_map",
    "widest_window",
    "simulate_variant",
    "lubrication_effect",
    "lubrication_table",
    "FigureSet",
    "make_figures",
    "animate",
    "register_cli",
]

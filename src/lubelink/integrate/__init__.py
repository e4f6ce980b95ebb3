"""Time integration: a driver for SciPy-style step solvers and the Bulirsch-Stoer method."""

from .driver import METHODS, Segment, integrate_segment, solver_class

__all__ = ["METHODS", "Segment", "integrate_segment", "solver_class"]

"""Time integration: methods that know nothing of the physics, one driver for all of them.

===================  ============================================================================
module               job
===================  ============================================================================
``_layout``          the integration state (work arrays) shared by the driver and the methods
``control``          error norm, starting step, step-size factor
``events``           locating a zero of the event function inside a step, grazes included
``driver``           the integration loop (compiled or Python), ``integrate`` and ``Segment``
``dop853``           Dormand-Prince 8(5,3) with dense output
``bulirsch_stoer``   Gragg-Bulirsch-Stoer extrapolation; also as a SciPy ``OdeSolver``
``exponential``      exponential Runge-Kutta for damped oscillators with a nonlinear load
``scipy_methods``    SciPy's RK45, Radau, BDF, LSODA behind the driver's method interface
===================  ============================================================================

Nothing here imports a physics module: the right-hand side, the event and its rate arrive as
arguments.
"""

from . import bulirsch_stoer, dop853, exponential
from .driver import Method, Segment, integrate
from .scipy_methods import SCIPY_METHODS, scipy_method

__all__ = ["METHODS", "COMPILED_METHODS", "SCIPY_METHODS", "method", "integrate", "Method", "Segment"]

_COMPILED = {
    "DOP853": Method("DOP853", dop853.init, dop853.step, dop853.dense, dop853.rows),
    "bulirsch-stoer": Method("BulirschStoer", bulirsch_stoer.init, bulirsch_stoer.step, bulirsch_stoer.dense,
                             bulirsch_stoer.rows, floats=bulirsch_stoer.FLOATS, ints=bulirsch_stoer.INTS,
                             setup=bulirsch_stoer.setup),
    "exponential": Method("exponential", exponential.init, exponential.step, exponential.dense, exponential.rows,
                          floats=exponential.FLOATS, setup=exponential.setup),
}
#: Methods whose loop runs compiled.
COMPILED_METHODS = tuple(_COMPILED)
#: Every method name.
METHODS = COMPILED_METHODS + SCIPY_METHODS


def method(name):
    """The :class:`Method` called ``name`` (one of :data:`METHODS`)."""
    if name in _COMPILED:
        return _COMPILED[name]
    if name in SCIPY_METHODS:
        return scipy_method(name)
    raise ValueError(f"unknown method {name!r}; choose one of {', '.join(METHODS)}")

"""Time integration: methods that know nothing of the physics, one driver for all of them.

=====================  ============================================================================
module                 job
=====================  ============================================================================
``_layout``            the integration state (work arrays) shared by the driver and the methods
``control``            error norm, starting step, step-size factor
``events``             locating a zero of the event function inside a step, grazes included
``driver``             the integration loop (compiled or Python), ``integrate`` and ``Segment``
``dop853``             Dormand-Prince 8(5,3) with dense output
``dense_steps``        DOP853 over a whole interval in one compiled loop, kept as its steps' interpolants
``bulirsch_stoer``     Gragg-Bulirsch-Stoer extrapolation; also as a SciPy ``OdeSolver``
``exponential``        exponential Runge-Kutta for damped oscillators with a nonlinear load
``exponential_dense``  its dense output, through the particular solution of each block
``exponential_adams``  exponential Adams predictor-corrector, same problems, 2 evaluations a step
``rodas``              RODAS4, a Rosenbrock method of order 4(3) for stiff problems (films of micrometres)
``phi``                the phi-functions of a damped oscillator's 2x2 block (for ``exponential``)
``scipy_methods``      SciPy's RK45, Radau, BDF, LSODA behind the driver's method interface
=====================  ============================================================================

Nothing here imports a physics module: the right-hand side, the event and its rate arrive as
arguments.
"""

from functools import lru_cache
from importlib import import_module

from .driver import STEPS_PER_CALL, Method, Options, Problem, Segment, integrate
from .scipy_methods import SCIPY_METHODS, scipy_method

__all__ = ["METHODS", "COMPILED_METHODS", "SCIPY_METHODS", "STEPS_PER_CALL", "method", "integrate", "Problem", "Options",
           "Method", "Segment"]

#: Methods whose loop runs compiled, and their modules (imported when first asked for); a method's
#: dense output lives in its module, or in the second module named.
_COMPILED = {"DOP853": ("dop853",), "bulirsch-stoer": ("bulirsch_stoer",),
             "exponential": ("exponential", "exponential_dense"),
             "exponential-adams": ("exponential_adams", "exponential_dense"), "rodas": ("rodas",)}
COMPILED_METHODS = tuple(_COMPILED)
#: Every method name.
METHODS = COMPILED_METHODS + SCIPY_METHODS


@lru_cache(maxsize=None)
def _compiled(name):
    module, *dense = (import_module(f".{m}", __name__) for m in _COMPILED[name])
    dense = dense[0].dense if dense else module.dense
    return Method({"bulirsch-stoer": "BulirschStoer"}.get(name, name), module.init, module.step, dense,
                  module.rows, floats=getattr(module, "FLOATS", 32), ints=getattr(module, "INTS", 16),
                  setup=getattr(module, "setup", None))


def method(name):
    """The :class:`Method` called ``name`` (one of :data:`METHODS`)."""
    if name in _COMPILED:
        return _compiled(name)
    if name in SCIPY_METHODS:
        return scipy_method(name)
    raise ValueError(f"unknown method {name!r}; choose one of {', '.join(METHODS)}")

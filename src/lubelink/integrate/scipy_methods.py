"""SciPy's solvers (RK45, Radau, BDF, LSODA) as methods of the driver, run from Python.

:func:`scipy_method` wraps one :class:`scipy.integrate.OdeSolver` class in the method interface
of :mod:`.driver` (``init``, ``step``, ``dense`` on the shared state), so that the driver's
sampling and event location, the same as for the compiled methods, serve them too. The driver then
runs as Python (``compiled=False``); the right-hand side may still be compiled.
"""

import numpy as np

from ._layout import F_HSTEP, F_MAXSTEP, F_T, F_TEND, F_TOLD, R_ATOL, R_RTOL, R_Y, R_YOLD, S_NFEV
from .driver import Method

__all__ = ["scipy_method", "SCIPY_METHODS"]

SCIPY_METHODS = ("RK45", "Radau", "BDF", "LSODA")


def scipy_method(name):
    """A fresh :class:`~.driver.Method` driving ``scipy.integrate.<name>`` (one per integration)."""
    import scipy.integrate

    cls = getattr(scipy.integrate, name)
    state = {}

    def init(rhs, p, W, fst, ist):
        n = W.shape[1]

        def fun(t, y):
            out = np.empty(n)
            rhs(t, np.ascontiguousarray(y, dtype=float), out, p)
            return out

        state["solver"] = cls(fun, fst[F_T], W[R_Y].copy(), fst[F_TEND], rtol=float(W[R_RTOL].min()),
                              atol=W[R_ATOL].copy(), max_step=fst[F_MAXSTEP])

    def step(rhs, p, W, fst, ist):
        solver = state["solver"]
        t = solver.t
        solver.step()
        ist[S_NFEV] = solver.nfev
        if solver.status == "failed":
            return False
        W[R_YOLD] = W[R_Y]
        W[R_Y] = solver.y
        fst[F_TOLD] = t
        fst[F_T] = solver.t
        fst[F_HSTEP] = solver.t - t
        state["dense"] = None
        return True

    def dense(rhs, p, W, fst, ist, t, out):
        if state.get("dense") is None:
            state["dense"] = state["solver"].dense_output()
        out[:] = state["dense"](t)

    return Method(name, init, step, dense, rows=lambda n: 16)

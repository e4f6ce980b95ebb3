"""Step-by-step driver for any :class:`scipy.integrate.OdeSolver`.

It does what ``solve_ivp`` does (sampling on a time grid from the dense
output, locating the root of one event function), plus what a long
simulation needs: a progress callback, a wall-clock budget and a clear
status instead of an exception. It knows nothing of the physics.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

__all__ = ["Segment", "integrate_segment", "solver_class", "METHODS"]

METHODS = ("DOP853", "RK45", "Radau", "BDF", "LSODA", "bulirsch-stoer")


def solver_class(method):
    """The :class:`~scipy.integrate.OdeSolver` subclass for a method name."""
    if method == "bulirsch-stoer":
        from .bulirsch_stoer import BulirschStoer

        return BulirschStoer
    import scipy.integrate as si

    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}; choose one of {', '.join(METHODS)}")
    return getattr(si, method)


@dataclass
class Segment:
    """Outcome of integrating from ``t0`` up to ``t_end`` or the first event.

    ``status`` is ``"finished"`` (reached ``t_end``), ``"event"`` (the event
    function crossed zero downwards at ``t_final``), ``"failed"`` (the
    solver gave up or the state became non-finite) or ``"timeout"`` (the
    wall-clock deadline passed).
    """

    t: np.ndarray
    y: np.ndarray
    status: str
    message: str
    t_final: float
    y_final: np.ndarray
    nfev: int = 0
    njev: int = 0
    nsteps: int = 0
    extra: dict = field(default_factory=dict)


def _first_crossing(event, sol, t_old, g_old, t_new, g_new, n_sub):
    """First time in ``(t_old, t_new]`` where ``event`` falls to zero or below, or None.

    The event is sampled on ``n_sub`` equal sub-intervals of the step (on the
    dense output), so a dip that starts and ends inside one long step is
    still seen; the first bracket is then refined by Brent's method.
    """
    if not g_old > 0.0:  # started at or below zero: the crossing is the start itself
        return t_old

    def g(t):
        return event(t, sol(t))

    ts = np.linspace(t_old, t_new, n_sub + 1)
    lo = t_old
    for t in ts[1:]:
        g_t = g_new if t == t_new else g(t)
        if not g_t > 0.0:
            if g_t == 0.0:
                return t
            return brentq(g, lo, t, xtol=4 * np.finfo(float).eps * max(1.0, abs(t)),
                          rtol=4 * np.finfo(float).eps, maxiter=200)
        lo = t
    return None


def integrate_segment(fun, t0, y0, t_end, t_eval, *, method="DOP853", rtol=1e-8, atol=1e-12,
                      max_step=np.inf, first_step=None, event=None, event_resolution=None,
                      deadline=None, progress=None):
    """Integrate ``dy/dt = fun(t, y)`` from ``t0`` until ``t_end`` or a terminal event.

    Parameters
    ----------
    fun : callable
        Right-hand side ``fun(t, y) -> ndarray``.
    t0, t_end : float
        Interval [s].
    y0 : ndarray
        Initial state.
    t_eval : ndarray
        Increasing sample times in ``(t0, t_end]`` (those before the event
        are returned).
    method : str or OdeSolver subclass
        Integrator.
    event : callable, optional
        ``event(t, y) -> float``; the segment ends where it crosses zero
        from positive to non-positive.
    event_resolution : float, optional
        Longest time between two samples of ``event`` [s]: longer steps are
        sampled inside on their dense output, so that a zero crossing and
        return within one step is not missed.
    deadline : float, optional
        ``time.perf_counter()`` value after which the run stops.
    progress : callable, optional
        Called with the current time after every step.

    Returns
    -------
    Segment
    """
    cls = solver_class(method) if isinstance(method, str) else method
    options = {"rtol": rtol, "atol": atol, "max_step": max_step}
    if first_step is not None:
        options["first_step"] = first_step
    non_finite = []  # the first time the right-hand side returned NaN or infinity

    def checked(t, y):
        dy = fun(t, y)
        if not non_finite and not np.all(np.isfinite(dy)):
            non_finite.append(t)
        return dy

    solver = cls(checked, t0, np.asarray(y0, dtype=float), t_end, **options)
    t_eval = np.asarray(t_eval, dtype=float)
    ts, ys = [], []
    i_eval = 0
    g_old = event(t0, solver.y) if event is not None else None
    status, message = "finished", "reached the end of the interval"
    t_final, y_final = t0, solver.y.copy()
    nsteps = 0
    while True:
        t_old = solver.t
        msg = solver.step()
        nsteps += 1
        if solver.status == "failed":
            y_last = solver.y_old if solver.y_old is not None else solver.y
            status, message = "failed", f"{solver.__class__.__name__} failed at t = {t_old:.9g} s: {msg}"
            if non_finite:
                message = (f"the right-hand side is not finite at t = {non_finite[0]:.9g} s (a load or the "
                           f"prescribed motion returned NaN or infinity)")
            t_final, y_final = t_old, y_last
            break
        t_new, y_new = solver.t, solver.y
        if not np.all(np.isfinite(y_new)):
            status, message = "failed", f"the state became non-finite at t = {t_new:.9g} s"
            t_final, y_final = t_old, solver.y_old
            break
        sol = None
        t_stop = t_new
        if event is not None:
            g_new = event(t_new, y_new)
            n_sub = 1
            if event_resolution is not None and t_new - t_old > event_resolution:
                n_sub = int(np.ceil((t_new - t_old) / event_resolution))
            if n_sub > 1 or not g_new > 0.0:
                sol = solver.dense_output()
                crossing = _first_crossing(event, sol, t_old, g_old, t_new, g_new, max(n_sub, 2))
                if crossing is not None:
                    t_stop = crossing
                    status, message = "event", f"event at t = {t_stop:.12g} s"
            g_old = g_new
        j = np.searchsorted(t_eval, t_stop, side="right")
        if j > i_eval:
            sol = sol or solver.dense_output()
            ts.append(t_eval[i_eval:j])
            ys.append(np.atleast_2d(sol(t_eval[i_eval:j]).T))
            i_eval = j
        if progress is not None:
            progress(t_stop)
        if status == "event":
            t_final, y_final = t_stop, (sol(t_stop) if t_stop != t_new else y_new.copy())
            break
        if solver.status == "finished":
            t_final, y_final = t_new, y_new.copy()
            break
        if deadline is not None and time.perf_counter() > deadline:
            status, message = "timeout", f"the wall-time budget ran out at t = {t_new:.9g} s"
            t_final, y_final = t_new, y_new.copy()
            break
    n = len(np.atleast_1d(y0))
    return Segment(
        t=np.concatenate(ts) if ts else np.empty(0),
        y=np.concatenate(ys) if ys else np.empty((0, n)),
        status=status, message=message, t_final=float(t_final), y_final=np.asarray(y_final, float),
        nfev=solver.nfev, njev=getattr(solver, "njev", 0), nsteps=nsteps,
        extra={"last_step": float(solver.step_size) if solver.step_size is not None else None},
    )

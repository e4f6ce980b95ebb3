"""The integration loop: any method, sampling on a time grid, an event, progress and a time budget.

:func:`advance` is the loop in compiled code. It takes the method (``init``, ``step``, ``dense``)
and the problem (``rhs``, ``event``, parameters ``p``) as arguments, as first-class
functions, so it knows nothing of either; it runs a method until the end of the interval, an event
(:func:`.events.locate`), a failure, or a pause (after a step budget, or at
``F_TPAUSE``) at which :func:`integrate` returns to Python for progress and the deadline and
calls it again. With ``compiled=False`` the same source runs as Python (the ``numpy`` backend):
then any Python callables serve as method and problem, which is how SciPy's solvers are driven
(:mod:`.scipy_methods`).

Signatures (``P`` the type of ``p``)::

    rhs(t, y, out, p)                      writes dy/dt into out
    event(t, y, p) -> (float, float, float)
                                           the event function (before ``sign``), its time
                                           derivative along solutions and a bound of that
                                           derivative's size over about a step (``inf``: none known)
    init(rhs, p, W, fst, ist)              first evaluation and step size
    step(rhs, p, W, fst, ist) -> bool      one accepted step; False if the step size underflows
    dense(rhs, p, W, fst, ist, t, out)     dense output of the last step at t
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from lubelink._jit import ENABLED, kernel
from ._layout import (EVENT, F_BOLD, F_DIR, F_GOLD, F_DOLD, F_HSTEP, F_MAXSTEP, F_RES, F_T, F_TBEFORE, F_TEND, F_TFINAL,
                      F_TOLD, F_TPAUSE, F_TSTOP, FAIL_NONFINITE, FAIL_RHS, FAIL_SMALL_STEP, FAILED, FINISHED, R_ATOL, R_RTOL,
                      R_Y, R_YBEFORE, R_YFINAL, R_YOLD, RUNNING, S_ARMED, S_EVENT, S_FAIL, S_IEVAL, S_INIT,
                      S_MAXSTEPS, S_SAMPLE, S_NFEV, S_NREJ, S_NSTEPS)
from .control import EPS, TOO_SMALL_STEP
from .events import locate

__all__ = ["Segment", "Problem", "Options", "Method", "integrate", "advance", "first_class", "precompile",
           "STEPS_PER_CALL", "BUDGETS"]

#: Steps of the first call into compiled code of a kind not yet timed; later calls take as many as
#: fill :data:`CALL_SECONDS`, at least one. One step first, so that a step of minutes (a 2-D film on
#: a fine grid) is timed before a budget is chosen: the deadline and Ctrl-C then act after at most
#: about one step, and a cheap kind pays one extra call (about 50 us).
STEPS_PER_CALL = 1
#: The step budget of a call into compiled code that the last integration of a kind measured, by
#: ``(method name, id(Numba type of p))``: the next one of that kind (the next segment of a run, a run
#: like an earlier one) starts with it, so a short segment takes one call (each costs about 50 us to
#: convert the arguments) instead of a first one of :data:`STEPS_PER_CALL` steps. Numba's types are
#: interned, so their identities stay unique.
BUDGETS: dict = {}
#: Wall time of one call into compiled code [s] between returns to Python (deadline, progress).
CALL_SECONDS = 0.05
#: With a progress callback, calls end at least every this fraction of the interval (a deadline
#: needs no more than the returns every :data:`CALL_SECONDS`: each return costs a fraction of a millisecond).
PROGRESS_FRACTION = 0.01


@dataclass
class Segment:
    """Outcome of integrating from ``t0`` up to ``t_end`` or the first event.

    ``status``: ``"finished"`` (reached ``t_end``), ``"event"`` (the event fell to zero; the zero
    lies between ``t_before``, where it is still positive, and ``t_final``), ``"failed"`` or
    ``"timeout"``. ``t``, ``y``: the samples of ``t_eval`` up to the end.
    """

    t: np.ndarray
    y: np.ndarray
    status: str
    message: str
    t_final: float
    y_final: np.ndarray
    t_before: float = np.nan
    y_before: np.ndarray | None = None
    nfev: int = 0
    nsteps: int = 0
    extra: dict = field(default_factory=dict)


@dataclass(frozen=True)
class Problem:
    """What to integrate: ``dy/dt = rhs(t, y)`` with the event ``g`` (signatures in the module docstring).

    ``p`` goes to both (its Numba type ``p_type`` if known: ``numba.typeof`` of a large named tuple
    costs a fraction of a millisecond). ``omega`` [rad/s] and ``zeta`` [-] are the linear part, one
    per oscillator of the state ``[x, x_dot]`` (the exponential methods integrate it exactly);
    ``jacobian`` says that ``rhs`` writes its Jacobian when handed an output of ``n + n^2`` entries
    (RODAS4; else it forms the Jacobian by differences).
    """

    rhs: object
    event: object
    p: object
    p_type: object = None
    omega: object = None
    zeta: object = 0.0
    jacobian: bool = False


@dataclass(frozen=True)
class Options:
    """How to integrate: tolerances (``rtol``, ``atol``, scalars or per component), the largest step,
    the longest interval between two samples of the event inside a step (``event_resolution``, None:
    the step), a ``time.perf_counter()`` ``deadline`` (status ``"timeout"``), whether the loop runs
    ``compiled`` (kernels as first-class functions) or as Python (the method's ``py_func``), and the
    method's own settings (``method``, e.g. Bulirsch-Stoer's ``max_order``)."""

    rtol: object = 1e-3
    atol: object = 1e-6
    max_step: float = np.inf
    event_resolution: float | None = None
    deadline: float | None = None
    compiled: bool = ENABLED
    method: dict = field(default_factory=dict)


@dataclass(frozen=True)
class Method:
    """An integration method: its kernels, the rows of ``W`` it needs, and how it is set up.

    ``setup(W, fst, ist, settings)`` fills the method's own slots before the first call from
    ``settings``: the problem's ``omega``, ``zeta`` and ``jacobian`` and the options' ``method`` dict.
    """

    name: str
    init: object
    step: object
    dense: object
    rows: object
    floats: int = 32
    ints: int = 16
    setup: object = None


@kernel
def advance(init, step, dense, rhs, event, p, sign, t_eval, out, W, fst, ist):
    """Integrate until the end, an event, a failure or a pause; returns ``RUNNING``, ``FINISHED``, ``EVENT`` or ``FAILED``.

    Samples of ``t_eval`` are written to ``out`` from row ``ist[S_IEVAL]`` on.
    """
    n = W.shape[1]
    if ist[S_INIT] == 0:
        ist[S_INIT] = 1
        init(rhs, p, W, fst, ist)
        if ist[S_EVENT] != 0:
            g, d, bound = event(fst[F_T], W[R_Y], p)
            fst[F_GOLD] = sign * g
            fst[F_DOLD] = sign * d
            fst[F_BOLD] = bound
            ist[S_ARMED] = 1 if fst[F_GOLD] > 0.0 else 0
        if fst[F_T] >= fst[F_TEND]:
            fst[F_TFINAL] = fst[F_T]
            for m in range(n):
                W[R_YFINAL, m] = W[R_Y, m]
            return FINISHED
    steps = 0
    n_eval = t_eval.shape[0]
    while True:
        if fst[F_T] >= fst[F_TPAUSE] or steps >= ist[S_MAXSTEPS]:
            return RUNNING
        t_old = fst[F_T]
        ok = step(rhs, p, W, fst, ist)
        steps += 1
        if not ok:
            if ist[S_FAIL] == 0:
                ist[S_FAIL] = FAIL_SMALL_STEP
            fst[F_TFINAL] = t_old
            for m in range(n):
                W[R_YFINAL, m] = W[R_Y, m]
            return FAILED
        ist[S_NSTEPS] += 1
        t_new = fst[F_T]
        for m in range(n):
            if not np.isfinite(W[R_Y, m]):
                ist[S_FAIL] = FAIL_NONFINITE
                fst[F_TFINAL] = t_old
                for k in range(n):
                    W[R_YFINAL, k] = W[R_YOLD, k]
                return FAILED
        hit = False
        if ist[S_EVENT] != 0:
            if ist[S_ARMED] != 0:
                hit = locate(dense, rhs, event, p, sign, W, fst, ist, t_old, t_new)
            else:
                g, d, bound = event(t_new, W[R_Y], p)
                fst[F_GOLD] = sign * g
                fst[F_DOLD] = sign * d
                fst[F_BOLD] = bound
                ist[S_ARMED] = 1 if fst[F_GOLD] > 0.0 else 0
        t_stop = fst[F_TFINAL] if hit else t_new
        i = ist[S_IEVAL]
        ist[S_SAMPLE] = 1
        while i < n_eval and t_eval[i] <= t_stop:
            if t_eval[i] == t_new:
                for m in range(n):
                    out[i, m] = W[R_Y, m]
            else:
                dense(rhs, p, W, fst, ist, t_eval[i], out[i])
            i += 1
        ist[S_SAMPLE] = 0
        ist[S_IEVAL] = i
        fst[F_TSTOP] = t_stop
        if hit:
            return EVENT
        if t_new >= fst[F_TEND]:
            fst[F_TFINAL] = t_new
            for m in range(n):
                W[R_YFINAL, m] = W[R_Y, m]
            return FINISHED


@kernel
def no_event(t, y, p):
    """An event that never happens (for segments that watch none)."""
    return 1.0, 0.0, 0.0


# --- first-class functions ------------------------------------------------------------------------
_lock = threading.Lock()
_first_class_cache = {}


@lru_cache(maxsize=1)
def _first_class_type():
    """The class of first-class function objects, with its Numba type computed once per object."""
    from numba import types
    from numba.extending import typeof_impl

    class FirstClass(types.CompileResultWAP):
        def __init__(self, cres):
            super().__init__(cres)
            self.numba_type = types.FunctionType(cres.signature)

    @typeof_impl.register(FirstClass)
    def _typeof(val, c):
        return val.numba_type

    return FirstClass


def first_class(dispatcher, sig):
    """``dispatcher`` compiled for ``sig`` as a first-class function object (cached), for :func:`advance`.

    Passing a dispatcher itself would make Numba compile :func:`advance` for that dispatcher's
    type, which it cannot cache on disk; a first-class function type it can.
    """
    key = (id(dispatcher), id(sig))  # identities: hashing a signature hashes the whole parameter type
    with _lock:
        held = _first_class_cache.get(key)
        if held is None:
            dispatcher.compile(sig.args)
            held = _first_class_cache[key] = (dispatcher, sig, _first_class_type()(dispatcher.overloads[sig.args]))
        return held[2]


def _by_identity(func):
    """Cache ``func(arg)`` by the identity of ``arg`` (a Numba type, or a tuple of them: types are
    interned, and hashing a large tuple type walks all of it), holding ``arg`` so that identities stay unique."""
    cache = {}

    def cached(arg):
        key = tuple(map(id, arg)) if isinstance(arg, tuple) else id(arg)
        held = cache.get(key)
        if held is None:
            with _lock:
                held = cache[key] = (arg, func(arg))
        return held[1]

    cached.__wrapped__ = func
    cached.__doc__ = func.__doc__
    return cached


@_by_identity
def signatures(p_type):
    """Numba signatures of ``(rhs, event, init, step, dense)`` for parameters of type ``p_type``."""
    from numba import types

    f8, i8 = types.float64, types.int64
    vec, mat, ivec = f8[::1], f8[:, ::1], i8[::1]
    rhs = types.void(f8, vec, vec, p_type)
    event = types.UniTuple(f8, 3)(f8, vec, p_type)
    fr = types.FunctionType(rhs)
    init = types.void(fr, p_type, mat, vec, ivec)
    step = types.boolean(fr, p_type, mat, vec, ivec)
    dense = types.void(fr, p_type, mat, vec, ivec, f8, vec)
    return rhs, event, init, step, dense


def _advance_types(types_head):
    """The argument types of :func:`advance` after those of its kernels and parameters ``types_head``."""
    from numba import types

    f8, i8 = types.float64, types.int64
    return types_head + (f8, f8[::1], f8[:, ::1], f8[:, ::1], f8[::1], i8[::1])


def _types_head(p_type):
    """The types of :func:`advance`'s kernels (``init``, ``step``, ``dense``, ``rhs``, ``event``) and parameters."""
    from numba import types

    sigs = signatures(p_type)
    return tuple(types.FunctionType(s) for s in (sigs[2], sigs[3], sigs[4], sigs[0], sigs[1])) + (p_type,)


def advance_types(p_type):
    """The argument types :func:`advance` is compiled for with any method and parameters of type ``p_type``."""
    return _advance_types(_types_head(p_type))


@_by_identity
def _entry_point(types_head):
    """:func:`advance` compiled for these argument types, called without Numba's type dispatch."""
    argtypes = _advance_types(types_head)
    advance.compile(argtypes)
    return advance.overloads[argtypes].entry_point


def precompile(method, p_type):
    """Compile ``method``'s kernels and :func:`advance` for parameters of type ``p_type``.

    Only the types of the right-hand side and of the event are needed, not their machine code: a
    cold start compiles this half while another process compiles the model's kernels.
    """
    sigs = signatures(p_type)
    for func, sig in zip((method.init, method.step, method.dense), sigs[2:]):
        first_class(func, sig)
    _entry_point(_types_head(p_type))


# --- the Python side of a segment -------------------------------------------------------------------
def _first_budget(key, deadline):
    """Steps of the first call into compiled code: the budget :data:`BUDGETS` holds for ``key``, at most
    :data:`STEPS_PER_CALL` before a deadline nearer than :data:`CALL_SECONDS` (its return checks it)."""
    steps = BUDGETS.get(key, STEPS_PER_CALL)
    near = deadline is not None and deadline - time.perf_counter() <= CALL_SECONDS
    return min(steps, STEPS_PER_CALL) if near else steps


def integrate(method, problem, t0, y0, t_end, t_eval, options=None, *, event_sign=0, progress=None):
    """Integrate ``problem`` from ``t0`` to ``t_end`` or the first zero of ``-event_sign * g``.

    Parameters
    ----------
    method : Method
        The integrator.
    problem : Problem
        Right-hand side, event, parameters and linear part. Kernels (``@kernel``) when compiled;
        else anything callable from Python (a kernel then runs compiled, its ``py_func`` as Python).
    t0, t_end : float
        Interval, ``t_end >= t0``.
    y0 : array_like, shape ``(n,)``
        Initial state.
    t_eval : array_like
        Increasing sample times in ``(t0, t_end]``.
    options : Options, optional
        Tolerances, largest step, event resolution, deadline, backend, the method's settings.
    event_sign : {-1, 0, 1}
        0: no event (``problem.event`` is ignored); ``-1``: the event is ``g`` falling to zero;
        ``+1``: ``-g`` falling to zero (``g`` rising to zero).
    progress : callable, optional
        ``progress(t)``, called at every return to Python.

    Returns
    -------
    Segment
    """
    o = Options() if options is None else options
    rhs, event, p, compiled = problem.rhs, problem.event, problem.p, o.compiled
    t_end = float(t_end)
    y0 = np.asarray(y0)
    n = y0.size
    dtype = y0.dtype if np.iscomplexobj(y0) else np.float64
    t_eval = np.ascontiguousarray(t_eval, dtype=float)
    W = np.zeros((method.rows(n), n), dtype=dtype)
    W[R_Y] = y0
    W[R_ATOL] = np.broadcast_to(np.asarray(o.atol, dtype=float), (n,))
    W[R_RTOL] = np.maximum(np.broadcast_to(np.asarray(o.rtol, dtype=float), (n,)), 100 * EPS)
    fst = np.zeros(method.floats)
    fst[F_T] = t0
    fst[F_TEND] = t_end
    fst[F_DIR] = 1.0
    fst[F_MAXSTEP] = o.max_step
    fst[F_RES] = o.event_resolution or 0.0
    fst[F_TSTOP] = t0
    fst[F_TFINAL] = t0
    ist = np.zeros(method.ints, dtype=np.int64)
    ist[S_EVENT] = int(event_sign != 0)
    if method.setup is not None:
        settings = {"zeta": problem.zeta, "jacobian": problem.jacobian, **o.method}
        if problem.omega is not None:
            settings["omega"] = problem.omega
        method.setup(W, fst, ist, settings)
    out = np.empty((t_eval.size, n), dtype=dtype)
    sign = -float(event_sign) if event_sign else 1.0
    if event_sign == 0:
        event = no_event if compiled else no_event.py_func
    key = None
    if compiled:
        import numba

        p_type = numba.typeof(p) if problem.p_type is None else problem.p_type
        sigs = signatures(p_type)
        args = (first_class(method.init, sigs[2]), first_class(method.step, sigs[3]),
                first_class(method.dense, sigs[4]), first_class(rhs, sigs[0]), first_class(event, sigs[1]))
        run = _entry_point(tuple(a.numba_type for a in args) + (p_type,))
        key = (method.name, id(p_type))
        ist[S_MAXSTEPS] = _first_budget(key, o.deadline)
    else:
        args = tuple(getattr(f, "py_func", f) for f in (method.init, method.step, method.dense)) + (rhs, event)
        run = advance.py_func
        ist[S_MAXSTEPS] = STEPS_PER_CALL
    deadline = o.deadline
    chunk = (t_end - t0) * PROGRESS_FRACTION if progress is not None else np.inf
    status, message = "finished", "reached the end of the interval"
    while True:
        fst[F_TPAUSE] = min(fst[F_T] + chunk, t_end)
        began, steps = time.perf_counter(), ist[S_NSTEPS]
        code = run(*args, p, sign, t_eval, out, W, fst, ist)
        if progress is not None:
            progress(float(fst[F_TSTOP]))
        if code == RUNNING:
            taken = max(int(ist[S_NSTEPS] - steps), 1)
            elapsed = max(time.perf_counter() - began, 1e-6)
            seconds = CALL_SECONDS if deadline is None else min(CALL_SECONDS, deadline - time.perf_counter())
            ist[S_MAXSTEPS] = int(min(max(taken * seconds / elapsed, 1), 1_000_000))  # (a deadline: it returns there)
            if deadline is not None and time.perf_counter() > deadline:
                status, message = "timeout", f"the wall-time budget ran out at t = {fst[F_T]:.9g} s"
                fst[F_TFINAL] = fst[F_T]
                W[R_YFINAL] = W[R_Y]
                break
            continue
        if code == EVENT:
            status, message = "event", f"event at t = {fst[F_TFINAL]:.12g} s"
        elif code == FAILED:
            status = "failed"
            if ist[S_FAIL] == FAIL_NONFINITE:
                message = f"the state became non-finite at t = {fst[F_T]:.9g} s"
            elif ist[S_FAIL] == FAIL_RHS:
                message = (f"the right-hand side is not finite just after t = {fst[F_TFINAL]:.9g} s (a load or "
                           "the prescribed motion returned NaN or infinity)")
            else:
                message = f"{method.name} failed at t = {fst[F_TFINAL]:.9g} s: {TOO_SMALL_STEP}"
        break
    if key is not None:
        BUDGETS[key] = int(ist[S_MAXSTEPS])
    m = int(ist[S_IEVAL])
    return Segment(
        t=t_eval[:m].copy(), y=out[:m], status=status, message=message, t_final=float(fst[F_TFINAL]),
        y_final=W[R_YFINAL].copy(), t_before=float(fst[F_TBEFORE]) if status == "event" else np.nan,
        y_before=W[R_YBEFORE].copy() if status == "event" else None, nfev=int(ist[S_NFEV]),
        nsteps=int(ist[S_NSTEPS]),
        extra={"last_step": float(fst[F_HSTEP]), "n_rejected": int(ist[S_NREJ]), "compiled": compiled,
               "t_old": float(fst[F_TOLD]), "steps_per_call": int(ist[S_MAXSTEPS])},
    )

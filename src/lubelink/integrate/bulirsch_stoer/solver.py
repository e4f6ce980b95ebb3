"""The SciPy face of the Gragg-Bulirsch-Stoer method: an :class:`scipy.integrate.OdeSolver`.

A thin wrapper that runs the kernels of :mod:`.kernels` as Python on the user's function, so that
``solve_ivp(fun, t_span, y0, method=BulirschStoer)`` and lubelink's compiled driver take the
same steps.
"""

from __future__ import annotations

import warnings

import numpy as np
from scipy.integrate import DenseOutput, OdeSolver

from lubelink.integrate._layout import (F_DIR, F_H, F_HSTEP, F_MAXSTEP, F_T, F_TEND, F_TOLD, R_ATOL, R_F, R_FOLD, R_RTOL, R_Y, R_YOLD, S_DENSE,
                       S_NREJ)
from lubelink.integrate.control import EPS, TOO_SMALL_STEP
from .kernels import _coefficients, init, step
from .tables import (DEFAULT_MAX_ORDER, FLOATS, INTS, KMAX, R_COEF, S_DENSECONTROL, S_K, S_KC, S_MU, S_NACC, rows,
                     setup)

__all__ = ["BulirschStoer", "GBSDenseOutput"]


def _validate_tol(rtol, atol, n):
    """Check ``rtol`` and ``atol`` as SciPy does, raising ``ValueError`` on bad input.

    ``rtol`` below ``100 * eps`` is raised to it with a warning (as SciPy); negative or
    non-finite values and wrong shapes are errors.
    """
    checked = []
    for name, tol in (("rtol", rtol), ("atol", atol)):
        tol = np.asarray(tol, dtype=float)
        if tol.ndim > 0 and tol.shape != (n,):
            raise ValueError(f"`{name}` must be a scalar or have shape ({n},), got shape {tol.shape}.")
        if not np.all(np.isfinite(tol)) or np.any(tol < 0):
            raise ValueError(f"`{name}` must be finite and non-negative, got {tol!r}.")
        checked.append(tol)
    rtol, atol = checked
    if np.any(rtol < 100 * EPS):
        warnings.warn(f"At least one element of `rtol` is too small. Setting `rtol = "
                      f"np.maximum(rtol, {100 * EPS})`.", stacklevel=3)
        rtol = np.maximum(rtol, 100 * EPS)
    return rtol, atol


def _validate_order(value, name, low, high):
    if isinstance(value, bool) or int(value) != value or not low <= value <= high:
        raise ValueError(f"`{name}` must be an integer in [{low}, {high}], got {value!r}.")
    return int(value)


class GBSDenseOutput(DenseOutput):
    """Polynomial interpolant over one GBS step: coefficients in powers of ``u = 2 (t - t_old) / H - 1``."""

    def __init__(self, t_old, t, coeffs):
        super().__init__(t_old, t)
        self.h = t - t_old
        self.coeffs = coeffs

    def _call_impl(self, t):
        u = 2.0 * (np.asarray(t) - self.t_old) / self.h - 1.0
        y = np.multiply.outer(np.ones_like(u), self.coeffs[-1]).T if u.ndim else self.coeffs[-1].copy()
        for c in self.coeffs[-2::-1]:
            y = y * u + (c[:, None] if u.ndim else c)
        return y


class BulirschStoer(OdeSolver):
    """GBS extrapolation method with order and step-size control and dense output.

    See the module docstring for the method and references. Use it like the SciPy solvers, e.g.
    ``solve_ivp(fun, t_span, y0, method=BulirschStoer, rtol=1e-10, atol=1e-12, dense_output=True,
    events=...)``; integration in either time direction is supported. It runs the kernels that
    lubelink's compiled driver runs, as Python.

    At high order the steps are long (a few per oscillation period). Event detection by sign
    changes at step ends (``solve_ivp``'s way) then misses an event function that crosses zero
    twice within one step; bound ``max_step`` where that matters.

    Parameters
    ----------
    fun : callable
        Right-hand side ``fun(t, y) -> array_like, shape (n,)``.
    t0 : float
        Initial time.
    y0 : array_like, shape (n,)
        Initial state (real or complex).
    t_bound : float
        Boundary time; the integration does not go beyond it.
    rtol, atol : float or array_like, shape (n,), optional
        Tolerances: a step is accepted when the RMS norm of
        ``error / (atol + rtol * max(|y_old|, |y_new|))`` is at most 1.
    max_step : float, optional
        Largest allowed step size.
    first_step : float, optional
        Initial step size (the fixed step size if ``adaptive=False``). Chosen automatically if
        omitted.
    vectorized : bool, optional
        Whether ``fun`` is vectorized (only passed to the base class).
    max_order : int, optional
        Maximal number of extrapolation columns ``k`` (method order ``2k``), from 3 to 12.
        Default 9 (as ODEX).
    fixed_order : int, optional
        Use exactly ``k = fixed_order`` columns in every step (no order control; the step size is
        still controlled if ``adaptive``).
    adaptive : bool, optional
        If False, take fixed steps of size ``first_step`` with ``fixed_order`` columns and no
        error control (for convergence studies). Default True.
    dense_error_control : bool, optional
        Reject steps whose dense-output error estimate is too large (ODEX does this). Default True.
    **extraneous
        Ignored, with a warning.

    Attributes
    ----------
    order : int
        Number of extrapolation columns ``k`` used in the last accepted step (before the first
        step: the initial choice). The method order is ``2 * order``.
    max_order : int
        Maximal number of columns.
    h_abs : float
        Size of the next step to try.
    nfev, njev, nlu : int
        Function evaluations (counted by the base class); ``njev = nlu = 0``.
    n_accepted, n_rejected : int
        Accepted steps, and rejected step attempts.
    y_old : ndarray or None
        State at the start of the last step.
    """

    def __init__(self, fun, t0, y0, t_bound, rtol=1e-3, atol=1e-6, max_step=np.inf, first_step=None,
                 vectorized=False, max_order=DEFAULT_MAX_ORDER, fixed_order=None, adaptive=True,
                 dense_error_control=True, **extraneous):
        if extraneous:
            warnings.warn("The following arguments have no effect for BulirschStoer: "
                          + ", ".join(f"`{x}`" for x in extraneous) + ".", stacklevel=2)
        super().__init__(fun, t0, y0, t_bound, vectorized, support_complex=True)
        self.rtol, self.atol = _validate_tol(rtol, atol, self.n)
        if not max_step > 0:
            raise ValueError(f"`max_step` must be positive, got {max_step!r}.")
        self.max_step = max_step
        self.max_order = _validate_order(max_order, "max_order", 3, KMAX)
        self.adaptive = bool(adaptive)
        low = 2 if self.adaptive else 1
        self.fixed_order = None if fixed_order is None else _validate_order(fixed_order, "fixed_order", low,
                                                                           self.max_order)
        if not self.adaptive and (first_step is None or self.fixed_order is None):
            raise ValueError("`adaptive=False` needs `first_step` and `fixed_order`.")
        interval = abs(t_bound - t0)
        if first_step is not None and not 0 < first_step <= interval:
            raise ValueError(f"`first_step` must be in (0, |t_bound - t0|] = (0, {interval}], got {first_step!r}.")
        self.y_old = None
        self._W = np.zeros((rows(self.n), self.n), dtype=self.y.dtype)
        self._W[R_Y] = self.y
        self._W[R_ATOL] = np.broadcast_to(self.atol, (self.n,))
        self._W[R_RTOL] = np.broadcast_to(self.rtol, (self.n,))
        self._fst = np.zeros(FLOATS)
        self._fst[F_T], self._fst[F_TEND], self._fst[F_DIR] = t0, t_bound, self.direction
        self._fst[F_MAXSTEP] = max_step
        self._ist = np.zeros(INTS, dtype=np.int64)
        setup(self._W, self._fst, self._ist, {"max_order": self.max_order, "fixed_order": self.fixed_order,
                                              "adaptive": self.adaptive, "first_step": first_step,
                                              "dense_error_control": dense_error_control})
        self.dense_error_control = bool(self._ist[S_DENSECONTROL])

        def rhs(t, y, out, p):
            out[:] = self.fun(t, y)

        self._rhs = rhs
        init.py_func(rhs, None, self._W, self._fst, self._ist)
        self.f = self._W[R_F].copy()
        self.order = int(self._ist[S_K])

    @property
    def h_abs(self):
        return float(self._fst[F_H])

    @property
    def n_accepted(self):
        return int(self._ist[S_NACC])

    @property
    def n_rejected(self):
        return int(self._ist[S_NREJ])

    def _step_impl(self):
        if not step.py_func(self._rhs, None, self._W, self._fst, self._ist):
            return False, TOO_SMALL_STEP
        self.y_old = self._W[R_YOLD].copy()
        self.t = float(self._fst[F_T])
        self.y = self._W[R_Y].copy()
        self.f = self._W[R_F].copy()
        self.order = int(self._ist[S_KC])
        return True, None

    def _dense_output_impl(self):
        if self._ist[S_DENSE] == 0:
            _coefficients(self._W, self._ist, R_YOLD, R_Y, R_FOLD, R_F, self._fst[F_HSTEP], self._ist[S_KC])
        coeffs = self._W[R_COEF:R_COEF + self._ist[S_MU] + 5].copy()
        return GBSDenseOutput(float(self._fst[F_TOLD]), self.t, coeffs)

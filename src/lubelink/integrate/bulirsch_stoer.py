"""Gragg-Bulirsch-Stoer (GBS) extrapolation integrator with step-size and order control.

Why this module exists
----------------------
No maintained Python library offers a Bulirsch-Stoer integrator: SciPy's
``solve_ivp`` has explicit Runge-Kutta (RK23, RK45, DOP853), Radau, BDF and
LSODA only. :class:`BulirschStoer` is therefore written by hand, as a
:class:`scipy.integrate.OdeSolver` subclass, so that it plugs into
``scipy.integrate.solve_ivp(..., method=BulirschStoer)`` with events,
``t_eval`` and dense output like the built-in methods. It knows nothing of the
problem it integrates.

Method
------
A step of size ``H`` from ``(t0, y0)`` runs the explicit midpoint rule with
``n_j`` substeps of size ``h_j = H / n_j`` (Gragg's method, ending with his
smoothing step) for ``j = 1, 2, ...``. The result ``T_j1`` has an error
expansion in even powers of ``h_j``, so Aitken-Neville extrapolation to
``h = 0`` gives ``T_jj`` of order ``2j``. The error of ``T_jj`` is estimated
by ``T_jj - T_j,j-1`` in SciPy's norm::

    err_j = rms((T_jj - T_j,j-1) / (atol + rtol * max(|y0|, |T_jj|)))

and the step is accepted when ``err_j <= 1``.

Order and step size follow the ODEX strategy of Hairer, Norsett & Wanner [1]_
(Section II.9), which refines Deuflhard's [2]_: every column ``j`` proposes a
step ``H_j`` from ``err_j``; the number of columns ``k`` for the next step is
the one with the least work per unit step ``W_j = A_j / H_j`` (``A_j`` is the
number of function evaluations for ``j`` columns), changed by at most one per
step; within a step a convergence monitor over the order window
``k - 1, k, k + 1`` accepts early, or rejects as soon as convergence by column
``k + 1`` is improbable. Divergence of the tableau and a stability check on
the first midpoint substeps halve the step.

Step-number sequence
--------------------
``n_j = 4j - 2 = 2, 6, 10, 14, ...`` instead of the harmonic ``2, 4, 6, 8``.
It grows linearly like the harmonic one, but all midpoint indices ``n_j / 2``
are odd. The dense output extrapolates values at the midpoint of the step,
and the GBS error expansion at grid point ``i`` depends on the parity of
``i``, so they must share a parity: ``2, 4, 6, 8`` mixes them. ODEX makes the
same choice whenever dense output is requested; ``solve_ivp`` needs the
dense output for events and ``t_eval``, so this class always uses it.

Dense output
------------
As in ODEX (Hairer-Norsett-Wanner II.9, "Dense output for the GBS method"):
the midpoint values ``y^(n_j/2)`` are extrapolated to ``y(t_mid)``, and
central differences (stride ``2 h_j``) of the stored ``f`` values around the
midpoint, extrapolated over the sequences that reach far enough, give
``H^kappa y^(kappa)(t_mid)`` for ``kappa = 1 ... mu`` with ``mu = 2k - 3``.
The interpolant is the polynomial of degree ``mu + 4`` that also matches
``y`` and ``H f`` at both ends of the step. Its local error is ``O(H^(2k))``,
one power of ``H`` less than the step's (the midpoint values, at odd grid
indices, carry an error term that does not vanish at ``t0``): measured
slopes 4.1 for ``k = 2`` and 6.0 for ``k = 3``, so the interpolant is of
order ``2k - 1 >= 5`` once ``k >= 3``. The difference to the interpolant of
one degree less estimates the interpolation error, and a step whose
estimate exceeds ten times the tolerance is rejected, as in ODEX; this
keeps the dense output within a small multiple of the tolerance at any
order. No function evaluations are added: the ``f`` values are those of the
midpoint sequences, and ``f(t1, y1)`` is reused as ``f0`` of the next step.

References
----------
.. [1] E. Hairer, S. P. Norsett, G. Wanner, "Solving Ordinary Differential
       Equations I: Nonstiff Problems", 2nd ed., Springer, 1993, Section II.9
       (the ODEX code).
.. [2] P. Deuflhard, "Order and stepsize control in extrapolation methods",
       Numer. Math. 41 (1983), 399-422.
"""

from __future__ import annotations

import math
import warnings
from functools import lru_cache

import numpy as np
from scipy.integrate import DenseOutput, OdeSolver

__all__ = ["BulirschStoer", "GBSDenseOutput", "step_number_sequence"]

EPS = np.finfo(float).eps

DEFAULT_MAX_ORDER = 9  # columns of the tableau, as ODEX's default KM = 9

# ODEX defaults (Hairer-Norsett-Wanner II.9).
_FAC1 = 0.02  # H_j / H is kept within [fac1**e / fac2, fac1**-e], e = 1/(2j-1)
_FAC2 = 4.0
_FAC3 = 0.8  # fewer columns if W_{k-1} < fac3 * W_k
_FAC4 = 0.9  # more columns if W_k < fac4 * W_{k-1}
_SAFE1 = 0.65  # H_j = H * safe2 * (safe1 / err_j)**(1/(2j-1))
_SAFE2 = 0.94
_SAFE3 = 0.5  # step reduction after divergence or failed stability check
_STAB_COLUMNS = 2  # the stability check runs in the first two sequences
_MU_DIFF = 4  # interpolant uses midpoint derivatives up to mu = 2k - _MU_DIFF + 1
_DENSE_REJECT = 10.0  # reject a step whose interpolation error exceeds this

TOO_SMALL_STEP = "Required step size is less than spacing between numbers."


class _Diverged(Exception):
    """The extrapolation tableau diverges or the midpoint rule is unstable."""


def step_number_sequence(max_order):
    """Substep numbers ``n_j = 4j - 2`` for ``j = 1 ... max_order``.

    Parameters
    ----------
    max_order : int
        Number of extrapolation columns.

    Returns
    -------
    ndarray of int
    """
    return 4 * np.arange(1, max_order + 1) - 2


def _extrapolation_weights(n):
    """Weights ``c`` such that ``sum_j c_j T_j`` is the value at ``h = 0``.

    ``T_j`` are samples at ``h_j = H / n_j`` of a polynomial in ``h**2``;
    ``c_j`` is the Lagrange basis polynomial ``L_j(0)`` in ``x = h**2``.
    """
    n2 = np.asarray(n, dtype=float) ** 2
    weights = np.empty(n2.size)
    for j, nj2 in enumerate(n2):
        others = np.delete(n2, j)
        weights[j] = np.prod(nj2 / (nj2 - others))
    return weights


def _difference_operator(n, rows):
    """Rows ``p = 0 ... rows-1``: ``(n/2)**p * delta**p f`` at the midpoint ``n/2``.

    ``delta g_i = g_(i+1) - g_(i-1)`` (stride two, so that only grid points of
    one parity enter). Times ``H`` this approximates ``H^(p+1) y^(p+1)`` at the
    midpoint of the step.
    """
    m = n // 2
    op = np.zeros((rows, n + 1))
    for p in range(rows):
        for l in range(p + 1):
            op[p, m + p - 2 * l] += (-1) ** l * math.comb(p, l)
        op[p] *= (n / 2) ** p
    return op


def _hermite_inverse(mu):
    """Inverse of the end conditions for ``u**(mu+1) * (a0 + a1 u + a2 u**2 + a3 u**3)``.

    Rows: value at ``u = -1``, value at ``u = +1``, derivative at ``-1``, at ``+1``.
    """
    powers = mu + 1 + np.arange(4)
    matrix = np.array([
        (-1.0) ** powers,
        np.ones(4),
        powers * (-1.0) ** (powers - 1),
        powers.astype(float),
    ])
    return np.linalg.inv(matrix)


def _max_error_shape(mu):
    """``max |u**mu (1 - u**2)**2|`` on ``[-1, 1]``."""
    if mu == 0:
        return 1.0
    v = mu / (mu + 4.0)
    return v ** (mu / 2.0) * (1.0 - v) ** 2


class _Tables:
    """Constants of the method for a given maximal number of columns."""

    def __init__(self, max_order):
        self.nseq = step_number_sequence(max_order)
        n_mu = 2 * max_order + 1
        # work A_j (1-based, index 0 unused): f0 plus n_i evaluations per sequence i <= j
        self.work = np.concatenate(([0.0], 1.0 + np.cumsum(self.nseq)))
        self.weights = {
            (a, b): _extrapolation_weights(self.nseq[a:b])
            for b in range(1, max_order + 1) for a in range(b)
        }
        self.diff_ops = [_difference_operator(int(n), 2 * (j + 1)) for j, n in enumerate(self.nseq)]
        self.hermite_inv = [_hermite_inverse(mu) for mu in range(n_mu)]
        self.taylor = np.array([1.0 / (math.factorial(i) * 2.0 ** i) for i in range(n_mu)])
        self.error_shape = np.array([_max_error_shape(mu) for mu in range(n_mu)])


@lru_cache(maxsize=None)
def _tables(max_order):
    return _Tables(max_order)


def _rms(x):
    return np.linalg.norm(x) / math.sqrt(x.size)


def _validate_tol(rtol, atol, n):
    """Check ``rtol`` and ``atol`` as SciPy does, raising ``ValueError`` on bad input.

    ``rtol`` below ``100 * eps`` is raised to it with a warning (as SciPy);
    negative or non-finite values and wrong shapes are errors.
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
    """Polynomial interpolant over one GBS step.

    Parameters
    ----------
    t_old, t : float
        Start and end of the step.
    coeffs : ndarray, shape (degree + 1, n)
        Coefficients in powers of ``u = 2 (t - t_old) / (t - t_old) - 1``,
        i.e. ``u = -1`` at ``t_old`` and ``u = 1`` at ``t``.
    """

    def __init__(self, t_old, t, coeffs):
        super().__init__(t_old, t)
        self.h = t - t_old
        self.coeffs = coeffs

    def _call_impl(self, t):
        u = 2.0 * (t - self.t_old) / self.h - 1.0
        if u.ndim == 0:
            y = self.coeffs[-1].copy()
            for c in self.coeffs[-2::-1]:
                y *= u
                y += c
            return y
        y = np.repeat(self.coeffs[-1][:, None], u.size, axis=1)
        for c in self.coeffs[-2::-1]:
            y *= u
            y += c[:, None]
        return y


class BulirschStoer(OdeSolver):
    """GBS extrapolation method with order and step-size control and dense output.

    See the module docstring for the method and references. Use it like the
    SciPy solvers, e.g. ``solve_ivp(fun, t_span, y0, method=BulirschStoer,
    rtol=1e-10, atol=1e-12, dense_output=True, events=...)``; integration in
    either time direction is supported.

    At high order the steps are long (a few per oscillation period). Event
    detection by sign changes at step ends (``solve_ivp``'s way) then misses
    an event function that crosses zero twice within one step; bound
    ``max_step`` where that matters.

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
        Initial step size (the fixed step size if ``adaptive=False``).
        Chosen automatically if omitted.
    vectorized : bool, optional
        Whether ``fun`` is vectorized (only passed to the base class).
    max_order : int, optional
        Maximal number of extrapolation columns ``k`` (method order ``2k``),
        from 3 to 12. Default 9 (as ODEX).
    fixed_order : int, optional
        Use exactly ``k = fixed_order`` columns in every step (no order
        control; the step size is still controlled if ``adaptive``).
    adaptive : bool, optional
        If False, take fixed steps of size ``first_step`` with
        ``fixed_order`` columns and no error control (for convergence
        studies). Default True.
    dense_error_control : bool, optional
        Reject steps whose dense-output error estimate is too large (ODEX
        does this). Default True.
    **extraneous
        Ignored, with a warning.

    Attributes
    ----------
    order : int
        Number of extrapolation columns ``k`` used in the last accepted step
        (before the first step: the initial choice). The method order is
        ``2 * order``.
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

    def __init__(self, fun, t0, y0, t_bound, rtol=1e-3, atol=1e-6, max_step=np.inf,
                 first_step=None, vectorized=False, max_order=DEFAULT_MAX_ORDER,
                 fixed_order=None, adaptive=True, dense_error_control=True, **extraneous):
        if extraneous:
            warnings.warn("The following arguments have no effect for BulirschStoer: "
                          + ", ".join(f"`{x}`" for x in extraneous) + ".", stacklevel=2)
        super().__init__(fun, t0, y0, t_bound, vectorized, support_complex=True)
        self.rtol, self.atol = _validate_tol(rtol, atol, self.n)
        if not max_step > 0:
            raise ValueError(f"`max_step` must be positive, got {max_step!r}.")
        self.max_step = max_step
        self.max_order = _validate_order(max_order, "max_order", 3, 12)
        self.adaptive = bool(adaptive)
        low = 2 if self.adaptive else 1
        self.fixed_order = (None if fixed_order is None
                            else _validate_order(fixed_order, "fixed_order", low, self.max_order))
        if not self.adaptive and (first_step is None or self.fixed_order is None):
            raise ValueError("`adaptive=False` needs `first_step` and `fixed_order`.")
        self.dense_error_control = bool(dense_error_control) and self.adaptive
        self.y_old = None
        self.n_accepted = 0
        self.n_rejected = 0
        self._tab = _tables(self.max_order)
        self._allocate()
        self.f = self.fun(self.t, self.y)
        self.order = self.fixed_order or self._initial_order()
        interval = abs(t_bound - t0)
        if first_step is None:
            self.h_abs = self._initial_step(interval)
        else:
            if not 0 < first_step <= interval:
                raise ValueError(f"`first_step` must be in (0, |t_bound - t0|] = (0, {interval}], "
                                 f"got {first_step!r}.")
            self.h_abs = float(first_step)
        self._k = self.order
        self._h_dense = np.inf
        self._dense = None

    # --- set-up ---------------------------------------------------------

    def _allocate(self):
        nseq = self._tab.nseq
        dtype = self.y.dtype
        offsets = np.concatenate(([0], np.cumsum(nseq + 1)))
        self._fstore = np.empty((offsets[-1], self.n), dtype=dtype)
        self._fseq = [self._fstore[offsets[j]:offsets[j + 1]] for j in range(nseq.size)]
        self._t1 = np.empty((nseq.size, self.n), dtype=dtype)
        self._ymid = np.empty((nseq.size, self.n), dtype=dtype)
        self._ya = np.empty(self.n, dtype=dtype)
        self._yb = np.empty(self.n, dtype=dtype)
        self._tmp = np.empty(self.n, dtype=dtype)
        # 1-based per column: proposed step sizes H_j and work per unit step W_j
        self._hh = np.zeros(self.max_order + 2)
        self._ww = np.zeros(self.max_order + 2)

    def _initial_order(self):
        """ODEX's choice ``k ~ 0.6 * (-log10 rtol) + 1.5``, within ``[2, max_order - 1]``."""
        digits = -math.log10(float(np.min(self.rtol)) + 1e-40)
        return max(2, min(self.max_order - 1, int(digits * 0.6 + 1.5)))

    def _initial_step(self, interval):
        """Hairer-Norsett-Wanner II.4 starting-step heuristic for order ``2k``."""
        if self.n == 0 or interval == 0:
            return min(interval, self.max_step)
        scale = self.atol + np.abs(self.y) * self.rtol
        d0, d1 = _rms(self.y / scale), _rms(self.f / scale)
        h0 = 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1
        h0 = min(h0, interval)
        f1 = self.fun(self.t + self.direction * h0, self.y + self.direction * h0 * self.f)
        d2 = _rms((f1 - self.f) / scale) / h0
        if d1 <= 1e-15 and d2 <= 1e-15:
            h1 = max(1e-6, h0 * 1e-3)
        else:
            h1 = (0.01 / max(d1, d2)) ** (1.0 / (2 * self.order + 1))
        return min(100 * h0, h1, interval, self.max_step)

    # --- one midpoint sequence and the tableau --------------------------

    def _midpoint_sequence(self, j, t, y, h, stability_scale):
        """Gragg's method with ``n_j`` substeps; fills ``T_j1``, ``f`` values, midpoint value.

        ``j`` is 0-based. ``h`` is the signed step. With ``stability_scale``
        the first substep is checked for instability (ODEX's test).
        """
        n = int(self._tab.nseq[j])
        hj = h / n
        fvals = self._fseq[j]
        fvals[0] = self.f
        y_prev, y_cur, tmp = self._ya, self._yb, self._tmp
        y_prev[...] = y
        np.multiply(self.f, hj, out=y_cur)
        y_cur += y
        for i in range(1, n):
            if 2 * i == n:
                self._ymid[j] = y_cur
            fvals[i] = self.fun(t + i * hj, y_cur)
            if i == 1 and stability_scale is not None:
                self._check_stability(fvals[1], stability_scale)
            np.multiply(fvals[i], 2.0 * hj, out=tmp)
            y_prev += tmp
            y_prev, y_cur = y_cur, y_prev
        fvals[n] = self.fun(t + h, y_cur)
        t1 = self._t1[j]
        np.multiply(fvals[n], hj, out=t1)
        t1 += y_prev
        t1 += y_cur
        t1 *= 0.5

    def _check_stability(self, f1, scale):
        base = _rms(self.f / scale) ** 2
        change = _rms((f1 - self.f) / scale) ** 2
        if change > 4.0 * max(base, EPS) or not np.isfinite(change):
            raise _Diverged

    def _column(self, col, t, y, h, checks):
        """Compute column ``col`` (1-based) of the tableau; return ``err_col`` (None for 1).

        Stores ``T_col,col`` in ``self._y_new`` and the proposed step ``H_col``
        and work per unit step ``W_col``.
        """
        stab = self._stability_scale if checks and col <= _STAB_COLUMNS else None
        self._midpoint_sequence(col - 1, t, y, h, stab)
        weights = self._tab.weights
        self._y_new = weights[0, col] @ self._t1[:col]
        if col == 1:
            return None
        lower = weights[1, col] @ self._t1[1:col]
        scale = self.atol + self.rtol * np.maximum(np.abs(y), np.abs(self._y_new))
        err = _rms((self._y_new - lower) / scale)
        if checks:
            if not err * EPS < 1.0 or (col > 2 and err >= self._err_old):
                raise _Diverged
            self._err_old = max(4.0 * err, 1.0)
        expo = 1.0 / (2 * col - 1)
        facmin = _FAC1 ** expo
        fac = min(_FAC2 / facmin, max(facmin, (err / _SAFE1) ** expo / _SAFE2))
        self._hh[col] = min(abs(h) / fac, self.max_step)
        self._ww[col] = self._tab.work[col] / self._hh[col]
        return err

    # --- one attempt ----------------------------------------------------

    def _attempt(self, t, y, h, k, full, reject):
        """Try a step of signed size ``h`` aiming at ``k`` columns.

        Returns ``(accepted, kc)`` with ``kc`` the last column computed.
        ``full`` computes columns 1, 2, ... k and accepts at the first
        converged one (ODEX's first and last step); otherwise the
        convergence monitor over columns ``k - 1, k, k + 1`` decides.
        """
        self._stability_scale = self.atol + self.rtol * np.abs(y)
        nseq = self._tab.nseq
        if full:
            for col in range(1, k + 1):
                err = self._column(col, t, y, h, checks=True)
                if col > 1 and err <= 1.0 and self.fixed_order is None:
                    return True, col
            return err <= 1.0, k
        for col in range(1, k):
            err = self._column(col, t, y, h, checks=True)
        if k > 2 and not reject:
            if err <= 1.0:
                return True, k - 1
            if err > (nseq[k] * nseq[k - 1] / nseq[0] ** 2) ** 2:
                return False, k - 1
        err = self._column(k, t, y, h, checks=True)
        if err <= 1.0:
            return True, k
        if err > (nseq[k] / nseq[0]) ** 2:
            return False, k
        err = self._column(k + 1, t, y, h, checks=True)
        return err <= 1.0, k + 1

    def _order_after_rejection(self, k, kc):
        if self.fixed_order is not None:
            return k
        ww = self._ww
        k = min(k, kc, self.max_order - 1)
        if k > 2 and ww[k - 1] < ww[k] * _FAC3:
            k -= 1
        return k

    def _next_order_and_step(self, kc, k, h_abs, reject):
        """ODEX's choice of columns and step size after an accepted step."""
        ww, hh, work = self._ww, self._hh, self._tab.work
        if self.fixed_order is not None:
            return k, (min(h_abs, hh[k]) if reject else hh[k])
        top = self.max_order - 1
        if kc == 2:
            kopt = 2 if reject else min(3, top)
        elif kc <= k:
            kopt = kc
            if ww[kc - 1] < ww[kc] * _FAC3:
                kopt = kc - 1
            if ww[kc] < ww[kc - 1] * _FAC4:
                kopt = min(kc + 1, top)
        else:
            kopt = kc - 1
            if kc > 3 and ww[kc - 2] < ww[kc - 1] * _FAC3:
                kopt = kc - 2
            if ww[kc] < ww[kopt] * _FAC4:
                kopt = min(kc, top)
        if reject:
            kopt = min(kopt, kc)
            return kopt, min(h_abs, hh[kopt])
        if kopt <= kc:
            return kopt, hh[kopt]
        if kc < k and ww[kc] < ww[kc - 1] * _FAC4:
            return kopt, hh[kc] * work[kopt + 1] / work[kc]
        return kopt, hh[kc] * work[kopt] / work[kc]

    # --- OdeSolver interface -------------------------------------------

    def _step_impl(self):
        if not self.adaptive:
            return self._fixed_step()
        t, y = self.t, self.y
        h_abs, k = self.h_abs, self._k
        min_step = 10 * abs(np.nextafter(t, self.direction * np.inf) - t)
        remaining = abs(self.t_bound - t)
        reject, restart = False, True
        while True:
            if restart:
                h_abs = min(h_abs, self.max_step, self._h_dense)
            last = 1.01 * h_abs >= remaining
            if last:
                h_abs = remaining
            if h_abs < min_step:
                return False, TOO_SMALL_STEP
            full = self.fixed_order is not None or (restart and (self.n_accepted == 0 or last))
            h = self.direction * h_abs
            try:
                accepted, kc = self._attempt(t, y, h, k, full, reject)
            except _Diverged:
                self.n_rejected += 1
                h_abs *= _SAFE3
                reject, restart = True, True
                continue
            if not accepted:
                self.n_rejected += 1
                k = self._order_after_rejection(k, kc)
                h_abs = self._hh[k]
                reject, restart = True, False
                continue
            t_new = self.t_bound if last else t + h
            y_new = self._y_new
            f_new = self.fun(t_new, y_new)
            self._dense = None
            if self.dense_error_control:
                coeffs, errint, mu = self._dense_coefficients(t, t_new, y, y_new, f_new, kc)
                self._h_dense = h_abs / max(errint ** (1.0 / (mu + 4)), 0.01)
                if errint > _DENSE_REJECT:
                    self.n_rejected += 1
                    h_abs = self._h_dense
                    reject, restart = True, True
                    continue
                self._dense = GBSDenseOutput(t, t_new, coeffs)
            self._k, self.h_abs = self._next_order_and_step(kc, k, h_abs, reject)
            self._accept(t, t_new, y, y_new, f_new, kc)
            return True, None

    def _fixed_step(self):
        t, y, k = self.t, self.y, self.fixed_order
        remaining = abs(self.t_bound - t)
        last = 1.01 * self.h_abs >= remaining
        h = self.direction * (remaining if last else self.h_abs)
        for col in range(1, k + 1):
            self._column(col, t, y, h, checks=False)
        t_new = self.t_bound if last else t + h
        y_new = self._y_new
        f_new = self.fun(t_new, y_new)
        self._dense = None
        self._accept(t, t_new, y, y_new, f_new, k)
        return True, None

    def _accept(self, t, t_new, y, y_new, f_new, kc):
        self._dense_args = (t, t_new, y, y_new, self.f, f_new, kc)
        self.y_old = y
        self.t = t_new
        self.y = y_new
        self.f = f_new
        self.order = kc
        self.n_accepted += 1

    def _dense_output_impl(self):
        if self._dense is None:
            t, t_new, y, y_new, f_old, f_new, kc = self._dense_args
            coeffs = self._dense_coefficients(t, t_new, y, y_new, f_new, kc, f_old)[0]
            self._dense = GBSDenseOutput(t, t_new, coeffs)
        return self._dense

    # --- dense output ---------------------------------------------------

    def _midpoint_derivatives(self, h, kc, mu):
        """``d[kappa] ~ H^kappa y^(kappa)(t_mid)`` for ``kappa = 0 ... mu`` (HNW II.9)."""
        tab = self._tab
        d = np.empty((mu + 1, self.n), dtype=self.y.dtype)
        d[0] = tab.weights[0, kc] @ self._ymid[:kc]
        if mu == 0:
            return d
        first = (np.arange(1, mu + 1) + 1) // 2 - 1  # first sequence reaching derivative kappa
        diffs = [h * (tab.diff_ops[j][:mu] @ self._fseq[j]) for j in range(kc)]
        for kappa in range(1, mu + 1):
            j0 = first[kappa - 1]
            column = np.array([diffs[j][kappa - 1] for j in range(j0, kc)])
            d[kappa] = tab.weights[j0, kc] @ column
        return d

    def _dense_coefficients(self, t, t_new, y, y_new, f_new, kc, f_old=None):
        """Interpolant coefficients in powers of ``u``, interpolation error estimate, ``mu``.

        The polynomial matches ``y`` and ``H f`` at ``u = -1, 1`` and
        ``d[kappa] / (kappa! 2^kappa)`` as coefficient of ``u^kappa``,
        ``kappa <= mu``. The estimate is the largest scaled difference to the
        polynomial with ``mu - 1``, ``c u^mu (1 - u^2)^2``.
        """
        tab = self._tab
        f_old = self.f if f_old is None else f_old
        h = t_new - t
        mu = max(2 * kc - _MU_DIFF + 1, 0)
        coeffs = np.empty((mu + 5, self.n), dtype=self.y.dtype)
        coeffs[:mu + 1] = self._midpoint_derivatives(h, kc, mu) * tab.taylor[:mu + 1, None]
        low = coeffs[:mu + 1]
        sign = (-1.0) ** np.arange(mu + 1)
        powers = np.arange(mu + 1)
        residual = np.array([
            y - sign @ low,
            y_new - low.sum(axis=0),
            0.5 * h * f_old - (powers * -sign) @ low,
            0.5 * h * f_new - powers @ low,
        ])
        coeffs[mu + 1:] = tab.hermite_inv[mu] @ residual
        if mu == 0:
            return coeffs, 0.0, mu
        top = coeffs[mu]
        residual_lower = residual + np.array([sign[mu], 1.0, -mu * sign[mu], mu])[:, None] * top
        c = top - tab.hermite_inv[mu - 1][0] @ residual_lower
        scale = self.atol + self.rtol * np.maximum(np.abs(y), np.abs(y_new))
        errint = _rms(c / scale) * tab.error_shape[mu]
        return coeffs, errint, mu

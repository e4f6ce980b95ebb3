"""Gragg-Bulirsch-Stoer (GBS) extrapolation integrator with step-size and order control.

Why this module exists
----------------------
No maintained Python library offers a Bulirsch-Stoer integrator: SciPy's
``solve_ivp`` has explicit Runge-Kutta (RK23, RK45, DOP853), Radau, BDF and
LSODA only. It is therefore written here, once: the kernels :func:`init`,
:func:`step` and :func:`dense` on the shared integration state
(:mod:`._layout`) are what the compiled driver runs, and
:class:`BulirschStoer`, a :class:`scipy.integrate.OdeSolver` for
``solve_ivp(..., method=BulirschStoer)``, is a thin wrapper that runs the same
source as Python on the user's function. It knows nothing of the problem it
integrates.

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

from .kernels import dense, init, step
from .tables import DEFAULT_MAX_ORDER, FLOATS, INTS, KMAX, rows, setup, step_number_sequence


def __getattr__(name):
    # the SciPy face imports scipy.integrate (most of a second): only when asked for
    if name in ("BulirschStoer", "GBSDenseOutput"):
        from . import solver

        return getattr(solver, name)
    raise AttributeError(name)

__all__ = ["BulirschStoer", "GBSDenseOutput", "step_number_sequence", "init", "step", "dense", "rows", "setup",
           "FLOATS", "INTS", "KMAX", "DEFAULT_MAX_ORDER"]

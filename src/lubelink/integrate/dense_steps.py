"""A whole integration kept as its steps' dense output: DOP853 run compiled, evaluated anywhere afterwards.

For a small system integrated once and read at many times (the driven crank's three states,
:mod:`lubelink.link.drive`): :func:`dop853_steps` takes the accepted steps of :mod:`.dop853` (SciPy's steps up
to rounding) in one compiled loop and stores each step's seventh-order interpolant; :class:`DenseSteps` is
that piecewise interpolant, evaluated vectorised like SciPy's ``OdeSolution``. No event, no sampling: the
loop knows the right-hand side only as the function it is handed.
"""

import numpy as np

from lubelink._jit import ENABLED, kernel
from . import dop853
from ._layout import F_DIR, F_HSTEP, F_MAXSTEP, F_T, F_TEND, F_TOLD, R_ATOL, R_RTOL, R_Y, S_INIT, S_NFEV

__all__ = ["dop853_steps", "DenseSteps", "integrate_dense", "join"]

ROWS = 8  # a step's interpolant: its 7 rows (dop853.R_COEF on) and the state at its start


@kernel
def dop853_steps(rhs, p, W, fst, ist, starts, pieces, count):
    """Accepted DOP853 steps until ``fst[F_T]`` reaches ``fst[F_TEND]`` or the arrays are full.

    Step ``k`` (from ``count`` on) is written as its start and size, ``starts[k] = (t_old, h)``, and its
    interpolant, ``pieces[k]`` (:data:`ROWS` rows of the state's length). Returns the steps written in all, or
    ``-1`` where a step underflowed; call again with that count and larger arrays to go on.
    """
    n = W.shape[1]
    if ist[S_INIT] == 0:
        dop853.init(rhs, p, W, fst, ist)
        ist[S_INIT] = 1
    k = count
    while fst[F_T] < fst[F_TEND] and k < starts.shape[0]:
        if not dop853.step(rhs, p, W, fst, ist):
            return -1
        dop853._coefficients(rhs, p, W, fst, ist)
        starts[k, 0] = fst[F_TOLD]
        starts[k, 1] = fst[F_HSTEP]
        for r in range(7):
            for m in range(n):
                pieces[k, r, m] = W[dop853.R_COEF + r, m]
        for m in range(n):
            pieces[k, 7, m] = W[dop853.R_YOLD, m]
        k += 1
    return k


class DenseSteps:
    """The interpolants of a run's steps: ``sol(t)`` the state at ``t`` (shape ``(n,)``, or ``(n, T)`` for ``T``
    times; clamped to the first and last step outside), ``ts`` the step boundaries, ``nfev`` the evaluations."""

    def __init__(self, starts, pieces, nfev):
        self.starts, self.pieces, self.nfev = starts, pieces, nfev
        self.ts = np.append(starts[:, 0], starts[-1, 0] + starts[-1, 1])
        self._rows = np.ascontiguousarray(pieces.transpose(1, 0, 2))  # [row, step, component]

    def __call__(self, t):
        t = np.asarray(t, dtype=float)
        tt = np.atleast_1d(t).ravel()
        i = np.clip(np.searchsorted(self.ts, tt, side="right") - 1, 0, len(self.starts) - 1)
        x = (tt - self.starts[i, 0]) / self.starts[i, 1]
        x = x[:, None]
        out = self._rows[6][i] * x
        for j in range(1, 7):  # dop853.dense's Horner scheme
            out += self._rows[6 - j][i]
            out *= x if j % 2 == 0 else 1.0 - x
        out += self._rows[7][i]
        return out[0] if t.ndim == 0 else out.T.reshape((-1,) + t.shape)


def join(first, second):
    """One :class:`DenseSteps`: ``first``'s steps that start before ``second`` starts, then ``second``'s (a run
    continued from ``first``'s state at its start)."""
    keep = first.starts[:, 0] < second.starts[0, 0]
    return DenseSteps(np.concatenate([first.starts[keep], second.starts]),
                      np.concatenate([first.pieces[keep], second.pieces]), first.nfev + second.nfev)


def integrate_dense(rhs, p, t0, y0, t_end, rtol, atol):
    """Integrate ``y' = rhs(t, y, out, p)`` (a compiled function) from ``(t0, y0)`` to ``t_end`` by DOP853 at the
    tolerances ``rtol``, ``atol``; the :class:`DenseSteps` of the run. Raises RuntimeError if a step underflows."""
    y0 = np.asarray(y0, dtype=float)
    n = y0.size
    if ENABLED:  # (as the driver passes it: a dispatcher itself would be matched against the step's other types)
        import numba

        from .driver import first_class, signatures

        rhs = first_class(rhs, signatures(numba.typeof(p))[0])
    W = np.zeros((dop853.rows(n), n))
    W[R_Y], W[R_ATOL], W[R_RTOL] = y0, atol, rtol
    fst, ist = np.zeros(32), np.zeros(16, dtype=np.int64)
    fst[F_T], fst[F_TEND], fst[F_DIR], fst[F_MAXSTEP] = t0, t_end, 1.0, np.inf
    capacity, count = 1024, 0
    starts, pieces = np.empty((capacity, 2)), np.empty((capacity, ROWS, n))
    while True:
        count = dop853_steps(rhs, p, W, fst, ist, starts, pieces, count)
        if count < 0:
            raise RuntimeError(f"DOP853: the step underflowed at t = {fst[F_T]!r}")
        if fst[F_T] >= t_end:
            return DenseSteps(starts[:count].copy(), pieces[:count].copy(), int(ist[S_NFEV]))
        capacity *= 2
        starts = np.concatenate([starts, np.empty_like(starts)])
        pieces = np.concatenate([pieces, np.empty_like(pieces)])

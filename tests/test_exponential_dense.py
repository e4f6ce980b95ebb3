"""The exponential method's dense output (integrate/exponential_dense.py) against independent references.

* of order four: its error inside a step from an exact state falls like ``h^5``;
* through the particular solution of each block it is the exact integral of the step's cubic
  load, as the phi-functions give it, on either side of the switch and backwards in time;
* chained along the samples (one rotation a sample) it is the direct evaluation.
"""

import math

import numpy as np
import pytest

from lubelink.integrate import exponential as E
from lubelink.integrate import exponential_dense as D
from lubelink.integrate._layout import F_DIR, F_MAXSTEP, F_T, F_TEND, R_ATOL, R_RTOL, R_Y
from test_exponential import forced, run_exp


def test_dense_output_is_of_order_four():
    """One step of size h from an exact state: the interpolant's error inside the step is ~h^5."""
    from lubelink.integrate._layout import F_H, F_HSTEP

    p = np.array([0.0, 2.0, 3.0, 50.0])
    t0 = 0.3
    hs = np.array([0.08, 0.04, 0.02, 0.01])
    grid = np.concatenate([[t0 + 0.37 * h, t0 + 0.5 * h, t0 + 0.81 * h] for h in hs] + [[t0]])
    order = np.argsort(grid)
    ref = np.empty((grid.size, 2))
    ref[order] = run_exp(p, grid.max(), rtol=1e-13, atol=1e-18, t_eval=grid[order]).y
    y0 = ref[-1]
    errors = []
    for k, h in enumerate(hs):
        W = np.zeros((E.rows(2), 2))
        fst, ist = np.zeros(E.FLOATS), np.zeros(32, dtype=np.int64)
        E.setup(W, fst, ist, {"omega": p[3:], "zeta": p[0]})
        W[R_Y], W[R_ATOL], W[R_RTOL] = y0, 1e3, 1e3  # accept whatever the error
        fst[F_DIR], fst[F_TEND], fst[F_MAXSTEP], fst[F_T] = 1.0, t0 + h, h, t0
        E.init(forced, p, W, fst, ist)
        fst[F_H] = h
        assert E.step(forced, p, W, fst, ist) and fst[F_HSTEP] == pytest.approx(h)
        out = np.empty(2)
        err = 0.0
        for j, theta in enumerate((0.37, 0.5, 0.81)):
            D.dense(forced, p, W, fst, ist, t0 + theta * h, out)
            err = max(err, abs(out[0] - ref[3 * k + j, 0]))
        errors.append(err)
    slope = np.polyfit(np.log(hs), np.log(errors), 1)[0]
    assert slope > 4.5, (errors, slope)


@pytest.mark.parametrize("zeta", [0.0, 0.02, 0.5, 0.99, 1.0, 2.0])
@pytest.mark.parametrize("h", [1e-3, -0.02])
@pytest.mark.parametrize("degree", [3, 5])
def test_dense_output_of_the_particular_solution_is_the_phi_functions_one(zeta, h, degree):
    """The exact integrals of a step with a polynomial load agree to rounding, from h omega = 0.01 to 1e3.

    The dense output takes ``exp(tau A) (y_n - P(0)) + P(tau)`` with the polynomial particular
    solution ``P`` for ``h omega >= DENSE_H_OMEGA[degree]`` (underdamped), the Taylor series of
    the solution below, the phi-functions for a block near or above critical damping;
    here both see the same random state and load (the Runge-Kutta method's cubic, the Adams
    method's quintic), on either side of the switch and backwards in time. The reference is the
    variation-of-constants sum ``phi_0 y + h sum_k k! theta^(k+1) phi_(k+1) Q_k`` block by block.
    """
    from lubelink.integrate._layout import F_HSTEP, F_TOLD, R_YOLD

    top = 1e3 if h > 0 else min(1e3, 30.0 / max(zeta, 0.03))  # backwards a damped block grows as exp(zeta omega |h|)
    omega = np.geomspace(0.01, top, 25) / abs(h)
    N = omega.size
    rng = np.random.default_rng(7)
    W = np.zeros((E.rows(2 * N), 2 * N))
    fst, ist = np.zeros(E.FLOATS), np.zeros(32, dtype=np.int64)
    E.setup(W, fst, ist, {"omega": omega, "zeta": zeta})
    W[R_YOLD] = rng.normal(size=2 * N) * np.concatenate([1.0 / omega, np.ones(N)])
    W[E.R_Q:E.R_Q + degree + 1] = rng.normal(size=(degree + 1, 2 * N))
    fst[F_HSTEP], fst[F_TOLD], fst[E.F_DEGREE] = h, 0.3, degree
    for dense in (D.dense, D.dense.py_func):
        fst[E.F_PART] = 0.0
        for theta in (0.1, 0.5, 0.93, 1.0):
            out = np.empty(2 * N)
            t = 0.3 + theta * h
            dense(forced, np.zeros(3 + N), W, fst, ist, t, out)
            theta = (t - 0.3) / h  # as the dense output sees it
            E._tables(W, h, theta, E.R_THETA, degree + 2)
            W[E.R_ERR] = 0.0
            for i in range(N):
                E._apply_block(W, E.R_THETA, R_YOLD, E.R_ERR, 1.0, i)
                for k in range(degree + 1):
                    E._apply_block(W, E.R_THETA + k + 1, E.R_Q + k, E.R_ERR, math.factorial(k) * theta ** (k + 1) * h, i)
            ref = W[E.R_ERR].copy()
            rate = (zeta + np.sqrt(max(zeta * zeta - 1.0, 0.0))) * omega  # of the fastest-growing solution backwards
            growth = np.tile(np.exp(np.maximum(0.0, -rate * theta * h)), 2)
            scale = (np.abs(W[R_YOLD]) + abs(h) * np.abs(W[E.R_Q:E.R_Q + degree + 1]).sum(axis=0)) * growth
            np.testing.assert_array_less(np.abs(out - ref), 1e-12 * scale)
    particular = np.isfinite(W[E.R_TURN, :N])  # (-inf: the Taylor series, NaN: the phi-functions)
    large = np.count_nonzero(omega * abs(h) >= D.DENSE_H_OMEGA[degree]) if zeta < D.DENSE_ZETA else 0
    assert particular.sum() == large
    assert np.count_nonzero(W[E.R_TURN, :N] == -np.inf) == (N - large if zeta < D.DENSE_ZETA else 0)


@pytest.mark.parametrize("zeta", [0.0, 0.05])
def test_dense_output_chained_along_the_samples_is_the_direct_one(zeta, monkeypatch):
    """Along ``t_eval`` the dense output takes ``exp(lambda tau)`` from the previous sample's by one
    rotation; computed directly at every sample instead (``CHAIN_LENGTH = 0``, the Python source)
    it agrees to 1e-13 of the solution's scale, on a grid of two spacings (the second needs new
    rotations) and over long steps of up to 60 samples (``h omega`` from 0.1 to 200)."""
    p = np.array([zeta, 0.0, 3.0, 2.0, 40.0, 700.0, 4000.0])
    t_eval = np.concatenate([np.arange(1, 1500) * 1e-3, 1.5 + np.arange(1, 800) * 7e-4])
    chained = run_exp(p, t_eval[-1], rtol=1e-5, atol=1e-9, t_eval=t_eval, compiled=False)
    assert chained.nsteps < t_eval.size / 20  # long steps: many samples each
    monkeypatch.setattr(D, "CHAIN_LENGTH", 0)
    direct = run_exp(p, t_eval[-1], rtol=1e-5, atol=1e-9, t_eval=t_eval, compiled=False)
    assert direct.nsteps == chained.nsteps
    scale = np.abs(direct.y).max(axis=0)
    np.testing.assert_array_less(np.abs(chained.y - direct.y) / scale, 1e-13)

"""RODAS4 (lubelink.integrate.rodas) on problems with exact solutions, compiled and as Python.

* the order of the step (4) and of the dense output (3), from errors at halved constant steps;
* a stiff linear system (eigenvalues to -1e6) against the matrix exponential, with steps far
  beyond the explicit stability limit;
* Prothero-Robinson, ``y' = -lam (y - g(t)) + g'(t)``: the ``df/dt`` of a time-dependent problem;
* the LU factorisation against NumPy's solve;
* events and samples through the driver, like every method (tests/test_integrate.py).
"""

import numpy as np
import pytest
from scipy.linalg import expm

from lubelink._jit import kernel
from lubelink.integrate import Options, Problem, integrate, method
from lubelink.integrate.rodas import lu_factor, lu_solve


@kernel
def linear(t, y, out, p):
    """``y' = M y`` with ``M = p``; an ``out`` of ``n + n^2`` also receives ``J = M`` (the stiff method's request)."""
    n = y.shape[0]
    for i in range(n):
        acc = 0.0
        for j in range(n):
            acc += p[i, j] * y[j]
        out[i] = acc
    if out.shape[0] > n:
        for i in range(n):
            for j in range(n):
                out[n + i * n + j] = p[i, j]


@kernel
def prothero_robinson(t, y, out, p):
    """``y' = -lam (y - cos t) - sin t`` (``lam = p[0]``): the exact solution from ``y(0) = 1`` is ``cos t``."""
    out[0] = -p[0] * (y[0] - np.cos(t)) - np.sin(t)


@kernel
def level(t, y, p):
    return y[0] - 0.5, 0.0, np.inf


def _stiff_matrix():
    rng = np.random.default_rng(3)
    Q, _ = np.linalg.qr(rng.standard_normal((4, 4)))
    D = np.array([[-1.0, 5.0, 0.0, 0.0], [-5.0, -1.0, 0.0, 0.0], [0.0, 0.0, -1e3, 0.0], [0.0, 0.0, 0.0, -1e6]])
    return np.ascontiguousarray(Q @ D @ Q.T)


def _constant_steps(rhs, p, y0, t_end, h, t_eval=np.zeros(0), compiled=True):
    """Steps of exactly ``h``: tolerances so loose that every step is accepted, ``max_step = h``."""
    return integrate(method("rodas"), Problem(rhs, level, p), 0.0, y0, t_end, t_eval,
                     Options(rtol=1e6, atol=1e6, max_step=h, compiled=compiled))


def test_lu_factor_solves_like_numpy():
    rng = np.random.default_rng(0)
    M = rng.standard_normal((7, 7))
    M[0, 0] = 0.0  # a pivot is needed
    b = rng.standard_normal(7)
    LU, piv, x = M.copy(), np.zeros(7), b.copy()
    assert lu_factor(LU, piv)
    lu_solve(LU, piv, x)
    np.testing.assert_allclose(x, np.linalg.solve(M, b), rtol=1e-12)
    assert not lu_factor(np.zeros((3, 3)), np.zeros(3))


@pytest.mark.parametrize("compiled", [True, False])
def test_order_four_step_order_three_dense_output(compiled):
    """Oscillator ``y'' = -y`` at constant steps: the end error falls 2^4, the mid-step samples' 2^3."""
    p = np.array([[0.0, 1.0], [-1.0, 0.0]])
    y0 = np.array([1.0, 0.0])
    end_err, dense_err = [], []
    for h in (0.2, 0.1, 0.05):
        t_eval = np.arange(0.5, 4.0, 1.0) * h  # mid-step samples of the first steps
        seg = _constant_steps(linear, p, y0, 4.0, h, t_eval, compiled)
        assert seg.status == "finished"
        end_err.append(np.abs(seg.y_final - [np.cos(4.0), -np.sin(4.0)]).max())
        # the dense output's local error: against the exact flow from each step's start
        local = []
        for t, y in zip(seg.t, seg.y):
            k = np.floor(t / h)
            start = expm(p * k * h) @ y0
            # the step's own start is the numerical one; the difference of starts is the global error
            local.append(np.abs(y - expm(p * (t - k * h)) @ start).max())
        dense_err.append(max(local))
    end_rates = np.log2(np.array(end_err[:-1]) / end_err[1:])
    dense_rates = np.log2(np.array(dense_err[:-1]) / dense_err[1:])
    assert np.all(np.abs(end_rates - 4.0) < 0.3), end_rates
    assert np.all(dense_rates > 2.7), dense_rates  # order 3 (the global part is of order 4)


@pytest.mark.parametrize("jacobian", [True, False])
def test_stiff_linear_system_against_the_matrix_exponential(jacobian):
    """Eigenvalues -1 +- 5i, -1e3, -1e6: an explicit method needs steps below 3e-6 s, RODAS4 takes a few hundred.

    With the problem's Jacobian the error tracks the tolerance to 1e-10; by forward differences
    ``J`` is wrong by about ``sqrt(eps) |f| / |y|``, which at the stiff eigenvalue 1e6 limits the
    accuracy (and the step) at tight tolerances, as for any Rosenbrock method.
    """
    M = _stiff_matrix()
    y0 = np.array([1.0, 0.5, -0.3, 0.2])
    t_eval = np.linspace(0.1, 2.0, 20)
    for rtol in (1e-4, 1e-6, 1e-8, 1e-10) if jacobian else (1e-4, 1e-6):
        seg = integrate(method("rodas"), Problem(linear, level, M, jacobian=jacobian), 0.0, y0, 2.0, t_eval,
                        Options(rtol=rtol, atol=rtol * 1e-3))
        assert seg.status == "finished"
        err = max(np.abs(y - expm(M * t) @ y0).max() for t, y in zip(seg.t, seg.y))
        assert err < 50 * rtol, (rtol, err)
        assert seg.nsteps < 3000, seg.nsteps  # explicit: 2 s / 3e-6 s = 7e5 steps


def test_prothero_robinson_time_dependent_stiff():
    """``lam = 1e6``: the step's end value follows ``cos t`` at any step, because ``df/dt`` enters the stages.

    RODAS4 is stiffly accurate, so its error estimate sees only the end values: on this problem it
    takes steps of a second (what its dense output in between is worth is the stiff component's,
    not ``cos t``'s; on the link the modes' vibration holds the steps short).
    """
    for rtol in (1e-5, 1e-8):
        for t_end in (0.7, 2.0, 5.0):
            seg = integrate(method("rodas"), Problem(prothero_robinson, level, np.array([1e6])), 0.0, np.array([1.0]),
                            t_end, np.zeros(0), Options(rtol=rtol, atol=rtol))
            assert seg.status == "finished"
            assert abs(seg.y_final[0] - np.cos(t_end)) < 10 * rtol
            assert seg.nsteps < 200


def test_event_located_on_the_dense_output():
    """``y = cos t`` falls to 0.5 at ``t = pi / 3``."""
    seg = integrate(method("rodas"), Problem(prothero_robinson, level, np.array([10.0])), 0.0, np.array([1.0]), 5.0,
                    np.zeros(0), Options(rtol=1e-8, atol=1e-10), event_sign=-1)
    assert seg.status == "event"
    assert abs(seg.t_final - np.pi / 3) < 1e-7


@kernel
def oscillators(t, y, out, p):
    """``q'' = -K q - C q'`` (``p = [K, C]``, ``N x N`` each) as ``y = [q, q']``, with its Jacobian on request."""
    N = y.shape[0] // 2
    n = 2 * N
    for i in range(N):
        out[i] = y[N + i]
        acc = 0.0
        for j in range(N):
            acc -= p[0, i, j] * y[j] + p[1, i, j] * y[N + j]
        out[N + i] = acc
    if out.shape[0] > n:
        for i in range(n * n):
            out[n + i] = 0.0
        for i in range(N):
            out[n + i * n + N + i] = 1.0
            for j in range(N):
                out[n + (N + i) * n + j] = -p[0, i, j]
                out[n + (N + i) * n + N + j] = -p[1, i, j]


def test_the_second_order_form_is_solved_through_half_the_unknowns():
    """``[q, q']`` with an exact Jacobian ``[[0, I], [-K, -C]]``: the step solves an ``N x N`` system
    (``c^2 I + c C + K``). Against the matrix exponential, with a stiff damping (1e6 1/s) coupling
    all; and on a non-stiff variant against the full ``2N`` solve (the Jacobian by differences)."""
    from lubelink.integrate.rodas import _second_order

    rng = np.random.default_rng(5)
    N = 4
    Q, _ = np.linalg.qr(rng.standard_normal((N, N)))
    K = Q @ np.diag([1.0, 30.0, 400.0, 2500.0]) @ Q.T
    y0 = np.r_[rng.standard_normal(N), np.zeros(N)]
    t_eval = np.linspace(0.05, 1.0, 20)
    for damping in (1e6, 1e2):
        C = damping * np.outer(Q[:, 0], Q[:, 0]) + 0.1 * np.eye(N)
        p = np.ascontiguousarray(np.stack([K, C]))
        M = np.block([[np.zeros((N, N)), np.eye(N)], [-K, -C]])
        assert _second_order(M)
        runs = {}
        for jacobian in (True, False):
            seg = integrate(method("rodas"), Problem(oscillators, level, p, jacobian=jacobian), 0.0, y0, 1.0, t_eval,
                            Options(rtol=1e-6, atol=1e-9))
            assert seg.status == "finished"
            err = max(np.abs(y - expm(M * t) @ y0).max() for t, y in zip(seg.t, seg.y))
            assert err < 300 * 1e-6, (damping, jacobian, err)  # as tests/test_integrate.py
            runs[jacobian] = seg
        if damping < 1e3:  # differences are accurate here: the same solution within the tolerance
            assert abs(runs[True].nsteps - runs[False].nsteps) <= 2
            scale = np.abs(runs[False].y).max()
            assert np.abs(runs[True].y - runs[False].y).max() < 2e-6 * scale  # (measured 3.6e-7)
    assert not _second_order(_stiff_matrix())

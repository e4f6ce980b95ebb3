"""The exponential integrator against independent references (its phi-functions: test_phi.py, its
dense output: test_exponential_dense.py).

* a free damped oscillator is integrated exactly, whatever the step;
* order four, fixed steps, on a forced oscillator with a nonlinear load (the fitted slope);
* with adaptive steps, the error follows the tolerance and the number of steps does not grow with
  the stiffest frequency (the point of the method).
"""

import numpy as np
import pytest

from lubelink._jit import kernel
from lubelink.integrate import exponential as E
from lubelink.integrate import Options, Problem, integrate, method
from lubelink.integrate._layout import F_DIR, F_MAXSTEP, F_TEND, R_ATOL, R_F, R_RTOL, R_Y


# --------------------------------------------------------------------------------------------------
@kernel
def forced(t, y, out, p):
    """Oscillators ``x'' + 2 zeta w x' + w^2 x = g(t, x)``; ``p = [zeta, eps, Omega, w_1 .. w_N]``.

    ``g = cos(Omega t) + eps x^2`` (a weak nonlinearity), the same for every oscillator.
    """
    N = y.shape[0] // 2
    for i in range(N):
        w = p[3 + i]
        x, v = y[i], y[N + i]
        out[i] = v
        out[N + i] = -w * w * x - 2 * p[0] * w * v + np.cos(p[2] * t) + p[1] * x * x


@kernel
def no_event(t, y, p):
    return 1.0, 0.0, 0.0


def run_exp(p, t_end, rtol=1e-8, atol=1e-12, t_eval=None, **kw):
    omegas = p[3:]
    return integrate(method("exponential"), Problem(forced, no_event, np.asarray(p, float), omega=omegas, zeta=p[0]), 0.0,
                     np.zeros(2 * len(omegas)), t_end, np.zeros(0) if t_eval is None else t_eval,
                     Options(rtol=rtol, atol=atol, **kw))


def free_exact(t, w, zeta, x0, v0):
    wd = w * np.sqrt(1 - zeta**2)
    e = np.exp(-zeta * w * t)
    x = e * (x0 * np.cos(wd * t) + (v0 + zeta * w * x0) / wd * np.sin(wd * t))
    return x


@kernel
def free(t, y, out, p):
    """A free damped oscillator, ``p = [omega, zeta]``."""
    out[0] = y[1]
    out[1] = -p[0] ** 2 * y[0] - 2 * p[1] * p[0] * y[1]


def test_a_free_damped_oscillator_is_integrated_exactly_in_long_steps():
    w, zeta = 300.0, 0.02
    seg = integrate(method("exponential"), Problem(free, no_event, np.array([w, zeta]), omega=[w], zeta=zeta), 0.0,
                    np.array([1e-3, 0.0]), 2.0, np.linspace(0.1, 2.0, 20), Options(rtol=1e-12, atol=1e-18))
    # the load is zero: the error estimates vanish and the step grows tenfold each time
    assert seg.nsteps < 12
    np.testing.assert_allclose(seg.y[:, 0], free_exact(seg.t, w, zeta, 1e-3, 0.0), rtol=0, atol=1e-15)


def fixed_steps(h, t_end, p):
    """Integrate with the kernels in fixed steps of ``h`` (no step control)."""
    n = 2 * (len(p) - 3)
    W = np.zeros((E.rows(n), n))
    fst, ist = np.zeros(E.FLOATS), np.zeros(32, dtype=np.int64)
    E.setup(W, fst, ist, {"omega": p[3:], "zeta": p[0]})
    W[R_ATOL], W[R_RTOL] = 1.0, 1.0
    fst[F_DIR], fst[F_TEND], fst[F_MAXSTEP] = 1.0, t_end, np.inf
    E.init(forced, p, W, fst, ist)
    t = 0.0
    for _ in range(int(round(t_end / h))):
        E._step_tables(W, h)
        E._stages(forced, p, W, ist, t, h)
        W[R_Y] = W[E.R_YNEW]
        t += h
        forced(t, W[R_Y], W[R_F], p)
        E._load(W, R_Y, R_F, E.R_G)
    return W[R_Y].copy()


def test_order_four_with_fixed_steps():
    """Two oscillators (w = 50 and 3000: h w up to 30), cos forcing and a weak quadratic load."""
    p = np.array([0.01, 2.0, 3.0, 50.0, 3000.0])
    ref = run_exp(p, 1.0, rtol=1e-13, atol=1e-18).y_final
    hs = 1.0 / np.array([10, 20, 40, 80])
    errors = [np.max(np.abs(fixed_steps(h, 1.0, p) - ref)) for h in hs]
    slope = np.polyfit(np.log(hs), np.log(errors), 1)[0]
    assert 3.8 < slope < 4.6, (errors, slope)


@pytest.mark.parametrize("zeta", [0.0, 0.02, 0.5, 0.99, 1.0, 2.0])
@pytest.mark.parametrize("h", [1e-3, -0.02])
def test_tables_by_doubling_are_the_phi_functions_of_the_step(zeta, h):
    """``phi_k`` of ``(h/2) A`` and ``h A`` doubled from ``(h/4) A`` = evaluated directly (phi.py),
    applied to a state ``(1/omega, 1)``: within 1e-13 of the scale of ``phi_k``, ``1/k!`` (times
    the growth of a damped block backwards), from ``h omega`` = 0.01 to 1e3."""
    top = 1e3 if h > 0 else min(1e3, 30.0 / max(zeta, 0.03))  # backwards a damped block grows as exp(zeta omega |h|)
    omega = np.geomspace(0.01, top, 41) / abs(h)
    N = omega.size
    x, v = 1.0 / omega, np.ones(N)
    growth = np.exp(np.maximum(0.0, -(zeta + np.sqrt(max(zeta * zeta - 1.0, 0.0))) * omega * h))
    scale = (x + v) * growth / np.array([1.0, 1.0, 2.0, 6.0, 24.0])[:, None]

    def applied(T):
        a, b = T[:, :N], T[:, N:]
        return np.abs(a * x + b * v) + np.abs(a * v + b * (-omega**2 * x - 2 * zeta * omega * v))

    W = np.zeros((E.rows(2 * N), 2 * N))
    E.setup(W, np.zeros(E.FLOATS), np.zeros(32, dtype=np.int64), {"omega": omega, "zeta": zeta})
    E._step_tables(W, h)
    doubled = W[E.R_HALF:E.R_HALF + 5].copy(), W[E.R_ONE:E.R_ONE + 5].copy()
    E._tables(W, h, 0.5, E.R_HALF, 5)
    E._tables(W, h, 1.0, E.R_ONE, 5)
    for got, row in zip(doubled, (E.R_HALF, E.R_ONE)):
        ref = W[row:row + 5]
        assert np.all(applied(got - ref) <= 1e-13 * (scale + applied(ref))), row


def test_error_follows_the_tolerance():
    p = np.array([0.01, 2.0, 3.0, 50.0, 400.0])
    ref = run_exp(p, 2.0, rtol=1e-13, atol=1e-18, t_eval=np.linspace(0.1, 2.0, 20)).y
    ratios = []
    for rtol in (1e-6, 1e-8, 1e-10):
        seg = run_exp(p, 2.0, rtol=rtol, atol=rtol * 1e-4, t_eval=np.linspace(0.1, 2.0, 20))
        scale = np.abs(ref).max(axis=0)
        ratios.append(np.max(np.abs(seg.y - ref) / scale) / rtol)
    assert max(ratios) < 100 and max(ratios) / min(ratios) < 100, ratios


def test_the_steps_do_not_follow_the_stiffest_frequency():
    """Raising the highest frequency 100-fold does not raise the number of steps (DOP853's grows 15-fold).

    The absolute tolerance is set to the soft oscillator's scale (its response is 1e-2, the stiff
    one's 1e-8): a much smaller one asks the stiff oscillator for a relative accuracy that makes
    the step follow its 1e-8 response instead (measured with atol 1e-14: 274, 1432, 2135 steps).
    """
    steps, dop = [], []
    for w_max in (1e2, 1e4):
        p = np.array([0.01, 0.0, 3.0, 10.0, w_max])
        steps.append(run_exp(p, 2.0, rtol=1e-8, atol=1e-10).nsteps)
        dop.append(integrate(method("DOP853"), Problem(forced, no_event, p), 0.0, np.zeros(4), 2.0, np.zeros(0),
                             Options(rtol=1e-8, atol=1e-10)).nsteps)
    assert steps[1] <= 1.2 * steps[0], steps  # measured 186, 84
    assert dop[1] > 10 * dop[0], dop  # measured 276, 4177: its stability bound

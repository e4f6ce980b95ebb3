"""The integration driver and its methods on problems with exact solutions, compiled and as Python.

* error proportional to the tolerance (SciPy's way of testing its solvers);
* the compiled DOP853 takes SciPy's steps; the compiled Bulirsch-Stoer takes the steps of the SciPy
  ``OdeSolver`` face (the same source run as Python);
* dense output and event location, grazes included: a zero of the event function and its return
  inside one step are found from the rate of the event, with no sub-sampling;
* progress and the wall-clock deadline.

No timing here: speed is measured in ``benchmarks/``.
"""

import numpy as np
import pytest

from lubelink._jit import kernel
from lubelink.integrate import COMPILED_METHODS, Options, Problem, integrate, method
from lubelink.integrate.bulirsch_stoer import BulirschStoer


@kernel
def oscillator(t, y, out, p):
    """``y'' = -p[0]^2 y``."""
    out[0] = y[1]
    out[1] = -p[0] ** 2 * y[0]


@kernel
def level(t, y, p):
    """Event ``y[0] - p[1]``, its rate ``y[1]`` and the bound of the rate, ``p[0]`` times the amplitude."""
    return y[0] - p[1], y[1], p[0] * np.sqrt(y[0] ** 2 + (y[1] / p[0]) ** 2)


def exact(t, w):
    return np.array([np.cos(w * t), -w * np.sin(w * t)])


def solve(t_end, p, m, compiled=True, event=None, event_sign=0, progress=None, t_eval=np.zeros(0), **kw):
    return integrate(method(m), Problem(oscillator, level if event is None else event, np.asarray(p, float)), 0.0,
                     np.array([1.0, 0.0]), t_end, t_eval, Options(compiled=compiled, **kw), event_sign=event_sign,
                     progress=progress)


@pytest.mark.parametrize("m", ["DOP853", "bulirsch-stoer"])
def test_error_tracks_the_tolerance(m):
    """Global error on 10 periods of the oscillator, scaled by rtol, stays within a band."""
    w = 2 * np.pi
    ratios = []
    for rtol in 10.0 ** -np.arange(4, 13, 2):
        seg = solve(10.0, [w], m, rtol=rtol, atol=rtol * 1e-3, t_eval=np.linspace(0.5, 10.0, 20))
        assert seg.status == "finished" and seg.t_final == 10.0
        err = max(np.max(np.abs(y - exact(t, w)) / np.array([1.0, w])) for t, y in zip(seg.t, seg.y))
        ratios.append(err / rtol)
    # global error ~ tolerance x number of steps x error growth, which varies with the order
    assert max(ratios) < 300 and max(ratios) / min(ratios) < 100, ratios


def test_compiled_dop853_takes_the_steps_of_scipy():
    from scipy.integrate import DOP853

    w = 3.0
    for rtol in (1e-5, 1e-10):
        seg = solve(10.0, [w], "DOP853", rtol=rtol, atol=rtol * 1e-3)
        sp = DOP853(lambda t, y: np.array([y[1], -w**2 * y[0]]), 0.0, np.array([1.0, 0.0]), 10.0, rtol=rtol,
                    atol=rtol * 1e-3)
        steps = 0
        while sp.status == "running":
            sp.step()
            steps += 1
        assert (seg.nfev, seg.nsteps) == (sp.nfev, steps)
        np.testing.assert_allclose(seg.y_final, sp.y, rtol=0, atol=1e-12 * w)


def test_compiled_bs_takes_the_steps_of_its_scipy_face():
    """The OdeSolver runs the same kernels as Python: the same steps and values up to rounding."""
    w = 3.0
    for rtol in (1e-4, 1e-8):
        seg = solve(10.0, [w], "bulirsch-stoer", rtol=rtol, atol=rtol * 1e-3)
        py = BulirschStoer(lambda t, y: np.array([y[1], -w**2 * y[0]]), 0.0, np.array([1.0, 0.0]), 10.0,
                           rtol=rtol, atol=rtol * 1e-3)
        steps = 0
        while py.status == "running":
            py.step()
            steps += 1
        assert (seg.nfev, seg.nsteps) == (py.nfev, steps)
        np.testing.assert_allclose(seg.y_final, py.y, rtol=0, atol=1e-12 * w)


@pytest.mark.parametrize("m", COMPILED_METHODS[:2])
@pytest.mark.parametrize("compiled", [True, False])
def test_dense_output_and_events(m, compiled):
    w = 2 * np.pi
    # first downward crossing of y = 0.5: cos(w t) = 0.5 at t = 1/6
    seg = solve(3.0, [w, 0.5], m, compiled, rtol=1e-10, atol=1e-13, t_eval=np.linspace(0.01, 3.0, 300),
                event_sign=-1)
    assert seg.status == "event"
    assert seg.t_final == pytest.approx(1 / 6, abs=1e-10)
    assert seg.t_before < seg.t_final <= seg.t_before + 1e-13  # a bracket a few rounding units wide
    assert seg.y_final[0] <= 0.5 < seg.y_before[0]
    assert seg.t[-1] <= seg.t_final < seg.t[-1] + 0.01
    for t, y in zip(seg.t, seg.y):  # the dense output between the steps
        np.testing.assert_allclose(y, exact(t, w), atol=1e-8 * w)


@pytest.mark.parametrize("m", COMPILED_METHODS[:2])
@pytest.mark.parametrize("depth", [1e-4, 1e-9])
def test_a_dip_inside_one_long_step_is_found_from_the_rate(m, depth):
    """``y[0] = cos t`` dips below ``-(1 - depth)`` for ``2 sqrt(2 depth)`` around ``t = pi`` (28 ms
    and 89 us): far shorter than the steps, found at the minimum of the event without sub-sampling."""
    seg = solve(4.0, [1.0, -(1.0 - depth)], m, rtol=1e-8, atol=1e-11, event_sign=-1)
    assert 4.0 / seg.nsteps > 0.1  # the steps are much longer than the window
    assert seg.status == "event"
    # where y = -(1 - depth) the slope is sqrt(2 depth): the dense output's error of ~rtol is
    # ~rtol / slope in time
    assert seg.t_final == pytest.approx(np.pi - np.arccos(1.0 - depth), abs=1e-7 / np.sqrt(depth))


def exact_method(h):
    """A method that steps the oscillator ``y'' = -y`` exactly, with steps of ``h``, and interpolates exactly.

    It isolates the event detector from integration error: a dip of the event in the dense output is
    there whatever its depth.
    """
    from lubelink.integrate import Method
    from lubelink.integrate._layout import F_H, F_HSTEP, F_T, F_TEND, F_TOLD, R_Y, R_YOLD

    def init(rhs, p, W, fst, ist):
        fst[F_H] = h

    def step(rhs, p, W, fst, ist):
        t = fst[F_T]
        t_new = min(t + h, fst[F_TEND])
        W[R_YOLD] = W[R_Y]
        W[R_Y] = exact(t_new, 1.0)
        fst[F_TOLD], fst[F_T], fst[F_HSTEP] = t, t_new, t_new - t
        return True

    def dense(rhs, p, W, fst, ist, t, out):
        out[:] = exact(t, 1.0)

    return Method("exact", init, step, dense, rows=lambda n: 16)


@pytest.mark.parametrize("depth", [1e-8, 1e-12, 1e-14])
def test_the_detector_finds_a_dip_of_any_duration(depth):
    """``cos t`` below ``-(1 - depth)`` for ``2 sqrt(2 depth)`` (283 us, 2.8 us, 0.28 us) inside 0.5 s steps."""
    seg = integrate(exact_method(0.5), Problem(oscillator, level, np.array([1.0, -(1.0 - depth)])), 0.0,
                    np.array([1.0, 0.0]), 4.0, np.zeros(0), Options(compiled=False), event_sign=-1)
    assert seg.status == "event"
    # the crossing time is ill-conditioned for a shallow dip: cos t is known to 1e-16 where its slope
    # is sqrt(2 depth), which at depth 1e-14 leaves the time a few parts in a thousand uncertain
    assert np.pi - seg.t_final == pytest.approx(np.arccos(1.0 - depth), rel=1e-3 if depth >= 1e-12 else 1e-2)


@kernel
def two_oscillators(t, y, out, p):
    """``x_i'' = -w_i^2 x_i``, ``p = [w_1, w_2, level]``."""
    out[0], out[1] = y[2], y[3]
    out[2] = -p[0] ** 2 * y[0]
    out[3] = -p[1] ** 2 * y[1]


@kernel
def sum_level(t, y, p):
    """``x_1 + x_2 - level`` with the bound ``sum w_i a_i`` of its rate."""
    bound = 0.0
    for i in range(2):
        bound += p[i] * np.sqrt(y[i] ** 2 + (y[2 + i] / p[i]) ** 2)
    return y[0] + y[1] - p[2], y[2] + y[3], bound


@kernel
def sum_level_unbounded(t, y, p):
    return y[0] + y[1] - p[2], y[2] + y[3], np.inf


@pytest.mark.parametrize("m", ["DOP853", "exponential", "exponential-adams"])
def test_the_rate_bound_skips_samples_but_no_zero(m):
    """A slow oscillation with a fast ripple crosses a level only where both are near their minima.

    ``cos t + 1e-3 cos(41 t) = -1.0009`` first near ``t = pi``; with the rate bound most of the
    ripple's samples are skipped, and the zero found is the same as with every sample taken, and
    as the closed form's (bisected on a fine grid).
    """
    from scipy.optimize import brentq

    p = np.array([1.0, 41.0, -1.0009])
    y0 = np.array([1.0, 1e-3, 0.0, 0.0])

    def g(t):
        return np.cos(t) + 1e-3 * np.cos(41 * t) - p[2]

    grid = np.linspace(0, 4, 400_001)
    first = np.argmax(g(grid) <= 0)
    t_exact = brentq(g, grid[first - 1], grid[first], xtol=1e-15)
    found = []
    for event in (sum_level, sum_level_unbounded):
        seg = integrate(method(m), Problem(two_oscillators, event, p, omega=p[:2], zeta=0.0), 0.0, y0, 4.0, np.zeros(0),
                        Options(rtol=1e-11, atol=1e-13, event_resolution=2 * np.pi / 41 / 4), event_sign=-1)
        assert seg.status == "event"
        found.append(seg.t_final)
    assert found[0] == pytest.approx(t_exact, abs=1e-8)
    assert found[1] == pytest.approx(t_exact, abs=1e-8)


def test_events_rising_through_zero():
    """``event_sign = +1`` watches the event rising to zero: ``cos(2 pi t) = 0.5`` upwards at t = 5/6."""
    seg = solve(3.0, [2 * np.pi, 0.5], "DOP853", rtol=1e-10, atol=1e-13, event_sign=1)
    assert seg.status == "event" and seg.t_final == pytest.approx(5 / 6, abs=1e-10)


def test_progress_and_deadline():
    seen = []
    seg = solve(50.0, [20.0], "bulirsch-stoer", rtol=1e-10, atol=1e-13, progress=seen.append)
    # about every 1 % of the interval (0.5 here; the steps are about 0.1 long)
    assert seg.status == "finished" and len(seen) >= 50
    assert np.all(np.diff(seen) >= 0) and np.max(np.diff(seen)) < 1.0 and seen[-1] == 50.0
    # the deadline is checked at each return to Python: after the first call's step
    late = solve(50.0, [20.0], "bulirsch-stoer", rtol=1e-10, atol=1e-13, deadline=0.0)
    assert late.status == "timeout" and "wall-time budget" in late.message
    assert 0.0 < late.t_final < 50.0 and np.all(np.isfinite(late.y_final))


@pytest.mark.parametrize("m", ["DOP853", "bulirsch-stoer"])
def test_a_slow_right_hand_side_overruns_the_deadline_by_at_most_a_step(monkeypatch, m):
    """Steps of a kind not yet timed: the first call into the loop takes one, so that the deadline (and
    Ctrl-C, which waits for the same return to Python) acts within about one step however long the
    steps are. A right-hand side that costs 10 ms of a virtual clock, the deadline 0.1 s away: the
    clock passes it by less than one step's evaluations (a fixed first call of 64 steps overran it
    by seconds)."""
    from lubelink.integrate import driver

    clock = {"now": 0.0, "calls": 0}

    def slow(t, y, out, p):
        clock["now"] += 0.01
        clock["calls"] += 1
        oscillator.py_func(t, y, out, p)

    monkeypatch.setattr(driver.time, "perf_counter", lambda: clock["now"])
    seg = integrate(method(m), Problem(slow, level.py_func, np.array([2 * np.pi, -2.0])), 0.0, np.array([1.0, 0.0]),
                    100.0, np.zeros(0), Options(compiled=False, rtol=1e-8, atol=1e-10, deadline=0.1))
    assert seg.status == "timeout" and 0.0 < seg.t_final < 100.0
    per_step = clock["calls"] / seg.nsteps
    assert clock["now"] - 0.1 <= 0.01 * per_step * 1.5 + 1e-12, (clock["now"], seg.nsteps, per_step)


def test_the_calls_into_compiled_code_change_nothing_but_their_number(monkeypatch):
    """The first call's step budget (the driver's ``BUDGETS``, what the last integration of the kind measured)
    and the budget it keeps: the same samples to the bit."""
    import numba

    from lubelink.integrate import driver

    t_eval = np.linspace(0.1, 20.0, 200)
    p = np.array([2 * np.pi])
    key = (method("DOP853").name, id(numba.typeof(p)))
    segs = []
    for k in (1, 64, 10**6):
        monkeypatch.setitem(driver.BUDGETS, key, k)
        segs.append(solve(20.0, p, "DOP853", rtol=1e-8, atol=1e-11, t_eval=t_eval))
        segs[-1].extra["kept"] = driver.BUDGETS[key]
    for seg in segs[1:]:
        np.testing.assert_array_equal(seg.y, segs[0].y)
        assert seg.nsteps == segs[0].nsteps
    assert segs[2].extra["kept"] == 10**6  # one call: nothing measured, the budget kept unchanged
    assert 1 <= segs[0].extra["kept"] <= 1_000_000  # measured after the first call


def test_scipy_methods_share_the_driver():
    w = 2 * np.pi
    for m in ("RK45", "Radau"):
        seg = solve(3.0, [w, 0.5], m, compiled=False, rtol=1e-10, atol=1e-13, event_sign=-1,
                    t_eval=np.linspace(0.01, 0.1, 10))
        assert seg.status == "event" and seg.t_final == pytest.approx(1 / 6, abs=1e-8)
        np.testing.assert_allclose(seg.y, np.array([exact(t, w) for t in seg.t]), atol=1e-7 * w)

"""lubelink.integrate.cumulative: SciPy's cumulative Simpson rule, without importing scipy.integrate."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.integrate import cumulative_simpson as scipy_cumulative_simpson

from lubelink.integrate.cumulative import cumulative_simpson


def test_exact_for_a_quadratic_on_uneven_points():
    x = np.array([0.0, 0.1, 0.35, 0.4, 0.9, 1.0, 1.7])
    y = 3.0 - 2.0 * x + 5.0 * x**2
    exact = 3.0 * x - x**2 + 5.0 * x**3 / 3.0
    np.testing.assert_allclose(cumulative_simpson(y, x), exact, rtol=0, atol=1e-13)


def test_third_order_on_a_smooth_function():
    errors = []
    for n in (41, 81, 161):
        x = np.sort(np.r_[0.0, np.random.default_rng(n).uniform(0.0, 2.0, n - 2), 2.0])
        x = np.linspace(0.0, 2.0, n) + 0.3 * (x - np.linspace(0.0, 2.0, n)) / n  # uneven, but not too much
        errors.append(np.max(np.abs(cumulative_simpson(np.cos(3 * x), x) - np.sin(3 * x) / 3)))
    rates = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(rates > 2.8), rates


@given(st.lists(st.floats(1e-3, 1.0), min_size=1, max_size=30), st.integers(0, 2**32 - 1))
def test_equals_scipys_rule(steps, seed):
    """SciPy's cumulative_simpson (and its trapezoid for two points) on uneven points, two rows at once."""
    x = np.cumsum(np.r_[0.0, steps])
    y = np.random.default_rng(seed).normal(size=(2, x.size))
    expected = scipy_cumulative_simpson(y, x=x, initial=0.0) if x.size > 2 else np.c_[np.zeros(2), 0.5 * (
        x[-1] - x[0]) * y.sum(axis=1)]
    np.testing.assert_allclose(cumulative_simpson(y, x), expected, rtol=1e-10, atol=1e-12 * np.max(np.abs(y)))


@pytest.mark.parametrize("n", [0, 1])
def test_fewer_than_two_points_integrate_to_nothing(n):
    assert np.all(cumulative_simpson(np.ones(n), np.arange(n, dtype=float)) == 0.0)

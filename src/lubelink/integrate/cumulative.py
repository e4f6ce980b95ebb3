"""Cumulative integral of samples by Simpson's rule on any (increasing) points.

This is SciPy's ``scipy.integrate.cumulative_simpson`` rule, written here because importing
``scipy.integrate`` (SciPy's ODE solvers, sparse algebra and special functions come with it) costs
about half a second, a quarter of a fresh ``simulate("paper")`` process, while the energy budget of
every run needs only this rule. ``tests/test_cumulative.py`` checks it against SciPy's.
"""

from __future__ import annotations

import numpy as np

__all__ = ["cumulative_simpson"]


def _parabola_integral(x0, x1, x2, y0, y1, y2, a, b):
    """``int_a^b`` of the parabola through ``(x0, y0)``, ``(x1, y1)``, ``(x2, y2)`` (element-wise)."""

    def weight(p, q, r):  # int_a^b (x - q)(x - r) dx / ((p - q)(p - r)), relative to a
        qa, ra, ba = q - a, r - a, b - a
        return (ba**3 / 3.0 - (qa + ra) * ba**2 / 2.0 + qa * ra * ba) / ((p - q) * (p - r))

    return y0 * weight(x0, x1, x2) + y1 * weight(x1, x0, x2) + y2 * weight(x2, x0, x1)


def cumulative_simpson(y, x):
    """``int_{x[0]}^{x[i]} y`` at every ``i`` (the first 0), along the last axis of ``y``.

    Composite Simpson's rule with SciPy's treatment of the pieces: each pair of intervals
    ``[x[2k], x[2k+2]]`` is integrated by the parabola through its three points, and the integral
    up to its middle point by the same parabola; the last interval of an odd count by the parabola
    through the last three points. Exact for quadratics, third order on a smooth ``y``. Two points:
    the trapezoid.

    Parameters
    ----------
    y : ndarray, shape ``(..., n)``
        Samples.
    x : ndarray, shape ``(n,)``
        Strictly increasing points.

    Returns
    -------
    ndarray, shape ``(..., n)``
    """
    y = np.asarray(y, dtype=float)
    x = np.asarray(x, dtype=float)
    n = x.size
    out = np.zeros(y.shape)
    if n < 2:
        return out
    if n == 2:
        out[..., 1] = 0.5 * (x[1] - x[0]) * (y[..., 0] + y[..., 1])
        return out
    k = np.arange(n - 1)
    first = k - k % 2  # the parabola of interval k starts at point first[k]
    first[-1] = n - 3
    pieces = _parabola_integral(x[first], x[first + 1], x[first + 2], y[..., first], y[..., first + 1],
                                y[..., first + 2], x[k], x[k + 1])
    out[..., 1:] = np.cumsum(pieces, axis=-1)
    return out

"""Tests of the general 2-D Reynolds solver ``lubelink.film.pressure_2d`` against independent references.

* the parallel-plate squeeze film on a rectangle: load against the double Fourier series;
* a very wide pad: the centre line against the 1-D film (``lubelink.film.pressure``, first-integral
  quadrature); a very narrow one against the short-bearing closed form;
* second-order grid convergence on a film that varies in X and Z;
* conservation of flow: the flow out through the pad boundary, from one-sided differences of the
  pressure, against the squeeze of the film inside;
* Swift-Stieber cavitation: ``p >= p_cav``, complementarity of the discrete problem, and a wide
  pad's centre line against the 1-D obstacle problem; half-Sommerfeld is the clipped solution.
"""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

from lubelink.film import pressure, pressure_2d, reynolds_2d_system

L_PAD = 0.05
MU = 0.1
H0 = 1e-4


def _load(p, X, Z):
    return np.trapezoid(np.trapezoid(p, Z, axis=1), X)


def _squeeze_load(a, b, K, n_terms=401):
    """Load of ``lap p = -K`` on ``a x b`` with ``p = 0`` on the edges: ``64 K a b / pi^6 sum 1/(m^2 n^2 (m^2/a^2 + n^2/b^2))``."""
    m = np.arange(1, n_terms, 2)[:, None]
    n = np.arange(1, n_terms, 2)[None, :]
    return 64.0 * K * a * b / np.pi ** 6 * np.sum(1.0 / (m ** 2 * n ** 2 * (m ** 2 / a ** 2 + n ** 2 / b ** 2)))


@pytest.mark.parametrize("B", [0.01, 0.05, 0.2])
def test_parallel_plate_squeeze_load_and_order(B):
    h_dot = -1e-3  # closing [m/s]
    K = -12.0 * MU * h_dot / H0 ** 3  # xi^3 lap p = 12 mu xi_t  ->  lap p = -K
    exact = _squeeze_load(L_PAD, B, K)
    errors = []
    for n in (16, 32, 64):
        X, Z = np.linspace(0, L_PAD, n + 1), np.linspace(-B / 2, B / 2, n + 1)
        p = pressure_2d(X, Z, H0, 0.0, MU, xi_t=h_dot)
        assert np.all(p >= 0)
        errors.append(abs(_load(p, X, Z) - exact) / exact)
    assert errors[-1] < 2e-3
    order = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(order > 1.8), order


def _wedge(X, Z=None):
    return H0 * (2.0 - X / L_PAD) + 0.0 * (0 if Z is None else Z)


def test_wide_pad_centre_line_is_the_1d_film():
    B = 10 * L_PAD
    X = np.linspace(0, L_PAD, 201)
    Z = np.linspace(-B / 2, B / 2, 401)
    p = pressure_2d(X, Z, _wedge, 2.0, MU)
    p1 = pressure(X, lambda x: H0 * (2.0 - x / L_PAD), 2.0, MU)
    assert_allclose(p[:, 200], p1, atol=2e-4 * p1.max())


@pytest.mark.parametrize("ratio", [0.02, 0.005])
def test_narrow_pad_is_the_short_bearing(ratio):
    B = ratio * L_PAD
    X = np.linspace(0, L_PAD, 801)
    Z = np.linspace(-B / 2, B / 2, 41)
    V = 2.0
    p = pressure_2d(X, Z, _wedge, V, MU)
    xi = H0 * (2.0 - X / L_PAD)
    A = 3.0 * MU * V * (-H0 / L_PAD) / xi ** 3  # short bearing: p = A (Z^2 - B^2/4)
    short = A[:, None] * (Z[None, :] ** 2 - B ** 2 / 4)
    inner = (X > 5 * B) & (X < L_PAD - 5 * B)  # the short limit fails within about B of the pad ends
    assert_allclose(p[inner], short[inner], atol=2e-3 * short.max())
    # the end layers, of width ~ B, cost O(B / l) of the load
    assert 0.1 * ratio < 1 - _load(p, X, Z) / _load(short, X, Z) < 1.5 * ratio


def _bumpy(X, Z):
    return H0 * (1.5 - 0.5 * X / L_PAD + 0.3 * np.cos(np.pi * Z / 0.02) * np.sin(np.pi * X / L_PAD))


def test_grid_convergence_second_order():
    B = 0.02
    loads = []
    for n in (20, 40, 80, 160):
        X, Z = np.linspace(0, L_PAD, 2 * n + 1), np.linspace(-B / 2, B / 2, n + 1)
        loads.append(_load(pressure_2d(X, Z, _bumpy, 1.5, MU, xi_t=lambda x, z: -2e-3 * x / L_PAD + 0 * z), X, Z))
    d = np.abs(np.diff(loads))
    order = np.log2(d[:-1] / d[1:])
    assert_allclose(order, 2.0, atol=0.15)


def test_flow_through_the_boundary_balances_the_squeeze():
    B, V = 0.02, 1.5

    def xi_t(x, z):
        return -2e-3 * (1.0 + np.cos(np.pi * z / B)) * np.sin(np.pi * x / L_PAD)

    misfit = []
    for n in (40, 80, 160):
        X, Z = np.linspace(0, L_PAD, 2 * n + 1), np.linspace(-B / 2, B / 2, n + 1)
        p = pressure_2d(X, Z, _bumpy, V, MU, xi_t=xi_t)
        xi = _bumpy(X[:, None], Z[None, :])
        hx, hz = X[1] - X[0], Z[1] - Z[0]

        def normal_derivative(pb, p1, p2, h):  # second-order one-sided, outward
            return (3 * pb - 4 * p1 + p2) / (2 * h)

        # q.n = -xi^3/(12 mu) dp/dn + (V xi / 2) n_X ; p = 0 on the edges
        out = (np.trapezoid(-xi[-1] ** 3 / (12 * MU) * normal_derivative(p[-1], p[-2], p[-3], hx) + V * xi[-1] / 2, Z)
               + np.trapezoid(-xi[0] ** 3 / (12 * MU) * normal_derivative(p[0], p[1], p[2], hx) - V * xi[0] / 2, Z)
               + np.trapezoid(-xi[:, -1] ** 3 / (12 * MU) * normal_derivative(p[:, -1], p[:, -2], p[:, -3], hz), X)
               + np.trapezoid(-xi[:, 0] ** 3 / (12 * MU) * normal_derivative(p[:, 0], p[:, 1], p[:, 2], hz), X))
        squeeze = _load(xi_t(X[:, None], Z[None, :]), X, Z)
        misfit.append(abs(out + squeeze) / abs(squeeze))
    assert misfit[-1] < 1e-3
    assert misfit[0] / misfit[-1] > 10  # converging at about second order


def _diverging_converging(X, Z):
    return H0 * (1.0 + 0.6 * np.cos(2 * np.pi * X / L_PAD)) + 0.0 * Z


@pytest.mark.parametrize("p_cav", [0.0, -5e3])
def test_swift_stieber_complementarity(p_cav):
    B = 0.02
    X, Z = np.linspace(0, L_PAD, 81), np.linspace(-B / 2, B / 2, 41)
    p_full = pressure_2d(X, Z, _diverging_converging, 1.0, MU)
    assert p_full.min() < p_cav - 1e3  # the full solution does cavitate
    p = pressure_2d(X, Z, _diverging_converging, 1.0, MU, cavitation="reynolds", p_cav=p_cav)
    assert p.min() >= p_cav - 1e-9 * abs(p).max()
    A, b = reynolds_2d_system(X, Z, _diverging_converging, 1.0, MU)
    pi = p[1:-1, 1:-1].ravel()
    w = A @ pi - b
    scale = np.abs(b).max()
    assert w.min() > -1e-9 * scale
    assert np.max(np.abs((pi - p_cav) * w)) < 1e-9 * scale * np.abs(p).max()
    cavitated = np.isclose(pi, p_cav, rtol=0, atol=1e-9 * np.abs(p).max())
    assert 0 < cavitated.sum() < pi.size
    hs = pressure_2d(X, Z, _diverging_converging, 1.0, MU, cavitation="half-sommerfeld", p_cav=p_cav)
    assert_allclose(hs, np.maximum(p_full, p_cav))


def test_swift_stieber_wide_pad_is_the_1d_obstacle_problem():
    B = 10 * L_PAD
    X, Z = np.linspace(0, L_PAD, 201), np.linspace(-B / 2, B / 2, 401)
    p = pressure_2d(X, Z, _diverging_converging, 1.0, MU, cavitation="reynolds", p_cav=0.0)
    p1 = pressure(X, lambda x: _diverging_converging(x, 0.0), 1.0, MU, cavitation="reynolds", p_cav=0.0,
                  grid_points=201)
    assert_allclose(p[:, 200], p1, atol=5e-3 * p1.max())


def test_rejects_bad_input():
    X, Z = np.linspace(0, L_PAD, 11), np.linspace(-0.005, 0.005, 7)
    with pytest.raises(ValueError, match="positive"):
        pressure_2d(X, Z, -1e-4, 1.0, MU)
    with pytest.raises(ValueError, match="broadcast"):
        pressure_2d(X, Z, np.ones(5) * H0, 1.0, MU)
    with pytest.raises(ValueError, match="strictly increasing"):
        pressure_2d(X[::-1], Z, H0, 1.0, MU)
    with pytest.raises(ValueError, match="cavitation"):
        pressure_2d(X, Z, H0, 1.0, MU, cavitation="swift")
    with pytest.raises(ValueError, match="p_cav"):
        pressure_2d(X, Z, H0, 1.0, MU, cavitation="reynolds", p_cav=10.0)

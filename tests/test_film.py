"""Tests of the Reynolds film (``lubelink.film``) against independent references.

docs/model.md §4 and "What the implementation must be checked against":

* the classical plane inclined slider (pressure and load, closed form);
* the parallel-plate squeeze film (pressure and load, closed form);
* the single-harmonic closed forms of section 4, implemented here as an oracle and
  itself checked against ``scipy.integrate.quad``;
* ``scipy.integrate.solve_bvp`` on the Reynolds ODE for a 3-mode film, with and
  without the squeeze term (``pressure``, ``pad_pressure`` and ``modal_force``);
* spectral convergence of the Gauss-Legendre quadrature in ``modal_force``, also for
  a thin film;
* physical properties (linearity, reversal, mirror symmetry, squeeze sign, squeeze
  damping, sub-ambient pressure);
* the cavitation options: half-Sommerfeld against the clipped closed form, Reynolds
  (Swift-Stieber) against the analytic free-boundary solution of a single-harmonic film;
* input validation.

Reynolds equation in the code's convention (link frame, ``V_r`` = velocity of the
flat collar relative to the shaped link, along +X)::

    (xi^3 p')' = 6 mu V_r xi' + 12 mu xi_t,   p(0) = p(l) = 0.

For the classical slider this is ``(h^3 p')' = 6 mu U h'`` with ``U`` the speed of the
flat runner and the inclined pad at rest, so ``V_r = U``.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_less
from scipy import integrate

from lubelink.film import modal_force, pad_pressure, pressure

# Section-6-like geometry: rod L = 1 m, square section B = 10 mm, clearance
# H = 0.2 mm (xi = 0.1 mm when undeflected), pad l = 50 mm, oil mu = 0.1 Pa s.
ROD = 1.0
WIDTH = 0.01
H = 2e-4
PAD = 0.05
MU = 0.1

QUAD = dict(epsabs=0.0, epsrel=1e-13, limit=200)


# ----------------------------------------------------------------------------------
# independent helpers
# ----------------------------------------------------------------------------------


@lru_cache(maxsize=None)
def _leggauss(n):
    """Gauss-Legendre nodes and weights on [-1, 1] (numpy's eigenvalue rule, cached)."""
    return np.polynomial.legendre.leggauss(n)


def slider_pressure(x, h_i, h_o, B, U, mu):
    """Classical plane inclined slider pressure (e.g. Hamrock, Fundamentals of Fluid Film Lubrication)."""
    h = h_i - (h_i - h_o) * x / B
    return 6.0 * mu * U * (h_i - h_o) * x * (B - x) / (B * (h_i + h_o) * h**2)


def slider_load(h_i, h_o, B, U, mu):
    """Classical load per unit width: 6 mu U B^2/(K^2 h_o^2) [ln(1+K) - 2K/(2+K)]."""
    K = h_i / h_o - 1.0
    return 6.0 * mu * U * B**2 / (K**2 * h_o**2) * (np.log1p(K) - 2.0 * K / (2.0 + K))


def branch_index_spec(bx):
    """The branch index of docs/model.md §4, ``m = floor((beta x + pi) / (2 pi))``."""
    return np.floor((np.asarray(bx) + np.pi) / (2.0 * np.pi))


def single_harmonic_antiderivatives(x, beta, clearance, phi):
    """docs/model.md §4.8 closed forms ``tilde I_1``, ``tilde I_2`` for ``xi = H/2 - phi sin(beta x)``.

    The branch index is ``m = floor((beta x + pi)/(2 pi))``. It is computed here as
    ``round((theta - arctan(tan theta))/pi)`` with ``theta = beta x / 2``, which equals
    ``m`` away from the poles of ``tan theta`` (checked in a test) and, unlike the
    floor form, stays consistent with the sign that floating point gives to
    ``tan theta`` when ``beta x`` lands exactly on ``pi + 2 pi k``.
    """
    x = np.asarray(x, dtype=float)
    bx = beta * x
    theta = 0.5 * bx
    t = np.tan(theta)
    m = np.rint((theta - np.arctan(t)) / np.pi)
    g1 = clearance**2 / 4.0 - phi**2
    assert g1 > 0, "closed forms need |phi| < H/2"
    g2 = -clearance / 2.0 + phi * np.sin(bx)
    Theta = np.arctan((0.5 * clearance * t - phi) / np.sqrt(g1)) + np.pi * m
    c = np.cos(bx)
    I1 = (clearance * g1**-1.5 * Theta + phi * c / (g1 * g2)) / beta
    I2 = (
        (0.5 * clearance**2 + phi**2) * g1**-2.5 * Theta
        - phi * c / (2.0 * g1 * g2**2)
        + 3.0 * clearance * phi * c / (4.0 * g1**2 * g2)
    ) / beta
    return I1, I2


def single_harmonic_pressure(X, n, phi, x0, V_r, mu=MU, clearance=H, pad_length=PAD, rod_length=ROD):
    """Closed-form wedge pressure ``6 mu V_r [I1(X) - I1(l)/I2(l) I2(X)]`` (docs/model.md §4.8)."""
    beta = n * np.pi / rod_length
    X = np.asarray(X, dtype=float)
    A1, A2 = single_harmonic_antiderivatives(x0 + X, beta, clearance, phi)
    B1, B2 = single_harmonic_antiderivatives(np.array([x0, x0 + pad_length]), beta, clearance, phi)
    I1, I2 = A1 - B1[0], A2 - B2[0]
    I1l, I2l = B1[1] - B1[0], B2[1] - B2[0]
    return 6.0 * mu * V_r * (I1 - I1l / I2l * I2)


def modal_film(q, q_dot, x0, clearance=H, rod_length=ROD):
    """Film ``xi``, its slope ``xi'`` and ``xi_t`` on the pad as callables of X (test-side)."""
    q = np.asarray(q, float)
    q_dot = np.asarray(q_dot, float)
    beta = np.arange(1, q.size + 1) * np.pi / rod_length

    def xi(X):
        X = np.asarray(X, float)
        return 0.5 * clearance - np.sin(np.multiply.outer(x0 + X, beta)) @ q

    def dxi(X):
        X = np.asarray(X, float)
        return -np.cos(np.multiply.outer(x0 + X, beta)) @ (beta * q)

    def xi_t(X):
        X = np.asarray(X, float)
        return -np.sin(np.multiply.outer(x0 + X, beta)) @ q_dot

    return xi, dxi, xi_t, beta


def bvp_pressure(xi, dxi, xi_t, V_r, mu, pad_length, h0):
    """Solve the Reynolds BVP with ``scipy.integrate.solve_bvp`` (scaled first-order system).

    Unknowns in ``s = X / l``: ``y0 = p / P0`` and ``y1 = (xi/h0)^3 d y0/ds``, so
    ``y0' = y1 / (xi/h0)^3`` and ``y1' = l^2 (6 mu V_r xi' + 12 mu xi_t) / (h0^3 P0)``.
    Returns a callable ``p(X)`` [Pa].
    """
    xi_t_scale = np.max(np.abs(xi_t(np.linspace(0, pad_length, 201)))) if xi_t is not None else 0.0
    P0 = 6.0 * mu * pad_length * (abs(V_r) + 2.0 * pad_length * xi_t_scale / h0) / h0**2

    def rhs(s, y):
        X = pad_length * s
        hat = xi(X) / h0
        src = 6.0 * mu * V_r * dxi(X)
        if xi_t is not None:
            src = src + 12.0 * mu * xi_t(X)
        return np.vstack([y[1] / hat**3, pad_length**2 * src / (h0**3 * P0)])

    def bc(ya, yb):
        return np.array([ya[0], yb[0]])

    s = np.linspace(0.0, 1.0, 101)
    sol = integrate.solve_bvp(rhs, bc, s, np.zeros((2, s.size)), tol=1e-10, bc_tol=1e-14, max_nodes=200_000)
    assert sol.success, sol.message
    return lambda X: P0 * sol.sol(np.asarray(X, float) / pad_length)[0]


def project(p, x0, beta, width=WIDTH, pad_length=PAD):
    """``F_n = -B int_0^l p(X) sin(beta_n (x0 + X)) dX`` and ``-B int p`` by ``quad``.

    The absolute quad tolerance is 1e-14 of ``l max|p|`` so that integrals that
    nearly cancel (symmetric films) do not chase an unreachable relative tolerance.
    """
    eps = 1e-14 * pad_length * np.abs(p(np.linspace(0.0, pad_length, 101))).max()
    opts = dict(epsabs=eps, epsrel=1e-13, limit=200)
    F = np.array([
        -width * integrate.quad(lambda X: float(p(X)) * np.sin(b * (x0 + X)), 0.0, pad_length, **opts)[0]
        for b in beta
    ])
    total = -width * integrate.quad(lambda X: float(p(X)), 0.0, pad_length, **opts)[0]
    return F, total


def film_kwargs(**over):
    kw = dict(mu=MU, clearance=H, pad_length=PAD, width=WIDTH, rod_length=ROD)
    kw.update(over)
    return kw


# ----------------------------------------------------------------------------------
# 1. Plane inclined slider
# ----------------------------------------------------------------------------------

SLIDER = dict(h_i=2e-4, h_o=1e-4, B=PAD, U=1.0, mu=MU)


def _slider_xi(h_i, h_o, B):
    return lambda X: h_i - (h_i - h_o) * np.asarray(X) / B


@pytest.mark.parametrize("as_array", [False, True], ids=["callable", "array"])
def test_inclined_slider_pressure(as_array):
    h_i, h_o, B, U, mu = SLIDER.values()
    X = np.linspace(0.0, B, 201)
    xi = _slider_xi(h_i, h_o, B)
    p = pressure(X, xi(X) if as_array else xi, U, mu)
    exact = slider_pressure(X, h_i, h_o, B, U, mu)
    # measured max |error| / max p: ~1e-15 (callable), ~1e-15 (array: the not-a-knot
    # spline reproduces a linear film exactly). 1e-11 leaves room for the cancellation
    # in I1 - I1(l)/I2(l) I2 and still catches any modelling error (which would be O(1)).
    assert_allclose(p, exact, rtol=0, atol=1e-11 * exact.max())
    assert exact.max() > 0  # converging in the direction of motion -> p > 0


def test_inclined_slider_load():
    h_i, h_o, B, U, mu = SLIDER.values()
    # The code's pressure at the test's own Gauss-Legendre nodes (plus the pad ends),
    # integrated by the test. The pressure is a smooth rational function; 200 GL nodes
    # integrate it to ~1e-15 relative.
    s, w = _leggauss(200)
    X = 0.5 * B * (s + 1.0)
    p = pressure(np.concatenate([[0.0], X, [B]]), _slider_xi(h_i, h_o, B), U, mu)[1:-1]
    W = 0.5 * B * np.sum(w * p)
    W_exact = slider_load(h_i, h_o, B, U, mu)
    # measured relative error ~1e-15; tolerance 1e-11 as above.
    assert_allclose(W, W_exact, rtol=1e-11)
    # and a second, cruder integration: Simpson's rule on 2001 points (error O(dx^4) ~1e-11)
    Xs = np.linspace(0.0, B, 2001)
    assert_allclose(integrate.simpson(pressure(Xs, _slider_xi(h_i, h_o, B), U, mu), x=Xs), W_exact, rtol=1e-9)


@settings(max_examples=50, deadline=None)
@given(
    ratio=st.floats(1.1, 5.0),
    h_o=st.floats(5e-6, 5e-4),
    U=st.floats(0.01, 20.0) | st.floats(-20.0, -0.01),
    mu=st.floats(1e-3, 1.0),
    B=st.floats(0.005, 0.2),
)
def test_inclined_slider_property(ratio, h_o, U, mu, B):
    h_i = ratio * h_o
    X = np.linspace(0.0, B, 101)
    p = pressure(X, _slider_xi(h_i, h_o, B), U, mu)
    exact = slider_pressure(X, h_i, h_o, B, U, mu)
    # worst measured over the examples ~1e-14 of max|p|; 1e-10 allows for K = 4
    # (steeper film, larger cancellation) without letting any real error through.
    assert_allclose(p, exact, rtol=0, atol=1e-10 * np.abs(exact).max())
    assert np.sign(p[50]) == np.sign(U)
    s, w = _leggauss(100)
    Xg = 0.5 * B * (s + 1.0)
    pg = pressure(np.concatenate([[0.0], Xg, [B]]), _slider_xi(h_i, h_o, B), U, mu)[1:-1]
    assert_allclose(0.5 * B * np.sum(w * pg), slider_load(h_i, h_o, B, U, mu), rtol=1e-10)


# ----------------------------------------------------------------------------------
# 2. Parallel-plate squeeze film
# ----------------------------------------------------------------------------------
# (h^3 p')' = 12 mu h_dot with h, h_dot constant and p(0) = p(l) = 0 gives
#   p = -6 mu h_dot X (l - X) / h^3,   W = int p = mu l^3 (-h_dot) / h^3 per unit width.


@pytest.mark.parametrize("h_dot", [-1e-3, 2.5e-4])
@pytest.mark.parametrize("V_r", [0.0, 3.0])
@pytest.mark.parametrize("as_array", [False, True], ids=["callable", "array"])
def test_parallel_plate_squeeze(h_dot, V_r, as_array):
    h = 8e-5
    X = np.linspace(0.0, PAD, 101)
    xi = lambda X: np.full_like(np.asarray(X, float), h)  # noqa: E731
    xi_t = lambda X: np.full_like(np.asarray(X, float), h_dot)  # noqa: E731
    if as_array:
        xi, xi_t = xi(X), xi_t(X)
    p = pressure(X, xi, V_r, MU, xi_t=xi_t)
    exact = -6.0 * MU * h_dot * X * (PAD - X) / h**3
    # flat film: the wedge term vanishes whatever V_r. Measured error ~1e-16 relative.
    assert_allclose(p, exact, rtol=0, atol=1e-12 * np.abs(exact).max())
    s, w = _leggauss(10)  # p is a quadratic: 10 nodes are exact
    Xg = 0.5 * PAD * (s + 1.0)
    pg = pressure(np.concatenate([[0.0], Xg, [PAD]]), lambda X: np.full_like(X, h), V_r, MU,
                  xi_t=lambda X: np.full_like(X, h_dot))[1:-1]
    W = 0.5 * PAD * np.sum(w * pg)
    assert_allclose(W, MU * PAD**3 * (-h_dot) / h**3, rtol=1e-12)


# ----------------------------------------------------------------------------------
# 3. Single-harmonic closed forms (docs/model.md §4.8)
# ----------------------------------------------------------------------------------

# (n, phi, x0): the n = 2 cases put the pad across x = L/2 (beta x = pi), where the
# branch index m jumps from 0 to 1; the last case is a thin film (xi_min = 0.1 H/2 at
# x = L/2, inside the pad but off its centre so that no force cancels by symmetry).
HARMONIC_CASES = [
    (1, 5e-5, 0.30),
    (1, -7e-5, 0.62),
    (2, -6e-5, 0.48),
    (2, 8e-5, 0.47),
    (3, 4e-5, 0.10),
    (1, 0.9e-4, 0.46),
]


@pytest.mark.parametrize("n, phi, x0", HARMONIC_CASES)
def test_closed_forms_match_quad(n, phi, x0):
    beta = n * np.pi / ROD
    xi = lambda x: H / 2 - phi * np.sin(beta * x)  # noqa: E731
    A1, A2 = single_harmonic_antiderivatives(x0, beta, H, phi)
    for X in (0.004, 0.017, 0.02, 0.033, PAD):
        B1, B2 = single_harmonic_antiderivatives(x0 + X, beta, H, phi)
        q1 = integrate.quad(lambda x: xi(x) ** -2, x0, x0 + X, **QUAD)[0]
        q2 = integrate.quad(lambda x: xi(x) ** -3, x0, x0 + X, **QUAD)[0]
        # measured worst relative difference 1.2e-12 (I2, phi = -7e-5: Theta gamma1^-5/2
        # and the rational terms cancel by ~3 digits). 1e-10 keeps the oracle trustworthy; a
        # wrong branch is off by O(1) (docs/model.md §4.8, the branch index m).
        assert_allclose(B1 - A1, q1, rtol=1e-10)
        assert_allclose(B2 - A2, q2, rtol=1e-10)


def test_branch_index_is_exercised_and_matches_spec():
    # the robust branch index equals the spec's floor form away from the poles
    bx = np.linspace(-7.0, 20.0, 2701)
    bx = bx[np.abs(np.cos(0.5 * bx)) > 1e-6]
    theta = 0.5 * bx
    assert_allclose(np.rint((theta - np.arctan(np.tan(theta))) / np.pi), branch_index_spec(bx))
    # and the n = 2 cases really straddle beta x = pi
    for n, phi, x0 in HARMONIC_CASES:
        if n == 2:
            beta = n * np.pi / ROD
            assert branch_index_spec(beta * x0) == 0 and branch_index_spec(beta * (x0 + PAD)) == 1
    # without the pi m correction the straddling integral would be badly wrong
    n, phi, x0 = 2, -6e-5, 0.48
    beta = n * np.pi / ROD
    g1 = H**2 / 4 - phi**2
    naive = lambda x: H * g1**-1.5 * np.arctan((0.5 * H * np.tan(0.5 * beta * x) - phi) / np.sqrt(g1)) / beta  # noqa: E731
    I1_naive = naive(x0 + PAD) - naive(x0)
    I1_good = np.diff(single_harmonic_antiderivatives(np.array([x0, x0 + PAD]), beta, H, phi)[0])[0]
    assert abs(I1_naive - I1_good) > 0.5 * abs(I1_good)


@pytest.mark.parametrize("V_r", [1.3, -0.4])
@pytest.mark.parametrize("n, phi, x0", HARMONIC_CASES)
def test_pressure_matches_single_harmonic_closed_form(n, phi, x0, V_r):
    beta = n * np.pi / ROD
    X = np.linspace(0.0, PAD, 101)
    p = pressure(X, lambda X: H / 2 - phi * np.sin(beta * (x0 + X)), V_r, MU)
    exact = single_harmonic_pressure(X, n, phi, x0, V_r)
    # measured worst 3.7e-11 of max|p| (phi = -7e-5, limited by the oracle's
    # cancellation, see above); typically 1e-13
    assert_allclose(p, exact, rtol=0, atol=1e-9 * np.abs(exact).max())


def test_pressure_from_sampled_curved_film():
    # xi and xi_t given as samples at X (interpolated by a spline in `pressure`),
    # on a curved film: wedge part against the closed form, and the full (wedge +
    # squeeze) result against the same film passed as callables (checked against
    # solve_bvp below). Spline error with 201 samples is O(dx^4 xi'''') ~ 1e-15
    # relative in the interior; measured pressure error ~1e-13. A spline with wrong
    # end conditions (e.g. natural: O(dx^2) at the ends) gives ~1e-7 and fails.
    n, phi, x0, V_r = 3, 8e-5, 0.2, 1.3
    beta = n * np.pi / ROD
    X = np.linspace(0.0, PAD, 201)
    xi = lambda X: H / 2 - phi * np.sin(beta * (x0 + X))  # noqa: E731
    xi_t = lambda X: -2e-3 * np.sin(beta * (x0 + X))  # noqa: E731
    exact = single_harmonic_pressure(X, n, phi, x0, V_r)
    assert_allclose(pressure(X, xi(X), V_r, MU), exact, rtol=0, atol=1e-10 * np.abs(exact).max())
    ref = pressure(X, xi, V_r, MU, xi_t=xi_t)
    assert_allclose(pressure(X, xi(X), V_r, MU, xi_t=xi_t(X)), ref, rtol=0, atol=1e-10 * np.abs(ref).max())


@pytest.mark.parametrize("n, phi, x0", HARMONIC_CASES)
def test_modal_force_matches_single_harmonic_closed_form(n, phi, x0):
    V_r = 1.3
    q = np.zeros(1 if n == 1 else 3)  # N = 1 for n = 1
    q[n - 1] = phi
    beta = np.arange(1, q.size + 1) * np.pi / ROD
    F, total, xi_min = modal_force(q, np.zeros_like(q), x0, V_r, **film_kwargs())
    F_ref, total_ref = project(lambda X: single_harmonic_pressure(X, n, phi, x0, V_r), x0, beta)
    # modal_force uses 32 GL nodes; measured relative error 1e-14..3e-13, and 1.5e-11
    # for phi = -7e-5 (oracle cancellation). Scale: the largest of |F_n| and |total|,
    # as either can be small when the pressure is nearly antisymmetric on the pad.
    scale = max(np.abs(F_ref).max(), abs(total_ref))
    assert_allclose(F, F_ref, rtol=0, atol=1e-8 * scale)
    assert_allclose(total, total_ref, rtol=0, atol=1e-8 * scale)
    X = np.linspace(0.0, PAD, 2001)
    assert xi_min >= (H / 2 - phi * np.sin(beta[n - 1] * (x0 + X))).min() - 1e-12


# ----------------------------------------------------------------------------------
# 4. Multi-mode film against solve_bvp
# ----------------------------------------------------------------------------------

Q3 = np.array([4e-5, -2.5e-5, 1.2e-5])
QDOT3 = np.array([2e-3, -1.5e-3, 8e-4])
X0_3 = 0.31


@pytest.fixture(scope="module", params=[False, True], ids=["wedge", "squeeze"])
def bvp_case(request):
    squeeze = request.param
    V_r = 1.5
    xi, dxi, xi_t, beta = modal_film(Q3, QDOT3, X0_3)
    p_ref = bvp_pressure(xi, dxi, xi_t if squeeze else None, V_r, MU, PAD, H / 2)
    return dict(squeeze=squeeze, V_r=V_r, xi=xi, xi_t=xi_t, beta=beta, p_ref=p_ref)


def test_pressure_matches_solve_bvp(bvp_case):
    c = bvp_case
    X = np.linspace(0.0, PAD, 257)
    p = pressure(X, c["xi"], c["V_r"], MU, xi_t=c["xi_t"] if c["squeeze"] else None)
    ref = c["p_ref"](X)
    # solve_bvp with tol = 1e-10 on the scaled system: measured max |difference| /
    # max|p| = 1.5e-10 (wedge, 2.0e-6 Pa of 12.7 kPa) and 5.0e-12 (squeeze, 1.3e-6 Pa
    # of 262 kPa). 1e-8 is far below any modelling error
    # (a wrong sign or factor in the squeeze term is O(1)).
    assert_allclose(p, ref, rtol=0, atol=1e-8 * np.abs(ref).max())


def test_pad_pressure_matches_solve_bvp(bvp_case):
    c = bvp_case
    X = np.linspace(0.0, PAD, 41)
    # batch of two time samples: the BVP state and a second state (mode 1 only)
    q = np.vstack([Q3, [3e-5, 0.0, 0.0]])
    q_dot = np.vstack([QDOT3, [0.0, 0.0, 0.0]])
    P = pad_pressure(X, q, q_dot, np.array([X0_3, 0.2]), np.array([c["V_r"], -0.7]),
                     mu=MU, clearance=H, rod_length=ROD, squeeze=c["squeeze"])
    assert P.shape == (2, X.size)
    ref = c["p_ref"](X)
    assert_allclose(P[0], ref, rtol=0, atol=1e-8 * np.abs(ref).max())
    ref2 = single_harmonic_pressure(X, 1, 3e-5, 0.2, -0.7)  # second sample: closed form
    assert_allclose(P[1], ref2, rtol=0, atol=1e-9 * np.abs(ref2).max())


def test_modal_force_matches_solve_bvp(bvp_case):
    c = bvp_case
    F, total, xi_min = modal_force(Q3, QDOT3, X0_3, c["V_r"], squeeze=c["squeeze"], **film_kwargs())
    F_ref, total_ref = project(c["p_ref"], X0_3, c["beta"])
    # measured 4.3e-11 (wedge) and 1.6e-12 (squeeze) relative to max|F_n|, the same
    # for the resultant; tolerance as for the pressure.
    scale = np.abs(F_ref).max()
    assert_allclose(F, F_ref, rtol=0, atol=1e-8 * scale)
    assert_allclose(total, total_ref, rtol=0, atol=1e-8 * abs(total_ref))
    assert xi_min < H / 2


def test_squeeze_changes_modal_force():
    # guards against the squeeze flag being ignored: the squeeze contribution is O(1)
    Fw, _, _ = modal_force(Q3, QDOT3, X0_3, 1.5, squeeze=False, **film_kwargs())
    Fs, _, _ = modal_force(Q3, QDOT3, X0_3, 1.5, squeeze=True, **film_kwargs())
    assert np.abs(Fs - Fw).max() > 0.1 * np.abs(Fw).max()


# ----------------------------------------------------------------------------------
# 5. Quadrature convergence of modal_force
# ----------------------------------------------------------------------------------


def _thin_state(target=0.05):
    """7-mode state scaled so that the film minimum on the pad is ``target * H/2``.

    Mode 7 dominates, so the film curves over the pad (``xi''`` ~ 0.04 1/m) and the
    near-zero of ``xi`` is a nearby complex singularity of ``xi^-3``: a hard case for
    the quadrature. (Films built from modes 1-3 alone are nearly polynomial over a
    50 mm pad; 8 nodes already reach round-off for them, even at 5% film.)
    """
    shape = np.array([0.3, 0.0, 0.1, 0.0, 0.0, 0.0, 1.0])
    x0 = 0.33
    X = np.linspace(0.0, PAD, 20001)
    beta = np.arange(1, shape.size + 1) * np.pi / ROD
    u = np.sin(np.outer(x0 + X, beta)) @ shape
    k = np.argmax(u)
    assert 0 < k < X.size - 1  # the thinnest point is inside the pad
    q = (1.0 - target) * (H / 2) / u[k] * shape
    return q, np.linspace(1e-3, -5e-4, shape.size), x0


@pytest.mark.parametrize("squeeze", [False, True], ids=["wedge", "squeeze"])
@pytest.mark.parametrize("thin", [False, True], ids=["moderate", "thin"])
def test_modal_force_quadrature_converges(thin, squeeze):
    if thin:
        q, q_dot, x0 = _thin_state(0.05)
    else:
        q, q_dot, x0 = Q3, QDOT3, X0_3
    kw = film_kwargs()
    F_ref, t_ref, xi_min = modal_force(q, q_dot, x0, 1.5, squeeze=squeeze, nodes=256, **kw)
    scale = np.abs(F_ref).max()
    errs = []
    for nodes in (8, 16, 32, 64):
        F, t, _ = modal_force(q, q_dot, x0, 1.5, squeeze=squeeze, nodes=nodes, **kw)
        errs.append(max(np.abs(F - F_ref).max() / scale, abs(t - t_ref) / abs(t_ref)))
    errs = np.array(errs)
    # Spectral (geometric) convergence: each doubling of the nodes gains at least two
    # orders until round-off (floor 1e-12 relative, measured round-off ~1e-14).
    # Measured, relative to max|F_n|, for nodes 8/16/32/64:
    #   moderate: ~6e-14 at all (round-off already at 8 nodes);
    #   thin wedge: 9.6e-2, 3.3e-5, 2.5e-13, 5e-15; thin squeeze: 6.7e-3, 1.1e-6, 7e-15, 3e-15.
    # An algebraic rule (e.g. trapezoid/Simpson, error ~ nodes^-2..-4) would fail.
    floor = 1e-12
    for a, b in zip(errs[:-1], errs[1:]):
        assert b < max(1e-2 * a, floor)
    assert errs[2] < floor  # the default nodes = 32 is at round-off even for a 5% film
    if thin:
        assert errs[0] > 1e-4  # the thin case really stresses the quadrature
        assert_allclose(xi_min, 0.05 * H / 2, rtol=1e-3)


def test_thin_film_reference_matches_closed_form():
    # the nodes = 256 reference itself, on a single-harmonic film with xi_min = 5% of
    # H/2 inside the pad, against the closed-form pressure projected by quad.
    n, x0 = 1, 0.46  # sin(pi x) peaks at x = 0.5, inside [0.46, 0.51], off centre
    phi = 0.95 * H / 2
    beta = np.array([np.pi / ROD])
    F, total, _ = modal_force(np.array([phi]), np.zeros(1), x0, 1.3, nodes=256, **film_kwargs())
    F_ref, total_ref = project(lambda X: single_harmonic_pressure(X, n, phi, x0, 1.3), x0, beta)
    # measured ~1e-10 relative (oracle cancellation at gamma1 = 0.0975 H^2/4)
    assert_allclose(F, F_ref, rtol=1e-8)
    assert_allclose(total, total_ref, rtol=1e-8)


# ----------------------------------------------------------------------------------
# 6. Physical properties
# ----------------------------------------------------------------------------------

# Modal states on a 1 um grid and velocities on a 1 um/s grid: physically dense enough,
# and free of subnormal floats (which would only test IEEE underflow, not the film).
film_states = st.tuples(
    st.integers(-60, 60).map(lambda k: k * 1e-6),
    st.integers(-20, 20).map(lambda k: k * 1e-6),
    st.integers(-10, 10).map(lambda k: k * 1e-6),
    st.floats(0.0, ROD - PAD),
)
modal_velocities = st.tuples(*[st.integers(-3000, 3000).map(lambda k: k * 1e-6)] * 3)


@settings(max_examples=40, deadline=None)
@given(state=film_states, V_r=st.floats(-5.0, 5.0).filter(lambda v: abs(v) > 1e-3),
       a=st.floats(0.1, 10.0), mu=st.floats(1e-3, 1.0))
def test_wedge_pressure_linear_in_speed_and_viscosity(state, V_r, a, mu):
    *q, x0 = state
    xi = modal_film(q, np.zeros(3), x0)[0]
    X = np.linspace(0.0, PAD, 51)
    p = pressure(X, xi, V_r, mu)
    # a flat film (q = 0) has p = 0 up to round-off, so the scale also includes the
    # natural wedge pressure 6 mu |V_r| l / (H/2)^2
    scale = np.abs(p).max() + 6.0 * mu * abs(V_r) * PAD / (H / 2) ** 2
    # linear in V_r and mu, odd in V_r (round-off only: 1e-12 of max|p|)
    assert_allclose(pressure(X, xi, a * V_r, mu), a * p, rtol=0, atol=1e-12 * a * scale)
    assert_allclose(pressure(X, xi, V_r, a * mu), a * p, rtol=0, atol=1e-12 * a * scale)
    assert_allclose(pressure(X, xi, -V_r, mu), -p, rtol=0, atol=1e-12 * scale)


@settings(max_examples=40, deadline=None)
@given(state=film_states, V_r=st.floats(-5.0, 5.0),
       qd=modal_velocities)
def test_mirror_symmetry(state, V_r, qd):
    # xi(X) -> xi(l - X), xi_t(X) -> xi_t(l - X) and V_r -> -V_r maps p(X) -> p(l - X)
    *q, x0 = state
    xi, _, xi_t, _ = modal_film(q, qd, x0)
    X = np.linspace(0.0, PAD, 51)
    p = pressure(X, xi, V_r, MU, xi_t=xi_t)
    pm = pressure(X, lambda X: xi(PAD - X), -V_r, MU, xi_t=lambda X: xi_t(PAD - X))
    # natural wedge + squeeze pressure scale (p may vanish, e.g. a flat film at rest)
    scale = np.abs(p).max() + 6.0 * MU * PAD * (abs(V_r) + 2.0 * PAD * np.abs(qd).sum() / (H / 2)) / (H / 2) ** 2
    assert_allclose(pm, p[::-1], rtol=0, atol=1e-11 * scale)


@pytest.mark.parametrize("direction", [1.0, -1.0])
def test_squeeze_pressure_sign_and_resultant(direction):
    # V_r = 0, mode-1 velocity only: u2_dot = a sin(beta1 x) has one sign on the pad,
    # so xi_t = -u2_dot has one sign. (xi^3 p')' = 12 mu xi_t with p = 0 at both ends:
    # closing film (xi_t < 0) -> p > 0 inside (maximum principle), and the resultant
    # on the link (-B int p) opposes the link velocity.
    q = np.array([3e-5, 1e-5, -5e-6])
    q_dot = np.array([direction * 2e-3, 0.0, 0.0])
    xi, _, xi_t, _ = modal_film(q, q_dot, X0_3)
    X = np.linspace(0.0, PAD, 51)
    p = pressure(X, xi, 0.0, MU, xi_t=xi_t)
    assert np.all(np.sign(xi_t(X)) == -direction)
    assert_array_less(0.0, direction * p[1:-1])
    F, total, _ = modal_force(q, q_dot, X0_3, 0.0, squeeze=True, **film_kwargs())
    assert direction * total < 0
    assert F @ q_dot < 0


@settings(max_examples=50, deadline=None)
@given(state=film_states,
       qd=modal_velocities)
def test_squeeze_film_is_dissipative(state, qd):
    # With V_r = 0 the film power on the link is
    #   sum_n F_n q_dot_n = -B int p u2_dot = B int p xi_t = -(B / 12 mu) int xi^3 p'^2 <= 0,
    # for any modal state and velocity: the squeeze film is a damper.
    *q, x0 = state
    q, q_dot = np.array(q), np.array(qd)
    F, _, _ = modal_force(q, q_dot, x0, 0.0, squeeze=True, **film_kwargs())
    # round-off allowance relative to |F| |q_dot|
    assert F @ q_dot <= 1e-12 * np.abs(F).sum() * np.abs(q_dot).sum()
    # and the identity itself, with p' from the test-side BVP-free formula:
    # xi^3 p' = 12 mu Q + C, Q = int_0^X xi_t, C fixed by int p' = 0.
    xi, _, xi_t, beta = modal_film(q, q_dot, x0)
    s, w = _leggauss(200)
    X = 0.5 * PAD * (s + 1.0)
    wX = 0.5 * PAD * w
    Q = -(((np.cos(beta * x0) - np.cos(np.outer(x0 + X, beta))) / beta) @ q_dot)
    inv3 = xi(X) ** -3
    C = -12.0 * MU * np.sum(wX * Q * inv3) / np.sum(wX * inv3)
    dp = (12.0 * MU * Q + C) * inv3
    dissipation = -(WIDTH / (12.0 * MU)) * np.sum(wX * xi(X) ** 3 * dp**2)
    assert_allclose(F @ q_dot, dissipation, rtol=1e-9, atol=1e-14 * np.abs(F).sum() * np.abs(q_dot).sum())


def test_sub_ambient_pressure_in_diverging_converging_film():
    # Documented, not hidden: the wedge-only Reynolds film (no cavitation, paper and
    # default model) has sub-ambient gauge pressure where the film diverges in the
    # direction of V_r. For a film symmetric about the pad centre, mirror symmetry
    # makes p antisymmetric: p(l - X) = -p(X), equal suction and overpressure.
    h0 = 1e-4
    xi = lambda X: h0 * (1.0 + 0.5 * np.sin(np.pi * np.asarray(X) / PAD))  # noqa: E731
    X = np.linspace(0.0, PAD, 201)
    p = pressure(X, xi, 1.0, MU)
    assert p.min() < -0.1 * p.max() < 0
    assert_allclose(p[::-1], -p, rtol=0, atol=1e-12 * np.abs(p).max())
    # the suction is where the film diverges (first half, xi' > 0 for V_r > 0)
    assert np.all(p[1:100] < 0) and np.all(p[101:-1] > 0)
    # Same for a real modal state: the pad straddles the thinnest point of mode 1.
    p1 = single_harmonic_pressure(X, 1, 5e-5, 0.475, 1.0)
    assert p1.min() < 0 < p1.max()
    assert_allclose(pressure(X, lambda X: H / 2 - 5e-5 * np.sin(np.pi * (0.475 + X)), 1.0, MU), p1,
                    rtol=0, atol=1e-9 * np.abs(p1).max())


# ----------------------------------------------------------------------------------
# 8. Cavitation options (docs/model.md §4.6)
# ----------------------------------------------------------------------------------
# Single-harmonic film with its thinnest point inside the pad (x = L/2, X = 30 mm):
# converging then diverging for V_r > 0. The full (Sommerfeld) solution dips to
# about -1.4 kPa near the exit, against a peak of 15.6 kPa.

CAV = dict(n=1, phi=6e-5, x0=0.47, V_r=1.3)


def _cav_film():
    beta = CAV["n"] * np.pi / ROD
    return beta, (lambda X: H / 2 - CAV["phi"] * np.sin(beta * (CAV["x0"] + np.asarray(X, float))))


def swift_stieber_reference(p_cav):
    """Analytic Swift-Stieber (Reynolds condition) solution for the CAV film, ``p_cav <= 0``.

    Full film on ``[0, X_r]`` with ``p(0) = 0``, ``p(X_r) = p_cav``, ``p'(X_r) = 0``:
    ``xi^3 p' = 6 mu V_r (xi - xi(X_r))``. Cavitated (``p = p_cav``) on ``[X_r, X_f]``.
    Reformation on ``[X_f, l]`` with ``p(X_f) = p_cav``, ``p'(X_f) = 0``, ``p(l) = 0``
    (absent when ``p_cav = 0``). ``X_r`` and ``X_f`` are single roots found by brentq,
    with the integrals from the closed forms of section 4.
    """
    from scipy.optimize import brentq

    beta, xi = _cav_film()
    K = 6.0 * MU * CAV["V_r"]

    def I(a, b):
        A = single_harmonic_antiderivatives(CAV["x0"] + np.asarray(b, float), beta, H, CAV["phi"])
        B = single_harmonic_antiderivatives(CAV["x0"] + np.asarray(a, float), beta, H, CAV["phi"])
        return A[0] - B[0], A[1] - B[1]

    def wedge(a, b, xi_a):  # p(b) - p(a) with p'(a) = 0 ... or p'(b) = 0 when xi_a = xi(b)
        i1, i2 = I(a, b)
        return K * (i1 - xi_a * i2)

    X_min = ROD / 2 - CAV["x0"]
    X_r = brentq(lambda Xr: wedge(0.0, Xr, xi(Xr)) - p_cav, X_min, PAD, xtol=1e-16)
    X_f = PAD if p_cav == 0 else brentq(lambda Xf: wedge(Xf, PAD, xi(Xf)) + p_cav, X_r, PAD, xtol=1e-16)
    xi_r, xi_f = xi(X_r), xi(X_f)

    def p(X):
        X = np.atleast_1d(np.asarray(X, float))
        out = np.full_like(X, p_cav)
        a, b = X <= X_r, X >= X_f
        out[a] = wedge(0.0, X[a], xi_r)
        out[b] = p_cav + wedge(X_f, X[b], xi_f)
        return out

    return X_r, X_f, p


def test_cavitation_film_is_converging_diverging():
    X = np.linspace(0.0, PAD, 201)
    full = single_harmonic_pressure(X, CAV["n"], CAV["phi"], CAV["x0"], CAV["V_r"])
    assert -2e3 < full.min() < -1e3 and 1.5e4 < full.max() < 1.6e4
    for p_cav in (0.0, -500.0, -1000.0):
        X_r, X_f, p = swift_stieber_reference(p_cav)
        assert 0.03 < X_r <= X_f <= PAD
        assert_allclose(p(np.array([PAD])), 0.0, atol=1e-8 * full.max())  # the reference closes


@pytest.mark.parametrize("p_cav", [0.0, -1000.0])
def test_half_sommerfeld_clips_the_full_solution(p_cav):
    _, xi = _cav_film()
    X = np.linspace(0.0, PAD, 201)
    full = single_harmonic_pressure(X, CAV["n"], CAV["phi"], CAV["x0"], CAV["V_r"])
    p = pressure(X, xi, CAV["V_r"], MU, cavitation="half-sommerfeld", p_cav=p_cav)
    # exact clipping of the full solution; measured ~1e-12 of max p (oracle round-off)
    assert_allclose(p, np.maximum(full, p_cav), rtol=0, atol=1e-10 * full.max())
    assert p.min() >= p_cav


@pytest.mark.parametrize("p_cav", [0.0, -1000.0])
def test_half_sommerfeld_modal_force(p_cav):
    from scipy.optimize import brentq

    q = np.array([CAV["phi"], 0.0, 0.0])
    betas = np.arange(1, 4) * np.pi / ROD
    full = lambda X: single_harmonic_pressure(np.atleast_1d(X), CAV["n"], CAV["phi"], CAV["x0"], CAV["V_r"])  # noqa: E731
    # kinks of the clipped pressure: sign changes of full - p_cav, refined by brentq
    Xs = np.linspace(1e-6, PAD - 1e-6, 501)
    d = full(Xs) - p_cav
    kinks = [brentq(lambda X: full(X)[0] - p_cav, Xs[i], Xs[i + 1], xtol=1e-16)
             for i in np.nonzero(np.sign(d[:-1]) != np.sign(d[1:]))[0]]
    assert len(kinks) == (1 if p_cav == 0 else 2)
    p = lambda X: max(full(X)[0], p_cav)  # noqa: E731
    F_ref = np.array([-WIDTH * integrate.quad(lambda X: p(X) * np.sin(b * (CAV["x0"] + X)), 0.0, PAD,
                                              points=kinks, **QUAD)[0] for b in betas])
    t_ref = -WIDTH * integrate.quad(p, 0.0, PAD, points=kinks, **QUAD)[0]
    scale = np.abs(F_ref).max()
    # Gauss-Legendre across the kink of the clipped pressure converges only
    # algebraically: measured 1.7e-4 (32 nodes, the default) and 1.6e-6 (256 nodes)
    # relative to max|F_n| for p_cav = 0.
    for nodes, tol in ((32, 1e-3), (256, 1e-5)):
        F, t, _ = modal_force(q, np.zeros(3), CAV["x0"], CAV["V_r"], cavitation="half-sommerfeld", p_cav=p_cav,
                              nodes=nodes, **film_kwargs())
        assert_allclose(F, F_ref, rtol=0, atol=tol * scale)
        assert_allclose(t, t_ref, rtol=0, atol=tol * scale)


@pytest.mark.parametrize("p_cav", [0.0, -500.0, -1000.0])
def test_reynolds_cavitation_matches_swift_stieber(p_cav):
    _, xi = _cav_film()
    X_r, X_f, p_ref = swift_stieber_reference(p_cav)
    X = np.linspace(0.0, PAD, 101)
    ref = p_ref(X)
    scale = ref.max()
    # Finite volumes with the obstacle condition: the error is set by how the grid
    # resolves the free boundaries. Measured max error / max p: <= 1.1e-5 at the
    # default 401 points, <= 8e-7 at 1601 (vs 1.6e-4 at 101 points).
    for grid_points, tol in ((401, 5e-5), (1601, 5e-6)):
        p = pressure(X, xi, CAV["V_r"], MU, cavitation="reynolds", p_cav=p_cav, grid_points=grid_points)
        assert_allclose(p, ref, rtol=0, atol=tol * scale)
        assert p.min() >= p_cav
    # the full-film solution is really different (it goes below p_cav and has no
    # cavitated zone), so the check above is not passed by the uncavitated solver
    full = pressure(X, xi, CAV["V_r"], MU)
    assert np.abs(full - ref).max() > 1e-2 * scale  # measured 2.3e-2 (p_cav = -1 kPa) to 9e-2


@pytest.mark.parametrize("p_cav", [0.0, -1000.0])
def test_reynolds_cavitation_modal_force(p_cav):
    X_r, X_f, p_ref = swift_stieber_reference(p_cav)
    q = np.array([CAV["phi"], 0.0, 0.0])
    betas = np.arange(1, 4) * np.pi / ROD
    p = lambda X: p_ref(X)[0]  # noqa: E731
    F_ref = np.array([-WIDTH * integrate.quad(lambda X: p(X) * np.sin(b * (CAV["x0"] + X)), 0.0, PAD,
                                              points=[X_r, X_f], **QUAD)[0] for b in betas])
    t_ref = -WIDTH * integrate.quad(p, 0.0, PAD, points=[X_r, X_f], **QUAD)[0]
    scale = np.abs(F_ref).max()
    # trapezoid on the solver grid: measured 3.6e-5..5.1e-5 (201 points, the default)
    # and 1.9e-6..4.3e-6 (801 points) relative to max|F_n|.
    for grid_points, tol in ((201, 2e-4), (801, 1e-5)):
        F, t, _ = modal_force(q, np.zeros(3), CAV["x0"], CAV["V_r"], cavitation="reynolds", p_cav=p_cav,
                                   grid_points=grid_points, **film_kwargs())
        assert_allclose(F, F_ref, rtol=0, atol=tol * scale)
        assert_allclose(t, t_ref, rtol=0, atol=tol * scale)


def test_grid_modal_force_is_the_trapezoidal_sine_transform():
    """grid_modal_force (the Reynolds-cavitation and finite-width films' last step) against quadrature:
    the error of the trapezoidal rule falls like h^2, the scale and the side multiply."""
    from lubelink.film.force import _tables
    from lubelink.film.reynolds import grid_modal_force

    x0, P0, N = 0.31, 2.5e4, 3
    beta = np.arange(1, N + 1) * np.pi / ROD
    ws = np.r_[np.sin(beta * x0), np.cos(beta * x0)]
    ref = np.array([-WIDTH * integrate.quad(lambda X: P0 * np.sin(np.pi * X / PAD) * np.sin(b * (x0 + X)), 0.0, PAD,
                                            **QUAD)[0] for b in beta])
    t_ref = -WIDTH * P0 * 2 * PAD / np.pi
    errors = []
    for G in (51, 101, 201):
        grid = np.linspace(0.0, PAD, G)
        trig = np.stack(_tables(beta, grid) + _tables(beta, grid))
        F = np.zeros(N)
        total = grid_modal_force(1.0, P0 * np.sin(np.pi * grid / PAD), grid[1], WIDTH, ws, trig, F)
        errors.append(max(np.abs(F - ref).max(), abs(total - t_ref)) / abs(t_ref))
        F_lower = np.zeros(N)
        lower = grid_modal_force(-1.0, P0 * np.sin(np.pi * grid / PAD), grid[1], 1.0, ws, trig, F_lower)
        assert_allclose(F_lower, -F / WIDTH, rtol=1e-14)
        assert lower == pytest.approx(-total / WIDTH, rel=1e-14)
    assert errors[-1] < 1e-4 and 3.9 < errors[0] / errors[1] < 4.1 and 3.9 < errors[1] / errors[2] < 4.1


# ----------------------------------------------------------------------------------
# 7. Bad input
# ----------------------------------------------------------------------------------

GOOD_XI = _slider_xi(2e-4, 1e-4, PAD)


def test_rejects_non_positive_film():
    X = np.linspace(0.0, PAD, 11)
    with pytest.raises(ValueError, match="film thickness xi must be finite and positive"):
        pressure(X, lambda X: 1e-4 - 4e-3 * np.asarray(X), 1.0, MU)  # negative beyond X = 25 mm
    with pytest.raises(ValueError, match="film thickness xi must be finite and positive"):
        pressure(X, lambda X: np.full_like(X, -1e-4), 1.0, MU)
    with pytest.raises(ValueError, match="film thickness xi must be finite and positive"):
        pressure(X, lambda X: np.full_like(X, np.nan), 1.0, MU)


@pytest.mark.parametrize("cavitation", ["none", "reynolds"])
@pytest.mark.parametrize("where", ["end", "start"])
def test_rejects_film_closed_at_pad_edge(where, cavitation):
    # Contact at a collar edge (docs/model.md §5.3: "often a collar edge") is a film of
    # zero thickness at X = 0 or X = l. The Reynolds integrals diverge there and no
    # pressure exists, so `pressure` must refuse, as its error message promises
    # ("positive on the whole pad"). It checks xi only at interior points (Gauss-
    # Legendre nodes; cell midpoints for "reynolds"), so this currently returns finite
    # numbers (~2.7e7 Pa next to the edge).
    X = np.linspace(0.0, PAD, 11)
    xi = (lambda X: 1e-4 * (1.0 - np.asarray(X) / PAD)) if where == "end" else (lambda X: 1e-4 * np.asarray(X) / PAD)
    with pytest.raises(ValueError, match="positive"):
        pressure(X, xi, 1.0, MU, cavitation=cavitation)


def test_rejects_positions_outside_pad():
    with pytest.raises(ValueError, match=r"X must lie in \[0, pad_length"):
        pressure(np.array([-1e-3, 0.01, PAD]), GOOD_XI, 1.0, MU)
    with pytest.raises(ValueError, match=r"X must lie in \[0, pad_length"):
        pressure(np.array([0.0, 0.01, 0.06]), GOOD_XI, 1.0, MU, pad_length=PAD)
    with pytest.raises(ValueError, match=r"X must lie in \[0, pad_length"):
        pressure(np.array([0.0]), GOOD_XI, 1.0, MU)  # zero-length pad


def test_rejects_unsorted_positions():
    with pytest.raises(ValueError, match="increasing"):
        pressure(np.array([0.0, 0.03, 0.02, PAD]), GOOD_XI, 1.0, MU)
    with pytest.raises(ValueError, match="increasing"):
        pressure(np.array([]), GOOD_XI, 1.0, MU)
    with pytest.raises(ValueError, match="increasing"):
        pressure(np.zeros((2, 2)), GOOD_XI, 1.0, MU)


def test_rejects_film_array_of_wrong_shape():
    X = np.linspace(0.0, PAD, 11)
    with pytest.raises(ValueError, match="xi must be a callable or an array shaped like X"):
        pressure(X, GOOD_XI(X)[:-1], 1.0, MU)
    with pytest.raises(ValueError, match="xi_t must be a callable or an array shaped like X"):
        pressure(X, GOOD_XI, 1.0, MU, xi_t=np.zeros(3))


def test_rejects_film_array_not_spanning_pad():
    # The docstring says that when xi is given as values at X, "X must run from 0 to l"
    # (the spline is the film on the whole pad). With X starting at 10 mm the spline
    # is silently extrapolated over [0, 10 mm] instead; it should raise.
    X = np.linspace(0.01, PAD, 11)
    with pytest.raises(ValueError):
        pressure(X, GOOD_XI(X), 1.0, MU, pad_length=PAD)

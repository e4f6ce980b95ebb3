"""Tests of the finite-width film (``lubelink.film.width``: terms across the width, the short bearing).

* the fitted terms against the closed forms of the width functions ``1 - tanh(x)/x`` and
  ``1 - 1/cosh(x)``, the sine terms against their partial fractions;
* the accuracy the docs state, over ``B / l`` from 0.1 to 100: the parallel squeeze film against
  its classical closed form, wedges with squeeze against ``pressure_2d`` on a grid graded towards
  the side edges;
* the terms against the general 2-D solver ``pressure_2d`` (sparse finite volumes, another
  method) over ``B / l`` from 0.2 to 5, with the squeeze term, and clipped (half-Sommerfeld);
* second-order convergence on the pad grid, and the decay of the sine series' tail;
* the limits: a wide pad is the 1-D film (first-integral quadrature), a narrow one the short bearing;
* the short film against its closed form on a linear wedge, its half-Sommerfeld and Swift-Stieber
  widths against a clipped quadrature and the 1-D obstacle solver across the width;
* the model: modal film forces equal ``-int int p sin(beta_n x)`` of ``pressure_2d``'s pressure,
  the numba and numpy backends run the ``paper`` scenario alike, unsupported options are refused.
"""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

import lubelink
from lubelink.config import ConfigError, resolve
from lubelink.film import pressure, pressure_2d, reynolds_cavitation, width_pressure, width_terms
from lubelink.film.width_table import ERRORS, TERMS
from lubelink.build import build_model

L_PAD = 0.05
MU = 0.1
H0 = 1e-4
V = 1.5


def wedge(X):
    return H0 * (2.0 - X / L_PAD)


def squeeze(X):
    return -2e-3 * np.sin(np.pi * X / L_PAD)


def test_fitted_terms_hold_the_width_functions():
    """On each eigenfunction of the pad the 2-D film is its 1-D film times ``g(x) = 1 - tanh(x) / x`` (the
    width integral over ``B``) or ``h(x) = 1 - 1 / cosh(x)`` (the centre line), ``x = sqrt(lambda) B / 2``;
    ``J`` terms give ``sum_j w_j x^2 / (x^2 + sigma_j^2)``. Relative errors within the tabulated ones on
    [1e-4, 1e8], fewer with more terms; 8 terms (the default) within 2e-4 and 5e-4."""
    x = np.logspace(-4, 8, 24001)
    g = 1 - np.tanh(x) / x
    h = 1 - 1 / np.cosh(np.minimum(x, 700))
    worst = []
    for J in sorted(TERMS):
        sigma, alpha, beta = (np.array(row) for row in TERMS[J])
        r = x[:, None] ** 2 / (x[:, None] ** 2 + sigma[None, :] ** 2)
        eg, eh = np.abs(r @ alpha / g - 1).max(), np.abs(r @ beta / h - 1).max()
        assert eg <= 1.05 * ERRORS[J][0] and eh <= 1.05 * ERRORS[J][1], J
        worst.append(max(eg, eh))
    assert np.all(np.diff(worst) < 0)
    assert ERRORS[8][0] < 2e-4 and ERRORS[8][1] < 5e-4
    t = width_terms(8)  # the model's table: these terms and weights
    assert_allclose(t[:3, :8], np.array(TERMS[8]), rtol=0, atol=0)


def test_width_functions():
    """``width_mean = 1 - tanh(x) / x`` and ``width_profile = 1 - cosh(zeta x) / cosh(x)``, their small-``x`` limits
    ``x^2 / 3`` and ``(1 - zeta^2) x^2 / 2`` (the short bearing's parabola), finite at large ``x``."""
    from lubelink.film import width_mean, width_profile

    x = np.array([1e-3, 5e-3, 0.02, 0.5, 3.0, 40.0])
    assert_allclose(width_mean(x), 1 - np.tanh(x) / x, rtol=1e-9)
    assert_allclose(width_mean(1e-5), 1e-10 / 3, rtol=1e-9)
    for zeta in (0.0, 0.3, -0.9):
        assert_allclose(width_profile(x, zeta), 1 - np.cosh(zeta * x) / np.cosh(x), rtol=1e-8)  # (its cancellation)
        assert_allclose(width_profile(1e-5, zeta), (1 - zeta ** 2) * 1e-10 / 2, rtol=1e-6)
    assert_allclose(width_profile(np.array([1e3, 1e8]), 0.5), 1.0)
    assert_allclose(width_mean(np.array([1e3, 1e8])), [1 - 1e-3, 1 - 1e-8])


def test_sine_terms_are_the_partial_fractions():
    """``g = sum_k 8 / (k pi)^2 x^2 / (x^2 + (k pi / 2)^2)``, ``h`` the same with ``+-4 / (k pi)``, ``k`` odd; the
    weights across the width ``(4 / (k pi)) sin(k pi s)``."""
    x = np.logspace(-3, 1, 200)
    t = width_terms(400, "sine", points=3)[:, :400]
    r = x[:, None] ** 2 / (x[:, None] ** 2 + t[0][None, :] ** 2)
    assert_allclose(r @ t[1], 1 - np.tanh(x) / x, rtol=1e-6)
    assert_allclose(r @ t[2], 1 - 1 / np.cosh(x), rtol=1e-6)
    k = 2 * np.arange(400) + 1
    assert_allclose(t[4], 4 / (np.pi * k) * np.sin(np.pi * k * 0.5))  # the middle point is the centre line


@pytest.fixture(scope="module")
def refs():
    """The references of docs/film2d.md's accuracy table: the squeeze plates in closed form, the graded width."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).parents[1] / "tools" / "figures"))
    import film2d_accuracy

    return film2d_accuracy


@pytest.mark.parametrize("ratio", [0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0])
def test_accuracy_over_the_aspect_ratio(ratio, refs):
    """The default settings (8 fitted terms, 201 pad points) hold the load within 0.2 % and the centre line
    within 0.5 % of its peak for any ``B / l`` up to 100: the parallel squeeze film against its closed form,
    linear wedges (thickness ratio 2 and 10) with squeeze against ``pressure_2d`` on the same pad grid, graded
    across the width (docs/film2d.md, the accuracy table: tools/figures/film2d_accuracy.py)."""
    B = ratio * L_PAD
    xt = -1e-3
    g, P, pc = width_pressure(lambda X: H0 + 0 * X, 0.0, MU, B, L_PAD, xi_t=lambda X: xt + 0 * X)
    load, centre = refs.squeeze_plates(g, B, L_PAD, 12 * MU * xt / H0 ** 3)
    assert abs(np.trapezoid(P, g) / load - 1) < 2e-3
    assert np.abs(pc - centre).max() < 5e-3 * np.abs(centre).max()
    Z = refs.graded_width(B, L_PAD)
    for steep in (2.0, 10.0):
        def xi(X):
            return H0 * (steep - (steep - 1) * X / L_PAD)

        g, P, pc = width_pressure(xi, V, MU, B, L_PAD, xi_t=squeeze)
        p = pressure_2d(g, Z, xi(g)[:, None], V, MU, xi_t=squeeze(g)[:, None])
        line = p[:, Z.size // 2]
        assert abs(np.trapezoid(P, g) / np.trapezoid(np.trapezoid(p, Z, axis=1), g) - 1) < 2e-3
        assert np.abs(pc - line).max() < 5e-3 * np.abs(line).max()


@pytest.mark.parametrize("ratio", [0.2, 1.0, 5.0])
def test_series_matches_the_2d_solver(ratio):
    B = ratio * L_PAD
    g, P, pc = width_pressure(wedge, V, MU, B, L_PAD, xi_t=squeeze, grid_points=401)
    X, Z = np.linspace(0, L_PAD, 401), np.linspace(-B / 2, B / 2, 161)
    p = pressure_2d(X, Z, wedge(X)[:, None], V, MU, xi_t=squeeze(X)[:, None])
    P2 = np.trapezoid(p, Z, axis=1)
    assert_allclose(np.trapezoid(P, g), np.trapezoid(P2, X), rtol=2e-3)
    assert_allclose(P, P2, atol=3e-3 * np.abs(P2).max())
    assert_allclose(pc, p[:, 80], atol=3e-3 * np.abs(p).max())


def test_series_second_order_on_the_grid():
    loads = [np.trapezoid(*width_pressure(wedge, V, MU, 0.01, L_PAD, xi_t=squeeze, grid_points=G)[1::-1])
             for G in (51, 101, 201, 401)]
    d = np.abs(np.diff(loads))
    assert_allclose(np.log2(d[:-1] / d[1:]), 2.0, atol=0.1)


def test_sine_series_tail():
    """On a pad no wider than long the sine terms' loads fall like ``k^-4`` (``c_k`` and the width integral
    ``~ 1/k``, ``p_k ~ 1/k^2``): tail ``~ K^-3``."""
    def load(K):
        g, P, _ = width_pressure(wedge, V, MU, 0.05, L_PAD, modes=K, series="sine")
        return np.trapezoid(P, g)

    ref = load(400)
    e4, e8 = abs(load(4) - ref), abs(load(8) - ref)
    assert e8 < 2e-3 * abs(ref)
    assert 5.0 < e4 / e8 < 12.0


def test_wide_pad_is_the_1d_film():
    misfit = []
    for ratio in (10, 20):
        B = ratio * L_PAD
        g, P, pc = width_pressure(wedge, V, MU, B, L_PAD, xi_t=squeeze, grid_points=401)
        p1 = pressure(g, wedge, V, MU, xi_t=squeeze)
        assert_allclose(pc, p1, atol=1e-3 * p1.max())
        misfit.append(1 - np.trapezoid(P, g) / (B * np.trapezoid(p1, g)))
    # the side strips, where the pressure falls to ambient, are ~ l wide: a load deficit ~ l / B
    assert 0 < misfit[1] < misfit[0] < 0.2
    assert_allclose(misfit[0] / misfit[1], 2.0, rtol=0.05)


def test_narrow_pad_is_the_short_bearing():
    B = 0.005 * L_PAD
    g, P, pc = width_pressure(wedge, V, MU, B, L_PAD, grid_points=2001)
    _, Ps, pcs = width_pressure(wedge, V, MU, B, L_PAD, reynolds="short", grid_points=2001)
    inner = (g > 5 * B) & (g < L_PAD - 5 * B)
    assert_allclose(P[inner], Ps[inner], rtol=2e-3)
    assert_allclose(pc[inner], pcs[inner], rtol=2e-3)


def test_short_film_closed_form():
    """``p = A (Z^2 - B^2/4)``, ``A = (3 mu / xi^3)(V xi' + 2 xi_t)``; on ``xi = 2 H0 - s X`` with constant ``xi_t``
    the load is ``-(mu B^3 / 2)(2 xi_t - s V) int xi^-3``, ``int_0^l xi^-3 = ((2H0 - s l)^-2 - (2H0)^-2) / (2 s)``."""
    B, s, c = 0.01, H0 / L_PAD, -1e-3
    exact = -(MU * B ** 3 / 2) * (2 * c - s * V) * ((H0) ** -2 - (2 * H0) ** -2) / (2 * s)
    errors = []
    for G in (101, 201, 401):
        g, P, pc = width_pressure(wedge, V, MU, B, L_PAD, xi_t=lambda X: c + 0 * X, reynolds="short", grid_points=G)
        errors.append(abs(np.trapezoid(P, g) / exact - 1))
        A = 3 * MU / wedge(g) ** 3 * (-s * V + 2 * c)
        assert_allclose(pc[1:-1], -A[1:-1] * B ** 2 / 4, rtol=1e-12)
    assert errors[-1] < 1e-4
    assert_allclose(np.log2(np.array(errors[:-1]) / errors[1:]), 2.0, atol=0.1)


@pytest.mark.parametrize("p_cav", [-2e3, -101325.0])
def test_short_film_cavitation(p_cav):
    """A separating film (``xi_t > 0``): the clipped parabola by quadrature, the Swift-Stieber width by the
    1-D obstacle solver applied across the width (``xi^3 p_ZZ = 12 mu xi_t``)."""
    B, xt = 0.01, 1e-2
    A = 0.5 * 12 * MU * xt / H0 ** 3
    assert -A * B ** 2 / 4 < p_cav  # cavitates
    flat = lambda X: H0 + 0 * X  # noqa: E731
    g, P, pc = width_pressure(flat, 0.0, MU, B, L_PAD, xi_t=lambda X: xt + 0 * X, reynolds="short",
                              cavitation="half-sommerfeld", p_cav=p_cav, grid_points=21)
    Z = np.linspace(-B / 2, B / 2, 200001)
    assert_allclose(P[1:-1], np.trapezoid(np.maximum(A * (Z ** 2 - B ** 2 / 4), p_cav), Z), rtol=1e-8)
    assert_allclose(pc[1:-1], p_cav)
    g, P, pc = width_pressure(flat, 0.0, MU, B, L_PAD, xi_t=lambda X: xt + 0 * X, reynolds="short",
                              cavitation="reynolds", p_cav=p_cav, grid_points=21)
    Zg = np.linspace(-B / 2, B / 2, 1001)
    p_line = np.empty_like(Zg)
    reynolds_cavitation(Zg, np.full(Zg.size - 1, H0), np.full(Zg.size, xt), 0.0, MU, p_cav, p_line)
    assert_allclose(P[1:-1], np.trapezoid(p_line, Zg), rtol=1e-4)
    assert p_line.min() >= p_cav


def _hump(X):
    return H0 * (1.0 + 0.6 * np.cos(2 * np.pi * X / L_PAD))


@pytest.mark.parametrize("ratio", [0.4, 10.0, 100.0])
def test_2d_half_sommerfeld_matches_the_2d_solver(ratio, refs):
    """The default 32 points across the width, gathered at its edges, on a narrow and on wide pads."""
    B, p_cav = ratio * L_PAD, -3e3 * min(ratio, 10.0)
    g, P, pc = width_pressure(_hump, 1.0, MU, B, L_PAD, cavitation="half-sommerfeld", p_cav=p_cav)
    Z = refs.graded_width(B, L_PAD)
    p = pressure_2d(g, Z, _hump(g)[:, None], 1.0, MU, cavitation="half-sommerfeld", p_cav=p_cav)
    assert 0.2 < np.mean(p == p_cav) < 0.8  # clipping is active
    P2 = np.trapezoid(p, Z, axis=1)
    assert abs(np.trapezoid(P, g) / np.trapezoid(P2, g) - 1) < 2e-3
    assert_allclose(P, P2, atol=2e-3 * np.abs(P2).max())
    assert_allclose(pc, p[:, Z.size // 2], atol=2e-3 * np.abs(p).max())


@pytest.mark.parametrize("sides", [1, 2])
def test_model_film_force_is_the_pressure_integral(sides):
    cfg = resolve("paper", {"beam.modes": 3, "film.reynolds": "2d", "film.model": "wedge+squeeze",
                            "film.clearance": 1e-3, "film.sides": sides,
                            "film.grid_points": 401})
    model = build_model(cfg)
    q = np.array([1.5e-4, -6e-5, 3e-5])
    q_dot = np.array([2e-3, 1e-3, -5e-4])
    t = 0.3
    F, total = model.film_loads(t, np.concatenate([q, q_dot]))
    x_star, V_r = model.kinematics(t).x_star, model.kinematics(t).V_r
    L, B, fm = cfg.mechanism.rod_length, cfg.beam.width, cfg.film
    beta = np.arange(1, 4) * np.pi / L
    X, Z = np.linspace(0, fm.pad_length, 401), np.linspace(-B / 2, B / 2, 81)
    u2 = np.sin(np.outer(x_star + X, beta)) @ q
    u2_dot = np.sin(np.outer(x_star + X, beta)) @ q_dot
    F_ref, total_ref = np.zeros(3), 0.0
    for side in (1, -1)[:sides]:
        p = pressure_2d(X, Z, (0.5 * fm.clearance - side * u2)[:, None], V_r, fm.viscosity,
                        xi_t=-side * u2_dot[:, None])
        P = np.trapezoid(p, Z, axis=1)
        F_ref -= side * np.trapezoid(P[:, None] * np.sin(np.outer(x_star + X, beta)), X, axis=0)
        total_ref -= side * np.trapezoid(P, X)
    assert_allclose(F, F_ref, rtol=3e-3, atol=3e-3 * np.abs(F_ref).max())
    assert_allclose(total, total_ref, rtol=3e-3)


@pytest.mark.parametrize("reynolds", ["2d", "short"])
def test_paper_backends_agree(reynolds):
    common = {"film.reynolds": reynolds, "solver.t_end": 0.05, "film.cavitation": "half-sommerfeld",
              "film.cavitation_pressure": 101225.0, "film.grid_points": 51, "output.pad_points": 11}
    a = lubelink.simulate("paper", set={**common, "solver.backend": "numba"})
    b = lubelink.simulate("paper", set={**common, "solver.backend": "numpy"})
    assert a.attrs["complete"] and b.attrs["complete"]
    assert_allclose(a.u2_mid, b.u2_mid, rtol=1e-9, atol=1e-12)
    assert_allclose(a.film_force, b.film_force, rtol=1e-8, atol=1e-9 * float(np.abs(b.film_force).max()))
    assert_allclose(a.pressure, b.pressure, rtol=1e-8, atol=1e-8 * float(np.abs(b.pressure).max()))
    assert float(np.abs(a.film_force).max()) > 0


def test_config_refuses_2d_with_swift_stieber():
    with pytest.raises(ConfigError, match=r"film.cavitation = 'reynolds': not available with film.reynolds = '2d'"):
        resolve("paper", {"film.reynolds": "2d", "film.cavitation": "reynolds"})
    resolve("paper", {"film.reynolds": "short", "film.cavitation": "reynolds"})  # supported
    with pytest.raises(ConfigError) as info:
        resolve("paper", {"film.reynolds": "3d", "film.width_modes": 0, "film.width_points": 2})
    text = str(info.value)
    assert "film.reynolds = '3d': must be one of \"1d\", \"2d\", \"short\"" in text
    assert "film.width_modes = 0: must be an integer in [1, 200]" in text
    assert "film.width_points = 2: must be an integer in [4, 4096]" in text
    with pytest.raises(ConfigError) as info:
        resolve("paper", {"film.reynolds": "2d", "film.width_series": "fourier"})
    assert "film.width_series = 'fourier': must be one of \"fitted\", \"sine\"" in str(info.value)
    with pytest.raises(ConfigError) as info:
        resolve("paper", {"film.reynolds": "2d", "film.width_modes": 30})
    text = str(info.value)
    assert f"film.width_modes = 30: must be an integer in [1, {max(TERMS)}] with film.width_series = 'fitted'" in text
    assert "\n" not in text.strip()  # one line
    resolve("paper", {"film.reynolds": "2d", "film.width_modes": 30, "film.width_series": "sine"})


def test_width_pressure_rejects_bad_options():
    with pytest.raises(ValueError, match="pressure_2d"):
        width_pressure(wedge, V, MU, 0.01, L_PAD, cavitation="reynolds")
    with pytest.raises(ValueError, match="reynolds"):
        width_pressure(wedge, V, MU, 0.01, L_PAD, reynolds="1d")
    with pytest.raises(ValueError, match="positive"):
        width_pressure(lambda X: -wedge(X), V, MU, 0.01, L_PAD)

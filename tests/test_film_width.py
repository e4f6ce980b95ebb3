"""Tests of the finite-width film (``lubelink.film.width``: the sine series across the width, the short bearing).

* the series against the general 2-D solver ``pressure_2d`` (sparse finite volumes, another
  method) over ``B / l`` from 0.2 to 5, with the squeeze term, and clipped (half-Sommerfeld);
* second-order convergence on the pad grid, and the decay of the series' tail;
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
from lubelink.film import pressure, pressure_2d, reynolds_cavitation, width_pressure
from lubelink.build import build_model

L_PAD = 0.05
MU = 0.1
H0 = 1e-4
V = 1.5


def wedge(X):
    return H0 * (2.0 - X / L_PAD)


def squeeze(X):
    return -2e-3 * np.sin(np.pi * X / L_PAD)


@pytest.mark.parametrize("ratio", [0.2, 1.0, 5.0])
def test_series_matches_the_2d_solver(ratio):
    B = ratio * L_PAD
    g, P, pc = width_pressure(wedge, V, MU, B, L_PAD, xi_t=squeeze, modes=40, grid_points=401)
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


def test_series_tail():
    """The terms' loads fall like ``k^-4`` (``c_k`` and the width integral ``~ 1/k``, ``p_k ~ 1/k^2``): tail ``~ K^-3``."""
    def load(K):
        g, P, _ = width_pressure(wedge, V, MU, 0.05, L_PAD, modes=K)
        return np.trapezoid(P, g)

    ref = load(400)
    e4, e8 = abs(load(4) - ref), abs(load(8) - ref)
    assert e8 < 2e-3 * abs(ref)
    assert 5.0 < e4 / e8 < 12.0


def test_wide_pad_is_the_1d_film():
    misfit = []
    for ratio in (10, 20):
        B = ratio * L_PAD
        g, P, pc = width_pressure(wedge, V, MU, B, L_PAD, xi_t=squeeze, modes=4 * ratio, grid_points=401)
        p1 = pressure(g, wedge, V, MU, xi_t=squeeze)
        assert_allclose(pc, p1, atol=1e-3 * p1.max())
        misfit.append(1 - np.trapezoid(P, g) / (B * np.trapezoid(p1, g)))
    # the side strips, where the pressure falls to ambient, are ~ l wide: a load deficit ~ l / B
    assert 0 < misfit[1] < misfit[0] < 0.2
    assert_allclose(misfit[0] / misfit[1], 2.0, rtol=0.05)


def test_narrow_pad_is_the_short_bearing():
    B = 0.005 * L_PAD
    g, P, pc = width_pressure(wedge, V, MU, B, L_PAD, modes=20, grid_points=2001)
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


def test_2d_half_sommerfeld_matches_the_2d_solver():
    B, p_cav = 0.02, -3e3
    g, P, pc = width_pressure(_hump, 1.0, MU, B, L_PAD, modes=40, cavitation="half-sommerfeld", p_cav=p_cav,
                              grid_points=401, width_points=400)
    X, Z = g, np.linspace(-B / 2, B / 2, 401)
    p = pressure_2d(X, Z, _hump(X)[:, None], 1.0, MU, cavitation="half-sommerfeld", p_cav=p_cav)
    assert p.min() == p_cav  # clipping is active
    assert_allclose(P, np.trapezoid(p, Z, axis=1), atol=3e-3 * np.abs(P).max())
    assert_allclose(pc, p[:, 200], atol=3e-3 * np.abs(p).max())


@pytest.mark.parametrize("sides", [1, 2])
def test_model_film_force_is_the_pressure_integral(sides):
    cfg = resolve("paper", {"beam.modes": 3, "film.reynolds": "2d", "film.model": "wedge+squeeze",
                            "film.clearance": 1e-3, "film.sides": sides, "film.width_modes": 30,
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


def test_width_pressure_rejects_bad_options():
    with pytest.raises(ValueError, match="pressure_2d"):
        width_pressure(wedge, V, MU, 0.01, L_PAD, cavitation="reynolds")
    with pytest.raises(ValueError, match="reynolds"):
        width_pressure(wedge, V, MU, 0.01, L_PAD, reynolds="1d")
    with pytest.raises(ValueError, match="positive"):
        width_pressure(lambda X: -wedge(X), V, MU, 0.01, L_PAD)

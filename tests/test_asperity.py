"""Greenwood-Tripp asperity contact and the film's thickness floor (docs/breakdown.md) against independent references."""

import numpy as np
import pytest
from scipy import integrate, special

from lubelink.film import asperity
from lubelink.film.reynolds import effective_film


def f52_closed_form(lam):
    # F_{5/2}(lam) = Gamma(7/2) exp(-lam^2/4) D_{-7/2}(lam) / sqrt(2 pi), D the parabolic cylinder function
    return special.gamma(3.5) * np.exp(-lam**2 / 4) * special.pbdv(-3.5, lam)[0] / np.sqrt(2 * np.pi)


def f52_by_quad(lam):
    g = lambda s: (s - lam) ** 2.5 * np.exp(-s * s / 2)  # noqa: E731
    return integrate.quad(g, lam, np.inf, epsabs=0, epsrel=1e-12, limit=200)[0] / np.sqrt(2 * np.pi)


@pytest.mark.parametrize("lam", [-25.0, -4.0, -1.0, 0.0, 0.5, 1.0, 2.0, 3.0, 4.0, 5.0])
def test_f52_against_closed_form_and_quadrature(lam):
    assert asperity.f52(lam) == pytest.approx(f52_closed_form(lam), rel=1e-9)
    assert asperity.f52(lam) == pytest.approx(f52_by_quad(lam), rel=1e-8)


def test_f52_derivative_is_minus_five_halves_f32():
    # d/dlam F_n = -n F_{n-1}: checks the integrand, not the quadrature
    lam, h = 1.3, 1e-4
    f32 = integrate.quad(lambda s: (s - lam) ** 1.5 * np.exp(-s * s / 2), lam, np.inf)[0] / np.sqrt(2 * np.pi)
    slope = (asperity.f52(lam + h) - asperity.f52(lam - h)) / (2 * h)
    assert slope == pytest.approx(-2.5 * f32, rel=1e-6)


def test_pressure_is_greenwood_tripp():
    K = asperity.asperity_factor(0.04, 1e-3)
    assert K == pytest.approx(16 * np.sqrt(2) * np.pi / 15 * 0.04**2 * np.sqrt(1e-3), rel=1e-14)
    assert asperity.asperity_pressure(2e-6, 1e-6, K, 1.14e11) == pytest.approx(K * 1.14e11 * f52_closed_form(2.0),
                                                                               rel=1e-9)
    assert asperity.asperity_pressure(2e-6, 0.0, K, 1.14e11) == 0.0


def test_effective_film_is_continuous_with_its_slope_and_exact_above_twice_the_floor():
    hf = 1e-6
    xi = np.linspace(-3e-6, 5e-6, 8001)
    h = np.array([effective_film(x, hf) for x in xi])
    assert np.all(h >= hf) and np.all(np.diff(h) >= 0)
    above = xi >= 2 * hf
    np.testing.assert_array_equal(h[above], xi[above])
    slope = np.diff(h) / np.diff(xi)
    assert np.max(np.abs(np.diff(slope))) < 1e-2  # no jump of the slope (C1)
    assert effective_film(3e-6, 0.0) == 3e-6


def _model(**film):
    from lubelink.config import resolve
    from lubelink.model import build_model

    sets = {"film.model": "wedge+squeeze", "film.roughness": 1e-6, "beam.modes": 3, "film.quadrature_nodes": 64}
    sets.update({f"film.{k}": v for k, v in film.items()})
    return build_model(resolve("paper", sets))


def test_modal_asperity_force_against_adaptive_quadrature():
    m = _model()
    p, cfg = m.params, m.config
    L, B, H, sig = 1.0, cfg.beam.width, cfg.film.clearance, 1e-6
    q = np.array([H / 2 - 1.5e-6, 2e-5, -1e-5])  # the link reaches within ~1.5 sigma of the pad
    x_star = 0.47
    F = np.zeros(3)
    total = asperity.modal_asperity_force(q, x_star, p.film, B, p.pad, L, F)
    K = asperity.asperity_factor(0.04, 1e-3)
    beta = np.arange(1, 4) * np.pi

    def pa(x):
        return K * 1.14e11 * f52_closed_form((H / 2 - np.sin(beta * x) @ q) / sig)

    ref = [-B * integrate.quad(lambda x: pa(x) * np.sin(b * x), x_star, x_star + 0.05, limit=200,
                               epsrel=1e-10)[0] for b in beta]
    np.testing.assert_allclose(F, ref, rtol=2e-4)
    assert total == pytest.approx(-B * integrate.quad(pa, x_star, x_star + 0.05, limit=200)[0], rel=2e-4)
    assert total < 0  # pushes the link away from the collar face


def test_load_share_moves_from_film_to_asperities_as_the_gap_closes():
    # the link closing the gap slowly (10 nm/s), collar at rest: film and asperity loads; the
    # film floor at sigma keeps the film force finite below the roughness scale
    from lubelink import film

    m = _model(thickness_floor=1e-6)
    p, cfg = m.params, m.config
    B, H = cfg.beam.width, cfg.film.clearance
    shares = []
    for gap_sigma in (6.0, 4.0, 3.0, 2.0, 1.0, 0.5, 0.0, -1.0):
        q = np.array([H / 2 - gap_sigma * 1e-6, 0.0, 0.0])
        q_dot = np.array([1e-8, 0.0, 0.0])
        film_load = film.modal_film_force(q, q_dot, 0.475, 0.0, p.film, B, p.pad, 1.0, np.zeros(3))
        asp_load = asperity.modal_asperity_force(q, 0.475, p.film, B, p.pad, 1.0, np.zeros(3))
        assert np.isfinite(film_load) and film_load < 0 and asp_load <= 0
        shares.append(asp_load / (asp_load + film_load))
    assert shares[0] < 1e-6 and shares[-1] > 0.9
    assert np.all(np.diff(shares) > 0)

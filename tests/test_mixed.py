"""The share of a run in mixed lubrication, up front (lubelink.mixed): the propped link against the closed
forms of a beam on three supports, the asperity force against the code's own quadrature of F_{5/2}, and
the shares' behaviour over the clearance (their cost against measured runs: benchmarks/bench.py --only
estimate, not a test)."""

import numpy as np
import pytest

import lubelink
from lubelink.film.asperity import asperity_factor, f52
from lubelink.mixed import (REACH, asperity_force, mixed_share, pad_films, prop_force, propped_deflection,
                            settled_shift)

L, EI, W = 1.3, 170.0, 40.0  # [m], [N m^2], a uniform load [N/m]
MODES = 200


def uniform_load():
    """Modal loads ``int w sin(beta_n x) dx`` [N] of a uniform load, modal stiffnesses ``EI beta^4 L / 2`` [N/m]."""
    n = np.arange(1, MODES + 1)
    beta = n * np.pi / L
    return W * (1.0 - np.cos(n * np.pi)) / beta, EI * beta**4 * L / 2.0, beta


def free_deflection(x):
    """Simply supported beam under the uniform load ``W``: ``w x (L^3 - 2 L x^2 + x^3) / (24 EI)``."""
    return W * x * (L**3 - 2.0 * L * x**2 + x**3) / (24.0 * EI)


def influence(x, a):
    """Deflection at ``x >= a`` of a simply supported beam under a unit load at ``a``:
    ``a (L - x) (2 L x - x^2 - a^2) / (6 EI L)``."""
    return a * (L - x) * (2.0 * L * x - x**2 - a**2) / (6.0 * EI * L)


def test_a_prop_at_midspan_carries_five_eighths_of_a_uniform_load():
    F, k, beta = uniform_load()
    assert prop_force(F, k, np.sin(beta * L / 2)) == pytest.approx(5.0 * W * L / 8.0, rel=1e-6)


@pytest.mark.parametrize("a", [0.2 * L, 0.37 * L, 0.8 * L])
def test_the_propped_link_is_the_closed_form_of_a_beam_on_three_supports(a):
    F, k, beta = uniform_load()
    s = np.sin(beta * a)
    P = prop_force(F, k, s)
    assert P == pytest.approx(free_deflection(a) / influence(a, a), rel=1e-6)
    x = np.array([a, a + 0.3 * (L - a), a + 0.7 * (L - a)])
    u = propped_deflection(F, k, s, np.sin(np.outer(x, beta)))
    assert u[0] == pytest.approx(0.0, abs=1e-9 * free_deflection(a))
    assert u[1:] == pytest.approx(free_deflection(x[1:]) - P * influence(x[1:], a), rel=1e-5)


def test_the_asperity_force_is_the_quadrature_of_the_code():
    """The closed form (a parabolic cylinder function) against the film's own Simpson rule, summed over the pad."""
    sigma, K, E, B, dx = 0.5e-6, asperity_factor(0.04, 1e-3), 1.1e11, 0.01, 1e-3
    h = np.array([[-0.3, 0.0, 0.8, 2.5, 6.0, 9.9, 12.0]]) * sigma
    expected = K * E * B * dx * sum(f52(v / sigma) for v in h[0])
    assert asperity_force(h, sigma, K, E, B, dx)[0] == pytest.approx(expected, rel=1e-8)


def test_one_mode_cannot_bend_through_the_collar_and_the_two_films_share_the_clearance():
    one = lubelink.resolve_config("guide", {"beam.modes": 1})
    h, _ = pad_films(one)
    assert h == pytest.approx(0.5 * one.film.clearance, abs=1e-15)
    guide = lubelink.resolve_config("guide")
    h, P = pad_films(guide)
    assert h[:, 0] + h[:, 1] == pytest.approx(guide.film.clearance, rel=1e-12)
    assert np.ptp(h) > 0.1 * guide.film.clearance and np.abs(P).max() > 0.0


def test_the_link_settles_where_the_asperities_carry_the_peak_joint_load():
    config = lubelink.resolve_config("guide")
    fm = config.film
    h, P = pad_films(config)
    shift = settled_shift(h, P, fm, config.beam.width)
    assert 0.0 < shift < 0.5 * fm.clearance
    side = int(np.argmin(h.min(axis=(0, 2))))
    K = asperity_factor(fm.summit_product, fm.summit_ratio)

    def carried(s):
        return asperity_force(h[:, side] - s, fm.roughness, K, fm.contact_modulus, config.beam.width,
                              fm.pad_length / h.shape[-1]).max()

    peak = np.abs(P).max()
    assert carried(shift - 0.02 * fm.roughness) < peak < carried(shift + 0.02 * fm.roughness)


def test_the_share_grows_as_the_clearance_closes_and_with_the_run():
    def share(clearance, t_end=2.0, **extra):
        return mixed_share(lubelink.resolve_config("guide", {"film.clearance": clearance, "solver.t_end": t_end,
                                                             **extra}))

    shares = [share(c) for c in (100e-6, 40e-6, 25e-6, 20e-6, 16e-6)]
    zones, loaded = [s.zone for s in shares], [s.loaded for s in shares]
    assert zones == sorted(zones) and loaded == sorted(loaded) and zones[0] == 0.0 < zones[-1] <= 0.5
    assert 0.0 <= min(loaded) and max(loaded) <= 1.0
    assert share(40e-6, 0.5).zone < share(40e-6, 2.0).zone  # the link sinks into the collar over the run
    assert share(40e-6, **{"film.roughness": 0.0}).zone == 0.0
    assert mixed_share(lubelink.resolve_config("paper")).zone == 0.0
    assert mixed_share(lubelink.resolve_config("spatial-slider-crank")).zone == 0.0
    far = share(40e-6, 0.2)  # 8 um of tilt and sinking short of the 10 roughness within reach
    assert far.zone == 0.0 and far.thinnest > REACH * 0.5e-6

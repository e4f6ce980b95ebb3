"""The analytic Jacobians (lubelink.film.jacobian, the asperity contact's, the model's) against
finite differences of the forces they differentiate, and the squeeze rate against the parallel-plate
squeeze film.

Central differences of the compiled right-hand side with steps chosen for each block (1e-10 m on
``q``, 1e-7 m/s on ``q_dot``) agree with the analytic entries to about 1e-9 of the largest entry;
the tolerance 1e-6 leaves room for the differences' own truncation error.
"""

import numpy as np
import pytest

from lubelink.build import build_model
from lubelink.config import resolve
from lubelink.film.asperity import asperity_stiffness, f52, greenwood_tripp_integral
from lubelink.film.force import modal_film_force
from lubelink.film.jacobian import has_film_jacobian, modal_film_jacobian, squeeze_rate
from lubelink.link.model import rhs
from conftest import central_differences

FILMS = [dict(model=m, cavitation=c, sides=s) for m in ("wedge", "wedge+squeeze")
         for c in ("none", "half-sommerfeld") for s in (1, 2)]



@pytest.mark.parametrize("opts", FILMS, ids=lambda o: "-".join(map(str, o.values())))
def test_film_jacobian_against_finite_differences(opts):
    cfg = resolve("lubricated", {"film.clearance": 1e-4, "beam.modes": 5, "film.model": opts["model"],
                                 "film.cavitation": opts["cavitation"], "film.sides": opts["sides"]})
    p = build_model(cfg).params
    rng = np.random.default_rng(1)
    N = 5
    q = rng.standard_normal(N) * 1e-5 / np.arange(1, N + 1) ** 2
    acted = 0.0
    for V_r in (1.3, -1.3):  # (one sign may cavitate the whole pad)
        q_dot = rng.standard_normal(N) * 1e-3
        args = (0.4, V_r, p.film, p.beam.width, p.pad, p.basis.rod_length)

        def force(q, q_dot):
            F = np.zeros(N)
            modal_film_force(q, q_dot, *args, F)
            return F

        Jq, Jv = np.zeros((N, N)), np.zeros((N, N))
        modal_film_jacobian(q, q_dot, *args, Jq, Jv)
        Jq_fd = central_differences(lambda x: force(x, q_dot), q, np.full(N, 1e-9))
        Jv_fd = central_differences(lambda x: force(q, x), q_dot, np.full(N, 1e-6))
        acted = max(acted, np.abs(Jq_fd).max())
        np.testing.assert_allclose(Jq, Jq_fd, rtol=0, atol=1e-6 * max(np.abs(Jq_fd).max(), 1.0))
        if opts["model"] == "wedge":
            assert not Jv.any()
        else:
            np.testing.assert_allclose(Jv, Jv_fd, rtol=0, atol=1e-6 * max(np.abs(Jv_fd).max(), 1.0))
    assert acted > 1e3  # the film acts


@pytest.mark.parametrize("cavitation", ["none", "half-sommerfeld"])
def test_rough_film_jacobian_near_contact_against_finite_differences(cavitation):
    """Rough surfaces within a few ``sigma`` of contact, no floor: the film is the mean gap and its squeeze
    flow carries the contact factor, which depends on ``q`` (the ``P`` term of the module's docstring)."""
    cfg = resolve("lubricated", {"film.clearance": 6e-6, "beam.modes": 4, "film.thickness_floor": 0.0,
                                 "film.cavitation": cavitation, "film.sides": 2})
    p = build_model(cfg).params
    N = 4
    q = np.array([1.5e-6, -4e-7, 2e-7, -1e-7])  # the gap 1.5 um +- 1.5 um along the pad: sigma = 1 um
    args = (0.4, 1.3, p.film, p.beam.width, p.pad, p.basis.rod_length)

    def force(q, q_dot):
        F = np.zeros(N)
        modal_film_force(q, q_dot, *args, F)
        return F

    q_dot = np.array([2e-3, -1e-3, 5e-4, 3e-4])
    Jq, Jv = np.zeros((N, N)), np.zeros((N, N))
    modal_film_jacobian(q, q_dot, *args, Jq, Jv)
    Jq_fd = central_differences(lambda x: force(x, q_dot), q, np.full(N, 1e-11))
    Jv_fd = central_differences(lambda x: force(q, x), q_dot, np.full(N, 1e-7))
    np.testing.assert_allclose(Jq, Jq_fd, rtol=0, atol=1e-6 * np.abs(Jq_fd).max())
    np.testing.assert_allclose(Jv, Jv_fd, rtol=0, atol=1e-6 * np.abs(Jv_fd).max())
    assert np.abs(Jq_fd).max() > 1e3


@pytest.mark.parametrize("sets", [
    {"film.clearance": 1e-4, "beam.modes": 5},
    {"film.clearance": 5e-6, "beam.modes": 4, "film.sides": 2, "beam.damping_ratio": 0.01},  # asperities touch
    {"beam.modes": 3, "model.equations": "printed"},
    {"film.clearance": 1e-4, "beam.modes": 3, "model.equations": "printed-film-sign", "film.thickness_floor": 2e-5},
], ids=["squeeze", "asperity", "printed", "film-sign-floor"])
def test_model_jacobian_against_finite_differences(sets):
    """The right-hand side's Jacobian (an ``out`` of ``n + n^2``) against its own differences, compiled."""
    cfg = resolve("lubricated", sets)
    model = build_model(cfg)
    assert model.jacobian_missing(None) == ""
    p = model.params
    n = 2 * cfg.beam.modes
    rng = np.random.default_rng(2)
    y = np.concatenate([rng.standard_normal(n // 2) * 2e-6, rng.standard_normal(n // 2) * 1e-3])
    t = 0.31
    out = np.empty(n + n * n)
    rhs(t, y, out, p)
    f = np.empty(n)
    rhs(t, y, f, p)
    np.testing.assert_array_equal(out[:n], f)

    def g(x):
        d = np.empty(n)
        rhs(t, x, d, p)
        return d

    J_fd = central_differences(g, y, np.r_[np.full(n // 2, 1e-10), np.full(n // 2, 1e-7)])
    np.testing.assert_allclose(out[n:].reshape(n, n), J_fd, rtol=0, atol=1e-6 * np.abs(J_fd).max())


def test_asperity_stiffness_is_the_derivative_of_the_pressure():
    """``F_5/2' = -5/2 F_3/2``; the closed form ``F_3/2(0) = Gamma(5/2) D_(-5/2)(0) / sqrt(2 pi)``."""
    from scipy.special import gamma, pbdv

    for lam in (-1.0, 0.5, 2.0, 4.0):
        d = (f52(lam + 1e-5) - f52(lam - 1e-5)) / 2e-5
        assert abs(d + 2.5 * greenwood_tripp_integral(lam, 1.5)) < 1e-8 * max(abs(d), 1e-6)
        closed = gamma(2.5) * np.exp(-lam ** 2 / 4) * pbdv(-2.5, lam)[0] / np.sqrt(2 * np.pi)
        assert abs(greenwood_tripp_integral(lam, 1.5) - closed) < 1e-9 * closed
    sigma, K, E = 1e-6, 1e-4, 2e11
    h = 2.5e-6
    d = (K * E * (f52((h + 1e-11) / sigma) - f52((h - 1e-11) / sigma))) / 2e-11
    assert abs(asperity_stiffness(h, sigma, K, E) - d) < 1e-6 * abs(d)


def test_squeeze_rate_is_the_parallel_plate_squeeze_film():
    """One mode, a short pad at the crest of mode 1, the link at rest and the collar still: the film's
    ``dF_1/dq_dot_1`` is the parallel-plate squeeze film ``-mu B l^3 / h^3`` (a classical closed form), so
    :func:`squeeze_rate` is ``-dF/dq_dot / m``."""
    cfg = resolve("lubricated", {"film.clearance": 1e-4, "beam.modes": 1, "film.pad_length": 0.01,
                                 "film.cavitation": "none"})
    model = build_model(cfg)
    p = model.params
    L, l = p.basis.rod_length, cfg.film.pad_length
    Jq, Jv = np.zeros((1, 1)), np.zeros((1, 1))
    modal_film_jacobian(np.zeros(1), np.zeros(1), 0.5 * (L - l), 0.0, p.film, p.beam.width, p.pad, L, Jq, Jv)
    mu, B, h = cfg.film.viscosity, cfg.beam.width, 0.5 * cfg.film.clearance
    plate = mu * B * l ** 3 / h ** 3
    assert abs(-Jv[0, 0] - plate) < 2e-4 * plate  # sin(beta x)^2 >= 0.9998 over the pad
    assert abs(squeeze_rate(cfg.film, B, p.basis.modal_mass) - plate / p.basis.modal_mass) < 1e-12 * plate


def test_what_the_analytic_jacobian_does_not_cover_is_named():
    for sets, words in [({"film.cavitation": "reynolds"}, "reynolds"), ({"film.reynolds": "2d"}, "2d")]:
        cfg = resolve("lubricated", sets)
        assert words in has_film_jacobian(cfg.film)
        assert words in build_model(cfg).jacobian_missing(None)
    assert build_model(resolve("spatial-slider-crank")).jacobian_missing(None) == ""
    assert "variable section" in build_model(resolve("spatial-slider-crank", {"beam.width_ratio": 0.7})).jacobian_missing(None)
    assert "sustained contact" in build_model(resolve("lubricated")).jacobian_missing((1.0, 0.1))
    assert build_model(resolve("lubricated", {"contact.law": "compliant"})).jacobian_missing((1.0, 0.1)) == ""


@pytest.mark.parametrize("v_minus", [0.05, 0.0], ids=["damped", "grazing"])
def test_compliant_contact_jacobian_in_a_contact_phase(v_minus):
    """The link pressed 1 um into the collar face: the right-hand side's Jacobian in the compliant
    contact phase (Lankarani-Nikravesh at the thinnest-film point) against its own differences."""
    cfg = resolve("lubricated", {"film.clearance": 1e-4, "beam.modes": 3, "contact.law": "compliant"})
    model = build_model(cfg)
    t = 0.37
    x_star, V_r = model.kinematics(t).x_star, model.kinematics(t).V_r
    L, l = cfg.mechanism.rod_length, cfg.film.pad_length
    x = np.linspace(x_star, x_star + l, 201)
    q = np.array([1.0, 0.02, -0.01])
    q *= (0.5 * cfg.film.clearance - cfg.contact.min_film + 1e-6) / np.max(np.sin(np.outer(x, [1, 2, 3]) * np.pi / L) @ q)
    y = np.r_[q, 0.01, -0.02, 0.005]
    p = model.with_phase((1.0, v_minus, 0.0))
    n = y.size
    out = np.empty(n + n * n)
    rhs(t, y, out, p)

    def g(z):
        d = np.empty(n)
        rhs(t, z, d, p)
        return d

    J = out[n:].reshape(n, n)
    J_fd = central_differences(g, y, np.r_[np.full(3, 1e-11), np.full(3, 1e-7)])
    assert np.abs(J[3:, :3] - central_differences(lambda z: plain_rhs(model.params, t, z), y, np.r_[np.full(3, 1e-11),
                  np.full(3, 1e-7)])[3:, :3]).max() > 1e3  # the contact adds stiffness
    np.testing.assert_allclose(J, J_fd, rtol=0, atol=1e-6 * np.abs(J_fd).max())


def plain_rhs(p, t, z):
    d = np.empty(z.size)
    rhs(t, z, d, p)
    return d

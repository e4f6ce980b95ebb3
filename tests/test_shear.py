"""The film's friction force and power loss (lubelink.film.shear) against closed forms and an independent quadrature."""

import numpy as np
import pytest
from scipy.integrate import quad

import lubelink
from lubelink.build import build_model
from lubelink.config import resolve
from lubelink.derived import film_losses
from lubelink.film.shear import dissipation, wall_shear
from lubelink.netcdf import config_of


def model_of(**film):
    overrides = {f"film.{k}": v for k, v in film.items()}
    return build_model(resolve("paper", {"beam.modes": 3, **overrides}))


def test_the_dissipation_is_the_integral_of_the_squared_shear_rate_across_the_film():
    mu, V, xi, dp = 0.1, 0.7, 3e-5, -4e6
    u_y = lambda y: V / xi + dp * (2.0 * y - xi) / (2.0 * mu)  # d/dy of V y/xi + dp (y^2 - xi y)/(2 mu)
    assert dissipation(xi, dp, V, mu) == pytest.approx(quad(lambda y: mu * u_y(y) ** 2, 0.0, xi)[0], rel=1e-12)
    assert wall_shear(xi, dp, V, mu) == pytest.approx(mu * u_y(0.0), rel=1e-12)


@pytest.mark.parametrize("sides", [1, 2])
def test_a_film_of_even_thickness_drags_the_link_as_plane_couette_flow(sides):
    m = model_of(sides=sides, clearance=1e-4)
    f = m.config.film
    q = np.zeros((2, 3))
    V = np.array([0.5, -1.2])
    friction, loss, _ = film_losses(m, q, q, np.array([0.3, 0.4]), V)
    friction = friction.sum(axis=0)
    h = 0.5 * f.clearance
    B = m.config.beam.width
    np.testing.assert_allclose(friction, sides * f.viscosity * V * B * f.pad_length / h, rtol=1e-12)
    np.testing.assert_allclose(loss, sides * f.viscosity * V**2 * B * f.pad_length / h, rtol=1e-12)


def reference(m, q, q_dot, x0, V, side):
    """Friction and power loss of one film by adaptive quadrature of the first integral, written from the equations."""
    f, B, L = m.config.film, m.config.beam.width, m.config.mechanism.rod_length
    mu, l = f.viscosity, f.pad_length
    beta = np.arange(1, q.size + 1) * np.pi / L
    xi = lambda X: 0.5 * f.clearance - side * np.sum(q * np.sin(beta * (x0 + X)))
    Q = lambda X: -side * np.sum(q_dot * (np.cos(beta * x0) - np.cos(beta * (x0 + X))) / beta)  # int_0^X xi_t
    if f.model == "wedge":
        Q = lambda X: 0.0
    I1 = quad(lambda X: xi(X) ** -2, 0, l, epsabs=0, epsrel=1e-13)[0]
    I2 = quad(lambda X: xi(X) ** -3, 0, l, epsabs=0, epsrel=1e-13)[0]
    I3 = quad(lambda X: Q(X) * xi(X) ** -3, 0, l, epsabs=0, epsrel=1e-13)[0]
    C = -(6 * mu * V * I1 + 12 * mu * I3) / I2
    dp = lambda X: (6 * mu * V * xi(X) + 12 * mu * Q(X) + C) / xi(X) ** 3
    friction = B * quad(lambda X: mu * V / xi(X) - 0.5 * xi(X) * dp(X), 0, l, epsabs=0, epsrel=1e-12)[0]
    loss = B * quad(lambda X: mu * V * V / xi(X) + xi(X) ** 3 * dp(X) ** 2 / (12 * mu), 0, l, epsabs=0,
                    epsrel=1e-12)[0]
    return friction, loss


@pytest.mark.parametrize("model", ["wedge", "wedge+squeeze"])
def test_a_deflected_film_agrees_with_an_independent_quadrature(model):
    m = model_of(model=model, sides=2, clearance=2e-4)
    q = np.array([[3e-5, -1.5e-5, 8e-6]])
    q_dot = np.array([[2e-3, 4e-3, -6e-3]])
    x0, V = 0.37, np.array([0.8])
    friction, loss, _ = film_losses(m, q, q_dot, np.array([x0]), V)
    friction = friction.sum(axis=0)
    ref = [reference(m, q[0], q_dot[0], x0, V[0], side) for side in (1, -1)]
    assert friction[0] == pytest.approx(sum(r[0] for r in ref), rel=1e-6)
    assert loss[0] == pytest.approx(sum(r[1] for r in ref), rel=1e-6)
    assert abs(loss[0] - sum(r[1] for r in ref)) > 0.0  # (the midpoint rule is not the quadrature: a real comparison)


def test_the_extrapolated_midpoint_rule_converges_at_fourth_order(monkeypatch):
    import lubelink.derived as derived

    m = model_of(model="wedge+squeeze", clearance=2e-4)
    q, q_dot = np.array([[4e-5, -2e-5, 1e-5]]), np.array([[2e-3, 4e-3, -6e-3]])
    exact = reference(m, q[0], q_dot[0], 0.3, 0.8, 1)[1]
    errors = []
    for pieces in (8, 16, 32):
        monkeypatch.setattr(derived, "LOSS_PIECES", pieces)
        errors.append(abs(film_losses(m, q, q_dot, np.array([0.3]), np.array([0.8]))[1][0] - exact) / exact)
    rates = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    np.testing.assert_allclose(rates, 4.0, atol=0.3)
    assert errors[-1] < 1e-7


def test_a_run_stores_friction_and_loss_and_the_loss_is_bounded_by_the_thickest_film(short):
    ds = lubelink.simulate("paper", {**short, "film.sides": 2, "film.cavitation": "half-sommerfeld"})
    assert ds["film_friction"].attrs["units"] == "N" and ds["film_power_loss"].attrs["units"] == "W"
    cfg = config_of(ds)
    f, B = cfg.film, cfg.beam.width
    thickest = 0.5 * f.clearance + float(np.abs(ds["u2"]).max())
    V = ds["V_r"].values
    # the Couette part alone: mu V^2 B int 1/xi >= mu V^2 B l / xi_max on each side, the Poiseuille part adds to it
    assert np.all(ds["film_power_loss"].values >= 2 * f.viscosity * V**2 * B * f.pad_length / thickest * (1 - 1e-9))
    assert np.all(np.sign(ds["film_friction"].values[np.abs(V) > 0.1]) == np.sign(V[np.abs(V) > 0.1]))


def test_the_moment_of_the_film_is_that_of_an_independent_quadrature_and_its_resultant_the_film_force():
    from lubelink.film import film_force_many

    m = model_of(model="wedge+squeeze", sides=2, clearance=2e-4)
    q, q_dot = np.array([[3e-5, -1.5e-5, 8e-6]]), np.array([[2e-3, 4e-3, -6e-3]])
    x0, V = 0.37, 0.8
    f, B, L = m.config.film, m.config.beam.width, m.config.mechanism.rod_length
    _, _, moment = film_losses(m, q, q_dot, np.array([x0]), np.array([V]))
    # p_g by quadrature of the first integral's gradient, then the moment of -side B p_g about O
    beta = np.arange(1, 4) * np.pi / L
    expected = 0.0
    for side in (1, -1):
        xi = lambda X: 0.5 * f.clearance - side * np.sum(q[0] * np.sin(beta * (x0 + X)))
        Q = lambda X: -side * np.sum(q_dot[0] * (np.cos(beta * x0) - np.cos(beta * (x0 + X))) / beta)
        l, mu = f.pad_length, f.viscosity
        I1, I2, I3 = (quad(g, 0, l, epsabs=0, epsrel=1e-13)[0] for g in
                      (lambda X: xi(X) ** -2, lambda X: xi(X) ** -3, lambda X: Q(X) * xi(X) ** -3))
        C = -(6 * mu * V * I1 + 12 * mu * I3) / I2
        dp = lambda X: (6 * mu * V * xi(X) + 12 * mu * Q(X) + C) / xi(X) ** 3
        # int_0^l (x0 + X) p dX = -int_0^l (x0 X + X^2/2) p'(X) dX (by parts, p = 0 at both ends)
        expected += -side * B * -quad(lambda X: (x0 * X + 0.5 * X * X) * dp(X), 0, l, epsabs=0, epsrel=1e-12)[0]
    assert moment[0] == pytest.approx(expected, rel=1e-6)
    force = film_force_many(q, q_dot, np.array([x0]), np.array([V]), m.params.film, B, m.params.pad, L)[0]
    assert abs(force) > 0 and abs(moment[0] / force - (x0 + 0.5 * f.pad_length)) < f.pad_length  # on the pad

"""Saltation matrices through contact phases: the compliant contact and the sustained contact.

References: the closed form of a flow carrying a parameter (``x' = -P x``), the zero monodromy of a
one-mode period that ends its Zeno cascade in a sustained contact (the constraint then fixes the
whole state), and central differences of the period map on a compliant orbit of ``paper-impact``.
"""

import math

import numpy as np
import pytest

from lubelink.config import resolve
from lubelink.steady import find_periodic
from lubelink.steady.variational import flow_with_jacobian

#: ``paper-impact`` with the film off, one mode: three compliant contacts a period (law "compliant"), or
#: (law "restitution", e = 0.2, zeta = 0.2, clearance 3.9 mm) nine impacts ending in a sustained contact.
COMPLIANT = {"beam.damping_ratio": 0.05, "film.model": "none", "film.clearance": 3.6e-3, "contact.restitution": 0.7,
             "contact.law": "compliant"}
SUSTAINED = {"beam.damping_ratio": 0.2, "film.model": "none", "film.clearance": 3.9e-3, "contact.restitution": 0.2}


def decay(t, y, out, p):
    """``x' = -P x`` with ``P = p[0]``."""
    out[0] = -p[0] * y[0]


def test_a_flow_carries_the_derivative_with_respect_to_its_parameter():
    # x(T) = x0 exp(-P T): dx/dx0 = exp(-P T), dx/dP = -T x0 exp(-P T); the difference in P is of a linear rhs
    P, T, x0, h = 3.0, 0.7, 2.0, 1e-3
    pars = (np.array([P + h / 2]), np.array([P - h / 2]), h, P)
    y, Phi, _ = flow_with_jacobian(decay, np.array([P]), 0.0, np.array([x0]), T, np.ones(1), rtol=1e-12, atol=1e-14,
                                   compiled=False, parameter=pars)
    assert Phi.shape == (1, 2)
    assert y[0] == pytest.approx(x0 * math.exp(-P * T), rel=1e-11)
    assert Phi[0, 0] == pytest.approx(math.exp(-P * T), rel=1e-10)
    assert Phi[0, 1] == pytest.approx(-T * x0 * math.exp(-P * T), rel=1e-9)


@pytest.fixture(scope="module")
def compliant_orbit():
    return find_periodic(resolve("paper-impact", COMPLIANT))


def test_compliant_orbit_multipliers_match_differences_of_the_map(compliant_orbit):
    orbit = compliant_orbit
    assert orbit.jacobian == "variational+saltation" and orbit.jacobian_note == ""
    pmap = orbit.period_map
    run = pmap.run(orbit.y0)
    assert len(run.contacts) == 3 and all(np.isfinite(c[1]) for c in run.contacts)
    M_fd, _, check = pmap.differences(orbit.y0, check=True)
    scale = pmap.scale()
    D = lambda A: A * scale[None, :] / scale[:, None]  # noqa: E731 (the scaled matrix)
    assert np.max(np.abs(D(orbit.monodromy - M_fd))) <= np.max(np.abs(D(check - M_fd)))
    mu_fd = np.sort_complex(np.linalg.eigvals(M_fd))
    err_fd = np.max(np.abs(np.sort_complex(np.linalg.eigvals(check)) - mu_fd))
    mu = np.sort_complex(orbit.multipliers)
    # within the sum of both estimates (the orbit's own includes its events' error: the run at 100x rtol)
    assert np.max(np.abs(mu - mu_fd)) <= err_fd + np.max(orbit.multiplier_errors)
    # the parameter matters: without the column dy/dP (the force's start frozen) the matrix is off by far more
    jumps = pmap.jumps(run)
    frozen = [(ev._replace(parameter=None), S) for ev, S in jumps]
    M_frozen = pmap.variational(orbit.y0, None, run, frozen)
    assert np.max(np.abs(D(M_frozen - M_fd))) > 100 * np.max(np.abs(D(check - M_fd)))


def test_sustained_contact_of_one_mode_has_the_zero_monodromy():
    # one mode held at a point: after the plastic impact the constraint fixes q and q_dot, so every start
    # arrives at the same state: M = 0 (the Zeno cascade's slow impacts, 1/v- in their matrices, cancel)
    orbit = find_periodic(resolve("paper-impact", SUSTAINED))
    assert orbit.jacobian == "variational+saltation", orbit.jacobian_note
    pmap = orbit.period_map
    run = pmap.run(orbit.y0)
    assert len(run.contacts) == 1 and len(run.impacts) > 5
    scale = pmap.scale()
    D = lambda A: A * scale[None, :] / scale[:, None]  # noqa: E731
    assert np.max(np.abs(D(orbit.monodromy))) < 1e-12
    M_fd, _, check = pmap.differences(orbit.y0, check=True)
    assert np.max(np.abs(D(M_fd))) <= np.max(np.abs(D(check - M_fd)))  # differences: zero within their estimate

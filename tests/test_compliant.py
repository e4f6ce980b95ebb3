"""The compliant contact over the pad face (lubelink.compliant.face_contact_force).

Tiers: quadrature (the modal force against scipy.integrate.quad of its definition, independent of how
finely the pad is sampled); closed form (a short contact at a pad edge is a triangle);
end to end (a dry guide: the contact over the pad keeps the link within a micrometre of the face where
the point law lets it through by several, and the impulse converges with the modes).
"""

import numpy as np
import pytest
from scipy import integrate

import lubelink
from lubelink import compliant, film
from lubelink.build import build_model
from lubelink.compliant import lankarani_nikravesh
from lubelink.config import resolve

X_STAR = 0.45
V_MINUS = 0.1


def _setup(modes):
    cfg = resolve("paper-impact", {"beam.modes": modes, "contact.law": "compliant", "contact.extent": "pad"})
    p = build_model(cfg).params
    x0 = film.pad_start(X_STAR, cfg.film.pad_length, p.film.pad_reference)
    return cfg, p, x0


def _by_quad(cfg, x0, q, q_dot, side):
    """``-side int w(x) sin(beta_n x) dx`` of the definition, by adaptive quadrature on a fine split of the pad."""
    f, c, B, L = cfg.film, cfg.contact, cfg.beam.width, cfg.mechanism.rod_length
    beta = np.arange(1, q.size + 1) * np.pi / L

    def load(x):
        delta = c.min_film - (f.clearance / 2 - side * np.sin(beta * x) @ q)
        return lankarani_nikravesh(delta, side * (np.sin(beta * x) @ q_dot), V_MINUS, B * c.face_stiffness, 1.0,
                                   c.restitution)

    cuts = np.linspace(x0, x0 + f.pad_length, 201)
    return np.array([-side * integrate.quad(lambda x: load(x) * np.sin(b * x), x0, x0 + f.pad_length,
                                            points=cuts[1:-1], limit=1000, epsabs=0, epsrel=1e-11)[0]
                     for b in beta])


# an interior contact (a stretch of the pad), an edge contact, the other side's face
STATES = [(np.array([1.0, 2e-1, -1e-1]), np.array([0.01, 0.0, 0.02]), 1.0, 3e-6),
          (np.array([1.0, 1.0, 2e-1]), np.zeros(3), 1.0, 1e-5),
          (np.array([1.0, 5e-1, 0.0]), np.array([-0.01, 0.0, 0.0]), -1.0, 2e-6)]


def _state(cfg, shape, depth, side):
    """``q`` of the shape ``shape`` [-] scaled so that mode 1 alone would press ``depth`` [m] into the face."""
    return side * (cfg.film.clearance / 2 - cfg.contact.min_film + depth) * shape * np.r_[1.0, 1e-3, 1e-3]


@pytest.mark.parametrize("shape, q_dot, side, depth", STATES)
def test_the_face_force_is_its_integral(shape, q_dot, side, depth):
    cfg, p, x0 = _setup(3)
    q = _state(cfg, shape, depth, side)
    F = np.zeros(3)
    total = compliant.face_contact_force(q, q_dot, x0, p.film, p.contact, p.pad, cfg.mechanism.rod_length, side,
                                         V_MINUS, cfg.beam.width, F)
    reference = _by_quad(cfg, x0, q, q_dot, side)
    assert total > 0.0 and np.all(np.isfinite(F))
    assert np.abs(F - reference).max() < 1e-9 * np.abs(reference).max()


def test_the_face_force_does_not_depend_on_the_samples():
    """The same state with 3 modes and with 11 (the extra ones zero): the pad is cut at 28 and at 60 samples
    (16 + 4 N), and the force is the same to round-off: the samples only bracket the contact's ends."""
    shape, q_dot, side, depth = STATES[0]
    forces = []
    for modes in (3, 11):
        cfg, p, x0 = _setup(modes)
        q = np.zeros(modes)
        qd = np.zeros(modes)
        q[:3] = _state(cfg, shape, depth, side)
        qd[:3] = q_dot
        F = np.zeros(modes)
        compliant.face_contact_force(q, qd, x0, p.film, p.contact, p.pad, cfg.mechanism.rod_length, side, V_MINUS,
                                     cfg.beam.width, F)
        forces.append(F[:3])
    assert np.abs(forces[0] - forces[1]).max() < 1e-10 * np.abs(forces[0]).max()


def test_a_short_edge_contact_is_its_triangle():
    """The pad edge just touching a link that leaves the face steeply: the penetrated stretch is far shorter
    than the samples' spacing, and the force is the triangle ``B k_f delta_e^2 / (2 |delta'|)`` (a static
    contact: no damping), not a sample's share of the pad."""
    cfg, p, x0 = _setup(3)
    L = cfg.mechanism.rod_length
    beta = np.arange(1, 4) * np.pi / L
    q = np.array([0.0, 0.0, 0.0])
    # mode 2 alone, its slope at the pad start large, its film at the start 0.2 um below min_film
    target = cfg.film.clearance / 2 - cfg.contact.min_film + 2e-7
    q[1] = target / np.sin(beta[1] * x0)
    F = np.zeros(3)
    total = compliant.face_contact_force(q, np.zeros(3), x0, p.film, p.contact, p.pad, L, 1.0, V_MINUS,
                                         cfg.beam.width, F)
    slope = abs(q[1] * beta[1] * np.cos(beta[1] * x0))
    step = cfg.film.pad_length / (p.pad.sample_trig.shape[2] - 1)
    assert 2e-7 / slope < 0.1 * step  # the contact is much shorter than a sample's spacing
    assert total == pytest.approx(cfg.beam.width * cfg.contact.face_stiffness * 2e-7**2 / (2 * slope), rel=1e-4)


@pytest.fixture(scope="module")
def dry_guide():
    """A dry joint of 0.1 mm clearance, 15 modes, to the end of the first contacts (tools/figures/contact_convergence.py)."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).parents[1] / "tools" / "figures"))
    import contact_convergence

    return contact_convergence


def test_the_pad_keeps_the_link_near_the_face_and_the_impulse_converges(dry_guide):
    """Up to 12 ms of a dry guide: the contact over the pad holds the link within 1 um below min_film where the
    point law (same damping, its own stiffness) lets it 1.7 um through; both transmit the same impulse, which
    converges with the modes (docs/model.md 5.4)."""
    _, _, _, impulse_7, depth_7 = dry_guide.contact_window(7, "pad")
    start, _, _, impulse_15, depth_15 = dry_guide.contact_window(15, "pad")
    _, _, _, point_impulse, point_depth = dry_guide.contact_window(15, "point")
    assert start == pytest.approx(5.61841e-3, abs=1e-8)
    assert depth_15 < 1e-6 < point_depth
    assert impulse_15 == pytest.approx(impulse_7, rel=0.02) and impulse_15 == pytest.approx(point_impulse, rel=0.02)

"""The share of a run in mixed lubrication, up front: where the link's tilt across the pad takes a rough film.

Nothing is integrated. The collar holds the link at ``x_star`` against the inertial load of its rigid
motion (the link's own mass, accelerated with the mechanism): quasi-statically, the link is a beam on
its two pins with a third point support there (:func:`prop_force`, the *rigid joint load*), and it
bends through that support, so that across the pad it leaves the collar's axis by its deflection
there (:func:`propped_deflection`): the films ``H/2 -+ u2`` of the pad
(:func:`pad_films`) thin towards its far end by about that much whatever the clearance. Sampled over
one crank revolution, the share of the pad's films within reach of the asperities
(:data:`REACH` roughness: the Greenwood-Tripp pressure is computed there, and costs a quadrature
per node) and the share of the revolution in which a film is under :data:`ONSET` roughness (the
asperities carry load: the stiff method takes shorter steps) are :func:`mixed_share`, which
:mod:`lubelink.estimate` prices.

Measured on ``guide`` (15 modes, 20 um of oil a side): the rigid joint load is 11.1 N on average
over a revolution and 17.6 N at most; the film force of the run 10.9 N and 17.6 N
(a stiff film holds the link where the support would). The tilt across the pad reaches 10.2 um;
the thinnest film of the run's first two revolutions 11.5 and 9.1 um (20 um less that tilt: 9.8 um);
the tilt does not depend on the clearance, which is why the steps of the clearance sweep of
``benchmarks/bench.py --only estimate`` stay flat down to 30 um and rise below, where ``H/2 - 10 um``
reaches a few roughness. Not modelled: the slow sinking of the link into the collar over the
revolutions (``guide``'s thinnest film falls from 9 um in its second revolution to 0.7 um in its
tenth), the film's translation across the clearance (larger for a thick film), gravity, the
collar's mass, a variable section (its sine-mode frequencies are taken as the uniform link's).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["MixedShare", "prop_force", "propped_deflection", "pad_films", "asperity_force", "settled_shift",
           "mixed_share", "REACH", "ONSET"]

#: Standardised film ``h / sigma`` below which the Greenwood-Tripp pressure is computed (its integral
#: is 0 beyond: :func:`lubelink.film.asperity.greenwood_tripp_integral`), and below which it carries a
#: share of the load worth a step (``F_{5/2}(4) / F_{5/2}(0)`` is 2e-6; ``F_{5/2}(2) / F_{5/2}(0)`` 0.01).
REACH, ONSET = 10.0, 4.0
#: How far [m] the link sinks into the collar a crank revolution, until the asperities carry the joint
#: load (:func:`settled_shift`). Measured, not derived: ``guide``'s thinnest film by revolution, second to
#: seventh, 9.05, 6.9, 5.2, 3.6, 2.4, 1.4 um (1.0-2.1 um a revolution); a 100 um clearance's 27.3 um
#: after 2.5 revolutions and 13.5 um after 10 (1.9 um a revolution late in the run).
SINK = 1.7e-6
#: Samples of the crank revolution, and points along the pad; :func:`settled_shift` looks for the largest
#: asperity force among the ``THINNEST`` samples of the thinnest films.
SAMPLES, POINTS, THINNEST = 64, 32, 8


class MixedShare(NamedTuple):
    """What :func:`mixed_share` returns.

    Attributes
    ----------
    zone : float
        Share of the pad's films (points times sides, over the revolution) thinner than
        :data:`REACH` roughness [-].
    loaded : float
        Share of the revolution with a film thinner than :data:`ONSET` roughness somewhere on the pad [-].
    thinnest : float
        The thinnest film over the revolution [m] (negative: the tilt exceeds the film).
    tilt : float
        The largest deflection across the pad from the collar's support point [m].
    """

    zone: float
    loaded: float
    thinnest: float
    tilt: float


def prop_force(F, k, s):
    """The force [N] on a point support that holds a link of sine modes at zero deflection under modal loads.

    The link deflects ``u = sum_n q_n sin(beta_n x)``, ``q_n = (F_n - P s_n) / k_n``, under modal loads
    ``F_n`` [N] and a point force ``-P`` at ``x_p`` (``s_n = sin(beta_n x_p)``); ``u(x_p) = 0`` gives
    ``P = (sum_n F_n s_n / k_n) / (sum_n s_n^2 / k_n)``: the free deflection at ``x_p`` over the
    flexibility there (Maxwell's influence coefficient). ``k_n`` [N/m]: the modal stiffness
    ``m_n omega_n^2``. Over the last axis of ``F``, ``s`` (and ``k``), broadcast over the others.
    """
    return np.sum(F * s / k, axis=-1) / np.sum(s * s / k, axis=-1)


def propped_deflection(F, k, s, shapes):
    """Deflection [m] of the propped link (:func:`prop_force`) at points of mode shapes ``shapes``.

    ``u(x) = sum_n (F_n - P s_n) sin(beta_n x) / k_n``; ``shapes`` ``(..., points, N)``: ``sin(beta_n x)`` at
    the points, ``F``, ``s`` ``(..., N)``. Returns ``(..., points)``.
    """
    P = prop_force(F, k, s)
    q = (F - P[..., None] * s) / k
    return np.einsum("...pn,...n->...p", shapes, q)


def asperity_force(h, roughness, factor, modulus, width, dx):
    """Resultant [N] of the Greenwood-Tripp pressure ``K E' F_{5/2}(h / sigma)`` over films ``h`` [m] (last
    axis: points ``dx`` [m] apart on a pad of width ``width`` [m]). ``F_{5/2}`` in closed form,
    ``Gamma(7/2) exp(-lam^2/4) D_{-7/2}(lam) / sqrt(2 pi)`` (:func:`lubelink.film.asperity.f52` integrates it;
    0 beyond :data:`REACH` as there)."""
    from scipy.special import gamma, pbdv

    lam = np.asarray(h, dtype=float) / roughness
    f = gamma(3.5) * np.exp(-lam * lam / 4.0) * pbdv(-3.5, lam)[0] / np.sqrt(2.0 * np.pi)
    return factor * modulus * width * dx * np.sum(np.where(lam < REACH, f, 0.0), axis=-1)


def pad_films(config, samples=SAMPLES, points=POINTS):
    """The films ``H/2 - side u2`` [m] across the pad of the propped link over one crank revolution, and the
    rigid joint load [N] at each sample (the support's force, :func:`prop_force`).

    Returns ``(h, P)``: ``h`` ``(samples, sides, points)`` (the first side ``H/2 - u2``), ``P`` ``(samples,)``;
    or None where there is no closed-form motion to sample (the spatial link; a user's motion): ``u2``
    relative to the collar's support at ``x_star``, under the rigid motion's inertial load
    (:func:`lubelink.beam.rigid_forcing`).
    """
    from .beam import modal_mass, natural_frequencies, rigid_forcing, wavenumbers
    from .link.kinematics import slider_crank

    b, m, fm = config.beam, config.mechanism, config.film
    if b.model != "planar":
        return None
    L, N = m.rod_length, b.modes
    period = 2.0 * np.pi / abs(m.crank_speed)
    t = np.arange(samples) * period / samples
    kin = slider_crank(t, m.crank_length, L, m.crank_speed, m.guide_distance)
    omega = natural_frequencies(N, L, b.youngs_modulus, b.second_moment, b.density, b.area)
    f = rigid_forcing(kin["A_O2"], kin["alpha"], N, L)  # per modal mass: F / m_n, with k / m_n = omega^2
    beta = wavenumbers(N, L)
    start = kin["x_star"] - (0.5 * fm.pad_length if fm.pad_reference == "centre" else 0.0)
    X = (np.arange(points) + 0.5) * fm.pad_length / points
    shapes = np.sin((start[:, None] + X[None, :])[..., None] * beta)
    s = np.sin(np.outer(kin["x_star"], beta))
    u = propped_deflection(f, omega**2, s, shapes)
    side = np.array([1.0, -1.0][:fm.sides])
    P = modal_mass(b.density, b.area, L) * prop_force(f, omega**2, s)
    return 0.5 * fm.clearance - side[None, :, None] * u[:, None, :], P


def settled_shift(h, P, film, width):
    """How far [m] the link moves towards the collar, from the films ``h`` of :func:`pad_films`, until the
    asperities carry the rigid joint load ``P``: their largest force over the revolution, on the side it
    moves to, equal to the largest ``|P|``; 0 where they carry that at ``h`` already (the link tilts both
    ways over a revolution: moving away from one side's asperities takes it into the other's). Bisection to
    0.01 roughness."""
    from .film.asperity import asperity_factor

    K = asperity_factor(film.summit_product, film.summit_ratio)
    dx = film.pad_length / h.shape[-1]
    target = float(np.max(np.abs(P)))
    toward = _toward(h)
    side = int(np.argmax(toward))
    films = h[np.argsort(h[:, side].min(axis=1))[:THINNEST], side]  # where the largest force is

    def carried(shift):
        return float(np.max(asperity_force(films - shift, film.roughness, K, film.contact_modulus, width, dx)))

    lo, hi = 0.0, film.clearance
    if carried(lo) >= target:
        return 0.0
    while hi - lo > 0.01 * film.roughness:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if carried(mid) < target else (lo, mid)
    return 0.5 * (lo + hi)


def _toward(h):
    """+1 for the side of the thinnest film, -1 for the other: the sign of the link's motion on each."""
    i = np.unravel_index(np.argmin(h), h.shape)
    toward = np.ones(h.shape[1])
    if h.shape[1] == 2:
        toward[1 - i[1]] = -1.0
    return toward


def mixed_share(config) -> MixedShare:
    """:class:`MixedShare` of a configuration over ``solver.t_end``: all zero without a film of rough surfaces
    (or without :func:`pad_films`).

    Revolution ``r`` (from 0) has the films of :func:`pad_films` moved towards the collar by
    ``min(r SINK, settled)`` (:data:`SINK`, :func:`settled_shift`), its share weighted by the part of it the
    run spans.
    """
    fm = config.film
    films = pad_films(config) if fm.enabled and fm.roughness > 0.0 else None
    if films is None:
        return MixedShare(0.0, 0.0, 0.5 * fm.clearance, 0.0)
    h, P = films
    tilt = float(np.max(np.abs(0.5 * fm.clearance - h)))
    revolutions = config.solver.t_end * abs(config.mechanism.crank_speed) / (2.0 * np.pi)
    if h.min() - SINK * revolutions >= REACH * fm.roughness:  # out of the asperities' reach all along
        return MixedShare(0.0, 0.0, float(h.min()), tilt)
    settled = settled_shift(h, P, fm, config.beam.width)
    whole = max(1, int(np.ceil(revolutions - 1e-9)))
    shift = np.minimum(np.arange(whole) * SINK, settled)
    lam = (h[None] - shift[:, None, None, None] * _toward(h)[None, None, :, None]) / fm.roughness
    weight = np.clip(revolutions - np.arange(whole), 0.0, 1.0) if revolutions > 0 else np.ones(whole)
    weight = weight / weight.sum()
    zone = np.mean(lam < REACH, axis=(1, 2, 3)) @ weight
    loaded = np.mean(np.any(lam < ONSET, axis=(2, 3)), axis=1) @ weight
    return MixedShare(float(zone), float(loaded), float(lam.min() * fm.roughness), tilt)

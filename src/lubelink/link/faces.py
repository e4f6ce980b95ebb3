"""The collar on one pair of faces of the link: the loads, their Jacobian, the contact and the thinnest film.

A pair of faces is one bending direction of the link: the block of sine-mode coordinates ``q``,
velocities ``q_t`` [m, m/s] whose deflection ``u = sum q_n sin(beta_n x)`` closes the film
``H/2 - u`` on one face (side +1) and opens it on the other (``H/2 + u``, side -1), under a
pad of ``width`` [m]. The planar link has one pair (``u2``, width ``b``); the spatial link has
``u2`` and, with ``film.faces = "u2+u3"``, ``u3`` (width ``h``). Both models call these
functions on their blocks, so the film, the asperity contact, the compliant and the sustained
contact, and their Jacobians are written once (:mod:`lubelink.link.model`, :mod:`lubelink.link.spatial_model`).

The modal forces ``F`` [N] are added to, never overwritten; ``p`` is the parameter structure
(:class:`lubelink.link.model.Params`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .. import compliant, contact, film
from .._jit import jitable
from ..beam import deflection_at, wavenumber
from ..film import asperity
from ..film import jacobian as film_jacobian
from ..params import CHOICES

__all__ = ["ContactPhase", "NO_PHASE", "PAD_START", "PAD_END", "contact_point", "contact_position", "phase_side",
           "in_sustained", "film_on", "asperity_on", "face_jacobian", "compliant_on",
           "compliant_jacobian_on", "sustained_on", "thinnest_on"]

#: ``model.equations`` code of the printed film sign (Eq. 20's ``+B P``).
PRINTED_FILM_SIGN = CHOICES["model.equations"].index("printed-film-sign")


class ContactPhase(NamedTuple):
    """A contact in progress: ``side`` (+1, -1; 0 for none), its approach velocity [m/s] and point.

    Under ``contact.law = "compliant"`` the compliant force acts; under ``"restitution"`` the link
    rides on the collar (sustained contact, :func:`lubelink.contact.constraint_force`) at
    ``point``: the material point of the link [m] where the contact began inside the pad, or
    :data:`PAD_START` / :data:`PAD_END` for a pad edge (which slides with the collar). The spatial
    model codes the pair in the side (:func:`lubelink.link.spatial_model.face_of`).
    """

    side: float
    v_minus: float
    point: float = 0.0


NO_PHASE = ContactPhase(0.0, 0.0, 0.0)
#: :attr:`ContactPhase.point` of a sustained contact at the start and at the end of the pad.
PAD_START, PAD_END = -1.0, -2.0


def contact_point(x_c, at_edge, x0, pad_length):
    """:attr:`ContactPhase.point` of a contact at ``x_c`` [m] (``at_edge``: a pad edge; pad from ``x0``)."""
    if not at_edge:
        return float(x_c)
    return PAD_START if abs(x_c - x0) <= abs(x_c - x0 - pad_length) else PAD_END


@jitable
def contact_position(point, x0, pad_length):
    """Where on the link [m] the contact of :attr:`ContactPhase.point` ``point`` acts, the pad starting at ``x0`` [m]."""
    if point == PAD_START:
        return x0
    if point == PAD_END:
        return x0 + pad_length
    return point


@jitable
def phase_side(phase):
    """The side of the contact phase ``phase`` (0: none; ``phase`` None: a law without phases)."""
    if phase is None:
        return 0.0
    return phase.side


@jitable
def in_sustained(phase, law):
    """Whether the segment is a sustained contact (restitution law, a phase with a side)."""
    return law == contact.RESTITUTION and phase_side(phase) != 0.0


# --- loads ----------------------------------------------------------------------------------------------
@jitable(inline=True)
def film_on(q, q_t, x_star, V_r, f, width, pad, L, equations, F):
    """Add the film's modal forces [N] (:func:`lubelink.film.modal_film_force` of the film ``f``, pad tables
    ``pad``, link length ``L``) to ``F``, which holds no other load yet (the printed film sign of ``equations``
    reverses ``F``). For a film that is on (``f.model`` not ``"none"``).

    The callers test ``f.model`` first: every right-hand side runs these lines, and evaluating ``p.pad`` (whose
    arrays Numba reference-counts) outside that test cost the dry link's right-hand side 139 -> 162-193 ns.
    """
    film.modal_film_force(q, q_t, x_star, V_r, f, width, pad, L, F)
    if equations == PRINTED_FILM_SIGN:
        F *= -1.0


@jitable
def asperity_on(rough, q, x_star, f, width, pad, L, F):
    """Add the asperity contact's modal forces [N] (:func:`lubelink.film.asperity.modal_asperity_force`) to ``F``
    (``rough``: the parameters' ``rough``, None for smooth surfaces: compiles to nothing). For rough surfaces
    (``f.roughness > 0``, which the callers test first, as for :func:`film_on`)."""
    if rough is None:
        return
    asperity.modal_asperity_force(q, x_star, f, width, pad, L, F)


@jitable
def face_jacobian(q, q_t, x_star, V_r, p, width, Jq, Jv):
    """Add ``dF/dq`` and ``dF/dq_t`` [N/m, N s/m] of :func:`film_on` and :func:`asperity_on` to ``Jq``, ``Jv`` (zero on
    entry).

    The film of :func:`~lubelink.film.jacobian.has_film_jacobian`
    (:func:`~lubelink.film.jacobian.modal_film_jacobian`) and the asperity contact
    (:func:`~lubelink.film.asperity.modal_asperity_jacobian`).
    """
    L = p.basis.rod_length
    if p.film.model != film.NO_FILM:
        film_jacobian.modal_film_jacobian(q, q_t, x_star, V_r, p.film, width, p.pad, L, Jq, Jv)
        if p.model.equations == PRINTED_FILM_SIGN:
            Jq *= -1.0
            Jv *= -1.0
    if p.film.roughness > 0.0 and p.rough is not None:
        asperity.modal_asperity_jacobian(q, x_star, p.film, width, p.pad, L, Jq)


# --- contact --------------------------------------------------------------------------------------------
@jitable
def compliant_on(phase, q, q_t, x_star, V_r, p, width, F):
    """Add the compliant contact force of ``phase`` (side +-1 on this pair) to ``F`` [N] (``phase`` None: no
    compliant law, compiles to nothing)."""
    if phase is None:
        return
    x0 = film.pad_start(x_star, p.film.pad_length, p.film.pad_reference)
    compliant.compliant_force(q, q_t, x0, V_r, p.film, p.contact, p.pad, p.basis.rod_length, phase.side,
                              phase.v_minus, width, F)


@jitable
def compliant_jacobian_on(phase, q, q_t, x_star, V_r, p, Jq, Jv):
    """Add the compliant contact's Jacobian of ``phase`` to ``Jq``, ``Jv`` (None: no compliant law, compiles to
    nothing)."""
    if phase is None:
        return
    x0 = film.pad_start(x_star, p.film.pad_length, p.film.pad_reference)
    compliant.compliant_jacobian(q, q_t, x0, V_r, p.film, p.contact, p.pad, p.basis.rod_length, phase.side,
                                 phase.v_minus, Jq, Jv)


@jitable
def sustained_on(q, q_t, acc, x_star, V_r, A_r, p, side, point, rate):
    """Subtract the sustained contact's modal force from the accelerations ``acc`` [m/s^2]; return its force [N].

    :func:`lubelink.contact.constraint_force` of the film ``H/2 - side u`` of the sine modes
    ``q`` [m], ``q_t`` [m/s] at ``point`` (:class:`ContactPhase`), the collar at ``x_star`` [m]
    sliding at ``V_r`` [m/s] with acceleration ``A_r`` [m/s^2], Baumgarte rate ``rate`` [1/s].
    """
    N = q.shape[0]
    L = p.basis.rod_length
    x0 = film.pad_start(x_star, p.film.pad_length, p.film.pad_reference)
    at_edge = point < 0.0
    x_c = contact_position(point, x0, p.film.pad_length)
    xi = 0.5 * p.film.clearance - side * deflection_at(q, x_c, L)
    m = p.basis.modal_mass
    lam = contact.constraint_force(q, q_t, acc, x_c, at_edge, False, side, xi - p.contact.min_film, V_r, A_r,
                                   rate, m, L)
    for n in range(N):
        acc[n] -= side * lam * np.sin(wavenumber(n + 1, L) * x_c) / m
    return lam


@jitable(inline=True)
def thinnest_on(x_star, q, p):
    """``(xi_min, x_c, at_edge, side)``: the thinnest film over the pad and the sides of the pair [m, m, -, -]
    (``q``: its sine-mode coordinates, or a state whose first ``N`` entries they are)."""
    x0 = film.pad_start(x_star, p.film.pad_length, p.film.pad_reference)
    return contact.thinnest_film_sides(q[:p.basis.modes], x0, p.film, p.pad, p.basis.rod_length, 0.0)

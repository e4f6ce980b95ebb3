"""The spatial model (``beam.model = "spatial"``): its compiled right-hand side and gap.

State ``y = [q1, q2, q3, q1_t, q2_t, q3_t]`` (``6 N``; :mod:`lubelink.link.spatial`): axial ``u1`` (the bar
modes of ``beam.axial_end``), in-plane ``u2`` and out-of-plane ``u3`` sine modes of a uniform link under the
rigid motion of the spatial slider-crank (:mod:`lubelink.link.spatial_motion`). The equations are
:func:`lubelink.link.spatial.accelerations`; the collar's film (and the asperity contact) act on the
``u2`` faces exactly as in the planar model, the same functions called on the ``q2`` block
(:func:`lubelink.film.modal_film_force`, :func:`lubelink.link.faces.thinnest_on`,
:func:`lubelink.contact.gap_rate`), and with ``film.faces = "u2+u3"`` a second pair on the ``u3``
faces, the same functions on the ``q3`` block (pad width ``beam.height``); the gap is the thinner
pair's (docs/spatial.md, "Film pairs"). The parameters are the planar
:class:`~lubelink.link.model.Params` (its basis: the ``N`` in-plane modes) with :class:`SpatialTable`
in ``Params.spatial``.

Contact on the pair whose film broke (side codes of :func:`face_of`: +-1 the ``u2`` faces, +-2
the ``u3`` faces): the compliant force on its block, the restitution impacts (the jump of its
block's velocities: the mass matrix is diagonal across the directions), and after a Zeno
sequence the sustained contact (:func:`lubelink.link.faces.sustained_on` on its block), all as in
the planar model.
A motion of the user's (:class:`~lubelink.link.spatial_motion.SpatialPrescribedMotion`, sampled or
callables) replaces the slider-crank.

With ``beam.axial_force = "inertial"`` (``Params.geometric``; None: compiled out) the axial force of the rigid
motion, the link's inertia in its spinning frame, gravity and the slider's force normal to its guide
(:func:`spatial_axial_terms`), stiffens both bending directions alike (:func:`spatial_geometric_on`, the planar
:mod:`lubelink.link.axial` primitives on the ``q2`` and the ``q3`` blocks), and the chord of the bent link turns
about both transverse axes to keep C on its guide (:func:`spatial_chord_on`,
:func:`lubelink.link.axial.frame_chord_rotation`, whose restriction the planar model's is; docs/model.md §1.5).

A variable section (the taper keys, or ``section=``) is integrated in the three Galerkin
eigenbases of :mod:`lubelink.link.spatial_section` (``SpatialTable.galerkin``; ``Params.galerkin`` is
the in-plane one, which the impact and the gap's rate bound read); a uniform link keeps the
sine-mode kernels. Not supported (refused by the validation): a collar mass, the paper's printed
equations, a variable section with the ``u3`` film pair.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .. import contact
from .._jit import jitable, kernel
from ..film import NO_FILM
from ..params import CHOICES
from . import axial, section, spatial, spatial_section
from .faces import (ContactPhase, asperity_on, compliant_jacobian_on, compliant_on, face_jacobian, film_on,
                    in_sustained, phase_side, sustained_on, thinnest_on)
from .spatial import _frame
from .spatial_motion import SpatialMotion, collar_acceleration_at, spatial_motion_at

__all__ = ["SpatialTable", "spatial_axial_terms", "spatial_geometric_on", "chord_terms", "spatial_chord_on",
           "spatial_chord_power", "spatial_rhs", "spatial_jacobian_given",
           "spatial_gap", "spatial_sustained_many", "face_of", "U2_U3"]

#: ``film.faces``'s code of the second film pair (on the ``u3`` faces).
U2_U3 = CHOICES["film.faces"].index("u2+u3")


class SpatialTable(NamedTuple):
    """What the spatial kernels read beyond the planar parameters.

    ``W``: the ``3 N`` natural frequencies ``[axial, in-plane, out-of-plane]`` [rad/s]
    (:func:`lubelink.link.spatial.frequencies`; of a variable section the Galerkin eigenvalues);
    ``motion``: the :class:`SpatialMotion`; ``galerkin``: the eigenbases of a variable section
    (:class:`~lubelink.link.spatial_section.SpatialGalerkin`; None for a uniform link); ``axial``: the free
    axial end's couplings (:class:`~lubelink.link.spatial.AxialBasis`; None for the fixed end, whose
    axial functions are the bending sines: the code for it is not compiled then).
    """

    W: np.ndarray
    motion: SpatialMotion
    galerkin: spatial_section.SpatialGalerkin | None = None
    axial: spatial.AxialBasis | None = None


@jitable
def effective_acceleration(A_O, e1, e2, e3, gravity):
    """``A_O - g`` in link-frame components [m/s^2] (a 3-tuple): gravity ``(g_X, g_Y, 0)`` of the fixed frame as an inertial load."""
    gX, gY = gravity
    return (A_O[0] - (gX * e1[0] + gY * e1[1]), A_O[1] - (gX * e2[0] + gY * e2[1]),
            A_O[2] - (gX * e3[0] + gY * e3[1]))


@jitable
def face_of(code):
    """``(block, side)`` of a contact's side code: ``+-1`` the ``u2`` faces (block 1 of the state), ``+-2`` the ``u3`` faces (block 2).

    The side (+1, -1) is that of the planar functions on the block: +1 the film ``H/2 - u``, -1 ``H/2 + u``.
    """
    if code > 1.5:
        return 2, 1.0
    if code < -1.5:
        return 2, -1.0
    return 1, code


@jitable
def _face_loads(q, q_t, x_star, V_r, p, width, F):
    """Add the film and the asperity contact of one pair of faces (:mod:`lubelink.link.faces`) to ``F`` [N] (zero)."""
    L = p.basis.rod_length
    if p.film.model != NO_FILM:
        film_on(q, q_t, x_star, V_r, p.film, width, p.pad, L, p.model.equations, F)
    if p.film.roughness > 0.0:
        asperity_on(p.rough, q, x_star, p.film, width, p.pad, L, F)


@jitable
def _compliant_spatial(phase, y, x_star, V_r, p, F):
    """Add the compliant contact force of ``phase`` (None: no compliant law, compiles to nothing) on its face's block."""
    if phase is None:
        return
    if not contact.is_compliant(p.contact.law) or phase.side == 0.0:
        return
    k, side = face_of(phase.side)
    N = p.basis.modes
    M = 3 * N
    compliant_on(ContactPhase(side, phase.v_minus, phase.point), y[k * N:(k + 1) * N], y[M + k * N:M + (k + 1) * N],
                 x_star, V_r, p, p.beam.height if k == 2 else p.beam.width, F[k * N:(k + 1) * N])


@jitable(inline=True)
def spatial_rhs_given(kin, y, out, p):
    """``dy/dt`` into ``out`` for the rigid motion ``kin`` (:class:`~lubelink.link.spatial.SpatialRigidMotion`), without a sustained contact."""
    _rhs_in(p.spatial.galerkin, p.spatial.axial, kin, y, out, p)


@jitable
def _rhs_in(g, axial, kin, y, out, p):
    """:func:`spatial_rhs_given` for the eigenbases ``g`` (None, a uniform link: the sine-mode equations; the
    branches of the other case are pruned when compiled, so a uniform link runs the code it always ran) and the
    free axial end's couplings ``axial`` (None: the fixed end, likewise)."""
    A_O, w, al = kin.A_O, kin.omega, kin.alpha
    x_star, V_r = kin.x_star, kin.V_r
    N = p.basis.modes
    M = 3 * N
    L = p.basis.rod_length
    if g is None:
        yq = y
    else:
        yq = spatial_section.physical(g, y)  # the sine-mode state
    F = out[M:]  # modal forces [N] of the three directions, replaced by the accelerations
    F[:] = 0.0
    _face_loads(yq[N:2 * N], yq[M + N:M + 2 * N], x_star, V_r, p, p.beam.width, F[N:2 * N])
    if p.film.faces == U2_U3:  # the u3 faces: pad width h
        _face_loads(yq[2 * N:M], yq[M + 2 * N:], x_star, V_r, p, p.beam.height, F[2 * N:])
    _compliant_spatial(p.phase, yq, x_star, V_r, p, F)
    spatial_geometric_on(p.geometric, kin, yq, p, F)
    A = effective_acceleration(A_O, kin.e1, kin.e2, kin.e3, p.mechanism.gravity)
    if g is None:
        spatial.accelerations(y, p.spatial.W, p.beam.damping_ratio, A, w, al, F, p.basis.modal_mass, L, out, axial)
        spatial_chord_on(p.geometric, kin, y, out, p)
    else:
        spatial_section.eigen_accelerations(g, y, yq, p.spatial.W, p.beam.damping_ratio, A, w, al, F,
                                            p.basis.modal_mass, out, axial)


@jitable
def spatial_axial_terms(g, kin, p):
    """``(c0, c1, c2)`` of the axial force ``N(x) = c0 + c1 x + c2 x^2`` [N, N/m, N/m^2] of the spatial slider-crank's
    rigid motion ``kin`` (:func:`~lubelink.link.axial.frame_axial_force`: the inertia of the link, gravity, and the
    slider's force normal to its guide ``slider_dir``; ``g`` the :class:`~lubelink.link.axial.GeometricTable`)."""
    A = effective_acceleration(kin.A_O, kin.e1, kin.e2, kin.e3, p.mechanism.gravity)
    d = _frame(p.spatial.motion.slider_dir, kin.e1, kin.e2, kin.e3)
    return axial.frame_axial_force(A, spatial.axis_acceleration(kin.omega, kin.alpha), d, 0.0, 0.0,
                                   g.mass_per_length, p.basis.rod_length)


@jitable
def spatial_geometric_on(g, kin, yq, p, F):
    """Add the axial force's geometric-stiffness forces ``-K q`` [N] of both bending directions to the modal forces
    ``F`` ``(3 N,)`` (the same ``K`` on the ``u2`` and the ``u3`` sines of the sine-mode state ``yq``; ``g`` None:
    ``beam.axial_force = "none"``, compiles to nothing)."""
    if g is None:
        return
    c0, c1, c2 = spatial_axial_terms(g, kin, p)
    N = p.basis.modes
    axial.geometric_load(g.moments, c0, c1, c2, yq[N:2 * N], F[N:2 * N])
    axial.geometric_load(g.moments, c0, c1, c2, yq[2 * N:3 * N], F[2 * N:3 * N])


@jitable
def chord_terms(kin, p):
    """The :class:`~lubelink.link.axial.ChordCoefficients` of the spatial slider-crank's rigid motion ``kin``: its guide
    ``slider_dir`` in the link frame, the frame's rates (:func:`~lubelink.link.axial.chord_coefficients`)."""
    d = _frame(p.spatial.motion.slider_dir, kin.e1, kin.e2, kin.e3)
    return axial.chord_coefficients(d, kin.omega, kin.alpha, p.basis.rod_length)


@jitable
def spatial_chord_on(g, kin, y, out, p):
    """Correct the bending accelerations in ``out`` for the rotation of the chord the slider forces on the bent link,
    about both transverse axes (:func:`~lubelink.link.axial.frame_chord_rotation` on the ``u2`` and ``u3`` blocks;
    ``g`` None: ``beam.axial_force = "none"``, nothing)."""
    if g is None:
        return
    N = p.basis.modes
    M = 3 * N
    axial.frame_chord_rotation(g.lever, g.slopes, g.mass_per_length, p.basis.modal_mass, chord_terms(kin, p),
                               y[N:M], y[M + N:], out[M + N:])


@jitable
def spatial_chord_power(g, kin, y, p):
    """The power [W] of the chord's rotation's modal forces (:func:`~lubelink.link.axial.frame_chord_rotation_force`
    at the accelerations of :func:`spatial_rhs_given`) at the uniform link's state ``y`` (``g`` None: 0)."""
    if g is None:
        return 0.0
    N = p.basis.modes
    M = 3 * N
    d = np.empty(2 * M)
    spatial_rhs_given(kin, y, d, p)
    F = np.empty(2 * N)
    axial.frame_chord_rotation_force(g.lever, g.slopes, g.mass_per_length, chord_terms(kin, p), y[N:M], y[M + N:],
                                     d[M + N:], F)
    return np.dot(y[M + N:], F)


@jitable
def _spatial_chord_jacobian(g, kin, y, J, p):
    """Turn the bending accelerations' rows of ``J`` into those with the chord's rotation (``g`` None: nothing)."""
    if g is None:
        return
    N = p.basis.modes
    M = 3 * N
    d = np.empty(2 * M)
    spatial_rhs_given(kin, y, d, p)
    axial.frame_chord_rotation_jacobian(g.lever, g.slopes, g.mass_per_length, p.basis.modal_mass, chord_terms(kin, p),
                                        y[N:M], y[M + N:], d[M + N:], J[M + N:, N:M], J[M + N:, M + N:], J[M + N:, :])


@jitable
def _spatial_geometric_jacobian(g, kin, p, Jq):
    """Subtract the geometric stiffness ``K`` [N/m] from the ``u2`` and ``u3`` blocks of ``Jq`` ``(3 N, 3 N)`` (the
    modal forces' ``dF/dq``; ``g`` None: nothing)."""
    if g is None:
        return
    c0, c1, c2 = spatial_axial_terms(g, kin, p)
    N = p.basis.modes
    axial.geometric_jacobian(g.moments, c0, c1, c2, Jq[N:2 * N, N:2 * N])
    axial.geometric_jacobian(g.moments, c0, c1, c2, Jq[2 * N:, 2 * N:])


@jitable
def _sustained_spatial(phase, t, kin, y, out, p):
    """Apply the sustained contact ``phase`` to ``out`` (``dy/dt`` without it) on its face's block; return its force [N].

    :func:`lubelink.link.faces.sustained_on` on the block, the collar acceleration of the spatial
    motion, the Baumgarte rate the block's highest frequency (None: compiles to nothing).
    """
    if phase is None:
        return 0.0
    k, side = face_of(phase.side)
    N = p.basis.modes
    M = 3 * N
    A_r = collar_acceleration_at(t, p.spatial.motion)
    return sustained_on(y[k * N:(k + 1) * N], y[M + k * N:M + (k + 1) * N], out[M + k * N:M + (k + 1) * N],
                        kin.x_star, kin.V_r, A_r, p, side, phase.point, p.spatial.W[(k + 1) * N - 1])


@jitable
def spatial_jacobian_given(kin, y, J, p):
    """``J = d(dy/dt)/dy`` ``(6 N, 6 N)`` of :func:`spatial_rhs_given` for the rigid motion ``kin``.

    The uniform link outside a sustained contact, as the planar :func:`~lubelink.link.model.jacobian_given`:
    the identity block of ``dQ/dt = Q_t``; :func:`~lubelink.link.spatial.oscillator_jacobian`; the film and
    asperity contact of each pair of faces (:func:`~lubelink.link.faces.face_jacobian` on its block) and the
    compliant contact of a contact phase on its block and the axial force's geometric stiffness on both bending
    blocks (``beam.axial_force``), divided by the modal mass (the free axial end's couplings of ``p.spatial.axial``
    in the frame's terms); then the bending rows turned into those with the chord's rotation
    (:func:`~lubelink.link.axial.frame_chord_rotation_jacobian`).
    """
    N = p.basis.modes
    M = 3 * N
    J[:, :] = 0.0
    Jq = J[M:, :M]
    Jv = J[M:, M:]
    x_star, V_r = kin.x_star, kin.V_r
    face_jacobian(y[N:2 * N], y[M + N:M + 2 * N], x_star, V_r, p, p.beam.width, Jq[N:2 * N, N:2 * N],
                  Jv[N:2 * N, N:2 * N])
    if p.film.faces == U2_U3:
        face_jacobian(y[2 * N:M], y[M + 2 * N:], x_star, V_r, p, p.beam.height, Jq[2 * N:, 2 * N:], Jv[2 * N:, 2 * N:])
    if p.contact.law == contact.COMPLIANT and phase_side(p.phase) != 0.0:
        _compliant_jacobian_spatial(p.phase, y, x_star, V_r, p, Jq, Jv)
    _spatial_geometric_jacobian(p.geometric, kin, p, Jq)
    Jq /= p.basis.modal_mass
    Jv /= p.basis.modal_mass
    spatial.oscillator_jacobian(p.spatial.W, p.beam.damping_ratio, kin.omega, kin.alpha, Jq, Jv, p.spatial.axial)
    for i in range(M):
        J[i, M + i] = 1.0
    _spatial_chord_jacobian(p.geometric, kin, y, J, p)


@jitable
def _compliant_jacobian_spatial(phase, y, x_star, V_r, p, Jq, Jv):
    """Add the compliant contact's Jacobian of ``phase`` on its face's block (None: compiles to nothing)."""
    if phase is None:
        return
    k, side = face_of(phase.side)
    N = p.basis.modes
    M = 3 * N
    b = slice(k * N, (k + 1) * N)
    compliant_jacobian_on(ContactPhase(side, phase.v_minus, phase.point), y[b], y[M + k * N:M + (k + 1) * N], x_star,
                          V_r, p, Jq[b, b], Jv[b, b])


@kernel
def spatial_rhs(t, y, out, p):
    """``dy/dt`` of the spatial modal equations into ``out`` (``y``, ``out`` shape ``(6 N,)``), a sustained contact included.

    An ``out`` of ``n + n^2`` entries asks for the Jacobian as well (:func:`spatial_jacobian_given`), as the planar
    :func:`~lubelink.link.model.rhs`.
    """
    kin = spatial_motion_at(t, p.spatial.motion)
    n = y.shape[0]
    if out.shape[0] > n:
        spatial_rhs_given(kin, y, out[:n], p)
        spatial_jacobian_given(kin, y, out[n:].reshape((n, n)), p)
        return
    spatial_rhs_given(kin, y, out, p)
    if in_sustained(p.phase, p.contact.law):
        _sustained_spatial(p.phase, t, kin, y, out, p)


@jitable(inline=True)
def spatial_gap_given(kin, y, p):
    """``(gap, rate, bound)``: the thinnest film over the face pairs minus ``min_film`` [m], its rate and a bound [m/s].

    The films of the ``u2`` faces, and with ``film.faces = "u2+u3"`` those of the ``u3`` faces
    (the same functions on the ``q3`` block): the gap is the smaller. The bound is the larger of
    the pairs' :func:`lubelink.contact.gap_rate_bound`, each direction's modes softened by the
    whole spin ``|w|`` (the most any direction's centrifugal term softens them); of a variable
    section (``u2`` faces only), :func:`lubelink.link.section.eigen_rate_bound` of the in-plane eigenmodes alike.
    """
    return _gap_in(p.spatial.galerkin, kin, y, p)


@jitable
def _gap_in(g, kin, y, p):
    """:func:`spatial_gap_given` for the eigenbases ``g`` (None: a uniform link; as :func:`_rhs_in`)."""
    N = p.basis.modes
    M = 3 * N
    L = p.basis.rod_length
    if g is None:
        yq = y
    else:
        yq = spatial_section.physical(g, y)
    q2, q2_t = yq[N:2 * N], yq[M + N:M + 2 * N]
    w = kin.omega
    V_r = kin.V_r
    xi, x_c, at_edge, side = thinnest_on(kin.x_star, q2, p)
    spin = np.sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2])
    rate = contact.gap_rate(q2, q2_t, x_c, at_edge, side, V_r, L)
    if g is None:
        bound = contact.gap_rate_bound(q2, q2_t, p.basis.omega_n, spin, V_r, L)
    else:  # the in-plane eigen-coordinates [eta2, eta2_t] and eigenbasis p.galerkin
        bound = section.eigen_rate_bound(p.galerkin, np.concatenate((y[N:2 * N], y[M + N:M + 2 * N])),
                                         p.basis.omega_n, spin, V_r)
    if p.film.faces == U2_U3 and g is None:  # (a variable section with the u3 pair is refused)
        q3, q3_t = y[2 * N:M], y[M + 2 * N:]
        xi3, x_c3, at_edge3, side3 = thinnest_on(kin.x_star, q3, p)
        bound = max(bound, contact.gap_rate_bound(q3, q3_t, p.spatial.W[2 * N:], spin, V_r, L))
        if xi3 < xi:
            xi = xi3
            rate = contact.gap_rate(q3, q3_t, x_c3, at_edge3, side3, V_r, L)
    return xi - p.contact.min_film, rate, bound


@jitable
def _thinnest_over_pairs(g, kin, y, p):
    """The thinnest film over the pad on the face pairs :func:`spatial_gap_given` watches [m] (``g`` as there)."""
    N = p.basis.modes
    yq = y if g is None else spatial_section.physical(g, y)
    xi = thinnest_on(kin.x_star, yq[N:2 * N], p)[0]
    if p.film.faces == U2_U3 and g is None:
        xi = min(xi, thinnest_on(kin.x_star, y[2 * N:3 * N], p)[0])
    return xi


@jitable
def _sustained_force(phase, t, kin, y, p):
    """The force [N] of the sustained contact ``phase`` (None: compiles to nothing)."""
    if phase is None:
        return 0.0
    out = np.empty(y.shape[0])
    spatial_rhs_given(kin, y, out, p)
    return _sustained_spatial(phase, t, kin, y, out, p)


@jitable
def _sustained_event(phase, t, kin, y, p):
    """The event of a sustained contact ``phase`` (None: compiles to nothing), as the planar model's
    (:func:`lubelink.link.model._sustained_event`): its force [N], which ends it at zero; or, once the film
    anywhere on the pad of either face pair is :data:`~lubelink.contact.PENETRATION` ``min_film`` below
    ``min_film``, that depth times the modal stiffness of the held block's highest mode [N] (<= 0)."""
    if phase is None:
        return 0.0
    force = _sustained_force(phase, t, kin, y, p)
    below = _thinnest_over_pairs(p.spatial.galerkin, kin, y, p) - (1.0 - contact.PENETRATION) * p.contact.min_film
    if below > 0.0:
        return force
    k = face_of(phase.side)[0]
    w = p.spatial.W[(k + 1) * p.basis.modes - 1]
    return below * p.basis.modal_mass * w * w


@kernel
def spatial_gap(t, y, p):
    """The event of the spatial model at ``t`` [s]: :func:`spatial_gap_given`, or in a sustained contact
    ``(force [N], 0, inf)`` (it ends when the force falls to zero)."""
    kin = spatial_motion_at(t, p.spatial.motion)
    if in_sustained(p.phase, p.contact.law):
        return _sustained_event(p.phase, t, kin, y, p), 0.0, np.inf
    return spatial_gap_given(kin, y, p)


@kernel
def spatial_sustained_many(t, y, side, point, p):
    """Force [N] of the sustained contact of side code ``side[i]`` (0: none, force 0) at ``point[i]`` at many samples ``t`` ``(T,)``, ``y`` ``(T, 6N)``."""
    out = np.zeros(t.shape[0])
    for i in range(t.shape[0]):
        if side[i] != 0.0:
            out[i] = _sustained_force(ContactPhase(side[i], 0.0, point[i]), t[i],
                                      spatial_motion_at(t[i], p.spatial.motion), y[i], p)
    return out

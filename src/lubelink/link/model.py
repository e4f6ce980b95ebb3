"""The modal model assembled from the physics: its parameters for compiled code, right-hand side and gap.

State ``y = [q_1..q_N, q_dot_1..q_dot_N]``. The right-hand side (:func:`rhs`) is the corrected
modal equation (docs/model.md section 2, paper Eq. 18 corrected):

    q_ddot_n = -(omega_n^2 - omega^2) q_n - 2 zeta omega_n q_dot_n
               - 2/(L beta_n) {(A_O2 - g_j) [1 + (-1)^(n+1)] + alpha L (-1)^(n+1)}
               + (F_n^film + F_n^contact + R sin(beta_n x_star) - sum_m K_nm q_m) / (rho A L / 2)

with ``g_j`` gravity along the link's ``j`` axis and ``K_nm`` the geometric stiffness of the axial force
(:mod:`.axial`; zero and compiled out unless ``beam.axial_force = "inertial"``, which also corrects the
accelerations for the rotation of the chord under the slider, :func:`chord_on`). Every term comes from its physics module
(:mod:`.kinematics`, :mod:`.beam`, :mod:`.film`, :mod:`.contact`); :func:`rhs`, :func:`gap` (the event
and its rate) are what the integrators run, compiled, or as Python on the ``numpy`` backend.

The paper's printed equations are variants of the same right-hand side (``model.equations``):
``printed-omega2`` adds ``-2 omega^2 q_n`` (Eq. 18's ``+omega^2``), ``double-count`` forces with
``A_O2 + omega v_O1`` (Eq. 18's ``a_O2 + omega v_O1`` read with Section 6's true ``a_O2``),
``printed`` both, ``printed-film-sign`` reverses the film force (Eq. 20's ``+B P``).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .. import beam, compliant, contact, film
from .._jit import jitable, kernel
from ..beam import wavenumber
from ..errors import BackendError
from ..params import CHOICES
from . import axial, section
from .faces import (ContactPhase, asperity_on, compliant_jacobian_on, compliant_on, face_jacobian, film_on,
                    in_sustained, phase_side, sustained_on, thinnest_on)
from .kinematics import MotionTable, collar_acceleration, motion_at

__all__ = ["Params", "Basis", "ContactPhase", "rhs", "gap", "rhs_given", "BackendError"]

_EQ = CHOICES["model.equations"]
PRINTED_OMEGA2, DOUBLE_COUNT, PRINTED, PRINTED_FILM_SIGN = (_EQ.index(v) for v in _EQ[1:])


class Basis(NamedTuple):
    """The sine modes: ``modes`` [-], ``rod_length`` [m], ``omega_n`` [rad/s], ``modal_mass`` [kg]."""

    modes: int
    rod_length: float
    omega_n: np.ndarray
    modal_mass: float


class Params(NamedTuple):
    """Everything compiled code reads, generated from a :class:`~lubelink.params.Config`.

    The sections are :func:`~lubelink.views.kernel_view` s of the dataclasses (same field
    names); ``basis``, ``pad`` and ``motion`` are tables derived from them; ``phase`` is the
    compliant contact of the segment; ``galerkin`` the eigenbasis of a variable section
    (:class:`~lubelink.link.section.GalerkinTable`; None for a uniform link, whose state is the sine
    modes themselves); ``spatial`` the table of the spatial model (None for the planar model,
    whose kernels never read it); ``rough`` the roughness with the asperity contact (None for smooth
    surfaces: the kernels are then compiled without it); ``geometric`` the geometric stiffness of the axial force
    (:class:`~lubelink.link.axial.GeometricTable`; None for ``beam.axial_force = "none"``: compiled out).
    """

    mechanism: tuple
    beam: tuple
    film: tuple
    collar: tuple
    contact: tuple
    model: tuple
    basis: Basis
    pad: film.PadTables
    motion: MotionTable
    phase: ContactPhase | None
    galerkin: section.GalerkinTable | None = None
    spatial: tuple | None = None  # lubelink.link.spatial_model.SpatialTable
    rough: float | None = None  # film.roughness [m] with the asperity contact, None: smooth (compiled out)
    geometric: axial.GeometricTable | None = None  # beam.axial_force = "inertial"; None: compiled out


@jitable(inline=True)
def rhs_given(t, kin, y, out, p):
    """``dy/dt`` into ``out`` for the rigid motion ``kin`` at ``t`` (:class:`~lubelink.link.kinematics.RigidMotion`)."""
    omega, alpha, x_star, V_r, reaction = kin.omega, kin.alpha, kin.x_star, kin.V_r, kin.reaction
    N = p.basis.modes
    L = p.basis.rod_length
    yq = section.physical(p.galerkin, y)  # the sine-mode state (y itself for a uniform link)
    q = yq[:N]
    q_dot = yq[N:]
    F = out[N:]  # modal forces [N], accumulated here before the accelerations replace them
    F[:] = 0.0
    if p.film.model != film.NO_FILM:
        film_on(q, q_dot, x_star, V_r, p.film, p.beam.width, p.pad, L, p.model.equations, F)
    if p.film.roughness > 0.0:
        asperity_on(p.rough, q, x_star, p.film, p.beam.width, p.pad, L, F)
    if reaction != 0.0:
        for n in range(N):
            F[n] += beam.point_load(reaction, x_star, wavenumber(n + 1, L))
    if contact.is_compliant(p.contact.law) and phase_side(p.phase) != 0.0:
        compliant_on(p.phase, q, q_dot, x_star, V_r, p, p.beam.width, F)
    geometric_on(p.geometric, t, kin, q, p, F)
    A_eff = effective_acceleration(kin.A_O2, omega, kin.angle, kin.v_O1, p.mechanism.gravity, p.model.equations)
    stiffening = stiffened(p.model.equations)
    zeta = p.beam.damping_ratio
    if not section.uniform(p.galerkin):
        _eigen_accelerations(p.galerkin, y, F, A_eff, alpha, omega, p.basis, zeta, stiffening, out)
        return
    m = p.basis.modal_mass
    for n in range(N):
        forcing = beam.rigid_load(A_eff, alpha, n + 1, L) + F[n] / m
        if stiffening:
            forcing -= 2.0 * omega * omega * y[n]
        out[N + n] = beam.modal_acceleration(y[n], y[N + n], p.basis.omega_n[n], zeta, omega, forcing)
        out[n] = y[N + n]
    chord_on(p.geometric, kin, y, out, p)


@jitable(inline=True)
def effective_acceleration(A_O2, omega, angle, v_O1, gravity, equations):
    """The transverse acceleration of O the modal load sees [m/s^2]: ``A_O2`` minus gravity ``(g_X, g_Y)``
    along the link's ``j`` axis (plus ``omega v_O1`` under the ``equations`` that count it twice).

    Scalars in, not the parameters: handing the whole parameter structure to a function in the right-hand
    side costs more than the right-hand side of a dry link (135 -> 181 ns a call, 5 modes).
    """
    gX, gY = gravity
    A_eff = A_O2
    if gX != 0.0 or gY != 0.0:  # gravity along the link's j axis
        A_eff -= -gX * np.sin(angle) + gY * np.cos(angle)
    if equations == DOUBLE_COUNT or equations == PRINTED:
        A_eff += omega * v_O1
    return A_eff


@jitable
def axial_terms(g, kin, p):
    """``(c0, c1, c2)`` of the axial force ``N(x) = c0 + c1 x + c2 x^2`` [N, N/m, N/m^2] of the rigid motion
    ``kin`` (:func:`~lubelink.link.axial.rigid_axial_force`; ``g`` its table; the slider on the +X line)."""
    return axial.rigid_axial_force(kin.A_O1, kin.A_O2, kin.omega, kin.alpha, kin.angle, kin.reaction, kin.x_star,
                                   p.mechanism.gravity, g.mass_per_length, p.basis.rod_length)


@jitable
def geometric_on(g, t, kin, q, p, F):
    """Add the axial force's geometric-stiffness forces ``-K q`` [N] to the modal forces ``F`` (``g`` None:
    ``beam.axial_force = "none"``, compiles to nothing)."""
    if g is None:
        return
    c0, c1, c2 = axial_terms(g, kin, p)
    axial.geometric_load(g.moments, c0, c1, c2, q, F)


@jitable
def chord_on(g, kin, y, out, p):
    """Correct the accelerations in ``out[N:]`` for the rotation of the chord the slider forces on the bent link
    (:func:`~lubelink.link.axial.chord_rotation`; ``g`` None: ``beam.axial_force = "none"``, nothing)."""
    if g is None:
        return
    N = p.basis.modes
    axial.chord_rotation(g.lever, g.slopes, g.mass_per_length, p.basis.rod_length, p.basis.modal_mass, kin.angle,
                         kin.omega, kin.alpha, y[:N], y[N:], out[N:])


@jitable
def chord_power(g, t, kin, y, p):
    """The power [W] of the chord rotation's modal forces (:func:`~lubelink.link.axial.chord_rotation_force`) at
    the state ``y`` of the uniform planar link (``g`` None: 0)."""
    if g is None:
        return 0.0
    N = p.basis.modes
    d = np.empty(2 * N)
    rhs_called(t, kin, y, d, p)
    F = np.empty(N)
    axial.chord_rotation_force(g.lever, g.slopes, g.mass_per_length, p.basis.rod_length, kin.angle, kin.omega,
                               kin.alpha, y[:N], y[N:], d[N:], F)
    return np.dot(y[N:], F)


@jitable
def _chord_jacobian(g, t, kin, y, J, p):
    """Turn the accelerations' rows of ``J`` into those with the chord's rotation (``g`` None: nothing)."""
    if g is None:
        return
    N = p.basis.modes
    d = np.empty(2 * N)
    rhs_called(t, kin, y, d, p)
    axial.chord_rotation_jacobian(g.lever, g.slopes, g.mass_per_length, p.basis.rod_length, p.basis.modal_mass,
                                  kin.angle, kin.omega, kin.alpha, y[:N], y[N:], d[N:], J[N:, :N], J[N:, N:], J[N:, :])


@jitable
def _geometric_jacobian(g, t, kin, p, Jq):
    """Subtract the geometric stiffness ``K`` [N/m] from ``Jq`` (the modal forces' ``dF/dq``; ``g`` None: nothing)."""
    if g is None:
        return
    c0, c1, c2 = axial_terms(g, kin, p)
    axial.geometric_jacobian(g.moments, c0, c1, c2, Jq)


@jitable(inline=True)
def stiffened(equations):
    """Whether the printed ``equations``' ``-2 omega^2 q_n`` (Eq. 18's ``+omega^2``) is in the modal equation."""
    return equations == PRINTED_OMEGA2 or equations == PRINTED


@jitable
def _eigen_accelerations(g, y, F, A_eff, alpha, omega, basis, zeta, stiffening, out):
    """:func:`~lubelink.link.section.eigen_accelerations` of the eigenbasis ``g`` (None: a uniform link, nothing)."""
    if g is None:
        return
    section.eigen_accelerations(g, y, F, A_eff, alpha, omega, basis.omega_n, zeta, basis.modal_mass, stiffening, out)


@jitable
def sustained_given(t, kin, A_r, y, out, p, side, point):
    """Apply the sustained contact on ``side`` at ``point`` to ``out`` (``dy/dt`` without it); return its force [N].

    The contact point is held where the contact began (:class:`ContactPhase`): a material point,
    or a pad edge. ``A_r`` NaN: the collar acceleration of ``p.motion`` at ``t``. The Baumgarte
    rate is the highest modal frequency of the basis.
    """
    N = p.basis.modes
    if A_r != A_r:
        A_r = collar_acceleration(t, p.motion)
    return sustained_on(y[:N], y[N:], out[N:], kin.x_star, kin.V_r, A_r, p, side, point, p.basis.omega_n[N - 1])


@jitable
def rhs_called(t, kin, y, out, p):
    """:func:`rhs_given` compiled as a function of its own, for the callers off the hot path (it is inlined into :func:`rhs` only)."""
    rhs_given(t, kin, y, out, p)


@jitable
def _sustained_term(phase, t, kin, A_r, y, out, p):
    """:func:`sustained_given` of the sustained contact ``phase`` (None: a law without phases, compiles to nothing)."""
    if phase is None:
        return 0.0
    return sustained_given(t, kin, A_r, y, out, p, phase.side, phase.point)


@jitable
def _sustained_event(phase, t, kin, A_r, y, p):
    """The event of a sustained contact ``phase`` (None: compiles to nothing): its force [N], which ends it at
    zero; or, once the film elsewhere on the pad is :data:`~lubelink.contact.PENETRATION` ``min_film`` below
    ``min_film`` (the link reaching the face at a second point, which one held point cannot stop), that
    depth times the modal stiffness of the highest mode [N] (<= 0)."""
    if phase is None:
        return 0.0
    out = np.empty(y.shape[0])
    rhs_called(t, kin, y, out, p)
    force = sustained_given(t, kin, A_r, y, out, p, phase.side, phase.point)
    below = thinnest_given(kin.x_star, y, p)[0] - (1.0 - contact.PENETRATION) * p.contact.min_film
    if below > 0.0:
        return force
    w = p.basis.omega_n[p.basis.modes - 1]
    return below * p.basis.modal_mass * w * w


@jitable
def rhs_with(t, kin, A_r, y, out, p):
    """``dy/dt`` into ``out``: :func:`rhs_given` and, in a sustained contact, its constraint force; return the force [N]."""
    rhs_called(t, kin, y, out, p)
    if in_sustained(p.phase, p.contact.law):
        return _sustained_term(p.phase, t, kin, A_r, y, out, p)
    return 0.0


@jitable(inline=True)
def event_with(t, kin, A_r, y, p):
    """The event: :func:`gap_given`, or in a sustained contact ``(force [N], 0, inf)``: it ends when the force falls to zero."""
    if in_sustained(p.phase, p.contact.law):
        return _sustained_event(p.phase, t, kin, A_r, y, p), 0.0, np.inf
    return gap_given(t, kin, y, p)


@jitable
def jacobian_given(t, kin, y, J, p):
    """``J = d(dy/dt)/dy`` ``(2N, 2N)`` of :func:`rhs_given` for the rigid motion ``kin`` at ``t``.

    The uniform planar link (no eigenbasis) outside a sustained contact, with the film of
    :func:`~lubelink.film.jacobian.has_film_jacobian`: ``dq/dt = q_dot`` gives the identity block;
    the modal oscillators ``-(omega_n^2 - omega^2)`` and ``-2 zeta omega_n`` on the diagonals;
    the film and the asperity contact (:func:`~lubelink.link.faces.face_jacobian`) and the compliant contact
    of a contact phase (:func:`~lubelink.link.faces.compliant_jacobian_on`) and the axial force's geometric
    stiffness (``beam.axial_force``) divided by the modal mass. The joint reaction, gravity and the rigid-motion
    load do not depend on the state.
    """
    omega, x_star, V_r = kin.omega, kin.x_star, kin.V_r
    N = p.basis.modes
    q = y[:N]
    q_dot = y[N:]
    J[:, :] = 0.0
    Jq = J[N:, :N]
    Jv = J[N:, N:]
    face_jacobian(q, q_dot, x_star, V_r, p, p.beam.width, Jq, Jv)
    if p.contact.law == contact.COMPLIANT and phase_side(p.phase) != 0.0:
        compliant_jacobian_on(p.phase, q, q_dot, x_star, V_r, p, Jq, Jv)
    _geometric_jacobian(p.geometric, t, kin, p, Jq)
    Jq /= p.basis.modal_mass
    Jv /= p.basis.modal_mass
    stiffening = stiffened(p.model.equations)
    for n in range(N):
        J[n, N + n] = 1.0
        w = p.basis.omega_n[n]
        Jq[n, n] -= w * w - omega * omega + (2.0 * omega * omega if stiffening else 0.0)
        Jv[n, n] -= 2.0 * p.beam.damping_ratio * w
    _chord_jacobian(p.geometric, t, kin, y, J, p)


@kernel
def rhs(t, y, out, p):
    """``dy/dt`` of the modal ODE into ``out`` (:func:`rhs_with`, with :func:`rhs_given` inlined).

    An ``out`` of ``n + n^2`` entries (``n = y.size``) asks for the Jacobian as well: ``dy/dt`` in
    its first ``n``, then :func:`jacobian_given` row by row (the stiff method's request, where
    :meth:`~lubelink.assembly.Model.jacobian_missing` says it applies).
    """
    kin = motion_at(t, p.motion)
    n = y.shape[0]
    if out.shape[0] > n:
        rhs_called(t, kin, y, out[:n], p)
        jacobian_given(t, kin, y, out[n:].reshape((n, n)), p)
        return
    rhs_given(t, kin, y, out, p)
    if in_sustained(p.phase, p.contact.law):
        _sustained_term(p.phase, t, kin, np.nan, y, out, p)


@jitable(inline=True)
def thinnest_given(x_star, y, p):
    """``(xi_min, x_c, at_edge, side)``: the thinnest film over the pad and the sides (``y``: sine-mode state)."""
    return thinnest_on(x_star, y, p)


@jitable(inline=True)
def gap_given(t, kin, y, p):
    """``(gap, rate, bound)``: thinnest film above breakdown, ``xi_min - min_film`` [m], its rate and a bound of the rate [m/s]."""
    N = p.basis.modes
    L = p.basis.rod_length
    yq = section.physical(p.galerkin, y)
    q, q_dot = yq[:N], yq[N:]
    xi, x_c, at_edge, side = thinnest_given(kin.x_star, yq, p)
    return (xi - p.contact.min_film, contact.gap_rate(q, q_dot, x_c, at_edge, side, kin.V_r, L),
            _rate_bound(p.galerkin, y, p.basis.omega_n, kin.omega, kin.V_r, L))


@jitable
def _rate_bound(g, y, omega_n, omega, V_r, rod_length):
    """A bound of the gap's rate [m/s]: by sine modes, or by the eigenmodes of ``g``."""
    if g is not None:
        return section.eigen_rate_bound(g, y, omega_n, omega, V_r)
    N = omega_n.shape[0]
    return contact.gap_rate_bound(y[:N], y[N:], omega_n, omega, V_r, rod_length)


@kernel
def gap(t, y, p):
    """The event: ``(gap [m], rate [m/s], bound of the rate [m/s])`` of the thinnest film above breakdown
    (in a sustained contact, its force, :func:`event_with`)."""
    return event_with(t, motion_at(t, p.motion), np.nan, y, p)


@kernel
def sustained_force_many(t, y, side, point, p):
    """Force [N] of the sustained contact on ``side[i]`` (0: none, force 0) at ``point[i]`` at many samples ``t`` ``(T,)``, ``y`` ``(T, 2N)``."""
    out = np.zeros(t.shape[0])
    d = np.empty(y.shape[1])
    for i in range(t.shape[0]):
        if side[i] != 0.0:
            kin = motion_at(t[i], p.motion)
            rhs_called(t[i], kin, y[i], d, p)
            out[i] = sustained_given(t[i], kin, np.nan, y[i], d, p, side[i], point[i])
    return out


@kernel
def compliant_many(t, y, side, v_minus, p):
    """``(force [N], power [W])`` of the compliant contact of ``side[i]`` (0: none) and approach velocity
    ``v_minus[i]`` at many samples ``t`` ``(T,)``, ``y`` ``(T, 2N)``: its resultant and its power on the link."""
    force = np.zeros(t.shape[0])
    power = np.zeros(t.shape[0])
    N = p.basis.modes
    F = np.empty(N)
    for i in range(t.shape[0]):
        if side[i] != 0.0:
            kin = motion_at(t[i], p.motion)
            x0 = film.pad_start(kin.x_star, p.film.pad_length, p.film.pad_reference)
            F[:] = 0.0
            force[i] = compliant.compliant_force(y[i, :N], y[i, N:], x0, kin.V_r, p.film, p.contact, p.pad,
                                                 p.basis.rod_length, side[i], v_minus[i], p.beam.width, F)
            power[i] = np.dot(y[i, N:], F)
    return force, power


@kernel
def thinnest_many(x_star, y, p):
    """Thinnest film [m] (over the pad and the sides) of many samples and where it is, ``x_c`` [m]: shape ``(T, 2)``
    (``x_star`` shape ``(T,)``, ``y`` ``(T, 2N)``)."""
    out = np.empty((x_star.shape[0], 2))
    for i in range(x_star.shape[0]):
        xi, x_c, _, _ = thinnest_given(x_star[i], y[i], p)
        out[i, 0] = xi
        out[i, 1] = x_c
    return out


@kernel
def rates_many(t, y, p):
    """``dy/dt`` [SI] at many samples ``t`` ``(T,)`` of integrator states ``y`` ``(T, 2N)``, free of contact
    (:func:`rhs_given`; the results' joint reactions read the accelerations)."""
    out = np.empty(y.shape)
    for i in range(t.shape[0]):
        rhs_given(t[i], motion_at(t[i], p.motion), y[i], out[i], p)
    return out

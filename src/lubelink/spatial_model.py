"""The spatial model (``beam.model = "spatial"``): its compiled right-hand side and gap, and its :class:`Model`.

State ``y = [q1, q2, q3, q1_t, q2_t, q3_t]`` (``6 N``; :mod:`lubelink.spatial`): axial ``u1``,
in-plane ``u2`` and out-of-plane ``u3`` sine modes of a uniform link under the rigid motion of
the spatial slider-crank (:mod:`lubelink.spatial_motion`). The equations are
:func:`lubelink.spatial.accelerations`; the collar's film (and the asperity contact) act on the
``u2`` faces exactly as in the planar model, the same functions called on the ``q2`` block
(:func:`lubelink.film.modal_film_force`, :func:`lubelink.faces.thinnest_on`,
:func:`lubelink.contact.gap_rate`), and with ``film.faces = "u2+u3"`` a second pair on the ``u3``
faces, the same functions on the ``q3`` block (pad width ``beam.height``); the gap is the thinner
pair's (docs/spatial.md, "Film pairs"). The parameters are the planar
:class:`~lubelink.model.Params` (its basis: the ``N`` in-plane modes) with :class:`SpatialTable`
in ``Params.spatial``.

Contact on the pair whose film broke (side codes of :func:`face_of`: +-1 the ``u2`` faces, +-2
the ``u3`` faces): the compliant force on its block, the restitution impacts (the jump of its
block's velocities: the mass matrix is diagonal across the directions), and after a Zeno
sequence the sustained contact (:func:`lubelink.faces.sustained_on` on its block), all as in
the planar model.
A motion of the user's (:class:`~lubelink.spatial_motion.SpatialPrescribedMotion`, sampled or
callables) replaces the slider-crank.

A variable section (the taper keys, or ``section=``) is integrated in the three Galerkin
eigenbases of :mod:`lubelink.spatial_section` (``SpatialTable.galerkin``; ``Params.galerkin`` is
the in-plane one, which the impact and the gap's rate bound read); a uniform link keeps the
sine-mode kernels. Not supported (refused by the validation): a collar mass, the paper's printed
equations, a variable section with the ``u3`` film pair.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from . import contact, section, spatial, spatial_section
from ._jit import jitable, kernel
from .assembly import Model, _backend, make_params
from .faces import ContactPhase, compliant_on, face_loads, in_sustained, sustained_on, thinnest_on
from .kinematics import RigidMotion
from .params import CHOICES
from .spatial_motion import (SpatialMotion, SpatialSliderCrank, collar_acceleration_at, geometry, motion_problems,
                             spatial_motion_at)

__all__ = ["SpatialTable", "spatial_rhs", "spatial_gap", "face_of", "SpatialModel", "build_spatial_model"]

#: ``film.faces``'s code of the second film pair (on the ``u3`` faces).
U2_U3 = CHOICES["film.faces"].index("u2+u3")


class SpatialTable(NamedTuple):
    """What the spatial kernels read beyond the planar parameters.

    ``W``: the ``3 N`` natural frequencies ``[axial, in-plane, out-of-plane]`` [rad/s]
    (:func:`lubelink.spatial.frequencies`; of a variable section the Galerkin eigenvalues);
    ``motion``: the :class:`SpatialMotion`; ``galerkin``: the eigenbases of a variable section
    (:class:`~lubelink.spatial_section.SpatialGalerkin`; None for a uniform link).
    """

    W: np.ndarray
    motion: SpatialMotion
    galerkin: spatial_section.SpatialGalerkin | None = None


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
    """``dy/dt`` into ``out`` for the rigid motion ``kin`` (:class:`~lubelink.spatial.SpatialRigidMotion`), without a sustained contact."""
    _rhs_in(p.spatial.galerkin, kin, y, out, p)


@jitable
def _rhs_in(g, kin, y, out, p):
    """:func:`spatial_rhs_given` for the eigenbases ``g`` (None, a uniform link: the sine-mode equations; the
    branches of the other case are pruned when compiled, so a uniform link runs the code it always ran)."""
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
    face_loads(yq[N:2 * N], yq[M + N:M + 2 * N], x_star, V_r, p, p.beam.width, F[N:2 * N])
    if p.film.faces == U2_U3:  # the u3 faces: pad width h
        face_loads(yq[2 * N:M], yq[M + 2 * N:], x_star, V_r, p, p.beam.height, F[2 * N:])
    _compliant_spatial(p.phase, yq, x_star, V_r, p, F)
    A = effective_acceleration(A_O, kin.e1, kin.e2, kin.e3, p.mechanism.gravity)
    if g is None:
        spatial.accelerations(y, p.spatial.W, p.beam.damping_ratio, A, w, al, F, p.basis.modal_mass, L, out)
    else:
        spatial_section.eigen_accelerations(g, y, yq, p.spatial.W, p.beam.damping_ratio, A, w, al, F,
                                            p.basis.modal_mass, out)


@jitable
def _sustained_spatial(phase, t, kin, y, out, p):
    """Apply the sustained contact ``phase`` to ``out`` (``dy/dt`` without it) on its face's block; return its force [N].

    :func:`lubelink.faces.sustained_on` on the block, the collar acceleration of the spatial
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


@kernel
def spatial_rhs(t, y, out, p):
    """``dy/dt`` of the spatial modal equations into ``out`` (``y``, ``out`` shape ``(6 N,)``), a sustained contact included."""
    kin = spatial_motion_at(t, p.spatial.motion)
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
    section (``u2`` faces only), :func:`lubelink.section.eigen_rate_bound` of the in-plane eigenmodes alike.
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
    (:func:`lubelink.model._sustained_event`): its force [N], which ends it at zero; or, once the film
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


@dataclass(frozen=True)
class SpatialModel(Model):
    """The spatial model: a :class:`~lubelink.assembly.Model` whose state is ``6 N`` long.

    ``omega_n``, ``modes`` and the film, gap and results are those of the in-plane direction;
    :attr:`state_frequencies` the ``3 N`` the exponential integrator reads.
    """

    @property
    def state_frequencies(self) -> np.ndarray:
        return self.params.spatial.W

    def jacobian_missing(self, phase=None) -> str:
        return "the spatial link (its Jacobian is not written yet)"

    def to_physical(self, y):
        """The sine-mode states ``[Q, Q_t]`` of integrator states ``y`` ``(..., 6 N)`` (the eigen-coordinates of a
        variable section, :mod:`lubelink.spatial_section`; ``y`` itself for a uniform link)."""
        g = self.params.spatial.galerkin
        return y if g is None else spatial_section.change_basis(g.phi, y)

    def to_state(self, yq):
        """The integrator states of sine-mode states ``yq`` ``(..., 6 N)`` (inverse of :meth:`to_physical`)."""
        g = self.params.spatial.galerkin
        return yq if g is None else spatial_section.change_basis(g.phi_inv, yq)

    def initial_state(self):
        return np.zeros(6 * self.modes)

    @property
    def faces(self) -> tuple:
        """The blocks of the state whose faces the collar guides: ``(1,)`` (``u2``), or ``(1, 2)`` (``u2``, ``u3``)."""
        return (1, 2) if self.config.film.faces == "u2+u3" else (1,)

    def block_state(self, y, k):
        """``[q_k, q_k_t]`` of states ``y`` ``(..., 6 N)``: block ``k`` (0 axial, 1 in-plane, 2 out-of-plane)."""
        y = np.asarray(y, dtype=float)
        N = self.modes
        return np.concatenate([y[..., k * N:(k + 1) * N], y[..., (3 + k) * N:(4 + k) * N]], axis=-1)

    def face_block(self, y, side):
        """``(block states [q_k, q_k_t], side +-1)`` of the pair of faces of the side code ``side`` (:func:`face_of`)."""
        k, s = face_of(float(side))
        return self.block_state(y, k), s

    def planar_state(self, y):
        """``[q2, q2_t]`` of states ``y`` ``(..., 6 N)``: the in-plane block the ``u2`` film and the results read.

        An in-plane state ``(..., 2 N)`` is returned as it is (the planar methods this class
        reuses call each other with in-plane states).
        """
        y = np.asarray(y, dtype=float)
        if y.shape[-1] == 2 * self.modes:
            return y
        return self.block_state(y, 1)

    def deflections(self, y, x):
        """``(u1, u2, u3)`` [m] at ``x`` [m] of states ``y`` ``(..., 6 N)``."""
        return spatial.deflections(y, x, self.config.mechanism.rod_length)

    def kinematics(self, t):
        """The in-plane part of the rigid motion at ``t`` [s] as a planar :class:`~lubelink.kinematics.RigidMotion`
        (``A_O2``, ``omega3``, ``alpha3``, ``x_star``, ``V_r``)."""
        k = self.motion.at(t)
        return RigidMotion(float(k.A_O[1]), float(k.omega[2]), float(k.alpha[2]), float(k.x_star), float(k.V_r))

    def functions(self):
        if self.compiled:
            return spatial_rhs, spatial_gap
        if self.motion.table() is not None:
            return spatial_rhs.py_func, spatial_gap.py_func
        at = self.motion.at  # a motion of callables: the same equations, its kinematics from Python

        return (lambda t, y, out, p: spatial_rhs_given(at(t), y, out, p),
                lambda t, y, p: spatial_gap_given(at(t), y, p))

    def rhs(self, t, y, phase=None):
        out = np.empty(6 * self.modes)
        self.functions()[0](float(t), np.ascontiguousarray(y, dtype=float), out, self.with_phase(phase))
        return out

    def thinnest_film(self, t, y):
        """``(xi_min, x_c, at_edge, side)`` over the face pairs; ``side`` the code of :func:`face_of` (+-2: ``u3`` faces)."""
        best = None
        for k in self.faces:
            xi, x_c, edge, side = Model.thinnest_film(self, t, self.block_state(y, k))
            if best is None or xi < best[0]:
                best = (xi, x_c, edge, side * k)
        return best

    def approach(self, t, y):
        """``(v, x_c, side)`` at the thinnest film over the face pairs [m/s, m, code of :func:`face_of`]."""
        _, x_c, edge, code = self.thinnest_film(t, y)
        k, side = face_of(code)
        b = self.block_state(y, k)
        N = self.modes
        v = side * contact.approach_velocity(b[:N], b[N:], x_c, self.kinematics(t).V_r if edge else 0.0,
                                             self.config.mechanism.rod_length)
        return float(v), x_c, code

    def impact(self, t, y, restitution=None):
        """The restitution law at the thinnest film: the jump of the velocities of its face's block (``q2_t`` or
        ``q3_t``; the modal mass matrix is diagonal across the directions), ``(y_plus, x_c, v_minus, side code)``."""
        v_minus, x_c, code = self.approach(t, y)
        k, side = face_of(code)
        N = self.modes
        y_plus = np.array(y, dtype=float)
        e = self.config.contact.restitution if restitution is None else restitution
        L = self.config.mechanism.rod_length
        if v_minus > 0.0:
            v = y_plus[(3 + k) * N:(4 + k) * N]
            if self.params.galerkin is not None:  # a variable section (u2 faces): the in-plane eigenbasis' jump
                v[:] = side * section.eigen_restitution_jump(self.params.galerkin, side * v, x_c, v_minus, e, L)
            else:
                v[:] = side * contact.restitution_jump(side * v, x_c, v_minus, e, L)
        return y_plus, x_c, v_minus, code

    def contact_force(self, t, y, phase):
        """The compliant force of ``phase`` ``(side code, v_minus)`` on its face's block: ``(modal force [N], magnitude [N])``."""
        k, side = face_of(float(phase[0]))
        width = self.config.beam.height if k == 2 else self.config.beam.width
        return super().contact_force(t, self.block_state(y, k), (side, phase[1]), width)

    def film_loads(self, t, y):
        """Modal film forces [N] and resultant along +e2 [N] of the ``u2`` faces' films."""
        return super().film_loads(t, self.planar_state(y))

    def sustained_force(self, t, y, side, point):
        """Force [N] of a sustained contact of side code ``side`` at ``point`` at states ``y`` ``(T, 6N)``, times ``t``."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        y = np.ascontiguousarray(np.reshape(y, (t.size, 6 * self.modes)), dtype=float)
        sides = np.broadcast_to(np.asarray(side, dtype=float), t.shape).copy()
        points = np.broadcast_to(np.asarray(point, dtype=float), t.shape).copy()
        f = spatial_sustained_many if self.compiled else spatial_sustained_many.py_func
        return f(t, y, sides, points, self.params)


def build_spatial_model(config, motion=None, section=None) -> SpatialModel:
    """The :class:`SpatialModel` of a validated configuration with ``beam.model = "spatial"``.

    ``motion``: a spatial motion of the user's (:mod:`lubelink.spatial_motion`), default the
    slider-crank of ``[mechanism]``. ``section``: a :class:`~lubelink.section.Section` with ``area``,
    ``second_moment`` (``I_z``) and ``second_moment_y`` (``I_y``) replacing the beam's; a variable
    section (this, or the taper keys) is integrated in the eigenbases of
    :mod:`lubelink.spatial_section`. Raises ConfigError for what the spatial model cannot run.
    """
    from .validation import ConfigError

    provider = SpatialSliderCrank(config.mechanism) if motion is None else motion
    problems = motion_problems(provider, config)
    if not problems and provider.table() is None and config.contact.law == "restitution":
        problems.append("contact.law = 'restitution' with a spatial motion of callables: its sustained contact needs "
                        "the collar's acceleration, which callables do not give; give the motion as samples "
                        "(lubelink.spatial_motion.sampled_spatial_motion), or use contact.law = 'compliant' or 'none'")
    b, L = config.beam, config.mechanism.rod_length
    variable = section is not None or not b.uniform
    if variable and config.film.faces == "u2+u3":
        problems.append("film.faces = 'u2+u3' with a variable section (section= or the taper keys) is not supported "
                        "with beam.model = 'spatial' (docs/spatial.md, Limitations); use film.faces = 'u2' or a "
                        "uniform link")
    if problems:
        raise ConfigError(problems)
    compiled, note = _backend(config, provider)
    if not variable:
        W = spatial.frequencies(b.modes, L, b.youngs_modulus, b.density, b.area, b.second_moment,
                                b.height * b.width**3 / 12.0)
        params = make_params(config, None)
        galerkin = None
    else:
        from .section import taper

        sec = taper(b, L) if section is None else section
        try:
            params = make_params(config, None, sec)
            W, _, galerkin = spatial_section.spatial_galerkin(sec, b.youngs_modulus, b.density, b.modes, L,
                                                              (params.basis.omega_n, params.basis.modal_mass,
                                                               params.galerkin))
        except ValueError as exc:
            raise ConfigError([f"beam.model = 'spatial': {exc}"]) from None
    table = provider.table()  # callables: the slider-crank's table holds the place (compiled code is not run)
    table = SpatialTable(np.ascontiguousarray(W, dtype=float), geometry(config.mechanism) if table is None else table,
                         galerkin)
    return SpatialModel(config, provider, params._replace(spatial=table), compiled, note)

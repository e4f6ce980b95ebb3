"""The spatial model's Python side: :class:`SpatialModel` (the :class:`~lubelink.assembly.Model` of a ``6 N``
state) and :func:`build_spatial_model`; its compiled side is :mod:`lubelink.link.spatial_model`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import contact
from .assembly import Model, _backend, make_params
from .errors import ConfigError
from .link import section, spatial, spatial_section
from .link.kinematics import RigidMotion
from .link.spatial_model import SpatialTable, face_of, spatial_gap, spatial_gap_given, spatial_rhs, \
    spatial_rhs_given, spatial_sustained_many
from .link.spatial_motion import SpatialSliderCrank, geometry, motion_problems

__all__ = ["SpatialModel", "build_spatial_model"]


@dataclass(frozen=True)
class SpatialModel(Model):
    """The spatial model: a :class:`~lubelink.assembly.Model` whose state is ``6 N`` long.

    ``omega_n``, ``modes`` and the film, gap and results are those of the in-plane direction;
    :attr:`state_frequencies` the ``3 N`` the exponential integrator reads.
    """

    @property
    def state_frequencies(self) -> np.ndarray:
        return self.params.spatial.W

    def to_physical(self, y):
        """The sine-mode states ``[Q, Q_t]`` of integrator states ``y`` ``(..., 6 N)`` (the eigen-coordinates of a
        variable section, :mod:`lubelink.link.spatial_section`; ``y`` itself for a uniform link)."""
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
        """``(u1, u2, u3)`` [m] at ``x`` [m] of states ``y`` ``(..., 6 N)`` (sine-mode states; ``u1`` in the axial
        modes of ``beam.axial_end``)."""
        return spatial.deflections(y, x, self.config.mechanism.rod_length, self.config.beam.axial_end)

    def kinematics(self, t):
        """The in-plane part of the rigid motion at ``t`` [s] as a planar :class:`~lubelink.link.kinematics.RigidMotion`
        (``A_O2``, ``omega3``, ``alpha3``, ``x_star``, ``V_r``, ``A_O1``)."""
        k = self.motion.at(t)
        return RigidMotion(float(k.A_O[1]), float(k.omega[2]), float(k.alpha[2]), float(k.x_star), float(k.V_r),
                           A_O1=float(k.A_O[0]))

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

    ``motion``: a spatial motion of the user's (:mod:`lubelink.link.spatial_motion`), default the
    slider-crank of ``[mechanism]``. ``section``: a :class:`~lubelink.link.section.Section` with ``area``,
    ``second_moment`` (``I_z``) and ``second_moment_y`` (``I_y``) replacing the beam's; a variable
    section (this, or the taper keys) is integrated in the eigenbases of
    :mod:`lubelink.link.spatial_section`. Raises ConfigError for what the spatial model cannot run.
    """
    provider = SpatialSliderCrank(config.mechanism) if motion is None else motion
    b, L = config.beam, config.mechanism.rod_length
    problems = motion_problems(provider, config)
    if not problems and provider.table() is None and config.contact.law == "restitution":
        problems.append("contact.law = 'restitution' with a spatial motion of callables: its sustained contact needs "
                        "the collar's acceleration, which callables do not give; give the motion as samples "
                        "(lubelink.link.spatial_motion.sampled_spatial_motion), or use contact.law = 'compliant' or 'none'")
    if not problems and b.axial_force != "none" and not isinstance(provider, SpatialSliderCrank):
        problems.append(f"beam.axial_force = {b.axial_force!r}: needs the slider-crank's motion (the slider's guide), "
                        f"not {type(provider).__name__}; use beam.axial_force = 'none'")
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
                                b.height * b.width**3 / 12.0, b.axial_end)
        params = make_params(config, None)
        galerkin = None
        axial = None if b.axial_end == "fixed" else spatial.free_axial_basis(b.modes, L, b.density * b.area)
    else:
        from .link.section import taper

        sec = taper(b, L) if section is None else section
        try:
            params = make_params(config, None, sec)
            W, _, galerkin, axial = spatial_section.spatial_galerkin(
                sec, b.youngs_modulus, b.density, b.modes, L,
                (params.basis.omega_n, params.basis.modal_mass, params.galerkin), b.axial_end)
        except ValueError as exc:
            raise ConfigError([f"beam.model = 'spatial': {exc}"]) from None
    table = provider.table()  # callables: the slider-crank's table holds the place (compiled code is not run)
    table = SpatialTable(np.ascontiguousarray(W, dtype=float), geometry(config.mechanism) if table is None else table,
                         galerkin, axial)
    return SpatialModel(config, provider, params._replace(spatial=table), compiled, note)

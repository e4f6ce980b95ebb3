"""The spatial model (``beam.model = "spatial"``): its compiled right-hand side and gap, and its :class:`Model`.

State ``y = [q1, q2, q3, q1_t, q2_t, q3_t]`` (``6 N``; :mod:`lubelink.spatial`): axial ``u1``,
in-plane ``u2`` and out-of-plane ``u3`` sine modes of a uniform link under the rigid motion of
the spatial slider-crank (:mod:`lubelink.spatial_motion`). The equations are
:func:`lubelink.spatial.accelerations`; the collar's film (and the asperity contact) act on the
``u2`` faces exactly as in the planar model, the same functions called on the ``q2`` block
(:func:`lubelink.film.modal_film_force`, :func:`lubelink.model.thinnest_given`,
:func:`lubelink.contact.gap_rate`); the ``u3`` faces carry no film (docs/spatial.md). The
parameters are the planar :class:`~lubelink.model.Params` (its basis: the ``N`` in-plane modes
the film and gap use) with :class:`SpatialTable` in ``Params.spatial``.

Contact on the ``u2`` faces: the compliant force (on ``q2``) and the restitution impacts (the
jump of ``q2_t``: the mass matrix is diagonal across the directions) as in the planar model; a
Zeno sequence of impacts stops the run with status ``chatter`` (no sustained contact yet).

A variable section (the taper keys, or ``section=``) is integrated in the three Galerkin
eigenbases of :mod:`lubelink.spatial_section` (``SpatialTable.galerkin``; ``Params.galerkin`` is
the in-plane one, which the impact and the gap's rate bound read); a uniform link keeps the
sine-mode kernels. Not supported (refused by the validation): a collar mass, the paper's printed
equations, a user-supplied motion.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from . import contact, film, section, spatial, spatial_section
from ._jit import jitable, kernel
from .assembly import Model, _backend, make_params
from .film import asperity
from .model import _compliant_term, phase_side, thinnest_given
from .spatial_motion import SpatialMotion, SpatialSliderCrank, spatial_motion_at

__all__ = ["SpatialTable", "spatial_rhs", "spatial_gap", "SpatialModel", "build_spatial_model"]


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


@jitable(inline=True)
def spatial_rhs_given(kin, y, out, p):
    """``dy/dt`` into ``out`` for the rigid motion ``kin`` (the tuple of :func:`spatial_motion_at`)."""
    _rhs_in(p.spatial.galerkin, kin, y, out, p)


@jitable
def _rhs_in(g, kin, y, out, p):
    """:func:`spatial_rhs_given` for the eigenbases ``g`` (None, a uniform link: the sine-mode equations; the
    branches of the other case are pruned when compiled, so a uniform link runs the code it always ran)."""
    A_O, w, al = kin[0], kin[1], kin[2]
    x_star, V_r = kin[4], kin[5]
    N = p.basis.modes
    M = 3 * N
    L = p.basis.rod_length
    if g is None:
        yq = y
    else:
        yq = spatial_section.physical(g, y)  # the sine-mode state
    q2, q2_t = yq[N:2 * N], yq[M + N:M + 2 * N]
    F = out[M:]  # modal forces [N] of the three directions, replaced by the accelerations
    F[:] = 0.0
    F2 = F[N:2 * N]
    if p.film.model != film.NO_FILM:
        film.modal_film_force(q2, q2_t, x_star, V_r, p.film, p.beam.width, p.pad, L, F2)
    if p.film.roughness > 0.0:
        asperity.modal_asperity_force(q2, x_star, p.film, p.beam.width, p.pad, L, F2)
    if p.contact.law == contact.COMPLIANT and phase_side(p.phase) != 0.0:
        _compliant_term(p.phase, q2, q2_t, x_star, V_r, p, F2)
    A = effective_acceleration(A_O, kin[7], kin[8], kin[9], p.mechanism.gravity)
    if g is None:
        spatial.accelerations(y, p.spatial.W, p.beam.damping_ratio, A, w, al, F, p.basis.modal_mass, L, out)
    else:
        spatial_section.eigen_accelerations(g, y, yq, p.spatial.W, p.beam.damping_ratio, A, w, al, F,
                                            p.basis.modal_mass, out)


@kernel
def spatial_rhs(t, y, out, p):
    """``dy/dt`` of the spatial modal equations into ``out`` (``y``, ``out`` shape ``(6 N,)``)."""
    spatial_rhs_given(spatial_motion_at(t, p.spatial.motion), y, out, p)


@jitable(inline=True)
def spatial_gap_given(kin, y, p):
    """``(gap, rate, bound)`` of the ``u2`` film: thinnest film minus ``min_film`` [m], its rate and a bound [m/s].

    The bound is :func:`lubelink.contact.gap_rate_bound` of the in-plane modes softened by the
    whole spin ``|w|`` (the most any direction's centrifugal term softens them); of a variable
    section, :func:`lubelink.section.eigen_rate_bound` of the in-plane eigenmodes alike.
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
    w = kin[1]
    V_r = kin[5]
    xi, x_c, at_edge, side = thinnest_given(kin[4], q2, p)
    spin = np.sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2])
    if g is None:
        bound = contact.gap_rate_bound(q2, q2_t, p.basis.omega_n, spin, V_r, L)
    else:  # the in-plane eigen-coordinates [eta2, eta2_t] and eigenbasis p.galerkin
        bound = section.eigen_rate_bound(p.galerkin, np.concatenate((y[N:2 * N], y[M + N:M + 2 * N])),
                                         p.basis.omega_n, spin, V_r)
    return xi - p.contact.min_film, contact.gap_rate(q2, q2_t, x_c, at_edge, side, V_r, L), bound


@kernel
def spatial_gap(t, y, p):
    """The event of the spatial model: :func:`spatial_gap_given` at ``t`` [s]."""
    return spatial_gap_given(spatial_motion_at(t, p.spatial.motion), y, p)


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
        variable section, :mod:`lubelink.spatial_section`; ``y`` itself for a uniform link)."""
        g = self.params.spatial.galerkin
        return y if g is None else spatial_section.change_basis(g.phi, y)

    def to_state(self, yq):
        """The integrator states of sine-mode states ``yq`` ``(..., 6 N)`` (inverse of :meth:`to_physical`)."""
        g = self.params.spatial.galerkin
        return yq if g is None else spatial_section.change_basis(g.phi_inv, yq)

    def initial_state(self):
        return np.zeros(6 * self.modes)

    def planar_state(self, y):
        """``[q2, q2_t]`` of states ``y`` ``(..., 6 N)``: the in-plane block the film, gap and results read.

        An in-plane state ``(..., 2 N)`` is returned as it is (the planar methods this class
        reuses call each other with in-plane states).
        """
        y = np.asarray(y, dtype=float)
        N = self.modes
        if y.shape[-1] == 2 * N:
            return y
        return np.concatenate([y[..., N:2 * N], y[..., 4 * N:5 * N]], axis=-1)

    def deflections(self, y, x):
        """``(u1, u2, u3)`` [m] at ``x`` [m] of states ``y`` ``(..., 6 N)``."""
        return spatial.deflections(y, x, self.config.mechanism.rod_length)

    def kinematics(self, t):
        """The planar-shaped tuple ``(A_O2, omega3, alpha3, x_star, V_r, 0, 0, nan)`` at ``t`` [s]."""
        k = self.motion.at(t)
        return (float(k[0][1]), float(k[1][2]), float(k[2][2]), float(k[4]), float(k[5]), 0.0, 0.0, np.nan)

    def functions(self):
        if self.compiled:
            return spatial_rhs, spatial_gap
        return spatial_rhs.py_func, spatial_gap.py_func

    def rhs(self, t, y, phase=None):
        out = np.empty(6 * self.modes)
        self.functions()[0](float(t), np.ascontiguousarray(y, dtype=float), out, self.params)
        return out

    def thinnest_film(self, t, y):
        return super().thinnest_film(t, self.planar_state(y))

    def approach(self, t, y):
        return super().approach(t, self.planar_state(y))

    def impact(self, t, y, restitution=None):
        """The restitution law on the ``u2`` faces: the jump of ``q2_t`` (:meth:`Model.impact` on the ``q2`` block)."""
        yp, x_c, v_minus, side = super().impact(t, self.planar_state(y), restitution)
        N = self.modes
        y_plus = np.array(y, dtype=float)
        y_plus[4 * N:5 * N] = yp[N:]
        return y_plus, x_c, v_minus, side

    def contact_force(self, t, y, phase):
        return super().contact_force(t, self.planar_state(y), phase)

    def film_loads(self, t, y):
        return super().film_loads(t, self.planar_state(y))

    def sustained_force(self, t, y, side, point):
        raise NotImplementedError("sustained contact is not implemented for the spatial model")


def build_spatial_model(config, motion=None, section=None) -> SpatialModel:
    """The :class:`SpatialModel` of a validated configuration with ``beam.model = "spatial"``.

    ``section``: a :class:`~lubelink.section.Section` with ``area``, ``second_moment`` (``I_z``) and
    ``second_moment_y`` (``I_y``) replacing the beam's; a variable section (this, or the taper keys)
    is integrated in the eigenbases of :mod:`lubelink.spatial_section`. Raises ConfigError for a
    section the spatial model cannot use.
    """
    from .validation import ConfigError

    if motion is not None:
        raise ConfigError(["beam.model = 'spatial': a user-supplied motion is not supported by the spatial model "
                           "(it runs the built-in spatial slider-crank of [mechanism]); use beam.model = 'planar'"])
    b, L = config.beam, config.mechanism.rod_length
    provider = SpatialSliderCrank(config.mechanism)
    compiled, note = _backend(config, provider)
    if section is None and b.uniform:
        W = spatial.frequencies(b.modes, L, b.youngs_modulus, b.density, b.area, b.second_moment,
                                b.height * b.width**3 / 12.0)
        params = make_params(config, None)
        galerkin = None
    else:
        from .section import taper

        sec = taper(b, L) if section is None else section
        try:
            params = make_params(config, None, sec)
            g = params.galerkin
            W, _, galerkin = spatial_section.spatial_galerkin(sec, b.youngs_modulus, b.density, b.modes, L,
                                                              (params.basis.omega_n, params.basis.modal_mass, g))
        except ValueError as exc:
            raise ConfigError([f"beam.model = 'spatial': {exc}"]) from None
    table = SpatialTable(np.ascontiguousarray(W, dtype=float), provider.table(), galerkin)
    return SpatialModel(config, provider, params._replace(spatial=table), compiled, note)

"""The model assembled from a configuration: :class:`Model` (parameters, motion, backend, and the
functions the integrators call) and :func:`build_model`.

The compiled side (the parameter structure, the right-hand side, the gap) is :mod:`lubelink.link.model`;
this module is its Python side: it builds the parameters from the validated dataclasses, picks the
backend, and offers one-state-at-a-time conveniences (impact, film loads, contact force) to the
contact logic, the results and the paper's figures.
"""

from __future__ import annotations

import logging
import warnings
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from . import _jit, beam, compliant, contact, film

from .link import axial, section
from .errors import BackendError
from .film.jacobian import has_film_jacobian
from .link.kinematics import MotionTable, SliderCrank, collar_acceleration, motion_at
from .link.faces import NO_PHASE, ContactPhase, contact_point, contact_position, in_sustained
from .link.model import (Basis, Params, compliant_many, event_with, gap, rhs, rhs_with, sustained_force_many,
                    sustained_given, thinnest_given)
from .params import Config
from .views import kernel_view

__all__ = ["Model", "compile_failed", "interpreted", "make_params"]

log = logging.getLogger("lubelink")


# --- parameters ---------------------------------------------------------------------------------------
#: The bits of ``ndarray.flags.num`` that Numba's array type depends on: C- and Fortran-contiguous,
#: aligned, writeable (NumPy's ``NPY_ARRAY_*`` values, part of its C API).
_TYPED_FLAGS = 0x0001 | 0x0002 | 0x0100 | 0x0400


def _layout(value):
    """What decides the Numba type of ``value``: its Python type, and for an array its dimensions,
    dtype and flags, recursively through tuples (None stays None)."""
    if isinstance(value, tuple):
        return type(value), tuple(map(_layout, value))
    if isinstance(value, np.ndarray):
        return value.ndim, value.dtype.str, value.flags.num & _TYPED_FLAGS
    return type(value)


_PARAMS_TYPES: dict = {}


def _change_basis(M, y):
    """``[q, q_dot]`` states ``y`` (shape ``(..., 2N)``) with both halves mapped by the ``(N, N)`` matrix ``M``
    (the vectorised twin of :func:`lubelink.link.section.physical`)."""
    y = np.asarray(y, dtype=float)
    N = M.shape[0]
    return np.concatenate([y[..., :N] @ M.T, y[..., N:] @ M.T], axis=-1)


def params_type(params):
    """``numba.typeof(params)``, remembered by the layout of the parameters.

    The type depends only on which tables are present and their array layouts, so every run of
    a configuration (and every point of a sweep over real parameters) shares it; ``typeof`` of
    the large named tuple itself costs about as much as integrating a short run.
    """
    key = _layout(params)
    found = _PARAMS_TYPES.get(key)
    if found is None:
        import numba

        found = _PARAMS_TYPES[key] = numba.typeof(params)
    return found


def _c(a):
    return np.ascontiguousarray(a, dtype=np.float64).copy()


def make_params(config: Config, table: MotionTable | None, cross_section=None) -> Params:
    """The :class:`Params` of a validated configuration (``table`` None: a placeholder motion).

    ``cross_section``: a :class:`~lubelink.link.section.Section` replacing the beam's (uniform or
    linearly tapered) one; any section but the uniform one is solved in the Galerkin eigenbasis.
    """
    b = config.beam
    L = config.mechanism.rod_length
    N = b.modes
    galerkin = None
    if cross_section is None and b.uniform:
        omega_n = beam.natural_frequencies(N, L, b.youngs_modulus, b.second_moment, b.density, b.area)
        m_ref = beam.modal_mass(b.density, b.area, L)
    else:
        sec = section.taper(b, L) if cross_section is None else cross_section
        omega_n, m_ref, galerkin = section.galerkin_table(sec, b.youngs_modulus, b.density, N, L)
    basis = Basis(int(N), float(L), _c(omega_n), float(m_ref))
    pad = film.pad_tables(N, L, config.film)
    if table is None:
        table = SliderCrank(config.mechanism).table(config.collar.mass)
    table = table._replace(knots=_c(table.knots), coef=_c(table.coef))
    phase = NO_PHASE if config.contact.law in ("compliant", "restitution") else None
    ct = kernel_view(config.contact)
    if config.contact.law == "compliant" and config.contact.extent == "pad":  # (see contact.COMPLIANT_PAD)
        ct = ct._replace(law=contact.COMPLIANT_PAD, stiffness=float(config.contact.face_stiffness), exponent=1.0)
    geometric = None
    if b.axial_force == "inertial":
        if galerkin is not None:
            from .validation import ConfigError

            raise ConfigError([f"beam.axial_force = {b.axial_force!r}: the axial force is modelled on the uniform "
                               "link only, not with a given cross_section; use beam.axial_force = 'none'"])
        geometric = axial.geometric_table(N, L, b.density * b.area)
    return Params(kernel_view(config.mechanism), kernel_view(config.beam), kernel_view(config.film),
                  kernel_view(config.collar), ct, kernel_view(config.model), basis, pad,
                  table, phase, galerkin, rough=float(config.film.roughness) if config.film.roughness > 0.0 else None,
                  geometric=geometric)


# --- the model, from Python ------------------------------------------------------------------------------
@dataclass(frozen=True)
class Model:
    """A configuration assembled for integration: parameters, motion, and the functions the integrators call.

    ``compiled`` says whether the kernels run compiled; ``backend_note`` why not, when the
    configuration asked for ``"auto"`` and got the ``numpy`` backend.
    """

    config: object
    motion: object
    params: Params
    compiled: bool
    backend_note: str = ""

    @cached_property
    def params_type(self):
        """The Numba type of :attr:`params` (the same for every phase): :func:`params_type`."""
        return params_type(self.params)

    @property
    def modes(self) -> int:
        return self.config.beam.modes

    @property
    def omega_n(self) -> np.ndarray:
        return self.params.basis.omega_n

    @property
    def state_frequencies(self) -> np.ndarray:
        """The natural frequencies of the integrator's state [rad/s] (the exponential method's ``omega``)."""
        return self.params.basis.omega_n

    def face_block(self, y, side):
        """``(states [q, q_dot], side)`` of the pair of faces a contact of ``side`` touches, its side +-1 on them:
        ``y`` itself, the link having one pair."""
        return np.asarray(y, dtype=float), side

    def planar_state(self, y):
        """The in-plane states ``[q, q_dot]`` of states ``y`` (``y`` itself; the spatial model's ``q2`` block)."""
        return y

    @property
    def modal_mass(self) -> float:
        return self.params.basis.modal_mass

    @property
    def sides(self) -> tuple:
        return (1, -1) if self.config.film.sides == 2 else (1,)

    @property
    def backend(self) -> str:
        return "numba" if self.compiled else "numpy"

    def initial_state(self):
        """Zero initial conditions (the paper's)."""
        return np.zeros(2 * self.modes)

    @property
    def uniform(self) -> bool:
        """Whether the integrator's state is the sine modes themselves (uniform link), not eigen-coordinates."""
        return self.params.galerkin is None

    def to_physical(self, y):
        """The sine-mode states ``[q, q_dot]`` [m, m/s] of integrator states ``y``, shape ``(..., 2N)``.

        The integrator's state is ``[eta, eta_dot]`` for a variable section (:mod:`lubelink.link.section`);
        ``y`` itself for a uniform link. :meth:`rhs` and :meth:`gap` take integrator states, the other
        methods and the results sine-mode states.
        """
        g = self.params.galerkin
        return y if g is None else _change_basis(g.phi, y)

    def to_state(self, yq):
        """The integrator states of sine-mode states ``yq`` (inverse of :meth:`to_physical`)."""
        g = self.params.galerkin
        return yq if g is None else _change_basis(g.phi_inv, yq)

    def with_phase(self, phase) -> Params:
        """The parameters of a segment with the compliant contact ``phase`` ``(side, v_minus)`` or None."""
        if self.params.phase is None:
            return self.params
        return self.params._replace(phase=NO_PHASE if phase is None else ContactPhase(
            float(phase[0]), float(phase[1]), float(phase[2]) if len(phase) > 2 else 0.0))

    def gravity_j(self, t):
        """Gravity along the link's ``j`` axis at ``t`` [m/s^2]."""
        gX, gY = self.config.mechanism.gravity
        angle = self.kinematics(t).angle
        return -gX * np.sin(angle) + gY * np.cos(angle)

    def kinematics(self, t):
        """The tuple of :func:`~lubelink.link.kinematics.motion_at` at ``t`` [s]."""
        if self.motion.table() is None:
            return self.motion.kinematics(t)
        return motion_at(float(t), self.params.motion)

    @property
    def watched(self) -> bool:
        """Whether the film's gap is watched (a film, or a contact law): the event of :meth:`functions`."""
        return self.config.film.enabled or self.config.contact.law != "none"

    def jacobian_missing(self, phase=None) -> str:
        """Why the right-hand side cannot give its Jacobian in ``phase`` (:func:`~lubelink.link.model.rhs`); ``""`` if it can.

        A stiff method then forms it by finite differences and the run says so.
        """
        if self.motion.table() is None and not self.compiled:
            return "a motion given as Python functions on the numpy backend"
        if not self.uniform:
            return "a variable section (eigen-coordinates)"
        if phase is not None and self.config.contact.law == "restitution":
            return "a sustained contact (its constraint force's Jacobian is not written yet)"
        if phase is not None and self.config.contact.extent == "pad":
            return "the compliant contact over the pad (its Jacobian is not written yet)"
        return has_film_jacobian(self.config.film)

    def functions(self):
        """``(rhs, event)`` for the driver: kernels, or Python functions on the ``numpy`` backend."""
        if self.compiled:
            return rhs, gap
        if self.motion.table() is not None:
            return rhs.py_func, gap.py_func
        kin = self.motion.kinematics

        def A_r(t, p):  # the motion's, where a sustained contact needs it
            return self.motion.collar_acceleration(t) if in_sustained(p.phase, p.contact.law) else np.nan

        return (lambda t, y, out, p: rhs_with(t, kin(t), A_r(t, p), y, out, p),
                lambda t, y, p: event_with(t, kin(t), A_r(t, p), y, p))

    # conveniences for Python callers (tests, the paper's figures): one state at a time
    def rhs(self, t, y, phase=None):
        """``dy/dt`` at ``(t, y)`` [SI]."""
        out = np.empty(2 * self.modes)
        f = self.functions()[0]
        f(float(t), np.ascontiguousarray(y, dtype=float), out, self.with_phase(phase))
        return out

    def gap(self, t, y):
        """Event function ``xi_min - min_film`` [m]."""
        return float(self.functions()[1](float(t), np.ascontiguousarray(y, dtype=float), self.params)[0])

    def thinnest_film(self, t, y):
        """``(xi_min, x_c, at_edge, side)``: the thinnest film over the pad and the sides."""
        xi, x_c, edge, side = thinnest_given(self.kinematics(t).x_star, np.ascontiguousarray(y, dtype=float),
                                             self.params)
        return float(xi), float(x_c), bool(edge), int(side)

    def contact_point(self, t, y):
        """:attr:`ContactPhase.point` of the thinnest film at ``(t, y)``."""
        _, x_c, edge, _ = self.thinnest_film(t, y)
        x0 = film.pad_start(self.kinematics(t).x_star, self.config.film.pad_length, self.params.film.pad_reference)
        return contact_point(x_c, edge, x0, self.config.film.pad_length)

    def approach(self, t, y):
        """``(v, x_c, side)``: normal approach velocity at the thinnest film [m/s], positive closing."""
        N = self.modes
        kin = self.kinematics(t)
        _, x_c, edge, side = self.thinnest_film(t, y)
        v = side * contact.approach_velocity(y[:N], y[N:], x_c, kin.V_r if edge else 0.0,
                                             self.config.mechanism.rod_length)
        return float(v), x_c, side

    def impact(self, t, y, restitution=None):
        """The restitution law at ``t`` (``restitution`` default ``contact.restitution``): ``(y_plus, x_c, v_minus, side)``."""
        N = self.modes
        v_minus, x_c, side = self.approach(t, y)
        y_plus = np.array(y, dtype=float)
        e = self.config.contact.restitution if restitution is None else restitution
        if v_minus > 0.0 and self.params.galerkin is not None:
            y_plus[N:] = side * section.eigen_restitution_jump(self.params.galerkin, side * y_plus[N:], x_c,
                                                               v_minus, e, self.config.mechanism.rod_length)
        elif v_minus > 0.0:
            y_plus[N:] = side * contact.restitution_jump(side * y_plus[N:], x_c, v_minus, e,
                                                         self.config.mechanism.rod_length)
        return y_plus, x_c, v_minus, side

    def sustained_force(self, t, y, side, point):
        """Force [N] of a sustained contact on ``side`` at ``point`` (:class:`ContactPhase`) at ``(t, y)``."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        y = np.ascontiguousarray(np.reshape(y, (t.size, 2 * self.modes)), dtype=float)
        sides = np.broadcast_to(np.asarray(side, dtype=float), t.shape).copy()
        points = np.broadcast_to(np.asarray(point, dtype=float), t.shape).copy()
        if self.compiled:
            return sustained_force_many(t, y, sides, points, self.params)
        rhs_f = self.functions()[0]
        p = self.params
        out = np.zeros(t.size)
        for i in range(t.size):
            if sides[i] != 0.0:
                d = np.empty(2 * self.modes)
                rhs_f(t[i], y[i], d, p)
                kin = self.kinematics(t[i])
                A_r = (collar_acceleration(t[i], p.motion) if self.motion.table() is not None
                       else self.motion.collar_acceleration(t[i]))
                out[i] = sustained_given(t[i], kin, A_r, y[i], d, p, sides[i], points[i])
        return out

    def compliant_loads(self, t, y, side, v_minus):
        """``(force [N], power [W])`` of the compliant contact at samples ``t`` ``(T,)`` of states ``y``: its
        resultant and its power on the link (:func:`~lubelink.link.model.compliant_many`; 0 where ``side`` is 0)."""
        t = np.ascontiguousarray(t, dtype=float)
        side = np.ascontiguousarray(side, dtype=float)
        v_minus = np.ascontiguousarray(v_minus, dtype=float)
        y = np.ascontiguousarray(y, dtype=float)
        if self.compiled and self.params.spatial is None and self.motion.table() is not None:
            return compliant_many(t, y, side, v_minus, self.params)
        force, power = np.zeros(t.size), np.zeros(t.size)
        for i in np.flatnonzero(side):
            F, force[i] = self.contact_force(t[i], y[i], (side[i], v_minus[i]))
            power[i] = float(np.dot(self.face_block(y[i], side[i])[0][self.modes:], F))
        return force, power

    def contact_position(self, t, phase):
        """Where on the link [m] the contact of ``phase`` ``(side, v_minus, point)`` acts at ``t``."""
        x0 = film.pad_start(self.kinematics(t).x_star, self.config.film.pad_length, self.params.film.pad_reference)
        return float(contact_position(phase[2], x0, self.config.film.pad_length))

    def sustained_loads(self, t, y, side, point):
        """Modal force [N] of a sustained contact on ``side`` at ``point`` (:class:`ContactPhase`) at ``(t, y)``
        (the compliant law's: :meth:`compliant_loads`)."""
        force = float(self.sustained_force(t, y, side, point)[0])
        x_c = self.contact_position(t, (side, 0.0, point))
        L = self.config.mechanism.rod_length
        return -self.face_block(y, side)[1] * force * np.sin(beam.wavenumbers(self.modes, L) * x_c)

    def film_loads(self, t, y):
        """Modal film forces [N] and the resultant film force along +j [N]."""
        N = self.modes
        kin = self.kinematics(t)
        F = np.zeros(N)
        y = np.ascontiguousarray(y, dtype=float)
        p = self.params
        total = film.modal_film_force(y[:N], y[N:], kin.x_star, kin.V_r, p.film, p.beam.width, p.pad, p.basis.rod_length, F)
        return F, float(total)

    def contact_force(self, t, y, phase, width=None):
        """Modal force [N] and magnitude [N] of the compliant contact in ``phase`` ``(side, v_minus)`` (on a face of
        ``width`` [m], default the link's)."""
        N = self.modes
        kin = self.kinematics(t)
        F = np.zeros(N)
        p = self.params
        x0 = film.pad_start(kin.x_star, p.film.pad_length, p.film.pad_reference)
        y = np.ascontiguousarray(y, dtype=float)
        force = compliant.compliant_force(y[:N], y[N:], x0, kin.V_r, p.film, p.contact, p.pad,
                                          p.basis.rod_length, float(phase[0]), float(phase[1]),
                                          p.beam.width if width is None else width, F)
        return F, float(force)


def _backend(config, motion):
    """``(compiled, note)`` for ``solver.backend``; raises :class:`BackendError` if ``"numba"`` cannot be had."""
    wanted = config.solver.backend
    if wanted == "numpy":
        return False, ""
    why = ""
    if not _jit.ENABLED:
        why = "Numba is not installed" if not _jit._WHY.startswith("LUBELINK") else "LUBELINK_DISABLE_JIT is set"
    elif motion.table() is None:
        hint = getattr(motion, "compile_hint", "lubelink.link.kinematics.sampled_motion")
        why = f"the motion is given as Python callables (use {hint} to compile it)"
    elif config.solver.method in ("RK45", "Radau", "BDF", "LSODA"):  # (the loop in Python, the physics compiled)
        return True, f"solver.method = {config.solver.method!r} steps in Python (SciPy) on the compiled right-hand side"
    if not why:
        return True, ""
    if wanted == "numba":
        raise BackendError(f"solver.backend = 'numba': not available, {why}; use solver.backend = 'auto' or 'numpy'")
    return False, f"compiled path not used: {why}"


def interpreted(model: Model, note: str) -> Model:
    """The ``numpy``-backend copy of ``model``, ``note`` saying why."""
    return Model(model.config, model.motion, model.params, False, note)


def compile_failed(model: Model, exc: BaseException) -> Model:
    """The ``numpy``-backend copy of ``model`` after a compile failure under ``backend = "auto"`` (warns)."""
    message = f"lubelink: the compiled path failed ({type(exc).__name__}: {exc}); running on the numpy backend"
    warnings.warn(message, RuntimeWarning, stacklevel=3)
    log.warning(message)
    return interpreted(model, f"compile failed: {type(exc).__name__}")

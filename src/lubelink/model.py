"""The modal model assembled from the physics: its parameters for compiled code, right-hand side and gap.

State ``y = [q_1..q_N, q_dot_1..q_dot_N]``. The right-hand side (:func:`rhs`) is the corrected
modal equation (docs/model.md section 2, paper Eq. 18 corrected):

    q_ddot_n = -(omega_n^2 - omega^2) q_n - 2 zeta omega_n q_dot_n
               - 2/(L beta_n) {(A_O2 - g_j) [1 + (-1)^(n+1)] + alpha L (-1)^(n+1)}
               + (F_n^film + F_n^contact + R sin(beta_n x_star)) / (rho A L / 2)

with ``g_j`` gravity along the link's ``j`` axis. Every term comes from its physics module
(:mod:`.kinematics`, :mod:`.beam`, :mod:`.film`, :mod:`.contact`); :func:`rhs`, :func:`gap` (the event
and its rate) are what the integrators run, compiled, or as Python on the ``numpy`` backend.

The paper's printed equations are variants of the same right-hand side (``model.equations``):
``printed-omega2`` adds ``-2 omega^2 q_n`` (Eq. 18's ``+omega^2``), ``double-count`` forces with
``A_O2 + omega v_O1`` (Eq. 18's ``a_O2 + omega v_O1`` read with Section 6's true ``a_O2``),
``printed`` both, ``printed-film-sign`` reverses the film force (Eq. 20's ``+B P``).
"""

from __future__ import annotations

import logging
import warnings
from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple

import numpy as np

from . import _jit, beam, contact, film, section
from .film import asperity
from ._jit import jitable, kernel
from .errors import BackendError
from .kinematics import MotionTable, SliderCrank, collar_acceleration, motion_at
from .params import CHOICES, Config, kernel_view

__all__ = ["Params", "Basis", "ContactPhase", "Model", "build_model", "rhs", "gap", "rhs_given", "BackendError"]

log = logging.getLogger("lubelink")

_EQ = CHOICES["model.equations"]
PRINTED_OMEGA2, DOUBLE_COUNT, PRINTED, PRINTED_FILM_SIGN = (_EQ.index(v) for v in _EQ[1:])


class Basis(NamedTuple):
    """The sine modes: ``modes`` [-], ``rod_length`` [m], ``omega_n`` [rad/s], ``modal_mass`` [kg]."""

    modes: int
    rod_length: float
    omega_n: np.ndarray
    modal_mass: float


class ContactPhase(NamedTuple):
    """A contact in progress: ``side`` (+1, -1; 0 for none), its approach velocity [m/s] and point.

    Under ``contact.law = "compliant"`` the compliant force acts; under ``"restitution"`` the link
    rides on the collar (sustained contact, :func:`lubelink.contact.constraint_force`) at
    ``point``: the material point of the link [m] where the contact began inside the pad, or
    :data:`PAD_START` / :data:`PAD_END` for a pad edge (which slides with the collar).
    """

    side: float
    v_minus: float
    point: float = 0.0


Phase = ContactPhase


class Params(NamedTuple):
    """Everything compiled code reads, generated from a :class:`~lubelink.params.Config`.

    The sections are :func:`~lubelink.params.kernel_view` s of the dataclasses (same field
    names); ``basis``, ``pad`` and ``motion`` are tables derived from them; ``phase`` is the
    compliant contact of the segment; ``galerkin`` the eigenbasis of a variable section
    (:class:`~lubelink.section.GalerkinTable`; None for a uniform link, whose state is the sine
    modes themselves).
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


NO_PHASE = ContactPhase(0.0, 0.0, 0.0)
#: :attr:`ContactPhase.point` of a sustained contact at the start and at the end of the pad.
PAD_START, PAD_END = -1.0, -2.0


def contact_point(x_c, at_edge, x0, pad_length):
    """:attr:`ContactPhase.point` of a contact at ``x_c`` [m] (``at_edge``: a pad edge; pad from ``x0``)."""
    if not at_edge:
        return float(x_c)
    return PAD_START if abs(x_c - x0) <= abs(x_c - x0 - pad_length) else PAD_END


# --- the right-hand side ----------------------------------------------------------------------------
@jitable
def _compliant_term(phase, q, q_dot, x_star, V_r, p, F):
    """Add the compliant contact force of ``phase`` (None: no compliant law, compiles to nothing)."""
    if phase is None:
        return
    if phase.side == 0.0 or p.contact.law != contact.COMPLIANT:
        return
    x0 = film.pad_start(x_star, p.film.pad_length, p.film.pad_reference)
    contact.compliant_force(q, q_dot, x0, V_r, p.film, p.contact, p.pad, p.basis.rod_length, phase.side,
                            phase.v_minus, F)


@jitable(inline=True)
def rhs_given(t, kin, y, out, p):
    """``dy/dt`` into ``out`` for the rigid motion ``kin`` at ``t`` (the tuple of :func:`~lubelink.kinematics.motion_at`)."""
    A_O2, omega, alpha, x_star, V_r, reaction, angle, v_O1 = kin
    N = p.basis.modes
    L = p.basis.rod_length
    yq = section.physical(p.galerkin, y)  # the sine-mode state (y itself for a uniform link)
    q = yq[:N]
    q_dot = yq[N:]
    F = out[N:]  # modal forces [N], accumulated here before the accelerations replace them
    F[:] = 0.0
    film.modal_film_force(q, q_dot, x_star, V_r, p.film, p.beam.width, p.pad, L, F)
    if p.model.equations == PRINTED_FILM_SIGN:
        F *= -1.0
    asperity.modal_asperity_force(q, x_star, p.film, p.beam.width, p.pad, L, F)
    if reaction != 0.0:
        for n in range(N):
            F[n] += beam.point_load(reaction, x_star, (n + 1) * np.pi / L)
    _compliant_term(p.phase, q, q_dot, x_star, V_r, p, F)
    gX, gY = p.mechanism.gravity
    A_eff = A_O2
    if gX != 0.0 or gY != 0.0:  # gravity along the link's j axis
        A_eff -= -gX * np.sin(angle) + gY * np.cos(angle)
    if p.model.equations == DOUBLE_COUNT or p.model.equations == PRINTED:
        A_eff += omega * v_O1
    stiffening = p.model.equations == PRINTED_OMEGA2 or p.model.equations == PRINTED
    _accelerations(p.galerkin, y, F, A_eff, alpha, omega, p.basis, p.beam.damping_ratio, stiffening, out)


@jitable
def _accelerations(g, y, F, A_eff, alpha, omega, basis, zeta, stiffening, out):
    """``out = dy/dt`` from the modal forces ``F`` [N] (aliasing ``out[N:]``): sine modes, or the eigenmodes of ``g``."""
    if g is not None:
        section.eigen_accelerations(g, y, F, A_eff, alpha, omega, basis.omega_n, zeta, basis.modal_mass,
                                    stiffening, out)
        return
    N = basis.modes
    L = basis.rod_length
    for n in range(N):
        forcing = beam.rigid_load(A_eff, alpha, n + 1, L) + F[n] / basis.modal_mass
        if stiffening:
            forcing -= 2.0 * omega * omega * y[n]
        out[N + n] = beam.modal_acceleration(y[n], y[N + n], basis.omega_n[n], zeta, omega, forcing)
        out[n] = y[N + n]


@jitable
def in_sustained(phase, law):
    """Whether the segment is a sustained contact (restitution law, a phase with a side)."""
    if phase is None:
        return False
    return law == contact.RESTITUTION and phase.side != 0.0


@jitable
def sustained_given(t, kin, A_r, y, out, p, side, point):
    """Apply the sustained contact on ``side`` at ``point`` to ``out`` (``dy/dt`` without it); return its force [N].

    The contact point is held where the contact began (:class:`ContactPhase`): a material point,
    or a pad edge. ``A_r`` NaN: the collar acceleration of ``p.motion`` at ``t``. The Baumgarte
    rate is the highest modal frequency of the basis.
    """
    N = p.basis.modes
    L = p.basis.rod_length
    q, q_dot = y[:N], y[N:]
    x0 = film.pad_start(kin[3], p.film.pad_length, p.film.pad_reference)
    at_edge = point < 0.0
    x_c = point
    if point == PAD_START:
        x_c = x0
    elif point == PAD_END:
        x_c = x0 + p.film.pad_length
    u = 0.0
    for n in range(N):
        u += q[n] * np.sin((n + 1) * np.pi / L * x_c)
    xi = 0.5 * p.film.clearance - side * u
    if A_r != A_r:
        A_r = collar_acceleration(t, p.motion)
    m = p.basis.modal_mass
    lam = contact.constraint_force(q, q_dot, out[N:], x_c, at_edge, False, side, xi - p.contact.min_film, kin[4],
                                   A_r, p.basis.omega_n[N - 1], m, L)
    for n in range(N):
        out[N + n] -= side * lam * np.sin((n + 1) * np.pi / L * x_c) / m
    return lam


@jitable
def _sustained_term(phase, t, kin, A_r, y, out, p):
    """:func:`sustained_given` of ``phase`` if it is a sustained contact: ``(True, force [N])``, else ``(False, 0)``.

    ``phase`` None (no contact law with phases) compiles to nothing.
    """
    if phase is None:
        return False, 0.0
    if phase.side == 0.0 or p.contact.law != contact.RESTITUTION:
        return False, 0.0
    return True, sustained_given(t, kin, A_r, y, out, p, phase.side, phase.point)


@jitable
def rhs_with(t, kin, A_r, y, out, p):
    """``dy/dt`` into ``out``: :func:`rhs_given` and, in a sustained contact, its constraint force."""
    rhs_given(t, kin, y, out, p)
    _sustained_term(p.phase, t, kin, A_r, y, out, p)


@jitable
def event_with(t, kin, A_r, y, p):
    """The event: :func:`gap_given`, or in a sustained contact ``(force [N], 0, inf)``: it ends when the force falls to zero."""
    if in_sustained(p.phase, p.contact.law):
        out = np.empty(y.shape[0])
        rhs_given(t, kin, y, out, p)
        return _sustained_term(p.phase, t, kin, A_r, y, out, p)[1], 0.0, np.inf
    return gap_given(t, kin, y, p)


@kernel
def rhs(t, y, out, p):
    """``dy/dt`` of the modal ODE into ``out``."""
    rhs_with(t, motion_at(t, p.motion), np.nan, y, out, p)


@jitable
def thinnest_given(x_star, y, p):
    """``(xi_min, x_c, at_edge, side)``: the thinnest film over the pad and the sides (``y``: sine-mode state)."""
    x0 = film.pad_start(x_star, p.film.pad_length, p.film.pad_reference)
    return contact.thinnest_film_sides(y[:p.basis.modes], x0, p.film, p.pad, p.basis.rod_length, 0.0)


@jitable
def gap_given(t, kin, y, p):
    """``(gap, rate, bound)``: thinnest film above breakdown, ``xi_min - min_film`` [m], its rate and a bound of the rate [m/s]."""
    N = p.basis.modes
    L = p.basis.rod_length
    yq = section.physical(p.galerkin, y)
    q, q_dot = yq[:N], yq[N:]
    xi, x_c, at_edge, side = thinnest_given(kin[3], yq, p)
    return (xi - p.contact.min_film, contact.gap_rate(q, q_dot, x_c, at_edge, side, kin[4], L),
            _rate_bound(p.galerkin, y, p.basis.omega_n, kin[1], kin[4], L))


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
            rhs_given(t[i], kin, y[i], d, p)
            out[i] = sustained_given(t[i], kin, np.nan, y[i], d, p, side[i], point[i])
    return out


# --- parameters ---------------------------------------------------------------------------------------
def _c(a):
    return np.ascontiguousarray(a, dtype=np.float64).copy()


def make_params(config: Config, table: MotionTable | None, cross_section=None) -> Params:
    """The :class:`Params` of a validated configuration (``table`` None: a placeholder motion).

    ``cross_section``: a :class:`~lubelink.section.Section` replacing the beam's (uniform or
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
    if table.knots is not None:
        table = table._replace(knots=_c(table.knots), coef=_c(table.coef))
    phase = NO_PHASE if config.contact.law in ("compliant", "restitution") else None
    return Params(kernel_view(config.mechanism), kernel_view(config.beam), kernel_view(config.film),
                  kernel_view(config.collar), kernel_view(config.contact), kernel_view(config.model), basis, pad,
                  table, phase, galerkin)


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
        """The Numba type of :attr:`params` (the same for every phase), computed once."""
        import numba

        return numba.typeof(self.params)

    @property
    def modes(self) -> int:
        return self.config.beam.modes

    @property
    def omega_n(self) -> np.ndarray:
        return self.params.basis.omega_n

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

        The integrator's state is ``[eta, eta_dot]`` for a variable section (:mod:`lubelink.section`);
        ``y`` itself for a uniform link. :meth:`rhs` and :meth:`gap` take integrator states, the other
        methods and the results sine-mode states.
        """
        g = self.params.galerkin
        if g is None:
            return y
        y = np.asarray(y, dtype=float)
        N = self.modes
        return np.concatenate([y[..., :N] @ g.phi.T, y[..., N:] @ g.phi.T], axis=-1)

    def to_state(self, yq):
        """The integrator states of sine-mode states ``yq`` (inverse of :meth:`to_physical`)."""
        g = self.params.galerkin
        if g is None:
            return yq
        yq = np.asarray(yq, dtype=float)
        N = self.modes
        return np.concatenate([yq[..., :N] @ g.phi_inv.T, yq[..., N:] @ g.phi_inv.T], axis=-1)

    def with_phase(self, phase) -> Params:
        """The parameters of a segment with the compliant contact ``phase`` ``(side, v_minus)`` or None."""
        if self.params.phase is None:
            return self.params
        return self.params._replace(phase=NO_PHASE if phase is None else ContactPhase(
            float(phase[0]), float(phase[1]), float(phase[2]) if len(phase) > 2 else 0.0))

    def gravity_j(self, t):
        """Gravity along the link's ``j`` axis at ``t`` [m/s^2]."""
        gX, gY = self.config.mechanism.gravity
        angle = self.kinematics(t)[6]
        return -gX * np.sin(angle) + gY * np.cos(angle)

    def kinematics(self, t):
        """The tuple of :func:`~lubelink.kinematics.motion_at` at ``t`` [s]."""
        if self.motion.table() is None:
            return self.motion.kinematics(t)
        return motion_at(float(t), self.params.motion)

    @property
    def watched(self) -> bool:
        """Whether the film's gap is watched (a film, or a contact law): the event of :meth:`functions`."""
        return self.config.film.enabled or self.config.contact.law != "none"

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
        xi, x_c, edge, side = thinnest_given(self.kinematics(t)[3], np.ascontiguousarray(y, dtype=float),
                                             self.params)
        return float(xi), float(x_c), bool(edge), int(side)

    def contact_point(self, t, y):
        """:attr:`ContactPhase.point` of the thinnest film at ``(t, y)``."""
        _, x_c, edge, _ = self.thinnest_film(t, y)
        x0 = film.pad_start(self.kinematics(t)[3], self.config.film.pad_length, self.params.film.pad_reference)
        return contact_point(x_c, edge, x0, self.config.film.pad_length)

    def approach(self, t, y):
        """``(v, x_c, side)``: normal approach velocity at the thinnest film [m/s], positive closing."""
        N = self.modes
        kin = self.kinematics(t)
        _, x_c, edge, side = self.thinnest_film(t, y)
        v = side * contact.approach_velocity(y[:N], y[N:], x_c, kin[4] if edge else 0.0,
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

    def film_loads(self, t, y):
        """Modal film forces [N] and the resultant film force along +j [N]."""
        N = self.modes
        kin = self.kinematics(t)
        F = np.zeros(N)
        y = np.ascontiguousarray(y, dtype=float)
        p = self.params
        total = film.modal_film_force(y[:N], y[N:], kin[3], kin[4], p.film, p.beam.width, p.pad, p.basis.rod_length, F)
        return F, float(total)

    def contact_force(self, t, y, phase):
        """Modal force [N] and magnitude [N] of the compliant contact in ``phase`` ``(side, v_minus)``."""
        N = self.modes
        kin = self.kinematics(t)
        F = np.zeros(N)
        p = self.params
        x0 = film.pad_start(kin[3], p.film.pad_length, p.film.pad_reference)
        y = np.ascontiguousarray(y, dtype=float)
        force = contact.compliant_force(y[:N], y[N:], x0, kin[4], p.film, p.contact, p.pad,
                                        p.basis.rod_length, float(phase[0]), float(phase[1]), F)
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
        why = "the motion is given as Python callables (use lubelink.kinematics.sampled_motion to compile it)"
    elif config.solver.method in ("RK45", "Radau", "BDF", "LSODA"):  # (the loop in Python, the physics compiled)
        return True, f"solver.method = {config.solver.method!r} steps in Python (SciPy) on the compiled right-hand side"
    if not why:
        return True, ""
    if wanted == "numba":
        raise BackendError(f"solver.backend = 'numba': not available, {why}; use solver.backend = 'auto' or 'numpy'")
    return False, f"compiled path not used: {why}"


def build_model(config: Config, motion=None, section=None) -> Model:
    """Assemble the model of a validated configuration.

    Parameters
    ----------
    config : Config
        Validated parameters.
    motion : object, optional
        A motion provider (see :mod:`lubelink.kinematics`); default: the slider-crank of
        ``config.mechanism``.
    section : lubelink.section.Section, optional
        ``A(x)``, ``I(x)`` replacing the beam's (uniform or ``beam.width_ratio``/``height_ratio``
        tapered) section.

    Raises
    ------
    BackendError
        ``solver.backend = "numba"`` for a configuration the compiled path cannot run.
    """
    motion = SliderCrank(config.mechanism) if motion is None else motion
    compiled, note = _backend(config, motion)
    if config.model.equations in ("double-count", "printed") and not isinstance(motion, SliderCrank):
        raise BackendError(f"model.equations = {config.model.equations!r} needs v_O1, which only the "
                           "slider-crank motion provides")
    return Model(config, motion, make_params(config, motion.table(config.collar.mass), section), compiled, note)


def compile_failed(model: Model, exc: BaseException) -> Model:
    """The ``numpy``-backend copy of ``model`` after a compile failure under ``backend = "auto"`` (warns)."""
    message = f"lubelink: the compiled path failed ({type(exc).__name__}: {exc}); running on the numpy backend"
    warnings.warn(message, RuntimeWarning, stacklevel=3)
    log.warning(message)
    return Model(model.config, model.motion, model.params, False, f"compile failed: {type(exc).__name__}")


@kernel
def thinnest_many(x_star, y, p):
    """Thinnest film [m] (over the pad and the sides) of many samples: ``x_star`` shape ``(T,)``, ``y`` ``(T, 2N)``."""
    out = np.empty(x_star.shape[0])
    for i in range(x_star.shape[0]):
        out[i] = thinnest_given(x_star[i], y[i], p)[0]
    return out

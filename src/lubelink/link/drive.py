"""The crank driven by a torque through a flywheel: the rigid slider-crank's dynamics (docs/model.md, "Driven crank").

With ``drive.law`` other than ``"speed"`` the crank angle ``phi(t)`` is not prescribed but follows from

    M(phi) phi_ddot + 1/2 M'(phi) phi_dot^2 = T_motor(phi_dot, t) + Q_slider(phi, phi_dot) + Q_gravity(phi),

the Lagrange equation of the rigid mechanism with one degree of freedom: the crank and flywheel
(``J_f``), the link as a rigid body (its mass, first and second moments about the crank pin O, the
same :func:`~lubelink.link.reactions.link_inertia` the joint reactions use), the slider (``m_s``) and
the collar's guided member (``m_c``). Every acceleration is :func:`~lubelink.link.kinematics.crank_state`'s;
the velocity of each body per unit crank speed (its *velocity coefficient*) is the same function's
acceleration at zero speed and unit crank acceleration, so the kinematics are written once. The
generalised inertia force is linear in ``phi_ddot``:

    Q_inertia(phi, phi_dot, phi_ddot) = M(phi) phi_ddot + 1/2 M'(phi) phi_dot^2

(:func:`inertia_torque`), hence ``M = Q_inertia(phi, 0, 1)`` and the velocity term ``Q_inertia(phi,
phi_dot, 0)``. The equation is integrated by DOP853 with dense output over the run, compiled
(:func:`integrate_crank` on :class:`TabulatedRates`' right-hand side :func:`tabulated_rates`, SciPy's ``solve_ivp``
its reference); :func:`driven_motion` samples ``phi``, ``phi_dot``, ``phi_ddot`` into a
:func:`~lubelink.link.kinematics.sampled_motion`, the prescribed rigid motion of the elastic link.

By itself the coupling is one-way: the link's elastic forces do not act back on the crank. The crank's
equation takes a further torque of time (``torque``: :func:`integrate_crank`, :func:`driven_motion`), through
which :mod:`lubelink.coupling` feeds the link's :func:`elastic_torque` back (``drive.coupling = "two-way"``).
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from .._jit import jitable, kernel
from ..params import Config, Drive, Mechanism
from .kinematics import SampledMotion, crank_state, sampled_motion

__all__ = ["RigidMasses", "rigid_masses", "inertia_torque", "generalised_inertia", "velocity_torque",
           "slider_velocity", "slider_torque", "gravity_torque", "motor_torque", "crank_rates", "integrate_crank",
           "CrankSolution", "DrivenMotion", "driven_motion", "motion_of", "ShiftedCrank", "join_cranks", "kinetic_energy", "elastic_torque", "TabulatedRates"]


class RigidMasses(NamedTuple):
    """The inertia of the rigid slider-crank.

    Attributes
    ----------
    flywheel : float
        Crank and flywheel about the crank axis [kg m^2] (``J_f``).
    link_mass, link_first, link_second : float
        The link's mass [kg], its first [kg m] and second [kg m^2] moments about the crank pin O along
        the link (``m``, ``S = int rho A x dx``, ``I_O = int rho A x^2 dx``).
    slider : float
        Slider mass [kg] (``m_s``).
    collar : float
        Mass of the collar and its guided member [kg] (``m_c``).
    gravity : tuple of float
        ``(g_X, g_Y)`` [m/s^2].
    """

    flywheel: float
    link_mass: float
    link_first: float
    link_second: float
    slider: float
    collar: float
    gravity: tuple = (0.0, 0.0)


def rigid_masses(config: Config, section=None) -> RigidMasses:
    """:class:`RigidMasses` of a configuration (``section``: a :class:`~lubelink.link.section.Section` replacing the beam's)."""
    from .reactions import link_inertia
    from .section import taper

    L = config.mechanism.rod_length
    inertia = link_inertia(section or taper(config.beam, L), config.beam.density, L, 1)
    return RigidMasses(config.drive.flywheel_inertia, inertia.mass, inertia.first, inertia.second,
                       config.drive.slider_mass, config.collar.mass, tuple(config.mechanism.gravity))


def _state(phi, phi_dot, phi_ddot, m: Mechanism):
    return crank_state(phi, phi_dot, phi_ddot, m.crank_length, m.rod_length, m.guide_distance)


def _unit(phi, m: Mechanism):
    """:func:`crank_state` at zero speed and unit crank acceleration: each acceleration is then the
    velocity of its quantity per unit crank speed (its velocity coefficient)."""
    return _state(phi, 0.0, 1.0, m)


def _slider_rate(unit, rod_length):
    """``dX_C/dphi`` [m]: the slider's velocity per unit crank speed, from the velocity coefficients ``unit``."""
    theta, _, g1, g2, _, g_w, *_, c = unit
    return c * g1 + np.sin(theta) * (g2 + g_w * rod_length)


def slider_velocity(phi, phi_dot, m: Mechanism):
    """Velocity of the slider C along +X [m/s] at crank angle ``phi`` [rad] and speed ``phi_dot`` [rad/s]."""
    return _slider_rate(_unit(phi, m), m.rod_length) * phi_dot


def inertia_torque(phi, phi_dot, phi_ddot, m: Mechanism, masses: RigidMasses):
    """Generalised inertia force of the rigid mechanism on the crank angle [N m]: ``M phi_ddot + M' phi_dot^2 / 2``.

    The sum over the bodies of their momentum's rate dotted with their velocity per unit crank speed
    (the link: its force and its moment about O). ``phi`` [rad], ``phi_dot`` [rad/s], ``phi_ddot``
    [rad/s^2]; elementwise on arrays.
    """
    return _inertia_torque(_state(phi, phi_dot, phi_ddot, m), _unit(phi, m), phi_ddot, m, masses)


def _inertia_torque(moving, unit, phi_ddot, m: Mechanism, masses: RigidMasses):
    """:func:`inertia_torque` from :func:`crank_state` at the motion (``moving``) and :func:`_unit`."""
    L = m.rod_length
    theta, _, A1, A2, w, al, _, _, _, Y_dd, c = moving
    _, _, g1, g2, _, g_w, _, _, _, g_Y, _ = unit
    s = np.sin(theta)
    mass, S, I_O = masses.link_mass, masses.link_first, masses.link_second
    link = (mass * A1 - S * w * w) * g1 + (mass * A2 + S * al) * g2 + (S * A2 + I_O * al) * g_w
    slider = masses.slider * (c * (A1 - w * w * L) + s * (A2 + al * L)) * _slider_rate(unit, L)
    return masses.flywheel * phi_ddot + link + slider + masses.collar * Y_dd * g_Y


def generalised_inertia(phi, m: Mechanism, masses: RigidMasses):
    """``M(phi)`` [kg m^2]: the rigid mechanism's inertia about the crank angle ``phi`` [rad] (kinetic energy ``M phi_dot^2 / 2``)."""
    unit = _unit(phi, m)
    return _inertia_torque(unit, unit, 1.0, m, masses)


def velocity_torque(phi, phi_dot, m: Mechanism, masses: RigidMasses):
    """``M'(phi) phi_dot^2 / 2`` [N m] at crank angle ``phi`` [rad] and speed ``phi_dot`` [rad/s]."""
    return inertia_torque(phi, phi_dot, 0.0, m, masses)


def kinetic_energy(phi, phi_dot, m: Mechanism, masses: RigidMasses):
    """Kinetic energy of the rigid mechanism ``M(phi) phi_dot^2 / 2`` [J]."""
    return 0.5 * generalised_inertia(phi, m, masses) * phi_dot * phi_dot


def slider_torque(phi, phi_dot, m: Mechanism, drive: Drive):
    """Generalised force of the slider's external loads on the crank angle [N m].

    The constant force ``drive.slider_force`` along +X and the Coulomb friction ``drive.slider_friction``
    against the slider's velocity: ``(F_s - F_f sign(X_C_dot)) dX_C/dphi``. ``phi`` [rad], ``phi_dot`` [rad/s].
    """
    return _slider_torque(_unit(phi, m), phi_dot, m, drive)


def _slider_torque(unit, phi_dot, m: Mechanism, drive: Drive):
    return _slider_load(_slider_rate(unit, m.rod_length), phi_dot, drive.slider_force, drive.slider_friction)


@jitable
def _slider_load(g_X, phi_dot, force, friction):
    """:func:`slider_torque` from the slider's rate ``g_X = dX_C/dphi`` [m], its ``force`` and ``friction`` [N]."""
    return force * g_X - friction * np.abs(g_X) * np.sign(phi_dot)


def gravity_torque(phi, m: Mechanism, masses: RigidMasses):
    """Generalised force of gravity [N m] on the crank angle ``phi`` [rad]: on the link, the slider and the collar.

    The crank and flywheel are taken balanced (their centre of mass on the crank axis).
    """
    return _gravity_torque(_unit(phi, m), m, masses)


def _gravity_torque(unit, m: Mechanism, masses: RigidMasses):
    gX, gY = masses.gravity
    theta, _, g1, g2, _, g_w, _, _, _, g_Y, c = unit
    if gX == 0.0 and gY == 0.0:
        return 0.0 * np.asarray(theta, dtype=float)
    s = np.sin(theta)
    g_i, g_j = gX * c - gY * s, gX * s + gY * c  # gravity along the link's i and j
    link = masses.link_mass * (g_i * g1 + g_j * g2) + masses.link_first * g_j * g_w
    return link + masses.slider * gX * _slider_rate(unit, m.rod_length) + masses.collar * gY * g_Y


def motor_torque(phi_dot, error_integral, drive: Drive, set_speed):
    """Motor torque on the crank about +k [N m] of ``drive.law``.

    ``phi_dot`` [rad/s]; ``error_integral`` [rad]: ``int (set_speed - phi_dot) dt`` (the controller's);
    ``set_speed`` [rad/s]: the controller's set speed (``mechanism.crank_speed``).
    """
    if drive.law not in LAWS[1:]:
        raise ValueError(f"drive.law = {drive.law!r}: the crank speed is prescribed, there is no motor torque")
    return _motor_law(LAWS.index(drive.law), phi_dot, error_integral, drive.torque, drive.stall_torque,
                      drive.no_load_speed, drive.proportional_gain, drive.integral_gain, set_speed)


#: ``drive.law`` by its code in compiled code (:func:`_motor_law`).
LAWS = ("speed", "torque", "torque-speed", "controller")


@jitable
def _motor_law(law, phi_dot, error_integral, torque, stall_torque, no_load_speed, proportional_gain, integral_gain,
               set_speed):
    """:func:`motor_torque` of the law coded ``law`` (:data:`LAWS`) [N m]."""
    if law == 1:
        return torque + 0.0 * phi_dot
    if law == 2:
        return stall_torque * (1.0 - phi_dot / no_load_speed)
    return torque + proportional_gain * (set_speed - phi_dot) + integral_gain * error_integral


def crank_rates(t, y, config: Config, masses: RigidMasses, torque=None):
    """Right-hand side of the crank's equation: ``y = (phi [rad], phi_dot [rad/s], int e dt [rad])`` -> rates.

    ``torque``: a further torque on the crank about +k [N m], a callable of the time ``t`` [s] (None: none).
    """
    phi, phi_dot, z = y
    m, d = config.mechanism, config.drive
    unit = _unit(phi, m)  # (once: every term below reads the velocity coefficients)
    load = (motor_torque(phi_dot, z, d, m.crank_speed) + _slider_torque(unit, phi_dot, m, d)
            + _gravity_torque(unit, m, masses) - _inertia_torque(_state(phi, phi_dot, 0.0, m), unit, 0.0, m, masses))
    if torque is not None:
        load = load + torque(t)
    return np.array([phi_dot, load / _inertia_torque(unit, unit, 1.0, m, masses), m.crank_speed - phi_dot])


@dataclass(frozen=True)
class CrankSolution:
    """The integrated crank motion: ``solution`` SciPy's ``OdeSolution`` of ``(phi, phi_dot, int e dt)``;
    ``torque`` the further torque of time it was integrated with (:func:`crank_rates`)."""

    solution: object
    config: Config
    masses: RigidMasses
    nfev: int
    torque: object = None

    def __call__(self, t):
        """``(phi [rad], phi_dot [rad/s], phi_ddot [rad/s^2], motor torque [N m])`` at times ``t`` [s]."""
        t = np.asarray(t, dtype=float)
        phi, phi_dot, z = self.solution(t)
        m = self.config.mechanism
        phi_ddot = crank_rates(t, (phi, phi_dot, z), self.config, self.masses, self.torque)[1]
        return phi, phi_dot, phi_ddot, motor_torque(phi_dot, z, self.config.drive, m.crank_speed)


#: Pieces over a turn of :class:`TabulatedRates`' splines (their error, ~h^4/384 of the fourth derivative: 1e-13).
TABLE_PIECES = 4096


class TabulatedRates:
    """:func:`crank_rates` with the rigid mechanism's terms tabulated over a turn, as compiled code.

    The terms of ``phi`` alone, ``M(phi)``, the velocity torque at unit speed (it is ``M'(phi) phi_dot^2 / 2``,
    quadratic in the speed), the gravity torque and the slider's rate ``dX_C/dphi`` (smooth, where its
    torque has kinks at the dead centres), are those functions sampled at :data:`TABLE_PIECES` + 1 angles and
    interpolated by periodic C2 cubic splines; the slider's torque from its rate, the motor torque and
    ``torque`` are evaluated as they are. ``params`` is what :func:`tabulated_rates` (the compiled right-hand
    side) takes: the table, the drive's numbers and ``torque`` as a piecewise cubic of time (``torque.x``
    its knots, ``torque.c`` SciPy's ``PPoly`` coefficients, zero outside the knots); calling the instance
    evaluates the same source as Python, where ``torque`` may be any callable of time.
    """

    def __init__(self, config: Config, masses: RigidMasses, torque=None, pieces=TABLE_PIECES):
        m, d = config.mechanism, config.drive
        table = _rate_table(m, masses, pieces)
        knots, cubic = np.zeros(1), np.zeros((1, 4))  # (no torque: no piece)
        if torque is not None and hasattr(torque, "c") and hasattr(torque, "x"):
            knots, cubic = np.ascontiguousarray(torque.x, dtype=float), np.ascontiguousarray(np.asarray(torque.c).T)
        law = LAWS.index(d.law) if d.law in LAWS[1:] else 1
        self.params = (table, 2.0 * np.pi / pieces, np.array([law, d.torque, d.stall_torque, d.no_load_speed,
                                                              d.proportional_gain, d.integral_gain, m.crank_speed,
                                                              d.slider_force, d.slider_friction], dtype=float),
                       knots, cubic)
        self.torque = torque

    def __call__(self, t, y):
        y = np.asarray(y, dtype=float)
        out = np.empty(3)
        extra = None if self.torque is None or hasattr(self.torque, "c") else float(self.torque(t))
        if extra is None:
            tabulated_rates.py_func(float(t), y, out, self.params)
        else:
            _crank_rates(float(t), y, out, self.params, extra)
        return out


@lru_cache(maxsize=8)
def _rate_table(m: Mechanism, masses: RigidMasses, pieces):
    """:class:`TabulatedRates`' splines ``[piece, term, power]`` (kept: every iteration of a coupling asks them)."""
    from scipy.interpolate import CubicSpline

    phi = np.linspace(0.0, 2.0 * np.pi, pieces + 1)
    unit = _unit(phi, m)
    columns = [_inertia_torque(unit, unit, 1.0, m, masses),
               _inertia_torque(_state(phi, 1.0, 0.0, m), unit, 0.0, m, masses),
               _gravity_torque(unit, m, masses) + 0.0 * phi, _slider_rate(unit, m.rod_length)]
    coefficients = []
    for f in columns:
        f = np.array(f, dtype=float)
        f[-1] = f[0]  # (one turn: equal to rounding)
        coefficients.append(CubicSpline(phi, f, bc_type="periodic").c)
    table = np.ascontiguousarray(np.stack(coefficients, axis=1).transpose(2, 1, 0))
    table.flags.writeable = False
    return table


@jitable
def _piecewise_cubic(knots, cubic, t):
    """The piecewise cubic of the ``knots`` [s] and ``cubic[i] = (c3, c2, c1, c0)`` at ``t`` [s]; 0 outside."""
    if knots.shape[0] < 2 or t < knots[0] or t > knots[-1]:
        return 0.0
    i = min(np.searchsorted(knots, t, side="right"), cubic.shape[0]) - 1
    dt = t - knots[i]
    return ((cubic[i, 0] * dt + cubic[i, 1]) * dt + cubic[i, 2]) * dt + cubic[i, 3]


@jitable
def _crank_rates(t, y, out, p, extra):
    """:func:`crank_rates` on :class:`TabulatedRates`' ``params`` ``p`` with a further torque ``extra`` [N m]."""
    table, step, drive, _, _ = p
    phi, phi_dot, z = y[0], y[1], y[2]
    turn = phi % (2.0 * np.pi)
    i = min(int(turn / step), table.shape[0] - 1)
    dx = turn - i * step
    M = ((table[i, 0, 0] * dx + table[i, 0, 1]) * dx + table[i, 0, 2]) * dx + table[i, 0, 3]
    velocity = ((table[i, 1, 0] * dx + table[i, 1, 1]) * dx + table[i, 1, 2]) * dx + table[i, 1, 3]
    gravity = ((table[i, 2, 0] * dx + table[i, 2, 1]) * dx + table[i, 2, 2]) * dx + table[i, 2, 3]
    rate = ((table[i, 3, 0] * dx + table[i, 3, 1]) * dx + table[i, 3, 2]) * dx + table[i, 3, 3]
    set_speed = drive[6]
    load = (_motor_law(int(drive[0]), phi_dot, z, drive[1], drive[2], drive[3], drive[4], drive[5], set_speed)
            + _slider_load(rate, phi_dot, drive[7], drive[8]) + gravity - velocity * phi_dot * phi_dot + extra)
    out[0] = phi_dot
    out[1] = load / M
    out[2] = set_speed - phi_dot


@kernel
def tabulated_rates(t, y, out, p):
    """The crank's right-hand side on :class:`TabulatedRates`' ``params`` ``p``, its further torque the
    piecewise cubic in them (``out``: ``(phi_dot, phi_ddot, set speed - phi_dot)``)."""
    _crank_rates(t, y, out, p, _piecewise_cubic(p[3], p[4], t))


def integrate_crank(config: Config, t_end, masses: RigidMasses | None = None, rtol=1e-11, atol=1e-12, torque=None,
                    method="compiled", t0=0.0, y0=None):
    """Integrate the crank's equation from ``phi = 0``, ``phi_dot = mechanism.crank_speed`` over ``[0, t_end]`` [s]
    (or from the state ``y0 = (phi, phi_dot, int e dt)`` at ``t0`` [s]).

    DOP853 with dense output at tolerances ``rtol``, ``atol`` on :class:`TabulatedRates`: the project's, compiled
    with its right-hand side (:func:`lubelink.integrate.dense_steps.integrate_dense`, ``method="compiled"``), or
    SciPy's ``solve_ivp`` on the same right-hand side called from Python (``method="scipy"``: the same steps up
    to rounding, 50-100x slower). ``torque``: a further torque of time on the crank (:func:`crank_rates`), a
    piecewise cubic (``x``, ``c``: SciPy's ``PPoly``) for the compiled method.
    """
    masses = rigid_masses(config) if masses is None else masses
    rates = TabulatedRates(config, masses, torque)
    y0 = [0.0, config.mechanism.crank_speed, 0.0] if y0 is None else [float(v) for v in y0]
    if method == "compiled":
        from ..integrate.dense_steps import integrate_dense

        if torque is not None and not hasattr(torque, "c"):
            raise ValueError("integrate_crank: the compiled method takes a piecewise cubic torque (x, c)")
        try:
            sol = integrate_dense(tabulated_rates, rates.params, float(t0), y0, float(t_end), rtol, atol)
        except RuntimeError as exc:
            raise RuntimeError(f"the crank's equation (drive.law = {config.drive.law!r}) failed: {exc}") from None
        return CrankSolution(sol, config, masses, sol.nfev, torque)
    from scipy.integrate import solve_ivp

    sol = solve_ivp(rates, (float(t0), float(t_end)), y0, method="DOP853", rtol=rtol, atol=atol, dense_output=True)
    if not sol.success:
        raise RuntimeError(f"the crank's equation (drive.law = {config.drive.law!r}) failed: {sol.message}")
    return CrankSolution(sol.sol, config, masses, int(sol.nfev), torque)


class _JoinedTorque:
    """The further torque of :func:`join_cranks`: ``first``'s before ``at`` [s], ``second``'s from it."""

    def __init__(self, first, second, at):
        self.first, self.second, self.at = first, second, at

    def __call__(self, t):
        t = np.asarray(t, dtype=float)
        zero = lambda s: 0.0 * s  # noqa: E731
        return np.where(t < self.at, (self.first or zero)(t), (self.second or zero)(t))


def join_cranks(first: CrankSolution, second: CrankSolution) -> CrankSolution:
    """One crank solution: ``first`` up to where ``second`` starts (it started from ``first``'s state there)."""
    from ..integrate.dense_steps import join

    at = float(second.solution.ts[0])
    torque = None if first.torque is None and second.torque is None else _JoinedTorque(first.torque, second.torque, at)
    return CrankSolution(join(first.solution, second.solution), second.config, second.masses,
                         first.nfev + second.nfev, torque)


@dataclass(frozen=True, eq=False)
class DrivenMotion(SampledMotion):
    """A :class:`~lubelink.link.kinematics.SampledMotion` of the driven crank, with the crank's solution (``crank``)."""

    crank: CrankSolution | None = None


#: Samples of the rigid motion per crank turn (at the fastest speed of the run).
SAMPLES_PER_TURN = 512


def driven_motion(config: Config, section=None, samples_per_turn=SAMPLES_PER_TURN, torque=None,
                  rtol=1e-11) -> DrivenMotion:
    """The link's rigid motion under the driven crank, for ``config.solver.t_end`` (and a turn beyond).

    ``crank_state`` at the integrated ``phi``, ``phi_dot``, ``phi_ddot``, sampled ``samples_per_turn``
    times a turn at the run's fastest crank speed and interpolated by C2 cubic splines (with the pin's axial
    acceleration ``A_O1``, which the axial force reads). ``torque``: a further torque of time on the crank
    (:func:`crank_rates`; the two-way coupling's, :mod:`lubelink.coupling`); ``rtol``: the crank's integration
    tolerance (:func:`integrate_crank`, ``atol = rtol / 10``).
    """
    masses = rigid_masses(config, section)
    margin = 2.0 * np.pi / abs(config.mechanism.crank_speed)
    crank = integrate_crank(config, config.solver.t_end + margin, masses, rtol, 0.1 * rtol, torque=torque)
    return motion_of(crank, config, masses, 0.0, samples_per_turn)


class ShiftedCrank:
    """A crank solution read from ``start`` [s] on: ``shifted(t) = crank(start + t)``."""

    def __init__(self, crank, start):
        self.crank, self.start = crank, float(start)

    def __call__(self, t):
        return self.crank(self.start + np.asarray(t, dtype=float))


def motion_of(crank, config: Config, masses: RigidMasses, start=0.0, samples_per_turn=SAMPLES_PER_TURN):
    """:func:`driven_motion`'s sampled motion of an integrated ``crank`` (:class:`CrankSolution`) from ``start`` [s]
    to its end, in the time from ``start`` (its ``crank`` then a :class:`ShiftedCrank`)."""
    m = config.mechanism
    t_grid = crank.solution.ts
    t_grid = t_grid[t_grid >= start]
    fastest = max(float(np.max(np.abs(crank.solution(t_grid)[1]))), 1e-3 * abs(m.crank_speed))
    step = 2.0 * np.pi / fastest / samples_per_turn
    t = np.linspace(0.0, t_grid[-1] - start, int(np.ceil((t_grid[-1] - start) / step)) + 1)
    phi, phi_dot, phi_ddot, _ = crank(start + t)
    theta, _, A_O1, A_O2, omega, alpha, x_star, V_r, _, Y_dd, c = _state(phi, phi_dot, phi_ddot, m)
    s = sampled_motion(t, A_O2, omega, x_star, alpha=alpha, V_r=V_r, reaction=-masses.collar * Y_dd / c,
                       angle=-theta, A_O1=A_O1)
    return DrivenMotion(**{f.name: getattr(s, f.name) for f in fields(s)},
                        crank=crank if start == 0.0 else ShiftedCrank(crank, start))


def elastic_torque(phi, phi_dot, phi_ddot, q, q_dot, q_ddot, m: Mechanism, inertia):
    """The torque the link's elastic motion puts on the crank, left out by the one-way coupling [N m].

    The elastic part of the link's generalised inertia force on ``phi``: the link's momentum rate and
    moment about O with the sine modes ``q`` [m], ``q_dot`` [m/s], ``q_ddot`` [m/s^2] (shape ``(T, N)``)
    less those of the rigid link (:func:`lubelink.link.reactions.joint_reactions`' ``P_i``, ``P_j``,
    ``M_O``), dotted with the velocity coefficients; ``inertia`` :func:`~lubelink.link.reactions.link_inertia`.
    Positive: it would speed the crank up.
    """
    _, _, A1, _, w, al, *_ = _state(phi, phi_dot, phi_ddot, m)
    _, _, g1, g2, _, g_w, *_ = _unit(phi, m)
    U, U_dot, U_ddot = q @ inertia.modal, q_dot @ inertia.modal, q_ddot @ inertia.modal
    P_i = -al * U - 2.0 * w * U_dot
    P_j = -w * w * U + U_ddot
    M_O = q_ddot @ inertia.modal_first - U * A1
    return -(P_i * g1 + P_j * g2 + M_O * g_w)

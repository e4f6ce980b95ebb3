"""Prescribed rigid-body motion of the link (docs/model.md section 3).

The beam needs, as functions of time, the true transverse acceleration of the link end O
(``A_O2``), the link's angular velocity ``omega`` and acceleration ``alpha``, the collar position
along the link ``x_star`` and its velocity relative to the link ``V_r``; and, for the extensions,
the joint reaction on the link, the link angle (gravity), ``v_O1`` (the paper's printed
equation variant) and ``A_O1``, the acceleration of O along the link (the axial force, :mod:`.axial`).
:func:`motion_at` evaluates all of them for one time in compiled code, from a :class:`MotionTable`:

* the slider-crank of the paper's Section 6 in closed form (:func:`slider_crank_state`);
* sampled motions (:func:`sampled_motion`), as piecewise cubics.

A motion given as Python callables (:class:`PrescribedMotion`) cannot enter compiled code; it runs
on the ``numpy`` backend, evaluated by :meth:`PrescribedMotion.kinematics`.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Callable, NamedTuple

import numpy as np

from .._jit import jitable, kernel
from ..params import Mechanism

__all__ = [
    "RigidMotion",
    "MotionTable",
    "SLIDER_CRANK",
    "SAMPLED",
    "crank_state",
    "slider_crank_state",
    "slider_crank",
    "motion_at",
    "SliderCrank",
    "PrescribedMotion",
    "SampledMotion",
    "sampled_motion",
    "collar_travel",
    "collar_acceleration",
    "pin_axial_acceleration",
]

#: ``MotionTable.kind`` of the closed-form slider-crank and of a sampled (spline) motion.
SLIDER_CRANK, SAMPLED = 0, 1
#: Channels of a sampled motion, in the order of the rows of ``MotionTable.coef``.
CHANNELS = ("A_O2", "omega", "alpha", "x_star", "V_r", "reaction", "angle", "A_O1")
#: The slider-crank's (empty) spline tables: of the same types as a sampled motion's, so that both
#: run the same compiled kernels.
NO_KNOTS, NO_COEF = np.zeros(0), np.zeros((len(CHANNELS), 4, 0))


class RigidMotion(NamedTuple):
    """Rigid motion of the link at one or more times (floats at one time: :func:`motion_at`).

    The spatial link's :class:`~lubelink.link.spatial.SpatialRigidMotion` has the same layout: ``omega``,
    ``alpha``, ``x_star``, ``V_r`` at positions 1-4, so that what reads the collar reads both.

    Attributes
    ----------
    A_O2 : float or ndarray
        True transverse acceleration of the link end O, ``a_O . j`` [m/s^2].
    omega : float or ndarray
        Angular velocity of the link about +k [rad/s].
    alpha : float or ndarray
        Angular acceleration of the link about +k [rad/s^2].
    x_star : float or ndarray
        Collar position along the link, from O [m].
    V_r : float or ndarray
        Collar velocity relative to the link, along +i [m/s].
    reaction : float or ndarray
        Force of the collar on the link along +j [N] (D7: ``-m_c Y_ddot / cos(theta)`` for the
        slider-crank; 0 without a collar mass).
    angle : float or ndarray
        Angle of the link axis ``i`` about +k from +X [rad] (gravity's direction in the link frame).
    v_O1 : float or ndarray
        Axial velocity of O [m/s] (NaN for a sampled motion; read by the printed equations only).
    A_O1 : float or ndarray
        Axial acceleration of O, ``a_O . i`` [m/s^2] (read by the axial force only, ``beam.axial_force``; NaN
        for a motion of callables without it, 0 for a motion from samples without it: such motions are refused
        with the axial force).
    """

    A_O2: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray
    x_star: np.ndarray
    V_r: np.ndarray
    reaction: np.ndarray = 0.0
    angle: np.ndarray = 0.0
    v_O1: np.ndarray = np.nan
    A_O1: np.ndarray = np.nan


class MotionTable(NamedTuple):
    """A motion in the form compiled code evaluates (:func:`motion_at`).

    ``kind`` is :data:`SLIDER_CRANK` (the four lengths and speed are used; ``knots`` and
    ``coef`` empty, :data:`NO_KNOTS` and :data:`NO_COEF`) or :data:`SAMPLED` (``knots`` [s] and
    ``coef``, shape ``(8, 4, knots.size - 1)``: for each of :data:`CHANNELS` the cubic
    coefficients on each interval, highest power first). ``collar_mass`` [kg] scales the
    slider-crank's joint reaction (D7). Both kinds have the same types, so they share the
    compiled kernels.
    """

    kind: int
    crank_length: float
    rod_length: float
    crank_speed: float
    guide_distance: float
    collar_mass: float
    knots: np.ndarray
    coef: np.ndarray


@jitable
def crank_state(phi, phi_dot, phi_ddot, crank_length, rod_length, guide_distance):
    """Kinematics of the Section 6 slider-crank and its collar at any crank motion (docs/model.md section 3).

    The crank turns anticlockwise about the fixed pivot at the origin through the angle ``phi``;
    O is the crank pin, the slider C runs on the +X axis, ``i`` points from O to C and the collar
    sits on the link under a vertical guide at ``X = a``. With ``phi_ddot = 0`` these are the paper's
    Section 6 formulas; the terms in ``phi_ddot`` (written last in each sum) are those of a crank
    that speeds up or slows down (docs/model.md, "Driven crank"). Works on a float (compiled) and
    elementwise on arrays (NumPy).

    Parameters
    ----------
    phi, phi_dot, phi_ddot : float or ndarray
        Crank angle [rad], speed [rad/s] and angular acceleration [rad/s^2].
    crank_length, rod_length, guide_distance : float
        ``OA`` [m], ``L`` [m], ``a`` [m].

    Returns
    -------
    tuple
        ``(theta [rad], v_O1 [m/s], A_O1 [m/s^2], A_O2 [m/s^2], omega [rad/s], alpha [rad/s^2],
        x_star [m], V_r [m/s], A_r [m/s^2], Y_ddot [m/s^2], cos_theta [-])``: ``-theta`` is the link
        angle, ``A_O1``, ``A_O2`` the crank pin's acceleration along ``i`` and ``j``, ``A_r = dV_r/dt``
        and ``Y_ddot`` the vertical acceleration of the collar.
    """
    OA, w0, a, e = crank_length, phi_dot, guide_distance, phi_ddot
    lam = OA / rod_length
    sphi = np.sin(phi)
    cphi = np.cos(phi)
    s_th = lam * sphi
    c_th = np.sqrt(1.0 - s_th * s_th)
    s_sum = sphi * c_th + cphi * s_th  # sin(phi + theta)
    c_sum = cphi * c_th - sphi * s_th  # cos(phi + theta)
    v_O1 = -OA * w0 * s_sum
    A_O1 = -OA * w0 * w0 * c_sum - OA * e * s_sum
    A_O2 = -OA * w0 * w0 * s_sum + OA * e * c_sum
    omega = -lam * w0 * cphi / c_th
    alpha = lam * w0 * w0 * sphi / c_th - lam**3 * w0 * w0 * cphi * cphi * sphi / c_th**3 - lam * e * cphi / c_th
    theta_dot = -omega
    theta_ddot = -alpha
    x_star = (a - OA * cphi) / c_th
    V_r = (OA * w0 * sphi * c_th + (a - OA * cphi) * s_th * theta_dot) / (c_th * c_th)
    A_r = (OA * w0 * w0 * cphi + 2.0 * V_r * s_th * theta_dot
           + x_star * (c_th * theta_dot * theta_dot + s_th * theta_ddot) + OA * e * sphi) / c_th
    lever = OA - lam * x_star  # Y = sin(phi) * lever
    Y_ddot = -w0 * w0 * sphi * lever - 2.0 * lam * w0 * cphi * V_r - lam * sphi * A_r + e * cphi * lever
    return np.arcsin(s_th), v_O1, A_O1, A_O2, omega, alpha, x_star, V_r, A_r, Y_ddot, c_th


@jitable
def slider_crank_state(t, crank_length, rod_length, crank_speed, guide_distance):
    """Kinematics of the Section 6 slider-crank and its collar (docs/model.md section 3).

    :func:`crank_state` of the crank turning at the constant speed ``omega0``, ``phi = omega0 t``
    (the paper's formulas). Works on a float (compiled) and elementwise on arrays (NumPy).

    Parameters
    ----------
    t : float or ndarray
        Time [s].
    crank_length, rod_length, crank_speed, guide_distance : float
        ``OA`` [m], ``L`` [m], ``omega0`` [rad/s], ``a`` [m].

    Returns
    -------
    tuple
        ``(theta [rad], v_O1 [m/s], A_O2 [m/s^2], omega [rad/s], alpha [rad/s^2], x_star [m],
        V_r [m/s], A_r [m/s^2], Y_ddot [m/s^2], cos_theta [-])``: ``-theta`` is the link angle,
        ``A_r = dV_r/dt`` and ``Y_ddot`` the vertical acceleration of the collar.
    """
    theta, v_O1, _, A_O2, omega, alpha, x_star, V_r, A_r, Y_ddot, c_th = crank_state(
        crank_speed * t, crank_speed, 0.0, crank_length, rod_length, guide_distance)
    return theta, v_O1, A_O2, omega, alpha, x_star, V_r, A_r, Y_ddot, c_th


def slider_crank(t, crank_length, rod_length, crank_speed, guide_distance):
    """:func:`slider_crank_state` as a dict of arrays, keyed by name, with the pin's axial acceleration.

    Keys: ``theta``, ``v_O1``, ``A_O1``, ``A_O2``, ``omega``, ``alpha``, ``x_star``, ``V_r``, ``A_r``,
    ``Y_ddot``, ``cos_theta`` (units as :func:`crank_state`).
    """
    names = ("theta", "v_O1", "A_O1", "A_O2", "omega", "alpha", "x_star", "V_r", "A_r", "Y_ddot", "cos_theta")
    t = np.asarray(t, dtype=float)
    values = crank_state(crank_speed * t, crank_speed, 0.0, crank_length, rod_length, guide_distance)
    return dict(zip(names, values))


@jitable
def knot_interval(t, knots):
    """``(i, t - knots[i])``: the piece of a piecewise polynomial that holds ``t`` (the end pieces outside)."""
    m = knots.shape[0] - 1
    i = np.searchsorted(knots, t, side="right") - 1
    if i < 0:
        i = 0
    elif i > m - 1:
        i = m - 1
    return i, t - knots[i]


@jitable
def cubic_piece(coef, channel, i, dx):
    """Value of channel ``channel`` of piece ``i`` at ``dx`` past its start (``PPoly`` layout, highest power first)."""
    return ((coef[channel, 0, i] * dx + coef[channel, 1, i]) * dx + coef[channel, 2, i]) * dx + coef[channel, 3, i]


@jitable
def piecewise_cubic(t, knots, coef, channel):
    """Value at ``t`` of channel ``channel`` of a piecewise cubic (``scipy.interpolate.PPoly`` layout).

    Outside the knots the end pieces are extended, as ``PPoly`` does.
    """
    i, dx = knot_interval(t, knots)
    return cubic_piece(coef, channel, i, dx)


@jitable(inline=True)
def motion_at(t, m):
    """Rigid motion of the link at time ``t`` [s] for the motion table ``m`` (:class:`MotionTable`).

    Returns
    -------
    RigidMotion
        Of floats.
    """
    if m.kind == SLIDER_CRANK:
        return _slider_crank_motion(t, m)
    return _sampled_motion(t, m.knots, m.coef)


@jitable
def _slider_crank_motion(t, m):
    """:func:`motion_at` of the slider-crank (:data:`SLIDER_CRANK`)."""
    theta, v_O1, A_O2, omega, alpha, x_star, V_r, A_r, Y_ddot, c_th = slider_crank_state(
        t, m.crank_length, m.rod_length, m.crank_speed, m.guide_distance)
    A_O1 = pin_axial_acceleration(t, -theta, m.crank_length, m.crank_speed)
    reaction = -m.collar_mass * Y_ddot / c_th
    return RigidMotion(A_O2, omega, alpha, x_star, V_r, reaction, -theta, v_O1, A_O1)


@jitable
def _sampled_motion(t, knots, coef):
    """:func:`motion_at` of a sampled motion (:data:`SAMPLED`): its splines at ``t``."""
    return RigidMotion(piecewise_cubic(t, knots, coef, 0), piecewise_cubic(t, knots, coef, 1),
                       piecewise_cubic(t, knots, coef, 2), piecewise_cubic(t, knots, coef, 3),
                       piecewise_cubic(t, knots, coef, 4), piecewise_cubic(t, knots, coef, 5),
                       piecewise_cubic(t, knots, coef, 6), np.nan, piecewise_cubic(t, knots, coef, 7))


@jitable
def pin_axial_acceleration(t, angle, crank_length, crank_speed):
    """``A_O1 = a_O . i`` [m/s^2]: the crank pin O's acceleration along the link, for the slider-crank.

    O turns on the crank circle, ``a_O = -OA omega0^2 (cos phi, sin phi)``, and ``i = (cos angle, sin angle)``
    (``angle`` [rad], the link's, ``-theta``): ``A_O1 = -OA omega0^2 cos(phi - angle)``, with ``t`` [s],
    ``crank_length`` [m], ``crank_speed`` [rad/s]. (Its ``j`` twin is ``A_O2`` of :func:`slider_crank_state`.) The
    slider-crank's motion reads it beside :func:`slider_crank_state` (the arithmetic of the constant-speed runs
    stays theirs); a driven crank's motion takes :func:`crank_state`'s ``A_O1``, which the tests check against it.
    """
    return -crank_length * crank_speed * crank_speed * np.cos(crank_speed * t - angle)


@kernel
def collar_many(t, m):
    """``(x_star [m], V_r [m/s])`` of :func:`motion_at` at every time of ``t`` [s] (the results' samples)."""
    x_star = np.empty(t.shape[0])
    V_r = np.empty(t.shape[0])
    for i in range(t.shape[0]):
        k = motion_at(t[i], m)
        x_star[i] = k.x_star
        V_r[i] = k.V_r
    return x_star, V_r


@jitable
def collar_acceleration(t, m):
    """``A_r = dV_r/dt`` [m/s^2], the collar's acceleration relative to the link, for the motion table ``m``.

    The slider-crank's closed form, or the derivative of the ``V_r`` spline of a sampled motion.
    """
    if m.kind == SLIDER_CRANK:
        return slider_crank_state(t, m.crank_length, m.rod_length, m.crank_speed, m.guide_distance)[7]
    i, dx = knot_interval(t, m.knots)
    return (3.0 * m.coef[4, 0, i] * dx + 2.0 * m.coef[4, 1, i]) * dx + m.coef[4, 2, i]


@dataclass(frozen=True)
class SliderCrank:
    """The paper's slider-crank as a motion provider."""

    mechanism: Mechanism

    def _kin(self, t):
        m = self.mechanism
        return slider_crank(t, m.crank_length, m.rod_length, m.crank_speed, m.guide_distance)

    def __call__(self, t) -> RigidMotion:
        k = self._kin(t)
        return RigidMotion(k["A_O2"], k["omega"], k["alpha"], k["x_star"], k["V_r"], 0.0 * k["x_star"], -k["theta"],
                           k["v_O1"], k["A_O1"])

    #: The slider-crank gives the axial acceleration of O (the axial force, ``beam.axial_force``).
    gives_axial_acceleration = True

    def table(self, collar_mass=0.0) -> MotionTable:
        """The :class:`MotionTable` of this motion for the compiled code."""
        m = self.mechanism
        return MotionTable(SLIDER_CRANK, float(m.crank_length), float(m.rod_length), float(m.crank_speed),
                           float(m.guide_distance), float(collar_mass), NO_KNOTS, NO_COEF)

    def joint_reaction(self, t, mass):
        """Force of the collar on the link along +j [N] (D7).

        The collar and its guided member (mass ``m_c``) move vertically with the link point under
        the guide; the guide takes horizontal force only, so the link pushes the collar with
        ``m_c Y_ddot / cos(theta)`` along +j and, by reaction, is pushed with the opposite force.
        """
        k = self._kin(t)
        return -mass * k["Y_ddot"] / k["cos_theta"]

    def link_angle(self, t):
        """Angle of the link axis ``i`` about +k from +X [rad]: ``-theta``."""
        return -self._kin(t)["theta"]

    @property
    def period(self) -> float:
        """Crank period [s]."""
        return 2.0 * np.pi / abs(self.mechanism.crank_speed)


@dataclass(frozen=True)
class PrescribedMotion:
    """A rigid motion given by user callables of time (each vectorised). Runs on the ``numpy`` backend.

    Parameters
    ----------
    A_O2, omega, alpha, x_star, V_r : callable
        Functions of time [s] returning the quantities of :class:`RigidMotion`.
    reaction : callable, optional
        Force of the collar on the link along +j [N] as a function of time; zero if omitted.
    angle : callable, optional
        Angle of the link axis about +k from the fixed +X axis [rad], used to resolve gravity and, with the
        axial force, the slider's guide (the +X line); zero (horizontal link) if omitted.
    A_O1 : callable, optional
        Acceleration of O along the link [m/s^2] (:class:`RigidMotion`), needed by ``beam.axial_force =
        "inertial"`` (refused without it: it does not follow from the other quantities).
    """

    A_O2: Callable
    omega: Callable
    alpha: Callable
    x_star: Callable
    V_r: Callable
    reaction: Callable | None = None
    angle: Callable | None = None
    A_O1: Callable | None = None

    @property
    def gives_axial_acceleration(self) -> bool:
        """Whether the motion gives ``A_O1``, which the axial force reads (``beam.axial_force``)."""
        return self.A_O1 is not None

    def table(self, collar_mass=0.0):
        """None: Python callables cannot be compiled (see :func:`sampled_motion`)."""
        return None

    def _value(self, f, t):
        t = np.asarray(t, dtype=float)
        if f is None:
            return np.zeros_like(t) if t.ndim else 0.0
        if t.ndim == 0:
            return float(f(t))
        return np.broadcast_to(np.asarray(f(t), dtype=float), t.shape)

    def link_angle(self, t):
        return self._value(self.angle, t)

    def __call__(self, t) -> RigidMotion:
        fields = (self.A_O2, self.omega, self.alpha, self.x_star, self.V_r, self.reaction, self.angle)
        nan = np.nan + 0.0 * self._value(None, t)
        return RigidMotion(*(self._value(f, t) for f in fields), nan, nan if self.A_O1 is None else
                           self._value(self.A_O1, t))

    def joint_reaction(self, t, mass):
        return self._value(self.reaction, t)

    def collar_acceleration(self, t, h=1e-6):
        """``dV_r/dt`` [m/s^2] at ``t`` [s]: central difference of the callable ``V_r`` over ``2 h`` [s]."""
        return (float(self._value(self.V_r, t + h)) - float(self._value(self.V_r, t - h))) / (2.0 * h)

    def kinematics(self, t):
        """The :class:`RigidMotion` of :func:`motion_at` at one time ``t`` [s], from the callables."""
        k = self(t)
        return RigidMotion(float(k.A_O2), float(k.omega), float(k.alpha), float(k.x_star), float(k.V_r),
                           float(self._value(self.reaction, t)), float(self._value(self.angle, t)), np.nan,
                           float(k.A_O1))


@dataclass(frozen=True, eq=False)
class SampledMotion(PrescribedMotion):
    """A motion from samples (:func:`sampled_motion`): the callables are the splines, compiled as a table."""

    knots: np.ndarray | None = None
    coef: np.ndarray | None = None

    def table(self, collar_mass=0.0) -> MotionTable:
        return MotionTable(SAMPLED, 0.0, 1.0, 0.0, 0.0, float(collar_mass), self.knots, self.coef)

    @property
    def span(self):
        """``(first, last)`` sample time [s]."""
        return float(self.knots[0]), float(self.knots[-1])


def sampled_motion(t, A_O2, omega, x_star, alpha=None, V_r=None, reaction=None, angle=None, A_O1=None):
    """A motion from samples, interpolated by C2 cubic splines; it runs compiled.

    ``alpha`` defaults to the spline derivative of ``omega`` and ``V_r`` to that of ``x_star``,
    so the five functions stay mutually consistent. ``A_O1``, the acceleration of O along the link, has no
    default: it does not follow from the others (O's position is not given; through the slider's guide it
    would divide by the sine of the link's angle, zero where the link lies along the guide), and the axial
    force (``beam.axial_force = "inertial"``) refuses a motion without it.

    Parameters
    ----------
    t : array_like
        Strictly increasing sample times [s], at least 4.
    A_O2, omega, x_star, alpha, V_r, reaction, angle, A_O1 : array_like
        Samples at ``t`` in the units of :class:`RigidMotion` (``reaction`` [N], ``angle`` [rad]).
    """
    from scipy.interpolate import CubicSpline

    t = np.asarray(t, dtype=float)
    if t.ndim != 1 or t.size < 4 or not np.all(np.isfinite(t)) or not np.all(np.diff(t) > 0):
        raise ValueError("sampled_motion: t must be a strictly increasing 1-D array of at least 4 finite times")

    def spline(name, values):
        values = np.asarray(values, dtype=float)
        if values.shape != t.shape or not np.all(np.isfinite(values)):
            raise ValueError(f"sampled_motion: {name} must be {t.size} finite samples, one per time")
        return CubicSpline(t, values)

    s_omega = spline("omega", omega)
    s_x = spline("x_star", x_star)
    splines = {
        "A_O2": spline("A_O2", A_O2),
        "omega": s_omega,
        "alpha": s_omega.derivative() if alpha is None else spline("alpha", alpha),
        "x_star": s_x,
        "V_r": s_x.derivative() if V_r is None else spline("V_r", V_r),
        "reaction": None if reaction is None else spline("reaction", reaction),
        "angle": None if angle is None else spline("angle", angle),
        "A_O1": None if A_O1 is None else spline("A_O1", A_O1),
    }
    coef = np.zeros((len(CHANNELS), 4, t.size - 1))
    for i, name in enumerate(CHANNELS):
        s = splines[name]
        if s is not None:
            coef[i, 4 - s.c.shape[0]:] = s.c
    return SampledMotion(A_O2=splines["A_O2"], omega=s_omega, alpha=splines["alpha"], x_star=s_x,
                         V_r=splines["V_r"], reaction=splines["reaction"], angle=splines["angle"],
                         A_O1=splines["A_O1"], knots=t, coef=np.ascontiguousarray(coef))


@lru_cache(maxsize=4096)
def collar_travel(mechanism: Mechanism, samples: int = 4097):
    """Smallest and largest collar position over one crank turn [m].

    Sampled on a fine grid of crank angles, then refined around the extreme samples by parabolic
    interpolation (``x_star`` is smooth in the crank angle: the vertex of the parabola through the
    three samples around an extremum is exact to the fourth power of the spacing).
    """
    m = mechanism

    def x_of(phi):  # x_star depends on the crank angle only: use unit crank speed
        return slider_crank_state(np.asarray(phi, dtype=float), m.crank_length, m.rod_length, 1.0,
                                  m.guide_distance)[5]

    phi = np.linspace(0.0, 2.0 * np.pi, samples)[:-1]  # one turn, periodic
    xs = x_of(phi)

    def extreme(i, sign):
        a, b, c = sign * xs[i - 1], sign * xs[i], sign * xs[(i + 1) % xs.size]
        denominator = a - 2.0 * b + c
        shift = 0.5 * (a - c) / denominator if denominator != 0.0 else 0.0
        # the refined point, or the sample if rounding made the refinement worse
        return sign * max(sign * float(x_of(phi[i] + shift * (phi[1] - phi[0]))), b)

    return extreme(int(np.argmin(xs)), -1.0), extreme(int(np.argmax(xs)), 1.0)

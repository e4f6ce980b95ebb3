"""Prescribed rigid-body motion of the link (MODEL.md section 3, decision D2).

The beam model needs five functions of time: the true transverse
acceleration of the link end O, ``A_O2``, the link's angular velocity
``omega`` and acceleration ``alpha``, the collar position along the link
``x_star`` and its velocity relative to the link ``V_r``. A *motion* is any
object with ``__call__(t) -> RigidMotion`` and ``joint_reaction(t, mass)``.

Providers:

* :class:`SliderCrank`: the paper's Section 6 mechanism (closed forms).
* :class:`PrescribedMotion`: user callables.
* :func:`sampled_motion`: user samples, interpolated by cubic splines.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Callable, NamedTuple

import numpy as np

from .params import Mechanism

__all__ = [
    "RigidMotion",
    "slider_crank",
    "SliderCrank",
    "PrescribedMotion",
    "sampled_motion",
    "collar_travel",
]


class RigidMotion(NamedTuple):
    """Rigid motion of the link at one or more times.

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
    """

    A_O2: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray
    x_star: np.ndarray
    V_r: np.ndarray


def slider_crank(t, crank_length, rod_length, crank_speed, guide_distance):
    """Kinematics of the Section 6 slider-crank and its collar.

    The crank turns anticlockwise about the fixed pivot at the origin with
    ``phi = omega0 t``; O is the crank pin, the slider C runs on the +X axis,
    ``i`` points from O to C and the collar sits on the link under a vertical
    guide at ``X = a`` (MODEL.md section 3).

    Parameters
    ----------
    t : float or array_like
        Time [s].
    crank_length : float
        ``OA`` [m].
    rod_length : float
        ``L`` [m].
    crank_speed : float
        ``omega0`` [rad/s].
    guide_distance : float
        ``a`` [m].

    Returns
    -------
    dict of ndarray
        ``theta`` [rad] (the link angle is ``-theta``), ``v_O1`` [m/s],
        ``A_O2`` [m/s^2], ``omega`` [rad/s], ``alpha`` [rad/s^2],
        ``x_star`` [m], ``V_r`` [m/s], ``A_r`` (``d V_r/dt``) [m/s^2] and
        ``Y_ddot``, the vertical acceleration of the collar [m/s^2].

    Notes
    -----
    ``v_O1``, ``A_O2``, ``omega`` and ``alpha`` are the paper's Section 6
    formulas; ``x_star`` and ``V_r`` follow from the guide geometry (D6).
    """
    t = np.asarray(t, dtype=float)
    OA, L, w0, a = crank_length, rod_length, crank_speed, guide_distance
    lam = OA / L
    phi = w0 * t
    sphi, cphi = np.sin(phi), np.cos(phi)
    s_th = lam * sphi
    c_th = np.sqrt(1.0 - s_th**2)
    theta = np.arcsin(s_th)
    s_sum = sphi * c_th + cphi * s_th  # sin(phi + theta)

    v_O1 = -OA * w0 * s_sum
    A_O2 = -OA * w0**2 * s_sum
    omega = -lam * w0 * cphi / c_th
    alpha = lam * w0**2 * sphi / c_th - lam**3 * w0**2 * cphi**2 * sphi / c_th**3

    theta_dot = -omega
    theta_ddot = -alpha
    x_star = (a - OA * cphi) / c_th
    V_r = (OA * w0 * sphi * c_th + (a - OA * cphi) * s_th * theta_dot) / c_th**2
    A_r = (
        OA * w0**2 * cphi
        + 2.0 * V_r * s_th * theta_dot
        + x_star * (c_th * theta_dot**2 + s_th * theta_ddot)
    ) / c_th
    lever = OA - lam * x_star  # Y = sin(phi) * lever
    Y_ddot = -(w0**2) * sphi * lever - 2.0 * lam * w0 * cphi * V_r - lam * sphi * A_r
    return {
        "theta": theta,
        "v_O1": v_O1,
        "A_O2": A_O2,
        "omega": omega,
        "alpha": alpha,
        "x_star": x_star,
        "V_r": V_r,
        "A_r": A_r,
        "Y_ddot": Y_ddot,
        "cos_theta": c_th,
    }


@dataclass(frozen=True)
class SliderCrank:
    """The paper's slider-crank as a motion provider."""

    mechanism: Mechanism

    def _kin(self, t):
        m = self.mechanism
        return slider_crank(t, m.crank_length, m.rod_length, m.crank_speed, m.guide_distance)

    def __call__(self, t) -> RigidMotion:
        k = self._kin(t)
        return RigidMotion(k["A_O2"], k["omega"], k["alpha"], k["x_star"], k["V_r"])

    def joint_reaction(self, t, mass):
        """Force of the collar on the link along +j [N] (D7).

        The collar and its guided member (mass ``m_c``) move vertically with
        the link point under the guide; the guide takes horizontal force only,
        so the link pushes the collar with ``m_c Y_ddot / cos(theta)`` along
        +j and, by reaction, is pushed with the opposite force.
        """
        if mass == 0.0:
            return np.zeros_like(np.asarray(t, dtype=float))
        k = self._kin(t)
        return -mass * k["Y_ddot"] / k["cos_theta"]

    def link_angle(self, t):
        """Angle of the link axis ``i`` about +k from +X [rad]: ``-theta``."""
        m = self.mechanism
        return -np.arcsin(m.crank_length / m.rod_length * np.sin(m.crank_speed * np.asarray(t, dtype=float)))

    @property
    def period(self) -> float:
        """Crank period [s]."""
        return 2.0 * np.pi / self.mechanism.crank_speed


@dataclass(frozen=True)
class PrescribedMotion:
    """A rigid motion given by user callables of time (each vectorised).

    Parameters
    ----------
    A_O2, omega, alpha, x_star, V_r : callable
        Functions of time [s] returning the quantities of :class:`RigidMotion`.
    reaction : callable, optional
        Force of the collar on the link along +j [N] as a function of time;
        zero if omitted.
    angle : callable, optional
        Angle of the link axis about +k from the fixed +X axis [rad], used
        only to resolve gravity; zero (horizontal link) if omitted.
    """

    A_O2: Callable
    omega: Callable
    alpha: Callable
    x_star: Callable
    V_r: Callable
    reaction: Callable | None = None
    angle: Callable | None = None

    def link_angle(self, t):
        t = np.asarray(t, dtype=float)
        return np.zeros_like(t) if self.angle is None else np.broadcast_to(np.asarray(self.angle(t), float), t.shape)

    def __call__(self, t) -> RigidMotion:
        functions = (self.A_O2, self.omega, self.alpha, self.x_star, self.V_r)
        if np.ndim(t) == 0:
            return RigidMotion(*(float(f(t)) for f in functions))
        t = np.asarray(t, dtype=float)
        return RigidMotion(*(np.broadcast_to(np.asarray(f(t), float), t.shape) for f in functions))

    def joint_reaction(self, t, mass):
        t = np.asarray(t, dtype=float)
        if self.reaction is None:
            return np.zeros_like(t)
        return np.broadcast_to(np.asarray(self.reaction(t), float), t.shape)


def sampled_motion(t, A_O2, omega, x_star, alpha=None, V_r=None, reaction=None):
    """A :class:`PrescribedMotion` from samples, by C2 cubic splines.

    ``alpha`` defaults to the spline derivative of ``omega`` and ``V_r`` to
    that of ``x_star``, so the five functions stay mutually consistent.

    Parameters
    ----------
    t : array_like
        Strictly increasing sample times [s], at least 4.
    A_O2, omega, x_star, alpha, V_r, reaction : array_like
        Samples at ``t`` in the units of :class:`RigidMotion` (reaction [N]).
    """
    from scipy.interpolate import CubicSpline

    t = np.asarray(t, dtype=float)
    if t.ndim != 1 or t.size < 4 or not np.all(np.diff(t) > 0):
        raise ValueError("sampled_motion: t must be a strictly increasing 1-D array of at least 4 times")

    def spline(name, values):
        values = np.asarray(values, dtype=float)
        if values.shape != t.shape or not np.all(np.isfinite(values)):
            raise ValueError(f"sampled_motion: {name} must be {t.size} finite samples, one per time")
        return CubicSpline(t, values)

    s_omega = spline("omega", omega)
    s_x = spline("x_star", x_star)
    return PrescribedMotion(
        A_O2=spline("A_O2", A_O2),
        omega=s_omega,
        alpha=s_omega.derivative() if alpha is None else spline("alpha", alpha),
        x_star=s_x,
        V_r=s_x.derivative() if V_r is None else spline("V_r", V_r),
        reaction=None if reaction is None else spline("reaction", reaction),
    )


@lru_cache(maxsize=4096)
def collar_travel(mechanism: Mechanism, samples: int = 4097):
    """Smallest and largest collar position over one crank turn [m].

    Sampled on a fine grid of crank angles, then polished by a bounded scalar
    minimisation around the extreme samples.
    """
    from scipy.optimize import minimize_scalar

    m = mechanism

    def x_of(phi):  # x_star depends on the crank angle only: use unit crank speed
        return slider_crank(phi, m.crank_length, m.rod_length, 1.0, m.guide_distance)["x_star"]

    period = 2.0 * np.pi
    ts = np.linspace(0.0, period, samples)
    xs = x_of(ts)
    dt = ts[1] - ts[0]
    i_lo, i_hi = int(np.argmin(xs)), int(np.argmax(xs))
    lo = minimize_scalar(lambda s: float(x_of(s)), bounds=(ts[i_lo] - dt, ts[i_lo] + dt),
                         method="bounded", options={"xatol": 1e-12})
    hi = minimize_scalar(lambda s: -float(x_of(s)), bounds=(ts[i_hi] - dt, ts[i_hi] + dt),
                         method="bounded", options={"xatol": 1e-12})
    return min(lo.fun, float(xs[i_lo])), max(-hi.fun, float(xs[i_hi]))

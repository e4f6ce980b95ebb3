"""The spatial slider-crank (RSSP) as a motion provider of the spatial model (docs/spatial.md).

The mechanism is the planar one of ``[mechanism]`` (crank ``OA``, link ``L``, crank speed
``omega0``, guide plane ``X = a``) with two keys that take it out of its plane:

* ``crank_tilt`` ``tau`` [rad]: the crank axis is ``k = (0, -sin tau, cos tau)``, the planar
  ``Z`` axis turned by ``tau`` about the slider line ``X``; the crank pin moves on
  ``O = OA (cos phi, sin phi cos tau, sin phi sin tau)``, ``phi = omega0 t``;
* ``slider_offset`` ``z_P`` [m]: the slider runs on the line ``(s, 0, z_P)``.

Both 0: the planar slider-crank, whose kinematics :func:`lubelink.spatial.slider_crank_rssp`
then reproduces (tests/test_spatial.py). :class:`SpatialMotion` is the table compiled code
reads, :func:`spatial_motion_at` the rigid motion at a time, :class:`SpatialSliderCrank` the
provider the spatial model and its results use, :func:`travel_problems` the validation of a
geometry over one crank turn.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ._jit import jitable
from .spatial import _dot, _frame, rssp_tuples

__all__ = ["SpatialMotion", "spatial_motion_at", "collar_acceleration_at", "SpatialSliderCrank", "geometry",
           "travel_problems"]


class SpatialMotion(NamedTuple):
    """The RSSP slider-crank in the form compiled code evaluates (:func:`spatial_motion_at`).

    Lengths [m], ``crank_speed`` [rad/s], ``guide`` the guide plane ``d . p = guide`` [m];
    ``crank_axis``, ``crank_ref`` (unit, normal to the axis), ``slider_dir`` unit 3-vectors [-],
    ``slider_point`` [m] (fixed frame).
    """

    crank_length: float
    rod_length: float
    crank_speed: float
    guide: float
    crank_axis: np.ndarray
    crank_ref: np.ndarray
    slider_point: np.ndarray
    slider_dir: np.ndarray


def geometry(mechanism) -> SpatialMotion:
    """The :class:`SpatialMotion` of a ``[mechanism]`` section (module docstring)."""
    m = mechanism
    tau = float(m.crank_tilt)
    return SpatialMotion(float(m.crank_length), float(m.rod_length), float(m.crank_speed), float(m.guide_distance),
                         np.array([0.0, -np.sin(tau), np.cos(tau)]), np.array([1.0, 0.0, 0.0]),
                         np.array([0.0, 0.0, float(m.slider_offset)]), np.array([1.0, 0.0, 0.0]))


@jitable
def spatial_motion_at(t, m):
    """Rigid motion of the link at ``t`` [s] for the table ``m``: :func:`~lubelink.spatial.slider_crank_rssp`.

    Returns ``(A_O, w, alpha, v_O, x_star, V_r, O, e1, e2, e3)``: link-frame components of the
    true acceleration [m/s^2] and velocity [m/s] of O, angular velocity [rad/s] and acceleration
    [rad/s^2]; collar position [m] and velocity along the link [m/s]; O [m] and the frame
    vectors in fixed components. The vectors are 3-tuples of floats (nothing is allocated per call).
    """
    return rssp_tuples(t, m.crank_length, m.rod_length, m.crank_speed, m.guide, m.crank_axis, m.crank_ref,
                       m.slider_point, m.slider_dir)


@jitable
def collar_acceleration_at(t, m):
    """``A_r = dV_r/dt`` [m/s^2], the collar's acceleration along the link, of the table ``m`` at ``t`` [s].

    The collar is where the link crosses the guide plane, ``x_star = num / den`` with
    ``num = guide - d . O``, ``den = d . e1``; with ``e1_t = w x e1`` and
    ``e1_tt = alpha x e1 + w x (w x e1)`` (link-frame components ``(0, w3, -w2)`` and
    ``(-(w2^2 + w3^2), alpha3 + w1 w2, w1 w3 - alpha2)``) and ``O_tt = A_O``, the second
    derivative is ``A_r = (num_tt - x_star den_tt - 2 V_r den_t) / den``.
    """
    A_O, w, al, v_O, x_star, V_r, O, e1, e2, e3 = spatial_motion_at(t, m)
    d = _frame(m.slider_dir, e1, e2, e3)  # the guide plane's normal in link-frame components
    den_t = d[1] * w[2] - d[2] * w[1]
    den_tt = (-d[0] * (w[1] * w[1] + w[2] * w[2]) + d[1] * (al[2] + w[0] * w[1]) + d[2] * (w[0] * w[2] - al[1]))
    return (-_dot(d, A_O) - x_star * den_tt - 2.0 * V_r * den_t) / d[0]


class Kinematics(NamedTuple):
    """Samples of the spatial rigid motion (arrays over time): what the results read."""

    A_O: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray
    x_star: np.ndarray
    V_r: np.ndarray


@dataclass(frozen=True)
class SpatialSliderCrank:
    """The RSSP slider-crank of a ``[mechanism]`` section as the spatial model's motion provider."""

    mechanism: object

    def table(self, collar_mass=0.0) -> SpatialMotion:
        """The :class:`SpatialMotion` compiled code reads (``collar_mass`` unused: refused by the validation)."""
        return geometry(self.mechanism)

    def at(self, t):
        """The tuple of :func:`spatial_motion_at` at one time ``t`` [s]."""
        return spatial_motion_at(float(t), self.table())

    def __call__(self, t) -> Kinematics:
        """:class:`Kinematics` at the times ``t`` [s] (``A_O``, ``omega``, ``alpha`` shape ``(T, 3)``)."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        m = self.table()
        rows = [spatial_motion_at(float(ti), m) for ti in t]
        return Kinematics(np.array([r[0] for r in rows]).reshape(-1, 3), np.array([r[1] for r in rows]).reshape(-1, 3),
                          np.array([r[2] for r in rows]).reshape(-1, 3), np.array([r[4] for r in rows]),
                          np.array([r[5] for r in rows]))


def travel_problems(mechanism, pad_length, pad_reference, samples=721):
    """Messages for a geometry that cannot turn or whose pad leaves the link over a crank turn (empty: fine).

    Over ``samples`` crank angles: the slider must reach the link (``|C - O| = L`` has a root),
    the link must cross the guide plane at a finite angle, and the pad (``film.pad_length``,
    ``pad_reference``) must stay inside ``(0, L)``.
    """
    g = geometry(mechanism)._replace(crank_speed=1.0)
    x = []
    with np.errstate(invalid="ignore", divide="ignore"):
        for phi in np.linspace(0.0, 2.0 * np.pi, samples):
            try:
                r = spatial_motion_at(phi, g)
            except ZeroDivisionError:  # plain floats: the link normal to the slider line or in the guide plane
                x.append(np.nan)
                continue
            x.append(r[4] if np.all(np.isfinite(r[0])) and np.isfinite(r[5]) else np.nan)
    x = np.array(x)
    m = mechanism
    where = (f"mechanism.crank_tilt = {m.crank_tilt}, mechanism.slider_offset = {m.slider_offset} "
             f"(beam.model = 'spatial')")
    if not np.all(np.isfinite(x)):
        return [f"{where}: the link (mechanism.rod_length = {m.rod_length}) cannot reach the slider line over "
                "a crank turn, or lies in the guide plane; reduce the tilt or the offset"]
    start = -0.5 * pad_length if pad_reference == "centre" else 0.0
    first, last = x.min() + start, x.max() + start + pad_length
    if not (first > 0.0 and last < m.rod_length):
        return [f"{where}, mechanism.guide_distance = {m.guide_distance}: the collar pad (film.pad_length = "
                f"{pad_length}) spans [{first:.4g}, {last:.4g}] m along the rod over a crank turn; it must stay "
                f"inside (0, {m.rod_length}) m"]
    return []

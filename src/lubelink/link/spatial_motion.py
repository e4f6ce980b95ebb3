"""The spatial slider-crank (RSSP) as a motion provider of the spatial model (docs/spatial.md).

The mechanism is the planar one of ``[mechanism]`` (crank ``OA``, link ``L``, crank speed
``omega0``, guide plane ``X = a``) with two keys that take it out of its plane:

* ``crank_tilt`` ``tau`` [rad]: the crank axis is ``k = (0, -sin tau, cos tau)``, the planar
  ``Z`` axis turned by ``tau`` about the slider line ``X``; the crank pin moves on
  ``O = OA (cos phi, sin phi cos tau, sin phi sin tau)``, ``phi = omega0 t``;
* ``slider_offset`` ``z_P`` [m]: the slider runs on the line ``(s, 0, z_P)``.

Both 0: the planar slider-crank, whose kinematics :func:`lubelink.link.spatial.slider_crank_rssp`
then reproduces (tests/test_spatial.py). :class:`SpatialMotion` is the table compiled code
reads, :func:`spatial_motion_at` the rigid motion at a time, :class:`SpatialSliderCrank` the
provider the spatial model and its results use, :func:`travel_problems` the validation of a
geometry over one crank turn.

A motion of the user's (docs/spatial.md, "A motion of your own") replaces the slider-crank:
:class:`SpatialPrescribedMotion` from callables of time (run by the ``numpy`` backend, like the
planar :class:`lubelink.link.kinematics.PrescribedMotion`), or :func:`sampled_spatial_motion` from
samples, C2 cubic splines in the same :class:`SpatialMotion` table (``knots``, ``coef``), so that
the one :func:`spatial_motion_at` serves both and the run is compiled.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from .._jit import jitable
from .kinematics import cubic_piece, knot_interval
from .spatial import SpatialRigidMotion, _cross, _dot, _frame, rssp_tuples

__all__ = ["SpatialMotion", "spatial_motion_at", "collar_acceleration_at", "SpatialSliderCrank", "geometry",
           "travel_problems", "SpatialPrescribedMotion", "SampledSpatialMotion", "sampled_spatial_motion", "CHANNELS"]

#: Rows of ``SpatialMotion.coef`` of a sampled motion: the link-frame components of ``A_O``
#: [m/s^2], ``w`` [rad/s], ``alpha`` [rad/s^2]; ``x_star`` [m], ``V_r`` [m/s]; the fixed-frame
#: components of ``e1``, ``e2`` [-].
CHANNELS = ("A_O1", "A_O2", "A_O3", "w1", "w2", "w3", "alpha1", "alpha2", "alpha3", "x_star", "V_r",
            "e1_X", "e1_Y", "e1_Z", "e2_X", "e2_Y", "e2_Z")


class SpatialMotion(NamedTuple):
    """The spatial rigid motion in the form compiled code evaluates (:func:`spatial_motion_at`).

    The RSSP slider-crank (``knots``, ``coef`` None): lengths [m], ``crank_speed`` [rad/s],
    ``guide`` the guide plane ``d . p = guide`` [m]; ``crank_axis``, ``crank_ref`` (unit, normal to
    the axis), ``slider_dir`` unit 3-vectors [-], ``slider_point`` [m] (fixed frame). A sampled
    motion (:func:`sampled_spatial_motion`): ``knots`` [s] and ``coef``, shape ``(17, 4,
    knots.size - 1)``, the cubic pieces of each of :data:`CHANNELS` (``scipy.interpolate.PPoly``
    layout); the slider-crank's fields are then unused.
    """

    crank_length: float
    rod_length: float
    crank_speed: float
    guide: float
    crank_axis: np.ndarray
    crank_ref: np.ndarray
    slider_point: np.ndarray
    slider_dir: np.ndarray
    knots: np.ndarray | None = None
    coef: np.ndarray | None = None


def geometry(mechanism) -> SpatialMotion:
    """The :class:`SpatialMotion` of a ``[mechanism]`` section (module docstring)."""
    m = mechanism
    tau = float(m.crank_tilt)
    return SpatialMotion(float(m.crank_length), float(m.rod_length), float(m.crank_speed), float(m.guide_distance),
                         np.array([0.0, -np.sin(tau), np.cos(tau)]), np.array([1.0, 0.0, 0.0]),
                         np.array([0.0, 0.0, float(m.slider_offset)]), np.array([1.0, 0.0, 0.0]))


@jitable
def spatial_motion_at(t, m):
    """Rigid motion of the link at ``t`` [s] for the table ``m``: :func:`~lubelink.link.spatial.slider_crank_rssp`,
    or the splines of a sampled motion (:func:`sampled_tuples`).

    Returns a :class:`~lubelink.link.spatial.SpatialRigidMotion` whose vectors are 3-tuples of floats
    (nothing is allocated per call).
    """
    return _spatial_motion(t, m, m.knots, m.coef)


@jitable
def _spatial_motion(t, m, knots, coef):
    """:func:`spatial_motion_at` with the spline tables as arguments (None: the slider-crank, compiled alone)."""
    if knots is None:
        return rssp_tuples(t, m.crank_length, m.rod_length, m.crank_speed, m.guide, m.crank_axis, m.crank_ref,
                           m.slider_point, m.slider_dir)
    return sampled_tuples(t, knots, coef)


@jitable
def sampled_tuples(t, knots, coef):
    """The tuple of :func:`spatial_motion_at` from the cubic pieces ``coef`` of :data:`CHANNELS` at ``t`` [s].

    ``e3 = e1 x e2``; ``v_O`` and ``O`` (which the model does not use) are NaN.
    """
    i, dx = knot_interval(t, knots)
    A_O = (cubic_piece(coef, 0, i, dx), cubic_piece(coef, 1, i, dx), cubic_piece(coef, 2, i, dx))
    w = (cubic_piece(coef, 3, i, dx), cubic_piece(coef, 4, i, dx), cubic_piece(coef, 5, i, dx))
    alpha = (cubic_piece(coef, 6, i, dx), cubic_piece(coef, 7, i, dx), cubic_piece(coef, 8, i, dx))
    e1 = (cubic_piece(coef, 11, i, dx), cubic_piece(coef, 12, i, dx), cubic_piece(coef, 13, i, dx))
    e2 = (cubic_piece(coef, 14, i, dx), cubic_piece(coef, 15, i, dx), cubic_piece(coef, 16, i, dx))
    nan3 = (np.nan, np.nan, np.nan)
    return SpatialRigidMotion(A_O, w, alpha, cubic_piece(coef, 9, i, dx), cubic_piece(coef, 10, i, dx), e1, e2,
                              _cross(e1, e2), nan3, nan3)


@jitable
def collar_acceleration_at(t, m):
    """``A_r = dV_r/dt`` [m/s^2], the collar's acceleration along the link, of the table ``m`` at ``t`` [s].

    The slider-crank: the collar is where the link crosses the guide plane, ``x_star = num / den``
    with ``num = guide - d . O``, ``den = d . e1``; with ``e1_t = w x e1`` and
    ``e1_tt = alpha x e1 + w x (w x e1)`` (link-frame components ``(0, w3, -w2)`` and
    ``(-(w2^2 + w3^2), alpha3 + w1 w2, w1 w3 - alpha2)``) and ``O_tt = A_O``, the second
    derivative is ``A_r = (num_tt - x_star den_tt - 2 V_r den_t) / den``. A sampled motion: the
    derivative of the ``V_r`` spline.
    """
    return _collar_acceleration(t, m, m.knots, m.coef)


@jitable
def _collar_acceleration(t, m, knots, coef):
    """:func:`collar_acceleration_at` with the spline tables as arguments (None: the slider-crank, compiled alone)."""
    if knots is not None:
        i, dx = knot_interval(t, knots)
        c = 10  # the row of V_r in CHANNELS
        return (3.0 * coef[c, 0, i] * dx + 2.0 * coef[c, 1, i]) * dx + coef[c, 2, i]
    k = spatial_motion_at(t, m)
    A_O, w, al, x_star, V_r = k.A_O, k.omega, k.alpha, k.x_star, k.V_r
    d = _frame(m.slider_dir, k.e1, k.e2, k.e3)  # the guide plane's normal in link-frame components
    den_t = d[1] * w[2] - d[2] * w[1]
    den_tt = (-d[0] * (w[1] * w[1] + w[2] * w[2]) + d[1] * (al[2] + w[0] * w[1]) + d[2] * (w[0] * w[2] - al[1]))
    return (-_dot(d, A_O) - x_star * den_tt - 2.0 * V_r * den_t) / d[0]


def _samples(rows) -> SpatialRigidMotion:
    """The :class:`~lubelink.link.spatial.SpatialRigidMotion` of ``rows`` (one per time) as arrays over time
    (vectors shape ``(T, 3)``)."""
    return SpatialRigidMotion(*(np.array(column, dtype=float) for column in zip(*rows)))


@dataclass(frozen=True)
class SpatialSliderCrank:
    """The RSSP slider-crank of a ``[mechanism]`` section as the spatial model's motion provider."""

    mechanism: object

    def table(self, collar_mass=0.0) -> SpatialMotion:
        """The :class:`SpatialMotion` compiled code reads (``collar_mass`` unused: refused by the validation)."""
        return geometry(self.mechanism)

    def at(self, t):
        """The :class:`~lubelink.link.spatial.SpatialRigidMotion` of :func:`spatial_motion_at` at one time ``t`` [s]."""
        return spatial_motion_at(float(t), self.table())

    def __call__(self, t) -> SpatialRigidMotion:
        """The rigid motion at the times ``t`` [s] as arrays over time (vectors shape ``(T, 3)``)."""
        m = self.table()
        return _samples([spatial_motion_at(float(ti), m) for ti in np.atleast_1d(np.asarray(t, dtype=float))])


@lru_cache(maxsize=4096)
def collar_travel(mechanism, samples=721):
    """Smallest and largest collar position over a crank turn [m] (NaN: the link cannot reach the
    slider line, or lies in the guide plane, somewhere in the turn), at ``samples`` crank angles.

    Remembered by the mechanism (as :func:`lubelink.link.kinematics.collar_travel`): a sweep validates
    each point more than once.
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
            x.append(r.x_star if np.all(np.isfinite(r.A_O)) and np.isfinite(r.V_r) else np.nan)
    x = np.array(x)
    if not np.all(np.isfinite(x)):
        return np.nan, np.nan
    return float(x.min()), float(x.max())


def travel_problems(mechanism, pad_length, pad_reference, samples=721):
    """Messages for a geometry that cannot turn or whose pad leaves the link over a crank turn (empty: fine).

    Over ``samples`` crank angles (:func:`collar_travel`): the slider must reach the link
    (``|C - O| = L`` has a root), the link must cross the guide plane at a finite angle, and the pad
    (``film.pad_length``, ``pad_reference``) must stay inside ``(0, L)``.
    """
    x_min, x_max = collar_travel(mechanism, samples)
    m = mechanism
    where = (f"mechanism.crank_tilt = {m.crank_tilt}, mechanism.slider_offset = {m.slider_offset} "
             f"(beam.model = 'spatial')")
    if not np.isfinite(x_min):
        return [f"{where}: the link (mechanism.rod_length = {m.rod_length}) cannot reach the slider line over "
                "a crank turn, or lies in the guide plane; reduce the tilt or the offset"]
    problem = _pad_problem(x_min, x_max, pad_length, pad_reference, m.rod_length)
    return [f"{where}, mechanism.guide_distance = {m.guide_distance}: {problem} over a crank turn"] if problem else []


def _pad_problem(x_min, x_max, pad_length, pad_reference, rod_length):
    """Why a collar travelling over ``[x_min, x_max]`` [m] puts its pad off the link, or ''."""
    start = -0.5 * pad_length if pad_reference == "centre" else 0.0
    first, last = x_min + start, x_max + start + pad_length
    if first > 0.0 and last < rod_length:
        return ""
    return (f"the collar pad (film.pad_length = {pad_length}) spans [{first:.4g}, {last:.4g}] m along the rod; "
            f"it must stay inside (0, {rod_length}) m")


# ----------------------------------------------------------------------------------- a motion of the user's
def _vector(value, what):
    """``value`` as a 3-tuple of finite floats, or ValueError naming ``what`` (the fast path: plain floats)."""
    try:
        if np.ndim(value) != 1:
            raise ValueError
        x, y, z = value
        v = (float(x), float(y), float(z))
    except (TypeError, ValueError):
        raise ValueError(f"{what}: must be 3 finite numbers (shape (3,)), got shape {np.shape(value)}") from None
    if not (math.isfinite(v[0]) and math.isfinite(v[1]) and math.isfinite(v[2])):
        raise ValueError(f"{what}: must be 3 finite numbers, got {list(v)}")
    return v


def _scalar(value, what):
    try:
        v = float(value) if np.ndim(value) == 0 else None
    except (TypeError, ValueError):
        v = None
    if v is None:
        raise ValueError(f"{what}: must be one number, got shape {np.shape(value)}")
    if not math.isfinite(v):
        raise ValueError(f"{what}: must be finite, got {v}")
    return v


def _check_frame(e1, e2, what):
    """ValueError unless ``e1``, ``e2`` (3-vectors, or rows of them) are orthonormal to 1e-6."""
    e1, e2 = np.asarray(e1, dtype=float), np.asarray(e2, dtype=float)
    n1, n2, c = np.linalg.norm(e1, axis=-1), np.linalg.norm(e2, axis=-1), np.sum(e1 * e2, axis=-1)
    bad = np.abs(n1 - 1.0) + np.abs(n2 - 1.0) + np.abs(c)
    if np.any(bad > 1e-6):
        k = int(np.argmax(bad))
        raise ValueError(f"{what}: e1 and e2 must be orthonormal (to 1e-6); got |e1| = {np.ravel(n1)[k]:.9g}, "
                         f"|e2| = {np.ravel(n2)[k]:.9g}, e1 . e2 = {np.ravel(c)[k]:.3g}")


def _orthonormal(e1, e2):
    """Whether the 3-tuples ``e1``, ``e2`` are orthonormal to 1e-6 (plain floats: per call of a motion)."""
    return (abs(_dot(e1, e1) - 1.0) < 2e-6 and abs(_dot(e2, e2) - 1.0) < 2e-6 and abs(_dot(e1, e2)) < 1e-6)


_X, _Y = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)
_NAN3 = (np.nan, np.nan, np.nan)


@dataclass(frozen=True, eq=False)
class SpatialPrescribedMotion:
    """A spatial rigid motion from callables of time (or constants); runs on the ``numpy`` backend.

    Each argument is a callable of one time ``t`` [s] (a float) or a constant. All vectors are
    3-vectors; the kinematic ones in link-frame components, as the model uses them
    (docs/spatial.md, "Kinematics of a material point").

    Parameters
    ----------
    A_O : callable or 3 numbers
        True (inertial) acceleration of the link end O, in link-frame components [m/s^2]: the
        components on ``e1, e2, e3`` of ``d^2 O / dt^2`` (not the derivative of the components of
        the velocity).
    omega, alpha : callable or 3 numbers
        Angular velocity [rad/s] and acceleration [rad/s^2] of the link frame, its components
        (``alpha`` is the derivative of the components ``omega``).
    x_star, V_r : callable or number
        Collar position along the link from O [m] and its velocity along ``e1`` relative to the
        link [m/s] (``V_r = dx_star/dt``).
    e1, e2 : callable or 3 numbers, optional
        The link axis and the in-plane bending direction in fixed-frame components [-]
        (orthonormal), used only to resolve ``mechanism.gravity`` on the link frame; default the
        fixed axes ``X``, ``Y``.
    """

    A_O: object
    omega: object
    alpha: object
    x_star: object
    V_r: object
    e1: object = None
    e2: object = None

    #: What the backend's note suggests for a motion that cannot be compiled.
    compile_hint = "lubelink.link.spatial_motion.sampled_spatial_motion"

    def __post_init__(self):
        self.at(0.0)  # every value's shape and finiteness, the frame's orthonormality: at t = 0

    def _get(self, name, t):
        f = getattr(self, name)
        return f(t) if callable(f) else f

    def table(self, collar_mass=0.0):
        """None: Python callables cannot be compiled (see :func:`sampled_spatial_motion`)."""
        return None

    def at(self, t):
        """The :class:`~lubelink.link.spatial.SpatialRigidMotion` at one time ``t`` [s], from the callables (``v_O``,
        ``O`` NaN)."""
        t = float(t)
        where = f"SpatialPrescribedMotion at t = {t:g} s"
        vec = {name: _vector(self._get(name, t), f"{where}: {name}") for name in ("A_O", "omega", "alpha")}
        e1 = _X if self.e1 is None else _vector(self._get("e1", t), f"{where}: e1")
        e2 = _Y if self.e2 is None else _vector(self._get("e2", t), f"{where}: e2")
        if (self.e1 is not None or self.e2 is not None) and not _orthonormal(e1, e2):
            _check_frame(e1, e2, where)
        return SpatialRigidMotion(vec["A_O"], vec["omega"], vec["alpha"],
                                  _scalar(self._get("x_star", t), f"{where}: x_star"),
                                  _scalar(self._get("V_r", t), f"{where}: V_r"), e1, e2, _cross(e1, e2), _NAN3, _NAN3)

    def __call__(self, t) -> SpatialRigidMotion:
        """The rigid motion at the times ``t`` [s] as arrays over time (vectors shape ``(T, 3)``)."""
        return _samples([self.at(ti) for ti in np.atleast_1d(np.asarray(t, dtype=float))])


@dataclass(frozen=True, eq=False)
class SampledSpatialMotion(SpatialPrescribedMotion):
    """A spatial motion from samples (:func:`sampled_spatial_motion`): a compiled :class:`SpatialMotion` table."""

    knots: np.ndarray | None = None
    coef: np.ndarray | None = None

    def __post_init__(self):
        pass

    def table(self, collar_mass=0.0) -> SpatialMotion:
        z = np.zeros(3)
        return SpatialMotion(0.0, 1.0, 0.0, 0.0, z, z, z, z, self.knots, self.coef)

    def at(self, t):
        return spatial_motion_at(float(t), self.table())

    @property
    def span(self):
        """``(first, last)`` sample time [s]."""
        return float(self.knots[0]), float(self.knots[-1])


def sampled_spatial_motion(t, A_O, omega, x_star, alpha=None, V_r=None, e1=None, e2=None) -> SampledSpatialMotion:
    """A spatial motion from samples, interpolated by C2 cubic splines (not-a-knot ends); it runs compiled.

    ``alpha`` defaults to the spline derivative of ``omega`` and ``V_r`` to that of ``x_star``, so
    the motion stays consistent. Accuracy for a smooth motion sampled every ``h``: the values
    ``O(h^4)``, the derivatives ``alpha``, ``V_r`` taken from the splines ``O(h^3)``
    (tests/test_spatial_motion.py measures both orders on the run). The run must lie inside the
    samples (``t[0] <= 0``, ``t[-1] >= solver.t_end``: no extrapolation).

    Parameters
    ----------
    t : array_like, shape ``(T,)``
        Strictly increasing sample times [s], at least 4.
    A_O, omega, alpha : array_like, shape ``(T, 3)``
        As :class:`SpatialPrescribedMotion`, one row per time [m/s^2, rad/s, rad/s^2].
    x_star, V_r : array_like, shape ``(T,)``
        Collar position [m] and velocity along the link [m/s].
    e1, e2 : array_like, shape ``(T, 3)`` or ``(3,)``, optional
        The link frame in fixed components [-] (orthonormal), for gravity; a ``(3,)`` is constant;
        default the fixed axes ``X``, ``Y``.
    """
    from scipy.interpolate import CubicSpline

    t = np.asarray(t, dtype=float)
    if t.ndim != 1 or t.size < 4 or not np.all(np.isfinite(t)) or not np.all(np.diff(t) > 0):
        raise ValueError(f"sampled_spatial_motion: t must be a 1-D array of at least 4 finite, strictly increasing "
                         f"times [s]; got shape {t.shape}"
                         + ("" if t.ndim != 1 or t.size < 4 or not np.all(np.isfinite(t))
                            else f", not increasing after t = {t[np.argmax(np.diff(t) <= 0)]:g} s")
                         + ("" if t.ndim != 1 or np.all(np.isfinite(t)) else ", with non-finite times"))

    def samples(name, values, width):
        shape = (t.size,) if width == 1 else (t.size, 3)
        a = np.asarray(values, dtype=float)
        if width == 3 and a.shape == (3,) and name in ("e1", "e2"):
            a = np.broadcast_to(a, shape)
        if a.shape != shape:
            raise ValueError(f"sampled_spatial_motion: {name} must have shape {shape} (one "
                             f"{'value' if width == 1 else 'row of 3'} per time of t), got {a.shape}")
        if not np.all(np.isfinite(a)):
            k = int(np.argmax(~np.isfinite(a).reshape(t.size, -1).all(axis=1)))
            raise ValueError(f"sampled_spatial_motion: {name} must be finite; not at t = {t[k]:g} s (sample {k})")
        return a

    def spline(name, values, width=3):
        return CubicSpline(t, samples(name, values, width), axis=0)

    s_omega, s_x = spline("omega", omega), spline("x_star", x_star, 1)
    f1 = samples("e1", _X if e1 is None else e1, 3)
    f2 = samples("e2", _Y if e2 is None else e2, 3)
    _check_frame(f1, f2, "sampled_spatial_motion")
    parts = [spline("A_O", A_O), s_omega, s_omega.derivative() if alpha is None else spline("alpha", alpha),
             s_x, s_x.derivative() if V_r is None else spline("V_r", V_r, 1),
             CubicSpline(t, f1, axis=0), CubicSpline(t, f2, axis=0)]
    rows = []
    for s_ in parts:  # PPoly coefficients (k, pieces[, 3]) -> rows of (4, pieces), padded to cubics
        c = s_.c.reshape(s_.c.shape[0], s_.c.shape[1], -1)
        for j in range(c.shape[2]):
            row = np.zeros((4, t.size - 1))
            row[4 - c.shape[0]:] = c[:, :, j]
            rows.append(row)
    coef = np.ascontiguousarray(np.array(rows))
    assert coef.shape[0] == len(CHANNELS)
    return SampledSpatialMotion(A_O=None, omega=None, alpha=None, x_star=None, V_r=None, knots=t.copy(), coef=coef)


def motion_problems(motion, config):
    """Messages for a motion the spatial model cannot run under ``config`` (empty: fine).

    It must be a spatial provider; a sampled one must cover the run ``[0, solver.t_end]``; the
    collar pad must stay on the link at the output times (and the knots inside the run).
    """
    if not isinstance(motion, (SpatialPrescribedMotion, SpatialSliderCrank)):
        return [f"motion = {type(motion).__name__}: beam.model = 'spatial' needs a spatial motion "
                "(lubelink.link.spatial_motion.SpatialPrescribedMotion or sampled_spatial_motion); a planar one "
                "(lubelink.link.kinematics) drives beam.model = 'planar'"]
    if isinstance(motion, SpatialSliderCrank):
        return []
    from ..params import sample_times

    s = config.solver
    t = sample_times(s)
    if isinstance(motion, SampledSpatialMotion):
        first, last = motion.span
        if first > 0.0 or last < s.t_end:
            return [f"motion: the samples span [{first:g}, {last:g}] s; the run [0, solver.t_end = {s.t_end:g}] s "
                    f"must lie inside them (give samples from t <= 0 to t >= {s.t_end:g} s, or shorten "
                    "solver.t_end)"]
        t = np.union1d(t, motion.knots[(motion.knots >= 0.0) & (motion.knots <= s.t_end)])
    x = motion(t).x_star
    fm, L = config.film, config.mechanism.rod_length
    problem = _pad_problem(float(x.min()), float(x.max()), fm.pad_length, fm.pad_reference, L)
    return [f"motion: x_star spans [{x.min():.4g}, {x.max():.4g}] m over the run, so {problem}"] if problem else []

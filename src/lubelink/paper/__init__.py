"""Reproduction of the paper's Section 6 results (Figs. 6-9), modal convergence and errata.

Orchestration only: this module runs the simulations (each configuration
once, see :class:`Study`), calibrates the clearance of the impact scenario
(:func:`calibrate_clearance`), and hands the results to the pure plotting
functions of :mod:`lubelink.plots`. It also holds the "as printed" variants
of the equations used to show what the errata change (:func:`simulate_variant`)
and the ``lubelink figures`` / ``lubelink animate`` commands.

Heavy libraries (Matplotlib, xarray, SciPy) are imported inside functions so
that importing this module (which ``lubelink --help`` does) stays cheap.

Paper: Marghitu & Guran, "The Dynamics of a Flexible Beam With a Lubricated
Prismatic Kinematic Pair", J. Vibration and Acoustics, Section 6.
"""

from __future__ import annotations

import json
import logging
import math
import os
import tempfile
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from .. import beam
from ..model import Model

__all__ = [
    "PAPER_IMPACT_TIME",
    "FIGURES",
    "VARIANTS",
    "Calibration",
    "Study",
    "first_impact_time",
    "calibrate_clearance",
    "calibrate_impact",
    "first_impact_map",
    "simulate_variant",
    "lubrication_effect",
    "lubrication_table",
    "FigureSet",
    "make_figures",
    "animate",
    "register_cli",
]

log = logging.getLogger(__name__)

#: First-impact time of the paper's Fig. 9 [s].
PAPER_IMPACT_TIME = 1.273

#: Figures written by :func:`make_figures`, in order, with their file stems.
FIGURES = {
    "fig6": "fig6-deflection-surface",
    "fig7": "fig7-lubrication",
    "fig8": "fig8-pressure",
    "fig9": "fig9-impact",
    "impact-map": "fig9-first-impact-map",
    "modes": "modal-convergence",
    "errata": "errata",
    "lubrication": "lubrication-effect",
}

#: Variants of the equations of motion (:func:`simulate_variant`).
VARIANTS = {
    "corrected": "corrected equations (lubelink)",
    "printed-omega2": "Eq. 18 as printed: +omega^2 q_n (stiffening)",
    "double-count": "Eq. 18 as printed: A_O2 + omega v_O1 (omega v_O1 counted twice)",
    "printed": "Eq. 18 as printed: both of the above",
    "printed-film-sign": "Eq. 20 as printed: film force +B p_g (gauge)",
}

#: Settings of the full-resolution and low-resolution figure sets.
RESOLUTIONS = {
    "full": {
        "overrides": {"solver.output_step": 1e-3},
        "dpi": 150,
        "modes": (1, 3, 5, 7),
        "modes_overrides": {"solver.rtol": 1e-7, "solver.atol": 1e-11},
        "lubrication": {"viscosities": (0.01, 0.1, 1.0), "clearances": (3e-3, 6e-3)},
        "calibration": {"span": 0.01, "points": 9, "xtol": 1e-10, "max_brackets": 3},
        "impact_map": {"viscosities": (2.5e-3, 5e-3, 0.01, 0.015, 0.02),
                       "clearances": tuple(np.round(np.arange(1.0e-3, 5.0001e-3, 0.05e-3), 8))},
    },
    "low": {
        "overrides": {"solver.t_end": 1.0, "solver.output_step": 5e-3, "solver.rtol": 1e-6,
                      "solver.atol": 1e-10, "output.x_points": 21, "output.pad_points": 11,
                      "film.quadrature_nodes": 16},
        "dpi": 60,
        "modes": (1, 3, 5, 7),
        "modes_overrides": {"solver.t_end": 0.3},
        "lubrication": {"viscosities": (0.1,), "clearances": (6e-3,)},
        "calibration": {"span": 0.004, "points": 3, "xtol": 1e-8, "max_brackets": 1},
        "impact_map": {"viscosities": (0.015,), "clearances": (1.3e-3, 3e-3)},
    },
}


# ----------------------------------------------------------------- first impact and calibration
def first_impact_time(config, t_stop=None, motion=None):
    """Time of the first film breakdown (the first impact) of a configuration [s].

    Integrates from zero initial conditions until the thinnest film on the pad
    reaches ``contact.min_film`` (the event the impact law acts on, located by
    root finding on the dense output) or ``t_stop``.

    Parameters
    ----------
    config : lubelink.Config
        Validated configuration (its contact law does not matter: the run
        stops at the first breakdown).
    t_stop : float, optional
        Last time searched [s]; default ``solver.t_end``.
    motion : object, optional
        Motion provider replacing the slider-crank.

    Returns
    -------
    float
        First breakdown time [s], ``inf`` if none up to ``t_stop``.

    Raises
    ------
    RuntimeError
        If the solver fails.
    """
    from ..model import build_model
    from ..simulate import segment_integrator

    model = build_model(config, motion)
    t_stop = config.solver.t_end if t_stop is None else float(t_stop)
    segment = segment_integrator(model)  # the integrator lubelink.simulate uses for this configuration
    seg = segment(0.0, model.initial_state(), t_stop, np.array([t_stop]), phase=None, event_sign=-1,
                  event_resolution=_event_resolution(model), deadline=None, progress=None)
    if seg.status == "event":
        return float(seg.t_final)
    if seg.status == "finished":
        return math.inf
    raise RuntimeError(seg.message)


def _event_resolution(model):
    """Gap sampling interval inside a step [s], as :func:`lubelink.simulate.run` sets it."""
    return 2.0 * np.pi / model.omega_n[-1] / 8.0


@dataclass(frozen=True)
class Calibration:
    """Outcome of :func:`calibrate_clearance`.

    Attributes
    ----------
    target : float
        Wanted first-impact time [s].
    clearance : float
        Recommended clearance ``H`` [m]: a root of ``t1(H) = target`` if one
        was found, else the clearance whose first impact is closest to target.
    first_impact : float
        First-impact time at ``clearance`` [s] (``inf``: none before ``t_stop``).
    reached : bool
        Whether ``|first_impact - target| <= tolerance``.
    tolerance : float
        Time tolerance of ``reached`` [s].
    viscosity : float
        Film viscosity of the configuration searched [Pa s].
    bracket : tuple of float
        Final clearance bracket around the sign change of ``t1(H) - target`` [m].
    bracket_times : tuple of float
        First-impact times at the bracket ends [s]; when they differ by more
        than ``tolerance`` the sign change is a jump of ``t1(H)``, not a root.
    evaluations : tuple of (float, float)
        Every ``(H [m], t1 [s])`` computed, in order.
    t_stop : float
        Last time searched in each run [s].
    config : str
        TOML of the configuration searched (without the clearance).
    message : str
        One sentence on the outcome.
    """

    target: float
    clearance: float
    first_impact: float
    reached: bool
    tolerance: float
    viscosity: float
    bracket: tuple
    bracket_times: tuple
    evaluations: tuple
    t_stop: float
    config: str
    message: str

    @property
    def miss(self) -> float:
        """``first_impact - target`` [s]."""
        return self.first_impact - self.target

    def to_json(self) -> str:
        def clean(v):
            if isinstance(v, float) and not math.isfinite(v):
                return None
            if isinstance(v, (list, tuple)):
                return [clean(x) for x in v]
            return v

        return json.dumps({k: clean(v) for k, v in asdict(self).items()}, indent=1)

    @classmethod
    def from_json(cls, text):
        d = json.loads(text)

        def inf(v):
            return math.inf if v is None else v

        d["first_impact"] = inf(d["first_impact"])
        d["bracket"] = tuple(d["bracket"])
        d["bracket_times"] = tuple(inf(v) for v in d["bracket_times"])
        d["evaluations"] = tuple((h, inf(t)) for h, t in d["evaluations"])
        return cls(**d)


_CALIBRATIONS: dict = {}


def calibrate_clearance(target=PAPER_IMPACT_TIME, source="paper-impact", set=None, clearances=None,
                        xtol=1e-10, tolerance=1e-6, horizon=0.05, max_brackets=3, cache_file=None,
                        refresh=False, progress=None):
    """Clearance ``H`` for which the first impact falls at ``target``, by root finding.

    The first-impact time ``t1(H)`` (:func:`first_impact_time`) is continuous
    in ``H`` only piecewise: on each *branch* the breakdown happens on the
    rising flank of the same deflection peak, and ``t1`` jumps to a later peak
    where a peak stops reaching the collar. So the search is:

    1. evaluate ``F(H) = min(t1(H), target + horizon) - target`` on the grid
       ``clearances``;
    2. on the grid intervals where ``F`` changes sign, run Brent's method
       (:func:`scipy.optimize.brentq`) down to ``xtol``; at most
       ``max_brackets`` of them, those whose early end (``t1 < target``) is
       closest to ``target`` first;
    3. a converged bracket whose end times agree within ``tolerance`` is a
       root (``reached``); otherwise it encloses a jump of ``t1`` and the end
       closer to ``target`` is the closest achievable first impact.

    Parameters
    ----------
    target : float
        Wanted first-impact time [s]; the paper's is 1.273 s.
    source : str, dict, path or Config
        Base configuration (default the ``paper-impact`` scenario).
    set : dict, optional
        Overrides applied to the base (not ``film.clearance``).
    clearances : array_like, optional
        Increasing grid of clearances [m]; default the base clearance
        ``* (1 + linspace(-0.01, 0.01, 9))``.
    xtol : float
        Clearance tolerance of Brent's method [m].
    tolerance : float
        Time within which ``target`` counts as reached [s].
    horizon : float
        Runs stop at ``target + horizon`` [s].
    max_brackets : int
        Most sign changes refined.
    cache_file : path, optional
        JSON file holding earlier calibrations: reused when the configuration,
        target and grid match, written (atomically) otherwise.
    refresh : bool
        Compute even if a cached result exists (and replace it).
    progress : callable, optional
        ``progress(H, t1)`` after every evaluation.

    Returns
    -------
    Calibration
    """
    from scipy.optimize import brentq

    from ..config import resolve, to_toml

    overrides = {k: v for k, v in (set or {}).items() if k != "film.clearance"}
    base = resolve(source, overrides)
    grid = np.sort(np.asarray(base.film.clearance * (1 + np.linspace(-0.01, 0.01, 9))
                              if clearances is None else clearances, dtype=float))
    t_stop = target + horizon
    from .. import __version__

    key = json.dumps([__version__, to_toml(base.replace(film=_with(base.film, clearance=0.0))), target,
                      [float(h) for h in grid], xtol, tolerance, horizon])
    if key in _CALIBRATIONS and not refresh:
        return _CALIBRATIONS[key]
    cached = None if refresh else _read_cache(cache_file, key)
    if cached is not None:
        _CALIBRATIONS[key] = cached
        return cached

    evaluations = []
    memo = {}

    def t1(H):
        H = float(H)
        if H in memo:
            return memo[H]
        cfg = resolve(base, {"film.clearance": H})
        t = memo[H] = float(first_impact_time(cfg, t_stop))
        evaluations.append((H, t))
        if progress is not None:
            progress(float(H), float(t))
        return t

    def F(H):
        return min(t1(H), t_stop) - target

    values = [F(H) for H in grid]
    candidates = []
    changes = [(a, fa, b, fb) for (a, fa), (b, fb) in zip(zip(grid, values), zip(grid[1:], values[1:]))
               if fa == 0.0 or fb == 0.0 or (fa < 0) != (fb < 0)]
    changes.sort(key=lambda c: -min(c[1], c[3]))  # the early end closest to target first
    for a, fa, b, fb in changes[:max_brackets]:
        if fa == 0.0 or fb == 0.0:
            H = a if fa == 0.0 else b
            candidates.append((H, H, target, target))
        else:
            brentq(F, a, b, xtol=xtol, rtol=4 * np.finfo(float).eps, maxiter=200)
            inside = sorted((h, t) for h, t in memo.items() if a <= h <= b)
            pairs = [(l, r) for l, r in zip(inside, inside[1:])
                     if (min(l[1], t_stop) < target) != (min(r[1], t_stop) < target)]
            left, right = min(pairs, key=lambda p: p[1][0] - p[0][0])
            candidates.append((left[0], right[0], left[1], right[1]))

    def miss(t):
        return abs(t - target)

    reached = [c for c in candidates if min(miss(c[2]), miss(c[3])) <= tolerance]
    if reached:
        H_l, H_r, t_l, t_r = min(reached, key=lambda c: c[1] - c[0])
        H, t = (H_l, t_l) if miss(t_l) <= miss(t_r) else (H_r, t_r)
        message = (f"first impact at {t:.6f} s for H = {H * 1e3:.6f} mm: a root of t1(H) = {target} s "
                   f"on a continuous branch (Brent's method)")
        ok = True
    else:
        finite = [(h, t) for h, t in evaluations if math.isfinite(t)]
        if finite:
            H, t = min(finite, key=lambda e: miss(e[1]))
        else:
            H, t = float(grid[-1]), math.inf
        near = [c for c in candidates if H in (c[0], c[1])]
        H_l, H_r, t_l, t_r = near[0] if near else (H, H, t, t)

        def when(t_):
            return "no impact" if not t_ < t_stop else f"{t_:.4f} s"

        closest = f"closest first impact {when(t)} at H = {H * 1e3:.6f} mm"
        if near:
            message = (f"{target} s is not reached: t1(H) jumps across it, from {when(t_l)} at "
                       f"H = {H_l * 1e3:.7f} mm to {when(t_r)} at H = {H_r * 1e3:.7f} mm; {closest}")
        elif candidates:
            message = (f"{target} s is not reached: every sign change of t1(H) - {target} s refined is a "
                       f"jump; {closest}")
        else:
            message = (f"{target} s is not reached: t1(H) - {target} s does not change sign on the grid "
                       f"[{grid[0] * 1e3:.4f}, {grid[-1] * 1e3:.4f}] mm; {closest}")
        ok = False
    result = Calibration(target=float(target), clearance=float(H), first_impact=float(t), reached=ok,
                         tolerance=float(tolerance), viscosity=float(base.film.viscosity),
                         bracket=(float(H_l), float(H_r)), bracket_times=(float(t_l), float(t_r)),
                         evaluations=tuple(evaluations), t_stop=float(t_stop), config=to_toml(base),
                         message=message)
    log.info("calibration: %s", message)
    _CALIBRATIONS[key] = result
    _write_cache(cache_file, key, result)
    return result


def calibrate_impact(target=PAPER_IMPACT_TIME, viscosities=(1e-3, 2e-3, 3e-3, 5e-3), clearances=None,
                     source="paper-impact", set=None, **kwargs):
    """Search viscosity and clearance for a first impact at ``target``.

    Runs :func:`calibrate_clearance` for every viscosity (the other
    parameter the paper leaves open that decides whether the film breaks
    down) and returns all outcomes with the best first.

    Parameters
    ----------
    viscosities : sequence of float
        ``mu`` values searched [Pa s].
    clearances : array_like
        Clearance grid [m] used for every viscosity.
    **kwargs
        Passed to :func:`calibrate_clearance`.

    Returns
    -------
    list of Calibration
        Sorted by ``reached`` then ``|first_impact - target|``.
    """
    out = [calibrate_clearance(target, source, {**(set or {}), "film.viscosity": float(mu)},
                               clearances=clearances, **kwargs) for mu in viscosities]
    return sorted(out, key=lambda c: (not c.reached, abs(c.miss)))


def first_impact_map(viscosities, clearances, source="paper-impact", set=None, t_stop=2.0, progress=None):
    """First-impact time on a grid of viscosity and clearance, and its crank phase.

    The evidence behind the calibration of Fig. 9: where on the crank turn
    the film can break down at all.

    Parameters
    ----------
    viscosities : sequence of float
        ``mu`` [Pa s].
    clearances : sequence of float
        ``H`` [m].
    t_stop : float
        Last time searched [s].
    progress : callable, optional
        ``progress(mu, H, t1)`` after every run.

    Returns
    -------
    xarray.Dataset
        ``first_impact`` [s] (``inf``: none before ``t_stop``) and ``phase``
        (time since the start of that crank turn [s]) on ``(viscosity,
        clearance)``; ``attrs["period"]`` is the crank period [s].
    """
    import xarray as xr

    from ..config import resolve

    t1 = np.full((len(viscosities), len(clearances)), np.inf)
    for i, mu in enumerate(viscosities):
        for j, H in enumerate(clearances):
            cfg = resolve(source, {**(set or {}), "film.viscosity": float(mu), "film.clearance": float(H)})
            t1[i, j] = first_impact_time(cfg, t_stop)
            if progress is not None:
                progress(float(mu), float(H), float(t1[i, j]))
    period = 2.0 * np.pi / abs(cfg.mechanism.crank_speed)
    phase = np.full_like(t1, np.nan)
    finite = np.isfinite(t1)
    phase[finite] = np.mod(t1[finite], period)
    dims = ("viscosity", "clearance")
    return xr.Dataset(
        {"first_impact": (dims, t1, {"units": "s"}),
         "phase": (dims, phase, {"units": "s", "long_name": "time since the start of the crank turn"})},
        coords={"viscosity": ("viscosity", list(viscosities), {"units": "Pa s"}),
                "clearance": ("clearance", list(clearances), {"units": "m"})},
        attrs={"period": period, "t_stop": t_stop},
    )


def _with(section, **changes):
    from dataclasses import replace

    return replace(section, **changes)


def _read_cache(path, key):
    if path is None or not Path(path).is_file():
        return None
    try:
        entries = json.loads(Path(path).read_text(encoding="utf-8"))
        return Calibration.from_json(entries[key]) if key in entries else None
    except (OSError, ValueError, KeyError, TypeError):
        log.warning("ignoring unreadable calibration cache %s", path)
        return None


def _write_cache(path, key, result):
    if path is None:
        return
    path = Path(path)
    entries = {}
    if path.is_file():
        try:
            entries = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            entries = {}
    entries[key] = result.to_json()
    _atomic_write(path, lambda tmp: Path(tmp).write_text(json.dumps(entries, indent=1), encoding="utf-8"))


def _atomic_write(path, write):
    """Call ``write(temporary_path)`` then rename it to ``path`` (same folder, same suffix)."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}-", suffix=path.suffix, dir=path.parent)
    os.close(fd)
    try:
        write(tmp)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


# ----------------------------------------------------------------- variants of the equations
def _variant_model(config, variant):
    """The model of ``config`` with the equations of ``variant`` (see :data:`VARIANTS`)."""
    from dataclasses import fields

    from ..kinematics import PrescribedMotion, SliderCrank, slider_crank
    from ..model import build_model

    if variant not in VARIANTS:
        raise ValueError(f"variant = {variant!r}: must be one of {', '.join(VARIANTS)}")
    motion = None
    if variant in ("double-count", "printed"):
        m = config.mechanism
        crank = SliderCrank(m)

        def kin(name):
            return lambda t: slider_crank(t, m.crank_length, m.rod_length, m.crank_speed,
                                          m.guide_distance)[name]

        def a_printed(t):
            k = slider_crank(t, m.crank_length, m.rod_length, m.crank_speed, m.guide_distance)
            return k["A_O2"] + k["omega"] * k["v_O1"]

        motion = PrescribedMotion(A_O2=a_printed, omega=kin("omega"), alpha=kin("alpha"),
                                  x_star=kin("x_star"), V_r=kin("V_r"),
                                  reaction=lambda t: crank.joint_reaction(t, config.collar.mass),
                                  angle=crank.link_angle)
    base = build_model(config, motion)
    if variant in ("corrected", "double-count"):
        return base
    stiffening = variant in ("printed-omega2", "printed")
    film_sign = -1.0 if variant == "printed-film-sign" else 1.0
    return PrintedModel(**{f.name: getattr(base, f.name) for f in fields(Model)},
                        stiffening=stiffening, film_sign=film_sign)


@dataclass(frozen=True)
class PrintedModel(Model):
    """:class:`lubelink.model.Model` with some of the paper's printed signs.

    ``stiffening``: ``+omega^2 q_n`` in the modal equation (Eq. 18 as
    printed) instead of the corrected ``-omega^2 q_n``, i.e. an extra
    ``-2 omega^2 q_n`` in ``q_ddot``. ``film_sign = -1``: the film force of
    Eq. 20 as printed, ``+B p_g`` on the link (gauge pressure kept).
    """

    stiffening: bool = False
    film_sign: float = 1.0

    def film_loads(self, t, y, kin=None):
        F, total = Model.film_loads(self, t, y, kin)
        return self.film_sign * F, self.film_sign * total

    def rhs(self, t, y, phase=None):
        dy = Model.rhs(self, t, y, phase)
        if self.stiffening:
            N = self.modes
            dy[N:] -= 2.0 * float(self.motion(t).omega) ** 2 * y[:N]
        return dy


def simulate_variant(source="paper", set=None, variant="corrected"):
    """Simulate with the corrected equations or one of the paper's printed variants.

    Parameters
    ----------
    source, set
        As for :func:`lubelink.simulate`.
    variant : str
        A key of :data:`VARIANTS`: ``"corrected"`` (lubelink's equations),
        ``"printed-omega2"`` (``+omega^2`` of Eq. 18), ``"double-count"``
        (``A_O2 + omega v_O1`` of Eq. 18 with Section 6's true ``a_O2``),
        ``"printed"`` (both) or ``"printed-film-sign"`` (Eq. 20's ``+B p_g``).

    Returns
    -------
    xarray.Dataset
        As :func:`lubelink.simulate`, with ``attrs["variant"]``.

    Raises
    ------
    ValueError
        For an unknown variant, or a variant other than ``"corrected"`` with
        a contact law (the variants are for impact-free runs).
    """
    from ..config import resolve
    from ..simulate import Run, run, to_dataset

    config = resolve(source, set)
    if variant == "corrected":
        ds = to_dataset(run(config))
    else:
        if config.contact.law != "none":
            raise ValueError(f"variant {variant!r} is available for contact.law = 'none' only")
        ds = to_dataset(_run_model(config, _variant_model(config, variant), Run))
    ds.attrs["variant"] = variant
    return ds


def _run_model(config, model, run_class):
    """Impact-free run of ``model`` from zero initial conditions, as :func:`lubelink.simulate.run`.

    Always on the reference (NumPy) segment integrator, which calls
    ``model.rhs``: the variants live in that method.
    """
    import time

    from ..simulate import reference_segment_integrator

    start = time.perf_counter()
    s = config.solver
    n_out = int(np.floor(s.t_end / s.output_step * (1 + 1e-12))) + 1
    t_eval = np.arange(n_out) * s.output_step
    y0 = model.initial_state()
    monitored = config.film.enabled or config.contact.law != "none"
    segment = reference_segment_integrator(model)
    seg = segment(0.0, y0, s.t_end, t_eval[1:], phase=None, event_sign=-1 if monitored else None,
                  event_resolution=_event_resolution(model), deadline=None, progress=None)
    out = run_class(model=model, t=np.concatenate([t_eval[:1], seg.t]),
                    y=np.concatenate([y0[None, :], seg.y]), nfev=seg.nfev, nsteps=seg.nsteps)
    if seg.status == "event":
        out.status, out.message = "film_breakdown", f"the film broke down at t = {seg.t_final:.9g} s"
    elif seg.status != "finished":
        out.status, out.message = "solver_failure", seg.message
    out.wall_time = time.perf_counter() - start
    return out


# ----------------------------------------------------------------- the study: every run once
class Study:
    """Runs simulations on demand, each distinct configuration and variant once.

    Parameters
    ----------
    overrides : dict, optional
        Applied to every configuration (e.g. the output resolution).
    progress : callable, optional
        ``progress(label)`` before every new simulation.
    """

    def __init__(self, overrides=None, progress=None):
        self.overrides = dict(overrides or {})
        self.progress = progress
        self._results = {}

    def config(self, source="paper", set=None):
        from ..config import resolve

        return resolve(source, {**self.overrides, **(set or {})})

    def dataset(self, source="paper", set=None, variant="corrected", label=None):
        """Results of ``source`` with ``set`` (after the study's overrides), computed once."""
        from ..config import to_toml

        config = self.config(source, set)
        key = (to_toml(config), variant)
        if key not in self._results:
            if self.progress is not None:
                self.progress(label or f"{source} {set or ''} {variant}".strip())
            self._results[key] = simulate_variant(config, variant=variant)
        return self._results[key]

    @property
    def runs(self) -> int:
        """Number of distinct simulations run so far."""
        return len(self._results)


# ----------------------------------------------------------------- lubrication effect (Fig. 7)
def lubrication_effect(viscosities=(0.01, 0.1, 1.0), clearances=(3e-3, 6e-3),
                       models=("wedge", "wedge+squeeze"), study=None):
    """Peak midpoint deflection with a film against the dry joint.

    Parameters
    ----------
    viscosities : sequence of float
        ``mu`` [Pa s].
    clearances : sequence of float
        ``H`` [m].
    models : sequence of str
        Film models.
    study : Study, optional
        Reuses its runs (and its overrides).

    Returns
    -------
    xarray.Dataset
        On ``(model, viscosity, clearance)``: ``peak`` (peak ``|u2_mid|`` [m]),
        ``peak_dry`` [m], ``change`` (``peak / peak_dry - 1`` [-]),
        ``smaller_fraction`` (fraction of samples where ``|u2_mid|`` is
        smaller than dry [-]), ``rms_difference`` [m], ``film_min`` (thinnest
        film [m]) and ``status`` of each run.
    """
    import xarray as xr

    study = study or Study()
    dry = study.dataset("paper-dry", label="paper-dry")
    u_dry = np.abs(dry.u2_mid.values)
    shape = (len(models), len(viscosities), len(clearances))
    out = {k: np.full(shape, np.nan) for k in ("peak", "smaller_fraction", "rms_difference", "film_min")}
    status = np.empty(shape, dtype=object)
    for i, model in enumerate(models):
        for j, mu in enumerate(viscosities):
            for k, H in enumerate(clearances):
                ds = study.dataset("paper", {"film.model": model, "film.viscosity": float(mu),
                                             "film.clearance": float(H)},
                                   label=f"{model} mu={mu:g} H={H * 1e3:g}mm")
                u = np.abs(ds.u2_mid.values)
                n = min(u.size, u_dry.size)
                out["peak"][i, j, k] = u.max()
                out["smaller_fraction"][i, j, k] = np.mean(u[:n] < u_dry[:n])
                out["rms_difference"][i, j, k] = np.sqrt(np.mean((ds.u2_mid.values[:n] - dry.u2_mid.values[:n]) ** 2))
                out["film_min"][i, j, k] = float(ds.film_min.min())
                status[i, j, k] = ds.attrs["status"]
    dims = ("model", "viscosity", "clearance")
    peak_dry = float(u_dry.max())
    return xr.Dataset(
        {
            "peak": (dims, out["peak"], {"units": "m", "long_name": "peak |u2_mid| with the film"}),
            "peak_dry": ((), peak_dry, {"units": "m", "long_name": "peak |u2_mid| of the dry joint"}),
            "change": (dims, out["peak"] / peak_dry - 1.0, {"units": "1", "long_name": "peak / peak_dry - 1"}),
            "smaller_fraction": (dims, out["smaller_fraction"],
                                 {"units": "1", "long_name": "fraction of time |u2_mid| below the dry joint's"}),
            "rms_difference": (dims, out["rms_difference"], {"units": "m", "long_name": "rms of u2_mid - dry"}),
            "film_min": (dims, out["film_min"], {"units": "m", "long_name": "thinnest film"}),
            "status": (dims, status.astype(str)),
        },
        coords={"model": list(models), "viscosity": ("viscosity", list(viscosities), {"units": "Pa s"}),
                "clearance": ("clearance", list(clearances), {"units": "m"})},
        attrs={"t_end": float(dry.time[-1])},
    )


def lubrication_table(effect):
    """Markdown table of :func:`lubrication_effect` (mm, %, µm)."""
    rows = ["| film | mu [Pa s] | H [mm] | peak with film [mm] | dry [mm] | change | time below dry | "
            "rms difference [µm] | thinnest film [mm] |",
            "|---|---|---|---|---|---|---|---|---|"]
    dry = float(effect.peak_dry)
    for model in effect.model.values:
        for mu in effect.viscosity.values:
            for H in effect.clearance.values:
                e = effect.sel(model=model, viscosity=mu, clearance=H)
                note = "" if str(e.status.values) == "complete" else f" ({e.status.values})"
                rows.append(f"| {model} | {mu:g} | {H * 1e3:g} | {float(e.peak) * 1e3:.4f}{note} | {dry * 1e3:.4f} | "
                            f"{float(e.change) * 100:+.2f} % | {float(e.smaller_fraction) * 100:.0f} % | "
                            f"{float(e.rms_difference) * 1e6:.1f} | {float(e.film_min) * 1e3:.4f} |")
    return "\n".join(rows) + "\n"


# ----------------------------------------------------------------- figures
@dataclass
class FigureSet:
    """What :func:`make_figures` produced: files, the data behind each figure, the calibration."""

    paths: dict = field(default_factory=dict)
    data: dict = field(default_factory=dict)
    calibration: Calibration | None = None
    runs: int = 0


def _save(fig, folder, stem, dpi, formats=("png", "pdf")):
    paths = []
    for ext in formats:
        path = Path(folder) / f"{stem}.{ext}"
        _atomic_write(path, lambda tmp, ext=ext: fig.savefig(tmp, dpi=dpi, format=ext))
        paths.append(path)
    return paths


def _fig6(study, res, ctx):
    from .. import plots

    ds = study.dataset("paper", label="paper")
    return plots.figure_deflection(ds), {"paper": ds}


def _fig7(study, res, ctx):
    from .. import plots

    data = {
        "dry joint (paper-dry)": study.dataset("paper-dry", label="paper-dry"),
        "wedge film (paper)": study.dataset("paper", label="paper"),
        "wedge + squeeze film": study.dataset("paper", {"film.model": "wedge+squeeze"}, label="paper, wedge+squeeze"),
    }
    styles = {"dry joint (paper-dry)": {"lw": 1.4, "color": "k"},
              "wedge film (paper)": {"lw": 1.0, "color": "C0"},
              "wedge + squeeze film": {"lw": 1.0, "color": "C2", "ls": "--"}}
    return plots.figure_lubrication(data, "dry joint (paper-dry)", styles=styles), data


def _fig8(study, res, ctx):
    from .. import plots

    ds = study.dataset("paper", label="paper")
    return plots.figure_pressure(ds), {"paper": ds}


def _fig9(study, res, ctx):
    from .. import plots

    c = res["calibration"]
    impact = ctx.get("impact", {})
    base = study.config("paper-impact", impact)
    grid = base.film.clearance * (1 + np.linspace(-c["span"], c["span"], c["points"]))
    bar = ctx.get("bar")

    def progress(H, t):
        if bar is not None:
            bar.set_postfix_str(f"calibrating: H = {H * 1e3:.6f} mm, first impact {t:.4f} s")

    def calibrate(refresh=False):
        return calibrate_clearance(PAPER_IMPACT_TIME, "paper-impact", {**study.overrides, **impact},
                                   clearances=grid, xtol=c["xtol"], max_brackets=c["max_brackets"],
                                   cache_file=ctx.get("cache"), refresh=refresh, progress=progress)

    def run(cal):
        t_end = max(base.solver.t_end, PAPER_IMPACT_TIME + 0.2)
        return study.dataset("paper-impact", {**impact, "film.clearance": cal.clearance, "solver.t_end": t_end},
                             label="paper-impact (calibrated)")

    def reproduces(cal, ds):
        first = ds.impact_time.values[0] if ds.impact_time.size else math.inf
        return first == cal.first_impact or abs(first - cal.first_impact) <= 1e-9

    cal = calibrate()
    ds = run(cal)
    if not reproduces(cal, ds):  # a cached calibration from another integrator path or version
        log.warning("the cached calibration does not reproduce its first impact; calibrating again")
        cal = calibrate(refresh=True)
        ds = run(cal)
    ctx["calibration"] = cal
    verdict = "reached" if cal.reached else f"not reachable, closest first impact {cal.first_impact:.4f} s"
    note = (f"H = {cal.clearance * 1e3:.4f} mm (root finding on H), mu = {cal.viscosity * 1e3:g} mPa s; "
            f"paper's 1.273 s {verdict}")
    fig = plots.figure_impact(ds, target=PAPER_IMPACT_TIME, min_film=base.contact.min_film, note=note)
    return fig, {"paper-impact": ds, "calibration": cal}


def _impact_map(study, res, ctx):
    from .. import plots

    m = res["impact_map"]
    bar = ctx.get("bar")

    def progress(mu, H, t):
        if bar is not None:
            bar.set_postfix_str(f"mu = {mu * 1e3:g} mPa s, H = {H * 1e3:.2f} mm: first impact {t:.4f} s")

    impacts = first_impact_map(m["viscosities"], m["clearances"], "paper-impact",
                               {**study.overrides, **ctx.get("impact", {})}, t_stop=2.0, progress=progress)
    return plots.figure_first_impact_map(impacts, target=PAPER_IMPACT_TIME), {"map": impacts}


def _modes(study, res, ctx):
    from .. import plots

    data = {n: study.dataset("paper", {"beam.modes": n, **res["modes_overrides"]}, label=f"paper, {n} modes")
            for n in res["modes"]}
    return plots.figure_modal_convergence(data), data


def _errata(study, res, ctx):
    from .. import plots

    labels = {"corrected": "corrected", "printed-omega2": "+omega^2 q (Eq. 18)",
              "double-count": "omega v_O1 twice (Eq. 18)", "printed": "Eq. 18 as printed",
              "printed-film-sign": "+B p_g (Eq. 20)"}
    data = {}
    for v, label in labels.items():
        ds = study.dataset("paper", variant=v, label=f"paper, {v}")
        if ds.attrs["status"] != "complete":
            label = f"{label}: film breaks down at {float(ds.time[-1]):.2f} s"
        data[label] = ds
    return plots.figure_errata(data, labels["corrected"]), data


def _lubrication(study, res, ctx):
    from .. import plots

    lub = res["lubrication"]
    effect = lubrication_effect(lub["viscosities"], lub["clearances"], study=study)
    fig = plots.figure_lubrication_effect(effect)
    return fig, {"effect": effect}


BUILDERS = {"fig6": _fig6, "fig7": _fig7, "fig8": _fig8, "fig9": _fig9, "impact-map": _impact_map,
            "modes": _modes,
            "errata": _errata, "lubrication": _lubrication}


def make_figures(outdir="figures", low_res=False, only=None, progress=False, formats=("png", "pdf"),
                 overrides=None, impact=None, dpi=None):
    """Compute and write the paper's figures (PNG and PDF) into ``outdir``.

    Parameters
    ----------
    outdir : path
        Folder (created if missing). Files are named after :data:`FIGURES`;
        existing ones are replaced, each atomically. The calibration of
        Fig. 9 is cached in ``outdir/calibration.json``, and the table of
        the lubrication effect is written as ``lubrication-effect.md``.
    low_res : bool
        Coarser output, looser tolerance, short modal runs, small figures:
        for tests and quick looks.
    only : sequence of str, optional
        Keys of :data:`FIGURES` to make (default all).
    progress : bool
        Progress bar on stderr.
    formats : sequence of str
        File formats.
    overrides : dict, optional
        Extra ``{"section.key": value}`` applied to every run (after the
        resolution's), e.g. ``{"beam.damping_ratio": 0.05}``.
    impact : dict, optional
        Overrides of the ``paper-impact`` scenario only (Fig. 9), e.g.
        ``{"film.viscosity": 2.5e-3, "film.clearance": 4.45e-3}``: the
        clearance is the centre of the calibration grid.
    dpi : int, optional
        Resolution of raster images (default 150, or 60 with ``low_res``).

    Returns
    -------
    FigureSet
    """
    res = RESOLUTIONS["low" if low_res else "full"]
    names = list(FIGURES) if only is None else list(only)
    unknown = [n for n in names if n not in FIGURES]
    if unknown:
        raise ValueError(f"unknown figure(s) {', '.join(unknown)}; choose from {', '.join(FIGURES)}")
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    bar = None
    if progress:
        import sys

        from tqdm.auto import tqdm

        bar = tqdm(total=len(names), unit="fig", desc="figures", file=sys.stderr, leave=False,
                   bar_format="{desc}{n}/{total} figures |{bar}| {elapsed}{postfix}")

    def announce(label):
        if bar is not None:
            bar.set_postfix_str(f"simulating {label}")

    study = Study({**res["overrides"], **(overrides or {})}, progress=announce)
    ctx = {"bar": bar, "cache": outdir / "calibration.json", "impact": dict(impact or {})}
    if dpi is not None:
        res = {**res, "dpi": dpi}
    out = FigureSet()
    try:
        for name in names:
            if bar is not None:
                bar.set_description(name)
            fig, data = BUILDERS[name](study, res, ctx)
            out.paths[name] = _save(fig, outdir, FIGURES[name], res["dpi"], formats)
            out.data[name] = data
            if name == "lubrication":
                table = outdir / "lubrication-effect.md"
                text = lubrication_table(data["effect"])
                _atomic_write(table, lambda tmp: Path(tmp).write_text(text, encoding="utf-8"))
                out.paths[name].append(table)
            if bar is not None:
                bar.update(1)
    finally:
        if bar is not None:
            bar.close()
    out.calibration = ctx.get("calibration")
    out.runs = study.runs
    return out


# ----------------------------------------------------------------- animation
def animate(source="paper", set=None, output="mechanism.gif", scale=50.0, fps=20, duration=0.4,
            speed=0.1, overwrite=False, dpi=80, progress=False):
    """Simulate and write an animation of the mechanism (GIF, or MP4 with ffmpeg).

    Parameters
    ----------
    source, set
        As for :func:`lubelink.simulate`; ``solver.t_end`` and
        ``solver.output_step`` are set from ``duration``, ``speed`` and ``fps``.
    output : path
        ``.gif`` (Pillow) or ``.mp4`` (needs ffmpeg); written atomically.
    scale : float
        Magnification of the deflection and clearance [-].
    fps : int
        Frames per second [1/s].
    duration : float
        Simulated time shown [s].
    speed : float
        Playback speed relative to real time [-] (0.1: ten times slower).
    overwrite : bool
        Replace an existing file.

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    ValueError
        For an unsupported suffix, missing ffmpeg, an existing file without
        ``overwrite`` or a non-positive option.
    """
    output = Path(output)
    suffix = output.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise ValueError(f"-o {output}: the animation must be a .gif or .mp4 file")
    for name, value in (("--scale", scale), ("--fps", fps), ("--duration", duration), ("--speed", speed)):
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise ValueError(f"{name} = {value}: must be a positive number")
    if output.exists() and not overwrite:
        raise ValueError(f"-o {output}: the file exists; add --overwrite to replace it")
    if not output.parent.exists():
        raise ValueError(f"-o {output}: folder {output.parent} does not exist")
    import matplotlib.animation as manim

    if suffix == ".mp4" and not manim.FFMpegWriter.isAvailable():
        raise ValueError(f"-o {output}: writing MP4 needs ffmpeg, which was not found; write a .gif instead")
    from ..simulate import simulate

    frame_step = speed / fps
    frames = int(round(duration / frame_step))
    if frames < 2:
        raise ValueError(f"--duration {duration}: shows fewer than 2 frames at --fps {fps} and --speed {speed}")
    ds = simulate(source, {**(set or {}), "solver.t_end": frames * frame_step, "solver.output_step": frame_step},
                  progress=progress)
    from .. import plots

    fig, anim = plots.animate_mechanism(ds, scale=scale, fps=fps, dpi=dpi)
    writer = manim.PillowWriter(fps=fps) if suffix == ".gif" else manim.FFMpegWriter(fps=fps)
    bar = None
    callback = None
    if progress:
        import sys

        from tqdm.auto import tqdm

        bar = tqdm(total=ds.sizes["time"], unit="frame", desc="animating", file=sys.stderr, leave=False)

        def callback(i, n):
            bar.update(1)
    try:
        _atomic_write(output, lambda tmp: anim.save(tmp, writer=writer, dpi=dpi, progress_callback=callback))
    finally:
        if bar is not None:
            bar.close()
    return output


# ----------------------------------------------------------------- command line
def _cmd_figures(args):
    from ..errors import UsageError

    only = None
    if args.only:
        only = [n.strip() for n in args.only.split(",") if n.strip()]
        bad = [n for n in only if n not in FIGURES]
        if bad:
            raise UsageError(f"--only {args.only}: unknown figure(s) {', '.join(bad)}; "
                             f"choose from {', '.join(FIGURES)}")
    out = Path(args.output)
    if out.exists() and not out.is_dir():
        raise UsageError(f"-o {out}: exists and is not a folder")
    formats = tuple(f.strip().lower() for f in args.formats.split(",") if f.strip())
    bad = [f for f in formats if f not in ("png", "pdf", "svg")]
    if bad or not formats:
        raise UsageError(f"--formats {args.formats}: choose from png, pdf, svg")
    if args.dpi is not None and not 10 <= args.dpi <= 1200:
        raise UsageError(f"--dpi {args.dpi}: must be in [10, 1200]")
    result = make_figures(out, low_res=args.low_res, only=only, progress=not args.quiet, formats=formats,
                          dpi=args.dpi)
    if not args.quiet:
        for name, paths in result.paths.items():
            print(f"{name:<12} " + "  ".join(str(p) for p in paths))
        if result.calibration is not None:
            print(f"{'calibration':<12} {result.calibration.message}")
        print(f"{'runs':<12} {result.runs} simulations")
    return 0


def _cmd_animate(args):
    from ..cli import resolve_args
    from ..errors import UsageError
    from ..config import ConfigError

    _, config = resolve_args(args)
    try:
        path = animate(config, None, args.output, scale=args.scale, fps=args.fps, duration=args.duration,
                       speed=args.speed, overwrite=args.overwrite, progress=not args.quiet)
    except ConfigError:
        raise
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    if not args.quiet:
        print(f"wrote {path}")
    return 0


def register_cli(subparsers, add_config_args):
    """Add the ``figures`` and ``animate`` subcommands to the ``lubelink`` parser."""
    p = subparsers.add_parser(
        "figures", help="write the paper's figures (Figs. 6-9, modal convergence, errata) as PNG and PDF",
        description="Compute the paper's Section 6 results and write the figures as PNG and PDF: "
                    + ", ".join(f"{k} ({v})" for k, v in FIGURES.items())
                    + ". Fig. 9's clearance is calibrated by root finding and cached in DIR/calibration.json. "
                      "Existing figure files in DIR are replaced.")
    p.add_argument("-o", "--output", default="figures", metavar="DIR", help="output folder (default: figures)")
    p.add_argument("--low-res", action="store_true",
                   help="coarse and quick: looser tolerance, short modal runs, small images")
    p.add_argument("--only", metavar="NAMES", help="comma-separated subset, e.g. fig6,fig9")
    p.add_argument("--formats", default="png,pdf", metavar="LIST",
                   help="comma-separated image formats (default png,pdf)")
    p.add_argument("--dpi", type=int, metavar="N", help="resolution of raster images (default 150; 60 with --low-res)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar and no list of files")
    p.set_defaults(handler=_cmd_figures)

    p = subparsers.add_parser(
        "animate", help="animate the mechanism (GIF, or MP4 with ffmpeg)",
        description="Simulate a configuration and animate the crank, the flexible link (deflection "
                    "magnified), the collar on its vertical guide and the slider.")
    add_config_args(p)
    p.add_argument("-o", "--output", required=True, metavar="FILE", help="animation file, .gif or .mp4")
    p.add_argument("--scale", type=float, default=50.0, metavar="FACTOR",
                   help="magnification of the deflection and clearance (default 50)")
    p.add_argument("--fps", type=int, default=20, metavar="N", help="frames per second (default 20)")
    p.add_argument("--duration", type=float, default=0.4, metavar="S",
                   help="simulated time shown [s] (default 0.4 s, two crank turns)")
    p.add_argument("--speed", type=float, default=0.1, metavar="FACTOR",
                   help="playback speed relative to real time (default 0.1: ten times slower)")
    p.add_argument("--overwrite", action="store_true", help="replace FILE if it exists")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    p.set_defaults(handler=_cmd_animate)

"""Fig. 9's first impact: the first-breakdown time, the clearance calibration and its cache.

:func:`first_impact_time` integrates one configuration up to its first film
breakdown; :func:`calibrate_clearance` finds by root finding the clearance
whose first impact falls at a wanted time (the paper's 1.273 s), caching the
outcome in memory and, optionally, in a JSON file; :func:`calibrate_impact`
repeats that over viscosities, and :func:`first_impact_map` tabulates the
first impact over a grid of viscosity and clearance.

This module and :mod:`lubelink.paper.variants` are the only ones of the
package that call the simulation core (``run``) directly.
"""

from __future__ import annotations

import json
import logging
import math
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from .._files import atomic_path

__all__ = [
    "PAPER_IMPACT_TIME",
    "Calibration",
    "first_impact_time",
    "calibrate_clearance",
    "calibrate_impact",
    "first_impact_map",
]

log = logging.getLogger(__name__)

#: First-impact time of the paper's Fig. 9 [s].
PAPER_IMPACT_TIME = 1.273


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
    from dataclasses import replace

    from ..simulate import method_name, run

    t_stop = config.solver.t_end if t_stop is None else float(t_stop)
    # no contact law: the run stops at the first breakdown; one output sample is enough; the method
    # is the one the run with its contact law takes (without one "auto" could pick another, whose
    # breakdown time differs within the tolerances)
    config = replace(config, contact=replace(config.contact, law="none"),
                     solver=replace(config.solver, t_end=t_stop, output_step=t_stop, method=method_name(config)))
    result = run(config, motion)
    if result.status == "film_breakdown":
        return float(result.event_time)
    if result.complete:
        return math.inf
    raise RuntimeError(result.message)



def _first_impact(config, t_stop):
    """:func:`first_impact_time` as ``lubelink.paper`` exports it, looked up at call time.

    Replacing ``lubelink.paper.first_impact_time`` (as the tests do with a
    synthetic ``t1(H)``) thus reaches every search of this module, as it did
    when the package was a single module.
    """
    from .. import paper

    return paper.first_impact_time(config, t_stop)


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
        t = memo[H] = float(_first_impact(cfg, t_stop))
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
        clearance)``; ``attrs["period"]`` is the crank period [s],
        ``attrs["pad_length"]`` the pad length [m].
    """
    import xarray as xr

    from ..config import resolve

    t1 = np.full((len(viscosities), len(clearances)), np.inf)
    for i, mu in enumerate(viscosities):
        for j, H in enumerate(clearances):
            cfg = resolve(source, {**(set or {}), "film.viscosity": float(mu), "film.clearance": float(H)})
            t1[i, j] = _first_impact(cfg, t_stop)
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
        attrs={"period": period, "t_stop": t_stop, "pad_length": cfg.film.pad_length},
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
    with atomic_path(path) as tmp:
        tmp.write_text(json.dumps(entries, indent=1), encoding="utf-8")

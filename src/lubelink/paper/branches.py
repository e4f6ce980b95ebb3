"""Branches of the first-impact time: where on the clearance axis Fig. 9's 1.273 s is reached.

The first-impact time ``t1(H)`` of the paper's model (:func:`first_impact_time`)
is continuous in the clearance ``H`` only piecewise. On a *branch* the film
breaks down on the flank of the same deflection peak and ``t1`` moves
continuously with ``H``; at a branch edge that peak stops reaching the collar
and ``t1`` jumps, usually by whole crank turns. With a long enough pad the film
breaks down in several turns at the same crank angle, so the branches of
consecutive turns lie side by side on the ``H`` axis, a few micrometres wide.

:func:`find_windows` locates, for any ``t1(H)`` (a callable), the *windows*:
clearance intervals on which ``t1`` stays within ``tol`` of a target time
without a jump, their edges bracketed by bisection, the branch around each
window (out to the jumps), and the centre of the window, the clearance that
is farthest from every value of ``H`` that misses the target.
:func:`branch_map` tabulates ``t1`` over the pad length and the clearance and
runs :func:`find_windows` on every pad length; :func:`widest_window` picks the
widest window of a map. ``docs/branch_map.py`` draws the map of docs/paper.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Window", "find_windows", "phase_refine", "branch_map", "widest_window", "windows_table"]


@dataclass(frozen=True)
class Window:
    """A clearance interval on which the first impact stays within ``tol`` of the target, continuously.

    Attributes
    ----------
    lo, hi : float
        Edges of the window [m], each the last clearance inside, bracketed to ``xtol``.
    lo_exit, hi_exit : str
        What lies beyond each edge: ``"jump"`` (``t1`` jumps: the end of the branch),
        ``"tolerance"`` (``t1`` leaves ``target +- tol`` continuously) or ``"grid"``
        (the end of the clearances searched).
    centre : float
        ``(lo + hi) / 2`` [m].
    first_impact : float
        ``t1(centre)`` [s].
    branch : tuple of float
        Edges of the continuous branch that holds the window [m] (the jumps; the
        window edge itself where it is a jump; the grid end if none is found).
    branch_times : tuple of float
        ``t1`` just inside the branch edges [s].
    beyond_times : tuple of float
        ``t1`` just outside the branch edges [s] (``inf``: no impact up to ``t_stop``).
    """

    lo: float
    hi: float
    lo_exit: str
    hi_exit: str
    centre: float
    first_impact: float
    branch: tuple
    branch_times: tuple
    beyond_times: tuple

    @property
    def width(self) -> float:
        """``hi - lo`` [m]."""
        return self.hi - self.lo

    @property
    def margin(self) -> float:
        """Distance from the centre to the nearer branch edge (jump) [m]."""
        return min(self.centre - self.branch[0], self.branch[1] - self.centre)


def _side(t, target, tol):
    """-1 below the window, 0 inside, +1 above (``inf`` counts as above)."""
    if not t < math.inf:
        return 1
    return 0 if abs(t - target) <= tol else (-1 if t < target else 1)


def _step(a, b):
    """``|a - b|`` for first-impact times, 0 between two "no impact" (``inf``)."""
    return 0.0 if a == b else abs(a - b)


def find_windows(t1, clearances, target, tol, dx=5e-9, xtol=1e-10, jump=1e-3, subdivide=4, check=16, refine=None):
    """Windows of ``t1(H)`` within ``tol`` of ``target`` on the clearances ``[H_0, H_-1]``.

    1. ``t1`` is evaluated on the grid ``clearances``;
    2. every interval between neighbouring evaluations, one below the window
       and one above it (``t1 < target - tol`` and ``t1 > target + tol`` or no
       impact), is cut into ``subdivide`` parts, again and again down to the
       width ``dx``: a branch of ``t1`` through the window, if any, lies inside;
       so is every interval for which ``refine(t1(a), t1(b))`` is true;
    3. neighbouring evaluations inside the window make a window; each edge is
       bracketed by bisection to ``xtol`` and classified: a *jump* if ``t1``
       still differs by more than ``jump`` across ``xtol``, else a continuous
       exit through the tolerance. ``check`` evenly spaced interior points
       confirm the window (a window they cut is split and re-bracketed);
    4. from each tolerance exit the branch is followed outward over the
       evaluations to its first jump, bracketed the same way.

    A window narrower than the grid spacing between two evaluations on the
    same side of the window is not found; ``dx`` bounds the width of the
    windows that step 2 can find.

    Parameters
    ----------
    t1 : callable
        ``t1(H)`` [s] for ``H`` [m]; ``inf`` for no impact.
    clearances : array_like
        Increasing grid of clearances [m].
    target, tol : float
        Wanted first-impact time and its tolerance [s].
    dx, xtol : float
        Finest subdivision of step 2 and bracket of the edges [m].
    jump : float
        Change of ``t1`` across ``xtol`` that counts as a jump [s].
    subdivide : int
        Parts per subdivision (>= 2).
    check : int
        Interior points checked per window.
    refine : callable, optional
        ``refine(ta, tb)``: also subdivide the interval between clearances with
        first impacts ``ta`` and ``tb`` (e.g. :func:`phase_refine`).

    Returns
    -------
    list of Window
        Sorted by decreasing width.
    """
    grid = np.asarray(clearances, dtype=float)
    if grid.ndim != 1 or grid.size < 2 or np.any(np.diff(grid) <= 0):
        raise ValueError(f"clearances must be an increasing grid of at least 2 values, got {grid!r}")
    if not (tol > 0 and dx > 0 and xtol > 0 and jump > 0):
        raise ValueError(f"tol, dx, xtol and jump must be > 0, got {tol}, {dx}, {xtol}, {jump}")
    if int(subdivide) < 2:
        raise ValueError(f"subdivide must be an integer >= 2, got {subdivide}")
    memo = {}

    def t(H):
        H = float(H)
        if H not in memo:
            memo[H] = float(t1(H))
        return memo[H]

    def side(H):
        return _side(t(H), target, tol)

    for H in grid:
        t(H)
    # 2. subdivide the intervals that cross the window
    while True:
        hs = sorted(memo)
        todo = [(a, b) for a, b in zip(hs, hs[1:]) if b - a > dx and (
            side(a) * side(b) == -1 or refine is not None and refine(t(a), t(b)))]
        if not todo:
            break
        for a, b in todo:
            for H in np.linspace(a, b, int(subdivide) + 1)[1:-1]:
                t(H)

    def bracket(inside, outside):
        """Bisect between a clearance inside the window and one outside; returns (last in, first out)."""
        while abs(outside - inside) > xtol:
            mid = 0.5 * (inside + outside)
            if side(mid) == 0:
                inside = mid
            else:
                outside = mid
        return inside, outside

    def find_jump(a, b):
        """The jump of ``t1`` between ``a`` and ``b``, bracketed to ``xtol`` (follow the larger step), or None."""
        while abs(b - a) > xtol and _step(t(a), t(b)) > jump:
            mid = 0.5 * (a + b)
            if _step(t(mid), t(a)) >= _step(t(b), t(mid)):
                b = mid
            else:
                a = mid
        return (a, b) if _step(t(a), t(b)) > jump else None

    def branch_end(inside, outside, direction):
        """Follow the branch from the window edge outward to its first jump: (edge, t inside, t beyond)."""
        hit = find_jump(inside, outside)
        while hit is None:
            hs = sorted(memo)
            i = hs.index(outside)
            if not 0 <= i + direction < len(hs):
                return outside, t(outside), math.nan
            inside, outside = outside, hs[i + direction]
            hit = find_jump(inside, outside)
        last, first = hit
        return last, t(last), t(first)

    def edge(inside, outside, direction):
        """Bracket a window edge: (edge, exit kind, (branch edge, t inside, t beyond))."""
        if outside is None:
            return inside, "grid", (inside, t(inside), math.nan)
        last, first = bracket(inside, outside)
        if _step(t(last), t(first)) > jump:
            return last, "jump", (last, t(last), t(first))
        return last, "tolerance", branch_end(last, first, direction)

    def runs(lo=-math.inf, hi=math.inf):
        """(first, last) of every run of consecutive evaluations inside the window, within [lo, hi]."""
        out, run = [], []
        for H in sorted(memo):
            if lo <= H <= hi and side(H) == 0:
                run.append(H)
            elif run:
                out.append((run[0], run[-1]))
                run = []
        return out + ([(run[0], run[-1])] if run else [])

    windows = []
    # 3. runs of evaluations inside the window
    pending = runs()
    while pending:
        a, b = pending.pop()
        hs = sorted(memo)
        ia, ib = hs.index(a), hs.index(b)
        lo, lo_exit, b_lo = edge(a, hs[ia - 1] if ia > 0 else None, -1)
        hi, hi_exit, b_hi = edge(b, hs[ib + 1] if ib + 1 < len(hs) else None, +1)
        cut = [H for H in np.linspace(lo, hi, int(check) + 2)[1:-1] if side(H) != 0]
        if cut:  # excursions inside: split there and bracket again
            pending += runs(lo, hi)
            continue
        centre = 0.5 * (lo + hi)
        windows.append(Window(lo=lo, hi=hi, lo_exit=lo_exit, hi_exit=hi_exit, centre=centre,
                              first_impact=t(centre), branch=(b_lo[0], b_hi[0]),
                              branch_times=(b_lo[1], b_hi[1]), beyond_times=(b_lo[2], b_hi[2])))
    return sorted(windows, key=lambda w: -w.width)


def phase_refine(target, period, band, jump=1e-3):
    """A ``refine`` predicate for :func:`find_windows`: a jump between impacts near the target's crank phase.

    Where the film breaks down at the same crank angle in several turns, the
    branches of those turns lie side by side, and the one at ``target`` may hide
    between two grid points whose impacts are in other turns. This predicate
    selects such intervals: ``t1`` jumps by more than ``jump`` [s] and each end
    is either no impact or an impact within ``band`` [s] of the target's phase
    in the crank ``period`` [s].
    """
    phase = math.fmod(target, period)

    def near(t):
        if not t < math.inf:
            return True
        d = abs(math.fmod(t, period) - phase)
        return min(d, period - d) <= band

    def refine(ta, tb):
        return (ta < math.inf or tb < math.inf) and not abs(ta - tb) <= jump and near(ta) and near(tb)

    return refine


def windows_table(windows, **columns):
    """Windows as a list of flat dicts (one row each), with ``columns`` added to every row."""
    return [{**columns, "lo": w.lo, "hi": w.hi, "width": w.width, "centre": w.centre,
             "first_impact": w.first_impact, "lo_exit": w.lo_exit, "hi_exit": w.hi_exit,
             "branch_lo": w.branch[0], "branch_hi": w.branch[1], "margin": w.margin,
             "branch_t_lo": w.branch_times[0], "branch_t_hi": w.branch_times[1],
             "beyond_t_lo": w.beyond_times[0], "beyond_t_hi": w.beyond_times[1]} for w in windows]


def branch_map(pad_lengths, clearances, source="paper-impact", set=None, target=None, tol=2e-3,
               t_stop=2.0, windows=True, progress=None, **search):
    """First-impact time over the pad length and the clearance, and the windows at ``target``.

    Parameters
    ----------
    pad_lengths : sequence of float
        Pad lengths ``l`` [m].
    clearances : sequence of float
        Increasing grid of clearances ``H`` [m], the same for every pad length.
    source : str, dict, path or Config
        Base configuration (default the ``paper-impact`` scenario).
    set : dict, optional
        Overrides of the base (e.g. ``{"beam.modes": 5, "film.viscosity": 0.02}``).
    target : float, optional
        Wanted first-impact time [s]; default the paper's 1.273 s.
    tol : float
        Tolerance of a window [s].
    t_stop : float
        Last time searched in each run [s].
    windows : bool
        Search the windows (:func:`find_windows`) on every pad length.
    progress : callable, optional
        ``progress(pad_length, n_runs)`` after every pad length.
    **search
        Passed to :func:`find_windows`.

    Returns
    -------
    xarray.Dataset
        ``first_impact`` [s] (``inf``: none up to ``t_stop``) on ``(pad_length, clearance)``
        (the grid runs only) and, on the dimension ``window``, one row per window found:
        its ``window_pad_length``, edges ``lo``, ``hi``, ``width``, ``centre`` [m], ``first_impact_centre``
        [s], the edges of its branch ``branch_lo``, ``branch_hi`` [m] and the exits ``lo_exit``,
        ``hi_exit``. ``attrs``: target, tol, t_stop, runs, period [s], modes, viscosity [Pa s].
    """
    import xarray as xr

    from ..config import resolve
    from .calibration import PAPER_IMPACT_TIME, _first_impact

    target = PAPER_IMPACT_TIME if target is None else float(target)
    grid = np.asarray(clearances, dtype=float)
    base = resolve(source, {k: v for k, v in (set or {}).items() if k not in ("film.clearance", "film.pad_length")})
    t1 = np.full((len(pad_lengths), grid.size), np.inf)
    rows, runs = [], 0
    for i, pad in enumerate(pad_lengths):
        cfg = resolve(base, {"film.pad_length": float(pad)})
        memo = {}

        def f(H, cfg=cfg, memo=memo):
            if H not in memo:
                memo[H] = _first_impact(resolve(cfg, {"film.clearance": float(H)}), t_stop)
            return memo[H]

        if windows:
            rows += windows_table(find_windows(f, grid, target, tol, **search), pad_length=float(pad))
        t1[i] = [f(float(H)) for H in grid]
        runs += len(memo)
        if progress is not None:
            progress(float(pad), len(memo))
    names = ["pad_length", "lo", "hi", "width", "centre", "first_impact", "lo_exit", "hi_exit", "branch_lo",
             "branch_hi", "margin", "branch_t_lo", "branch_t_hi", "beyond_t_lo", "beyond_t_hi"]
    units = {"first_impact": "s", "lo_exit": "", "hi_exit": "", "branch_t_lo": "s", "branch_t_hi": "s",
             "beyond_t_lo": "s", "beyond_t_hi": "s"}
    rename = {"first_impact": "first_impact_centre", "pad_length": "window_pad_length"}
    table = {rename.get(n, n):
             ("window", np.array([r[n] for r in rows], dtype=str if n.endswith("exit") else float),
              {"units": units.get(n, "m")}) for n in names}
    return xr.Dataset(
        {"first_impact": (("pad_length", "clearance"), t1, {"units": "s"}), **table},
        coords={"pad_length": ("pad_length", [float(p) for p in pad_lengths], {"units": "m"}),
                "clearance": ("clearance", grid, {"units": "m"})},
        attrs={"target": target, "tol": float(tol), "t_stop": float(t_stop), "runs": runs,
               "period": 2.0 * np.pi / abs(base.mechanism.crank_speed), "modes": base.beam.modes,
               "viscosity": base.film.viscosity},
    )


def widest_window(maps):
    """The widest window of one or more :func:`branch_map` datasets: ``(dataset, row index)`` or None."""
    best = None
    for ds in ([maps] if not isinstance(maps, (list, tuple)) else maps):
        for k in range(ds.sizes.get("window", 0)):
            w = float(ds.width[k])
            if best is None or w > best[0]:
                best = (w, ds, k)
    return None if best is None else best[1:]

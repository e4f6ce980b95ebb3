"""Branches of the first-impact time (lubelink.paper.branches) and the paper-impact scenario.

The window search is checked on a synthetic ``t1(H)`` whose windows, jumps and branch edges are
known in closed form; the map on one cheap real case (a few dozen one-mode runs); the scenario
through ``lubelink.simulate`` against the paper's 1.273 s.
"""

import math

import numpy as np
import pytest

import lubelink
from lubelink.paper import PAPER_IMPACT_TIME, first_impact_time
from lubelink.paper.branches import branch_map, find_windows, phase_refine, widest_window

TARGET, TOL = 1.05, 0.01


def synthetic(H):
    """Branches with known edges: a sloped one, a flat narrow one, a no-impact gap, a hidden flat one."""
    if H < 3.0:
        return 0.5
    if H < 4.0:
        return 1.0 + 0.1 * (H - 3.0)   # through the window [1.04, 1.06] for H in [3.4, 3.6]
    if H < 4.05:
        return 1.05                     # inside, bounded by jumps at 4 and 4.05
    if H < 6.2:
        return math.inf                 # no impact
    if H < 6.5:
        return 1.045 + 0.02 * (H - 6.2)  # inside, bounded by jumps at 6.2 and 6.5
    if H < 8.4:
        return 0.45
    if H < 8.6:
        return 1.05                     # hidden: both neighbours of the unit grid below the window
    return 0.65 if H < 9.0 else 0.85


def test_windows_of_a_synthetic_first_impact_time():
    calls = []

    def t1(H):
        calls.append(H)
        return synthetic(H)

    xtol = 1e-9
    ws = find_windows(t1, np.arange(0.0, 11.0), TARGET, TOL, dx=1e-3, xtol=xtol)
    assert [round(w.width, 6) for w in ws] == [0.3, 0.2, 0.05]  # widest first; the hidden one missed
    wide, sloped, flat = ws
    # sloped: leaves the tolerance continuously at 3.4 and 3.6, its branch ends at the jumps 3 and 4
    assert (sloped.lo_exit, sloped.hi_exit) == ("tolerance", "tolerance")
    assert sloped.lo == pytest.approx(3.4, abs=2 * xtol) and sloped.hi == pytest.approx(3.6, abs=2 * xtol)
    assert sloped.branch[0] == pytest.approx(3.0, abs=2 * xtol) and sloped.branch[1] == pytest.approx(4.0, abs=2 * xtol)
    assert sloped.beyond_times[0] == 0.5 and sloped.beyond_times[1] == 1.05
    assert sloped.centre == pytest.approx(3.5, abs=2 * xtol) and sloped.first_impact == pytest.approx(1.05, abs=1e-9)
    assert sloped.margin == pytest.approx(0.5, abs=4 * xtol)
    # bounded by jumps on both sides: the window is the branch
    for w, lo, hi, beyond in ((flat, 4.0, 4.05, (1.1, math.inf)), (wide, 6.2, 6.5, (math.inf, 0.45))):
        assert (w.lo_exit, w.hi_exit) == ("jump", "jump")
        assert w.lo == pytest.approx(lo, abs=2 * xtol) and w.hi == pytest.approx(hi, abs=2 * xtol)
        assert w.branch == (w.lo, w.hi)
        assert w.beyond_times[0] == pytest.approx(beyond[0], abs=1e-6) and w.beyond_times[1] == beyond[1]
    assert len(calls) == len(set(calls)) < 600  # each clearance evaluated once


def test_branch_followed_into_no_impact():
    """A branch that ends where the first impact disappears (``inf`` beyond): the jump is bracketed."""

    def t1(H):
        return 0.5 if H < 3.0 else (1.0 + 0.1 * (H - 3.0) if H < 4.0 else math.inf)

    (w,) = find_windows(t1, np.arange(0.0, 11.0), TARGET, TOL, dx=1e-3, xtol=1e-9)
    assert w.branch[0] == pytest.approx(3.0, abs=2e-9) and w.branch[1] == pytest.approx(4.0, abs=2e-9)
    assert w.beyond_times == (0.5, math.inf)
    assert w.branch_times[1] == pytest.approx(1.1, abs=1e-8)


def test_an_excursion_between_grid_points_splits_the_window():
    """t1 leaves the window on [3.4, 3.6), between grid points: the interior check finds it."""

    def t1(H):
        if not 2.0 <= H < 5.0:
            return math.inf
        return 0.5 if 3.4 <= H < 3.6 else 1.05

    ws = sorted(find_windows(t1, np.arange(0.0, 11.0), TARGET, TOL, dx=1e-3, xtol=1e-9), key=lambda w: w.lo)
    assert [(round(w.lo, 6), round(w.hi, 6)) for w in ws] == [(2.0, 3.4), (3.6, 5.0)]
    assert all((w.lo_exit, w.hi_exit) == ("jump", "jump") for w in ws)


def test_phase_refinement_finds_a_window_hidden_between_other_turns():
    # 0.45, 0.65, 0.85 and 1.05 share the crank phase 0.05 s of a 0.2 s turn; the jumps between
    # them are searched, and the window at 8.4-8.6 appears
    ws = find_windows(synthetic, np.arange(0.0, 11.0), TARGET, TOL, dx=1e-3, xtol=1e-9,
                      refine=phase_refine(TARGET, 0.2, 0.01))
    hidden = [w for w in ws if 8 < w.centre < 9]
    assert len(hidden) == 1
    assert hidden[0].lo == pytest.approx(8.4, abs=1e-3) and hidden[0].hi == pytest.approx(8.6, abs=1e-3)
    assert (hidden[0].lo_exit, hidden[0].hi_exit) == ("jump", "jump")
    # a phase outside the band does not trigger the refinement
    assert not phase_refine(TARGET, 0.2, 0.01)(0.5, 0.58)
    assert phase_refine(TARGET, 0.2, 0.01)(0.45, math.inf)
    assert not phase_refine(TARGET, 0.2, 0.01)(math.inf, math.inf)


@pytest.mark.parametrize("kwargs, needle", [
    ({"clearances": [1.0]}, "increasing grid"),
    ({"clearances": [2.0, 1.0]}, "increasing grid"),
    ({"tol": 0.0}, "must be > 0"),
    ({"subdivide": 1}, "subdivide"),
])
def test_window_search_rejects_bad_input(kwargs, needle):
    args = {"clearances": [0.0, 1.0], "tol": TOL, **kwargs}
    with pytest.raises(ValueError, match=needle):
        find_windows(synthetic, args.pop("clearances"), TARGET, args.pop("tol"), **args)


def test_branch_map_finds_the_paper_impact_window_on_a_coarse_grid():
    """One pad length, 5 clearances 5 um apart: the window of paper-impact and its first impact."""
    config = lubelink.resolve_config("paper-impact")
    H0, pad = config.film.clearance, config.film.pad_length
    ds = branch_map([pad], H0 + np.arange(-2, 3) * 5e-6, t_stop=1.4, dx=2.5e-7, xtol=1e-10)
    assert ds.first_impact.dims == ("pad_length", "clearance") and ds.first_impact.attrs["units"] == "s"
    assert ds.attrs["runs"] < 200
    best = widest_window(ds)
    assert best is not None
    k = best[1]
    lo, hi = float(ds.lo[k]), float(ds.hi[k])
    assert lo < H0 < hi
    assert abs(float(ds.first_impact_centre[k]) - PAPER_IMPACT_TIME) <= 2e-3
    # the scenario sits at the centre of the window to within a tenth of its width
    assert abs(H0 - 0.5 * (lo + hi)) < 0.1 * (hi - lo)
    # the edges are where the first impact leaves 1.273 s +- 2 ms, or jumps
    for edge, exit_ in ((lo, str(ds.lo_exit.values[k])), (hi, str(ds.hi_exit.values[k]))):
        assert exit_ in ("tolerance", "jump")
    # checked by fresh runs: inside at the edges, outside 1 nm beyond them (the edges are bracketed to 0.1 nm)
    for H, inside in ((lo, True), (hi, True), (lo - 1e-9, False), (hi + 1e-9, False)):
        t = first_impact_time(lubelink.resolve_config("paper-impact", {"film.clearance": H}), 1.4)
        assert (abs(t - PAPER_IMPACT_TIME) <= 2e-3) == inside, (H, t)


def test_paper_impact_reproduces_the_papers_first_impact():
    ds = lubelink.simulate("paper-impact", set={"output.x_points": 5, "output.pad_points": 11})
    assert ds.impact_time.size >= 1
    first = float(ds.impact_time[0])
    assert abs(first - PAPER_IMPACT_TIME) <= 2e-3
    # the film breaks down only once the link is in the seventh crank turn: nothing before
    assert float(ds.film_min.sel(time=slice(0, first - 1e-3)).min()) > lubelink.resolve_config(
        "paper-impact").contact.min_film
    # after the Zeno sequence of rebounds the link rides on the collar (sustained contact): the run reaches t_end
    assert ds.attrs["status"] == "complete", ds.attrs["message"]
    assert float(ds.time[-1]) == pytest.approx(2.0)

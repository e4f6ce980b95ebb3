"""The up-front cost estimate and the default wall-time budget (issue 15, item 14).

No timing here: the estimate is a function of the configuration, checked against the work it
counts (steps, gap samples) and against the measurements written in lubelink.estimate.
"""

import math
import subprocess
import sys

import pytest

import lubelink
from lubelink.estimate import duration, run_cost


def cost(**overrides):
    return run_cost(lubelink.resolve_config("paper", overrides))


def test_the_two_runs_that_never_finished_are_flagged_up_front():
    tiny_step = cost(**{"solver.max_step": 1e-9, "solver.t_end": 0.2, "solver.method": "DOP853"})  # (as measured)
    assert tiny_step.steps == pytest.approx(2e8)
    assert "solver.max_step = 1e-09 s over solver.t_end = 0.2 s" in tiny_step.reason
    assert 10 * 60 < tiny_step.seconds < 4 * 3600  # measured: about 36 min on the reference machine
    many_modes = cost(**{"beam.modes": 200, "solver.t_end": 0.2})
    assert "samples of the gap" in many_modes.reason and "mode 200" in many_modes.reason
    assert 30 < many_modes.seconds < 600  # measured: 93 s on the reference machine


def test_ordinary_runs_are_estimated_short_and_the_estimate_grows_with_the_work():
    assert cost().seconds < 1.0
    assert cost(**{"beam.modes": 7}).seconds < 1.0
    assert cost(**{"solver.t_end": 20.0}).seconds == pytest.approx(10 * cost().seconds, rel=1e-9)
    assert cost(**{"solver.backend": "numpy"}).seconds > 50 * cost().seconds
    assert cost(**{"solver.method": "RK45"}).seconds > cost().seconds
    dry = run_cost(lubelink.resolve_config("paper-dry", {"beam.modes": 200, "solver.t_end": 0.2}))
    assert dry.seconds < 0.1 * cost(**{"beam.modes": 200, "solver.t_end": 0.2}).seconds  # no gap to watch


def test_durations_read_as_people_say_them():
    assert duration(0.25) == "0.25 s" and duration(600) == "10 min" and duration(7200) == "2 h"
    assert duration(3 * 86400) == "3 days" and duration(math.inf) == "forever"


def test_the_cli_warns_before_a_run_that_its_budget_will_stop(tmp_path):
    r = subprocess.run([sys.executable, "-m", "lubelink", "run", "-q", "--set", "solver.max_step=1e-9",
                        "--set", "solver.t_end=0.2", "--set", "solver.max_wall_time=1", "-o", "r.nc"],
                       cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert r.returncode == 1  # stopped by its budget, the results so far written
    first = r.stderr.strip().splitlines()[0]
    assert first.startswith("lubelink: warning: this run is estimated to take about")
    assert "solver.max_wall_time = 1 s will stop it first" in first
    ds = lubelink.load(tmp_path / "r.nc")
    assert ds.attrs["status"] == "timeout" and ds.attrs["complete"] == 0


def test_the_cli_says_the_budget_in_the_summary_and_the_help(tmp_path):
    r = subprocess.run([sys.executable, "-m", "lubelink", "run", "--set", "solver.t_end=0.1", "--no-output"],
                       cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0 and r.stderr == ""
    assert "(budget solver.max_wall_time = 3600 s)" in r.stdout
    help_text = subprocess.run([sys.executable, "-m", "lubelink", "run", "--help"], capture_output=True,
                               text=True).stdout
    assert "default 3600 s" in " ".join(help_text.split())


def test_the_stiff_film_is_priced_for_the_method_that_runs():
    """At 100 um (``benchmarks/stiff.py``: 0.9 s with 15 modes by RODAS4, about 12 min by the
    exponential method) the estimate knows both, within a factor of a few."""
    stiff = {"film.clearance": 1e-4, "contact.law": "compliant", "beam.modes": 15}
    rodas = run_cost(lubelink.resolve_config("lubricated", stiff))
    assert 0.2 < rodas.seconds < 5.0 and "stiff film" in rodas.reason
    slow = run_cost(lubelink.resolve_config("lubricated", {**stiff, "solver.method": "exponential"}))
    assert 120.0 < slow.seconds < 3600.0 and "not made for a stiff film" in slow.reason


@pytest.mark.parametrize("name", ["paper", "paper-dry", "paper-impact", "lubricated", "spatial-slider-crank"])
def test_the_counted_work_is_that_of_the_run_within_a_factor_of_two(name):
    """The steps and the right-hand-side evaluations the estimate prices against those the run counts (its
    seconds against the measured ones: ``benchmarks/bench.py --only estimate``, not a test)."""
    from lubelink.estimate import EVALS_PER_STEP
    from lubelink.simulate import run

    config = lubelink.resolve_config(name)
    estimate = run_cost(config)
    result = run(config)
    assert 0.5 < estimate.steps / result.nsteps < 2.0
    assert 0.5 < estimate.steps * EVALS_PER_STEP[result.method] / result.nfev < 2.0

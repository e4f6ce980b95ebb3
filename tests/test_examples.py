"""The examples in examples/ run and show what they say they show."""

import importlib.util
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def load(name):
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_custom_motion_is_quasi_static():
    # crank 1 Hz against omega_1 = 148 rad/s: dynamic factor (2 pi/148)^2 ~ 2e-3, damping lag 2 zeta
    # omega/omega_1 ~ 4e-2 of the peak, so 10 % is a loose but failing-when-wrong bound
    assert load("custom_motion").main(t_end=1.0) < 0.1


def test_film_models_cavitation_matters_with_the_crank_reversed():
    rows = load("film_models").main(t_end=0.6)
    paper, reverse = "paper's crank sense", "crank reversed"
    peak = {key: value[0] for key, value in rows.items()}
    # paper's sense: the squeeze film damps, the wedge film alone does not (docs/paper.md, Fig. 7)
    assert peak[paper, "wedge+squeeze"] < 0.95 * peak[paper, "dry"]
    assert peak[paper, "wedge (paper)"] == pytest.approx(peak[paper, "dry"], rel=0.05)
    # reversed: the wedge pressure is sub-ambient on the whole pad. Without cavitation the suction
    # pulls the link onto the collar and the film breaks down; clipped at ambient, nothing is left
    # of it (a force of a few percent of the unclipped one at most) and the link moves as if dry.
    assert rows[reverse, "wedge (paper)"][2] == "film_breakdown"
    assert rows[reverse, "wedge, half-Sommerfeld"][2] == "complete"
    assert rows[reverse, "wedge, half-Sommerfeld"][1] < 0.02 * rows[reverse, "wedge (paper)"][1]
    assert peak[reverse, "wedge, half-Sommerfeld"] == pytest.approx(peak[reverse, "dry"], rel=1e-3)
    # and the example shows half-Sommerfeld differing from the unclipped film (issue 16, item 11)
    assert peak[reverse, "wedge, half-Sommerfeld"] != pytest.approx(peak[reverse, "wedge (paper)"], rel=1e-3)

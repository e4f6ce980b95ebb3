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


def test_squeeze_film_damps_and_wedge_does_not():
    peaks = load("film_models").main(t_end=0.6)
    assert peaks["wedge+squeeze"] < 0.95 * peaks["dry"]
    assert peaks["wedge (paper)"] == pytest.approx(peaks["dry"], rel=0.05)

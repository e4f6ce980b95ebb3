"""The two-process first compile (lubelink._prewarm): its protocol and what makes it effective."""

import subprocess
import sys
import time

import pytest

from lubelink import _jit, _prewarm
from lubelink.config import from_dict, parse_toml, resolve, to_toml
from lubelink.integrate.driver import signatures
from lubelink.model import build_model, rhs
from lubelink.simulate import run

pytestmark = pytest.mark.skipif(not _jit.ENABLED, reason="Numba disabled")

CASES = [("paper", {}), ("paper-dry", {"beam.modes": 5}), ("paper-impact", {}),
         ("paper", {"film.cavitation": "reynolds", "film.sides": 2, "film.model": "wedge+squeeze"}),
         ("paper", {"contact.law": "compliant", "beam.modes": 3})]


@pytest.mark.parametrize("name, overrides", CASES)
def test_the_helper_rebuilds_the_same_parameter_types_from_the_toml(name, overrides):
    """The helper gets the configuration as TOML: its kernels must be the parent's, type for type."""
    model = build_model(resolve(name, overrides))
    again = build_model(from_dict(parse_toml(to_toml(model.config), "<test>")))
    assert again.params_type == model.params_type


def test_a_warm_cache_starts_no_helper_and_an_unseen_signature_is_cold():
    model = build_model(resolve("paper", {"solver.t_end": 2e-3}))
    run(model.config)  # compiled, hence cached
    assert _prewarm._cached(rhs, signatures(model.params_type)[0].args)
    assert _prewarm.start(model) is None
    assert not _prewarm._cached(rhs, ("not", "a", "signature"))


def test_the_helper_reports_each_kernel_and_ends():
    model = build_model(resolve("paper", {"solver.t_end": 2e-3}))
    run(model.config)
    p = subprocess.run([sys.executable, "-m", "lubelink._prewarm"], input=to_toml(model.config), text=True,
                       capture_output=True, timeout=600)
    assert p.returncode == 0, p.stderr
    assert p.stdout.split() == ["rhs", "gap"]


def test_the_driver_compiled_from_types_is_the_one_a_run_calls():
    """``precompile`` builds the driver's argument types from the signatures alone (no right-hand
    side compiled): the run must find that overload and compile no other."""
    from lubelink import integrate
    from lubelink.integrate import driver
    from lubelink.simulate import method_name

    model = build_model(resolve("paper-dry", {"solver.t_end": 2e-3, "beam.modes": 2}))
    driver.precompile(integrate.method(method_name(model.config)), model.params_type)
    before = set(driver.advance.overloads)
    run(model.config)
    assert set(driver.advance.overloads) == before


def _script(code):
    return subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE)


def test_wait_returns_when_the_kernels_are_reported_or_the_helper_ends_or_the_limit_passes():
    done = _script("print('rhs'); print('gap', flush=True); import time; time.sleep(30)")
    t0 = time.monotonic()
    _prewarm.wait(done)
    assert time.monotonic() - t0 < 20
    done.kill()
    dead = _script("print('rhs')")  # ends before 'gap'
    t0 = time.monotonic()
    _prewarm.wait(dead)
    assert time.monotonic() - t0 < 20
    for stuck in (_script("import time; time.sleep(30)"), _script("print('nocache', flush=True); "
                                                                    "import time; time.sleep(30)")):
        t0 = time.monotonic()
        _prewarm.wait(stuck, limit=1.0)
        assert time.monotonic() - t0 < 5
        stuck.kill()
        stuck.wait()
    _prewarm.wait(None)  # nothing started: nothing to wait for

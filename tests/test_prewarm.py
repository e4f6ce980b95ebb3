"""The two-process first compile (lubelink._prewarm): its protocol and what makes it effective."""

import os
import subprocess
import sys
import time

import numpy as np
import pytest

from lubelink import _jit, _prewarm
from lubelink.config import from_dict, parse_toml, resolve, to_toml
from lubelink.integrate.driver import signatures
from lubelink.link.model import rhs
from lubelink.build import build_model
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


# ---------------------------------------------------------------- a cold short run: Python, compiling beside
def _first(monkeypatch, tmp_path, warm=False, busy=False, limit=None):
    """``first_run`` of ``paper`` with the cache state (``warm``: True, False, or ``"rhs"``: the right-hand side
    only), the lock and the limit given."""
    monkeypatch.setenv("LUBELINK_FIRST_RUN", "python")
    monkeypatch.setattr(_prewarm, "_is_warm", lambda dispatcher, args: warm is True or (warm == "rhs" and dispatcher is rhs))
    monkeypatch.setattr(_prewarm, "_WARM", {})
    monkeypatch.setattr(_prewarm, "_lock_path", lambda dispatcher: str(tmp_path / "compile.lock"))
    started = []
    monkeypatch.setattr(_prewarm.subprocess, "Popen", lambda *a, **k: started.append(a) or _NoProcess())
    monkeypatch.setattr(_prewarm, "compile_on_two_cores", lambda model, motion=None: started.append("compile"))
    if limit is not None:
        monkeypatch.setattr(_prewarm, "FIRST_RUN_LIMIT", limit)
    model = build_model(resolve("paper", {"solver.t_end": 0.2}))
    if busy:
        import fcntl
        import os

        fd = os.open(tmp_path / "compile.lock", os.O_RDWR | os.O_CREAT)
        fcntl.flock(fd, fcntl.LOCK_EX)
    return model, _prewarm.first_run(model), started


class _NoProcess:
    pid = 0
    stdin = type("Sink", (), {"write": lambda self, b: None, "close": lambda self: None})()

    def poll(self):
        return 0


def test_a_warm_cache_runs_compiled_and_starts_nothing(monkeypatch, tmp_path):
    model, chosen, started = _first(monkeypatch, tmp_path, warm=True)
    assert chosen is model and chosen.compiled and started == []


def test_a_cold_short_run_runs_as_python_and_compiles_in_the_background(monkeypatch, tmp_path):
    model, chosen, started = _first(monkeypatch, tmp_path)
    assert not chosen.compiled and chosen.params is model.params
    assert "background" in chosen.backend_note and len(started) == 1
    assert started[0][0][-2:] == ["lubelink._background", str(tmp_path / "compile.lock")]


def test_a_cold_long_run_compiles_in_the_foreground(monkeypatch, tmp_path):
    model, chosen, started = _first(monkeypatch, tmp_path, limit=0.0)
    assert chosen is model and started == ["compile"]
    said = []
    monkeypatch.setattr(_prewarm, "_WARM", {})
    assert _prewarm.first_run(model, say=said.append) is model and said == [_prewarm.COMPILING]


def test_while_a_background_compile_runs_a_short_run_is_python_and_starts_no_second(monkeypatch, tmp_path):
    model, chosen, started = _first(monkeypatch, tmp_path, warm="rhs", busy=True)  # rhs cached, the rest not yet
    assert not chosen.compiled and "being built in the background" in chosen.backend_note and started == []


def test_while_a_background_compile_runs_a_cached_run_runs_compiled(monkeypatch, tmp_path):
    """Issue 37 item 6: a held lock sent a configuration whose kernels were all cached to Python (a 1.5 s
    compiled run became a 30 s timeout). The right-hand side, the method's step and the driver cached: compiled."""
    model, chosen, started = _first(monkeypatch, tmp_path, warm=True, busy=True)
    assert chosen is model and chosen.compiled and started == []


def test_a_run_of_the_session_is_cached_beyond_its_right_hand_side():
    """``_run_is_cached`` reads the on-disk cache of the method's step and the driver (the session compiled
    ``paper``'s kernels before the tests), and says no for a method whose step is not compiled for the type."""
    import numba

    model = build_model(resolve("paper", {"solver.t_end": 2e-3, "solver.method": "DOP853"}))
    run(model.config)
    assert _prewarm._run_is_cached(model.config, model.params_type)
    other = numba.typeof(np.zeros((1, 1, 1), dtype=np.int32))  # a type no test integrates with (a float64
    # vector is one: the integrator's own tests run DOP853 on it)
    assert not _prewarm._run_is_cached(model.config, other)


def test_kernels_ready_says_whether_a_run_would_compile(tmp_path):
    """What a sweep's pilot asks first: yes for a run of the session (compiled, cached), and for the ``numpy``
    backend (nothing to compile); no for the spatial link (not checked) and in a process with an empty cache."""
    config = resolve("paper", {"solver.t_end": 2e-3})
    run(config)
    assert _prewarm.kernels_ready(config)
    assert _prewarm.kernels_ready(resolve("paper", {"solver.backend": "numpy"}))
    assert not _prewarm.kernels_ready(resolve("spatial-slider-crank"))
    code = "from lubelink import _prewarm, config; print(_prewarm.kernels_ready(config.resolve('paper')))"
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300,
                       env={**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)})
    assert r.returncode == 0 and r.stdout.strip() == "False", r.stderr


@pytest.mark.parametrize("env, compiles", [({"LUBELINK_FIRST_RUN": "compile"}, True), ({"LUBELINK_PREWARM": "0"}, False)])
def test_the_environment_turns_it_off(monkeypatch, tmp_path, env, compiles):
    """``LUBELINK_FIRST_RUN=compile`` compiles first on two cores, ``LUBELINK_PREWARM=0`` leaves the compile to
    the run (where each kernel is first called)."""
    model, _, started = _first(monkeypatch, tmp_path)
    started.clear()
    for name, value in env.items():
        monkeypatch.setenv(name, value)
    assert _prewarm.first_run(model) is model
    assert started == (["compile"] if compiles else [])


def test_the_numpy_estimate_prices_the_results_of_a_film_only():
    from lubelink.estimate import results_cost

    wet = resolve("paper", {"solver.backend": "numpy"})
    assert 1.0 < results_cost(wet) < 5.0  # measured 2.1 s on the 2-core machine (estimate.py)
    assert results_cost(resolve("paper-dry", {"solver.backend": "numpy"})) < 0.01
    assert results_cost(resolve("paper")) < 0.05  # compiled: milliseconds


@pytest.mark.skipif(os.name != "posix", reason="the background compile is POSIX only")
def test_a_cold_first_run_end_to_end_then_a_compiled_run_with_the_same_results(tmp_path):
    """Through the command, on an empty cache: the first run is Python and names the background
    compile's pid; once that process has ended, the same run is compiled and agrees."""
    import os
    import re

    import lubelink

    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache"), "LUBELINK_FIRST_RUN": "python"}
    args = ["run", "paper", "-q", "--set", "solver.t_end=0.2", "--set", "output.x_points=11"]
    first = subprocess.run([sys.executable, "-m", "lubelink", *args, "-o", "a.nc"], cwd=tmp_path, env=env,
                           capture_output=True, text=True, timeout=300)
    assert first.returncode == 0, first.stderr
    ds = lubelink.load(tmp_path / "a.nc")
    assert ds.attrs["backend"] == "numpy" and "background" in ds.attrs["backend_note"]
    pid = int(re.search(r"pid (\d+)", ds.attrs["backend_note"]).group(1))
    deadline = time.monotonic() + 600
    while os.path.exists(f"/proc/{pid}") and time.monotonic() < deadline:
        time.sleep(0.5)
    second = subprocess.run([sys.executable, "-m", "lubelink", *args, "-o", "b.nc"], cwd=tmp_path, env=env,
                            capture_output=True, text=True, timeout=300)
    assert second.returncode == 0, second.stderr
    again = lubelink.load(tmp_path / "b.nc")
    assert again.attrs["backend"] == "numba" and again.attrs["backend_note"] == ""
    assert abs(again["u2_mid"] - ds["u2_mid"]).max() < 1e-9  # [m]; the peak is 2.7 mm


LOST_CTRL_C = """
import contextlib, ctypes, os, signal, sys, time
from lubelink._prewarm import ctrl_c_while_compiling

def inside():  # Python called back from C, as LLVM's object cache calls Numba while it compiles
    os.kill(os.getpid(), signal.SIGINT)
    for _ in range(10000):
        sum(range(10))

callback = ctypes.CFUNCTYPE(None)(inside)
began = time.monotonic()
try:
    with ctrl_c_while_compiling() if sys.argv[1] == "guarded" else contextlib.nullcontext():
        callback()
        while time.monotonic() < began + 3:
            time.sleep(0.001)
    print("finished")
except KeyboardInterrupt:
    print(f"interrupted after {time.monotonic() - began:.3f} s")
"""


@pytest.mark.skipif(not hasattr(__import__("signal"), "setitimer"), reason="POSIX timers")
def test_a_ctrl_c_lost_in_a_callback_from_the_compiler_interrupts_all_the_same(tmp_path):
    """Ctrl-C inside a ctypes callback (where Numba's compilation runs Python) is printed as "Exception
    ignored" and lost: the program goes on. Inside ``ctrl_c_while_compiling`` it is raised again and
    leaves the block within a fraction of a second, with nothing else said."""
    import signal

    script = tmp_path / "lost.py"
    script.write_text(LOST_CTRL_C)
    out = {}
    for mode in ("bare", "guarded"):
        r = subprocess.run([sys.executable, str(script), mode], capture_output=True, text=True, timeout=60,
                           preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
        assert r.returncode == 0, r.stderr
        out[mode] = r
    assert out["bare"].stdout.strip() == "finished" and "Exception ignored" in out["bare"].stderr
    said = out["guarded"].stdout.strip()
    assert out["guarded"].stderr == ""  # the lost one is not reported: it is raised again
    assert said.startswith("interrupted after") and float(said.split()[2]) < 1.0, said


@pytest.mark.skipif(not _jit.ENABLED, reason="Numba is off")
def test_a_compile_is_announced_once_and_a_compiled_function_not_at_all():
    import numba

    @numba.njit
    def twice(x):
        return 2.0 * x

    said = []
    with _prewarm.announcing(said.append) as once:
        assert twice(1.0) == 2.0 and twice(2) == 4  # two compilations (float, int): one announcement
    assert said == [_prewarm.COMPILING]
    with _prewarm.announcing(said.append) as once:
        twice(3.0)  # compiled already: nothing said
        once("first_run's own line")  # the once-only say given to first_run
        once("a second line")
    assert said == [_prewarm.COMPILING, "first_run's own line"]
    with _prewarm.announcing(None) as once:
        assert once is None

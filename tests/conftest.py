import os

import pytest
from hypothesis import settings

# CI runs a bounded fuzz; `HYPOTHESIS_PROFILE=long pytest` (or `thorough`, 10000 examples) explores more locally.
settings.register_profile("ci", max_examples=60, deadline=None)
settings.register_profile("long", max_examples=2000, deadline=None)
settings.register_profile("thorough", max_examples=10_000, deadline=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

# A cold short run would run as Python beside a background compile (lubelink._prewarm.first_run):
# the tests compile in the foreground, as they did, except those of that feature.
os.environ.setdefault("LUBELINK_FIRST_RUN", "compile")
# Most of a cold suite's time is Numba compiling; LLVM's optimisation level 1 instead of 3 compiles the `paper`
# kernels with 0.82x the CPU (42 s against 51 s) and leaves the arithmetic, and so every result, as it is (the
# suite checks results, benchmarks/ measures speed at the default level). Set before Numba is imported.
os.environ.setdefault("NUMBA_OPT", "1")

#: A short run of the paper's mechanism, enough for end-to-end checks.
SHORT = {"solver.t_end": 0.3, "solver.output_step": 1e-3, "output.x_points": 21, "output.pad_points": 11}


def central_differences(f, x, steps):
    """The Jacobian of ``f`` at ``x`` by central differences of step ``steps[k]`` in ``x[k]`` (the Jacobian tests'
    second method)."""
    import numpy as np

    J = np.empty((f(x).size, x.size))
    for k in range(x.size):
        e = np.zeros(x.size)
        e[k] = steps[k]
        J[:, k] = (f(x + e) - f(x - e)) / (2 * steps[k])
    return J


@pytest.fixture
def short():
    return dict(SHORT)


def pytest_configure(config):
    """Compile the kernels once, in the controlling process, before pytest-xdist starts its workers.

    The workers then load them from Numba's on-disk cache instead of each compiling them (the
    first compilation takes about a minute of CPU on a 2-core machine).
    """
    if hasattr(config, "workerinput"):  # a worker: the controller has compiled
        return
    import sys

    from lubelink.warmup import compile_all

    print(f"lubelink.warmup.compile_all: {compile_all():.0f} s", file=sys.stderr)


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    """Keep the cases of a parametrized test on one xdist worker (``--dist loadgroup``, by the test's name).

    Its cases mostly share a kind of configuration, whose kernels the first case compiles and the others find in
    memory; spread over two workers at the same moment, both would compile them (a cold suite compiled the 2-D
    film's kernels twice, 70 s each, for two cases of one test).
    """
    for item in items:
        if getattr(item, "callspec", None) is not None and item.get_closest_marker("xdist_group") is None:
            item.add_marker(pytest.mark.xdist_group(item.nodeid.split("[", 1)[0]))


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    """With ``LUBELINK_COMPILE_LOG=FILE``, append each test's compilation time in its own process [s] to ``FILE``
    (a tab-separated line: seconds, test): what a cold suite spends compiling, test by test."""
    path = os.environ.get("LUBELINK_COMPILE_LOG")
    if not path:
        yield
        return
    import time

    from numba.core import event

    class Clock(event.Listener):
        depth, start, seconds = 0, 0.0, 0.0

        def on_start(self, ev):
            if self.depth == 0:
                self.start = time.perf_counter()
            self.depth += 1

        def on_end(self, ev):
            self.depth -= 1
            if self.depth == 0:
                self.seconds += time.perf_counter() - self.start

    clock = Clock()
    with event.install_listener("numba:compile", clock):
        yield
    if clock.seconds > 0.0:
        with open(path, "a") as f:
            f.write(f"{clock.seconds:.1f}\t{item.nodeid}\n")

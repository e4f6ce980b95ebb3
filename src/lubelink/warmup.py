"""Compile every kernel once (or load it from the on-disk cache): ``lubelink compile``.

The first run in a new environment compiles the kernels it needs, which takes tens of seconds;
they are cached on disk (:mod:`lubelink._jit`) and shared by every configuration whose parameters
have the same types: the values do not matter, but an option that adds or removes a table does
(a cavitation grid, rough surfaces, a contact law, the spatial link). :func:`compile_all` pays it
up front for every compiled method and every built-in scenario: before a test session, on each
worker of a cluster, or in a container image; ``tests/test_warmup.py`` checks that nothing a
built-in scenario or the steady-state commands run compiles after it.

With two cores a second process compiles the spatial link and the film scenarios' kinds (:data:`SECOND`) while this
one compiles the rest; this process then runs those steps too, which loads what the other wrote
(and compiles anything the other's cache writes lost to a race on a shared index file).
"""

from __future__ import annotations

import os
import subprocess
import sys
import time

__all__ = ["compile_all", "steps", "SECOND"]

METHODS = ("auto", "DOP853", "bulirsch-stoer", "exponential", "exponential-adams", "rodas")

#: The steps a second process takes (the spatial link and the film scenarios' kinds: about half the work of a cold
#: :func:`compile_all`).
SECOND = ("spatial", "variational spatial", "scenario spatial-slider-crank", "compliant results",
          "scenario paper-impact", "scenario lubricated", "scenario guide", "scenario guide-mixed")


def _short(name, **overrides):
    from .config import resolve

    return resolve(name, {"solver.t_end": 2e-3, "solver.output_step": 1e-3, **overrides})


def _method(method, results=False):
    from ._prewarm import compile_on_two_cores
    from .build import build_model
    from .results import to_dataset
    from .simulate import run

    # a film, its events, two modes: every branch the kernels have is compiled with them
    config = _short("paper", **{"beam.modes": 2, "solver.method": method})
    model = build_model(config)
    compile_on_two_cores(model)  # (a helper process compiles the right-hand side and the gap the first time)
    result = run(config, model=model)
    if results:
        to_dataset(result)


def _compliant_results():
    from .results import to_dataset
    from .simulate import run

    # the results of a compliant contact (its batched force kernel)
    to_dataset(run(_short("paper", **{"beam.modes": 2, "film.clearance": 1e-4, "contact.law": "compliant",
                                      "contact.min_film": 1e-6, "solver.t_end": 7e-3})))


def _spatial():
    from .results import to_dataset
    from .simulate import run

    for method in ("exponential", "DOP853"):  # its parameters have a type of their own: the methods again
        spatial_run = run(_short("spatial-slider-crank", **{"beam.modes": 2, "solver.method": method}))
    to_dataset(spatial_run)


def _variational(spatial=False):
    import numpy as np

    from .build import build_model
    from .config import resolve
    from .steady.variational import flow_with_jacobian

    configs = ((resolve("spatial-slider-crank", {"beam.modes": 2}),) if spatial
               else (resolve("paper", {"beam.modes": 2}), resolve("paper-dry")))
    for config in configs:
        m = build_model(config)
        n = m.initial_state().size
        flow_with_jacobian(m.functions()[0], m.params, 0.0, np.zeros(n), 1e-3, np.ones(n), p_type=m.params_type,
                           jacobian=not m.jacobian_missing(None))


def _scenario(name):
    from ._prewarm import compile_on_two_cores, compile_results
    from .build import build_model
    from .simulate import run

    config = _short(name)
    model = build_model(config)
    compile_on_two_cores(model)
    run(config, model=model)
    compile_results(model)


def steps(methods=METHODS):
    """The steps of :func:`compile_all`, ``{name: (message, callable)}`` in order."""
    from .config import SCENARIOS

    out = {f"method {m}": (f"compiling the right-hand side, the gap and {m}", lambda m=m: _method(m))
           for m in methods}
    out["results"] = ("compiling the results", lambda: _method(methods[-1], results=True))
    out["compliant results"] = ("compiling the results of a compliant contact", _compliant_results)
    out["spatial"] = ("compiling the spatial model (beam.model = 'spatial')", _spatial)
    out["variational"] = ("compiling the variational equations (lubelink periodic, lubelink continue)", _variational)
    out["variational spatial"] = ("compiling the spatial link's variational equations",
                                  lambda: _variational(spatial=True))
    # every built-in scenario: a film option given or not (a cavitation table, rough surfaces, a contact law) changes
    # the parameters' type, and with it the kernels and the method its "auto" chooses
    for name in SCENARIOS:
        out[f"scenario {name}"] = (f"compiling the scenario {name}", lambda name=name: _scenario(name))
    return out


def _second_process(names):
    """A process taking the steps ``names`` (``python -m lubelink.warmup NAME ...``), or None."""
    from ._prewarm import cores

    if not names or cores() < 2:
        return None
    try:
        return subprocess.Popen([sys.executable, "-m", "lubelink.warmup", *names], stdin=subprocess.DEVNULL,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=dict(os.environ))
    except OSError:
        return None


def compile_all(methods=METHODS, progress=None, processes=2):
    """Compile (or load) the kernels of ``methods``, of the built-in scenarios and of the results; return the
    wall time [s].

    Parameters
    ----------
    methods : sequence of str
        ``solver.method`` values to prepare (the default: every compiled method).
    progress : callable, optional
        ``progress(message)`` before each step.
    processes : int
        2: a second process takes the steps of :data:`SECOND` at the same time (with two cores); 1: all here.
    """
    from . import _jit

    start = time.perf_counter()
    if not _jit.ENABLED:
        return 0.0
    todo = steps(methods)
    second = [n for n in SECOND if n in todo]
    other = _second_process(second) if processes > 1 else None
    later = second if other is not None else []
    ended = False
    for name, (message, step) in todo.items():
        if name in later:
            continue
        if progress:
            progress(message)
        step()
        if progress and other is not None and not ended and other.poll() is not None:
            ended = True
            progress(f"(the second process has ended, {time.perf_counter() - start:.0f} s in)")
    if other is not None:
        if progress:
            progress("waiting for the second process")
        other.wait()
        for name in later:  # loads what it wrote
            message, step = todo[name]
            if progress:
                progress(message + " (loading)")
            step()
    return time.perf_counter() - start


if __name__ == "__main__":
    table = steps()
    for step_name in sys.argv[1:]:
        table[step_name][1]()

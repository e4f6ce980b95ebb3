"""Compile every kernel once (or load it from the on-disk cache): ``lubelink compile``.

The first run in a new environment compiles the kernels it needs, which takes tens of seconds;
they are cached on disk (:mod:`lubelink._jit`) and shared by every configuration whose parameters
have the same types: the values do not matter, but an option that adds or removes a table does
(a cavitation grid, rough surfaces, a contact law, the spatial link). :func:`compile_all` pays it
up front for every compiled method and every built-in scenario: before a test session, on each
worker of a cluster, or in a container image; ``tests/test_warmup.py`` checks that nothing a
built-in scenario or the steady-state commands run compiles after it.
"""

from __future__ import annotations

import time

__all__ = ["compile_all"]


def compile_all(methods=("auto", "DOP853", "bulirsch-stoer", "exponential", "exponential-adams", "rodas"),
                progress=None):
    """Compile (or load) the kernels of ``methods`` and of the results; return the wall time [s].

    Parameters
    ----------
    methods : sequence of str
        ``solver.method`` values to prepare (the default: every compiled method).
    progress : callable, optional
        ``progress(message)`` before each step.
    """
    from . import _jit
    from ._prewarm import compile_on_two_cores, compile_results
    from .build import build_model
    from .config import SCENARIOS, resolve
    from .results import to_dataset
    from .simulate import run

    start = time.perf_counter()
    if not _jit.ENABLED:
        return 0.0
    for method in methods:
        if progress:
            progress(f"compiling the right-hand side, the gap and {method}")
        # a film, its events, two modes: every branch the kernels have is compiled with them
        config = resolve("paper", {"beam.modes": 2, "solver.method": method, "solver.t_end": 2e-3,
                                   "solver.output_step": 1e-3})
        model = build_model(config)
        compile_on_two_cores(model)  # (a helper process compiles the right-hand side and the gap the first time)
        result = run(config, model=model)
    if progress:
        progress("compiling the results")
    to_dataset(result)
    # the results of a compliant contact (its batched force kernel)
    to_dataset(run(resolve("paper", {"beam.modes": 2, "film.clearance": 1e-4, "contact.law": "compliant",
                                     "contact.min_film": 1e-6, "solver.t_end": 7e-3, "solver.output_step": 1e-3})))
    if progress:
        progress("compiling the spatial model (beam.model = 'spatial')")
    for method in ("exponential", "DOP853"):  # its parameters have a type of their own: the methods again
        spatial_run = run(resolve("spatial-slider-crank", {"beam.modes": 2, "solver.method": method,
                                                           "solver.t_end": 2e-3, "solver.output_step": 1e-3}))
    to_dataset(spatial_run)
    if progress:
        progress("compiling the variational equations (lubelink periodic, lubelink continue)")
    import numpy as np

    from .steady.variational import flow_with_jacobian

    dry, spatial = resolve("paper-dry"), resolve("spatial-slider-crank", {"beam.modes": 2})
    for m in (model, build_model(dry), build_model(spatial)):
        n = m.initial_state().size
        flow_with_jacobian(m.functions()[0], m.params, 0.0, np.zeros(n), 1e-3, np.ones(n), p_type=m.params_type,
                           jacobian=not m.jacobian_missing(None))
    # every built-in scenario: a film option given or not (a cavitation table, rough surfaces, a contact law) changes
    # the parameters' type, and with it the kernels and the method its "auto" chooses
    for name in SCENARIOS:
        if progress:
            progress(f"compiling the scenario {name}")
        config = resolve(name, {"solver.t_end": 2e-3, "solver.output_step": 1e-3})
        model = build_model(config)
        compile_on_two_cores(model)
        run(config, model=model)
        compile_results(model)
    return time.perf_counter() - start

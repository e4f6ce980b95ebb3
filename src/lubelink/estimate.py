"""Up-front cost of a run: an order-of-magnitude estimate of its wall time, from the configuration.

Nothing is integrated: the estimate counts the work the configuration implies and prices it
with costs measured on a 2-core laptop-class machine (compiled backend; a faster machine runs
faster). It is meant to catch the runs that would take hours before they start (a tiny
``solver.max_step``, hundreds of modes), not to time a normal run, which it puts well below a
second (start-up, compilation or loading the compiled code, and writing the file come on top).
Measured against it on that machine: ``solver.max_step = 1e-9`` over ``t_end = 0.2`` s is estimated
at 37 min and ran 2.8e5 steps in its first 3 s (36 min in all); 200 modes over 0.2 s are estimated
at 82 s and ran in 93 s.

The work counted:

* **steps**: at least ``t_end / max_step``; for the explicit methods (DOP853, RK45,
  Bulirsch-Stoer) at least ``t_end * omega_N / 5`` (their stability limit on the fastest mode);
  at least 250 per simulated second (what the tolerances ask of the paper's mechanism);
* **right-hand-side evaluations**: the steps times the evaluations of one step of the method,
  each priced by the film quadrature (``modes x quadrature_nodes``), the Reynolds cavitation
  grid, and the Python overhead of SciPy's methods or of the ``numpy`` backend;
* **gap samples** (film or contact law on): the event detector samples the gap every quarter
  period of the fastest mode (:func:`lubelink.simulate.event_resolution`), each sample costing
  ``modes x quadrature_nodes``; this is what makes 200 modes slow.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["Estimate", "run_cost", "results_cost", "duration"]

#: Right-hand-side evaluations per step (the exponential Adams method: two, and its fit and sums over
#: the tables, which cost about one more with one mode: 2.9 us a step of ``paper`` at a fixed step
#: against 0.93 us an evaluation).
EVALS_PER_STEP = {"DOP853": 12, "RK45": 6, "bulirsch-stoer": 9, "exponential": 7, "exponential-adams": 3, "Radau": 7,
                  "BDF": 3, "LSODA": 3, "rodas": 7}
#: The stiff method's steps per simulated second on a stiff film (``benchmarks/stiff.py``: 3,800-4,900 at
#: 100 um with 15-63 modes), and the cost of its analytic Jacobian [s] per ``N^2 nodes + N nodes^2`` and
#: film side (the LU factorisation is included: fitted to 92, 216 and 681 us a step with 15, 31, 63 modes).
STIFF_STEPS_PER_SECOND, JACOBIAN_PER_TERM = 5000.0, 3.2e-9
#: A non-stiff method's steps on a stiff film: at least ``t_end * squeeze_rate * (N / 3)^STIFF_POWER /
#: STIFF_STABILITY``: more modes resolve a deformation local to the pad, which the film damps faster
#: (fitted to the exponential method at the rate 2.6e6 1/s: 1.27e5 steps for 2 s with 3 modes,
#: 1.08e7 with 15).
STIFF_STABILITY, STIFF_POWER = 41.0, 2.76
#: Methods whose step is bounded by the fastest mode: ``h <= STABILITY / omega_N``.
EXPLICIT = ("DOP853", "RK45", "bulirsch-stoer")
#: SciPy's methods: run as Python, step by step.
SCIPY = ("RK45", "Radau", "BDF", "LSODA")
STABILITY = 5.0
#: Steps per simulated second that the default tolerances take on the paper's mechanism.
STEPS_PER_SECOND = 250.0
#: Seconds: one compiled right-hand-side evaluation, and per mode and quadrature node.
EVAL_BASE, EVAL_PER_MODE_NODE = 0.8e-6, 0.004e-6
#: Seconds per point of the Reynolds cavitation grid per evaluation.
EVAL_PER_GRID_POINT = 0.035e-6
#: Seconds per pad grid point and term across the width (``film.reynolds = "2d"``) per evaluation,
#: and per grid point, term and point across the width when that film is clipped (half-Sommerfeld).
EVAL_PER_WIDTH_TERM, EVAL_PER_WIDTH_CLIP = 0.01e-6, 0.001e-6
#: Seconds added per evaluation and per step by SciPy's methods (run as Python).
SCIPY_PER_EVAL, SCIPY_PER_STEP = 40e-6, 100e-6
#: Factor of the ``numpy`` backend (the same source run as Python) on a compiled evaluation.
NUMPY_FACTOR = 200.0
#: Seconds: one sample of the gap, and per mode and quadrature node.
SAMPLE_BASE, SAMPLE_PER_MODE_NODE = 0.3e-6, 0.017e-6
#: Seconds per output sample of the film's results series on the ``numpy`` backend, and per pad
#: point of its pressure field (one mode; a mode more adds half). Measured: ``paper`` (2001 samples,
#: 41 pad points) 2.1 s, with 11 pad points 0.56 ms per sample, with 7 modes 2.9 ms per sample.
RESULTS_PER_SAMPLE, RESULTS_PER_PAD_POINT = 0.38e-3, 16e-6


@dataclass(frozen=True)
class Estimate:
    """Estimated wall time of a run [s], its steps, and what dominates it (a phrase)."""

    seconds: float
    steps: float
    reason: str

    def __str__(self):
        return f"about {duration(self.seconds)} ({self.reason})"


def duration(seconds: float) -> str:
    """``"0.2 s"``, ``"12 min"``, ``"3.1 h"``, ``"4.2 days"``: a duration as people say it."""
    if not math.isfinite(seconds):
        return "forever"
    if seconds < 90:
        return f"{seconds:.2g} s"
    if seconds < 5400:
        return f"{seconds / 60:.2g} min"
    if seconds < 2 * 86400:
        return f"{seconds / 3600:.2g} h"
    return f"{seconds / 86400:.3g} days"


def _fastest_mode(config) -> float:
    from .beam import natural_frequencies

    b = config.beam
    return float(natural_frequencies(b.modes, config.mechanism.rod_length, b.youngs_modulus, b.second_moment,
                                     b.density, b.area)[-1])


def run_cost(config) -> Estimate:
    """Estimated wall time of :func:`lubelink.simulate.run` on a validated configuration."""
    from .choice import film_squeeze_rate, method_name, stiff_reason

    s, b, fm = config.solver, config.beam, config.film
    method = method_name(config)
    omega = _fastest_mode(config)
    n_nodes = b.modes * fm.quadrature_nodes * (fm.sides if fm.enabled else 0)

    floors = [(STEPS_PER_SECOND * s.t_end, "")]
    if math.isfinite(s.max_step):
        floors.append((s.t_end / s.max_step,
                       f"solver.max_step = {s.max_step:.3g} s over solver.t_end = {s.t_end:.3g} s"))
    if method in EXPLICIT:
        floors.append((s.t_end * omega / STABILITY,
                       f"{method} is explicit and mode {b.modes} vibrates at {omega:.3g} rad/s"))
    rate = film_squeeze_rate(config)
    if method == "rodas" and stiff_reason(config):
        floors.append((s.t_end * STIFF_STEPS_PER_SECOND, "a stiff film"))
    elif method not in ("rodas", "Radau", "BDF", "LSODA") and rate > 0.0:
        floors.append((s.t_end * rate * (b.modes / 3.0) ** STIFF_POWER / STIFF_STABILITY,
                       f"{method} is not made for a stiff film: the squeeze film damps at {rate:.3g} 1/s "
                       "(solver.method = 'auto' or 'rodas')"))
    steps, why_steps = max(floors, key=lambda f: f[0])

    per_eval = EVAL_BASE + EVAL_PER_MODE_NODE * n_nodes
    if fm.enabled and fm.reynolds == "2d":
        per_eval += EVAL_PER_WIDTH_TERM * fm.grid_points * fm.width_modes * fm.sides
        if fm.cavitation == "half-sommerfeld":
            per_eval += EVAL_PER_WIDTH_CLIP * fm.grid_points * fm.width_modes * fm.width_points * fm.sides
    elif fm.enabled and (fm.cavitation == "reynolds" or fm.reynolds == "short"):
        per_eval += EVAL_PER_GRID_POINT * fm.grid_points * fm.sides
    if s.backend == "numpy":
        per_eval *= NUMPY_FACTOR
    per_step = EVALS_PER_STEP.get(method, 12) * per_eval
    if method == "rodas":
        N, nodes = b.modes, fm.quadrature_nodes
        per_step += JACOBIAN_PER_TERM * (N * N * nodes + N * nodes * nodes) * max(fm.sides if fm.enabled else 0, 1)
    if method in SCIPY:
        per_step += EVALS_PER_STEP.get(method, 12) * SCIPY_PER_EVAL + SCIPY_PER_STEP
    step_seconds = steps * per_step

    sample_seconds, samples = 0.0, 0.0
    if fm.enabled or config.contact.law != "none":
        samples = s.t_end * omega * 4.0 / (2.0 * math.pi)
        per_sample = SAMPLE_BASE + SAMPLE_PER_MODE_NODE * max(n_nodes, b.modes * fm.quadrature_nodes)
        sample_seconds = samples * per_sample * (NUMPY_FACTOR if s.backend == "numpy" else 1.0)

    if sample_seconds > step_seconds:
        reason = (f"{samples:.2g} samples of the gap, every quarter period of mode {b.modes} "
                  f"({2 * math.pi / omega:.2g} s), with {b.modes} mode(s)")
    else:
        reason = f"{steps:.2g} {method} steps" + (f": {why_steps}" if why_steps else "")
    return Estimate(step_seconds + sample_seconds, steps, reason)


def results_cost(config) -> float:
    """Estimated wall time [s] of the results series (:func:`lubelink.results.collect`) of a
    run on the ``numpy`` backend (compiled, they cost a few milliseconds)."""
    s = config.solver
    if s.backend != "numpy" or not config.film.enabled:
        return 0.0
    per_sample = RESULTS_PER_SAMPLE + RESULTS_PER_PAD_POINT * config.output.pad_points * (
        1.0 + 0.5 * (config.beam.modes - 1)) * config.film.sides
    return (s.t_end / s.output_step + 1.0) * per_sample

"""Up-front cost of a run: an order-of-magnitude estimate of its wall time, from the configuration.

Nothing is integrated: the estimate counts the work the configuration implies and prices it
with costs measured on a 2-core laptop-class machine (compiled backend; a faster machine runs
faster). It catches the runs that would take hours before they start (a tiny ``solver.max_step``,
hundreds of modes) and prices a normal one within a factor of two: ``benchmarks/bench.py --only
estimate`` prints both for every built-in scenario (start-up, compilation or loading the compiled
code, and writing the file come on top).
Measured against it on that machine: ``solver.max_step = 1e-9`` over ``t_end = 0.2`` s is estimated
at 37 min and ran 2.8e5 steps in its first 3 s (36 min in all); 200 modes over 0.2 s are estimated
at 82 s and ran in 93 s.

The work counted:

* **steps**: at least ``t_end / max_step``; for the explicit methods (DOP853, RK45,
  Bulirsch-Stoer) at least ``t_end * omega_N / 5`` (their stability limit on the fastest mode);
  at least 400 per simulated second (what the tolerances ask of the paper's mechanism; 250 without
  a film or a contact law); the
  spatial link's at least ``t_end * omega_a / 3.5`` (its first axial mode, which the methods follow);
* **right-hand-side evaluations**: the steps times the evaluations of one step of the method,
  each priced by the film quadrature (``modes x quadrature_nodes``), the half-Sommerfeld film and
  rough surfaces (per node), the Reynolds cavitation grid, the exponential methods' work on the
  state, and the Python overhead of SciPy's methods or of the ``numpy`` backend;
* **gap samples** (film or contact law on): the event detector samples the gap every quarter
  period of the fastest mode (:func:`lubelink.simulate.event_resolution`), each sample costing
  ``modes x quadrature_nodes``; this is what makes 200 modes slow;
* **the results** (:func:`results_cost`): per output sample, the film's series, the energy's powers
  and the joint reactions evaluate the film about six times; a fixed part builds the model and the
  Dataset;
* **mixed lubrication** (:mod:`lubelink.mixed`, rough surfaces): the collar holds the link against its
  rigid motion's inertial load and the link bends through it, tilting about 10 um across ``guide``'s pad
  whatever the clearance, and it sinks into the collar over the revolutions until the asperities carry
  the joint load; the share of the pad's films within reach of the asperities costs a Greenwood-Tripp
  quadrature per node and evaluation (:data:`GT_INTEGRAL`), the share of the run with the asperities
  loaded adds stiff steps (:data:`LOADED_STEPS`).

Measured against it (``simulate()`` warm, 2026-11-28, ``benchmarks/bench.py --only estimate``): the built-in
scenarios took 0.73-1.32x their estimate on a quiet machine, except ``guide-mixed`` at 2.6x before the
mixed-lubrication share; with it, at a load average of 3-8 on the shared 2-core machine (CPU time; the short
scenarios, whose estimate it leaves alone, took 1.3-3.5x theirs at that load), ``guide`` 0.99-1.06x,
``guide-mixed`` 1.78-2.24x, and ``guide`` along its clearance over 0.5 s (100 to 16 um: 0.61 to 2.55 s of CPU)
0.70-0.90x. Its share of the pad within reach of the asperities (0.05) is 0.19 in the run's first 0.5 s: the
run's pad lies flatter in the collar than the quasi-static tilt, so ``guide-mixed`` stays on the low side.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .mixed import mixed_share

__all__ = ["Estimate", "run_cost", "results_cost", "duration"]

#: Right-hand-side evaluations per step (the exponential Adams method: two, and its fit and sums over
#: the tables, which cost about one more with one mode: 2.9 us a step of ``paper`` at a fixed step
#: against 0.93 us an evaluation; DOP853: 12 stages, its dense output and the gap's samples, 19.6-22
#: measured on ``paper``, ``paper-impact`` and ``lubricated``).
EVALS_PER_STEP = {"DOP853": 20, "RK45": 6, "bulirsch-stoer": 9, "exponential": 7, "exponential-adams": 3, "Radau": 7,
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
#: Steps per simulated second that the default tolerances take on the paper's mechanism with a film or a
#: contact law (424-446 measured with one mode), and without either (238 on ``paper-dry``).
STEPS_PER_SECOND, DRY_STEPS_PER_SECOND = 400.0, 250.0
#: Steps of the spatial link per radian of its first axial mode (``spatial-slider-crank``: 1179 steps over
#: 0.5 s at 8.1e3 rad/s).
AXIAL_RADIANS_PER_STEP = 3.5
#: Seconds: one compiled right-hand-side evaluation, and per mode and quadrature node.
EVAL_BASE, EVAL_PER_MODE_NODE = 0.5e-6, 0.004e-6
#: Seconds per quadrature node and film side: the half-Sommerfeld film's running integral of ``p'``
#: (``paper`` with DOP853: 0.55 -> 2.03 us an evaluation at 32 nodes), and rough surfaces' mean gap
#: and asperity pressure (0.55 -> 2.02 us).
EVAL_PER_CLIPPED_NODE, EVAL_PER_ROUGH_NODE = 0.05e-6, 0.05e-6
#: Seconds per step and squared state size: the exponential methods' work on the state (their phi
#: functions and tables; ``spatial-slider-crank``, 18 states: 13.5 us a step for 7 evaluations of 0.9 us).
EXPONENTIAL_PER_STATE2 = 0.01e-6
#: Seconds of one Greenwood-Tripp integral (``F_{5/2}`` or ``F_{3/2}``, a 256-interval quadrature: 257
#: exponentials), computed at every node within reach of the asperities (:mod:`lubelink.mixed`), at each
#: evaluation and, for the stiff method's Jacobian, once more a step. ``benchmarks/bench.py --only estimate``
#: prints it alone (4.3-7.6 us on the shared 2-core machine); in the runs of ``guide`` at 16 um and of
#: ``guide-mixed``, 4.2 and 3.3 us (their time a step beyond ``guide``'s at 40 um, over the integrals counted).
GT_INTEGRAL = 4.0e-6
#: The stiff method's steps grow by this times the share of the run with the asperities loaded
#: (:attr:`lubelink.mixed.MixedShare.loaded`): the clearance sweep of ``guide`` over 0.5 s (steps 1.17, 1.47,
#: 1.91 times those of 40 um at 25, 20, 16 um; shares 0.06, 0.22, 0.31: 2.1-2.9), and ``guide-mixed`` over
#: 2 s (2.2 times ``guide``'s steps, share 0.22: 5.5).
LOADED_STEPS = 3.0
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
#: Compiled results: seconds per output sample (the state's series), per film side (its pressure and
#: shear), and the film's evaluations per sample that the results make (film force, energy powers,
#: joint reactions), measured: ``paper`` 5.3, ``paper-dry`` 2.2, ``lubricated`` 22, ``guide`` 92 us a
#: sample (CPU time); the spatial link's (three directions, the u3 faces' film) about 4x the planar link's.
RESULTS_BASE, RESULTS_PER_SIDE, RESULTS_EVALS, RESULTS_SPATIAL = 1.5e-6, 2.5e-6, 6.0, 4.0
#: Seconds building the model and the Dataset of a run.
RESULTS_FIXED = 1.5e-3
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

    watched = fm.enabled or config.contact.law != "none"
    floors = [((STEPS_PER_SECOND if watched else DRY_STEPS_PER_SECOND) * s.t_end, "")]
    if math.isfinite(s.max_step):
        floors.append((s.t_end / s.max_step,
                       f"solver.max_step = {s.max_step:.3g} s over solver.t_end = {s.t_end:.3g} s"))
    if method in EXPLICIT:
        floors.append((s.t_end * omega / STABILITY,
                       f"{method} is explicit and mode {b.modes} vibrates at {omega:.3g} rad/s"))
    if b.model == "spatial":
        floors.append((s.t_end * _first_axial_mode(config) / AXIAL_RADIANS_PER_STEP, ""))
    rate = film_squeeze_rate(config)
    mixed = mixed_share(config)
    if method == "rodas" and stiff_reason(config):
        floors.append((s.t_end * STIFF_STEPS_PER_SECOND * (1.0 + LOADED_STEPS * mixed.loaded),
                       "a stiff film" + (f", the asperities loaded {mixed.loaded:.0%} of the run" if mixed.loaded
                                         else "")))
    elif method not in ("rodas", "Radau", "BDF", "LSODA") and rate > 0.0:
        floors.append((s.t_end * rate * (b.modes / 3.0) ** STIFF_POWER / STIFF_STABILITY,
                       f"{method} is not made for a stiff film: the squeeze film damps at {rate:.3g} 1/s "
                       "(solver.method = 'auto' or 'rodas')"))
    steps, why_steps = max(floors, key=lambda f: f[0])

    per_eval = _per_eval(config, mixed)
    if s.backend == "numpy":
        per_eval *= NUMPY_FACTOR
    per_step = EVALS_PER_STEP.get(method, 12) * per_eval
    if method.startswith("exponential"):
        per_step += EXPONENTIAL_PER_STATE2 * (2 * b.modes * (3 if b.model == "spatial" else 1)) ** 2
    if method == "rodas":
        N, nodes = b.modes, fm.quadrature_nodes
        per_step += JACOBIAN_PER_TERM * (N * N * nodes + N * nodes * nodes) * max(fm.sides if fm.enabled else 0, 1)
        per_step += GT_INTEGRAL * mixed.zone * fm.quadrature_nodes * fm.sides
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


def _per_eval(config, mixed=None) -> float:
    """Seconds of one compiled evaluation of the right-hand side (``mixed``: :func:`lubelink.mixed.mixed_share`
    of ``config``, computed when not given)."""
    b, fm = config.beam, config.film
    if not fm.enabled:
        return EVAL_BASE
    nodes = fm.quadrature_nodes * fm.sides
    per_eval = EVAL_BASE + EVAL_PER_MODE_NODE * b.modes * nodes
    if fm.reynolds == "2d":
        per_eval += EVAL_PER_WIDTH_TERM * fm.grid_points * fm.width_modes * fm.sides
        if fm.cavitation == "half-sommerfeld":
            per_eval += EVAL_PER_WIDTH_CLIP * fm.grid_points * fm.width_modes * fm.width_points * fm.sides
    elif fm.cavitation == "reynolds" or fm.reynolds == "short":
        per_eval += EVAL_PER_GRID_POINT * fm.grid_points * fm.sides
    elif fm.cavitation == "half-sommerfeld":
        per_eval += EVAL_PER_CLIPPED_NODE * nodes
    if fm.roughness > 0.0:
        per_eval += (EVAL_PER_ROUGH_NODE + GT_INTEGRAL * (mixed or mixed_share(config)).zone) * nodes
    return per_eval


def _first_axial_mode(config) -> float:
    """The spatial link's first axial frequency [rad/s]: ``(pi / L) sqrt(E / rho)``, half that with a free end."""
    b, L = config.beam, config.mechanism.rod_length
    omega = math.pi / L * math.sqrt(b.youngs_modulus / b.density)
    return 0.5 * omega if b.axial_end == "free" else omega


def results_cost(config, mixed=None) -> float:
    """Estimated wall time [s] of the results (:func:`lubelink.results.collect` and the Dataset) of a run
    (``mixed``: as :func:`_per_eval`)."""
    s = config.solver
    samples = s.t_end / s.output_step + 1.0
    if s.backend != "numpy":
        fm = config.film
        per_sample = RESULTS_BASE + RESULTS_EVALS * (_per_eval(config, mixed) - EVAL_BASE)
        if fm.enabled:
            per_sample += RESULTS_PER_SIDE * fm.sides
        if config.beam.model == "spatial":
            per_sample *= RESULTS_SPATIAL
        return RESULTS_FIXED + samples * per_sample
    if not config.film.enabled:
        return RESULTS_FIXED
    per_sample = RESULTS_PER_SAMPLE + RESULTS_PER_PAD_POINT * config.output.pad_points * (
        1.0 + 0.5 * (config.beam.modes - 1)) * config.film.sides
    return RESULTS_FIXED + samples * per_sample

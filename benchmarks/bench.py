"""What a user waits for: ``lubelink.simulate()`` and ``lubelink run`` end to end, and where the time goes.

Printed, in this order (``benchmarks/README.md`` records a run):

1. **simulate** -- ``lubelink.simulate(case)`` end to end (Dataset included) for ``paper`` with 1 and
   7 modes, ``paper-dry`` with 5 and 7 modes and ``paper-impact``: median and minimum of
   ``--repeats`` warm calls, split into the integration (``simulate.run``), sampling the results
   (``results.collect``) and wrapping them in xarray; with the method, evaluations and steps.
2. **run** -- ``lubelink run -o FILE`` as a whole process (interpreter start, imports, compiled
   kernels loaded from the cache, integration, NetCDF written), median of ``--repeats``.
3. **scipy** -- the naive modal model: ``scipy.integrate.solve_ivp(method="DOP853")`` on the same
   right-hand side run as NumPy (``solver.backend = "numpy"``), dry, 7 modes, at the same
   tolerances, against ``simulate("paper-dry")`` with 7 modes timed in the same run.
4. **methods** -- every compiled method at the default tolerances on ``paper`` and ``paper-dry``
   for 1, 3, 7 and 15 modes: time of ``simulate.run``, evaluations, steps, and the largest error of
   ``u2`` (all points, all samples) against a tight DOP853 run (rtol 1e-12, atol 1e-15).
5. **compile** -- in fresh processes with an empty ``NUMBA_CACHE_DIR``: ``lubelink run`` cold and
   warm, as installed (a first run as Python beside a background compile, and when that compile
   is done), compiled first with the helper process of :mod:`lubelink._prewarm`, compiled first
   in one process; and ``lubelink compile`` (every kernel).

7. **start** -- whole fresh processes, warm cache, in turn (A B C ...): ``python -c "import
   lubelink; lubelink.simulate('paper')"`` and ``lubelink run`` beside the imports they cannot do
   without (``numpy, scipy``; ``xarray``, which the returned Dataset needs; ``numba, scipy.linalg``,
   which loading a compiled kernel imports; all three: the floor); wall and CPU medians.

``--compare-with PATH`` also times ``simulate()`` and the compiled right-hand side and gap per call
(in a compiled loop) with the lubelink of another checkout (``PATH/src``): one warm process per
checkout, asked in turn (A B A B ...), so that the shared machine's drifting speed cancels in the
ratios.

Times are wall-clock on a shared machine: compare ratios within one run, not across runs.

Usage::

    python benchmarks/bench.py                         # everything (a few minutes on 2 cores)
    python benchmarks/bench.py --only simulate,run --repeats 9
    python benchmarks/bench.py --only simulate --compare-with ../old-checkout
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

CASES = [("paper", 1), ("paper", 7), ("paper-dry", 5), ("paper-dry", 7), ("paper-impact", 1)]
SECTIONS = ("simulate", "run", "scipy", "methods", "compile", "estimate", "start")
TIGHT = {"solver.method": "DOP853", "solver.rtol": 1e-12, "solver.atol": 1e-15}


def machine():
    cpu = platform.processor() or "unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()}, load average {load:.2f}"


def ms(seconds):
    return f"{1e3 * seconds:8.1f} ms"


def timed(fn, repeats):
    """``(median, min, last result)`` of ``repeats`` calls of ``fn`` after one warm-up call."""
    fn()
    times, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times), min(times), result


# --- 1. simulate() end to end ---------------------------------------------------------------------------
SERVER_SNIPPET = """
import sys, time
import numpy as np
import lubelink
from lubelink.config import resolve
try:
    from lubelink.link.model import gap, rhs
except ImportError:  # a checkout before lubelink.link
    from lubelink.model import gap, rhs
try:
    from lubelink.build import build_model
except ImportError:  # a checkout before lubelink.build
    from lubelink.model import build_model
try:
    from lubelink.link.spatial_model import spatial_gap, spatial_rhs
except ImportError:
    try:  # a checkout before lubelink.link
        from lubelink.spatial_model import spatial_gap, spatial_rhs
    except ImportError:  # a checkout without the spatial model
        spatial_gap = spatial_rhs = None
try:
    import numba
except ImportError:
    numba = None

def loops(f, g):
    @numba.njit
    def loop_rhs(n, y, out, p):
        for i in range(n):
            f(0.1 + i * 1e-7, y, out, p)
    @numba.njit
    def loop_gap(n, y, p):
        for i in range(n):
            g(0.1 + i * 1e-7, y, p)
    return loop_rhs, loop_gap

if numba is not None:
    LOOPS = {False: loops(rhs, gap), True: loops(spatial_rhs, spatial_gap) if spatial_rhs is not None else None}
cache = {}


def value(text):
    try:
        return float(text)
    except ValueError:  # a choice
        return text


print("ready", flush=True)
for line in sys.stdin:
    scenario, modes, what, *extra = line.split()
    over = {"beam.modes": int(modes), **{k: value(v) for k, v in (e.split("=") for e in extra)}}
    key = (scenario, modes, *extra)
    if key not in cache:
        model = build_model(resolve(scenario, over))
        p = model.params
        y = np.full(model.initial_state().size, 1e-6 if model.params.spatial is not None else 1e-5)
        fns = LOOPS[model.params.spatial is not None] if numba is not None else None
        cache[key] = (p, y, np.empty_like(y), fns)
        lubelink.simulate(scenario, over)
        if fns is not None:
            fns[0](1, y, cache[key][2], p)
            fns[1](1, y, p)
    p, y, out, fns = cache[key]
    start = time.perf_counter()
    if what == "simulate":
        lubelink.simulate(scenario, over)
        print(time.perf_counter() - start, flush=True)
    elif what == "rhs":
        fns[0](20000, y, out, p)
        print((time.perf_counter() - start) / 20000, flush=True)
    else:
        fns[1](20000, y, p)
        print((time.perf_counter() - start) / 20000, flush=True)
"""


def servers(sources):
    """One warm process per ``src`` folder, timing on request (:data:`SERVER_SNIPPET`): a request is
    ``"SCENARIO MODES simulate|rhs|gap [KEY=VALUE ...]"`` (a number, or the text of a choice), the answer seconds
    (per call for the kernels, in a compiled loop)."""
    procs = []
    for src in sources:
        env = dict(os.environ, PYTHONPATH=str(src), LUBELINK_PREWARM="0")
        proc = subprocess.Popen([sys.executable, "-c", SERVER_SNIPPET], env=env, stdin=subprocess.PIPE,
                                stdout=subprocess.PIPE, text=True)
        if proc.stdout.readline().strip() != "ready":
            raise RuntimeError(f"the lubelink in {src} did not start")
        procs.append(proc)
    return procs


def interleaved(requests, repeats):
    """The minimum of ``repeats`` timings of each ``(process, request)``, asked in turn (A B A B ...)."""
    times = [[] for _ in requests]
    for _ in range(repeats + 1):  # the first round warms up (compiles, fills caches)
        for (proc, request), found in zip(requests, times):
            proc.stdin.write(request + "\n")
            proc.stdin.flush()
            found.append(float(proc.stdout.readline()))
    return [min(found[1:]) for found in times]


def compare(other, repeats):
    """``simulate()`` and the compiled right-hand side and gap per call, this checkout against ``other``,
    timed in turn in two warm processes so that the machine's drifting speed cancels in the ratios."""
    here = Path(__file__).resolve().parents[1] / "src"
    src = Path(other).resolve() / "src"
    print(f"\n   against the lubelink in {src}: two warm processes timed in turn, minimum of {repeats}")
    print(f"{'case':<16}{'modes':>5}  {'what':<10}{'other':>12}{'this':>12}{'this/other':>12}")
    procs = servers([src, here])
    try:
        for scenario, modes in CASES:
            for what in ("simulate", "rhs", "gap"):
                theirs, mine = interleaved([(proc, f"{scenario} {modes} {what}") for proc in procs], repeats)
                unit = (lambda v: f"{1e9 * v:9.0f} ns") if what != "simulate" else ms
                print(f"{scenario:<16}{modes:>5}  {what:<10}{unit(theirs):>12}{unit(mine):>12}{mine / theirs:>11.2f}x")
    finally:
        for proc in procs:
            proc.stdin.close()
            proc.wait()


def bench_simulate(args):
    import lubelink
    from lubelink.config import resolve
    from lubelink.results import collect, dataset
    from lubelink.simulate import run

    print("\n1. simulate() end to end (warm; median and min of", args.repeats, "calls)")
    print(f"{'case':<16}{'modes':>5} {'method':<12}{'simulate':>12}{'min':>12}{'run':>12}{'collect':>12}"
          f"{'xarray':>12}{'nfev':>8}{'steps':>7}")
    rows = []
    for scenario, modes in CASES:
        overrides = {"beam.modes": modes}
        t_sim, t_min, ds = timed(lambda: lubelink.simulate(scenario, overrides), args.repeats)
        config = resolve(scenario, overrides)
        t_run, _, r = timed(lambda: run(config), args.repeats)
        t_col, _, c = timed(lambda: collect(r), args.repeats)
        t_xr, _, _ = timed(lambda: dataset(c), args.repeats)
        print(f"{scenario:<16}{modes:>5} {ds.attrs['solver_method']:<12}{ms(t_sim):>12}{ms(t_min):>12}"
              f"{ms(t_run):>12}{ms(t_col):>12}{ms(t_xr):>12}{r.nfev:>8}{r.nsteps:>7}")
        rows.append((t_sim, t_min))
    if args.compare_with:
        compare(args.compare_with, args.repeats)
    return rows


# --- 2. lubelink run as a process -----------------------------------------------------------------------
def lubelink_process(argv, env=None):
    """Wall time of ``python -m lubelink argv`` as a whole process."""
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "lubelink", *argv], check=True, env=env, capture_output=True)
    return time.perf_counter() - start


def bench_run(args):
    print("\n2. `lubelink run -o FILE` as a whole process (warm cache; median of", args.repeats, "runs)")
    with tempfile.TemporaryDirectory() as tmp:
        for scenario, modes in (("paper", 1), ("paper", 7)):
            argv = ["run", scenario, "--set", f"beam.modes={modes}", "-o", f"{tmp}/out.nc", "--overwrite"]
            times = [lubelink_process(argv) for _ in range(args.repeats + 1)][1:]
            python = [lubelink_process(["--version"]) for _ in range(3)]
            print(f"   {scenario} {modes} mode(s): {ms(statistics.median(times))}  "
                  f"(min {ms(min(times))}; `lubelink --version` {ms(statistics.median(python))})")


# --- 3. the naive SciPy modal model ---------------------------------------------------------------------
def bench_scipy(args):
    from scipy.integrate import solve_ivp

    import lubelink
    from lubelink.config import resolve
    from lubelink.build import build_model

    modes = 7
    config = resolve("paper-dry", {"beam.modes": modes, "solver.backend": "numpy"})
    model = build_model(config)
    rhs = model.functions()[0]
    p = model.params
    s = config.solver
    t_eval = np.arange(0.0, s.t_end + 0.5 * s.output_step, s.output_step)

    def f(t, y):
        out = np.empty_like(y)
        rhs(t, y, out, p)
        return out

    def naive():
        return solve_ivp(f, (0.0, s.t_end), model.initial_state(), method="DOP853", t_eval=t_eval, rtol=s.rtol,
                         atol=s.atol)

    print(f"\n3. the naive SciPy modal model: solve_ivp DOP853 on the NumPy right-hand side, paper-dry, {modes} modes, "
          f"rtol {s.rtol:g}, atol {s.atol:g}")
    start = time.perf_counter()
    sol = naive()
    t_naive = time.perf_counter() - start
    t_sim, _, ds = timed(lambda: lubelink.simulate("paper-dry", {"beam.modes": modes}), args.repeats)
    u2_naive = sol.y[:modes].T @ np.sin(np.outer(np.arange(1, modes + 1) * np.pi / config.mechanism.rod_length,
                                                 ds.x.values))
    err = float(np.max(np.abs(u2_naive - ds.u2.values)))
    print(f"   solve_ivp: {ms(t_naive)} ({sol.nfev} evaluations); lubelink.simulate: {ms(t_sim)} "
          f"({ds.attrs['solver_method']}, {ds.attrs['nfev']} evaluations): {t_naive / t_sim:.0f}x; "
          f"largest difference of u2 {err * 1e6:.3f} um")


# --- 4. the methods against the number of modes ----------------------------------------------------------
def bench_methods(args):
    from lubelink.config import resolve
    from lubelink.results import collect
    from lubelink.simulate import run

    print("\n4. methods at the default tolerances (run only; error: largest |u2 - u2_tight| over x and t)")
    print(f"{'case':<12}{'modes':>5} {'method':<16}{'time':>12}{'nfev':>8}{'steps':>7}{'error [um]':>12}")
    for scenario in ("paper", "paper-dry"):
        for modes in (1, 3, 7, 15):
            base = {"beam.modes": modes}
            tight = collect(run(resolve(scenario, {**base, **TIGHT})))["u2"]
            for method in ("DOP853", "exponential", "bulirsch-stoer"):
                config = resolve(scenario, {**base, "solver.method": method})
                t, _, r = timed(lambda: run(config), max(1, args.repeats // 2))
                err = float(np.max(np.abs(collect(r)["u2"] - tight)))
                print(f"{scenario:<12}{modes:>5} {method:<16}{ms(t):>12}{r.nfev:>8}{r.nsteps:>7}{err * 1e6:>12.4f}")


# --- 5. compilation -------------------------------------------------------------------------------------
def _wait_for(pid):
    """Wait until process ``pid`` has ended (Linux); return the seconds waited."""
    start = time.perf_counter()
    while os.path.exists(f"/proc/{pid}"):
        time.sleep(0.1)
    return time.perf_counter() - start


def bench_compile(args):
    import re

    print("\n5. a first run, each in fresh processes with an empty NUMBA_CACHE_DIR")
    variants = (("as installed (Python beside a background compile)", {}),
                ("compiled first, with the helper process (LUBELINK_FIRST_RUN=compile)", {"LUBELINK_FIRST_RUN": "compile"}),
                ("compiled first, one process (LUBELINK_PREWARM=0)", {"LUBELINK_PREWARM": "0"}))
    for label, extra in variants:
        with tempfile.TemporaryDirectory() as cache, tempfile.TemporaryDirectory() as tmp:
            env = dict(os.environ, NUMBA_CACHE_DIR=cache, **extra)
            argv = ["run", "-o", f"{tmp}/out.nc", "--overwrite"]
            start = time.perf_counter()
            out = subprocess.run([sys.executable, "-m", "lubelink", *argv], check=True, env=env, capture_output=True,
                                 text=True).stdout
            cold = time.perf_counter() - start
            pid = re.search(r"background, pid (\d+)", out)
            ready = f", compiled kernels ready {cold + _wait_for(int(pid.group(1))):.1f} s after its start" if pid else ""
            warm = lubelink_process(argv, env)
            print(f"   `lubelink run` cold, {label}: {cold:.1f} s{ready}, then warm: {warm:.2f} s", flush=True)
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        print(f"   `lubelink compile` (every kernel, every method) cold: {lubelink_process(['compile'], env):.1f} s")


# --- 6. the up-front estimate against the run ------------------------------------------------------------
def bench_estimate(args):
    """Every built-in scenario: the estimate (run_cost + results_cost, what ``lubelink run`` announces) against the
    whole simulate(), warm: its wall time and its CPU time (the minimum of 3 each; on a loaded machine the CPU
    time is the figure to read, the wall time grows with the load)."""
    import lubelink
    from lubelink.config import SCENARIOS, resolve
    from lubelink.estimate import results_cost, run_cost

    print("\n6. estimated cost against simulate(), every built-in scenario (warm; min of 3)")
    print(f"{'scenario':<22}{'estimate':>10}{'wall':>10}{'cpu':>10}{'wall/est':>10}{'cpu/est':>9}")
    for name in SCENARIOS:
        config = resolve(name)
        estimate = run_cost(config).seconds + results_cost(config)
        lubelink.simulate(name)  # warm: compiled and loaded
        wall, cpu = math.inf, math.inf
        for _ in range(3):
            w0, c0 = time.perf_counter(), time.process_time()
            lubelink.simulate(name)
            wall, cpu = min(wall, time.perf_counter() - w0), min(cpu, time.process_time() - c0)
        print(f"{name:<22}{estimate:>9.3g}s{wall:>9.3g}s{cpu:>9.3g}s{wall / estimate:>10.2f}{cpu / estimate:>9.2f}")
    bench_mixed(args)


#: The clearances [m] of ``guide`` swept against the estimate's share of mixed lubrication, over ``MIXED_T_END`` [s].
CLEARANCES, MIXED_T_END = (100e-6, 60e-6, 40e-6, 30e-6, 25e-6, 20e-6, 16e-6), 0.5


def bench_mixed(args):
    """``guide`` along its clearance (``CLEARANCES``, 0.5 s): the estimate and its shares of mixed lubrication
    (:func:`lubelink.mixed.mixed_share`) against the run's steps and CPU time (the minimum of 2, warm), and the
    cost of one Greenwood-Tripp integral in compiled code (the estimate's ``GT_INTEGRAL``)."""
    import numba

    import lubelink
    from lubelink.config import resolve
    from lubelink.estimate import GT_INTEGRAL, results_cost, run_cost
    from lubelink.film.asperity import f52
    from lubelink.mixed import mixed_share

    @numba.njit
    def many(lams):
        total = 0.0
        for lam in lams:
            total += f52(lam)
        return total

    lams = np.linspace(0.0, 9.9, 20000)
    many(lams[:2])
    best = min(_timed(lambda: many(lams)) for _ in range(5)) / lams.size
    print(f"\n   one Greenwood-Tripp integral (F_5/2, compiled): {1e6 * best:.2f} us (priced at "
          f"{1e6 * GT_INTEGRAL:.2f} us)")
    print(f"   guide along its clearance, t_end = {MIXED_T_END} s (warm; min of 2)")
    print(f"   {'clearance':>9}{'zone':>7}{'loaded':>8}{'steps est':>10}{'steps':>8}{'estimate':>10}{'cpu':>9}"
          f"{'cpu/est':>9}")
    for clearance in CLEARANCES:
        config = resolve("guide", {"film.clearance": clearance, "solver.t_end": MIXED_T_END})
        share, est = mixed_share(config), run_cost(config)
        seconds = est.seconds + results_cost(config)
        lubelink.simulate(config)
        cpu, steps = math.inf, 0
        for _ in range(2):
            c0 = time.process_time()
            ds = lubelink.simulate(config)
            cpu = min(cpu, time.process_time() - c0)
            steps = int(ds.attrs["nsteps"])
        print(f"   {1e6 * clearance:>7.0f}um{share.zone:>7.3f}{share.loaded:>8.2f}{est.steps:>10.0f}{steps:>8}"
              f"{seconds:>9.3g}s{cpu:>8.3g}s{cpu / seconds:>9.2f}")


def _timed(f):
    t0 = time.perf_counter()
    f()
    return time.perf_counter() - t0


# --- 7. a fresh process's start ------------------------------------------------------------------------
START = [("import numpy, scipy", "import numpy, scipy"),
         ("import xarray", "import xarray"),
         ("one cached Numba kernel", "import kernel; kernel.f(1.0)"),
         ("floor: kernel + xarray", "import kernel, xarray; kernel.f(1.0)"),
         ("simulate('paper')", "import lubelink; lubelink.simulate('paper')")]
#: The smallest compiled kernel Numba can load from its cache (``kernel.py`` in a temporary directory).
KERNEL = "import numba\n\n\n@numba.njit(cache=True)\ndef f(x):\n    return x + 1.0\n"


def process_times(argv, cwd=None):
    """``(wall, cpu)`` [s] of one process ``argv`` (CPU: user + system of the child)."""
    import resource

    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run(argv, check=True, capture_output=True, cwd=cwd)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def bench_start(args):
    print("\n7. a fresh process, warm cache (in turn; median of", args.repeats, "rounds; wall and CPU)")
    with tempfile.TemporaryDirectory() as tmp:
        Path(tmp, "kernel.py").write_text(KERNEL)
        cases = [(name, [sys.executable, "-c", code]) for name, code in START]
        cases.append(("lubelink run -o FILE", [sys.executable, "-m", "lubelink", "run", "-o", f"{tmp}/out.nc",
                                              "--overwrite"]))
        for _, argv in cases:  # once each first: the kernel cached, the byte code in the page cache
            process_times(argv, cwd=tmp)
        times = {name: [] for name, _ in cases}
        for _ in range(args.repeats):
            for name, argv in cases:
                times[name].append(process_times(argv, cwd=tmp))
    for name, _ in cases:
        wall = statistics.median(w for w, _ in times[name])
        cpu = statistics.median(c for _, c in times[name])
        print(f"   {name:28s} wall {ms(wall):>9s}  cpu {ms(cpu):>9s}")


def timed_once(fn):
    start = time.perf_counter()
    fn()
    return time.perf_counter() - start


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--only", default=",".join(SECTIONS), help="comma-separated sections: " + ", ".join(SECTIONS))
    parser.add_argument("--compare-with", metavar="PATH", help="a checkout of another lubelink version")
    args = parser.parse_args(argv)
    only = [s.strip() for s in args.only.split(",") if s.strip()]
    unknown = sorted(set(only) - set(SECTIONS))
    if unknown:
        parser.error(f"--only: unknown section(s) {', '.join(unknown)}; choose from {', '.join(SECTIONS)}")
    import lubelink

    print(f"lubelink {lubelink.__version__} on {machine()}")
    for name in SECTIONS:
        if name in only:
            globals()[f"bench_{name}"](args)


if __name__ == "__main__":
    main()

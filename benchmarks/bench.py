"""Speed and accuracy of lubelink's integration paths: the reference (NumPy right-hand side, SciPy-style
stepping) against the compiled fast path (Numba), for DOP853 and Bulirsch-Stoer.

Printed, in this order (the figures recorded in ``benchmarks/README.md`` come from this script):

1. **Cases** -- ``paper`` with 1 and 7 modes, ``paper-dry`` with 1 and 7 modes, ``paper-impact``;
   0-2 s, rtol 1e-8 (atol 1e-12): for each method and path, the median wall and CPU time of
   ``lubelink.simulate.run(config)`` after a warm-up run, the right-hand-side evaluations, and the
   largest error of the midpoint deflection ``u2_mid`` against a tight run (rtol 1e-12,
   atol 1e-16; see below). Path ``jit+scipy`` is SciPy's stepping (the reference driver) on the
   compiled right-hand side, to separate the two gains.
2. **Against solve_ivp** -- ``scipy.integrate.solve_ivp(model.rhs, ..., method="DOP853")`` on the
   plain NumPy right-hand side with the gap as a terminal event, timed in the same run as the
   fastest compiled path.
3. **Scaling** -- the compiled paths against the number of modes (1, 3, 5, 7, 15) and the simulated
   time (0.5, 1, 2, 4 s): time, evaluations, time per evaluation and per step.
4. **Results** -- ``simulate()`` is ``run()`` plus ``to_dataset()``: both timed, and the two film
   quantities of the samples, which dominate ``to_dataset``: the resultant film force (per-sample
   loop over ``Model.film_loads``, batched NumPy ``film.resultant_force``, batched kernel
   ``_kernels.film_force_many``) and the pad pressure (``film.pad_pressure``, batched kernel
   ``_kernels.pad_pressure_many``).
5. **Evaluations against tolerance** -- DOP853 and Bulirsch-Stoer (compiled) on ``paper`` with 1
   and 7 modes for rtol 1e-6 ... 1e-12.
6. **Compilation** -- a cold compile and a cached load, each in a fresh process with its own
   ``NUMBA_CACHE_DIR``.

The tight runs that define the errors use the compiled DOP853 (the reference path at rtol 1e-12
takes minutes with 7 modes); for the 1-mode cases the reference DOP853 at rtol 1e-12 is run too
and its difference to the compiled one printed, to show that the choice does not matter.

Usage::

    python benchmarks/bench.py            # everything (about 10 minutes on a 2-core machine)
    python benchmarks/bench.py --quick    # one repeat, 7-mode reference runs on 0-0.2 s scaled x10
    python benchmarks/bench.py --repeats 5 --skip compile
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

CASES = [("paper", 1), ("paper", 7), ("paper-dry", 1), ("paper-dry", 7), ("paper-impact", 1)]
METHODS = ("DOP853", "bulirsch-stoer")
RTOL, ATOL, T_END = 1e-8, 1e-12, 2.0
#: Reference runs slower than this [s] are not repeated (and not warmed up).
SLOW = 10.0


def machine():
    cpu = "unknown"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    import numba
    import scipy

    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return (f"{os.cpu_count()} CPUs ({cpu}), load average {load:.1f} at start; python {platform.python_version()}, "
            f"numpy {np.__version__}, scipy {scipy.__version__}, numba {numba.__version__}")


def config(scenario, modes, method="DOP853", backend="numba", t_end=T_END, rtol=RTOL, atol=ATOL):
    from lubelink.config import resolve

    return resolve(scenario, {"beam.modes": modes, "solver.method": method, "solver.backend": backend,
                              "solver.t_end": t_end, "solver.rtol": rtol, "solver.atol": atol})


def timed(fn, repeats, warmup=True):
    """Median wall and CPU time of ``fn()`` over ``repeats`` calls (after one warm-up call), and its last result."""
    if warmup:
        fn()
    walls, cpus = [], []
    for _ in range(repeats):
        w, c = time.perf_counter(), time.process_time()
        result = fn()
        walls.append(time.perf_counter() - w)
        cpus.append(time.process_time() - c)
    return statistics.median(walls), statistics.median(cpus), result


def u2_mid(result):
    N = result.model.modes
    return result.y[:, :N] @ np.sin(np.arange(1, N + 1) * np.pi / 2)


def scipy_stepping():
    """A context in which ``run()`` uses SciPy's stepping on the compiled right-hand side."""
    import contextlib
    import importlib

    from lubelink.integrate import fast

    sim = importlib.import_module("lubelink.simulate")  # the module (lubelink.simulate is also a function)

    @contextlib.contextmanager
    def patched():
        original = sim.segment_integrator
        sim.segment_integrator = lambda model: fast.make_segment_integrator(model, stepping="scipy")
        try:
            yield
        finally:
            sim.segment_integrator = original

    return patched()


def fmt_time(seconds):
    return f"{seconds * 1e3:9.1f} ms" if seconds < 10 else f"{seconds:9.2f} s "


# ------------------------------------------------------------------------------------------------
def bench_cases(args):
    from lubelink.simulate import run

    print(f"\n1. Cases: 0-{T_END:g} s, rtol {RTOL:g}, atol {ATOL:g}; median of {args.repeats} after a warm-up "
          f"(reference runs over {SLOW:g} s: one run{', 7-mode reference runs on 0-0.2 s x10' if args.quick else ''})")
    print(f"   {'case':<16} {'method':<15} {'path':<10} {'wall':>12} {'cpu':>12} {'nfev':>9} "
          f"{'max|err u2_mid| [m]':>20} {'speed-up':>9}")
    rows = []
    for scenario, modes in CASES:
        tight = run(config(scenario, modes, "DOP853", "numba", rtol=1e-12, atol=1e-16))
        tight_u = u2_mid(tight)
        note = ""
        if modes == 1:
            ref_tight = run(config(scenario, modes, "DOP853", "numpy", rtol=1e-12, atol=1e-16))
            note = f"(tight reference path - tight compiled: {np.max(np.abs(u2_mid(ref_tight) - tight_u)):.1e} m)"
        for method in METHODS:
            ref_time = None
            for path in ("reference", "jit+scipy", "fast"):
                if path == "jit+scipy" and method != "DOP853":
                    continue
                backend = "numpy" if path == "reference" else "numba"
                scale = 1.0
                t_end = T_END
                if path == "reference" and args.quick and modes > 1:
                    t_end, scale = 0.2, T_END / 0.2
                cfg = config(scenario, modes, method, backend, t_end=t_end)

                def once(cfg=cfg, path=path):
                    if path == "jit+scipy":
                        with scipy_stepping():
                            return run(cfg)
                    return run(cfg)

                if path == "reference":  # the first run is the warm-up, or the only run if slow
                    w0, c0 = time.perf_counter(), time.process_time()
                    result = once()
                    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
                    if wall < SLOW and not args.quick:
                        wall, cpu, result = timed(once, args.repeats, warmup=False)
                else:
                    wall, cpu, result = timed(once, args.repeats)
                wall, cpu = wall * scale, cpu * scale
                nfev = int(result.nfev * scale)
                if scale == 1.0:
                    n = min(len(result.t), len(tight.t))
                    err = f"{np.max(np.abs(u2_mid(result)[:n] - tight_u[:n])):20.2e}"
                else:
                    err = f"{'(0-0.2 s x10)':>20}"
                if path == "reference":
                    ref_time = wall
                speed = f"{ref_time / wall:8.0f}x" if path != "reference" else f"{'':9}"
                print(f"   {scenario + f' N={modes}':<16} {method:<15} {path:<10} {fmt_time(wall)} {fmt_time(cpu)} "
                      f"{nfev:9d} {err} {speed}")
                rows.append((scenario, modes, method, path, wall, cpu, nfev))
        if note:
            print(f"   {'':<16} {note}")
    return rows


def bench_solve_ivp(args, rows):
    from scipy.integrate import solve_ivp

    from lubelink.model import build_model
    from lubelink.simulate import run

    print("\n2. Against scipy.integrate.solve_ivp on the plain NumPy right-hand side (DOP853, gap event), "
          "same run")
    print(f"   {'case':<16} {'solve_ivp wall':>15} {'fastest compiled':>26} {'ratio':>8}")
    for scenario, modes in [("paper", 1)] + ([] if args.quick else [("paper", 3)]):
        cfg = config(scenario, modes)
        model = build_model(cfg)
        t_eval = np.arange(int(round(T_END / cfg.solver.output_step)) + 1) * cfg.solver.output_step
        def gap(t, y):
            return model.gap(t, y)

        gap.terminal, gap.direction = True, -1

        def ivp():
            return solve_ivp(model.rhs, (0.0, T_END), model.initial_state(), method="DOP853", rtol=RTOL, atol=ATOL,
                             t_eval=t_eval, events=gap)

        w0 = time.perf_counter()
        ivp()
        reps = 1 if time.perf_counter() - w0 > SLOW or args.quick else args.repeats
        wall_ivp, _, sol = timed(ivp, reps, warmup=False)
        best = None
        for method in METHODS:
            wall, _, _ = timed(lambda m=method: run(config(scenario, modes, m)), args.repeats)
            if best is None or wall < best[0]:
                best = (wall, method)
        print(f"   {scenario + f' N={modes}':<16} {fmt_time(wall_ivp):>15} {fmt_time(best[0])} ({best[1]:>14}) "
              f"{wall_ivp / best[0]:7.0f}x   (solve_ivp nfev {sol.nfev})")


def bench_scaling(args):
    from lubelink.simulate import run

    print("\n3. Scaling of the compiled paths (paper scenario, rtol 1e-8)")
    print(f"   {'':<22} {'method':<15} {'wall':>12} {'cpu':>12} {'nfev':>9} {'steps':>7} {'cpu/nfev':>10} "
          f"{'cpu/step':>10}")
    for label, values, key in (("modes N (0-2 s)", (1, 3, 5, 7, 15), "modes"),
                               ("t_end [s] (1 mode)", (0.5, 1.0, 2.0, 4.0), "t_end"),
                               ("t_end [s] (7 modes)", (0.5, 1.0, 2.0, 4.0), "t_end7")):
        if args.quick and key == "t_end7":
            continue
        for v in values:
            for method in METHODS:
                if key == "modes":
                    cfg = config("paper", v, method)
                else:
                    cfg = config("paper", 7 if key == "t_end7" else 1, method, t_end=v)
                wall, cpu, r = timed(lambda cfg=cfg: run(cfg), args.repeats)
                print(f"   {label + f' = {v:g}':<22} {method:<15} {fmt_time(wall)} {fmt_time(cpu)} {r.nfev:9d} "
                      f"{r.nsteps:7d} {cpu / r.nfev * 1e6:8.2f} us {cpu / r.nsteps * 1e6:8.1f} us")


def bench_tolerance(args):
    from lubelink.simulate import run

    print("\n5. Evaluations against tolerance (paper scenario, compiled paths, atol = rtol * 1e-4)")
    print(f"   {'case':<14} {'rtol':>7} {'DOP853 nfev':>12} {'BS nfev':>10} {'BS/DOP853':>10} "
          f"{'DOP853 wall':>12} {'BS wall':>12}")
    for modes in (1, 7):
        for rtol in (1e-6, 1e-8, 1e-10, 1e-12):
            res = {}
            for method in METHODS:
                cfg = config("paper", modes, method, rtol=rtol, atol=rtol * 1e-4)
                res[method] = timed(lambda cfg=cfg: run(cfg), 1 if modes > 1 else args.repeats)
            d, b = res["DOP853"], res["bulirsch-stoer"]
            print(f"   {f'paper N={modes}':<14} {rtol:7.0e} {d[2].nfev:12d} {b[2].nfev:10d} "
                  f"{b[2].nfev / d[2].nfev:10.2f} {fmt_time(d[0])} {fmt_time(b[0])}")


def bench_results(args):
    from lubelink import _kernels, film
    from lubelink.simulate import run, to_dataset

    print("\n4. simulate() = run() + to_dataset(): the results Dataset (compiled DOP853). film_force of the")
    print("   samples: per-sample loop, film.resultant_force (NumPy, batched), _kernels.film_force_many;")
    print("   pressure(time, X): film.pad_pressure (NumPy, batched) and _kernels.pad_pressure_many")
    print(f"   {'case':<16} {'run()':>12} {'to_dataset()':>14} {'force: loop':>12} {'NumPy':>12} {'kernel':>12}"
          f" {'pressure: NumPy':>16} {'kernel':>12}")
    for modes in (1, 7):
        cfg = config("paper", modes)
        wall_run, _, result = timed(lambda: run(cfg), args.repeats)
        wall_ds, _, _ = timed(lambda: to_dataset(result), max(1, args.repeats - 2))
        model, fm = result.model, cfg.film
        N = model.modes
        q, q_dot = result.y[:, :N], result.y[:, N:]
        kin = model.motion(result.t)
        x0 = film.pad_start(np.asarray(kin.x_star), fm.pad_length, fm.pad_reference)

        def loop():
            return np.array([model.film_loads(t, y)[1] for t, y in zip(result.t, result.y)])

        def numpy_batch():
            return film.resultant_force(q, q_dot, x0, kin.V_r, mu=fm.viscosity, clearance=fm.clearance,
                                        pad_length=fm.pad_length, width=cfg.beam.width,
                                        rod_length=cfg.mechanism.rod_length, nodes=fm.quadrature_nodes)

        wall_loop, _, forces = timed(loop, 1)
        wall_np, _, forces_np = timed(numpy_batch, args.repeats)
        p = _kernels.pack(model)
        y = np.ascontiguousarray(result.y)
        wall_k, _, forces_k = timed(lambda: _kernels.film_force_many(result.t, y, p), args.repeats)
        assert np.allclose(forces_k, forces, rtol=1e-9, atol=1e-12) and np.allclose(forces_np, forces, rtol=1e-9,
                                                                                       atol=1e-12)
        X = np.linspace(0.0, fm.pad_length, cfg.output.pad_points)
        wall_pnp, _, pres = timed(lambda: film.pad_pressure(X, q, q_dot, x0, kin.V_r, mu=fm.viscosity,
                                                            clearance=fm.clearance,
                                                            rod_length=cfg.mechanism.rod_length), args.repeats)
        wall_pk, _, pres_k = timed(lambda: _kernels.pad_pressure_many(model, result.t, result.y, X), args.repeats)
        assert np.allclose(pres_k, pres, rtol=0, atol=1e-11 * np.max(np.abs(pres)))
        print(f"   {f'paper N={modes}':<16} {fmt_time(wall_run)} {fmt_time(wall_ds):>14} {fmt_time(wall_loop)} "
              f"{fmt_time(wall_np)} {fmt_time(wall_k)} {fmt_time(wall_pnp):>16} {fmt_time(wall_pk)}")


def bench_compile(args):
    print("\n6. Compilation of the fast path (fresh processes, private NUMBA_CACHE_DIR)")
    code = ("import time; t = time.perf_counter(); c = time.process_time(); "
            "from lubelink.integrate import fast; fast.compile_all(); "
            "print(time.perf_counter() - t, time.process_time() - c)")
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache}
        for label in ("cold (compiles)", "cached (loads)"):
            out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
            wall, cpu = (float(v) for v in out.stdout.split()[-2:])
            print(f"   {label:<16} wall {wall:6.1f} s, cpu {cpu:6.1f} s (import of lubelink and numba included)")
    print("   (NUMBA_CACHE_DIR redirects the cache, so the in-tree __pycache__ cache is not used here)")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=3, help="timed repeats per measurement (default 3)")
    parser.add_argument("--quick", action="store_true", help="one repeat; 7-mode reference runs shortened")
    parser.add_argument("--skip", action="append", default=[],
                        choices=["cases", "ivp", "scaling", "results", "compile", "tolerance"],
                        help="leave out a part (repeatable)")
    args = parser.parse_args(argv)
    if args.quick:
        args.repeats = 1
    print("lubelink integration benchmark")
    print("machine:", machine())
    from lubelink.integrate import fast

    w = time.perf_counter()
    fast.compile_all()
    print(f"fast path ready in {time.perf_counter() - w:.1f} s (compile or cache load)")
    rows = bench_cases(args) if "cases" not in args.skip else []
    if "ivp" not in args.skip:
        bench_solve_ivp(args, rows)
    if "scaling" not in args.skip:
        bench_scaling(args)
    if "results" not in args.skip:
        bench_results(args)
    if "tolerance" not in args.skip:
        bench_tolerance(args)
    if "compile" not in args.skip:
        bench_compile(args)
    if hasattr(os, "getloadavg"):
        print(f"\nload average at the end: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()

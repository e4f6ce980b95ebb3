"""Throughput of ``lubelink sweep``: points per second on 1 and 2 Dask workers, and the overhead per point.

The sweep: the ``paper`` scenario over ``mechanism.crank_speed`` (20 values, 25-40 rad/s) x
``film.viscosity`` (``--points / 20`` values, 0.05-0.2 Pa s), 400 points by default. It is run

1. serially in this process, calling the same per-point function the workers call (simulation,
   results Dataset, summary): the baseline, the cost of the simulations themselves;
2. with :func:`lubelink.sweep.run_sweep` on a ``LocalCluster`` of N worker processes (one thread
   each) for each N of ``--workers``, into a fresh Zarr store.

Each cluster is the one ``lubelink sweep`` starts (``lubelink.sweep.LOCAL_CLUSTER_CONFIG``), started
and warmed (imports, one tiny simulation per worker) before its timing starts: worker start-up is
paid once per cluster, not per point. Reported per run:

* points/s and speed-up over the serial baseline;
* overhead per point = (wall time x workers - serial time) / points: the worker-time each point
  costs beyond its simulation (scheduling, transfers, storing, and on a machine with as many cores
  as workers the client and scheduler competing with the workers). Meaningful only on an otherwise
  idle machine: the load average is printed after each phase;
* workers busy: the share of the workers' wall time spent inside points (from the audit trace);
* gap between points: mean time a worker spends between the end of a point and the start of its
  next one (Dask's dispatch, transfers, bookkeeping), robust to other load on the machine;
* client CPU per point: CPU time of this process (client and scheduler threads) per point,
  including fixed costs (validating every point, creating and reading the store).

The wall time per point on 2 workers is compared with two single runs measured in the same run, in
one loop before the sweeps and again after them (their mean): ``simulate("paper")`` (the issue's
target, <= 0.75x), and ``simulate()`` of the sweep's own points (their mean), what a user would run
without a sweep. The second is the like-for-like
figure: the sweep's points are not ``paper``; their cost grows with the crank speed (485 steps at
25 rad/s, 847 at ``paper``'s 31.4, 2637 at 40), so on average a point costs 1.2-1.4x ``paper``.

Usage::

    python benchmarks/sweep_throughput.py                     # 400 points of 2 s (about a minute)
    python benchmarks/sweep_throughput.py --t-end 0.5         # shorter simulations
    python benchmarks/sweep_throughput.py --points 40 --workers 1,2,4
"""

from __future__ import annotations

import argparse
import logging
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path


def sweep_definition(points, t_end):
    if points % 20:
        raise SystemExit("--points must be a multiple of 20")
    return {
        "base": "paper",
        "set": {"solver.t_end": t_end},
        "vary": {"mechanism.crank_speed": {"start": 25.0, "stop": 40.0, "num": 20},
                 "film.viscosity": {"start": 0.05, "stop": 0.2, "num": points // 20}},
        "store": {"quantities": ["peak_u2_mid", "impact_count", "first_impact_time", "peak_pressure",
                                 "min_film", "peak_film_force"]},
    }


def warm_up():
    """Import everything a point needs and run one tiny simulation (in a worker)."""
    import lubelink
    from lubelink.sweep import summarise

    summarise(lubelink.simulate("paper", set={"solver.t_end": 0.01, "output.x_points": 5}))
    return os.getpid()


def single_runs(sp):
    """``(paper, points)``: the median wall time of ``lubelink.simulate("paper")`` and the mean of
    ``lubelink.simulate(config)`` over the sweep's points (Dataset included: the user's single runs,
    the alternative to a sweep), timed in one loop, a ``paper`` run before each point, so that both
    see the same machine (its speed drifts by tens of per cent within minutes)."""
    import statistics

    import lubelink

    configs, invalid = sp.point_configs()
    assert not invalid
    for config in list(configs.values())[:5]:
        lubelink.simulate("paper")
        lubelink.simulate(config)
    paper, points = [], []
    for config in configs.values():
        t0 = time.perf_counter()
        lubelink.simulate("paper")
        t1 = time.perf_counter()
        lubelink.simulate(config)
        t2 = time.perf_counter()
        paper.append(t1 - t0)
        points.append(t2 - t1)
    return statistics.median(paper), statistics.fmean(points)


def serial(sp):
    from lubelink.sweep import _compute_point, _TaskOptions

    configs, invalid = sp.point_configs()
    assert not invalid
    opts = _TaskOptions(sp.quantities, (), sp.max_impacts, 0, sp.base_config.solver.output_step, "serial")
    warm_up()
    t0 = time.perf_counter()
    sim = 0.0
    for flat, config in configs.items():
        record, _ = _compute_point(flat, config, opts)
        sim += record["wall_time"]
    return time.perf_counter() - t0, sim


def on_cluster(sp, workers, folder, task_seconds):
    import dask
    from distributed import Client, LocalCluster

    from lubelink.sweep import LOCAL_CLUSTER_CONFIG, run_sweep

    with dask.config.set(LOCAL_CLUSTER_CONFIG), \
            LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0",
                         silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
        client.run(warm_up)
        store, trace = Path(folder) / f"w{workers}.zarr", Path(folder) / f"w{workers}.log"
        cpu0, t0 = time.process_time(), time.perf_counter()
        ds = run_sweep(sp, store, client=client, progress=False, task_seconds=task_seconds, trace=trace)
        wall, cpu = time.perf_counter() - t0, time.process_time() - cpu0
        assert bool(ds.done.all())
        failed = int((~ds.status.isin(["complete", "film_breakdown", "chatter", "out_of_domain"])).sum())
        shutil.rmtree(store)
    busy, gaps = worker_times(trace)
    return wall, cpu, failed, busy / (wall * workers), gaps


def worker_times(trace):
    """Total time the workers spent inside points, and the mean gap between consecutive points of
    a worker (Dask's dispatch, transfers and bookkeeping), from the audit trace."""
    events = {}
    for line in Path(trace).read_text().splitlines():
        t, pid, event, _, _ = line.split()
        events.setdefault(pid, []).append((float(t), event))
    busy, gaps = 0.0, []
    for seq in events.values():
        seq.sort()
        for (t1, e1), (t2, e2) in zip(seq, seq[1:]):
            if e1 == "start" and e2 == "end":
                busy += t2 - t1
            elif e1 == "end" and e2 == "start":
                gaps.append(t2 - t1)
    return busy, sum(gaps) / len(gaps) if gaps else 0.0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--points", type=int, default=400, help="points in the sweep (multiple of 20)")
    parser.add_argument("--t-end", type=float, default=2.0, help="simulated time per point [s] (default 2)")
    parser.add_argument("--workers", default="1,2", help="comma-separated worker counts (default 1,2)")
    parser.add_argument("--task-seconds", type=float, default=0.5,
                        help="run_sweep(task_seconds=...): points per Dask task (0: one point per task)")
    args = parser.parse_args(argv)

    from lubelink.sweep import read_sweep

    sp = read_sweep(sweep_definition(args.points, args.t_end))
    counts = [int(w) for w in args.workers.split(",")]
    print(f"{args.points} points of the 'paper' scenario, {args.t_end:g} s each, task_seconds {args.task_seconds:g}; "
          f"{os.cpu_count()} cores; load average {os.getloadavg()[0]:.2f} at start", flush=True)

    t_serial, t_sim = serial(sp)
    n = sp.size
    before = single_runs(sp)
    print(f"single runs before the sweeps: simulate('paper') {1e3 * before[0]:.2f} ms (median), simulate() of "
          f"the sweep's points {1e3 * before[1]:.2f} ms (mean), in one loop", flush=True)
    print(f"serial baseline: {t_serial:.1f} s ({1e3 * t_serial / n:.1f} ms per point, of which "
          f"{1e3 * t_sim / n:.1f} ms in the simulation itself), load average {os.getloadavg()[0]:.2f}",
          flush=True)
    rows = [("serial, in-process", "-", t_serial, n / t_serial, 1.0, None, None, None, None, 0)]
    with tempfile.TemporaryDirectory() as folder:
        for w in counts:
            wall, cpu, failed, utilisation, gap = on_cluster(sp, w, folder, args.task_seconds)
            rows.append(("run_sweep, LocalCluster", str(w), wall, n / wall, t_serial / wall,
                         1e3 * (wall * w - t_serial) / n, 100 * utilisation, 1e3 * gap, 1e3 * cpu / n, failed))
            print(f"{w} worker(s): {wall:.1f} s, load average {os.getloadavg()[0]:.2f}", flush=True)

    after = single_runs(sp)
    print(f"single runs after the sweeps: simulate('paper') {1e3 * after[0]:.2f} ms (median), simulate() of "
          f"the sweep's points {1e3 * after[1]:.2f} ms (mean)", flush=True)
    t_one, t_points = 0.5 * (before[0] + after[0]), 0.5 * (before[1] + after[1])

    # failed: an error or a lost worker; a film breakdown or chatter is a result of the physics
    head = ("mode", "workers", "wall [s]", "points/s", "speed-up", "overhead/point [ms]",
            "workers busy [%]", "gap between points [ms]", "client CPU/point [ms]", "failed points")

    def cell(v, fmt):
        return "-" if v is None else format(v, fmt)

    table = [head] + [(r[0], r[1], f"{r[2]:.1f}", f"{r[3]:.3f}", f"{r[4]:.2f}", cell(r[5], ".1f"),
                       cell(r[6], ".1f"), cell(r[7], ".2f"), cell(r[8], ".2f"), str(r[9])) for r in rows]
    widths = [max(len(row[i]) for row in table) for i in range(len(head))]
    print()
    for i, row in enumerate(table):
        print("  ".join(cell.ljust(wd) for cell, wd in zip(row, widths)))
        if i == 0:
            print("  ".join("-" * wd for wd in widths))
    by_workers = {r[1]: r[2] for r in rows}
    if "1" in by_workers and "2" in by_workers:
        print(f"\n2 workers / 1 worker: {by_workers['1'] / by_workers['2']:.2f}x")
    for r in rows[1:]:
        print(f"{r[1]} worker(s): wall time per point {1e3 * r[2] / n:.2f} ms = "
              f"{r[2] / n / t_one:.2f}x one simulate('paper') (target <= 0.75x on 2 workers), "
              f"{r[2] / n / t_points:.2f}x simulate() of the same points (single runs: the mean of before and after)")
    print(f"load average at end {os.getloadavg()[0]:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

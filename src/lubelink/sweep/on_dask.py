"""Running a sweep on Dask: the cluster (:func:`_dask_client`) and the task window (:func:`_execute`).

:func:`_dask_client` gives the user's client, one connected to a scheduler, or a ``LocalCluster``
started for the run (:data:`LOCAL_CLUSTER_CONFIG`); :func:`_execute` keeps a moving window of
tasks in flight, one point per task or as many as take about ``task_seconds`` once the points'
duration is known (:class:`~lubelink.sweep.local.Batcher`), each task's points committed as it
completes (:class:`~lubelink.sweep.local.Tally`). Dask is imported inside the functions.
"""

from __future__ import annotations

import contextlib
import logging
import time
import uuid

from .compute import _compute_points, _describe, _empty_record
from .local import Batcher, _cpu_count, _hold_sigint, _main_not_rerun
from .schema import SweepError

__all__ = ["LOCAL_CLUSTER_CONFIG"]

log = logging.getLogger(__name__)

#: Dask settings of the local cluster that :func:`run_sweep` starts: Dask's diagnostics sampling
#: (event-loop tick every 20 ms, system monitor, worker profiler) costs about a tenth of a core per
#: process on a small machine, taken from the simulations; a sweep does without it. Dask's nanny
#: also starts its workers with ``MALLOC_TRIM_THRESHOLD_=65536`` (freed memory back to the system at
#: once), which turns glibc's adaptive thresholds off: every array above 128 KiB is then mapped afresh
#: and a ``paper`` point took 5-10 % longer in a worker than in a process of its own (2 % without it).
#: A point's arrays are a few megabytes, freed when it ends; the sweep keeps glibc's defaults (None
#: unsets the variable, Dask's documented way; one set in the environment still wins).
LOCAL_CLUSTER_CONFIG = {
    "distributed.admin.tick.interval": "500ms",
    "distributed.admin.system-monitor.interval": "2s",
    "distributed.worker.profile.enabled": False,
    "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None,
}



@contextlib.contextmanager
def _dask_client(client, scheduler, workers):
    """``(client, description)``: the user's client, one connected to ``scheduler``, or a LocalCluster."""
    if client is not None:
        yield client, f"Dask client {getattr(client, 'scheduler', None) and client.scheduler.address}"
        return
    from distributed import Client, LocalCluster

    if scheduler:
        try:
            c = Client(scheduler)  # waits distributed.comm.timeouts.connect (Dask config, 30 s)
        except Exception as exc:  # noqa: BLE001 - OSError, TimeoutError, ValueError for a bad address
            raise SweepError(f"scheduler {scheduler}: cannot connect ({exc})") from None
        try:
            yield c, f"Dask scheduler {scheduler}"
        finally:
            c.close()
        return
    import dask

    n = workers or _cpu_count()
    with _main_not_rerun():  # (the nanny starts a worker again after one died: for the cluster's life)
        held = _hold_sigint()
        try:
            with dask.config.set(LOCAL_CLUSTER_CONFIG):
                cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                       silence_logs=logging.ERROR, dashboard_address=":0")
                c = Client(cluster)
        except BaseException:
            held()
            raise
        try:
            held()  # a Ctrl-C pressed while the cluster started is raised here
            yield c, f"LocalCluster, {n} worker process(es)"
        finally:
            c.close()
            cluster.close()



def _threads(client):
    """Worker threads of a Dask cluster (1 while it has none yet)."""
    try:
        return max(1, sum(client.nthreads().values()))
    except Exception:  # noqa: BLE001 - a scheduler without workers yet
        return 1


def _execute(client, st, sp, pending, opts, trace, tally, task_seconds):
    """Submit the pending points in a moving window of tasks; store each task's points as it completes.

    A task computes one point, or, once the points are known to be short, as many as take about
    ``task_seconds`` on a worker, so that Dask's per-task cost (a few milliseconds of scheduler,
    network and worker time) stays small beside the simulations.
    """
    from distributed import as_completed

    token = uuid.uuid4().hex[:8]
    batcher = Batcher(pending, task_seconds)
    active = {}
    # on this client's event loop: by default as_completed waits for (and gathers) the futures on the
    # loop of the process's default client, which is another client's whenever one was made current
    # (``with Client() as c``) or started later; asyncio objects used across the two loops' threads
    # lose wake-ups, and the sweep waits for ever for a result that the scheduler holds
    ac = as_completed(loop=client.loop, with_results=True, raise_errors=False)

    def submit(n_tasks):
        """Submit up to ``n_tasks`` more tasks in one graph update."""
        tasks = []
        while len(tasks) < n_tasks and batcher:
            tasks.append(batcher.batch(nthreads))
        if not tasks:
            return
        futures = client.map(_compute_points, tasks, [[sp.overrides(f) for f in t] for t in tasks],
                             base=sp.base_config, opts=opts, trace=trace, pure=False,
                             key=[f"lubelink-sweep-{sp.hash[:8]}-{token}-{t[0]}-{len(t)}" for t in tasks])
        for task, fut in zip(tasks, futures):
            active[fut] = task
        ac.update(futures)

    nthreads = _threads(client)
    window = 3 * nthreads + 2
    last_window = time.monotonic()
    lost = 0
    try:
        submit(nthreads + 1)  # one point a task until a point's duration is known, then the window in batches
        for fut, result in ac:
            task = active.pop(fut)
            if fut.status == "finished":
                results, seconds = result
                batcher.timed(seconds, len(task))
            elif fut.status == "error" and len(task) > 1:  # find which point kills its workers
                batcher.single.extend(task)
                results = []
            elif fut.status == "error":
                exc = result[1] if isinstance(result, tuple) else result
                state = "worker_died" if type(exc).__name__ == "KilledWorker" else "error"
                results = [(task[0], _empty_record(sp.quantities, sp.max_impacts, state, _describe(exc)), {})]
            else:  # cancelled or lost with the connection: not stored, computed on the next run
                lost += len(task)
                results = []
            tally.commit(results)
            del fut, result, results
            if time.monotonic() - last_window > 30.0:  # follow a cluster that scales
                nthreads, last_window = _threads(client), time.monotonic()
                window = 3 * nthreads + 2
            if len(active) <= window // 2:  # refill in batches: fewer messages to the scheduler
                submit(window - len(active))
    except BaseException:
        with contextlib.suppress(Exception):
            client.cancel(list(active))
        raise
    tally.session["lost"] = lost
    if lost:
        log.warning("%d point(s) were not computed (their tasks were cancelled or lost with the Dask "
                    "connection); run the sweep again to compute them", lost)

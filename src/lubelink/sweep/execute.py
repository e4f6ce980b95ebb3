"""Running a sweep on Dask (the client side): :func:`run_sweep`.

Validate every point, open (or resume) the store, start or reach a Dask cluster
(:func:`_dask_client`), then keep a moving window of tasks in flight (:func:`_execute`): one point
per task, or as many as take about ``task_seconds`` once the points' duration is known. Each
task's points are committed to the store as it completes, so an interruption loses at most the
points being computed. Dask and tqdm are imported inside the functions; the progress bar
(:class:`lubelink.progress.Bar`) writes plain lines where stderr is not a terminal.
"""

from __future__ import annotations

import contextlib
import logging
import os
import shutil
import sys
import time
import uuid
from pathlib import Path

import numpy as np

from ..config import ConfigError
from ..params import sample_times
from .compute import _compute_points, _describe, _empty_record, _TaskOptions
from .parse import MAX_POINTS, MAX_POINTS_LIMIT, read_sweep
from .schema import SweepError
from .store import _check_attrs, _export_netcdf, _is_netcdf, _side_store, _Store, load_sweep

__all__ = ["run_sweep", "sweep", "LOCAL_CLUSTER_CONFIG"]

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


# ====================================================================== running
def _cpu_count() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def _hold_sigint():
    """Block SIGINT in the calling (main) thread; returns what restores the mask.

    Ctrl-C at a terminal reaches the whole process group. The local cluster's processes, started
    meanwhile (by threads started meanwhile), inherit the blocked mask: the signal reaches the client
    alone, which stops the sweep and closes the cluster, instead of each worker printing its own
    KeyboardInterrupt traceback. A Ctrl-C pressed while the mask is held waits, and is raised when
    it is restored.
    """
    import signal
    import threading
    from multiprocessing import resource_tracker

    if not hasattr(signal, "pthread_sigmask") or threading.current_thread() is not threading.main_thread():
        return lambda: None
    resource_tracker.ensure_running()  # now: the thread that starts it later unblocks SIGINT as it does
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    return lambda: signal.pthread_sigmask(signal.SIG_SETMASK, previous)


@contextlib.contextmanager
def _main_not_rerun():
    """While it lasts, the processes multiprocessing starts do not run the ``__main__`` script again.

    The local cluster's workers are started by multiprocessing's spawn method (Dask's default),
    which runs the parent's ``__main__`` script in each child (as ``__mp_main__``) so that what
    it defines can be unpickled there: a script calling :func:`run_sweep` at its top level,
    without ``if __name__ == "__main__":``, would run again in every worker (and its sweep find
    the store in use). A worker needs nothing of the script (its tasks are lubelink's functions
    of configurations), so ``__main__`` is shown to multiprocessing as the module ``__main__``,
    which a child leaves alone (``multiprocessing.spawn._fixup_main_from_name``): for a script,
    or a module run with ``python -m``, as for the ``lubelink`` command itself.
    """
    import importlib.machinery

    main = sys.modules.get("__main__")
    if main is None or (getattr(main, "__file__", None) is None and getattr(main, "__spec__", None) is None):
        yield  # an interactive session: nothing to run again
        return
    spec = main.__spec__
    main.__spec__ = importlib.machinery.ModuleSpec("__main__", None)
    try:
        yield
    finally:
        main.__spec__ = spec


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


def run_sweep(sweep, store=None, *, client=None, scheduler=None, workers=None, retry_failed=False,
              overwrite=False, progress=True, trace=None, task_seconds=0.5, max_points=None):
    """Run a parameter sweep on Dask and return every point's results.

    Points already in ``store`` are skipped (the run resumes); each finished
    point is stored at once, so interrupting loses at most the points being
    computed at that moment.

    Parameters
    ----------
    sweep : str, os.PathLike, dict or Sweep
        Sweep file or its parsed content (:func:`read_sweep`).
    store : str or os.PathLike, optional
        Results: a Zarr directory (default ``<sweep file name>.zarr``), or a
        ``.nc`` file (NetCDF, written when the run ends).
    client : distributed.Client, optional
        Your own Dask client (kept open). Otherwise ``scheduler`` is connected
        to, or a ``LocalCluster`` of ``workers`` processes (default: one per
        core, one thread each) is started for this call.
    scheduler : str, optional
        Address of a running Dask scheduler, e.g. ``"tcp://10.0.0.5:8786"``.
    workers : int, optional
        Worker processes of the local cluster.
    retry_failed : bool
        Compute again the stored points whose status is not ``complete``
        (except ``invalid``).
    overwrite : bool
        Discard a store that holds another sweep instead of refusing.
    progress : bool
        Show a progress bar (done, failed, remaining, time left).
    trace : str or os.PathLike, optional
        Audit file: every point computation appends a ``start`` and an ``end``
        line (it must be on a file system that the workers can write).
    task_seconds : float
        Once the points' duration is known, a Dask task computes as many
        points as take about this long [s] (at least one), so that Dask's
        per-task overhead stays small for short points; 0 sends one point
        per task. A crash loses at most the tasks being computed.
    max_points : int, optional
        Largest sweep to run (default :data:`~lubelink.sweep.parse.MAX_POINTS`, 100000): a
        larger one is refused before anything is validated or stored, with its estimated time
        and memory; give its size (or more) to run it.

    Returns
    -------
    xarray.Dataset
        Over the swept dimensions: ``done``, ``status``, ``message``,
        ``wall_time`` and the chosen quantities (units in their attrs); the
        attrs hold the sweep, its hash, the base configuration and ``runs``
        (JSON, one entry per run of this sweep).

    Raises
    ------
    lubelink.ConfigError
        An invalid sweep file, or invalid points (unless
        ``invalid_points = "record"``), before anything is computed.
    SweepError
        A store of another sweep, a store in use, an unreachable scheduler, an output that cannot
        be written, a sweep larger than ``max_points``.
    """
    sp = read_sweep(sweep)
    if store is None:
        if sp.origin in ("sweep", "store"):
            raise SweepError("run_sweep: give store=... for a sweep that is not read from a file")
        store = Path(f"{Path(sp.origin).stem}.zarr")
    path = Path(store)
    if scheduler and workers:
        raise SweepError("give either a scheduler address or a number of local workers, not both")
    if client is not None and (scheduler or workers):
        raise SweepError("give either a Dask client or a scheduler address / number of workers")
    check_size(sp, max_points, workers or (None if scheduler or client is not None else _cpu_count()))
    problem = output_problem(path)
    if problem:
        raise SweepError(f"{path}: {problem}")

    with contextlib.ExitStack() as stack:
        where = None
        if scheduler:  # reach it before anything is created: an unreachable one leaves nothing behind
            client, where = stack.enter_context(_dask_client(None, scheduler, None))
        return _run(sp, path, client, where, workers, retry_failed, overwrite, progress, trace, task_seconds)


def check_size(sp, max_points=None, workers=None):
    """Refuse a sweep of more points than ``max_points`` (default :data:`MAX_POINTS`), saying what
    it would cost (:meth:`Sweep.estimate`)."""
    cap = MAX_POINTS if max_points is None else int(max_points)
    if sp.size > cap:
        hint = (f"allow it with --max-points {sp.size} (max_points= in Python)"
                if sp.size <= MAX_POINTS_LIMIT else f"split it (at most {MAX_POINTS_LIMIT:.0e} points)")
        raise SweepError(f"{sp.origin}: {sp.size:,} points, more than the limit of {cap:,}; it would take "
                         f"{sp.estimate(workers)}; {hint}")


def output_problem(path):
    """Why a sweep's results could not be written at ``path`` (checked before anything runs)."""
    from .._files import folder_problem, target_problem

    if _is_netcdf(path):
        return target_problem(path) if os.path.lexists(path) else folder_problem(path.parent)
    if os.path.lexists(path):
        return target_problem(path, directory=True)
    return folder_problem(path.parent)


def _run(sp, path, client, where, workers, retry_failed, overwrite, progress, trace, task_seconds):
    bar = _bar(progress, sp.size, "validating") if sp.size >= 500 else None
    try:
        invalid = sp.invalid_points_of(progress=(lambda n: bar.update(n - bar.n)) if bar else None)
    finally:
        if bar is not None:
            bar.close()
    if invalid and sp.invalid_points == "error":
        raise ConfigError(sp.invalid_report(invalid))
    valid = np.ones(sp.size, dtype=bool)
    valid[list(invalid)] = False

    export = None
    if _is_netcdf(path):
        export, side = path, _side_store(path)
        if path.exists() and not side.exists():
            previous = load_sweep(path)
            if _check_attrs(path, previous.attrs, sp, overwrite):
                previous = None
            elif not len(_pending(valid, previous.done.values.reshape(-1), previous.status.values.reshape(-1),
                                  retry_failed)) \
                    and not _unrecorded(invalid, previous.done.values.reshape(-1)):
                return previous  # nothing to do
        else:
            previous = None
        st = _Store.open(side, sp, overwrite=overwrite)
        if previous is not None:
            st.import_dataset(previous)
    else:
        st = _Store.open(path, sp, overwrite=overwrite)

    session = {"started": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()), "computed": 0, "failed": 0,
               "interrupted": False, "host": os.uname().nodename if hasattr(os, "uname") else "",
               "lubelink_version": _lubelink_version()}
    t0 = time.perf_counter()
    discard = False
    try:
        done, status = st.state()
        st.write([(flat, _empty_record(sp.quantities, sp.max_impacts, "invalid", "; ".join(invalid[flat]), 0.0), {})
                  for flat in _unrecorded(invalid, done)])
        done, status = st.state()
        pending = _pending(valid, done, status, retry_failed)
        session["resumed"] = int(done.sum()) - int(done[pending].sum())
        if len(pending):
            with _dask_client(client, None, workers) as (cl, described):
                session["scheduler"] = where or described
                _execute(cl, st, sp, pending, done, status, progress, trace, session, task_seconds)
    except BaseException:
        session["interrupted"] = True
        # a store this call created, in which no point was computed: leave nothing behind
        discard = st.created and session["computed"] == 0
        raise
    finally:
        session["wall_time"] = round(time.perf_counter() - t0, 3)
        session["finished"] = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
        if discard:
            st.close_files()
            shutil.rmtree(st.path, ignore_errors=True)
        else:
            st.close(session)
            if export is not None:
                ds = _export_netcdf(st.path, export)
                if bool(ds.done.all()):
                    shutil.rmtree(st.path, ignore_errors=True)
    return load_sweep(path)


#: Alias of :func:`run_sweep`.
sweep = run_sweep


def _lubelink_version():
    from .. import __version__

    return __version__


def _unrecorded(invalid, done):
    return [flat for flat in invalid if not done[flat]]


def _pending(valid, done, status, retry_failed):
    """Flat indices to compute (an array): valid points not stored (and failed ones with ``retry_failed``)."""
    todo = valid & ~done
    if retry_failed:
        todo |= valid & done & (status != "complete") & (status != "invalid")
    return np.flatnonzero(todo)


class _Queue:
    """The pending flat indices (a NumPy array) consumed from the front, as ``deque`` would be;
    a large sweep keeps one integer array, not a Python object per point."""

    def __init__(self, flats):
        self._flats, self._next = np.asarray(flats, dtype=np.int64), 0

    def __len__(self):
        return len(self._flats) - self._next

    def popleft(self):
        flat = int(self._flats[self._next])
        self._next += 1
        return flat


def _bar(progress, total, desc, initial=0):
    """A :class:`lubelink.progress.Bar` of points on stderr: tqdm's on a terminal, plain lines in a log."""
    from ..progress import Bar

    return Bar(total, desc, "pt", stream=sys.stderr, enabled=progress, initial=initial,
               dynamic_ncols=True, smoothing=0.05, mininterval=0.2,
               bar_format="{desc}: {percentage:3.0f}%|{bar}| {n}/{total} [{elapsed}<{remaining}, "
                          "{rate_fmt}{postfix}]")


def _execute(client, st, sp, pending, done, status, progress, trace, session, task_seconds):
    """Submit the pending points in a moving window of tasks; store each task's points as it completes.

    A task computes one point, or, once the points are known to be short, as many as take about
    ``task_seconds`` on a worker, so that Dask's per-task cost (a few milliseconds of scheduler,
    network and worker time) stays small beside the simulations.
    """
    from collections import deque

    from distributed import as_completed

    opts = _TaskOptions(quantities=sp.quantities, time_series=sp.time_series, max_impacts=sp.max_impacts,
                        n_time=len(sample_times(sp.base_config.solver)) if sp.time_series else 0,
                        output_step=sp.base_config.solver.output_step, tag=sp.hash[:12])
    trace = str(Path(trace).resolve()) if trace else None
    token = uuid.uuid4().hex[:8]
    queue = _Queue(pending)
    single = deque()  # points of a batch that killed its workers: run again one per task
    active = {}
    # on this client's event loop: by default as_completed waits for (and gathers) the futures on the
    # loop of the process's default client, which is another client's whenever one was made current
    # (``with Client() as c``) or started later; asyncio objects used across the two loops' threads
    # lose wake-ups, and the sweep waits for ever for a result that the scheduler holds
    ac = as_completed(loop=client.loop, with_results=True, raise_errors=False)
    retried = int(done[pending].sum())
    failed = int((done & (status != "complete")).sum()) - retried
    n_done = int(done.sum()) - retried
    per_point = None  # seconds per point on a worker (moving average)

    def threads():
        try:
            return max(1, sum(client.nthreads().values()))
        except Exception:  # noqa: BLE001 - a scheduler without workers yet
            return 1

    def batch():
        if single:
            return [single.popleft()]
        n = 1
        if per_point is not None and task_seconds > 0:
            n = int(task_seconds / max(per_point, 1e-6))
            # keep every worker busy to the end, with tasks of at least a tenth of task_seconds: each
            # task costs the scheduler and the client several milliseconds
            n = min(n, 256, max(len(queue) // (2 * nthreads), n // 10))
        return [queue.popleft() for _ in range(min(max(1, n), len(queue)))]

    def submit(n_tasks):
        """Submit up to ``n_tasks`` more tasks in one graph update."""
        tasks = []
        while len(tasks) < n_tasks and (queue or single):
            tasks.append(batch())
        if not tasks:
            return
        futures = client.map(_compute_points, tasks, [[sp.overrides(f) for f in t] for t in tasks],
                             base=sp.base_config, opts=opts, trace=trace, pure=False,
                             key=[f"lubelink-sweep-{sp.hash[:8]}-{token}-{t[0]}-{len(t)}" for t in tasks])
        for task, fut in zip(tasks, futures):
            active[fut] = task
        ac.update(futures)

    nthreads = threads()
    window = 3 * nthreads + 2
    last_window = time.monotonic()
    bar = _bar(progress, sp.size, "sweep", initial=n_done)
    bar.stage(f"{len(pending)} point(s) to compute, {n_done} stored; {nthreads} worker(s)")
    bar.note(f"failed {failed}, remaining {sp.size - n_done}", refresh=False)
    lost = 0
    try:
        submit(nthreads + 1)  # one point a task until a point's duration is known, then the window in batches
        for fut, result in ac:
            task = active.pop(fut)
            if fut.status == "finished":
                results, seconds = result
                per_point = seconds / len(task) if per_point is None else \
                    0.8 * per_point + 0.2 * seconds / len(task)
            elif fut.status == "error" and len(task) > 1:  # find which point kills its workers
                single.extend(task)
                results = []
            elif fut.status == "error":
                exc = result[1] if isinstance(result, tuple) else result
                state = "worker_died" if type(exc).__name__ == "KilledWorker" else "error"
                results = [(task[0], _empty_record(sp.quantities, sp.max_impacts, state, _describe(exc)), {})]
            else:  # cancelled or lost with the connection: not stored, computed on the next run
                lost += len(task)
                results = []
            if results:
                st.write(results)
                new_failed = sum(1 for _, record, _ in results if record["status"] != "complete")
                session["computed"] += len(results)
                session["failed"] += new_failed
                n_done += len(results)
                failed += new_failed
                bar.note(f"failed {failed}, remaining {sp.size - n_done}", refresh=False)
                bar.update(len(results))
            del fut, result, results
            if time.monotonic() - last_window > 30.0:  # follow a cluster that scales
                nthreads, last_window = threads(), time.monotonic()
                window = 3 * nthreads + 2
            if len(active) <= window // 2:  # refill in batches: fewer messages to the scheduler
                submit(window - len(active))
    except BaseException:
        with contextlib.suppress(Exception):
            client.cancel(list(active))
        raise
    finally:
        bar.close()
    session["lost"] = lost
    if lost:
        log.warning("%d point(s) were not computed (their tasks were cancelled or lost with the Dask "
                    "connection); run the sweep again to compute them", lost)

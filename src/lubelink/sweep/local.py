"""Running a sweep without Dask: in the calling process, or on a pool of worker processes.

:func:`run_serial` computes the points one after the other in this process; :func:`run_pool` on a
``concurrent.futures.ProcessPoolExecutor`` of worker processes (``forkserver`` where there is one,
else ``spawn``). Both commit every point through :class:`Tally`, as the Dask path
(:func:`lubelink.sweep.execute._execute`) does: the store, its journal, the counts and the
progress bar are the same on every path. :class:`Batcher` sizes the tasks of the pool and of
Dask alike.
"""

from __future__ import annotations

import contextlib
import math
import os
import sys
import time
from collections import deque

import numpy as np

from .compute import _compute_points, _empty_record

__all__ = ["run_serial", "run_pool", "start_server", "free_cores", "Tally", "Batcher", "POOL_CONTEXT", "DEATHS"]

#: Start method of the pool's processes: ``forkserver`` (a server process imports lubelink once,
#: each worker is a fork of it: no copy of a parent's threads, 0.04 s to shut down) where it
#: exists, else ``spawn``. Measured on 2 loaded cores, first results of 2 workers (imports and the
#: kernels loaded from Numba's cache), two runs: ``spawn`` 3.7-5.7 s and 1.0-1.3 s to shut down,
#: ``forkserver`` 3.5-4.6 s and 0.04 s (``fork`` 2.4-3.4 s, but unsafe beside threads).
POOL_CONTEXT = "forkserver"
#: Modules the forkserver imports once for all its workers; the last runs the sweep's first point for a
#: moment (:mod:`lubelink.sweep._warm`), so that every worker starts with its kernels loaded.
PRELOAD = ["lubelink.sweep.compute", "lubelink.simulate", "lubelink.results", "lubelink.sweep._warm"]
#: A point that breaks the pool this many times, computed alone, is stored as ``worker_died``
#: (Dask's ``distributed.scheduler.allowed-failures`` is 3 as well).
DEATHS = 3


def _cpu_count() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


#: Seconds of CPU use :func:`free_cores` looks back on: since this module was imported (a command's
#: start-up) when that is between :data:`LOOK_MIN` and :data:`LOOK_MAX`, else a fresh sample this long.
LOOK_MIN, LOOK_MAX = 0.3, 30.0


def _cpu_sample():
    """``(wall [s], busy [s of CPU, all processes], own [s of CPU, this process])``, or None without /proc/stat."""
    try:
        with open("/proc/stat", "rb") as f:
            ticks = [int(v) for v in f.readline().split()[1:9]]
        hz = os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, AttributeError):
        return None
    idle = ticks[3] + ticks[4]  # idle, iowait
    return time.monotonic(), (sum(ticks) - idle) / hz, time.process_time()


_MARK = _cpu_sample()


def free_cores():
    """``(free, busy)``: cores of this process's affinity not kept busy by other processes [cores], and
    how many the others kept busy, measured from /proc/stat (the CPU time of every process less this
    process's own, over the time since this module was imported, or a fresh 0.3 s sample); from the
    1-minute load average where there is no /proc/stat."""
    cores = _cpu_count()
    mark = _MARK
    now = _cpu_sample()
    if mark is None or now is None:
        try:
            busy = os.getloadavg()[0]
        except (OSError, AttributeError):
            return float(cores), 0.0
        return max(0.0, cores - busy), busy
    if not LOOK_MIN <= now[0] - mark[0] <= LOOK_MAX:
        mark = now
        time.sleep(LOOK_MIN)
        now = _cpu_sample()
    wall = max(now[0] - mark[0], 1e-3)
    others = max(0.0, (now[1] - mark[1]) - (now[2] - mark[2])) / wall
    total = os.cpu_count() or cores  # /proc/stat counts every core, not only those of the affinity
    busy = min(float(cores), others * cores / total)
    return max(0.0, cores - busy), busy


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


def _hold_sigint():
    """Hold Ctrl-C back while processes start; returns what lets it through again.

    Ctrl-C at a terminal reaches the whole process group. SIGINT is blocked in the calling (main)
    thread: the processes started meanwhile (the pool's forkserver and workers, the local
    cluster's, by threads started meanwhile) inherit the blocked mask, so the signal reaches this
    process alone, which stops the sweep and its workers, instead of each worker printing its own
    KeyboardInterrupt traceback. Another thread of this process (Zarr's I/O loop) may still take
    the signal for the process, and Python then runs its handler in the main thread: meanwhile the
    handler only notes it. A Ctrl-C pressed while held waits, and is raised when let through (by
    the handler that was in place).
    """
    import signal
    import threading
    from multiprocessing import resource_tracker

    if not hasattr(signal, "pthread_sigmask") or threading.current_thread() is not threading.main_thread():
        return lambda: None
    resource_tracker.ensure_running()  # now: the thread that starts it later unblocks SIGINT as it does
    pressed = []
    handler = signal.getsignal(signal.SIGINT)
    if callable(handler):
        signal.signal(signal.SIGINT, lambda signum, frame: pressed.append(signum))
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})

    def release():
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)  # one pending is noted now
        if callable(handler):
            signal.signal(signal.SIGINT, handler)
            if pressed:
                handler(signal.SIGINT, None)

    return release


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


class Batcher:
    """The points of the next task: one until a point's duration is known, then as many as take about
    ``task_seconds`` (fewer towards the end, so that every worker has work to the last); points to
    run one a task (``single``, those of a task that killed its worker) come first."""

    def __init__(self, pending, task_seconds):
        self.queue, self.single, self.task_seconds = _Queue(pending), deque(), task_seconds
        self.per_point = None  # seconds per point on a worker (moving average)

    def __bool__(self):
        return bool(len(self.queue) or self.single)

    def timed(self, seconds, points):
        rate = seconds / max(points, 1)
        self.per_point = rate if self.per_point is None else 0.8 * self.per_point + 0.2 * rate

    def batch(self, nthreads):
        if self.single:
            return [self.single.popleft()]
        n = 1
        if self.per_point is not None and self.task_seconds > 0:
            n = int(self.task_seconds / max(self.per_point, 1e-6))
            # keep every worker busy to the end, with tasks of at least a tenth of task_seconds
            n = min(n, 256, max(len(self.queue) // (2 * nthreads), n // 10))
        return [self.queue.popleft() for _ in range(min(max(1, n), len(self.queue)))]


def _bar(progress, total, desc, initial=0):
    """A :class:`lubelink.progress.Bar` of points on stderr: tqdm's on a terminal, plain lines in a log."""
    from ..progress import Bar

    return Bar(total, desc, "pt", stream=sys.stderr, enabled=progress, initial=initial,
               dynamic_ncols=True, smoothing=0.05, mininterval=0.2,
               bar_format="{desc}: {percentage:3.0f}%|{bar}| {n}/{total} [{elapsed}<{remaining}, "
                          "{rate_fmt}{postfix}]")


class Tally:
    """Commits finished points to the store and counts them, for every executor: the store's journal
    line is the commit; ``session`` (the run's entry in the store's ``runs``) and the bar follow."""

    def __init__(self, st, sp, pending, done, status, progress, session, workers):
        self.st, self.sp, self.session = st, sp, session
        retried = int(done[pending].sum())
        self.failed = int((done & (status != "complete")).sum()) - retried
        self.n_done = int(done.sum()) - retried
        self.bar = _bar(progress, sp.size, "sweep", initial=self.n_done)
        self.bar.stage(f"{len(pending)} point(s) to compute, {self.n_done} stored; {workers} worker(s)")
        self.bar.note(f"failed {self.failed}, remaining {sp.size - self.n_done}", refresh=False)

    def commit(self, results):
        """Store ``[(flat, record, series), ...]`` (one journal append), then count them."""
        if not results:
            return
        self.st.write(results)
        new_failed = sum(1 for _, record, _ in results if record["status"] != "complete")
        self.session["computed"] += len(results)
        self.session["failed"] += new_failed
        self.n_done += len(results)
        self.failed += new_failed
        self.bar.note(f"failed {self.failed}, remaining {self.sp.size - self.n_done}", refresh=False)
        self.bar.update(len(results))

    def close(self):
        self.bar.close()


def run_serial(sp, pending, opts, trace, tally):
    """Compute the points one after the other in this process, each stored as it ends."""
    base = sp.base_config
    for flat in np.asarray(pending, dtype=np.int64).tolist():
        results, _ = _compute_points([flat], [sp.overrides(flat)], base, opts, trace)
        tally.commit(results)
    tally.session["lost"] = 0


def _worker_init():
    """In each worker of the pool: Ctrl-C at a terminal (the whole process group) is the parent's to
    handle; the worker is stopped by it, without a KeyboardInterrupt traceback of its own."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _context():
    import multiprocessing as mp

    try:
        ctx = mp.get_context(POOL_CONTEXT)
    except ValueError:  # no forkserver (Windows)
        return mp.get_context("spawn")
    ctx.set_forkserver_preload(PRELOAD)
    return ctx


def start_server(sp, flat, opts):
    """Start the pool's forkserver now (where there is one; SIGINT held as :func:`_new_pool` holds it),
    warming up on point ``flat`` of ``sp`` (:mod:`lubelink.sweep._warm`), without waiting for it: it
    imports lubelink and loads the point's kernels while this process builds the store. Returns the
    file the server creates once ready (for :func:`run_pool`'s ``ready``), or None."""
    import json

    from ..config import to_toml
    from ._warm import ENV
    from .spec import config_with

    ctx = _context()
    if ctx.get_start_method() != "forkserver":
        return None
    from multiprocessing import forkserver

    if getattr(forkserver._forkserver, "_forkserver_pid", None) is not None:
        return None  # already running (an earlier sweep of this process): its preload is done

    import tempfile

    ready = os.path.join(tempfile.gettempdir(), f"lubelink-warm-{os.getpid()}-{time.monotonic_ns()}")
    point = {"config": to_toml(config_with(sp.base_config, sp.overrides(flat))), "quantities": list(opts.quantities),
             "max_impacts": opts.max_impacts, "ready": ready, "parent": os.getpid()}
    held = _hold_sigint()
    before = os.environ.get(ENV)
    os.environ[ENV] = json.dumps(point)  # the server's environment (read once, by its preload)
    try:
        forkserver.ensure_running()
    finally:
        if before is None:
            os.environ.pop(ENV, None)
        else:
            os.environ[ENV] = before
        held()
    if not _OUTSTANDING:
        import atexit

        atexit.register(_remove_outstanding)
    _OUTSTANDING.add(ready)
    return ready


#: Ready files of servers started by :func:`start_server` that no :func:`_await_server` consumed (a sweep
#: stopped before its pool started): removed at exit.
_OUTSTANDING = set()


def _remove_outstanding():
    for ready in list(_OUTSTANDING):
        with contextlib.suppress(OSError):
            os.unlink(ready)
    _OUTSTANDING.clear()


#: Longest wait [s] for the server's warm-up (a cold cache compiles there) before the workers start anyway.
READY_WAIT = 600.0


def _await_server(ready):
    """Wait (Ctrl-C works) until the server started by :func:`start_server` has done its warm-up."""
    if not ready:
        return
    deadline = time.monotonic() + READY_WAIT
    try:
        while not os.path.exists(ready) and time.monotonic() < deadline:
            time.sleep(0.01)
    finally:
        _OUTSTANDING.discard(ready)
        with contextlib.suppress(OSError):
            os.unlink(ready)


def _new_pool(workers):
    """A pool of ``workers`` processes, all started now with SIGINT blocked (its forkserver too, and so
    every worker, forked from it): Ctrl-C at a terminal, which reaches the whole process group, is
    this process's alone, and it cannot cut a worker's start in half (a worker started after the
    pool's queues are gone prints a traceback). A Ctrl-C pressed meanwhile is raised once the
    workers are up, and stops them."""
    from concurrent.futures import ProcessPoolExecutor

    ctx = _context()
    held = _hold_sigint()
    pool = None
    try:
        if ctx.get_start_method() == "forkserver":
            from multiprocessing import forkserver

            forkserver.ensure_running()
        pool = ProcessPoolExecutor(workers, mp_context=ctx, initializer=_worker_init)
        getattr(pool, "_launch_processes", lambda: None)()  # (CPython 3.9+; else started on demand)
    finally:
        try:
            held()
        except BaseException:
            if pool is not None:
                _stop(pool)
            raise
    return pool


def _stop(pool):
    """Stop a pool at once: queued tasks cancelled, its processes terminated (an interruption)."""
    procs = list((getattr(pool, "_processes", None) or {}).values())
    for p in procs:  # first: a worker still starting must not find the pool's queues gone (a traceback of its own)
        with contextlib.suppress(Exception):
            p.terminate()
    for p in procs:
        with contextlib.suppress(Exception):
            p.join(5.0)
    pool.shutdown(wait=False, cancel_futures=True)


def run_pool(sp, pending, opts, trace, tally, workers, task_seconds, ready=None, per_point=None):
    """Compute the points on a pool of ``workers`` processes, a moving window of tasks in flight, each
    task's points stored as it completes.

    A worker that dies (killed, out of memory) breaks the pool: its points and those of the other
    tasks in flight are computed again, one point a task and one task at a time, on a new pool; a
    point that breaks it :data:`DEATHS` times alone is stored as ``worker_died``. ``ready``: the file
    of :func:`start_server` to wait for first; ``per_point``: a point's time [s] where it was measured
    (the pilot of :mod:`lubelink.sweep.execute`), so that the first tasks are sized by it.
    """
    from concurrent.futures import FIRST_COMPLETED, wait
    from concurrent.futures.process import BrokenProcessPool

    batcher = Batcher(pending, task_seconds)
    batcher.per_point = per_point or None
    deaths = {}
    suspects = deque()  # points of tasks in flight when the pool broke: computed alone
    window = 2 * workers + 1
    active = {}
    with _main_not_rerun():  # a worker does not run the caller's __main__ script again
        _await_server(ready)
        pool = _new_pool(workers)
        try:
            while active or batcher or suspects:
                limit = 1 if suspects else window
                while len(active) < limit and (suspects or batcher):
                    task = [suspects.popleft()] if suspects else batcher.batch(workers)
                    fut = pool.submit(_compute_points, task, [sp.overrides(f) for f in task], sp.base_config,
                                      opts, trace)
                    active[fut] = task
                finished, _ = wait(list(active), return_when=FIRST_COMPLETED)
                broken = []
                for fut in finished:
                    task = active.pop(fut)
                    exc = fut.exception()
                    if exc is None:
                        results, seconds = fut.result()
                        batcher.timed(seconds, len(task))
                        tally.commit(results)
                    elif isinstance(exc, BrokenProcessPool):
                        broken.append(task)
                    else:  # the task itself failed (a result that cannot be sent back): its points fail
                        from .compute import _describe

                        tally.commit([(f, _empty_record(sp.quantities, sp.max_impacts, "error", _describe(exc),
                                                        math.nan), {}) for f in task])
                if broken:
                    broken += list(active.values())  # the whole pool is gone: every task in flight
                    active.clear()
                    pool.shutdown(wait=True, cancel_futures=True)
                    if len(broken) == 1 and len(broken[0]) == 1:  # alone: this point killed its worker
                        flat = broken[0][0]
                        deaths[flat] = deaths.get(flat, 0) + 1
                        if deaths[flat] >= DEATHS:
                            tally.commit([(flat, _empty_record(sp.quantities, sp.max_impacts, "worker_died",
                                                               f"the point killed its worker process {DEATHS} times",
                                                               math.nan), {})])
                        else:
                            suspects.appendleft(flat)
                    else:
                        suspects.extend(f for task in broken for f in task)
                    pool = _new_pool(workers)
        except BaseException:
            _stop(pool)
            raise
        pool.shutdown(wait=True)
    tally.session["lost"] = 0


"""Running a sweep (the client side): :func:`run_sweep`.

Validate every point, open (or resume) the store, choose where the points run
(:func:`choose_executor`: this process, a pool of processes, or Dask; by the time of pilot points
computed here, :func:`run_pilot`, where the kernels are cached), then compute them there
(:func:`lubelink.sweep.local.run_serial`, :func:`~lubelink.sweep.local.run_pool`,
:func:`lubelink.sweep.on_dask._execute`). Each task's points are committed to the store as it
completes, the same way on every path (:class:`~lubelink.sweep.local.Tally`), so an interruption
loses at most the points being computed. Dask and tqdm are imported inside the functions; the
progress bar (:class:`lubelink.progress.Bar`) writes plain lines where stderr is not a terminal.
"""

from __future__ import annotations

import contextlib
import logging
import math
import os
import shutil
import sys
import time
from pathlib import Path

import numpy as np

from ..config import ConfigError
from ..params import sample_times
from .compute import _compute_points, _empty_record, _TaskOptions
from .local import Tally, _bar, _cpu_count, free_cores, run_pool, run_serial, start_server
from .on_dask import LOCAL_CLUSTER_CONFIG, _dask_client, _execute, _threads
from .parse import MAX_POINTS, MAX_POINTS_LIMIT, read_sweep
from .schema import SweepError
from .store import _check_attrs, _export_netcdf, _is_netcdf, _side_store, _Store, load_sweep

__all__ = ["run_sweep", "sweep", "LOCAL_CLUSTER_CONFIG", "EXECUTORS", "SERIAL_SECONDS", "DASK_SECONDS",
           "PILOT_POINTS", "PILOT_SECONDS", "choose_executor", "wants_pilot", "run_pilot"]

log = logging.getLogger(__name__)

# ====================================================================== running
#: ``run_sweep(executor=...)`` and ``lubelink sweep --executor``.
EXECUTORS = ("auto", "serial", "processes", "dask")
#: ``executor="auto"`` runs a sweep in the calling process when its points' estimated time
#: (:func:`lubelink.estimate.run_cost`, one process) is under this [s]. Measured (whole command,
#: ``paper``, 2 cores): this process 3.9 s + 10.3 ms a point, a pool of 2 workers 6.8 s + 4.9 ms a
#: point; the pool overtakes from about 540 points, estimated at 0.84 s (docs/sweeps.md).
SERIAL_SECONDS = 1.0
#: ``executor="auto"`` runs a sweep on a Dask ``LocalCluster`` when its points' estimated time is
#: over this [s] (inf: never; a process pool was faster at every size measured, docs/sweeps.md).
DASK_SECONDS = math.inf
#: The pilot of ``executor="auto"`` (where the kernels are cached and more than one worker would run,
#: :func:`wants_pilot`): this process computes the first pending points, each stored as it ends (done
#: work, as on the serial path), until ``PILOT_POINTS`` points after the first (which loads the compiled
#: kernels) are timed or they took ``PILOT_SECONDS`` [s]; their mean time, the store's commit included,
#: prices the rest here and on the pool (:func:`choose_executor`'s ``timed``). Sweeps of at most
#: ``PILOT_POINTS + 1`` points run here at once.
PILOT_POINTS, PILOT_SECONDS = 8, 0.25
#: Seconds a pool adds beside this process: its forkserver's start (imports, the compiled kernels
#: loaded, a warm-up point: ``SERVER_WARM``, less the time it has run while this process validated the
#: points, built the store and ran the pilot: it starts with them where the estimate says the pool may
#: pay, ``SPECULATE_SECONDS``, and a core beside this process's is free), and the workers' start and stop
#: (``POOL_START``). On a loaded machine (load average 3.5 on 2 cores) a server started beside the pilot
#: made 400 points in this process 4-5 s slower (17.0-20.4 s against 12.8-14.9 s).
SERVER_WARM, POOL_START, SPECULATE_SECONDS = 2.0, 0.4, 0.1


def serial_seconds(sp, n_points, sample=16):
    """Estimated time [s] of ``n_points`` of sweep ``sp`` in one process: the mean of
    :func:`lubelink.estimate.run_cost` over up to ``sample`` points spread over the grid."""
    from ..config import validate
    from ..estimate import run_cost

    picks = sorted({int(i) for i in np.linspace(0, sp.size - 1, min(sp.size, sample))})
    seconds = []
    for flat in picks:
        try:
            seconds.append(run_cost(validate(sp.point_config(flat))).seconds)
        except ConfigError:
            continue
    return n_points * (float(np.mean(seconds)) if seconds else 0.0)


def _workers(executor, workers, dask_given):
    """``(n, load)``: the worker processes of a pool (``workers``, else one per free core for ``"auto"``:
    :func:`~lubelink.sweep.local.free_cores`) and a note on the other processes' load (or "")."""
    n, load = workers or _cpu_count(), ""
    if executor == "auto" and not workers and not dask_given and n > 1:
        free, busy = free_cores()
        n = max(1, min(n, int(free + 0.5)))
        load = f"; other processes keep {busy:.1f} of {_cpu_count()} cores busy"
    return n, load


def wants_pilot(sp, n_points, executor="auto", workers=None, dask_given=False):
    """Whether ``"auto"`` times pilot points of ``sp`` before it chooses (:data:`PILOT_POINTS`): more than a
    worker would run, more points than the pilot, and the kernels of the sweep's base configuration
    cached (:func:`lubelink._prewarm.kernels_ready`; else the pilot would compile, and the estimate
    decides)."""
    from .._prewarm import kernels_ready

    if executor != "auto" or dask_given or n_points <= PILOT_POINTS + 1:
        return False
    if _workers(executor, workers, dask_given)[0] < 2:
        return False
    try:
        return kernels_ready(sp.base_config)
    except Exception:  # noqa: BLE001 - a model that cannot be built here: its points fail alike; the estimate decides
        return False


def choose_executor(sp, n_points, executor="auto", workers=None, dask_given=False, timed=None):
    """``(kind, workers, line)``: where ``n_points`` points of ``sp`` run (``"serial"``,
    ``"processes"`` or ``"dask"``), on how many worker processes, and one line saying why.

    ``"auto"`` without ``workers`` starts a worker per free core (:func:`~lubelink.sweep.local.free_cores`:
    those the other processes of the machine leave idle, rounded to the nearest): with one core free
    (or none), the points run in this process. With ``timed``, ``(points, seconds, pool_start)``: ``points``
    pilot points took ``seconds`` each in this process, and a pool would add ``pool_start`` [s]: the points
    run where they end sooner, ``n_points x seconds`` here or ``pool_start + n_points x seconds / workers``;
    else by the estimate (:func:`serial_seconds` against :data:`SERIAL_SECONDS`). The pool's workers share the
    cores other processes leave free (``workers`` given: as many workers as asked, at most that speed-up).
    Measured with ``--workers 2`` on the shared 2-core machine at a load average of 3.5-5, four pairs of runs,
    400 points: a pool 19.1, 21.6, 12.3, 11.5 s against this process's 12.8, 29.7, 10.8, 9.6 s: the pool lost
    three times of four; a pilot that counted on 2 cores had priced it at 6.7 s against 8.5 s here."""
    n, load = _workers(executor, workers, dask_given)
    if executor == "auto":
        if dask_given:
            kind, why = "dask", "a Dask client or scheduler was given"
        elif n == 1:
            kind, why = "serial", "one worker" if not load else "one core free"
        elif timed is not None:
            points, seconds, pool_start = timed
            cores = min(float(n), max(1.0, free_cores()[0])) if workers else float(n)
            here, pool = n_points * seconds, pool_start + n_points * seconds / cores
            kind = "processes" if pool < here else "serial"
            why = (f"{points} point(s) here took {1e3 * seconds:.3g} ms each: about {here:.2g} s in this process, "
                   f"{pool:.2g} s on {n} workers" + (f" ({cores:.1f} cores free)" if cores < n else ""))
        else:
            est = serial_seconds(sp, n_points)
            if est < SERIAL_SECONDS:
                kind, why = "serial", f"about {est:.2g} s of simulation, less than a pool takes to start"
            elif est > DASK_SECONDS:
                kind, why = "dask", f"about {est:.3g} s of simulation, more than {DASK_SECONDS:g} s"
            else:
                kind, why = "processes", f"about {est:.3g} s of simulation"
    else:
        kind, why = executor, "asked for"
    why += load
    if kind == "serial":
        return kind, 1, f"{n_points:,} point(s) in this process ({why})"
    if kind == "processes":
        return kind, n, f"{n_points:,} point(s) on a pool of {n} worker processes ({why})"
    where = "the given Dask cluster" if dask_given else f"a Dask LocalCluster of {n} workers"
    return kind, n, f"{n_points:,} point(s) on {where} ({why})"


def run_sweep(sweep, store=None, *, executor="auto", client=None, scheduler=None, workers=None, retry_failed=False,
              overwrite=False, progress=True, trace=None, task_seconds=0.5, max_points=None):
    """Run a parameter sweep (in this process, on a pool of processes or on Dask) and return every
    point's results.

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
    executor : {"auto", "serial", "processes", "dask"}
        Where the points run: ``"serial"`` one after the other in this process, ``"processes"`` on
        a pool of ``workers`` processes (``concurrent.futures``), ``"dask"`` on Dask (``client``,
        ``scheduler``, or a ``LocalCluster`` of ``workers`` processes started for this call).
        ``"auto"`` (the default): Dask when a client or a scheduler is given; else in this process
        when ``workers=1``; else, where the compiled kernels are cached, the first points are computed
        (and stored) here and timed (:func:`run_pilot`), and the rest run where they end sooner
        (here, or on a pool that must start: :func:`choose_executor`); without the cache, in this
        process when the points' estimated time is under :data:`SERIAL_SECONDS` (less than a pool
        takes to start), a pool below :data:`DASK_SECONDS`, Dask beyond.
        The choice is logged (and printed with ``progress``) and recorded in the run's entry of
        the store's ``runs`` attribute (``executor``).
    client : distributed.Client, optional
        Your own Dask client (kept open).
    scheduler : str, optional
        Address of a running Dask scheduler, e.g. ``"tcp://10.0.0.5:8786"``.
    workers : int, optional
        Worker processes of the pool or of the local cluster (default: one per core, one thread
        each).
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
        Once the points' duration is known, a task (of Dask or of the pool) computes as many
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
    return load_sweep(_run_sweep(sweep, store, executor=executor, client=client, scheduler=scheduler, workers=workers,
                                 retry_failed=retry_failed, overwrite=overwrite, progress=progress, trace=trace,
                                 task_seconds=task_seconds, max_points=max_points))


def _run_sweep(sweep, store=None, *, executor="auto", client=None, scheduler=None, workers=None, retry_failed=False,
               overwrite=False, progress=True, trace=None, task_seconds=0.5, max_points=None):
    """:func:`run_sweep` without loading the results: the path they are in (the command reads its
    summary from the store with Zarr alone, :func:`lubelink.sweep.store.outcome`; xarray and its
    Dask import cost about 1.5 s)."""
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
    if executor not in EXECUTORS:
        raise SweepError(f"executor={executor!r}: must be one of {', '.join(EXECUTORS)}")
    if (scheduler or client is not None) and executor not in ("auto", "dask"):
        raise SweepError(f"executor={executor!r} runs on this machine: a Dask client or scheduler needs "
                         "executor 'dask' (or 'auto')")
    if executor == "serial" and workers not in (None, 1):
        raise SweepError(f"executor='serial' runs in this process: workers={workers} needs 'processes' or 'dask'")
    check_size(sp, max_points, workers or (None if scheduler or client is not None else _cpu_count()))
    problem = output_problem(path)
    if problem:
        raise SweepError(f"{path}: {problem}")

    with contextlib.ExitStack() as stack:
        where = None
        if scheduler:  # reach it before anything is created: an unreachable one leaves nothing behind
            client, where = stack.enter_context(_dask_client(None, scheduler, None))
        return _run(sp, path, executor, client, where, workers, retry_failed, overwrite, progress, trace,
                    task_seconds)


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


def _run(sp, path, executor, client, where, workers, retry_failed, overwrite, progress, trace, task_seconds):
    opts = _TaskOptions(quantities=sp.quantities, time_series=sp.time_series, max_impacts=sp.max_impacts,
                        n_time=len(sample_times(sp.base_config.solver)) if sp.time_series else 0,
                        output_step=sp.base_config.solver.output_step, tag=sp.hash[:12])
    choice = ready = started = None
    new = client is None and not os.path.lexists(_side_store(path) if _is_netcdf(path) else path) \
        and not (_is_netcdf(path) and path.exists())
    pilot = new and wants_pilot(sp, sp.size, executor, workers, False)
    if new:
        # a new store: every point is pending (less the invalid ones), so the executor is known now (or after
        # the pilot), and a pool's server imports lubelink and loads the kernels while the points are
        # validated, the store is built and the pilot runs (about 2 s of a start)
        if pilot:  # the server on a free core beside the pilot, where the pool may pay
            if serial_seconds(sp, sp.size) >= SPECULATE_SECONDS and free_cores()[0] >= 1.5:
                ready, started = start_server(sp, 0, opts), time.monotonic()
        else:
            choice = choose_executor(sp, sp.size, executor, workers, False)
            if choice[0] == "processes":
                ready, started = start_server(sp, 0, opts), time.monotonic()
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
                return path  # nothing to do
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
            trace = str(Path(trace).resolve()) if trace else None
            tally = per_point = None
            try:
                if not new and client is None:  # a resumed store: its pending points known only now
                    pilot = wants_pilot(sp, len(pending), executor, workers, False)
                if pilot and len(pending) > PILOT_POINTS + 1:
                    tally = Tally(st, sp, pending, done, status, progress, session, _workers(executor, workers,
                                                                                             False)[0])
                    points, per_point, pending = run_pilot(sp, pending, opts, trace, tally)
                    warm = SERVER_WARM if started is None else max(0.0, SERVER_WARM - (time.monotonic() - started))
                    choice = choose_executor(sp, len(pending), executor, workers, False,
                                             timed=(points, per_point, POOL_START + warm))
                elif choice is None or len(pending) != sp.size:
                    choice = choose_executor(sp, len(pending), executor, workers, client is not None)
                kind, n, why = choice
                session["executor"] = kind
                log.info("%s", why)
                if progress:
                    print(f"lubelink sweep: {why}", file=sys.stderr, flush=True)
                if kind == "dask":
                    with _dask_client(client, None, workers) as (cl, described):
                        session["scheduler"] = where or described
                        tally = Tally(st, sp, pending, done, status, progress, session, _threads(cl))
                        _execute(cl, st, sp, pending, opts, trace, tally, task_seconds)
                else:
                    session["scheduler"] = ("this process" if kind == "serial"
                                            else f"process pool, {n} worker process(es)")
                    tally = tally or Tally(st, sp, pending, done, status, progress, session, n)
                    if kind == "serial":
                        run_serial(sp, pending, opts, trace, tally)
                    else:
                        if ready is None and started is None:
                            ready = start_server(sp, int(pending[0]), opts)
                        run_pool(sp, pending, opts, trace, tally, n, task_seconds, ready, per_point)
            finally:
                if tally is not None:
                    tally.close()
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
    return path


def run_pilot(sp, pending, opts, trace, tally):
    """Compute the first of the ``pending`` points in this process, each stored as it ends (:func:`run_serial`'s
    way), timing them: ``(points, seconds, rest)``, the points timed (after the first, which loads the compiled
    kernels), their mean time [s] with the store's commit, and the points left (:data:`PILOT_POINTS`,
    :data:`PILOT_SECONDS`)."""

    flats = np.asarray(pending, dtype=np.int64)
    base, points, spent, i = sp.base_config, 0, 0.0, 0
    while i < len(flats) and points < PILOT_POINTS and spent < PILOT_SECONDS:
        t0 = time.perf_counter()
        flat = int(flats[i])
        results, _ = _compute_points([flat], [sp.overrides(flat)], base, opts, trace)
        tally.commit(results)
        if i:
            points, spent = points + 1, spent + time.perf_counter() - t0
        i += 1
    return points, (spent / points if points else 0.0), flats[i:]


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



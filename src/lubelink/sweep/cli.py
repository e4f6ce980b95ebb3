"""The ``sweep`` and ``plot-sweep`` subcommands: :func:`register_cli` and their handlers.

``lubelink.cli`` imports the package ``lubelink.sweep`` as an extension and calls
``register_cli(subparsers, add_config_args)``. Bad input is a :class:`lubelink.errors.UsageError`
(one line, exit status 2); ``--check`` prints the plan table, a finished run the summary table.
Dask, Zarr and Matplotlib are imported inside the handlers.
"""

from __future__ import annotations

import contextlib
import json
import sys
from pathlib import Path

from .._files import atomic_path, target_problem
from ..config import ConfigError, _name
from ..errors import UsageError, exit_status, interrupted
from .execute import EXECUTORS, _bar, _cpu_count, _run_sweep, check_size, output_problem
from .parse import MAX_POINTS, MAX_POINTS_LIMIT, read_sweep
from .plot import plot_sweep
from .schema import SweepError, _fmt, _parameters
from .spec import Sweep
from .store import _is_netcdf, _side_store, load_sweep, outcome

__all__ = ["register_cli"]


# ====================================================================== command line
def register_cli(subparsers, add_config_args):
    """Add the ``sweep`` and ``plot-sweep`` subcommands."""
    del add_config_args  # a sweep file names its own base configuration
    p = subparsers.add_parser(
        "sweep", help="run a parameter sweep (resumable): in this process, on a process pool or on Dask",
        description="Run every point of a sweep file and store the results (Zarr, or NetCDF for FILE.nc) "
                    "as they finish: in this process, on a pool of worker processes or on Dask (--executor; "
                    "by default the one that finishes first). Running the same command again resumes: "
                    "stored points are skipped. See docs/sweeps.md.")
    p.add_argument("sweep_file", metavar="SWEEP.toml", help="the sweep definition")
    p.add_argument("-o", "--output", metavar="RESULTS",
                   help="results store: DIR.zarr or FILE.nc (default: <sweep file name>.zarr here)")
    p.add_argument("--executor", choices=EXECUTORS, default="auto",
                   help="where the points run: serial (this process), processes (a pool of --workers processes), "
                        "dask (a local Dask cluster of --workers processes, or --scheduler); auto (default): "
                        "dask with --scheduler, else serial for --workers 1 or a sweep of a few seconds, else "
                        "processes")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="address of a running Dask scheduler, e.g. tcp://10.0.0.5:8786 (implies --executor dask)")
    p.add_argument("--workers", metavar="N",
                   help="worker processes of the pool or of the local Dask cluster (default: one per core; "
                        "1 runs in this process)")
    p.add_argument("--retry-failed", action="store_true",
                   help="compute again the stored points whose status is not 'complete'")
    p.add_argument("--overwrite", action="store_true", help="discard a store that holds a different sweep")
    p.add_argument("--check", action="store_true",
                   help="print the plan (size, estimated time and memory, what is stored) at once, then validate "
                        "every point; compute nothing")
    p.add_argument("--max-points", metavar="N",
                   help=f"run (or check) a sweep of up to N points; without it a sweep of more than {MAX_POINTS:,} "
                        "points is refused up front, with its estimated time and memory")
    p.add_argument("--trace", metavar="FILE",
                   help="append a start and an end line per point computation to FILE (audit)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar and no summary")
    p.set_defaults(handler=_cmd_sweep)

    p = subparsers.add_parser(
        "plot-sweep", help="draw a response map of a sweep's results",
        description="Heat map of a stored quantity over two swept parameters, curves for one, facets for "
                    "three (fix more with --select).")
    p.add_argument("results", metavar="RESULTS", help="a sweep store (DIR.zarr or FILE.nc)")
    p.add_argument("--quantity", metavar="NAME", help="quantity to draw (default peak_u2_mid); 'status' maps outcomes")
    p.add_argument("--select", action="append", default=[], metavar="DIM=VALUE",
                   help="fix a dimension at VALUE, a value of the sweep in the unit of its axis (e.g. "
                        "film.viscosity=100 on an axis in mPa s) or with a unit ('film.viscosity=0.1 Pa s'); "
                        "repeatable")
    p.add_argument("-o", "--output", metavar="FILE.png",
                   help="image file (default: <results name>-<quantity>.png here)")
    p.add_argument("--overwrite", action="store_true", help="replace the image file if it exists")
    p.set_defaults(handler=_cmd_plot_sweep)


def _require(*modules, extra):
    """A one-line usage error when an optional dependency is missing."""
    import importlib.util

    missing = [m for m in modules if importlib.util.find_spec(m) is None]
    if missing:
        raise UsageError(f"{', '.join(missing)} not installed; install the extra: pip install 'lubelink[{extra}]'")


def _plan(sp: Sweep, path, estimate):
    params = _parameters()
    rows = [("sweep", sp.origin), ("base", f"{sp.base}" + (f", with [set] {', '.join(sp.fixed)}" if sp.fixed else ""))]
    for i, a in enumerate(sp.axes):
        units = params[a.name][1]
        span = f"{_fmt(a.values[0])} .. {_fmt(a.values[-1])}" if len(a.values) > 1 else _fmt(a.values[0])
        rows.append(("dimensions" if i == 0 else "", f"{a.name}: {len(a.values)} ({a.scale}, {span}"
                     + (f" {units}" if units and units != "1" else "") + ")"))
    if sp.point_rows:
        rows.append(("dimensions" if not sp.axes else "",
                     f"point: {len(sp.point_rows)} explicit points of {', '.join(sp.point_names)}"))
    rows.append(("points", f"{sp.size:,}"))
    rows.append(("estimate", str(estimate)))
    rows.append(("stored per point", ", ".join(("status", "message", "wall_time") + sp.quantities)
                 + (f"; time series {', '.join(sp.time_series)}" if sp.time_series else "")))
    rows.append(("hash", sp.hash[:16]))
    if path is not None and (path.exists() or _side_store(path).exists()):
        try:
            ds = load_sweep(path)
            same = ds.attrs.get("sweep_hash") == sp.hash
            rows.append(("results", f"{path}: {int(ds.done.sum())} of {sp.size} points stored" if same
                         else f"{path}: holds a different sweep (would need --overwrite)"))
        except SweepError as exc:
            rows.append(("results", str(exc)))
    elif path is not None:
        rows.append(("results", f"{path} (new)"))
    return _table(rows)


def _table(rows):
    width = max(len(k) for k, _ in rows)
    return "\n".join(f"{k:<{width}}  {v}" for k, v in rows)


def _summary(stored, sp: Sweep, path):
    """The lines printed after a sweep; ``stored`` is :func:`~lubelink.sweep.store.outcome` of its results."""
    done, status_all, message, attrs = stored
    status = status_all[done]
    counts = {}
    for s in status:
        counts[str(s)] = counts.get(str(s), 0) + 1
    n_done = int(done.sum())
    complete = counts.pop("complete", 0)
    run = json.loads(attrs.get("runs", "[]") or "[]")
    last = run[-1] if run else {}
    rows = [
        ("sweep", f"{sp.origin}: {sp.size} points (" + " x ".join(f"{d} {n}" for d, n in zip(sp.dims, sp.shape)) + ")"),
        ("results", str(path)),
        ("stored", f"{n_done} of {sp.size}: {complete} complete, {n_done - complete} failed"
                   + (" (" + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())) + ")" if counts else "")),
    ]
    if last:
        rate = last["computed"] / last["wall_time"] if last.get("wall_time") else 0.0
        rows.append(("this run", f"{last['computed']} computed in {last['wall_time']:.1f} s"
                     + (f" ({rate:.3g} points/s)" if last["computed"] else "")
                     + (f" on {last['scheduler']}" if last.get("scheduler") else "")
                     + f"; {last.get('resumed', 0)} were already stored"))
    if n_done < sp.size:
        rows.append(("remaining", f"{sp.size - n_done} points; run the same command again to compute them"))
    if counts:
        first = next(i for i, s in enumerate(status_all) if str(s) not in ("complete", ""))
        rows.append(("first failure", f"{sp.label(first)}: {message[first]}"))
    return _table(rows)


def _cmd_sweep(args):
    path_in = Path(args.sweep_file)
    if path_in.is_dir():
        raise UsageError(f"SWEEP.toml = {args.sweep_file!r}: is a folder, not a sweep file")
    if not path_in.exists():
        raise UsageError(f"SWEEP.toml = {args.sweep_file!r}: no such file")
    max_points = None
    if args.max_points is not None:
        try:
            max_points = int(args.max_points)
        except ValueError:
            max_points = 0
        if not 1 <= max_points <= MAX_POINTS_LIMIT:
            raise UsageError(f"--max-points {_name(args.max_points)}: must be a whole number in "
                             f"[1, {MAX_POINTS_LIMIT}]")
    workers = None
    if args.workers is not None:
        try:
            workers = int(args.workers)
        except ValueError:
            workers = 0
        if workers < 1:
            raise UsageError(f"--workers {args.workers}: must be a whole number >= 1")
    if args.scheduler and workers:
        raise UsageError("give either --scheduler ADDRESS (an existing cluster) or --workers N (a local one), not both")
    if args.scheduler and args.executor not in ("auto", "dask"):
        raise UsageError(f"--executor {args.executor} runs on this machine: --scheduler needs --executor dask")
    if args.executor == "serial" and workers not in (None, 1):
        raise UsageError(f"--executor serial runs in this process: --workers {workers} needs --executor "
                         "processes or dask")
    sp = read_sweep(path_in)
    out = Path(args.output) if args.output else Path(f"{path_in.stem}.zarr")
    problem = output_problem(out)
    if problem:
        raise UsageError(f"-o {out}: {problem}")
    estimate = sp.estimate(workers or (None if args.scheduler else _cpu_count()))
    if args.check:
        print(_plan(sp, out, estimate), flush=True)  # at once, before the points are validated
        try:
            check_size(sp, max_points, estimate.workers)
        except SweepError as exc:
            raise UsageError(str(exc)) from None
        bar = _bar(not args.quiet, sp.size, "validating") if sp.size >= 500 else None
        try:
            invalid = sp.invalid_points_of(progress=(lambda n: bar.update(n - bar.n)) if bar else None)
        finally:
            if bar is not None:
                bar.close()
        print(_table([("validated".ljust(len("stored per point")), f"{sp.size:,} points, "
                                    + (f"{len(invalid):,} invalid" if invalid else "all valid"))]))
        if invalid and sp.invalid_points == "error":
            raise ConfigError(sp.invalid_report(invalid))
        return 0
    try:
        check_size(sp, max_points, estimate.workers)
    except SweepError as exc:
        raise UsageError(str(exc)) from None
    _require(*(("distributed",) if args.executor == "dask" or args.scheduler else ()), "zarr", "xarray",
             extra="sweep")
    if not args.quiet:
        print(f"{sp.origin}: {sp.size:,} points -> {out}; estimate {estimate}", file=sys.stderr)
    try:
        results = _run_sweep(sp, out, executor=args.executor, scheduler=args.scheduler, workers=workers,
                       retry_failed=args.retry_failed,
                       overwrite=args.overwrite, progress=not args.quiet, trace=args.trace,
                       max_points=max_points)
    except SweepError as exc:
        raise UsageError(str(exc)) from None
    except KeyboardInterrupt as exc:
        stored = "?"
        with contextlib.suppress(Exception):
            stored = int(outcome(out)[0].sum())  # (Zarr alone: xarray would take a second or two to import)
        if not (out.exists() or _side_store(out).exists()):
            print(f"lubelink: {interrupted(exc)}; no point was stored", file=sys.stderr)
        else:
            print(f"lubelink: {interrupted(exc)}; {stored} of {sp.size} points are stored in {out}; run the same "
                  "command again to resume", file=sys.stderr)
        return exit_status(exc)
    stored = outcome(results)
    if not args.quiet:
        print(_summary(stored, sp, out))
    return 0 if bool(stored[0].all()) else 1


def _cmd_plot_sweep(args):
    path = Path(args.results)
    if not (path.exists() or (_is_netcdf(path) and _side_store(path).exists())):
        raise UsageError(f"RESULTS = {args.results!r}: no such sweep store")
    select = {}
    for text in args.select:
        if "=" not in text:
            raise UsageError(f"--select {text!r}: must look like DIM=VALUE, e.g. film.viscosity=100 (mPa s)")
        dim, value = (part.strip() for part in text.split("=", 1))
        select[dim] = value
    if args.output:
        _check_image(Path(args.output), args.overwrite)
    _require("matplotlib", "zarr", "xarray", extra="plot,sweep")
    import matplotlib

    matplotlib.use("Agg")
    try:
        ds = load_sweep(path)
        quantity = args.quantity
        fig = plot_sweep(ds, quantity, select=select)
    except SweepError as exc:
        raise UsageError(str(exc)) from None
    quantity = quantity or ("peak_u2_mid" if "peak_u2_mid" in ds else "status")
    out = Path(args.output) if args.output else Path(f"{path.name.split('.')[0]}-{quantity}.png")
    _check_image(out, args.overwrite)
    try:
        with atomic_path(out, overwrite=args.overwrite) as tmp:
            fig.savefig(tmp, dpi=120, bbox_inches="tight", format=out.suffix.lstrip(".").lower() or "png")
    except FileExistsError:
        raise UsageError(f"-o {out}: appeared while the plot was drawn; it was not replaced (add --overwrite "
                         "to replace it)") from None
    except OSError as exc:
        raise UsageError(f"-o {out}: could not be written ({exc.strerror or exc})") from None
    print(f"wrote {out}")
    return 0


#: Image formats of ``plot-sweep -o`` (Matplotlib's, by suffix).
IMAGE_SUFFIXES = (".png", ".pdf", ".svg", ".jpg", ".jpeg", ".tif", ".tiff", ".webp", ".eps", ".ps")


def _check_image(out, overwrite):
    """Refuse, before drawing, an image file that cannot be written: an existing one without
    ``--overwrite``, anything but a regular file, a suffix that is not an image format."""
    import os

    if out.suffix.lower() not in IMAGE_SUFFIXES:
        raise UsageError(f"-o {out}: name an image file, one of " + ", ".join(f"*{s}" for s in IMAGE_SUFFIXES))
    problem = target_problem(out)
    if not problem and os.path.lexists(out) and not overwrite:
        problem = "the file exists; add --overwrite to replace it"
    if problem:
        raise UsageError(f"-o {out}: {problem}")

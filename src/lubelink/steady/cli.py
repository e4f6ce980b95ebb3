"""The ``periodic``, ``continue`` and ``plot-branch`` subcommands: :func:`register_cli` and their handlers.

``lubelink.cli`` imports this package as an extension and calls
``register_cli(subparsers, add_config_args)``. Exit status: 0 success; 1 no periodic response
found (``periodic``, nothing written) or a branch that stopped before ``--to`` (``continue``, the
points found are written); 2 invalid input. Matplotlib is imported inside the handlers.
"""

from __future__ import annotations

import sys
from pathlib import Path

from ..errors import UsageError
from .problem import JACOBIANS

__all__ = ["register_cli"]


def register_cli(subparsers, add_config_args):
    """Add the ``periodic``, ``continue`` and ``plot-branch`` subcommands."""
    p = subparsers.add_parser(
        "periodic", help="find the periodic steady state by shooting, with its Floquet multipliers",
        description="Find the response with the period of the crank (2 pi/|omega0|) by shooting: Newton's "
                    "method on y(T; y0) = y0, the monodromy matrix from the variational equations (with a "
                    "saltation matrix at each impact; finite differences at a graze or a compliant or sustained "
                    "contact). Writes one period of the usual "
                    "results plus floquet_modulus and floquet_argument. See docs/periodic.md.")
    add_config_args(p)
    p.add_argument("-o", "--output", metavar="FILE.nc",
                   help="results file (default: <scenario or config name>-periodic.nc here)")
    p.add_argument("--overwrite", action="store_true", help="replace FILE.nc if it exists")
    p.add_argument("--periods", type=int, default=1, metavar="K",
                   help="crank turns in the period (2: period-doubled responses; default 1)")
    p.add_argument("--warmup", type=int, default=0, metavar="N",
                   help="periods of transient from rest before Newton's method (default 0)")
    _common(p, "auto")
    p.set_defaults(handler=_cmd_periodic)

    p = subparsers.add_parser(
        "continue", help="response curve: follow the periodic response over a parameter",
        description="Pseudo-arclength continuation of the periodic response as PARAMETER (default the crank "
                    "speed) goes from its value (or --from) to --to, with the Floquet multipliers of every "
                    "orbit; folds and bifurcations (a multiplier leaving the unit circle through +1, -1 or as "
                    "a complex pair) are reported. Writes the branch (NetCDF) and, with --figure, the peak "
                    "deflection against the parameter with stability marked. See docs/periodic.md.")
    add_config_args(p)
    p.add_argument("--parameter", default="mechanism.crank_speed", metavar="SECTION.KEY",
                   help="the real parameter to vary (default mechanism.crank_speed; the period follows it)")
    p.add_argument("--from", dest="start", type=float, metavar="VALUE", help="start (default: the configuration's value)")
    p.add_argument("--to", dest="stop", type=float, required=True, metavar="VALUE", help="end of the branch")
    p.add_argument("--max-step", type=float, metavar="DELTA",
                   help="largest change of the parameter between two orbits (default |to - from|/100)")
    p.add_argument("--max-points", type=int, default=2000, metavar="N", help="most orbits (default 2000)")
    p.add_argument("--warmup", type=int, default=0, metavar="N",
                   help="periods of transient from rest before the first shooting (default 0)")
    p.add_argument("-o", "--output", metavar="FILE.nc",
                   help="branch file (default: <scenario or config name>-branch.nc here)")
    p.add_argument("--figure", metavar="FILE.png", help="also draw the response curve")
    p.add_argument("--overwrite", action="store_true", help="replace existing files")
    _common(p, "auto")
    p.set_defaults(handler=_cmd_continue)

    p = subparsers.add_parser(
        "plot-branch", help="draw response curves from branch files",
        description="Peak midpoint deflection against the parameter for one or more branch files of "
                    "'lubelink continue', stable solid, unstable dashed, resonances omega_1/k marked.")
    p.add_argument("branches", nargs="+", metavar="FILE.nc", help="branch files")
    p.add_argument("-o", "--output", required=True, metavar="FILE.png", help="image file")
    scale = p.add_mutually_exclusive_group()
    scale.add_argument("--linear", action="store_true",
                       help="linear deflection axis (default: logarithmic where the peaks span a decade or more, "
                            "else linear)")
    scale.add_argument("--log", action="store_true", help="logarithmic deflection axis")
    p.add_argument("--title", help="figure title")
    p.add_argument("--overwrite", action="store_true", help="replace FILE.png if it exists")
    p.set_defaults(handler=_cmd_plot_branch)


def _common(p, default):
    p.add_argument("--jacobian", choices=JACOBIANS, default=default,
                   help="monodromy matrix: 'auto' (variational equations, with a saltation matrix at each "
                        "impact; finite differences at a graze or a compliant or sustained contact), or always "
                        f"one of them (default {default})")
    p.add_argument("--tol", type=float, default=1e-9, help="scaled residual of Newton's method (default 1e-9)")
    p.add_argument("-q", "--quiet", action="store_true", help="no summary")


#: The largest ``--tol`` (a scaled residual of Newton's method; beyond it an orbit is not an orbit).
MAX_TOL = 1e-3


def _check_numbers(args):
    """Refuse the numeric options out of their ranges before anything is computed: one line each, naming
    the option, its value and the range (exit status 2)."""
    import math

    problems = []

    def need(option, value, ok, rule):
        if value is not None and not ok(value):
            problems.append(f"{option} {value}: {rule}")

    need("--tol", args.tol, lambda v: 0.0 < v <= MAX_TOL, f"must be a number in (0, {MAX_TOL:g}]")
    need("--warmup", args.warmup, lambda v: v >= 0, "must be >= 0")
    need("--periods", getattr(args, "periods", None), lambda v: v >= 1, "must be >= 1")
    need("--max-points", getattr(args, "max_points", None), lambda v: v >= 2, "must be >= 2")
    need("--max-step", getattr(args, "max_step", None), lambda v: 0.0 < v < math.inf, "must be a finite number > 0")
    need("--from", getattr(args, "start", None), math.isfinite, "must be a finite number")
    need("--to", getattr(args, "stop", None), math.isfinite, "must be a finite number")
    if problems:
        raise UsageError("\n".join(problems))


def _target(args, suffix, option="--output", given=None, source=None, figure=False):
    """The output path, checked before anything is computed (so that no work is lost at the end): results
    with a NetCDF suffix, a figure with a suffix Matplotlib writes; an existing target only with
    ``--overwrite`` and only a regular file; a writable folder (:func:`lubelink._files.target_problem`)."""
    from .._files import target_problem
    from ..netcdf import EXISTS, output_problem

    path = Path(given) if given else Path(f"{Path(str(source)).stem}{suffix}")
    if figure:
        kinds = _figure_kinds()
        if path.suffix.lower().lstrip(".") not in kinds:
            raise UsageError(f"{option} {path}: a figure is written as " + ", ".join(f".{k}" for k in kinds)
                             + "; name the file accordingly")
        problem = EXISTS if path.exists() and not args.overwrite else target_problem(path)
    else:
        problem = output_problem(path, args.overwrite)
    if problem == EXISTS:
        raise UsageError(f"{option} {path}: the file exists; add --overwrite to replace it")
    if problem:
        raise UsageError(f"{option} {path}: {problem}")
    return path


def _figure_kinds():
    """File suffixes Matplotlib writes a figure as (png, pdf, svg, ...)."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    return sorted(Figure().canvas.get_supported_filetypes())


def _table(rows):
    width = max(len(k) for k, _ in rows)
    return "\n".join(f"{k:<{width}}  {v}" for k, v in rows)


def _multipliers(mu):
    import numpy as np

    parts = []
    for m in mu[:6]:
        parts.append(f"{abs(m):.6g}" + (f" (arg {np.angle(m):+.4g})" if abs(m.imag) > 1e-12 * abs(m) else
                                          " (real, negative)" if m.real < 0 else ""))
    return ", ".join(parts) + (" ..." if len(mu) > 6 else "")


def _cmd_periodic(args):
    import time

    import numpy as np

    from ..cli_io import resolve_args
    from ..cli_io import write_results as _write_results
    from .orbit import find_periodic, orbit_results
    from .shooting import ShootingError

    began = time.perf_counter()
    _check_numbers(args)
    source, config = resolve_args(args)
    path = _target(args, "-periodic.nc", given=args.output, source=source)
    try:
        orbit = find_periodic(config, periods=args.periods, warmup=args.warmup, jacobian=args.jacobian, tol=args.tol)
    except ShootingError as exc:
        print(f"lubelink: {exc}", file=sys.stderr)
        return 1
    r = orbit_results(orbit)
    path, failure = _write_results(r, path, args.overwrite)
    if not args.quiet and path is not None:
        a = r.attrs
        u = np.abs(r["u2_mid"])
        i = int(np.argmax(u))
        # a multiplier within its accuracy estimate of the unit circle is on it, as far as can be told
        from . import floquet

        mu, err = orbit.multipliers, orbit.multiplier_errors
        on = np.abs(np.abs(mu) - 1.0) <= err
        stable = ("stable" if orbit.stable else "unstable" if floquet.outside(mu, err) else
                  f"not asymptotically stable (a multiplier on the unit circle, to its accuracy {np.max(err[on]):.1e})")
        rows = [("source", str(source)),
                ("period", f"{orbit.period:.6g} s" + (f" ({args.periods} crank turns)" if args.periods > 1 else "")),
                ("newton", f"{orbit.iterations} step(s) after {orbit.warmup} period(s) of transient; residual "
                           f"{a['residual']:.2g} (scaled), |q(T) - q(0)| = {a['residual_q']:.2g} m"),
                ("monodromy", f"{orbit.jacobian}, {orbit.evaluations} period(s) integrated"
                              + (f" ({orbit.jacobian_note})" if orbit.jacobian_note else "")),
                ("floquet", f"|multipliers| {_multipliers(orbit.multipliers)}: {stable}"),
                ("peak |u2_mid|", f"{1e3 * u[i]:.4f} mm at t = {float(r['time'][i]):.4f} s")]
        if "u3_mid" in r:  # the spatial model: the out-of-plane and axial midpoint too
            u3 = np.abs(r["u3_mid"])
            j = int(np.argmax(u3))
            q1 = np.asarray(r["q1"])  # u1(L/2) = sum_n q1_n sin(n pi / 2)
            u1 = np.max(np.abs(q1 @ np.sin(0.5 * np.pi * np.arange(1, q1.shape[1] + 1))))
            rows += [("peak |u3_mid|", f"{1e3 * u3[j]:.4f} mm at t = {float(r['time'][j]):.4f} s"),
                     ("peak |u1_mid|", f"{1e6 * u1:.4f} um (axial)")]
        if "film_min" in r:
            rows.append(("thinnest film", f"{1e3 * float(np.min(r['film_min'])):.4f} mm"))
        rows.append(("impacts", f"{a['impact_count']} in the period"))
        rows.append(("wall time", f"{a['wall_time']:.3f} s finding and sampling the orbit (its wall_time), "
                                  f"{time.perf_counter() - began:.3f} s in all"))
        rows.append(("wrote", str(path)))
        print(_table(rows))
    if failure:
        print(f"lubelink: error: {failure}", file=sys.stderr)
        return 1
    return 0


def _cmd_continue(args):
    import time

    from ..cli_io import resolve_args
    from ..cli_io import write_results as _write_results
    from ..results import dataset
    from .branch import branch_results, find_branch
    from .shooting import MapFailure, ShootingError

    began = time.perf_counter()
    _check_numbers(args)
    source, config = resolve_args(args)
    path = _target(args, "-branch.nc", given=args.output, source=source)
    figure = _target(args, "", "--figure", given=args.figure, figure=True) if args.figure else None
    try:
        branch, summaries, family = find_branch(
            config, args.stop, args.parameter, start=args.start, warmup=args.warmup, jacobian=args.jacobian,
            max_parameter_step=args.max_step, max_points=args.max_points, tol=args.tol)
    except (ShootingError, MapFailure) as exc:
        print(f"lubelink: no periodic response at the start: {exc}", file=sys.stderr)
        return 1
    r = branch_results(branch, summaries, family)
    path, failure = _write_results(r, path, args.overwrite)
    if figure is not None and path is not None:
        try:
            _save_figure(dataset(r), figure, title=f"{source}: periodic response against {args.parameter}")
        except OSError as exc:  # the branch is written: say so and go on
            failure = f"--figure {figure}: could not be written ({exc.strerror or exc}); the branch is in {path}"
            figure = None
    if not args.quiet and path is not None:
        pts = branch.points
        stable = sum(p.stable for p in pts)
        rows = [("source", str(source)),
                ("branch", f"{len(pts)} periodic responses, {args.parameter} from {pts[0].parameter:.6g} to "
                           f"{pts[-1].parameter:.6g}; {stable} stable"),
                ("status", branch.status + ("" if branch.status == "complete" else f": {branch.message}")),
                ("bifurcations", r.attrs["bifurcations"]),
                ("monodromy", r.attrs["jacobian"]),
                ("wall time", f"{branch.wall_time:.2f} s finding the branch (its wall_time), "
                              f"{time.perf_counter() - began:.2f} s in all; {branch.evaluations} periods integrated"),
                ("wrote", str(path) + (f", {figure}" if figure else ""))]
        print(_table(rows))
    if failure:
        print(f"lubelink: error: {failure}", file=sys.stderr)
        return 1
    return 0 if branch.status == "complete" else 1


def _save_figure(branches, path, title=None, log=None):
    import matplotlib

    matplotlib.use("Agg")
    from .._files import atomic_path
    from .plot import figure_branch

    fig = figure_branch(branches, title=title, log=log)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=130, format=path.suffix.lstrip(".").lower() or "png")


def _cmd_plot_branch(args):
    from .._files import read_netcdf

    out = _target(args, "", given=args.output, figure=True)
    branches = {}
    for name in args.branches:
        p = Path(name)
        if not p.is_file():
            raise UsageError(f"FILE.nc = {name!r}: no such branch file")
        ds = read_netcdf(p, "branch file", UsageError, name=name)
        if "max_modulus" not in ds or "parameter" not in ds:
            raise UsageError(f"{name}: not a branch file of 'lubelink continue'")
        branches[p.stem] = ds
    _save_figure(branches if len(branches) > 1 else next(iter(branches.values())), out, title=args.title,
                 log=True if args.log else False if args.linear else None)
    print(f"wrote {out}")
    return 0

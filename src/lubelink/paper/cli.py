"""The ``lubelink figures`` and ``lubelink animate`` subcommands.

:func:`register_cli` is what :mod:`lubelink.cli` calls for every extension
module (it imports ``lubelink.paper`` by name and calls its
``register_cli(subparsers, add_config_args)``). The handlers turn bad input
into :class:`lubelink.errors.UsageError` (one line, exit status 2) and import
the heavy libraries only when they run.
"""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import UsageError, suggest
from .animation import animate
from .figures import FIGURES, make_figures

__all__ = ["register_cli"]

#: Image formats ``lubelink figures --formats`` accepts.
FORMATS = ("png", "pdf", "svg")


def _cmd_figures(args):
    only = None
    if args.only:
        only = [n.strip() for n in args.only.split(",") if n.strip()]
        bad = [n for n in only if n not in FIGURES]
        if bad:
            raise UsageError(f"--only {args.only}: unknown figure(s) {', '.join(bad)}"
                             f"{suggest(bad[0], FIGURES)}; choose from {', '.join(FIGURES)}")
    out = Path(args.output)
    if out.exists() and not out.is_dir():
        raise UsageError(f"-o {out}: exists and is not a folder")
    from .._files import folder_problem

    problem = folder_problem(out if out.exists() else out.parent)  # before minutes of simulations
    if problem:
        raise UsageError(f"-o {out}: {problem}")
    formats = tuple(f.strip().lower() for f in args.formats.split(",") if f.strip())
    bad = [f for f in formats if f not in FORMATS]
    if bad or not formats:
        raise UsageError(f"--formats {args.formats}: choose from {', '.join(FORMATS)}"
                         + (suggest(bad[0], FORMATS) if bad else ""))
    if args.dpi is not None and not 10 <= args.dpi <= 1200:
        raise UsageError(f"--dpi {args.dpi}: must be in [10, 1200]")
    from .._files import target_problem

    for name in only or FIGURES:  # a figure's file taken by a folder, a FIFO, ...: said before computing
        for fmt in formats:
            target = out / f"{FIGURES[name]}.{fmt}"
            problem = target_problem(target) if os.path.lexists(target) else None
            if problem:
                raise UsageError(f"-o {out}: {target.name} {problem}")
    try:
        result = make_figures(out, low_res=args.low_res, only=only, progress=not args.quiet, formats=formats,
                              dpi=args.dpi)
    except OSError as exc:  # the disk filled up, a file appeared meanwhile, ...
        raise UsageError(f"-o {out}: could not be written ({exc.strerror or exc})") from None
    if not args.quiet:
        for name, paths in result.paths.items():
            print(f"{name:<12} " + "  ".join(str(p) for p in paths))
        if result.calibration is not None:
            print(f"{'calibration':<12} {result.calibration.message}")
        print(f"{'runs':<12} {result.runs} simulations")
    return 0


def _cmd_animate(args):
    from ..cli_io import resolve_args
    from ..config import ConfigError

    _, config = resolve_args(args)
    try:
        path = animate(config, None, args.output, fps=args.fps, duration=args.duration,
                       speed=args.speed, overwrite=args.overwrite, progress=not args.quiet)
    except ConfigError:
        raise
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    except OSError as exc:  # the file appeared meanwhile, the disk filled up, ...
        raise UsageError(f"-o {args.output}: could not be written ({exc.strerror or exc})") from None
    if not args.quiet:
        print(f"wrote {path}")
    return 0


def register_cli(subparsers, add_config_args):
    """Add the ``figures`` and ``animate`` subcommands to the ``lubelink`` parser."""
    p = subparsers.add_parser(
        "figures", help="write the paper's figures (Figs. 6-9, modal convergence, errata) as PNG and PDF",
        description="Compute the paper's Section 6 results and write the figures as PNG and PDF: "
                    + ", ".join(f"{k} ({v})" for k, v in FIGURES.items())
                    + ". Fig. 9's clearance is calibrated by root finding and cached in DIR/calibration.json. "
                      "Existing figure files in DIR are replaced.")
    p.add_argument("-o", "--output", default="figures", metavar="DIR", help="output folder (default: figures)")
    p.add_argument("--low-res", action="store_true",
                   help="coarse and quick: looser tolerance, short modal runs, small images")
    p.add_argument("--only", metavar="NAMES", help="comma-separated subset, e.g. fig6,fig9")
    p.add_argument("--formats", default="png,pdf", metavar="LIST",
                   help="comma-separated image formats (default png,pdf)")
    p.add_argument("--dpi", type=int, metavar="N", help="resolution of raster images (default 150; 60 with --low-res)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar and no list of files")
    p.set_defaults(handler=_cmd_figures)

    p = subparsers.add_parser(
        "animate", help="animate the mechanism (GIF, or MP4 with ffmpeg)",
        description="Simulate a configuration and animate it in two views, each to scale: the "
                    "mechanism in its plane (crank, link, collar on its vertical guide, slider; X, Y "
                    "in m), and the link in its own frame (deflection u2 in mm along x in m, the "
                    "collar faces at +-H/2).")
    add_config_args(p)
    p.add_argument("-o", "--output", required=True, metavar="FILE", help="animation file, .gif or .mp4")
    p.add_argument("--fps", type=int, default=20, metavar="N", help="frames per second (default 20)")
    p.add_argument("--duration", type=float, default=0.4, metavar="S",
                   help="simulated time shown [s] (default 0.4 s, two crank turns)")
    p.add_argument("--speed", type=float, default=0.1, metavar="FACTOR",
                   help="playback speed relative to real time (default 0.1: ten times slower)")
    p.add_argument("--overwrite", action="store_true", help="replace FILE if it exists")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    p.set_defaults(handler=_cmd_animate)

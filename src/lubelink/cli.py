"""Command-line interface: ``lubelink run | config | scenarios | ...``.

Exit status: 0 success, 1 a run that ended early (its partial results are
still written, marked as partial), 2 invalid input (one line per problem,
no traceback), 130 interrupted.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from pathlib import Path

from .cli_io import _load_results, is_results_file, resolve_args
from .cli_io import write_results as _write_results
from .errors import (BackendError, ConfigError, Terminated, UsageError, catch_interrupts, exit_status, interrupted,
                     was_interrupted)

__all__ = ["main", "resolve_args", "UsageError"]

EPILOG = """examples:
  lubelink run                                  the paper's slider-crank (scenario 'paper')
  lubelink run --scenario paper-impact -o impact.nc
  lubelink run my.toml --set beam.modes=5 --set film.viscosity=0.2
  lubelink config --scenario paper-dry          print the full configuration as commented TOML
  lubelink show impact.nc                       the summary and configuration of a results file
  lubelink run impact.nc --set beam.modes=3     run a results file's configuration again (impact-rerun.nc)
"""


#: Modules that add subcommands: each has ``register_cli(subparsers, add_config_args)``, which adds
#: its parsers with ``set_defaults(handler=function(args) -> exit status)``; they import heavy
#: libraries (Matplotlib, Dask) only inside the handlers.
EXTENSIONS = ("lubelink.paper", "lubelink.sweep", "lubelink.steady")


def _add_config_args(p):
    from .scenarios import SCENARIOS

    names = ", ".join(SCENARIOS)
    p.add_argument("config", nargs="?", metavar="CONFIG.toml|SCENARIO|RESULTS.nc",
                   help="TOML configuration file (its top-level 'scenario' key names the base), the name of "
                        f"a built-in scenario ({names}), or a results file (the configuration it was computed "
                        "with); default 'paper'")
    p.add_argument("--scenario", metavar="NAME", help=f"built-in scenario to start from when no CONFIG is given: {names}")
    p.add_argument("--set", dest="overrides", action="append", default=[], metavar="SECTION.KEY=VALUE",
                   help="override one parameter, value in TOML syntax (repeatable), e.g. --set beam.modes=5")


def _default_budget():
    from .scenarios import DEFAULT_MAX_WALL_TIME

    return DEFAULT_MAX_WALL_TIME


def build_parser(extensions=True):
    """The ``lubelink`` parser; ``extensions=False`` leaves out the subcommands of :data:`EXTENSIONS`
    (a core command such as ``run`` does not import them)."""
    from . import __version__

    parser = argparse.ArgumentParser(
        prog="lubelink", formatter_class=argparse.RawDescriptionHelpFormatter, epilog=EPILOG,
        description="Vibration of a flexible link carrying a lubricated prismatic joint "
                    "(Marghitu & Guran, corrected and extended).")
    parser.add_argument("--version", action="version", version=f"lubelink {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    p = sub.add_parser("run", help="run one simulation and write its results as NetCDF",
                       description="Run one simulation, print a summary and write the results (NetCDF). "
                                   "With no arguments it runs the 'paper' scenario. The output file is checked "
                                   "before the run; a run estimated to take long says so before it starts, and "
                                   "every run stops after its wall-time budget, solver.max_wall_time (default "
                                   f"{_default_budget():g} s; inf for none), keeping its results so far.")
    _add_config_args(p)
    p.add_argument("-o", "--output", metavar="FILE.nc",
                   help="results file (default: <scenario or config name>.nc in the current folder)")
    p.add_argument("--overwrite", action="store_true", help="replace FILE.nc if it exists")
    p.add_argument("--no-output", action="store_true", help="do not write a results file")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar and no summary")

    p = sub.add_parser("config", help="print the resolved configuration as commented TOML",
                       description="Validate a configuration and print it in full as TOML, each key with a "
                                   "comment giving its symbol, unit, meaning and valid values (a starting point "
                                   "for your own file; it loads back to the same configuration).")
    _add_config_args(p)

    p = sub.add_parser("show", help="print the summary and the configuration of a results file",
                       description="Print the summary of a results file, as lubelink run printed it, and the "
                                   "configuration it was computed with (TOML). 'lubelink run FILE.nc' runs that "
                                   "configuration again.")
    p.add_argument("file", metavar="FILE.nc", help="a results file written by lubelink run or lubelink.save")
    p.add_argument("--no-config", action="store_true", help="the summary only")
    sub.add_parser("scenarios", help="list the built-in scenarios", description="List the built-in scenarios.")
    sub.add_parser("compile", help="compile the numerical kernels now (cached on disk)",
                   description="Compile every numerical kernel (or load it from Numba's on-disk cache) and say how "
                               "long it took: a first run in a new installation otherwise does this itself. Useful "
                               "before a test session, on each worker of a cluster, or in a container image.")
    for module in EXTENSIONS if extensions else ():
        importlib.import_module(module).register_cli(sub, _add_config_args)
    return parser


def _source_label(source, overrides, shown=4):
    """``source`` as the summary names it: with the ``--set`` overrides that changed it, if any."""
    from .config import parse_override

    latest = {}
    for text in overrides:  # the last --set of a key wins, as in resolve_args
        latest.pop(parse_override(text)[0], None)
        latest[parse_override(text)[0]] = text.strip()
    if not latest:
        return str(source)
    texts = list(latest.values())
    listed = ", ".join(texts[:shown]) + (f", ... ({len(texts)} in all; the file's config attribute has them)"
                                         if len(texts) > shown else "")
    return f"{source} + {len(texts)} override{'s' if len(texts) > 1 else ''}: {listed}"


#: An up-front cost estimate above this [s] is reported before the run starts.
WARN_SECONDS = 60.0


def _warn_cost(config):
    """Say before the run when its estimated cost is long, or beyond its wall-time budget."""
    import math

    from dataclasses import replace

    from .estimate import duration, results_cost, run_cost

    est = run_cost(config)
    est = replace(est, seconds=est.seconds + results_cost(config))
    budget = config.solver.max_wall_time
    if est.seconds > budget:
        spelled = f" ({duration(budget)})" if budget >= 90 else ""
        print(f"lubelink: warning: this run is estimated to take {est}; solver.max_wall_time = "
              f"{budget:g} s{spelled} will stop it first, with status 'timeout' and the results so far; set a "
              "larger solver.max_wall_time (or inf) to let it finish", file=sys.stderr)
    elif est.seconds > WARN_SECONDS:
        print(f"lubelink: note: this run is estimated to take {est}"
              + (f"; it stops after solver.max_wall_time = {budget:g} s" if math.isfinite(budget) else ""),
              file=sys.stderr)
    return est


PROGRESS_DELAY = 0.5


def _nothing():
    import contextlib

    return contextlib.nullcontext()


def _cmd_run(args):
    import time

    from ._prewarm import announcing, first_run
    from .build import build_model
    from .netcdf import EXISTS, output_problem
    from .results import collect
    from .simulate import run

    began = time.perf_counter()
    if args.output is not None and args.no_output:
        raise UsageError(f"-o {args.output} and --no-output: give one of them")
    if args.output is not None and not args.output.strip():
        raise UsageError(f"-o {args.output!r}: an empty file name; give FILE.nc, or --no-output")
    source, config = resolve_args(args)
    path = None
    if not args.no_output:
        stem = Path(str(source)).stem + ("-rerun" if is_results_file(str(source)) else "")
        path = Path(args.output) if args.output else Path(f"{stem}.nc")
        problem = output_problem(path, args.overwrite)
        if problem == EXISTS:
            raise UsageError(f"-o {path}: the file exists; add --overwrite to replace it")
        if problem:
            raise UsageError(f"-o {path}: {problem}")
    _warn_cost(config)
    from .progress import Progress, on_terminal

    show = not args.quiet and on_terminal(sys.stderr)  # never into a redirected log
    with Progress(config.solver.t_end, sys.stderr, delay=PROGRESS_DELAY) if show else _nothing() as bar:
        say = bar.phase if show else None if args.quiet else lambda line: print(f"lubelink: {line}", file=sys.stderr)
        with announcing(say) as once:
            result = run(config, progress=bar.update if show else None, model=first_run(build_model(config), say=once))
            if show:
                bar.phase("sampling the results")
            results = collect(result)
        failure = None
        if path is not None:
            if show:
                bar.phase(f"writing {path.name}")
            path, failure = _write_results(results, path, args.overwrite)
    if not args.quiet:
        from .summary import summary

        print(summary(results, _source_label(source, args.overrides), path, time.perf_counter() - began))
    if failure:
        print(f"lubelink: error: {failure}", file=sys.stderr)
        return 1
    return 0 if results.attrs["complete"] else 1


def _cmd_config(args):
    from .config import SCENARIOS
    from .template import template

    source, config = resolve_args(args)
    sys.stdout.write(template(config, scenario=source if source in SCENARIOS else None))
    return 0


def _cmd_show(args):
    if not Path(args.file).is_file():
        raise UsageError(f"FILE.nc = {args.file!r}: no such file")
    from .summary import summary

    ds = _load_results(args.file)
    print(summary(ds, args.file, None, None))
    if not args.no_config:
        print("\nconfiguration (lubelink run " + args.file + " runs it again):\n")
        sys.stdout.write(str(ds.attrs.get("config", "(none stored)")).rstrip("\n") + "\n")
    return 0


def _cmd_scenarios(args):
    from .config import SCENARIOS

    width = max(map(len, SCENARIOS))
    for name, spec in SCENARIOS.items():
        print(f"{name:<{width}}  {spec['description']}")
    return 0


def _cmd_compile(args):
    from .warmup import compile_all

    seconds = compile_all(progress=lambda message: print(message, file=sys.stderr, flush=True))
    print(f"compiled (or loaded from the cache) in {seconds:.1f} s")
    return 0


COMMANDS = {"run": _cmd_run, "config": _cmd_config, "show": _cmd_show, "scenarios": _cmd_scenarios,
            "compile": _cmd_compile}


def main(argv=None):
    """Entry point of the ``lubelink`` command; returns the exit status."""
    argv = sys.argv[1:] if argv is None else list(argv)
    command = next((a for a in argv if not a.startswith("-")), None)
    parser = build_parser(extensions=command not in COMMANDS)
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 2
    handler = COMMANDS.get(args.command) or args.handler
    restore = _on_termination()
    try:
        return handler(args)
    except ConfigError as exc:
        shown = exc.problems[:MAX_ERROR_LINES]
        for problem in shown:
            print(f"lubelink: error: {problem}", file=sys.stderr)
        if len(exc.problems) > len(shown):
            print(f"lubelink: error: ... and {len(exc.problems) - len(shown)} more", file=sys.stderr)
        return 2
    except (UsageError, BackendError) as exc:
        print(f"lubelink: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as exc:
        print(f"lubelink: {interrupted(exc)}; nothing was written", file=sys.stderr)
        return exit_status(exc)
    finally:
        restore()


#: The most faults of a configuration printed, one line each (the rest are counted in one more line).
MAX_ERROR_LINES = 50


def console():
    """The ``lubelink`` command as a process of its own (``[project.scripts]``, ``python -m lubelink``).

    :func:`main`, with three things only a whole process may do. Ctrl-C before :func:`main` has
    parsed the command (while the libraries load) gets the same one line as later. Start-up imports NumPy, Numba and
    the compiled kernels, a few hundred thousand objects of which none is garbage: the cycle
    collector runs less often meanwhile (about 0.1 s). And once the command has returned, its output
    written, renamed and flushed, and the exit handlers run, the process ends without the
    interpreter's teardown, which frees Numba's objects one by one (about 0.25 s of a 1.5 s
    ``lubelink run``).
    """
    import atexit
    import gc
    import os

    gc.set_threshold(20_000, 50, 1_000)
    catch_interrupts()
    try:
        status = main()
    except KeyboardInterrupt as exc:  # before main's own handler: loading the libraries, parsing
        print(f"lubelink: {interrupted(exc)}", file=sys.stderr)
        status = exit_status(exc)
    except Exception:
        if not was_interrupted():
            raise
        print("lubelink: interrupted", file=sys.stderr)  # (Ctrl-C inside an import: see catch_interrupts)
        status = 130
    getattr(atexit, "_run_exitfuncs", lambda: None)()  # (public in effect: what the interpreter runs at exit)
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe: nothing more to say
            pass
    os._exit(0 if status is None else int(status))


def _on_termination():
    """Turn SIGTERM and SIGHUP into :class:`~lubelink.errors.Terminated` (a KeyboardInterrupt: the
    same clean-up as Ctrl-C, temporaries removed); returns what restores the previous handlers.

    A signal that is ignored (``nohup``) stays ignored; outside the main thread nothing changes.
    """
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        return lambda: None

    def handler(signum, frame):
        raise Terminated(signum)

    previous = {}
    for name in ("SIGTERM", "SIGHUP"):
        sig = getattr(signal, name, None)
        if sig is not None and signal.getsignal(sig) is signal.SIG_DFL:
            previous[sig] = signal.signal(sig, handler)

    def restore():
        for sig, old in previous.items():
            signal.signal(sig, old)

    return restore

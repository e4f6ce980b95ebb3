"""What every command reads and writes: the configuration from its arguments, results files in and out.

``lubelink run`` and the commands of the application packages (``lubelink periodic``, ``continue``,
the paper's) share these, so they live below all of them (:mod:`lubelink.cli` dispatches to the
packages, which import this module, not the dispatcher).
"""

from __future__ import annotations

import os
from pathlib import Path

from .errors import UsageError, suggest

__all__ = ["resolve_args", "is_results_file", "write_results"]


def resolve_args(args):
    """``(source, Config)`` from the CONFIG/--scenario/--set arguments; raises UsageError or ConfigError."""
    from .config import SCENARIOS, parse_override, resolve

    if args.config and args.scenario:
        raise UsageError("give either CONFIG.toml or --scenario, not both "
                         "(a file picks its base with its top-level 'scenario' key)")
    if args.config and Path(args.config).is_dir():
        raise UsageError(f"CONFIG.toml = {args.config!r}: is a folder, not a configuration file")
    if args.config and not Path(args.config).exists():
        if args.config in SCENARIOS:  # `lubelink run paper-dry`: a scenario by name
            args.config, args.scenario = None, args.config
        else:
            raise UsageError(f"CONFIG.toml = {args.config!r}: no such file or scenario"
                             + suggest(args.config, SCENARIOS))
    overrides = dict(parse_override(text) for text in args.overrides)
    source = args.config or args.scenario or "paper"
    if args.config and is_results_file(args.config):
        return source, resolve(_results_config(args.config), overrides)
    return source, resolve(source, overrides)


#: The first bytes of a NetCDF file: classic (CDF 1, 2, 5) or NetCDF-4 (HDF5).
_NETCDF_MAGIC = (b"CDF\x01", b"CDF\x02", b"CDF\x05", b"\x89HDF\r\n\x1a\n")


def is_results_file(path):
    """Whether ``path`` is a NetCDF file (by its first bytes), as ``lubelink run`` and ``show`` take them."""
    try:
        with open(path, "rb") as f:
            head = f.read(8)
    except OSError:
        return False
    return any(head.startswith(magic) for magic in _NETCDF_MAGIC)


def _load_results(path):
    """The results dataset of the file ``path``; a file that is not lubelink results is a UsageError."""
    from .netcdf import ResultsFileError, load

    try:
        return load(path)
    except ResultsFileError as exc:
        raise UsageError(str(exc)) from None


def _results_config(path):
    """The configuration a results file was computed with (its ``config`` attribute)."""
    from .netcdf import ResultsFileError, config_of

    try:
        return config_of(_load_results(path))
    except ResultsFileError as exc:
        raise UsageError(f"{path}: {exc}") from None


def write_results(results, path, overwrite):
    """Write the results to ``path``; if that fails, beside it, here or in the temporary folder.

    Returns ``(written path or None, error message or None)``.
    """
    import tempfile

    from ._files import fallback_path
    from .netcdf import write

    if not overwrite and os.path.lexists(path):  # it was checked before the run
        reason = f"{path} appeared while the results were computed; it was not replaced"
    else:
        try:
            return write(results, path, overwrite=overwrite), None
        except Exception as exc:  # noqa: BLE001 - whatever the failure, the computed results are kept
            reason = _reason(exc)
    tried = []
    for folder in (path.parent, Path.cwd(), Path(tempfile.gettempdir())):
        if any(folder.resolve() == t.resolve() for t in tried):
            continue
        tried.append(folder)
        other = fallback_path(folder / path.name)
        if other is None:
            continue
        try:
            write(results, other, overwrite=False)
        except Exception:  # noqa: BLE001 - try the next folder
            continue
        return other, f"-o {path}: could not be written ({reason}); the results were written to {other} instead"
    return None, (f"-o {path}: could not be written ({reason}), nor in "
                  + ", ".join(str(t) for t in tried) + "; the results are lost")


def _reason(exc):
    from .netcdf import ResultsFileError

    if isinstance(exc, ResultsFileError):
        return str(exc)
    if isinstance(exc, OSError) and exc.strerror:
        return exc.strerror
    return f"{type(exc).__name__}: {exc}"


#: A run shorter than this [s] shows no progress line.

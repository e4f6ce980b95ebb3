"""Results files: NetCDF-4 written atomically, read back with their format checked.

:func:`write` writes a :class:`~lubelink.results.Results` with netCDF4 alone (the command line's
path: no xarray import), :func:`save` an :class:`xarray.Dataset`; both give the same file
(compressed, CF attributes, the library versions added), published by renaming a temporary
(:func:`lubelink._files.atomic_path`). :func:`output_problem` checks a target before a run, so that
a run is not lost at its end; :func:`load` reads a file back, :func:`config_of` the configuration
it was computed with.
"""

from __future__ import annotations

import os
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from ._files import atomic_path, read_netcdf, target_problem
from .variables import CONVENTIONS

__all__ = ["FORMAT_VERSION", "ResultsFileError", "write", "save", "load", "config_of", "output_problem",
           "NETCDF_SUFFIXES", "EXISTS", "COMPRESSION", "file_attrs", "library_versions", "RENAMED", "renamed",
           "CONVENTIONS"]


#: Version of the results layout; :func:`load` refuses other major versions.
FORMAT_VERSION = "1.1"

#: Names of earlier minor versions of the layout and their names now: :func:`load` and
#: :func:`lubelink.sweep.load_sweep` read the old names as the new. Format 1.0 named the pad's
#: coordinate ``X``, which CF readers confuse with the link's ``x`` (names differing only by case).
RENAMED = {"X": "x_pad"}


class ResultsFileError(ValueError):
    """A results file that cannot be written or read as lubelink results."""


#: zlib level of every variable in a results file (level 1-4 halve the file; higher gains little).
COMPRESSION = 2


def library_versions():
    """The netCDF-C and HDF5 library versions behind netCDF4 (imported here: only writers ask)."""
    import netCDF4

    return f"netCDF-C {netCDF4.__netcdf4libversion__}, HDF5 {netCDF4.__hdf5libversion__}"


def file_attrs(attrs):
    """The global attributes of a results file: ``attrs`` with the netCDF-C and HDF5 versions
    added to ``versions`` and booleans as integers (NetCDF has no boolean type)."""
    out = {k: (int(v) if isinstance(v, (bool, np.bool_)) else v) for k, v in attrs.items()}
    libs = library_versions()
    if "versions" in out and libs not in str(out["versions"]):
        out["versions"] = f"{out['versions']}, {libs}"
    return out


def write(results, path, overwrite=False):
    """Write :class:`~lubelink.results.Results` to NetCDF-4 at ``path`` atomically, with netCDF4 (no xarray import).

    The file is what :func:`save` would write of :func:`~lubelink.results.to_dataset`: :func:`load` reads it back.
    """
    import netCDF4

    path = _checked_target(path, overwrite)
    with _publishing(path, overwrite) as tmp:
        with netCDF4.Dataset(tmp, "w", format="NETCDF4") as nc:
            sizes = {}
            for dims, data, _ in list(results.coords.values()) + list(results.data_vars.values()):
                for dim, n in zip(dims, np.shape(data)):
                    sizes[dim] = n
            for dim, n in sizes.items():
                nc.createDimension(dim, n)
            beside = {name: set(dims) for name, (dims, _, _) in results.coords.items() if dims != (name,)}
            for name, (dims, data, attrs) in list(results.coords.items()) + list(results.data_vars.items()):
                data = np.asarray(data)
                var = nc.createVariable(name, data.dtype, dims, zlib=bool(data.size), complevel=COMPRESSION)
                auxiliary = " ".join(c for c, on in beside.items() if name in results.data_vars and on <= set(dims))
                var.setncatts({**attrs, "coordinates": auxiliary} if auxiliary else attrs)  # (CF: coordinates
                # beside an index, such as crank_angle beside time, are named by the variables that have them)
                if data.size:
                    var[...] = data
            nc.setncatts(file_attrs(results.attrs))
    return path


#: File name suffixes of results files (NetCDF); any other is refused rather than silently written as NetCDF.
NETCDF_SUFFIXES = (".nc", ".nc4", ".netcdf")
#: :func:`output_problem` of a target that exists (when replacing it was not asked for).
EXISTS = "the file exists"


def output_problem(path, overwrite=False):
    """Why results could not be written at ``path``, or None; checked before a run, so that a
    run is not lost at the end: a NetCDF suffix, an existing file only with ``overwrite`` and only
    a regular file, a writable folder (:func:`lubelink._files.target_problem`)."""
    path = Path(path)
    if path.suffix.lower() not in NETCDF_SUFFIXES:
        return (f"results are written as NetCDF; name the file *.nc (e.g. {path.with_suffix('.nc').name})"
                if path.suffix else f"results are written as NetCDF; name the file {path.name}.nc")
    if os.path.lexists(path) and not overwrite:
        return EXISTS
    return target_problem(path)


def _checked_target(path, overwrite):
    path = Path(path)
    problem = output_problem(path, overwrite)
    if problem == EXISTS:
        raise ResultsFileError(f"{path} exists; pass overwrite=True (--overwrite) to replace it")
    if problem:
        raise ResultsFileError(f"{path}: {problem}")
    return path


@contextmanager
def _publishing(path, overwrite):
    """:func:`atomic_path`, its refusals as :class:`ResultsFileError` (a file that appeared at
    ``path`` since the check, or that is not a regular file)."""
    try:
        with atomic_path(path, overwrite=overwrite) as tmp:
            yield tmp
    except FileExistsError:
        raise ResultsFileError(f"{path} appeared while the results were computed; it was not replaced "
                               "(pass overwrite=True, --overwrite, to replace it)") from None
    except IsADirectoryError as exc:
        raise ResultsFileError(f"{path}: {exc.strerror}") from None


def save(dataset, path, overwrite=False):
    """Write ``dataset`` to NetCDF at ``path`` atomically (:func:`atomic_path`).

    Raises
    ------
    ResultsFileError
        If ``path`` exists and ``overwrite`` is false (also when it appears while writing), is not
        a regular file, does not end in ``.nc`` (:data:`NETCDF_SUFFIXES`), or its folder is missing
        or not writable.
    """
    path = _checked_target(path, overwrite)
    encoding = {name: {"zlib": bool(v.size), "complevel": COMPRESSION, "_FillValue": None}
                for name, v in dataset.variables.items()}
    dataset = dataset.copy(deep=False)
    dataset.attrs = file_attrs(dataset.attrs)
    with _publishing(path, overwrite) as tmp:
        dataset.to_netcdf(tmp, engine="netcdf4", encoding=encoding)
    return path


def load(path):
    """Read a results file written by :func:`save`, checking its format version."""
    path = Path(path)
    ds = read_netcdf(path, "results file", ResultsFileError)
    version = str(ds.attrs.get("lubelink_format", ""))
    if version.split(".")[0] != FORMAT_VERSION.split(".")[0]:
        raise ResultsFileError(f"{path}: results format {version or 'missing'}, "
                               f"this lubelink reads format {FORMAT_VERSION}")
    return renamed(ds)


def renamed(ds):
    """``ds`` with the names of earlier minor versions of the layout as they are now (:data:`RENAMED`)."""
    old = {name: new for name, new in RENAMED.items() if name in ds.variables and new not in ds.variables}
    return ds.rename(old) if old else ds


def config_of(dataset):
    """The :class:`~lubelink.params.Config` a results dataset was computed with.

    Raises :class:`ResultsFileError` for a dataset that is not lubelink results (no ``config``
    attribute, or not TOML), :class:`~lubelink.config.ConfigError` for a configuration this
    version does not accept.
    """
    from .config import ConfigError, from_stored, parse_toml

    attrs = getattr(dataset, "attrs", None)
    text = attrs.get("config") if isinstance(attrs, dict) else None
    if not isinstance(text, str):
        raise ResultsFileError("not lubelink results: the dataset has no 'config' attribute (the configuration "
                               "it was computed with)")
    try:
        data = parse_toml(text, "the results' config attribute")
    except ConfigError as exc:
        raise ResultsFileError(f"not lubelink results: {exc.problems[0]}") from None
    return from_stored(data, origin="the results' config attribute")

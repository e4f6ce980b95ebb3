"""Results as an :class:`xarray.Dataset`: assembly, NetCDF save and load.

Every variable carries ``units`` and ``long_name``; the dataset's attrs hold
the run status, solver statistics, versions and the full configuration as
TOML text, which is enough to re-run it (:func:`config_of`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ._files import atomic_path

__all__ = ["FORMAT_VERSION", "save", "load", "config_of", "atomic_path", "ResultsFileError"]

#: Version of the results layout; :func:`load` refuses other major versions.
FORMAT_VERSION = "1.0"


class ResultsFileError(ValueError):
    """A results file that cannot be written or read as lubelink results."""


def variable(dims, data, units, long_name, **attrs):
    """``(dims, data, attrs)`` tuple for :class:`xarray.Dataset` construction."""
    return dims, np.asarray(data), {"units": units, "long_name": long_name, **attrs}


def save(dataset, path, overwrite=False):
    """Write ``dataset`` to NetCDF at ``path`` atomically (:func:`atomic_path`).

    Raises
    ------
    ResultsFileError
        If ``path`` exists and ``overwrite`` is false, or the folder is missing.
    """
    path = Path(path)
    if path.exists() and not overwrite:
        raise ResultsFileError(f"{path} exists; pass overwrite=True (--overwrite) to replace it")
    if not path.parent.exists():
        raise ResultsFileError(f"{path}: folder {path.parent} does not exist")
    with atomic_path(path) as tmp:
        dataset.to_netcdf(tmp, engine="netcdf4")
    return path


def load(path):
    """Read a results file written by :func:`save`, checking its format version."""
    import xarray as xr

    path = Path(path)
    if not path.exists():
        raise ResultsFileError(f"{path}: no such results file")
    try:
        ds = xr.load_dataset(path, engine="netcdf4")
    except Exception as exc:  # the backend raises many types for a foreign file
        raise ResultsFileError(f"{path}: not a readable NetCDF file ({exc})") from None
    version = str(ds.attrs.get("lubelink_format", ""))
    if version.split(".")[0] != FORMAT_VERSION.split(".")[0]:
        raise ResultsFileError(f"{path}: results format {version or 'missing'}, "
                               f"this lubelink reads format {FORMAT_VERSION}")
    return ds


def config_of(dataset):
    """The :class:`~lubelink.params.Config` a results dataset was computed with."""
    import tomllib

    from .config import from_dict

    return from_dict(tomllib.loads(dataset.attrs["config"]))

"""The layout of a sweep store: the variables a new store is created with, and its two writers.

One array per stored quantity over the swept dimensions (chunked to about 4096 points), the
``done`` mask, the swept parameters as coordinates with their units, the optional time series
(never written until a point arrives) and the attributes that identify the sweep.
:func:`_variables` describes them once; :func:`write_empty` creates the store with Zarr alone
(what :class:`~lubelink.sweep.store._Store` does: neither xarray nor Dask is imported, about 0.8 s
of a sweep's start); :func:`_template` gives the same store as an xarray Dataset (its time series
lazy Dask arrays) for ``Dataset.to_zarr``, the reference the tests compare the Zarr writer with.
"""

from __future__ import annotations

import base64
import time
from dataclasses import dataclass

import numpy as np

from ..params import sample_times
from ..results import CONVENTIONS, VARIABLE_ATTRS, VARIABLES
from .schema import ALWAYS, QUANTITIES, SERIES, SWEEP_FORMAT, _parameters
from .spec import Sweep


# ====================================================================== the store
def _chunks(shape, target=4096):
    """Chunk shape over the swept dimensions holding about ``target`` points."""
    chunks, room = [], target
    for n in reversed(shape):
        c = max(1, min(n, room))
        chunks.append(c)
        room = max(1, room // c)
    return tuple(reversed(chunks))


#: Units and long names of the time series: those of the results files.
_SERIES_ATTRS = {name: (VARIABLES[name].units, VARIABLES[name].long_name) for name in SERIES}


@dataclass(frozen=True)
class _Var:
    """One variable of the store: its dimensions, values (or, ``values is None``, an unwritten array of
    ``shape`` filled with NaN: a time series), attributes and chunks (None: Zarr's choice)."""

    dims: tuple
    values: object
    attrs: dict
    chunks: tuple | None = None
    shape: tuple | None = None
    coord: bool = False


def _coordinate(name, values):
    """A coordinate of the time series, as the results files write it."""
    v = VARIABLES[name]
    return _Var((name,), values, {"units": v.units, "long_name": v.long_name, **VARIABLE_ATTRS.get(name, {})},
                coord=True)


def _variables(sp: Sweep):
    """``({name: _Var}, attrs)`` of an empty store: coordinates first, then the summaries filled with
    their no-data values (NaN, -1, ""), ``done`` and the time series."""
    from ..config import to_toml

    params = _parameters()
    dims, shape = sp.dims, sp.shape
    chunks = _chunks(shape)
    out = {}

    def param_attrs(name, scale):
        _, units, long_name = params[name]
        units = {"units": units} if units else {}  # a choice (a string) has none
        return {**units, "long_name": long_name, "parameter": name, "scale": scale}

    def array(values):
        values = list(values)
        return np.array(values, dtype=object) if isinstance(values[0], str) else np.array(values)

    for a in sp.axes:
        out[a.name] = _Var((a.name,), array(a.values), param_attrs(a.name, a.scale), coord=True)
    if sp.point_rows:
        out["point"] = _Var(("point",), np.arange(len(sp.point_rows)), {"units": "1", "long_name": "point number"},
                            coord=True)
        for j, name in enumerate(sp.point_names):
            out[name] = _Var(("point",), array(r[j] for r in sp.point_rows), param_attrs(name, "list"), coord=True)

    for name in list(ALWAYS) + list(sp.quantities):
        if name in ALWAYS:
            units, long_name = ALWAYS[name]
            kind = "s" if name in ("status", "message") else "f"
        else:
            units, long_name, kind = QUANTITIES[name]
        vdims, vchunks = dims, chunks
        if kind == "s":
            values = np.full(shape, "", dtype=object)
        elif kind == "i":
            values = np.full(shape, -1, dtype=np.int64)
        elif kind == "impacts":
            values = np.full(shape + (sp.max_impacts,), np.nan)
            vdims, vchunks = dims + ("impact",), chunks + (sp.max_impacts,)
            out["impact"] = _Var(("impact",), np.arange(sp.max_impacts), {"units": "1", "long_name": "impact number"},
                                 coord=True)
        else:
            values = np.full(shape, np.nan)
        out[name] = _Var(vdims, values, {"units": units, "long_name": long_name}, vchunks)
    out["done"] = _Var(dims, np.zeros(shape, dtype=bool),
                       {"units": "1", "long_name": "point stored: computed, or recorded as failed or invalid"}, chunks)

    if sp.time_series:
        cfg = sp.base_config
        t = sample_times(cfg.solver)
        out["time"] = _coordinate("time", t)
        extra = {
            "mode": np.arange(1, cfg.beam.modes + 1),
            "x": np.linspace(0.0, cfg.mechanism.rod_length, cfg.output.x_points),
            "x_pad": np.linspace(0.0, cfg.film.pad_length, cfg.output.pad_points),
        }
        for name in sp.time_series:
            edim = SERIES[name][0]
            eshape = ()
            if edim:
                out[edim] = _coordinate(edim, extra[edim])
                eshape = (len(extra[edim]),)
            units, long_name = _SERIES_ATTRS[name]
            out[name] = _Var(dims + ("time",) + ((edim,) if edim else ()), None, {"units": units, "long_name": long_name},
                             (1,) * len(shape) + (len(t),) + eshape, shape + (len(t),) + eshape)

    from .. import __version__

    attrs = {
        "Conventions": CONVENTIONS,
        "title": "lubelink parameter sweep",
        "source": f"lubelink {__version__}",
        "lubelink_sweep_format": SWEEP_FORMAT,
        "lubelink_version": __version__,
        "sweep_hash": sp.hash,
        "swept_dims": " ".join(dims),
        "quantities": " ".join(sp.quantities),
        "time_series": " ".join(sp.time_series),
        "points_total": sp.size,
        "sweep": sp.to_toml(),
        "base_config": to_toml(sp.base_config),
        "created": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        "runs": "[]",
    }
    return out, attrs


def _template(sp: Sweep):
    """``(Dataset, encoding)`` of an empty store for ``Dataset.to_zarr(..., compute=False)``: the
    variables of :func:`_variables`, the time series as lazy Dask arrays (never written until a point
    arrives). The reference :func:`write_empty` is tested against; xarray and Dask are imported here."""
    import xarray as xr

    variables, attrs = _variables(sp)
    coords, data, encoding = {}, {}, {}
    for name, v in variables.items():
        values = v.values
        if values is None:
            import dask.array as dsa

            values = dsa.full(v.shape, np.nan, chunks=v.chunks)
        (coords if v.coord else data)[name] = (v.dims, values, v.attrs)
        if v.chunks is not None:
            encoding[name] = {"chunks": v.chunks}
    return xr.Dataset(data, coords=coords, attrs=attrs), encoding


#: Zarr's ``fill_value`` of each NumPy kind, as xarray's ``to_zarr`` writes it (floats NaN, the rest
#: Zarr's default) and the ``_FillValue`` attribute xarray adds to a float array (its bytes, base64).
_NAN_ATTR = base64.standard_b64encode(np.array(np.nan, dtype="<f8").tobytes()).decode()


def write_empty(sp: Sweep, folder):
    """Create the empty store of ``sp`` in the new folder ``folder`` with Zarr alone: the arrays, their
    attributes and the values that differ from each array's fill value, as ``Dataset.to_zarr`` of
    :func:`_template` writes them (``dimension_names``, a float's ``_FillValue`` attribute, the
    ``coordinates`` attribute naming the non-dimension coordinates a variable shares dimensions with)."""
    import zarr

    variables, attrs = _variables(sp)
    g = zarr.open_group(str(folder), mode="w-", zarr_format=3)
    g.attrs.update(attrs)
    aux = [n for n, v in variables.items() if v.coord and v.dims != (n,)]  # non-dimension coordinates
    for name, v in variables.items():
        a = dict(v.attrs)
        if not v.coord:
            shared = sorted(c for c in aux if set(variables[c].dims) <= set(v.dims))
            if shared:
                a["coordinates"] = " ".join(shared)
        values = v.values
        if values is None:
            dtype, shape = np.dtype(float), v.shape
        else:
            dtype, shape = values.dtype, values.shape
        fill = None
        if dtype.kind == "f":
            fill = np.nan
            a["_FillValue"] = _NAN_ATTR
        chunks = {} if v.chunks is None else {"chunks": v.chunks}
        arr = g.create(name, shape=shape, dtype=str if dtype.kind == "O" else dtype, fill_value=fill,
                       dimension_names=v.dims, **chunks)
        arr.attrs.put(a)
        if values is not None:
            arr[...] = values
    return g

"""The layout of a sweep store: the empty Dataset a new store is created from.

One array per stored quantity over the swept dimensions (chunked to about 4096 points), the
``done`` mask, the swept parameters as coordinates with their units, the optional time series
(lazy Dask arrays, never written until a point arrives) and the attributes that identify the
sweep. :mod:`.store` writes it; xarray and Dask are imported inside :func:`_template`.
"""

from __future__ import annotations

import time

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


def _coordinate(name, values):
    """``(dims, values, attrs)`` of a coordinate of the time series, as the results files write it."""
    v = VARIABLES[name]
    return (name,), values, {"units": v.units, "long_name": v.long_name, **VARIABLE_ATTRS.get(name, {})}


def _template(sp: Sweep):
    """``(Dataset, encoding)`` of an empty store: summaries filled with their
    no-data values (NaN, -1, ""), time series as lazy Dask arrays (never written
    until a point arrives)."""
    import xarray as xr

    from ..config import to_toml

    params = _parameters()
    dims, shape = sp.dims, sp.shape
    chunks = _chunks(shape)
    coords, data, encoding = {}, {}, {}

    def param_attrs(name, scale):
        _, units, long_name = params[name]
        units = {"units": units} if units else {}  # a choice (a string) has none
        return {**units, "long_name": long_name, "parameter": name, "scale": scale}

    def array(values):
        values = list(values)
        return np.array(values, dtype=object) if isinstance(values[0], str) else np.array(values)

    for a in sp.axes:
        coords[a.name] = ((a.name,), array(a.values), param_attrs(a.name, a.scale))
    if sp.point_rows:
        coords["point"] = (("point",), np.arange(len(sp.point_rows)), {"units": "1", "long_name": "point number"})
        for j, name in enumerate(sp.point_names):
            coords[name] = (("point",), array(r[j] for r in sp.point_rows), param_attrs(name, "list"))

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
            coords["impact"] = (("impact",), np.arange(sp.max_impacts), {"units": "1", "long_name": "impact number"})
        else:
            values = np.full(shape, np.nan)
        data[name] = (vdims, values, {"units": units, "long_name": long_name})
        encoding[name] = {"chunks": vchunks}
    data["done"] = (dims, np.zeros(shape, dtype=bool),
                    {"units": "1", "long_name": "point stored: computed, or recorded as failed or invalid"})
    encoding["done"] = {"chunks": chunks}

    if sp.time_series:
        import dask.array as dsa

        cfg = sp.base_config
        t = sample_times(cfg.solver)
        coords["time"] = _coordinate("time", t)
        extra = {
            "mode": np.arange(1, cfg.beam.modes + 1),
            "x": np.linspace(0.0, cfg.mechanism.rod_length, cfg.output.x_points),
            "x_pad": np.linspace(0.0, cfg.film.pad_length, cfg.output.pad_points),
        }
        for name in sp.time_series:
            edim = SERIES[name][0]
            eshape = ()
            if edim:
                coords[edim] = _coordinate(edim, extra[edim])
                eshape = (len(extra[edim]),)
            vshape = shape + (len(t),) + eshape
            vchunks = (1,) * len(shape) + (len(t),) + eshape
            units, long_name = _SERIES_ATTRS[name]
            data[name] = (dims + ("time",) + ((edim,) if edim else ()),
                          dsa.full(vshape, np.nan, chunks=vchunks), {"units": units, "long_name": long_name})
            encoding[name] = {"chunks": vchunks}

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
    return xr.Dataset(data, coords=coords, attrs=attrs), encoding

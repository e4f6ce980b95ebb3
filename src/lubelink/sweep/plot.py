"""The response map of a sweep: :func:`plot_sweep` (curves, heat map, facets).

Matplotlib is imported inside :func:`plot_sweep` only.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import suggest
from .schema import SweepError, _fmt
from .store import load_sweep

__all__ = ["plot_sweep"]


# ====================================================================== plotting
def _edges(values, log):
    v = np.asarray(values, dtype=float)
    if log:
        return np.exp(_edges(np.log(v), False))
    if v.size == 1:
        half = 0.5 if v[0] == 0 else 0.1 * abs(v[0])
        return np.array([v[0] - half, v[0] + half])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[v[0] - (mid[0] - v[0])], mid, [v[-1] + (v[-1] - mid[-1])]])


def _axis_values(ds, dim, lists_as_categories):
    """``(positions, tick labels or None, log)`` of a dimension coordinate on a plot axis.

    Strings, and in heat maps lists of values, are placed at equal spacing and
    labelled; ranges keep their linear or log scale; a numeric list spanning two
    decades or more is drawn on a log axis.
    """
    def text(v):
        return _fmt(v.item() if hasattr(v, "item") else v)

    c = ds[dim]
    if dim == "point":  # explicit points: label each with its parameter values
        params = [n for n, v in ds.coords.items() if v.dims == ("point",) and n != "point"]
        labels = [", ".join(f"{n.split('.')[-1]}={text(ds[n].values[i])}" for n in params) for i in range(c.size)]
        return np.arange(c.size, dtype=float), labels, False
    scale = c.attrs.get("scale", "list")
    if c.dtype.kind not in "fiu" or (lists_as_categories and scale == "list" and c.size > 1):
        return np.arange(c.size, dtype=float), [text(v) for v in c.values], False
    v = c.values.astype(float)
    wide = scale == "list" and v.size > 1 and v.min() > 0 and v.max() / v.min() >= 100
    return v, None, scale == "log" or wide


def _label(ds, name):
    units = ds[name].attrs.get("units", "")
    return f"{name} [{units}]" if units and units != "1" else name


def plot_sweep(results, quantity=None, *, select=None, fig=None):
    """Response map of one quantity over the swept dimensions.

    One dimension left (after ``select``): curves; two: a heat map; three:
    heat maps faceted along the last one. Points that failed are marked with
    a cross; points not yet computed are left blank.

    Parameters
    ----------
    results : xarray.Dataset or path
        :func:`run_sweep` / :func:`load_sweep` output, or a store path.
    quantity : str, optional
        Stored quantity (default ``peak_u2_mid`` when stored); ``status``
        draws a map of the outcomes.
    select : dict, optional
        ``{dimension: value}`` slices (nearest value for numbers); ``impact``
        selects which of ``impact_times``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    ds = results if hasattr(results, "data_vars") else load_sweep(results)
    dims = ds.attrs.get("swept_dims", "").split()
    stored = [q for q in ds.attrs.get("quantities", "").split() if q in ds] + ["status", "wall_time"]
    if quantity is None:
        quantity = "peak_u2_mid" if "peak_u2_mid" in ds else stored[0]
    if quantity not in ds or quantity not in stored:
        raise SweepError(f"quantity {quantity!r}: not stored in these results; choose from "
                         + ", ".join(stored) + suggest(quantity, stored))
    select = dict(select or {})
    for dim, value in list(select.items()):
        if dim not in ds.dims:
            raise SweepError(f"select {dim}: no such dimension; the dimensions are "
                             + ", ".join(ds[quantity].dims) + suggest(dim, ds.dims))
        if dim in ds.coords and ds[dim].dtype.kind in "fiu":
            try:
                select[dim] = float(value)
            except (TypeError, ValueError):
                raise SweepError(f"select {dim}={value!r}: must be a number") from None
    numeric = {d: v for d, v in select.items() if d in ds.coords and ds[d].dtype.kind in "fiu"}
    exact = {d: v for d, v in select.items() if d not in numeric}
    if "impact" in ds[quantity].dims and "impact" not in select:
        exact["impact"] = 0
    try:
        sub = ds.sel(numeric, method="nearest") if numeric else ds
        sub = sub.sel({d: v for d, v in exact.items() if d in ds.coords and d != "impact"})
        if "impact" in exact:
            sub = sub.isel(impact=int(exact["impact"]))
    except KeyError as exc:
        raise SweepError(f"select: no such value {exc}") from None
    free = [d for d in dims if d in sub[quantity].dims]
    if len(free) > 3 or not free:
        raise SweepError(f"{len(free)} swept dimensions left ({', '.join(free) or 'none'}): plot-sweep draws "
                         "1 (curves), 2 (heat map) or 3 (facets); fix the others with --select DIM=VALUE")
    done = sub["done"].values.astype(bool)
    failed = done & (sub["status"].values.astype(str) != "complete")
    values = sub[quantity]
    units = ds[quantity].attrs.get("units", "")
    title = quantity + (f" [{units}]" if units and units != "1" else "")
    categories = None
    if quantity == "status" or values.dtype.kind in "OUS":
        categories = sorted({str(v) for v in values.values.reshape(-1)[done.reshape(-1)]}) or ["(none)"]
        codes = np.vectorize(lambda v: categories.index(str(v)) if str(v) in categories else -1,
                             otypes=[float])(values.values)
        data = np.where(done, codes, np.nan)
    else:
        data = np.where(done, values.values.astype(float), np.nan)
    da = values.copy(data=data).transpose(*free)
    failed = values.copy(data=failed).transpose(*free).values
    if select:
        title += "  (" + ", ".join(f"{d} = {_fmt(sub[d].item()) if d in sub.coords else v}"
                                   for d, v in select.items()) + ")"

    panels = [None] if len(free) < 3 else list(range(sub.sizes[free[2]]))
    if len(panels) > 16:
        raise SweepError(f"{free[2]} has {len(panels)} values, too many panels: fix it with --select "
                         f"{free[2]}=VALUE, or another dimension")
    ncols = min(len(panels), 4)
    nrows = math.ceil(len(panels) / ncols)
    fig = fig or plt.figure(figsize=(7.0, 4.8) if len(free) < 3 else (3.6 * ncols + 1.0, 3.0 * nrows + 0.6))
    if len(free) == 1:
        ax = fig.add_subplot()
        x, ticks, log = _axis_values(sub, free[0], False)
        ax.plot(x, da.values, "o-", label=quantity)
        if failed.any():
            ax.plot(x[failed], da.values[failed], "x", color="tab:red", ms=9, mew=2,
                    label="failed (status not complete)")
            ax.legend()
        if ticks:
            ax.set_xticks(x, ticks)
        if log:
            ax.set_xscale("log")
        if categories:
            ax.set_yticks(range(len(categories)), categories)
        ax.set_xlabel(_label(sub, free[0]))
        ax.set_ylabel(title)
        ax.set_title(ds[quantity].attrs.get("long_name", quantity), fontsize=10)
        ax.grid(True, alpha=0.3)
        return fig

    finite = data[np.isfinite(data)]
    vmin, vmax = (finite.min(), finite.max()) if finite.size else (0.0, 1.0)
    cmap = plt.get_cmap("viridis", len(categories)) if categories else "viridis"
    if categories:
        vmin, vmax = -0.5, len(categories) - 0.5
    axes = fig.subplots(nrows, ncols, squeeze=False)
    mesh = None
    for k, panel in enumerate(panels):
        ax = axes.flat[k]
        z = da.values if panel is None else da.values[..., panel]
        f = failed if panel is None else failed[..., panel]
        x, xt, xlog = _axis_values(sub, free[0], True)
        y, yt, ylog = _axis_values(sub, free[1], True)
        mesh = ax.pcolormesh(_edges(x, xlog), _edges(y, ylog), z.T, cmap=cmap, vmin=vmin, vmax=vmax,
                             shading="flat")
        if f.any() and not categories:
            ix, iy = np.nonzero(f)
            ax.plot(x[ix], y[iy], "x", color="white", ms=7, mew=2, markeredgecolor="black")
        if xt:
            ax.set_xticks(x, xt)
        if yt:
            ax.set_yticks(y, yt)
        if xlog:
            ax.set_xscale("log")
        if ylog:
            ax.set_yscale("log")
        ax.set_xlabel(_label(sub, free[0]))
        ax.set_ylabel(_label(sub, free[1]))
        if panel is not None:
            ax.set_title(f"{free[2]} = {_fmt(sub[free[2]].values[panel].item())}", fontsize=9)
        else:
            ax.set_title(ds[quantity].attrs.get("long_name", quantity), fontsize=10)
    for ax in axes.flat[len(panels):]:
        ax.set_visible(False)
    cbar = fig.colorbar(mesh, ax=axes.ravel().tolist())
    if categories:
        cbar.set_ticks(range(len(categories)), labels=categories)
    cbar.set_label(title + ("   x: failed" if failed.any() and not categories else ""))
    return fig

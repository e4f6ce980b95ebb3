"""The response map of a sweep: :func:`plot_sweep` (curves, heat map, facets).

Matplotlib is imported inside :func:`plot_sweep` only.
"""

from __future__ import annotations

import math
import re

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
    """``(positions, tick labels or None, log, label)`` of a dimension coordinate on a plot axis,
    in its display unit (:func:`lubelink.plots.units.display_unit`).

    Strings, and in heat maps lists of swept values, are placed at equal spacing and
    labelled; linear ranges (and the time axis of a series) are drawn on a linear axis; log
    ranges and numeric lists on a log axis where they span a decade or more, else on a linear
    one (:func:`lubelink.plots.units.log_scale`).
    """
    from ..plots.units import display_unit, label, log_scale

    c = ds[dim]
    if dim == "point":  # explicit points: label each with its parameter values
        params = [n for n, v in ds.coords.items() if v.dims == ("point",) and n != "point"]
        shown = {}
        for n in params:
            unit, size = display_unit(ds[n].attrs.get("units", ""), ds[n].values if ds[n].dtype.kind in "fiu" else None)
            shown[n] = (unit, size)

        def text(n, v):
            unit, size = shown[n]
            if isinstance(v, (int, float)) and not isinstance(v, bool):
                return f"{v / size:.4g}" + (f" {unit}" if unit else "")
            return _fmt(v)

        labels = [", ".join(f"{n.split('.')[-1]}={text(n, ds[n].values[i].item())}" for n in params)
                  for i in range(c.size)]
        return np.arange(c.size, dtype=float), labels, False, "point"
    scale = c.attrs.get("scale", "list" if "parameter" in c.attrs else "range")
    numeric = c.dtype.kind in "fiu"
    unit, size = display_unit(c.attrs.get("units", ""), c.values if numeric else None)
    name = label(dim, unit)
    if not numeric or (lists_as_categories and scale == "list" and c.size > 1):
        ticks = [f"{v.item() / size:.4g}" if numeric else _fmt(v.item()) for v in c.values]
        return np.arange(c.size, dtype=float), ticks, False, name
    v = c.values.astype(float)
    return v / size, None, scale in ("list", "log") and log_scale(v), name


def _shown(c, grid=None):
    """The value of a scalar coordinate ``c`` in its display unit, e.g. ``100 mPa s``: the unit of
    the axis of ``grid`` (the whole coordinate) when given."""
    from ..plots.units import display_unit

    value = c.values.item() if hasattr(c.values, "item") else c.values
    if c.dtype.kind not in "fiu":
        return _fmt(value)
    unit, size = display_unit(c.attrs.get("units", ""), value if grid is None else grid.values)
    return f"{value / size:.4g}" + (f" {unit}" if unit else "")


_NUMBER = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*")


def _grid_text(values, unit):
    """The values of a grid as a message lists them (the first and last few of a long one)."""
    shown = [f"{v:.4g}" for v in values]
    more = ""
    if len(shown) > 10:
        shown, more = shown[:4] + ["..."] + shown[-2:], f" ({len(values)} values)"
    return ", ".join(shown) + (f" {unit}" if unit else "") + more


def _pick(ds, dim, value):
    """The value of the numeric coordinate ``dim`` that ``value`` names, as stored (SI).

    A string (what ``--select`` gives) is a number in the display unit of the dimension's axis
    (:func:`lubelink.plots.units.display_unit`: ``100`` for 100 mPa s on an axis in mPa s),
    optionally followed by a unit of the same quantity (``"0.1 Pa s"``); it names a grid value
    when it rounds to it at the 4 significant digits the axis labels show. A number (Python) is
    in the stored unit and must equal a grid value to 1e-9. Any other value is refused with the
    grid in the axis's unit: a sweep has results at its grid values only.
    """
    from ..plots.units import DISPLAY, display_unit

    c = ds[dim]
    si = str(c.attrs.get("units", "")).strip()
    unit, size = display_unit(si, c.values)
    grid = c.values.astype(float)
    shown = grid / size
    if isinstance(value, str):
        m = _NUMBER.fullmatch(value)
        if m is None:
            raise SweepError(f"select {dim}={value!r}: must be a number" + (f" in {unit}" if unit else ""))
        number, written = float(m.group(1)), m.group(2)
        units = {label: s for label, s in DISPLAY.get(si, ())}
        units.setdefault(si, 1.0)
        if written and written not in units:
            raise SweepError(f"select {dim}={value!r}: unknown unit {written!r}; write the number in {unit or si}"
                             + (", or follow it with one of " + ", ".join(units) if len(units) > 1 else ""))
        target = number * (units[written] if written else size) / size  # in the axis's unit
        magnitude = np.where(shown != 0.0, np.abs(shown), 1.0)
        half_digit = np.where(shown != 0.0, 0.5 * 10.0 ** (np.floor(np.log10(magnitude)) - 3), 0.0)  # of the 4th
        tol = np.maximum(half_digit, 1e-9 * np.max(np.abs(shown)))
    else:
        try:
            number, written = float(value), None
        except (TypeError, ValueError):
            raise SweepError(f"select {dim}={value!r}: must be a number (in {si or 'its unit'})") from None
        target = number / size
        tol = np.full(grid.shape, 1e-9 * max(np.max(np.abs(shown)), abs(target)))
    near = np.abs(shown - target)
    hits = np.flatnonzero(near <= tol)
    if hits.size:
        return grid[hits[np.argmin(near[hits])]].item()
    hint = ""
    in_si = np.any(np.abs(grid - number) <= 1e-9 * np.max(np.abs(grid)))
    if isinstance(value, str) and not written and size != 1.0 and in_si:  # the number as stored: say so
        hint = f" ({number:g} is a value in {si}: write {number / size:.4g}, or '{number:g} {si}')"
    what = f"{number:.6g} {written or unit}".strip() if isinstance(value, str) else f"{number:.6g} {si}".strip()
    raise SweepError(f"select {dim}={value!r}: {what} is not a value of the sweep; its values are "
                     f"{_grid_text(shown, unit)}{hint}")


#: Quantities that describe the run itself, meaningful for failed points too: they are drawn for
#: every stored point. Every other quantity of a point that did not complete comes from a partial
#: run, and is masked (drawn blank, marked x).
RUN_STATISTICS = ("status", "wall_time", "end_time", "nfev")

#: The order of a categorical quantity's values on a map's colour bar (others follow, sorted).
ORDER = {"regime": ("full film", "mixed", "contact", "dry")}


def _fix_ticks(ax, xlog, ylog, xticks, yticks):
    from ..plots.units import plain_ticks

    if not xlog and not xticks:
        plain_ticks(ax.xaxis)
    if not ylog and not yticks:
        plain_ticks(ax.yaxis)


def plot_sweep(results, quantity=None, *, select=None, fig=None):
    """Response map of one quantity over the swept dimensions.

    One dimension left (after ``select``): curves; two: a heat map; three:
    heat maps faceted along the last one. A stored time series adds ``time`` as the first
    dimension (curves against time, or a time-parameter map). Values are drawn in display units
    (mm, µm, kPa, ...: :mod:`lubelink.plots.units`). Points that did not complete are masked and
    marked with a cross (their values come from a partial run), except for the run statistics
    :data:`RUN_STATISTICS`; points not yet computed are left blank.

    Parameters
    ----------
    results : xarray.Dataset or path
        :func:`run_sweep` / :func:`load_sweep` output, or a store path.
    quantity : str, optional
        Stored quantity or time series (default ``peak_u2_mid`` when stored); ``status``
        draws a map of the outcomes.
    select : dict, optional
        ``{dimension: value}`` slices at values of the sweep's grid: a number in the stored (SI)
        unit, or a string as ``--select`` gives it, a number in the unit of the dimension's axis
        (``"100"`` for 100 mPa s) optionally with a unit (``"0.1 Pa s"``). A value off the grid
        is refused, naming the grid's values. ``impact`` selects which of ``impact_times``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    from ..plots.units import display_unit, label

    ds = results if hasattr(results, "data_vars") else load_sweep(results)
    dims = ds.attrs.get("swept_dims", "").split()
    series = [q for q in ds.attrs.get("time_series", "").split() if q in ds]
    stored = [q for q in ds.attrs.get("quantities", "").split() if q in ds] + series + ["status", "wall_time"]
    if quantity is None:
        quantity = "peak_u2_mid" if "peak_u2_mid" in ds else stored[0]
    if quantity not in ds or quantity not in stored:
        raise SweepError(f"quantity {quantity!r}: not stored in these results; choose from "
                         + ", ".join(stored) + suggest(quantity, stored))
    select = dict(select or {})
    exact = {}
    for dim, value in list(select.items()):
        if dim not in ds.dims:
            raise SweepError(f"select {dim}: no such dimension; the dimensions are "
                             + ", ".join(ds[quantity].dims) + suggest(dim, ds.dims))
        if dim == "impact":  # which impact of impact_times: its number
            try:
                exact[dim] = int(value)
            except (TypeError, ValueError):
                raise SweepError(f"select impact={value!r}: must be an impact number (0 the first)") from None
        elif dim in ds.coords and ds[dim].dtype.kind in "fiu":
            exact[dim] = _pick(ds, dim, value)
        elif dim in ds.coords and value not in set(ds[dim].values.tolist()):
            raise SweepError(f"select {dim}={value!r}: not a value of the sweep; its values are "
                             + ", ".join(_fmt(v) for v in ds[dim].values.tolist()))
        else:
            exact[dim] = value
    if "impact" in ds[quantity].dims and "impact" not in select:
        exact["impact"] = 0
    try:
        sub = ds.sel({d: v for d, v in exact.items() if d in ds.coords and d != "impact"})
        if "impact" in exact:
            sub = sub.isel(impact=exact["impact"])
    except (KeyError, IndexError) as exc:
        raise SweepError(f"select: no such value {exc}") from None
    is_series = quantity in series
    if is_series:
        extra = [d for d in sub[quantity].dims if d not in dims and d != "time"]
        if extra:
            raise SweepError(f"{quantity} has the dimension {extra[0]} besides time: pick one value with "
                             f"--select {extra[0]}=VALUE")
        is_series = "time" in sub[quantity].dims  # (a series at one selected time is drawn as a summary)
    free = (["time"] if is_series else []) + [d for d in dims if d in sub[quantity].dims]
    n_swept = len(free) - is_series
    if len(free) > 3 or not free or (not is_series and n_swept == 0):
        raise SweepError(f"{n_swept} swept dimensions left ({', '.join(free[is_series:]) or 'none'}): plot-sweep "
                         "draws 1 (curves), 2 (heat map) or 3 (facets)" + (" with time as one" if is_series else "")
                         + "; fix the others with --select DIM=VALUE")
    done = sub["done"].astype(bool)
    failed_da = done & (sub["status"].astype(str) != "complete")
    values = sub[quantity]
    mask_failed = quantity not in RUN_STATISTICS
    categories = None
    if quantity == "status" or values.dtype.kind in "OUS":
        shown = values.values.reshape(-1)[np.broadcast_to(done.values, values.shape).reshape(-1)]
        present = {str(v) for v in shown}
        categories = [c for c in ORDER.get(quantity, ()) if c in present] + sorted(present - set(ORDER.get(quantity, ())))
        categories = categories or ["(none)"]
        codes = np.vectorize(lambda v: categories.index(str(v)) if str(v) in categories else -1,
                             otypes=[float])(values.values)
        da = values.copy(data=codes).where(done)
        unit, size = "", 1.0
    else:
        keep = done & ~failed_da if mask_failed else done
        da = values.astype(float).where(keep)
        unit, size = display_unit(values.attrs.get("units", ""), da.values)
        da = da / size
    da = da.transpose(*free)
    failed = failed_da.broadcast_like(values).transpose(*free).values
    title = label(quantity, unit)
    if select:
        title += "  (" + ", ".join(f"{d} = {_shown(sub[d], ds[d]) if d in sub.coords else v}"
                                   for d, v in select.items()) + ")"
    long_name = ds[quantity].attrs.get("long_name", quantity)

    panels = [None] if len(free) < 3 else list(range(sub.sizes[free[2]]))
    if len(panels) > 16:
        raise SweepError(f"{free[2]} has {len(panels)} values, too many panels: fix it with --select "
                         f"{free[2]}=VALUE, or another dimension")
    ncols = min(len(panels), 4)
    nrows = math.ceil(len(panels) / ncols)
    fig = fig or plt.figure(figsize=(7.0, 4.8) if len(free) < 3 else (3.6 * ncols + 1.0, 3.0 * nrows + 0.6))
    if len(free) == 1:
        ax = fig.add_subplot()
        x, ticks, log, xname = _axis_values(sub, free[0], False)
        ax.plot(x, da.values, "o-" if not is_series else "-", label=quantity)
        if failed.any():
            if is_series:  # the one point drawn did not complete: show its partial run apart
                partial = values.astype(float).transpose(*free).values / size
                ax.plot(x, partial, "--", color="tab:gray",
                        label=f"partial run (status {sub['status'].item()}, not complete)")
            else:
                ax.plot(x[failed], np.full(int(failed.sum()), 0.03), "x", color="tab:red", ms=9, mew=2,
                        transform=ax.get_xaxis_transform(), clip_on=False,
                        label="did not complete (masked)" if mask_failed else "did not complete")
            ax.legend()
        if ticks:
            ax.set_xticks(x, ticks)
        if log:
            ax.set_xscale("log")
        if categories:
            ax.set_yticks(range(len(categories)), categories)
        _fix_ticks(ax, log, False, ticks, categories)
        ax.set_xlabel(xname)
        ax.set_ylabel(title)
        ax.set_title(long_name, fontsize=10)
        ax.grid(True, alpha=0.3)
        return fig

    data = da.values
    finite = data[np.isfinite(data)]
    vmin, vmax = (finite.min(), finite.max()) if finite.size else (0.0, 1.0)
    cmap = plt.get_cmap("viridis", len(categories)) if categories else plt.get_cmap("viridis")
    if categories:
        vmin, vmax = -0.5, len(categories) - 0.5
    axes = fig.subplots(nrows, ncols, squeeze=False)
    mesh = None
    marked = False
    for k, panel in enumerate(panels):
        ax = axes.flat[k]
        z = data if panel is None else data[..., panel]
        f = failed if panel is None else failed[..., panel]
        x, xt, xlog, xname = _axis_values(sub, free[0], True)
        y, yt, ylog, yname = _axis_values(sub, free[1], True)
        mesh = ax.pcolormesh(_edges(x, xlog), _edges(y, ylog), z.T, cmap=cmap, vmin=vmin, vmax=vmax,
                             shading="flat")
        if f.any() and not categories:
            if is_series:  # a failed point is a blank row: mark it at the start of the time axis
                rows = np.nonzero(f.any(axis=0))[0]
                ax.plot(np.full(rows.size, 0.0), y[rows], "x", color="white", ms=7, mew=2,
                        markeredgecolor="black", transform=ax.get_yaxis_transform(), clip_on=False)
            else:
                ix, iy = np.nonzero(f)
                ax.plot(x[ix], y[iy], "x", color="white", ms=7, mew=2, markeredgecolor="black")
            marked = True
        if xt:
            ax.set_xticks(x, xt)
        if yt:
            ax.set_yticks(y, yt)
        if xlog:
            ax.set_xscale("log")
        if ylog:
            ax.set_yscale("log")
        _fix_ticks(ax, xlog, ylog, xt, yt)
        ax.set_xlabel(xname)
        ax.set_ylabel(yname if k % ncols == 0 else "")  # (facets share their axes)
        if panel is not None:
            ax.set_title(f"{free[2]} = {_shown(sub[free[2]][panel], sub[free[2]])}", fontsize=9)
        else:
            ax.set_title(long_name, fontsize=10)
    for ax in axes.flat[len(panels):]:
        ax.set_visible(False)
    cbar = fig.colorbar(mesh, ax=axes.ravel().tolist())
    if categories:
        cbar.set_ticks(range(len(categories)), labels=categories)
    else:
        from ..plots.units import plain_ticks

        plain_ticks(cbar.ax.yaxis)
    cbar.set_label(title + ("   x: did not complete (masked)" if marked and mask_failed else
                            "   x: did not complete" if marked else ""))
    return fig

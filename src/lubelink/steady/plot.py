"""The response-curve figure: peak deflection against the parameter, stability marked.

Draws a branch Dataset of :func:`lubelink.continuation`: stable orbits as solid lines, unstable
ones dashed, neutral ones (a multiplier on the unit circle, as for the undamped link) dotted;
bifurcations as markers; for a crank-speed branch the resonances ``omega0 = omega_n / k`` as
vertical lines. Matplotlib is imported inside the functions.
"""

from __future__ import annotations

import numpy as np

from ..plots._style import MM, _figure, _legend, _style
from ..plots.units import log_scale

__all__ = ["plot_branch", "figure_branch", "resonances"]

_MARKERS = {0: ("o", "fold"), 1: ("s", "branch point (+1)"), 2: ("D", "period doubling (-1)"),
            3: ("^", "Neimark-Sacker"), 4: ("*", "resonance (neutral, +1)")}


def resonances(ds, modes=(1,)):
    """``[(omega0, n, k)]``: the crank speeds ``omega_n / k`` inside the branch's range [rad/s]."""
    if ds.attrs.get("parameter") != "mechanism.crank_speed":
        return []
    x = np.abs(ds.parameter.values)
    lo, hi = float(x.min()), float(x.max())
    out = []
    for n in modes:
        if n > ds.mode.size:
            continue
        w = float(ds.omega_n.values[0, n - 1])
        for k in range(max(1, int(np.ceil(w / hi))), int(np.floor(w / lo)) + 1):
            out.append((w / k, n, k))
    return out


def _mark_resonances(ax, found, min_gap=0.012, label_gap=0.04):
    """Vertical lines at the resonances ``(omega0, n, k)``, thinned where they crowd (low speeds).

    A line is drawn when it is at least ``min_gap`` of the axis span from the last one drawn, and
    labelled when at least ``label_gap`` from the last label.
    """
    if not found:
        return
    lo, hi = ax.get_xlim()
    span = hi - lo
    last_line = last_label = -np.inf
    for w, n, k in sorted(found, reverse=True):  # from high speeds (sparse) to low (crowded)
        if abs(last_line - w) < min_gap * span:
            continue
        ax.axvline(w, color="0.5", lw=0.7, ls=(0, (2, 3)), zorder=0)
        last_line = w
        if abs(last_label - w) >= label_gap * span:
            ax.annotate(f"$\\omega_{n}/{k}$", (w, 1.0), xycoords=("data", "axes fraction"), ha="center",
                        va="top", fontsize=7, color="0.35", xytext=(0, -2), textcoords="offset points")
            last_label = w


def _state(ds, margin=1e-7):
    """Per point: 1 stable, -1 unstable, 0 neutral (a multiplier on the circle, within its accuracy
    estimate ``floquet_error``; ``margin`` for a branch file without it)."""
    if "floquet_error" in ds:
        moduli, err = ds.floquet_modulus.values, ds.floquet_error.values
        inside = np.all(moduli < 1.0 - err, axis=1)
        return np.where(inside, 1, np.where(np.any(moduli > 1.0 + err, axis=1), -1, 0))
    m = ds.max_modulus.values
    return np.where(m < 1.0 - margin, 1, np.where(m > 1.0 + margin, -1, 0))


def plot_branch(ds, ax=None, quantity="peak_u2_mid", label=None, color=None, marks=True):
    """Draw ``quantity`` (mm for lengths) against the parameter on ``ax``; returns ``ax``.

    Stable stretches solid, unstable dashed, neutral dotted; bifurcations as markers (with
    ``marks``).
    """
    if ax is None:
        import matplotlib.pyplot as plt

        ax = plt.gca()
    x = ds.parameter.values
    y = ds[quantity].values * (MM if ds[quantity].attrs.get("units") == "m" else 1.0)
    state = _state(ds)
    styles = {1: "-", -1: "--", 0: ":"}
    color = color or "C0"
    first = True
    start = 0
    for i in range(1, len(x) + 1):
        if i == len(x) or state[i] != state[start]:
            stop = min(i + 1, len(x))  # overlap one point so that the curve is continuous
            ax.plot(x[start:stop], y[start:stop], styles[int(state[start])], color=color, lw=1.4,
                    label=label if first else None)
            first = False
            start = i
    if marks and ds.bifurcation.size:
        for code, lam, point in zip(ds.bifurcation_type.values, ds.bifurcation_parameter.values,
                                    ds.bifurcation_point.values):
            marker, name = _MARKERS[int(code)]
            j = int(point)
            f = (lam - x[j - 1]) / (x[j] - x[j - 1]) if x[j] != x[j - 1] else 0.0
            yb = y[j - 1] + min(max(f, 0.0), 1.0) * (y[j] - y[j - 1])
            ax.plot([lam], [yb], marker, color=color, mec="k", ms=6, ls="none")
    units = ds.parameter.attrs.get("units", "")
    ax.set_xlabel(f"{ds.attrs.get('parameter', 'parameter')}" + (f" [{units}]" if units else ""))
    unit = "mm" if ds[quantity].attrs.get("units") == "m" else ds[quantity].attrs.get("units", "")
    ax.set_ylabel(f"{quantity} [{unit}]")
    return ax


def figure_branch(branches, title=None, transients=None, log=None, modes=(1,), quantity="peak_u2_mid"):
    """A response-curve figure of one or more branches.

    Parameters
    ----------
    branches : xarray.Dataset or dict of str -> xarray.Dataset
        Branch Datasets (label -> Dataset).
    title : str, optional
    transients : dict of str -> (array, array), optional
        Label -> (parameter values, peak ``|u2_mid|`` [m]) of long transients, drawn as crosses.
    log : bool, optional
        Logarithmic deflection axis; by default one where the values drawn span a decade or
        more, a linear one otherwise (:func:`lubelink.plots.units.log_scale`).
    modes : tuple of int
        Modes whose resonances ``omega_n / k`` are marked (crank-speed branches).
    """
    if not isinstance(branches, dict):
        branches = {None: branches}
    with _style():
        fig = _figure(8.0, 4.8)
        ax = fig.subplots()
        for i, (label, ds) in enumerate(branches.items()):
            plot_branch(ds, ax, quantity, label=label, color=f"C{i}")
        for j, (label, (x, y)) in enumerate((transients or {}).items()):
            ax.plot(x, np.asarray(y) * MM, "x", color="k", ms=6, mew=1.4, label=label)
        first = next(iter(branches.values()))
        _mark_resonances(ax, resonances(first, modes))
        if log is None:
            drawn = [ds[quantity].values for ds in branches.values()] + [y for _, y in (transients or {}).values()]
            log = log_scale(np.concatenate([np.ravel(v) for v in drawn]))
        if log:
            ax.set_yscale("log")
        # the line styles and markers explained once
        ax.plot([], [], "-", color="0.3", label="stable")
        ax.plot([], [], "--", color="0.3", label="unstable")
        if any((_state(ds) == 0).any() for ds in branches.values()):
            ax.plot([], [], ":", color="0.3", label="neutral (|multiplier| = 1)")
        shown = sorted({int(c) for ds in branches.values() for c in ds.bifurcation_type.values})
        for code in shown:
            ax.plot([], [], _MARKERS[code][0], color="w", mec="k", label=_MARKERS[code][1])
        _legend(ax, 6)
        if title:
            fig.suptitle(title)
    return fig

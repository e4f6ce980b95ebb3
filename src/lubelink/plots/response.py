"""Responses of single runs: deflection, midpoint, film pressure, impacts, thinnest film.

The ``plot_*`` functions draw one panel (paper Figs. 6-9) on the axes they
are given, or on the current pyplot axes; the ``figure_*`` functions compose
the paper's Figs. 6-9 on a new :class:`matplotlib.figure.Figure`.
"""

from __future__ import annotations

import numpy as np

from ._style import KPA, MM, UM, _ax, _figure, _legend, _levels, _style
from .units import log_scale

__all__ = [
    "plot_deflection_surface",
    "plot_deflection_3d",
    "plot_midpoint",
    "plot_midpoint_difference",
    "plot_pressure_surface",
    "plot_impacts",
    "plot_film_min",
    "figure_deflection",
    "figure_lubrication",
    "figure_pressure",
    "figure_impact",
]


# ----------------------------------------------------------------- single panels
def plot_deflection_surface(ds, ax=None, levels=24, cmap="RdBu_r"):
    """Filled contour of the deflection ``u2(x, t)`` (paper Fig. 6).

    Parameters
    ----------
    ds : xarray.Dataset
        Results with ``u2`` [m] on ``(time, x)``.
    ax : matplotlib.axes.Axes, optional
    levels : int
        Largest number of contour levels (round values, symmetric about zero).

    Returns
    -------
    matplotlib.contour.QuadContourSet
        With ``.axes``; pass it to ``colorbar``.
    """
    ax = _ax(ax)
    u = ds.u2.values * MM
    cs = ax.contourf(ds.time.values, ds.x.values, u.T, levels=_levels(u, levels), cmap=cmap)
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("position along the link x [m]")
    return cs


def plot_deflection_3d(ds, ax=None, t_max=None, max_lines=250, cmap="RdBu_r"):
    """3-D surface of ``u2(x, t)`` [mm] over ``(t, x)`` (paper Fig. 6 style).

    The surface is rasterised inside vector outputs so PDFs stay small.

    Parameters
    ----------
    ds : xarray.Dataset
        Results with ``u2`` [m].
    ax : mpl_toolkits.mplot3d.Axes3D, optional
    t_max : float, optional
        Last time drawn [s] (default all).
    max_lines : int
        Largest number of time samples drawn (the data are strided).
    """
    ax = _ax(ax, projection="3d")
    if t_max is not None:
        ds = ds.sel(time=slice(None, t_max))
    stride = max(1, int(np.ceil(ds.sizes["time"] / max_lines)))
    t = ds.time.values[::stride]
    x = ds.x.values
    u = ds.u2.values[::stride] * MM
    T, Xg = np.meshgrid(t, x, indexing="ij")
    top = float(np.nanmax(np.abs(u))) or 1.0
    ax.plot_surface(T, Xg, u, cmap=cmap, vmin=-top, vmax=top, linewidth=0, antialiased=False,
                    rcount=len(t), ccount=len(x), rasterized=True)
    ax.set_xlabel("t [s]", labelpad=2)
    ax.set_ylabel("x [m]", labelpad=2)
    ax.set_zlabel("u2 [mm]", labelpad=2)
    ax.view_init(elev=30, azim=-60)
    return ax


def plot_midpoint(datasets, ax=None, styles=None):
    """Midpoint deflection ``u2(L/2, t)`` [mm] of several runs on one axes.

    Parameters
    ----------
    datasets : dict of str -> xarray.Dataset
        Legend label -> results (``u2_mid`` [m]).
    styles : dict of str -> dict, optional
        Extra ``plot`` keywords per label.
    """
    ax = _ax(ax)
    styles = styles or {}
    for label, ds in datasets.items():
        ax.plot(ds.time.values, ds.u2_mid.values * MM, label=label, **styles.get(label, {"lw": 1.0}))
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("midpoint deflection u2(L/2, t) [mm]")
    _legend(ax, len(datasets))
    return ax


def plot_midpoint_difference(datasets, reference, ax=None, styles=None):
    """``u2_mid - u2_mid[reference]`` [µm] for every other run (on the reference's times).

    Parameters
    ----------
    datasets : dict of str -> xarray.Dataset
        Label -> results; each is interpolated on the reference's time
        samples (a run that ended early is drawn up to its end).
    reference : str
        Label of the run subtracted.
    """
    ax = _ax(ax)
    styles = styles or {}
    ref = datasets[reference]
    t = ref.time.values
    for label, ds in datasets.items():
        if label == reference:
            continue
        d = np.interp(t, ds.time.values, ds.u2_mid.values) - ref.u2_mid.values
        d[(t < ds.time.values[0]) | (t > ds.time.values[-1])] = np.nan  # no extrapolation
        ax.plot(t, d * UM, label=label, **styles.get(label, {"lw": 0.9}))
    ax.axhline(0.0, color="0.3", lw=0.6)
    ax.set_xlabel("time t [s]")
    ax.set_ylabel(f"u2(L/2, t) minus {reference} [µm]")
    _legend(ax, len(datasets) - 1)
    return ax


def plot_pressure_surface(ds, ax=None, levels=24, cmap="RdBu_r"):
    """Filled contour of the gauge film pressure ``P - p_am`` [kPa] over the pad (paper Fig. 8).

    Parameters
    ----------
    ds : xarray.Dataset
        Results with ``pressure`` [Pa] on ``(time, x_pad)`` (a run with a film).

    Returns
    -------
    matplotlib.contour.QuadContourSet
    """
    ax = _ax(ax)
    p = ds.pressure.values * KPA
    cs = ax.contourf(ds.time.values, ds.x_pad.values * MM, p.T, levels=_levels(p, levels), cmap=cmap)
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("position on the pad X [mm]")
    return cs


def plot_impacts(ds, ax=None, target=None, label="lubelink"):
    """Midpoint deflection [mm] with every impact marked (paper Fig. 9).

    Parameters
    ----------
    ds : xarray.Dataset
        Results of a run with a contact law (``impact_time`` [s]).
    target : float, optional
        Paper's first-impact time [s], drawn as a dashed line.
    """
    ax = _ax(ax)
    t, u = ds.time.values, ds.u2_mid.values * MM
    ax.plot(t, u, lw=1.0, color="C0", label=label)
    times = ds.impact_time.values
    if times.size:
        ax.plot(times, np.interp(times, t, u), "v", color="C3", ms=6,
                label=f"impacts ({times.size}; first at {times[0]:.4f} s)")
    if target is not None:
        ax.axvline(target, color="k", ls="--", lw=0.9, label=f"paper's impact, t = {target} s")
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("midpoint deflection u2(L/2, t) [mm]")
    ax.legend(loc="lower right")
    return ax


def plot_film_min(ds, ax=None, min_film=None):
    """Thinnest film on the pad [mm] against time, with the breakdown threshold.

    Parameters
    ----------
    ds : xarray.Dataset
        Results with ``film_min`` [m].
    min_film : float, optional
        Breakdown threshold ``xi_min`` [m].
    """
    ax = _ax(ax)
    ax.plot(ds.time.values, ds.film_min.values * MM, lw=0.9, color="C2", label="thinnest film (sampled)")
    for ti in ds.impact_time.values:
        ax.axvline(ti, color="C3", lw=0.5, alpha=0.6)
    if min_film is not None:
        ax.axhline(min_film * MM, color="C3", ls=":", lw=0.9, label=f"breakdown, {min_film * UM:g} µm")
    if log_scale(np.append(ds.film_min.values, [] if min_film is None else [min_film])):  # decades: a log axis
        ax.set_yscale("log")
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("thinnest film [mm]")
    ax.legend(loc="lower right", fontsize=8)
    return ax


# ----------------------------------------------------------------- whole figures
def figure_deflection(ds, title=None, t_zoom=0.4):
    """Paper Fig. 6: filled contour of ``u2(x, t)`` and a 3-D surface of its start.

    Parameters
    ----------
    ds : xarray.Dataset
        Results with ``u2`` [m].
    t_zoom : float
        The 3-D surface shows ``[0, t_zoom]`` [s] (default two crank turns).

    Returns
    -------
    matplotlib.figure.Figure
    """
    with _style():
        fig = _figure(10.0, 4.0)
        ax1 = fig.add_subplot(1, 2, 1)
        cs = plot_deflection_surface(ds, ax1)
        fig.colorbar(cs, ax=ax1, label="u2 [mm]")
        ax2 = fig.add_subplot(1, 2, 2, projection="3d")
        plot_deflection_3d(ds, ax2, t_max=t_zoom)
        ax2.set_title(f"first {t_zoom:g} s", fontsize=9)
        fig.suptitle(title or "Deflection of the flexible link in time and space (paper Fig. 6)")
    return fig


def figure_lubrication(datasets, reference, title=None, styles=None):
    """Paper Fig. 7: midpoint deflection with and without lubricant, and the differences.

    Parameters
    ----------
    datasets : dict of str -> xarray.Dataset
        Label -> results; ``reference`` (the dry joint) is subtracted below.
    reference : str
        Label of the dry run.
    """
    with _style():
        fig = _figure(8.0, 6.0)
        ax1, ax2 = fig.subplots(2, 1, sharex=True)
        plot_midpoint(datasets, ax1, styles)
        plot_midpoint_difference(datasets, reference, ax2, styles)
        ax1.set_xlabel("")
        fig.suptitle(title or "Deflection with and without lubrication (paper Fig. 7)")
    return fig


def figure_pressure(ds, title=None):
    """Paper Fig. 8: gauge film pressure over the pad and time, and the film force."""
    with _style():
        fig = _figure(8.0, 6.0)
        ax1, ax2 = fig.subplots(2, 1, sharex=True, height_ratios=[2, 1])
        cs = plot_pressure_surface(ds, ax1)
        fig.colorbar(cs, ax=ax1, label="gauge pressure P - p_am [kPa]")
        ax1.set_xlabel("")
        ax1.grid(False)
        ax2.plot(ds.time.values, ds.film_force.values, lw=0.8, color="C1")
        ax2.set_xlabel("time t [s]")
        ax2.set_ylabel("film force on link [N]")
        fig.suptitle(title or "Pressure in the lubricant film (paper Fig. 8)")
    return fig


def figure_impact(ds, target=None, min_film=None, title=None, note=None, zoom=0.04):
    """Paper Fig. 9: midpoint deflection with film breakdown and impacts, the thinnest film, a zoom.

    Parameters
    ----------
    ds : xarray.Dataset
        Results of a run with a contact law.
    target : float, optional
        Paper's first-impact time [s].
    min_film : float, optional
        Breakdown threshold [m].
    note : str, optional
        Subtitle (e.g. how the clearance was found).
    zoom : float
        Half-width of the zoom around the first impact (and ``target``) [s].
    """
    times = ds.impact_time.values
    with _style():
        fig = _figure(8.0, 7.5 if times.size else 6.0)
        if times.size:
            ax1, ax2, ax3 = fig.subplots(3, 1, height_ratios=[2, 1, 1.3])
        else:
            (ax1, ax2), ax3 = fig.subplots(2, 1, sharex=True, height_ratios=[2, 1]), None
        plot_impacts(ds, ax1, target=target)
        ax1.set_xlabel("")
        plot_film_min(ds, ax2, min_film=min_film)
        ax2.sharex(ax1)
        ax2.set_xlabel("")
        if target is not None:
            ax2.axvline(target, color="k", ls="--", lw=0.9)
        if ax3 is not None:
            t0 = times[0]
            ends = [t0, t0] if target is None else [min(t0, target), max(t0, target)]
            part = ds.sel(time=slice(ends[0] - zoom, ends[1] + zoom))
            ax3.plot(part.time.values, part.u2_mid.values * MM, lw=1.2, color="C0")
            first = np.interp(t0, ds.time.values, ds.u2_mid.values) * MM
            ax3.plot([t0], [first], "v", color="C3", ms=7,
                     label=f"first impact, t = {t0:.4f} s, approach velocity "
                           f"{ds.impact_velocity.values[0] * MM:.3g} mm/s")
            if target is not None:
                ax3.axvline(target, color="k", ls="--", lw=0.9, label=f"paper's impact, t = {target} s")
            ax3.set_xlabel("time t [s]")
            ax3.set_ylabel("u2(L/2, t) [mm]")
            ax3.legend(loc="lower left", fontsize=8)
            ax3.set_title("zoom on the first impact", fontsize=9)
        if note:
            ax1.set_title(note, fontsize=9)
        fig.suptitle(title or "Midpoint deflection with film breakdown and impact, e = 0.7 (paper Fig. 9)")
    return fig

"""Figures comparing several runs: modal convergence, errata, lubrication effect, first-impact map.

Each ``figure_*`` function composes a whole figure on a new
:class:`matplotlib.figure.Figure` from results computed by
:mod:`lubelink.paper`.
"""

from __future__ import annotations

import numpy as np

from ._style import MM, _figure, _legend, _style
from .units import log_scale
from .response import plot_midpoint, plot_midpoint_difference

__all__ = [
    "figure_modal_convergence",
    "figure_errata",
    "figure_lubrication_effect",
    "figure_first_impact_map",
]


def figure_modal_convergence(datasets, reference=None, title=None):
    """Midpoint deflection for several mode counts and the difference from the largest.

    Parameters
    ----------
    datasets : dict of int -> xarray.Dataset
        Number of modes -> results.
    reference : int, optional
        Mode count subtracted (default: the largest).
    """
    reference = max(datasets) if reference is None else reference
    labelled = {f"N = {n}": ds for n, ds in sorted(datasets.items())}
    with _style():
        fig = _figure(8.0, 6.0)
        ax1, ax2 = fig.subplots(2, 1, sharex=True)
        plot_midpoint(labelled, ax1)
        plot_midpoint_difference(labelled, f"N = {reference}", ax2)
        ax1.set_xlabel("")
        fig.suptitle(title or "Modal convergence: 1, 3, 5 and 7 modes")
    return fig


def figure_errata(datasets, reference, title=None):
    """Corrected equations against the paper's printed ones: ``u2_mid`` and the differences.

    Parameters
    ----------
    datasets : dict of str -> xarray.Dataset
        Label -> results of each variant.
    reference : str
        Label of the corrected run.
    """
    # The corrected run is a wide dark line under the others, which are thin (and dashed), so that
    # it shows wherever a variant coincides with it (the omega^2 sign is invisible at this scale).
    # Below, the variants are drawn from the largest difference to the smallest, each on top of
    # the larger ones, with a style of its own: two variants that nearly coincide both show.
    dashes = ["--", "-.", ":", "-"]  # the fourth is thin and solid, unlike the reference
    variants = [label for label in datasets if label != reference]
    styles = {reference: {"lw": 3.0, "color": "0.25", "zorder": 1, "solid_capstyle": "butt"}}
    for i, label in enumerate(variants):
        styles[label] = {"lw": 1.2, "ls": dashes[i % len(dashes)], "color": f"C{i}", "zorder": 2 + i}
    ref = datasets[reference].u2_mid.values

    def spread(label):
        ds = datasets[label]
        n = min(ds.u2_mid.size, ref.size)
        return float(np.nanmax(np.abs(ds.u2_mid.values[:n] - ref[:n]))) if n else 0.0

    largest_first = sorted(variants, key=spread, reverse=True)
    for z, label in enumerate(largest_first):
        styles[label] = {**styles[label], "zorder": 2 + z}
    with _style():
        fig = _figure(8.0, 6.0)
        ax1, ax2 = fig.subplots(2, 1, sharex=True)
        plot_midpoint(datasets, ax1, styles)
        plot_midpoint_difference({reference: datasets[reference], **{k: datasets[k] for k in largest_first}},
                                 reference, ax2, styles)
        ax1.set_xlabel("")
        fig.suptitle(title or "Effect of the errata: corrected (wide line) against printed equations (thin)")
    return fig


def figure_lubrication_effect(effect, title=None):
    """Change of the peak midpoint deflection caused by the film, against viscosity.

    Parameters
    ----------
    effect : xarray.Dataset
        From :func:`lubelink.paper.lubrication_effect` (``change`` on
        ``(model, viscosity, clearance)``, ``film_min``).
    """
    markers = {"wedge": "o-", "wedge+squeeze": "s--"}
    t_end = effect.attrs.get("t_end")
    span = f" over 0-{t_end:g} s" if t_end else ""
    with _style():
        fig = _figure(8.0, 6.0)
        ax1, ax2 = fig.subplots(2, 1, sharex=True)
        broken = False
        for i, H in enumerate(effect.clearance.values):
            for model in effect.model.values:
                e = effect.sel(model=model, clearance=H)
                style = dict(color=f"C{i}", label=f"{model}, H = {H * MM:g} mm")
                mu = effect.viscosity.values
                ax1.plot(mu, e.change.values * 100, markers.get(str(model), "^-"), **style)
                ax2.plot(mu, e.film_min.values * MM, markers.get(str(model), "^-"), **style)
                bad = e.status.values != "complete"
                if bad.any():
                    broken = True
                    ax1.plot(mu[bad], e.change.values[bad] * 100, "kx", ms=9)
                    ax2.plot(mu[bad], e.film_min.values[bad] * MM, "kx", ms=9)
        if broken:
            ax1.plot([], [], "kx", ms=9, label="film broke down: run ended early")
        ax1.axhline(0.0, color="k", lw=0.8)
        ax1.set_ylabel("peak |u2(L/2)|: change from dry [%]")
        _legend(ax1, 4)
        if log_scale(effect.viscosity.values):
            ax2.set_xscale("log")
        ax2.set_xlabel("viscosity mu [Pa s]")
        ax2.set_ylabel("thinnest film [mm]")
        fig.suptitle(title or f"Does the film reduce the deflection? Peak |u2(L/2)|{span}, film against dry joint")
    return fig


def figure_first_impact_map(impacts, target=None, title=None):
    """When can the film break down? First-impact times over viscosity and clearance.

    Parameters
    ----------
    impacts : xarray.Dataset
        From :func:`lubelink.paper.first_impact_map`: ``first_impact`` [s]
        and ``phase`` [s] on ``(viscosity, clearance)``, ``attrs["period"]``
        the crank period [s].
    target : float, optional
        The paper's first-impact time [s], marked on both panels.
    """
    period = float(impacts.attrs["period"])
    with _style():
        fig = _figure(8.0, 6.5)
        ax1, ax2 = fig.subplots(2, 1, height_ratios=[1.4, 1])
        for i, mu in enumerate(impacts.viscosity.values):
            t1 = impacts.first_impact.sel(viscosity=mu).values
            ok = np.isfinite(t1)
            ax1.plot(impacts.clearance.values[ok] * MM, t1[ok], ".", ms=4, color=f"C{i}",
                     label=f"mu = {mu * 1e3:g} mPa s")
        if target is not None:
            ax1.axhline(target, color="k", ls="--", lw=0.9, label=f"paper, {target} s")
        ax1.set_xlabel("clearance H [mm]")
        ax1.set_ylabel("first impact [s]")
        _legend(ax1, impacts.sizes["viscosity"] + 1)
        angle = impacts.phase.values[np.isfinite(impacts.phase.values)] / period * 360.0
        ax2.hist(angle, bins=np.arange(0, 361, 5), color="C0")
        if target is not None:
            ax2.axvline((target % period) / period * 360.0, color="k", ls="--", lw=0.9,
                        label=f"paper's impact: {(target % period) / period * 360.0:.0f}°")
            ax2.legend(loc="upper right", fontsize=8)
        ax2.set_xlim(0, 360)
        ax2.set_xticks(np.arange(0, 361, 45))
        ax2.set_xlabel("crank angle at the first impact [deg]")
        ax2.set_ylabel("runs")
        n, hit = impacts.first_impact.size, int(np.isfinite(impacts.first_impact.values).sum())
        pad = impacts.attrs.get("pad_length")
        where = "" if pad is None else f", pad {float(pad) * 1e3:g} mm"
        fig.suptitle(title or f"First film breakdown from zero initial conditions{where}: {hit} of {n} runs")
    return fig

"""Figures of lubelink results (paper Figs. 6-9 and beyond), drawn with Matplotlib.

Every function here is pure: it takes results :class:`xarray.Dataset` objects
(see :func:`lubelink.simulate`) and draws on the axes it is given, or, when
``ax`` is omitted, on the current pyplot axes; it returns what it drew on.
The ``figure_*`` functions compose whole figures on a new
:class:`matplotlib.figure.Figure` (no pyplot state), ready for ``savefig``.
Nothing here computes a simulation: :mod:`lubelink.paper` does that.

Lengths are drawn in mm, deflection differences in µm, pressures in kPa,
times in s.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "STYLE",
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
    "figure_modal_convergence",
    "figure_errata",
    "figure_lubrication_effect",
    "figure_first_impact_map",
    "draw_mechanism",
    "animate_mechanism",
]

#: Matplotlib settings of every figure (readable at column width).
STYLE = {
    "font.size": 10,
    "axes.titlesize": 11,
    "axes.labelsize": 10,
    "legend.fontsize": 9,
    "xtick.labelsize": 9,
    "ytick.labelsize": 9,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "figure.constrained_layout.use": True,
    "savefig.bbox": "tight",
}

MM, UM, KPA = 1e3, 1e6, 1e-3


def _ax(ax, projection=None):
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt

    if projection is None:
        return plt.gca()
    return plt.gcf().add_subplot(projection=projection)


def _figure(width=7.0, height=4.2):
    import matplotlib
    from matplotlib.figure import Figure

    with matplotlib.rc_context(STYLE):
        return Figure(figsize=(width, height), layout="constrained")


def _levels(data, n):
    """Round, symmetric contour levels covering ``data``."""
    from matplotlib.ticker import MaxNLocator

    top = float(np.nanmax(np.abs(data))) or 1.0
    return MaxNLocator(nbins=n, symmetric=True).tick_values(-top, top)


def _style():
    import matplotlib

    return matplotlib.rc_context(STYLE)


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


def _legend(ax, n):
    """Legend above the axes, in columns, so that it never hides the curves."""
    longest = max((len(t) for t in ax.get_legend_handles_labels()[1]), default=0)
    ncols = min(n, 4 if longest <= 20 else 3 if longest <= 28 else 2)
    ax.legend(loc="lower left", bbox_to_anchor=(0.0, 1.0), ncols=max(ncols, 1), fontsize=8, frameon=False,
              borderaxespad=0.2, handlelength=1.8, columnspacing=1.2)


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
        Results with ``pressure`` [Pa] on ``(time, X)`` (a run with a film).

    Returns
    -------
    matplotlib.contour.QuadContourSet
    """
    ax = _ax(ax)
    p = ds.pressure.values * KPA
    cs = ax.contourf(ds.time.values, ds.X.values * MM, p.T, levels=_levels(p, levels), cmap=cmap)
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
    with _style():
        fig = _figure(8.0, 6.0)
        ax1, ax2 = fig.subplots(2, 1, sharex=True)
        plot_midpoint(datasets, ax1, {reference: {"lw": 1.6, "color": "k"}})
        plot_midpoint_difference(datasets, reference, ax2)
        ax1.set_xlabel("")
        fig.suptitle(title or "Effect of the errata: corrected against printed equations")
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
        fig.suptitle(title or f"First film breakdown from zero initial conditions: {hit} of {n} runs")
    return fig


# ----------------------------------------------------------------- mechanism
def _mechanism_geometry(ds, i, scale, cfg):
    """Points of the mechanism at time sample ``i`` in the fixed frame [m]."""
    from ..kinematics import slider_crank

    m, fm = cfg.mechanism, cfg.film
    t = float(ds.time.values[i])
    k = slider_crank(t, m.crank_length, m.rod_length, m.crank_speed, m.guide_distance)
    phi = m.crank_speed * t
    pin = m.crank_length * np.array([np.cos(phi), np.sin(phi)])
    th = float(k["theta"])
    e_i = np.array([np.cos(th), -np.sin(th)])
    e_j = np.array([np.sin(th), np.cos(th)])
    x = ds.x.values
    u = ds.u2.values[i]
    rod = pin + np.outer(x, e_i) + scale * np.outer(u, e_j)
    slider = pin + m.rod_length * e_i
    x_star = float(ds.x_star.values[i])
    x0 = x_star - 0.5 * fm.pad_length if fm.pad_reference == "centre" else x_star
    return {"cfg": cfg, "t": t, "pin": pin, "e_i": e_i, "e_j": e_j, "rod": rod, "slider": slider,
            "x_star": x_star, "x0": x0, "guide_point": pin + x_star * e_i}


def draw_mechanism(ds, i=0, ax=None, scale=50.0, artists=None, config=None):
    """Draw (or update) the slider-crank at time sample ``i``.

    The crank, the flexible link with its deflection magnified ``scale``
    times (the clearance is magnified alike, so the gap is to scale with the
    deflection), the collar on its vertical guide at ``X = a`` and the slider.

    Parameters
    ----------
    ds : xarray.Dataset
        Results of a slider-crank run (``u2``, ``x_star``; the configuration
        is read from ``attrs["config"]``).
    i : int
        Time sample.
    scale : float
        Magnification of the deflection and of the clearance [-].
    artists : dict, optional
        Returned by an earlier call on the same axes: updated in place.
    config : lubelink.Config, optional
        The run's configuration (default: parsed from ``ds.attrs["config"]``).

    Returns
    -------
    dict
        The Matplotlib artists, for :func:`animate_mechanism`.
    """
    from matplotlib.patches import Polygon

    if config is None:
        from ..results import config_of

        config = config_of(ds)
    g = _mechanism_geometry(ds, i, scale, config)
    cfg, pin, e_i, e_j = g["cfg"], g["pin"], g["e_i"], g["e_j"]
    m, fm = cfg.mechanism, cfg.film
    thick = 0.02
    if fm.enabled or cfg.contact.law != "none":
        face = scale * 0.5 * fm.clearance
    else:
        face = 0.012
    corners = [g["x0"], g["x0"] + fm.pad_length]

    def pad(side):  # collar face at side * face from the chord, body beyond it
        inner, outer = side * face, side * (face + thick)
        return np.array([pin + corners[0] * e_i + inner * e_j, pin + corners[1] * e_i + inner * e_j,
                         pin + corners[1] * e_i + outer * e_j, pin + corners[0] * e_i + outer * e_j])

    collar = pad(1)
    lower = pad(-1) if getattr(fm, "sides", 1) == 2 else None
    member = g["guide_point"] + (face + thick) * e_j
    slider = g["slider"]
    slider_box = slider + np.array([[-0.05, -0.025], [0.05, -0.025], [0.05, 0.025], [-0.05, 0.025]])
    label = f"t = {g['t']:.3f} s   deflection and clearance magnified x{scale:g}"
    if artists is None:
        ax = _ax(ax)
        a = {}
        ax.plot([-0.15, m.crank_length + m.rod_length + 0.15], [-0.025, -0.025], color="0.5", lw=1.0)
        ax.plot([m.guide_distance] * 2, [-0.35, 0.35], color="0.5", lw=1.0, ls="--")
        ax.plot([0.0], [0.0], "ko", ms=5)
        a["crank"], = ax.plot([0.0, pin[0]], [0.0, pin[1]], color="k", lw=3)
        a["chord"], = ax.plot(*np.array([pin, slider]).T, color="0.6", lw=0.8, ls=":")
        a["rod"], = ax.plot(g["rod"][:, 0], g["rod"][:, 1], color="C0", lw=2.5)
        a["collar"] = ax.add_patch(Polygon(collar, closed=True, color="C1", alpha=0.9))
        if lower is not None:
            a["collar_lower"] = ax.add_patch(Polygon(lower, closed=True, color="C1", alpha=0.9))
        a["member"], = ax.plot([member[0]], [member[1]], "s", color="C1", ms=7)
        a["slider"] = ax.add_patch(Polygon(slider_box, closed=True, color="0.4"))
        a["text"] = ax.text(0.02, 0.95, label, transform=ax.transAxes, va="top")
        ax.set_aspect("equal")
        ax.set_xlim(-0.15, m.crank_length + m.rod_length + 0.15)
        ax.set_ylim(-0.35, 0.35)
        ax.set_xlabel("X [m]")
        ax.set_ylabel("Y [m]")
        return a
    artists["crank"].set_data([0.0, pin[0]], [0.0, pin[1]])
    artists["chord"].set_data(*np.array([pin, slider]).T)
    artists["rod"].set_data(g["rod"][:, 0], g["rod"][:, 1])
    artists["collar"].set_xy(collar)
    if lower is not None:
        artists["collar_lower"].set_xy(lower)
    artists["member"].set_data([member[0]], [member[1]])
    artists["slider"].set_xy(slider_box)
    artists["text"].set_text(label)
    return artists


def animate_mechanism(ds, scale=50.0, fps=20, frames=None, size=(7.0, 3.2), dpi=80):
    """Animation of the mechanism over the samples of ``ds``.

    Parameters
    ----------
    ds : xarray.Dataset
        Results of a slider-crank run; every time sample is a frame unless
        ``frames`` selects some.
    scale : float
        Magnification of the deflection [-].
    fps : int
        Frames per second of the animation [1/s].
    frames : sequence of int, optional
        Time samples to show.
    size : (float, float)
        Figure size [in].

    Returns
    -------
    (matplotlib.figure.Figure, matplotlib.animation.FuncAnimation)
    """
    from matplotlib.animation import FuncAnimation

    frames = list(range(ds.sizes["time"])) if frames is None else list(frames)
    import matplotlib
    from matplotlib.figure import Figure

    with matplotlib.rc_context({**STYLE, "figure.constrained_layout.use": False}):
        fig = Figure(figsize=size, dpi=dpi)  # fixed layout: no re-layout on every frame
        ax = fig.add_subplot(1, 1, 1)
        fig.subplots_adjust(left=0.1, right=0.98, bottom=0.16, top=0.97)
        ax.grid(False)
        from ..results import config_of

        config = config_of(ds)
        artists = draw_mechanism(ds, frames[0], ax, scale, config=config)

    def update(i):
        draw_mechanism(ds, i, scale=scale, artists=artists, config=config)
        return list(artists.values())

    anim = FuncAnimation(fig, update, frames=frames, interval=1000.0 / fps, blit=False)
    return fig, anim

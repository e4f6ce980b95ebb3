"""The mechanism itself: the slider-crank drawn at one time sample, and animated.

Two views, each in true coordinates with one unit per axis (nothing magnified):

* :func:`draw_mechanism`: the mechanism in the fixed plane, ``X``, ``Y`` [m], to scale (the
  link's deflection, a few millimetres on a 1 m link, is too small to see there);
* :func:`draw_link_view`: the link seen in its own frame, the deflection ``u2`` [mm] against the
  position ``x`` along the link [m], with the collar faces at ``±H/2`` over the pad.

:func:`animate_mechanism` shows both, one above the other, each with its legend.
"""

from __future__ import annotations

import numpy as np

from ._style import MM, STYLE, _ax

__all__ = ["draw_mechanism", "draw_link_view", "animate_mechanism"]

#: Drawn size of the collar block across the link [m] (the paper gives none; a sketch at scale).
COLLAR_DEPTH = 0.03


def _mechanism_geometry(ds, i, cfg):
    """Points of the mechanism at time sample ``i`` in the fixed frame [m], to scale."""
    from ..link.kinematics import slider_crank

    m, fm = cfg.mechanism, cfg.film
    t = float(ds.time.values[i])
    k = slider_crank(t, m.crank_length, m.rod_length, m.crank_speed, m.guide_distance)
    phi = m.crank_speed * t
    pin = m.crank_length * np.array([np.cos(phi), np.sin(phi)])
    th = float(k["theta"])
    e_i = np.array([np.cos(th), -np.sin(th)])
    e_j = np.array([np.sin(th), np.cos(th)])
    rod = pin + np.outer(ds.x.values, e_i) + np.outer(ds.u2.values[i], e_j)
    x_star = float(ds.x_star.values[i])
    x0 = x_star - 0.5 * fm.pad_length if fm.pad_reference == "centre" else x_star
    return {"t": t, "pin": pin, "e_i": e_i, "e_j": e_j, "rod": rod, "slider": pin + m.rod_length * e_i,
            "x_star": x_star, "x0": x0, "guide_point": pin + x_star * e_i}


def _legend(ax, ncols):
    ax.legend(loc="lower left", bbox_to_anchor=(0.0, 1.0), ncols=ncols, fontsize=7, frameon=False,
              borderaxespad=0.2, handlelength=1.8, columnspacing=1.0)


def _config(ds, config):
    if config is not None:
        return config
    from ..netcdf import config_of

    return config_of(ds)


def draw_mechanism(ds, i=0, ax=None, artists=None, config=None, legend=True):
    """Draw (or update) the slider-crank at time sample ``i``, to scale in the fixed plane.

    The crank, the link (its deflection is drawn true, so invisibly small), the collar block on
    the vertical guide at ``X = a`` and the slider. Axes ``X``, ``Y`` [m], equal scales.

    Parameters
    ----------
    ds : xarray.Dataset
        Results of a slider-crank run (``u2``, ``x_star``; the configuration
        is read from ``attrs["config"]``).
    i : int
        Time sample.
    artists : dict, optional
        Returned by an earlier call on the same axes: updated in place.
    config : lubelink.Config, optional
        The run's configuration (default: parsed from ``ds.attrs["config"]``).
    legend : bool
        Draw a legend above the axes.

    Returns
    -------
    dict
        The Matplotlib artists, for :func:`animate_mechanism`.
    """
    from matplotlib.patches import Polygon

    cfg = _config(ds, config)
    g = _mechanism_geometry(ds, i, cfg)
    pin, e_i, e_j = g["pin"], g["e_i"], g["e_j"]
    m, fm = cfg.mechanism, cfg.film
    a0, a1 = g["x0"], g["x0"] + fm.pad_length
    half = 0.5 * fm.clearance + COLLAR_DEPTH
    collar = np.array([pin + a0 * e_i - half * e_j, pin + a1 * e_i - half * e_j,
                       pin + a1 * e_i + half * e_j, pin + a0 * e_i + half * e_j])
    slider_box = g["slider"] + np.array([[-0.04, -0.02], [0.04, -0.02], [0.04, 0.02], [-0.04, 0.02]])
    if artists is None:
        ax = _ax(ax)
        a = {}
        span = (-0.12, m.crank_length + m.rod_length + 0.08)
        reach = 1.6 * m.crank_length
        ax.plot(span, [-0.02, -0.02], color="0.5", lw=1.0, label="slider's track")
        ax.plot([m.guide_distance] * 2, [-reach, reach], color="0.5", lw=1.0, ls="--",
                label=f"collar's guide, X = a = {m.guide_distance:g} m")
        ax.plot([0.0], [0.0], "ko", ms=4)
        a["crank"], = ax.plot([0.0, pin[0]], [0.0, pin[1]], color="k", lw=3, label="crank OA")
        a["rod"], = ax.plot(g["rod"][:, 0], g["rod"][:, 1], color="C0", lw=2.0, label="link (to scale)")
        a["collar"] = ax.add_patch(Polygon(collar, closed=True, color="C1", alpha=0.9, label="collar"))
        a["slider"] = ax.add_patch(Polygon(slider_box, closed=True, color="0.4", label="slider"))
        ax.set_aspect("equal")
        ax.set_xlim(*span)
        ax.set_ylim(-reach, reach)
        ax.set_xlabel("X [m]")
        ax.set_ylabel("Y [m]")
        if legend:
            _legend(ax, 3)
        return a
    artists["crank"].set_data([0.0, pin[0]], [0.0, pin[1]])
    artists["rod"].set_data(g["rod"][:, 0], g["rod"][:, 1])
    artists["collar"].set_xy(collar)
    artists["slider"].set_xy(slider_box)
    return artists


def draw_link_view(ds, i=0, ax=None, artists=None, config=None, legend=True):
    """Draw (or update) the link in its own frame at time sample ``i``: ``u2`` [mm] against ``x`` [m].

    The collar faces are drawn at ``+H/2`` (and ``-H/2`` for a two-sided collar) over the pad
    ``[x0, x0 + l]``, where the film is ``H/2 - u2`` (``H/2 + u2``), so the gap is read off
    directly. A dry joint without a contact law has faces that constrain nothing (dashed).

    Parameters
    ----------
    ds, i, artists, config, legend
        As for :func:`draw_mechanism`.

    Returns
    -------
    dict
        The Matplotlib artists.
    """
    cfg = _config(ds, config)
    fm = cfg.film
    x = ds.x.values
    x_star = float(ds.x_star.values[i])
    x0 = x_star - 0.5 * fm.pad_length if fm.pad_reference == "centre" else x_star
    pad = [x0, x0 + fm.pad_length]
    face = 0.5 * fm.clearance * MM
    sides = (1, -1) if getattr(fm, "sides", 1) == 2 else (1,)
    acts = fm.enabled or cfg.contact.law != "none"
    t = float(ds.time.values[i])
    if artists is None:
        ax = _ax(ax)
        a = {}
        top = max(1.35 * face, 1.1 * float(np.nanmax(np.abs(ds.u2.values))) * MM)
        ax.axhline(0.0, color="0.6", lw=0.8, ls=":", label="undeformed link")
        a["link"], = ax.plot(x, ds.u2.values[i] * MM, color="C0", lw=2.0, label="link deflection u2(x, t)")
        what = "collar face (film)" if fm.enabled else "collar face (contact)" if acts else \
            "collar face (dry joint, no contact law: not a constraint)"
        for k, side in enumerate(sides):
            a[f"face{k}"], = ax.plot(pad, [side * face] * 2, color="C1", lw=3.0, ls="-" if acts else "--",
                                     solid_capstyle="butt", label=what if k == 0 else None)
            a[f"body{k}"] = ax.fill_between(pad, side * face, side * top, color="C1", alpha=0.25, lw=0)
        a["time"] = ax.text(0.99, 0.04, f"t = {t:.3f} s", transform=ax.transAxes, ha="right", va="bottom")
        ax.set_xlim(float(x[0]), float(x[-1]))
        ax.set_ylim(-top, top)
        ax.set_xlabel("position along the link x [m]")
        ax.set_ylabel("deflection u2 [mm]")
        if legend:
            _legend(ax, 3)
        return a
    artists["link"].set_ydata(ds.u2.values[i] * MM)
    ax = artists["link"].axes
    top = ax.get_ylim()[1]
    for k, side in enumerate(sides):
        artists[f"face{k}"].set_xdata(pad)
        artists[f"body{k}"].remove()
        artists[f"body{k}"] = ax.fill_between(pad, side * face, side * top, color="C1", alpha=0.25, lw=0)
    artists["time"].set_text(f"t = {t:.3f} s")
    return artists


def animate_mechanism(ds, fps=20, frames=None, size=(7.0, 5.2), dpi=80):
    """Animation of the mechanism over the samples of ``ds``: the fixed plane above, the link below.

    Parameters
    ----------
    ds : xarray.Dataset
        Results of a slider-crank run; every time sample is a frame unless
        ``frames`` selects some.
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
        top = fig.add_axes((0.1, 0.6, 0.88, 0.28))
        bottom = fig.add_axes((0.1, 0.09, 0.88, 0.36))
        for ax in (top, bottom):
            ax.grid(False)
        config = _config(ds, None)
        plane = draw_mechanism(ds, frames[0], top, config=config)
        link = draw_link_view(ds, frames[0], bottom, config=config)

    def update(i):
        draw_mechanism(ds, i, artists=plane, config=config)
        draw_link_view(ds, i, artists=link, config=config)
        return list(plane.values()) + list(link.values())

    anim = FuncAnimation(fig, update, frames=frames, interval=1000.0 / fps, blit=False)
    return fig, anim

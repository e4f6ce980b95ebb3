"""The mechanism itself: the slider-crank drawn at one time sample, and animated.

Lengths in the fixed frame [m]; the deflection and the clearance are
magnified by ``scale``.
"""

from __future__ import annotations

import numpy as np

from ._style import STYLE, _ax

__all__ = ["draw_mechanism", "animate_mechanism"]


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

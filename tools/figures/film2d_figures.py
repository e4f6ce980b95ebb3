"""Draw the figures of docs/film2d.md and print its tables: the film of finite width.

    PYTHONPATH=src python tools/figures/film2d_figures.py [OUTDIR]      # default docs/figures; about a minute

* ``film2d-maps.png``: pressure maps (X by Z) of one film of the ``paper`` run for three widths,
  full solution and Swift-Stieber, by :func:`lubelink.film.pressure_2d`;
* ``film2d-force.png``: the film force of that film over ``B / l`` from 0.1 to 10 for the 1-D film,
  the short bearing and the 2-D film (the sine series of the model, and ``pressure_2d``);
* ``film2d-fig7.png``: the paper's Fig. 7 question (does the film lower the peak deflection?) with
  the 1-D, short and 2-D films, wedge and wedge+squeeze; the peaks and the Fig. 9 question (first
  impact of ``paper-impact``) are printed as Markdown tables.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

import lubelink
from lubelink.film import pressure, pressure_2d, width_pressure
from lubelink.results import atomic_path

FILMS = ("1d", "short", "2d")
COLOURS = {"1d": "C0", "short": "C1", "2d": "C2", "dry": "k"}


def _save(fig, path):
    """Write a figure atomically (the project's writer)."""
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110)
    print(f"wrote {path}")


def paper_film(ds, suction=False):
    """The film ``xi(X)`` [m], its rate [m/s] and ``V_r`` [m/s] of ``ds`` (a ``paper`` run) at its peak film
    force, or (``suction``) where its pressure is lowest."""
    cfg = lubelink.results.config_of(ds)
    i = int(np.argmin(ds.pressure.values.min(axis=1)) if suction else np.argmax(np.abs(ds.film_force.values)))
    q, q_dot = ds.q.values[i], ds.q_dot.values[i]
    x0, V_r = float(ds.x_star.values[i]), float(ds.V_r.values[i])
    beta = np.arange(1, q.size + 1) * np.pi / cfg.mechanism.rod_length
    H = cfg.film.clearance

    def xi(X):
        return 0.5 * H - np.sin(np.multiply.outer(x0 + np.asarray(X), beta)) @ q

    def xi_t(X):
        return -(np.sin(np.multiply.outer(x0 + np.asarray(X), beta)) @ q_dot)

    return xi, xi_t, V_r, float(ds.time.values[i]), cfg


def maps(ds, out):
    import matplotlib.pyplot as plt

    peak, suction = paper_film(ds), paper_film(ds, suction=True)
    cfg = peak[4]
    l, mu = cfg.film.pad_length, cfg.film.viscosity
    print(f"maps: peak force at t = {peak[3]:.4f} s, lowest pressure at t = {suction[3]:.4f} s")
    cases = [(0.2, "none", peak), (1.0, "none", peak), (5.0, "none", peak), (1.0, "none", suction),
             (1.0, "reynolds", suction)]
    fig, axes = plt.subplots(1, len(cases), figsize=(19, 3.6), constrained_layout=True)
    X = np.linspace(0, l, 161)
    for ax, (ratio, cav, (xi, xi_t, V_r, t, _)) in zip(axes, cases):
        B = ratio * l
        Z = np.linspace(-B / 2, B / 2, 81)
        p = pressure_2d(X, Z, xi(X)[:, None], V_r, mu, xi_t=xi_t(X)[:, None], cavitation=cav, p_cav=-2e3)
        lim = np.abs(p).max()
        im = ax.pcolormesh(X * 1e3, Z * 1e3, p.T, cmap="RdBu_r", vmin=-lim, vmax=lim, shading="gouraud")
        ax.contour(X * 1e3, Z * 1e3, p.T, levels=8, colors="k", linewidths=0.4)
        ax.set_aspect("equal" if ratio <= 1 else "auto")
        ax.set_xlabel("X [mm]")
        ax.set_ylabel("Z [mm]")
        ax.set_title(f"t = {t:.4f} s, B/l = {ratio:g}" + (", Swift-Stieber" if cav == "reynolds"
                                                          else ""), fontsize=9)
        fig.colorbar(im, ax=ax, label="gauge pressure [Pa]", shrink=0.8)
    _save(fig, out / "film2d-maps.png")
    plt.close(fig)


def force_over_width(xi, xi_t, V_r, cfg, out):
    import matplotlib.pyplot as plt

    l, mu = cfg.film.pad_length, cfg.film.viscosity
    ratios = np.geomspace(0.1, 10, 21)
    X = np.linspace(0, l, 401)
    p1 = np.trapezoid(pressure(X, xi, V_r, mu, xi_t=xi_t), X)  # per unit width [N/m]
    force = {f: [] for f in FILMS}
    check = []
    for r in ratios:
        B = r * l
        force["1d"].append(B * p1)
        for f in ("short", "2d"):
            g, P, _ = width_pressure(xi, V_r, mu, B, l, xi_t=xi_t, reynolds=f, grid_points=401)
            force[f].append(np.trapezoid(P, g))
        if r in ratios[::5]:
            Xc, Z = np.linspace(0, l, 201), np.linspace(-B / 2, B / 2, 81)
            p = pressure_2d(Xc, Z, xi(Xc)[:, None], V_r, mu, xi_t=xi_t(Xc)[:, None])
            check.append(np.trapezoid(np.trapezoid(p, Z, axis=1), Xc))
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4), constrained_layout=True)
    for f in FILMS:
        ax.loglog(ratios, np.abs(force[f]), color=COLOURS[f], label=f"film.reynolds = '{f}'")
        bx.semilogx(ratios, np.array(force[f]) / np.array(force["1d"]), color=COLOURS[f])
    ax.loglog(ratios[::5], np.abs(check), "o", mfc="none", color="C2", label="pressure_2d (finite volumes)")
    ax.axvline(0.2, color="0.6", ls=":")
    bx.axvline(0.2, color="0.6", ls=":")
    ax.set_xlabel("B / l")
    ax.set_ylabel("|film force| [N]")
    ax.legend(fontsize=8)
    bx.set_xlabel("B / l")
    bx.set_ylabel("film force / 1-D film force")
    bx.set_ylim(0, 1.5)
    _save(fig, out / "film2d-force.png")
    plt.close(fig)
    return ratios, force


def fig7(out):
    import matplotlib.pyplot as plt

    rows = []
    runs = {}
    dry = lubelink.simulate("paper-dry")
    peak_dry = float(np.abs(dry.u2_mid).max())
    for model in ("wedge", "wedge+squeeze"):
        for f in FILMS:
            began = time.perf_counter()
            ds = lubelink.simulate("paper", set={"film.reynolds": f, "film.model": model})
            wall = time.perf_counter() - began
            peak = float(np.abs(ds.u2_mid).max())
            below = float(np.mean(np.abs(ds.u2_mid.values) <= np.abs(dry.u2_mid.values)))
            rows.append((model, f, peak, 100 * (peak / peak_dry - 1), 100 * below,
                         float(np.abs(ds.film_force).max()), float(ds.pressure.max()), ds.attrs["nfev"], wall))
            runs[model, f] = ds
    fig, axes = plt.subplots(2, 1, figsize=(9, 6), sharex=True, constrained_layout=True)
    for ax, model in zip(axes, ("wedge", "wedge+squeeze")):
        ax.plot(dry.time, dry.u2_mid * 1e3, color="k", lw=0.8, label="dry")
        for f in FILMS:
            ds = runs[model, f]
            ax.plot(ds.time, ds.u2_mid * 1e3, color=COLOURS[f], lw=0.8, label=f"{model}, {f}")
        ax.set_ylabel("u2 at midpoint [mm]")
        ax.legend(fontsize=8, ncol=4)
    axes[-1].set_xlabel("t [s]")
    _save(fig, out / "film2d-fig7.png")
    plt.close(fig)
    print(f"\ndry peak |u2_mid| = {peak_dry * 1e3:.4f} mm\n")
    print("| film.model | film.reynolds | peak [mm] | change vs dry | time below dry | peak force [N] "
          "| peak pressure [Pa] | rhs evaluations | wall [s] |")
    print("|---|---|---|---|---|---|---|---|---|")
    for model, f, peak, change, below, force, p_max, nfev, wall in rows:
        print(f"| {model} | {f} | {peak * 1e3:.4f} | {change:+.2f} % | {below:.0f} % | {force:.4g} | {p_max:.4g} "
              f"| {nfev} | {wall:.2f} |")


def fig9():
    print("\n| film.reynolds | impacts | first impact [s] | status |")
    print("|---|---|---|---|")
    for f in FILMS:
        ds = lubelink.simulate("paper-impact", set={"film.reynolds": f})
        first = f"{float(ds.impact_time[0]):.4f}" if ds.impact.size else "none"
        print(f"| {f} | {ds.impact.size} | {first} | {ds.attrs['status']} |")


def main(argv):
    out = Path(argv[0]) if argv else Path(__file__).resolve().parents[2] / "docs" / "figures"
    out.mkdir(parents=True, exist_ok=True)
    ds = lubelink.simulate("paper", set={"film.model": "wedge+squeeze"})
    xi, xi_t, V_r, t, cfg = paper_film(ds)
    print(f"film of the wedge+squeeze paper run at t = {t:.4f} s (peak film force), V_r = {V_r:.4f} m/s, "
          f"xi from {xi(np.linspace(0, cfg.film.pad_length, 101)).min() * 1e3:.4f} mm")
    maps(ds, out)
    ratios, force = force_over_width(xi, xi_t, V_r, cfg, out)
    print("\n| B / l | 1-D [N] | short [N] | 2-D [N] | 2-D / 1-D |")
    print("|---|---|---|---|---|")
    for i in range(0, ratios.size, 5):
        print(f"| {ratios[i]:.3g} | {force['1d'][i]:.4g} | {force['short'][i]:.4g} | {force['2d'][i]:.4g} "
              f"| {force['2d'][i] / force['1d'][i]:.3f} |")
    fig7(out)
    fig9()


if __name__ == "__main__":
    main(sys.argv[1:])

"""Draw the branch map of docs/paper.md: Fig. 9's first-impact time over the clearance and the pad length.

    python docs/branch_map.py [OUTDIR] [--recompute]     # default docs/figures

The maps (:func:`lubelink.paper.branch_map`, the paper's model: wedge film, no cavitation) are
written beside the figure as ``fig9-branch-map-<N>mode.nc`` (local files: ``*.nc`` is not in git)
and reused unless ``--recompute`` is given (1 mode and its zoom: 13,884 runs, 12 min; 5 modes:
3,168 runs, 19 min; one process, measured at ``nice -n 19`` on 2 shared cores).
The windows found (clearance intervals whose first impact is within 2 ms of 1.273 s) are also
written as ``fig9-windows.csv``. Everything is written atomically.
"""

from __future__ import annotations

import csv
import io
import sys
import time
from pathlib import Path

import numpy as np

from lubelink._files import atomic_path
from lubelink.paper.branches import branch_map, phase_refine, widest_window

TARGET, TOL, PERIOD = 1.273, 2e-3, 0.2
#: the maps: (name, overrides, pad lengths [m], clearances [m], last time searched [s])
MAPS = [
    ("1mode", {"beam.modes": 1, "film.viscosity": 0.014}, np.round(np.arange(0.05, 0.2001, 0.01), 4),
     np.round(np.arange(3.0e-3, 6.5e-3, 1e-5), 9), 2.0),
    # around the widest window of the 1-mode map: finer in pad length and clearance
    ("1mode-zoom", {"beam.modes": 1, "film.viscosity": 0.014}, np.round(np.arange(0.112, 0.1281, 0.002), 4),
     np.round(np.arange(5.30e-3, 5.70e-3, 5e-6), 9), 2.0),
    # 5 modes cost 10 times more a run: coarser, and searched up to 1.4 s only
    ("5mode", {"beam.modes": 5, "film.viscosity": 0.02}, np.round(np.arange(0.05, 0.1501, 0.025), 4),
     np.round(np.arange(3.5e-3, 6.0e-3, 2e-5), 9), 1.4),
]
SEARCH = dict(dx=2.5e-7, refine=phase_refine(TARGET, PERIOD, 0.01))


def compute(name, settings, pads, clearances, t_stop, out):
    import xarray as xr

    path = out / f"fig9-branch-map-{name}.nc"
    began = time.perf_counter()

    def progress(pad, n):
        print(f"  {name}: pad {pad * 1e3:.0f} mm, {n} runs, {time.perf_counter() - began:.0f} s", flush=True)

    ds = branch_map(pads, clearances, set=settings, target=TARGET, tol=TOL, t_stop=t_stop, progress=progress,
                    **SEARCH)
    ds.attrs["wall_time"] = time.perf_counter() - began
    with atomic_path(path) as tmp:
        ds.to_netcdf(tmp, engine="netcdf4")
    return xr.load_dataset(path, engine="netcdf4")


def load_or_compute(name, settings, pads, clearances, t_stop, out, recompute):
    import xarray as xr

    path = out / f"fig9-branch-map-{name}.nc"
    if path.is_file() and not recompute:
        return xr.load_dataset(path, engine="netcdf4")
    return compute(name, settings, pads, clearances, t_stop, out)


def write_windows(maps, path):
    rows = []
    for name, ds in maps.items():
        for k in range(ds.sizes.get("window", 0)):
            rows.append({"map": name, "modes": int(ds.attrs["modes"]), "viscosity": float(ds.attrs["viscosity"]),
                         "pad_length": float(ds.window_pad_length[k]),
                         **{v: (str(ds[v].values[k]) if v.endswith("exit") else float(ds[v].values[k]))
                            for v in ("lo", "hi", "width", "centre", "first_impact_centre", "lo_exit", "hi_exit",
                                      "branch_lo", "branch_hi", "margin")}})
    rows.sort(key=lambda r: -r["width"])
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(rows[0]) if rows else ["map"])
    w.writeheader()
    w.writerows(rows)
    with atomic_path(path) as tmp:
        tmp.write_text(buf.getvalue(), encoding="utf-8")
    return rows


def figure(maps, best):
    import matplotlib.pyplot as plt
    from matplotlib.colors import BoundaryNorm, ListedColormap

    from lubelink.plots._style import _figure, _style

    import lubelink

    scenario = lubelink.resolve_config("paper-impact")

    def mine(ds):
        """Whether the map is of the scenario's settings and holds its pad length."""
        pads = ds.pad_length.values
        return (int(ds.attrs["modes"]) == scenario.beam.modes and np.isclose(ds.attrs["viscosity"], scenario.film.viscosity)
                and bool(np.any(np.isclose(pads, scenario.film.pad_length))))

    with _style():
        fig = _figure(11.0, 4.0 * len(maps))
        axes = fig.subplots(len(maps), 2, width_ratios=[3, 1], squeeze=False)
        colours = ListedColormap(list(plt.get_cmap("tab10").colors) + [(0.85, 0.85, 0.85)])
        norm = BoundaryNorm(np.arange(-0.5, 11.0, 1.0), colours.N)
        for (name, ds), (ax, side) in zip(maps.items(), axes):
            t1 = ds.first_impact.values
            turn = np.where(np.isfinite(t1), np.floor(t1 / PERIOD), 10)
            H = ds.clearance.values * 1e3
            pads = ds.pad_length.values * 1e3
            mesh = ax.pcolormesh(H, pads, turn, cmap=colours, norm=norm, shading="nearest", rasterized=True)
            wl, wc, ww = ds.window_pad_length.values * 1e3, ds.centre.values * 1e3, ds.width.values * 1e6
            if wl.size:
                ax.scatter(wc, wl, s=8 + 40 * ww / max(ww.max(), 1e-9), facecolors="none", edgecolors="k",
                           lw=1.0, label=f"first impact {TARGET} s +- {TOL * 1e3:.0f} ms (size: width)")
            if best is not None and best[0] is ds:
                k = best[1]
                ax.plot(ds.centre.values[k] * 1e3, wl[k], "^", color="gold", ms=10, mec="k",
                        label="centre of the widest window")
            if mine(ds):
                ax.plot(scenario.film.clearance * 1e3, scenario.film.pad_length * 1e3, "*", color="red", ms=14,
                        mec="k", label="paper-impact")
            ax.set_xlabel("clearance H [mm]")
            ax.set_ylabel("pad length l [mm]")
            ax.set_title(f"{name}: {ds.attrs['modes']} mode{'s' if ds.attrs['modes'] > 1 else ''}, "
                         f"mu = {ds.attrs['viscosity'] * 1e3:g} mPa s, searched to {ds.attrs['t_stop']:g} s: "
                         "crank turn of the first impact", fontsize=9)
            ax.legend(loc="upper left", fontsize=7)
            cb = fig.colorbar(mesh, ax=ax, ticks=range(11), pad=0.01)
            cb.ax.set_yticklabels([str(i + 1) for i in range(10)] + ["none"], fontsize=7)
            cb.set_label("turn (1.273 s: turn 7)")
            for pad in pads:
                sel = wl == pad
                side.plot(np.full(sel.sum(), pad), ww[sel], "o", color="C0", ms=3)
            if best is not None and best[0] is ds:
                side.plot(wl[best[1]], ww[best[1]], "^", color="gold", ms=10, mec="k")
            if mine(ds):
                k = np.flatnonzero((ds.lo.values <= scenario.film.clearance) & (scenario.film.clearance <= ds.hi.values)
                                   & np.isclose(wl, scenario.film.pad_length * 1e3))
                side.plot(wl[k], ww[k], "*", color="red", ms=12, mec="k")
            side.set_xlabel("pad length l [mm]")
            side.set_ylabel("window width [um]")
            side.set_title("windows at 1.273 s", fontsize=9)
        fig.suptitle("Fig. 9 of the paper's model: when the film first breaks down (wedge film, no cavitation)")
    return fig


def main(out="docs/figures", recompute=False):
    import matplotlib

    matplotlib.use("Agg")
    out = Path(out)
    maps = {m[0]: load_or_compute(*m, out, recompute) for m in MAPS}
    rows = write_windows(maps, out / "fig9-windows.csv")
    best = widest_window(list(maps.values()))
    for r in rows[:10]:
        print(f"{r['map']}: l = {r['pad_length'] * 1e3:.0f} mm, H = [{r['lo'] * 1e3:.7f}, {r['hi'] * 1e3:.7f}] mm, "
              f"width {r['width'] * 1e9:.0f} nm ({r['lo_exit']}/{r['hi_exit']}), centre {r['centre'] * 1e3:.7f} mm "
              f"-> {r['first_impact_centre']:.6f} s; branch [{r['branch_lo'] * 1e3:.7f}, {r['branch_hi'] * 1e3:.7f}] mm")
    for name, ds in maps.items():
        print(f"{name}: {ds.attrs['runs']} runs, {ds.attrs.get('wall_time', float('nan')):.0f} s")
    fig = figure(maps, best)
    with atomic_path(out / "fig9-branch-map.png") as tmp:
        fig.savefig(tmp, dpi=100)


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    main(*(args[:1] or ["docs/figures"]), recompute="--recompute" in sys.argv)

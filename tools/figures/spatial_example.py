"""The spatial link's example: the ``spatial-slider-crank`` scenario, both bending directions (docs/spatial.md).

Runs ``lubelink.simulate`` with ``beam.model = "spatial"``: first the planar case (the paper's
mechanism, dry, against the planar model), then the scenario (crank axis tilted 0.2 rad about the
slider line, slider line 5 cm out of the plane, wedge film on the ``u2`` faces). Writes
docs/figures/spatial-rssp.png and prints the figures quoted in docs/spatial.md.

    PYTHONPATH=src python tools/figures/spatial_example.py [--t-end 0.5]
"""

import argparse
from pathlib import Path

import numpy as np

import lubelink

TIGHT = {"solver.rtol": 1e-10, "solver.atol": 1e-14}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--t-end", type=float, default=0.5)
    ap.add_argument("-o", default=str(Path(__file__).resolve().parents[2] / "docs" / "figures" / "spatial-rssp.png"))
    args = ap.parse_args()
    over = {"beam.modes": 3, "solver.t_end": args.t_end, **TIGHT}
    planar = lubelink.simulate("paper-dry", set=over)
    sp = lubelink.simulate("paper-dry", set={**over, "beam.model": "spatial"})
    print(f"planar case: max |u3| = {np.max(np.abs(sp.u3.values)):.3g} m, max |u2_mid - planar| = "
          f"{np.max(np.abs(sp.u2_mid.values - planar.u2_mid.values)):.3g} m "
          f"(peak {np.max(np.abs(planar.u2_mid.values)):.4g} m), max |u1| = {np.max(np.abs(sp.u1.values)):.3g} m")
    ds = lubelink.simulate("spatial-slider-crank", set={"solver.t_end": args.t_end, **TIGHT})
    dry = lubelink.simulate("spatial-slider-crank", set={"solver.t_end": args.t_end, "film.model": "none", **TIGHT})
    u1_mid = ds.u1.sel(x=0.5, method="nearest")
    print(f"spatial-slider-crank ({ds.attrs['status']}): peak |u2_mid| = {np.max(np.abs(ds.u2_mid.values)):.4g} m, "
          f"peak |u3_mid| = {np.max(np.abs(ds.u3_mid.values)):.4g} m, peak |u1(L/2)| = "
          f"{np.max(np.abs(u1_mid.values)):.3g} m, thinnest film {np.min(ds.film_min.values):.4g} m; dry: peak "
          f"|u2_mid| = {np.max(np.abs(dry.u2_mid.values)):.4g} m, |u3_mid| = {np.max(np.abs(dry.u3_mid.values)):.4g} m")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from lubelink._files import atomic_path

    t = ds.time.values
    fig, ax = plt.subplots(3, 1, figsize=(7, 6), sharex=True)
    for a, u, name in zip(ax, (ds.u2_mid, ds.u3_mid, u1_mid), ("u2 (in the crank's plane)", "u3 (out of it)",
                                                              "u1 (axial)")):
        a.plot(t, 1e3 * u.values)
        a.set_ylabel(f"{name.split()[0]}(L/2) [mm]")
        a.set_title(name, fontsize=9)
    ax[0].plot(t, 1e3 * planar.u2_mid.values, lw=0.8, ls="--", label="planar mechanism (paper-dry)")
    ax[0].legend(fontsize=8, loc="upper right")
    ax[-1].set_xlabel("time [s]")
    fig.suptitle("lubelink run --scenario spatial-slider-crank (RSSP, crank axis tilted 0.2 rad)", fontsize=10)
    fig.tight_layout()
    with atomic_path(args.o, overwrite=True) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    print("wrote", args.o)


if __name__ == "__main__":
    main()

"""Figures of docs/breakdown.md: the paper's model against the `lubricated` scenario.

    PYTHONPATH=src python tools/figures/breakdown_figures.py [OUTDIR]        (default docs/figures)

Writes ``breakdown-deflection.png`` (midpoint deflection of the dry link, the paper's wedge film
and the `lubricated` scenario, with their peaks: Fig. 7's question) and ``breakdown-loads.png``
(load carried by the film and by the asperities, and the contact force, over time, in the
`lubricated` scenario and in a light-oil, small-clearance variant that reaches mixed lubrication). Every
PNG is written atomically. Prints the numbers quoted in docs/breakdown.md.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import lubelink
from lubelink._files import atomic_path

#: A light oil and a small clearance: the full film no longer keeps the link off the collar's
#: asperities (mixed lubrication).
THIN = {"film.viscosity": 5e-4, "film.clearance": 3.0e-3}


def _save(fig, path):
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110)


def peak(ds):
    u = np.abs(ds.u2_mid.values)
    i = int(np.argmax(u))
    return float(u[i]), float(ds.time.values[i])


def main(outdir="docs/figures"):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(outdir)
    runs = {
        "dry (paper-dry)": lubelink.simulate("paper-dry"),
        "wedge film (paper)": lubelink.simulate("paper"),
        "full film, cavitation, rough (lubricated)": lubelink.simulate("lubricated"),
    }
    thin = {"paper, mu = 0.5 mPa s, H = 3 mm": lubelink.simulate("paper", set={**THIN, "contact.law": "restitution"}),
            "lubricated, mu = 0.5 mPa s, H = 3 mm": lubelink.simulate("lubricated", set=THIN)}
    fig, ax = plt.subplots(figsize=(8, 4))
    for name, ds in {**runs, **thin}.items():
        u, t = peak(ds)
        print(f"{name:45s} status {ds.attrs['status']:9s} peak |u2_mid| {1e3 * u:.4f} mm at {t:.4f} s, "
              f"impacts {ds.attrs['impact_count']}")
        ax.plot(ds.time, 1e3 * ds.u2_mid, lw=0.9, label=f"{name}: peak {1e3 * u:.3f} mm")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("u2(L/2) [mm]")
    ax.legend(fontsize=7)
    fig.tight_layout()
    _save(fig, out / "breakdown-deflection.png")
    plt.close(fig)

    fig, axes = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    for ax, (name, ds) in zip(axes, [("lubricated", runs["full film, cavitation, rough (lubricated)"]),
                                     ("lubricated, mu = 0.5 mPa s, H = 3 mm", thin["lubricated, mu = 0.5 mPa s, H = 3 mm"])]):
        ax.plot(ds.time, -ds.film_force, lw=0.9, label="film")
        if "asperity_force" in ds:
            ax.plot(ds.time, -ds.asperity_force, lw=0.9, label="asperities")
            print(f"{name}: peak asperity load {float(-ds.asperity_force.min()):.4g} N, "
                  f"peak film load {float(-ds.film_force.min()):.4g} N")
        if "contact_force" in ds:
            ax.plot(ds.time, ds.contact_force, lw=0.9, label="collar contact (impacts excluded)")
            print(f"{name}: samples in sustained contact {int(ds.contact_phase.sum())}")
        ax.set_ylabel("load on the link, -j [N]")
        ax.set_title(name, fontsize=9)
        ax.legend(fontsize=7)
    axes[-1].set_xlabel("t [s]")
    fig.tight_layout()
    _save(fig, out / "breakdown-loads.png")
    plt.close(fig)


if __name__ == "__main__":
    main(*sys.argv[1:])

"""Convergence in modes at three clearances: the table of docs/model.md section 7.5.

Scenario ``lubricated`` (full film, half-Sommerfeld cavitation near ambient, rough surfaces) with
``contact.law = "compliant"`` at ``film.clearance`` 1 mm, 100 um and 20 um, for N = 3, 7, 15, 31,
63 modes, 0-``--t-end`` s. For each: peak ``|u2_mid|``, the largest deflection at the collar edge
``|u2(x_star)|``, the thinnest film and the peak film force, and each one's difference to the
63-mode run. Writes ``docs/figures/mode-convergence.md`` (a Markdown table) and prints it.

Usage::

    python tools/figures/mode_convergence.py              # about 3 minutes on 2 cores
    python tools/figures/mode_convergence.py --t-end 0.2 --modes 3,7,15 --output /tmp/table.md
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
CLEARANCES = (1e-3, 1e-4, 2e-5)


def measures(ds):
    """``(peak |u2_mid| [um], peak |u2(x_star)| [um], thinnest film [um], peak |film force| [N])``."""
    L = float(ds.x.values[-1])  # the link's length (the deflection's grid spans it)
    n = ds["mode"].values
    u_collar = np.sum(ds.q.values * np.sin(np.outer(ds.x_star.values, n) * np.pi / L), axis=1)
    return (1e6 * float(np.abs(ds.u2_mid).max()), 1e6 * float(np.abs(u_collar).max()),
            1e6 * float(ds.film_min.min()), float(np.abs(ds.film_force).max()))


def main():
    import lubelink

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-end", type=float, default=1.0)
    ap.add_argument("--modes", default="3,7,15,31,63")
    ap.add_argument("--output", default=str(ROOT / "docs" / "figures" / "mode-convergence.md"))
    args = ap.parse_args()
    modes = [int(m) for m in args.modes.split(",")]
    lines = [f"`lubricated`, compliant contact, 0-{args.t_end:g} s; in brackets the difference to {modes[-1]} modes.",
             "",
             "| clearance | N | peak abs u2_mid [um] | peak abs u2(x_star) [um] | thinnest film [um] | "
             "peak film force [N] | method | wall [s] |",
             "|---|---|---|---|---|---|---|---|"]
    for H in CLEARANCES:
        rows = []
        for n in modes:
            t0 = time.perf_counter()
            ds = lubelink.simulate("lubricated", set={"film.clearance": H, "contact.law": "compliant",
                                                      "beam.modes": n, "solver.t_end": args.t_end})
            rows.append((n, measures(ds), ds.attrs["solver_method"], time.perf_counter() - t0, ds.attrs["status"]))
        ref = rows[-1][1]
        for n, m, method, wall, status in rows:
            cells = [f"{v:.4g} ({v - r:+.2g})" for v, r in zip(m, ref)]
            lines.append(f"| {H * 1e6:g} um | {n} | " + " | ".join(cells) + f" | {method}"
                         + ("" if status == "complete" else f", {status}") + f" | {wall:.2f} |")
    text = "\n".join(lines) + "\n"
    out = Path(args.output)
    tmp = out.with_suffix(".tmp")
    tmp.write_text(text, encoding="utf-8")
    tmp.replace(out)
    print(text)


if __name__ == "__main__":
    main()

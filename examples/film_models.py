"""The paper's wedge film against the squeeze film and cavitation, on the paper's mechanism.

Prints the peak midpoint deflection and the peak film force for each film
model over one second. The squeeze term damps the link (its force opposes
the link's velocity); the wedge term alone does not.
"""

import numpy as np

import lubelink


def main(t_end=1.0):
    rows = []
    for label, overrides in [
        ("dry", {"film.model": "none"}),
        ("wedge (paper)", {}),
        ("wedge+squeeze", {"film.model": "wedge+squeeze"}),
        ("wedge+squeeze, half-Sommerfeld", {"film.model": "wedge+squeeze", "film.cavitation": "half-sommerfeld"}),
    ]:
        ds = lubelink.simulate("paper", set={"solver.t_end": t_end, **overrides})
        force = float(np.abs(ds.film_force).max()) if "film_force" in ds else 0.0
        rows.append((label, float(np.abs(ds.u2_mid).max()), force))
    for label, peak, force in rows:
        print(f"{label:32s} peak |u2_mid| {1e3 * peak:7.4f} mm   peak film force {force:8.3f} N")
    return {label: peak for label, peak, _ in rows}


if __name__ == "__main__":
    main()

"""Film models side by side: wedge, squeeze and cavitation, with the crank turning both ways.

Prints the peak midpoint deflection, the peak film force and the status of each run on the
paper's mechanism (docs/model.md §4). With the paper's crank sense the wedge film pushes the link
away from the collar (its pressure is above ambient, docs/paper.md Fig. 8), so a cavitation rule
has nothing to clip in the wedge film; the squeeze film damps the link. Turned the other way,
the wedge pressure is below ambient on the whole pad: without cavitation that suction pulls the
link onto the collar until the film breaks down, while half-Sommerfeld cavitation at ambient
pressure clips it all away and the link moves as if dry. The cavitation pressure is set to the
ambient pressure here (``film.cavitation_pressure = 101325``): with the default of 0 Pa (absolute)
the oil could carry up to one atmosphere of tension before the rule acts.
"""

import numpy as np

import lubelink

P_AM = 101325.0  # [Pa], the default film.ambient_pressure
FILMS = [
    ("dry", {"film.model": "none"}),
    ("wedge (paper)", {}),
    ("wedge, half-Sommerfeld", {"film.cavitation": "half-sommerfeld", "film.cavitation_pressure": P_AM}),
    ("wedge+squeeze", {"film.model": "wedge+squeeze"}),
    ("wedge+squeeze, half-Sommerfeld",
     {"film.model": "wedge+squeeze", "film.cavitation": "half-sommerfeld", "film.cavitation_pressure": P_AM}),
]
SENSES = [("paper's crank sense", 10 * np.pi), ("crank reversed", -10 * np.pi)]


def main(t_end=1.0):
    """Run every film model with both crank senses; ``{(sense, film): (peak [m], force [N], status)}``."""
    rows = {}
    for sense, crank_speed in SENSES:
        for label, overrides in FILMS:
            ds = lubelink.simulate("paper", set={"solver.t_end": t_end, "mechanism.crank_speed": crank_speed,
                                                 **overrides})
            force = float(np.abs(ds.film_force).max()) if "film_force" in ds else 0.0
            rows[sense, label] = (float(np.abs(ds.u2_mid).max()), force, ds.attrs["status"])
    for sense, _ in SENSES:
        print(f"{sense}, 0 - {t_end:g} s:")
        for label, _ in FILMS:
            peak, force, status = rows[sense, label]
            print(f"  {label:32s} peak |u2_mid| {1e3 * peak:7.4f} mm   peak film force {force:8.3f} N   {status}")
    return rows


if __name__ == "__main__":
    main()

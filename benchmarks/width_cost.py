"""Cost of the 2-D film's right-hand side over the pad's aspect ratio ``B / l``, per set of width terms.

    PYTHONPATH=src python benchmarks/width_cost.py [--evaluations 20000]

``paper`` with ``film.reynolds = "2d"`` (``B / l = 0.2``), and with the pad shortened to
``B / l`` = 1, 10, 100 (``beam.width`` = 10 mm stays); the time of one compiled right-hand side
(``model.rhs`` in a compiled loop, median of 5 loops; ``film2d_cost.per_rhs``) for the default
terms and for the sine series of as many terms as it needs there to hold the load within 0.2 % and
the centre line within 0.5 % (``film.width_series = "sine"``; docs/film2d.md). Runs against a
checkout without ``film.width_series`` too (the sine series was its only one). Wall-clock on a
shared machine: compare ratios within one run.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from film2d_cost import _loop, per_rhs  # noqa: E402

from lubelink.params import Film  # noqa: E402

WIDTH = 0.01  # paper's beam.width [m]
#: (B / l, sine terms that hold the load within 0.2 % and the centre line within 0.5 %)
CASES = [(0.2, 8), (1.0, 8), (10.0, 12), (100.0, 48)]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--evaluations", type=int, default=20000)
    args = parser.parse_args()
    many = _loop()
    has_series = "width_series" in Film.__dataclass_fields__
    print("| B / l | terms | one rhs [µs] |")
    print("|---|---|---|")
    for ratio, sine_terms in CASES:
        base = {"film.reynolds": "2d", "film.pad_length": WIDTH / ratio}
        runs = [("default (8)", base)]
        if has_series:
            runs.append((f"sine, {sine_terms}", {**base, "film.width_series": "sine", "film.width_modes": sine_terms}))
        else:
            runs.append((f"sine, {sine_terms}", {**base, "film.width_modes": sine_terms}))
        for name, settings in runs:
            cost = per_rhs(settings, args.evaluations, many)
            print(f"| {ratio:g} | {name} | {cost * 1e6:.2f} |", flush=True)


if __name__ == "__main__":
    main()

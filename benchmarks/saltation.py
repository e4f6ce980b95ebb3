"""The monodromy through impacts: saltation matrices against differences of the period map.

The impacting orbit of tests/test_periodic.py (``paper-impact`` with the film off, ``zeta = 0.05``,
``e = 0.7``, 3 impacts a period) with 1 and 2 modes, and the same with ``contact.law = "compliant"``
(3 compliant contacts a period, 1 mode: each contact's start carries the approach velocity as a
parameter, lubelink.phases), timed warm in turn (median and minimum of ``--repeats``):

1. ``lubelink.periodic(config)`` with ``jacobian="auto"`` (the variational equations between
   impacts and a saltation matrix at each) and with ``"finite-difference"``;
2. the monodromy matrix with its check alone at the periodic state (``PeriodMap(y0, "checked")``;
   ``jacobian="auto"`` then the differences of :meth:`~lubelink.steady.problem.PeriodMap.differences`).

Printed: the times, their ratio, the largest distance between the two sets of multipliers against
the differences' own accuracy estimate, and the product of the moduli against its closed form
``exp(-2 zeta omega_1 T) e^(2 x impacts)`` (one mode: Liouville between impacts, ``det S = e^2``).

Usage::

    python benchmarks/saltation.py               # about half a minute once compiled
    python benchmarks/saltation.py --repeats 21
"""

from __future__ import annotations

import argparse
import math
import statistics
import warnings

import numpy as np

from steady import timed  # the list of wall times of repeated calls (this folder)

IMPACT = {"beam.damping_ratio": 0.05, "film.model": "none", "film.clearance": 3.6e-3, "contact.restitution": 0.7}


def show(label, times):
    print(f"  {label:<44} median {1e3 * statistics.median(times):8.1f} ms   min {1e3 * min(times):8.1f} ms")
    return statistics.median(times)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=9)
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    import lubelink
    from lubelink.config import resolve
    from lubelink.steady import find_periodic

    for modes, law in ((1, "restitution"), (2, "restitution"), (1, "compliant")):
        config = resolve("paper-impact", {**IMPACT, "beam.modes": modes, "contact.law": law})
        auto = find_periodic(config)  # warm-up (compiles)
        fd = find_periodic(config, jacobian="finite-difference")
        pmap = auto.period_map
        impacts = len(pmap.run(auto.y0).impacts)
        print(f"paper-impact, {law}, {modes} mode(s), {impacts} impacts a period, T = {auto.period:.6g} s "
              f"({auto.jacobian} against {fd.jacobian})")
        times = {}
        for name, jac in (("saltation", "auto"), ("differences", "finite-difference")):
            times[name] = show(f"periodic(), {name}", timed(lambda: lubelink.periodic(config, jacobian=jac),
                                                             args.repeats))
        print(f"  ratio differences / saltation: {times['differences'] / times['saltation']:.2f}")

        def monodromy_saltation():
            pmap._last = None
            return pmap(auto.y0, "checked")

        t_s = show("monodromy + check, saltation", timed(monodromy_saltation, args.repeats))
        t_d = show("monodromy + check, differences", timed(lambda: pmap.differences(auto.y0, True), args.repeats))
        print(f"  ratio differences / saltation: {t_d / t_s:.2f}")
        M_fd, count, check = pmap.differences(auto.y0, True)
        mu_s = np.sort_complex(auto.multipliers)
        mu_d = np.sort_complex(np.linalg.eigvals(M_fd))
        estimate = np.max(np.abs(np.sort_complex(np.linalg.eigvals(check)) - mu_d))
        print(f"  multipliers (saltation): {np.array2string(np.abs(mu_s), precision=9)}")
        print(f"  |mu_saltation - mu_differences| max {np.max(np.abs(mu_s - mu_d)):.2e} (differences' estimate "
              f"{estimate:.2e}, {count} runs; saltation's estimate {np.max(auto.multiplier_errors):.2e})")
        if modes == 1 and law == "restitution":
            e, zeta, w1 = IMPACT["contact.restitution"], IMPACT["beam.damping_ratio"], pmap.model.omega_n[0]
            exact = math.exp(-2 * zeta * w1 * auto.period) * e ** (2 * impacts)
            for name, mu in (("saltation", mu_s), ("differences", mu_d)):
                print(f"  prod |mu| / closed form - 1, {name}: {np.prod(np.abs(mu)) / exact - 1:.2e}")


if __name__ == "__main__":
    main()

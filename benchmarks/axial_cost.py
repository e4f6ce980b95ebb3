"""What makes ``beam.axial_force = "inertial"`` cost the exponential-Adams method steps (docs/model.md §1.5).

``paper-dry`` with 5 modes on the NumPy backend (so that the geometric stiffness's load,
``lubelink.link.axial.geometric_load``, can be replaced from Python), with the stiffness ``K(t)`` of the axial
force as it is, left out, replaced by its period mean as a constant, by that mean plus a constant diagonal, or by
its diagonal or its off-diagonal part alone. Printed: the right-hand sides each run takes (``nfev``).

With ``--scenarios``: what the axial force costs each built-in scenario, warm ``simulate()`` with
``beam.axial_force = "none"`` and ``"inertial"`` timed in turn (A B A B ...), the minimum and the median of
``--repeats`` pairs, their ratio and the right-hand sides of each.

    python benchmarks/axial_cost.py                          # a minute or two
    python benchmarks/axial_cost.py --scenarios --repeats 5  # several minutes (guide, guide-mixed are stiff)
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import lubelink
from lubelink.link import axial
from lubelink.link.kinematics import pin_axial_acceleration, slider_crank

MODES, L, RHO_A = 5, 1.0, 0.765


def mean_stiffness():
    """``K`` [N/m] of the axial force's terms averaged over a crank turn (256 samples), ``paper-dry``."""
    cfg = lubelink.config.resolve("paper-dry", {"beam.modes": MODES})
    m = cfg.mechanism
    t = np.linspace(0.0, 2 * np.pi / m.crank_speed, 257)[:-1]
    k = slider_crank(t, m.crank_length, L, m.crank_speed, m.guide_distance)
    terms = np.zeros(3)
    for i in range(t.size):
        angle = -k["theta"][i]
        A1 = pin_axial_acceleration(t[i], angle, m.crank_length, m.crank_speed)
        terms += axial.rigid_axial_force(A1, k["A_O2"][i], k["omega"][i], k["alpha"][i], angle, 0.0, k["x_star"][i],
                                         (0.0, 0.0), RHO_A, L)
    return axial.geometric_stiffness(axial.slope_moments(MODES, L), terms / t.size)


def variant(name, K_mean):
    """The replacement of ``geometric_load`` for ``name`` (None: the model's own)."""
    def load(moments, c0, c1, c2, q, F):
        K = c0 * moments[0] + c1 * moments[1] + c2 * moments[2]
        K = {"none": 0.0 * K, "diagonal": np.diag(np.diag(K)), "off-diagonal": K - np.diag(np.diag(K)),
             "mean": K_mean, "mean + 700 N/m": K_mean + 700.0 * np.eye(q.shape[0])}[name]
        F -= K @ q
    return None if name == "as it is" else load


def main():
    import lubelink.config  # noqa: F401

    own = axial.geometric_load
    K_mean = mean_stiffness()
    print(f"period mean of K_nn / m [1/s^2]: {np.round(np.diag(K_mean) / (RHO_A * L / 2), 2)}")
    for name in ("as it is", "none", "mean", "mean + 700 N/m", "diagonal", "off-diagonal"):
        axial.geometric_load = variant(name, K_mean) or own
        ds = lubelink.simulate("paper-dry", {"beam.modes": MODES, "beam.axial_force": "inertial",
                                             "solver.backend": "numpy"})
        print(f"  K {name:15}: nfev {ds.attrs['nfev']:5d} ({ds.attrs['solver_method']}, {ds.attrs['status']})")
    axial.geometric_load = own
    ds = lubelink.simulate("paper-dry", {"beam.modes": MODES, "solver.backend": "numpy"})
    print(f"  beam.axial_force = 'none': nfev {ds.attrs['nfev']}")


def scenarios(repeats, only=None):
    """The table of ``--scenarios``: per built-in scenario, ``simulate()`` with the axial force off and on."""
    from lubelink.scenarios import SCENARIOS

    print(f"warm simulate(), {repeats} pairs timed in turn; ms min / median")
    print(f"{'scenario':22} {'none':>17} {'inertial':>17} {'ratio':>6} {'nfev none':>10} {'nfev inertial':>14}")
    for name in only or SCENARIOS:
        times, nfev = {"none": [], "inertial": []}, {}
        for k in range(repeats + 1):  # the first pair warms up (compiles, fills caches)
            for force in ("none", "inertial"):
                start = time.perf_counter()
                ds = lubelink.simulate(name, {"beam.axial_force": force})
                if k:
                    times[force].append(time.perf_counter() - start)
                nfev[force] = (ds.attrs["nfev"], ds.attrs["status"])
        lo = {f: 1e3 * min(v) for f, v in times.items()}
        med = {f: 1e3 * float(np.median(v)) for f, v in times.items()}
        print(f"{name:22} {lo['none']:7.1f} / {med['none']:7.1f} {lo['inertial']:7.1f} / {med['inertial']:7.1f} "
              f"{med['inertial'] / med['none']:6.2f} {nfev['none'][0]:10d} {nfev['inertial'][0]:14d}"
              + ("" if nfev["none"][1] == nfev["inertial"][1] == "complete" else f"  {nfev}"))


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenarios", action="store_true", help="the cost per built-in scenario")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--only", help="comma-separated scenarios (with --scenarios)")
    args = parser.parse_args()
    if args.scenarios:
        scenarios(args.repeats, args.only.split(",") if args.only else None)
    else:
        main()

"""The periodic steady state's cost beside one ``simulate()``: ``periodic("paper")`` and a response curve.

Timed in one process, warm, in turn (so that a change of the machine's load moves all alike):

1. ``lubelink.simulate("paper")``: 2 s of the paper's mechanism, the yardstick;
2. ``lubelink.periodic("paper")``: shooting from rest (Newton's steps, the monodromy matrix and its
   check, one period sampled into a Dataset);
3. ``lubelink.continuation("paper", set={"beam.damping_ratio": 0.01}, start=5, stop=60)``: the
   response curve of docs/periodic.md (it ends at 58.24 rad/s, where the film closes), and
   ``paper-dry`` without damping from 5 to 60 rad/s (issue 36: no bifurcation but at resonances,
   no orbit called stable).

Printed: medians (and minima) in ms, the ratios to ``simulate("paper")`` measured in the same run,
the branch's points, its time per point, its bifurcations and how it ended, and the accuracy of the
multipliers (the largest ``||mu| - 1|`` of the undamped branch against the largest estimate).
Issue 36's targets: ``periodic("paper") <= 20 ms`` and a 100-point curve ``<= 5 s`` when
``simulate("paper")`` takes 7 ms, i.e. at most about 2.9x and 710x one ``simulate("paper")``.

Usage::

    python benchmarks/steady.py                  # about a minute
    python benchmarks/steady.py --repeats 21 --no-branch
"""

from __future__ import annotations

import argparse
import os
import statistics
import time


def timed(f, repeats):
    times = []
    for _ in range(repeats):
        began = time.perf_counter()
        f()
        times.append(time.perf_counter() - began)
    return times


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=11, help="timings of simulate and periodic (default 11)")
    parser.add_argument("--no-branch", action="store_true", help="skip the response curves")
    args = parser.parse_args()

    import numpy as np

    import lubelink

    lubelink.simulate("paper")
    lubelink.periodic("paper")  # compiles (first run) and warms
    sim, per = [], []
    for _ in range(args.repeats):  # in turn
        sim += timed(lambda: lubelink.simulate("paper"), 1)
        per += timed(lambda: lubelink.periodic("paper"), 1)
    ds = lubelink.periodic("paper")
    s_med, p_med = statistics.median(sim), statistics.median(per)
    print(f"load average {os.getloadavg()[0]:.2f}")
    print(f"simulate('paper')      median {1e3 * s_med:7.2f} ms  min {1e3 * min(sim):7.2f} ms")
    print(f"periodic('paper')      median {1e3 * p_med:7.2f} ms  min {1e3 * min(per):7.2f} ms  "
          f"= {p_med / s_med:.2f}x simulate (target <= 2.9x: 20 ms at 7 ms)")
    print(f"  {ds.attrs['iterations']} Newton steps, {ds.attrs['map_evaluations']} periods integrated, monodromy "
          f"{ds.attrs['jacobian']}, |mu| {ds.floquet_modulus.values}, estimates "
          f"{ds.floquet_error.values if 'floquet_error' in ds else '(none: an older checkout)'}")
    if args.no_branch:
        return
    cases = [("paper, zeta 0.01", "paper", {"beam.damping_ratio": 0.01}),
             ("paper-dry, undamped", "paper-dry", {"beam.damping_ratio": 0.0})]
    for label, source, settings in cases:
        began = time.perf_counter()
        b = lubelink.continuation(source, set=settings, start=5.0, stop=60.0)
        wall = time.perf_counter() - began
        ref = statistics.median(timed(lambda: lubelink.simulate("paper"), 5))
        n = b.sizes["point"]
        print(f"continuation {label}, 5 -> 60 rad/s: {wall:.2f} s, {n} points, {1e3 * wall / n:.1f} ms a point "
              f"= {wall / ref:.0f}x simulate ({1e3 * ref:.2f} ms just after; target <= 710x for 100 points); "
              f"{b.attrs['map_evaluations']} periods integrated, {int(b.stable.sum())} stable")
        print(f"  {b.attrs['status']}: {b.attrs['message']}")
        print(f"  bifurcations: {b.attrs['bifurcations']}")
        if settings["beam.damping_ratio"] == 0.0 and source == "paper-dry":
            err = np.abs(b.floquet_modulus.values - 1.0)
            print(f"  largest ||mu| - 1| {err.max():.2e}" + (
                f", largest estimate {b.floquet_error.values.max():.2e}, every error within its estimate: "
                f"{bool(np.all(err <= b.floquet_error.values))}" if "floquet_error" in b else ""))


if __name__ == "__main__":
    main()

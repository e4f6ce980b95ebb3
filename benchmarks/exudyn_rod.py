"""lubelink against Exudyn 1.13.6 on the dry slider-crank rod: speed and midpoint deflection.

Compared: the ``paper-dry`` scenario with 5 modes (``lubelink.simulate("paper-dry",
{"beam.modes": 5})``, a pinned-pinned Euler-Bernoulli rod in modal coordinates, linear, in the
frame of its chord) and the same rod in Exudyn, an independent flexible multibody code:

* 8 ``ObjectANCFCable2D`` elements (nodes ``NodePoint2DSlope1``; geometrically nonlinear, with
  the axial stiffness EA and the axial inertia the modal model leaves out), rho A = 0.765 kg/m,
  EI = 172.5 N m^2, EA = 2.07e7 N, L = 1 m, no damping, no gravity;
* pin O (x = 0): the first node's X and Y follow the crank pin, OA (cos phi, sin phi) with
  phi = omega0 t, omega0 = 10 pi rad/s, OA = 0.07 m, by two ``ObjectConnectorCoordinate``
  constraints to ground whose ``offsetUserFunction`` is an Exudyn *symbolic* user function
  (an expression evaluated in C++, no Python call-back during the solve); pin C (x = L): the
  last node's Y = 0 (massless slider on the X axis);
* at t = 0 the rod lies straight from (0.07, 0) to (1.07, 0) and moves rigidly with the
  mechanism (nodal velocities v_O + omega_rod k x r, slope rates omega_rod k x i), as lubelink
  starts from zero modal coordinates and velocities;
* ``SolveDynamic``: generalized-alpha with spectral radius 1, index-3 constraints (Exudyn's
  default ``useIndex2Constraints = False``), h = 1e-4 s, 0-2 s, all other settings Exudyn's
  defaults (modified Newton, dense linear solver, one thread, standard build, not
  ``sys.exudynFast``); no solution file, the node positions are sampled every 1 ms by sensors
  kept in memory.

The compared quantity is the midpoint's deflection from the chord,
``u2_mid = (P_mid - (P_O + P_C) / 2) . j`` with ``j = k x i`` and ``i`` the unit vector from O to
C (lubelink's ``u2_mid``); the Exudyn series is interpolated onto lubelink's 1 ms samples. Printed:
the wall times (Exudyn: the ``SolveDynamic`` call alone, then with model building and output, as
medians of the repeats, and the import; lubelink: ``simulate()`` end to end, warm, median after a
warm-up call, and its integration alone, ``lubelink.simulate.run``, Exudyn's ``SolveDynamic``'s
counterpart), the ratio of Exudyn's solve alone to lubelink's end to end (and to its integration
alone), the largest difference
of ``u2_mid`` over 0-2 s in µm and in per cent of Exudyn's peak ``|u2_mid|``, the convergence
of the Exudyn model (h = 5e-5 s and 16 elements against the 8-element, h = 1e-4 s run), lubelink at
the ``--tolerances`` with its integration error, and the ratio *at matched accuracy*: the fastest
lubelink run whose integration error is no larger than the Exudyn model's own distance from its
converged solution (the largest change under refinement in the convergence runs; with ``--quick`` the
issue's 3 µm).

Of the ways tried to drive pin O, the symbolic offsets were the fastest: the same offsets as
Python functions took 1.5-1.6x as long, a rigid crank body (a ``NodeRigidBody2D`` held at the
origin, its angle driven by a velocity-level coordinate constraint, joined to the first node by
an ``ObjectJointRevolute2D``) 1.2-1.4x; all three gave the same ``u2_mid`` within 0.01 µm.

Exudyn runs in a subprocess with its own interpreter (this file in ``--worker`` mode, which
imports only Exudyn and NumPy), so Exudyn is not a dependency of lubelink: it serves only as an
independent reference here, and a large compiled package with its own release cycle should not
enter lubelink's environment for a benchmark. Set it up once::

    python -m venv /tmp/exuenv && /tmp/exuenv/bin/pip install exudyn==1.13.6 numpy

and run, with lubelink's interpreter::

    python benchmarks/exudyn_rod.py                 # under a minute on 2 busy cores
    python benchmarks/exudyn_rod.py --quick         # without the convergence runs
    python benchmarks/exudyn_rod.py --repeats 5 --exudyn-python /path/to/python
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

CRANK, ROD, OMEGA0 = 0.07, 1.0, 10.0 * np.pi  # OA [m], L [m], crank speed [rad/s]
SIDE, YOUNG, DENSITY = 0.01, 207e9, 7650.0  # square section [m], E [Pa], rho [kg/m^3]
T_END, SAMPLE = 2.0, 1e-3  # [s]
BASE = (8, 1e-4)  # elements, step: the model the issue prescribes
CONVERGENCE = [(8, 5e-5), (16, 1e-4), (16, 5e-5)]
TARGET_RATIO, TARGET_DIFF = 400.0, 3.0  # [-], [% of peak |u2_mid|]
#: The Exudyn model's distance from its converged solution [m] as the issue states it ("within 3 µm");
#: without ``--quick`` the convergence runs estimate it: the largest change of ``u2_mid`` when the step,
#: the mesh or both are refined (2.4-2.8 µm; refining both, the two errors partly cancel: 0.3 µm).
EXUDYN_ERROR = 3e-6


# --------------------------------------------------------------------------- Exudyn (side interpreter)
def build_exudyn(exu, elements, step):
    """The rod in a new Exudyn system; returns (mbs, settings, sensors of P_O, P_mid, P_C, keep-alive)."""
    from exudyn.advancedUtilities import CreateSymbolicUserFunction
    from exudyn.itemInterface import (MarkerNodeCoordinate, NodePoint2DSlope1, NodePointGround,
                                      ObjectANCFCable2D, ObjectConnectorCoordinate, SensorNode)

    if elements % 2:
        raise ValueError("an even number of elements puts a node at the midpoint")
    esym = exu.symbolic
    area, inertia = SIDE**2, SIDE**4 / 12.0
    mbs = exu.SystemContainer().AddSystem()
    # Rigid motion at t = 0 (phi = theta = 0): v_O = (0, OA omega0), rod angle rate -theta_dot.
    omega_rod = -CRANK / ROD * OMEGA0
    v_O = np.array([0.0, CRANK * OMEGA0])
    nodes = []
    for k in range(elements + 1):
        x = k * ROD / elements
        v = v_O + omega_rod * np.array([0.0, x])  # omega_rod k x (x, 0)
        nodes.append(mbs.AddNode(NodePoint2DSlope1(referenceCoordinates=[CRANK + x, 0.0, 1.0, 0.0],
                                                   initialVelocities=[v[0], v[1], 0.0, omega_rod])))
    for k in range(elements):
        mbs.AddObject(ObjectANCFCable2D(length=ROD / elements, massPerLength=DENSITY * area,
                                        bendingStiffness=YOUNG * inertia, axialStiffness=YOUNG * area,
                                        nodeNumbers=[nodes[k], nodes[k + 1]]))

    ground = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=mbs.AddNode(NodePointGround()), coordinate=0))

    def fix(node, coordinate):
        """Constrain a nodal coordinate (a displacement from the reference) to ground's."""
        marker = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=node, coordinate=coordinate))
        return mbs.AddObject(ObjectConnectorCoordinate(markerNumbers=[ground, marker]))

    def pin_x(mbs, t, itemNumber, lOffset):
        return CRANK * esym.cos(OMEGA0 * t) - CRANK  # minus the reference X of node 0

    def pin_y(mbs, t, itemNumber, lOffset):
        return CRANK * esym.sin(OMEGA0 * t)

    keep = []  # the symbolic functions must outlive the solve
    for coordinate, offset in ((0, pin_x), (1, pin_y)):
        constraint = fix(nodes[0], coordinate)
        keep.append(CreateSymbolicUserFunction(mbs, offset, "offsetUserFunction", constraint))
        mbs.SetObjectParameter(constraint, "offsetUserFunction", keep[-1])
    fix(nodes[-1], 1)  # slider: Y_C = 0

    sensors = [mbs.AddSensor(SensorNode(nodeNumber=n, outputVariableType=exu.OutputVariableType.Position,
                                        storeInternal=True, writeToFile=False))
               for n in (nodes[0], nodes[elements // 2], nodes[-1])]
    mbs.Assemble()

    settings = exu.SimulationSettings()
    settings.timeIntegration.endTime = T_END
    settings.timeIntegration.numberOfSteps = round(T_END / step)
    settings.timeIntegration.generalizedAlpha.spectralRadius = 1.0
    settings.timeIntegration.verboseMode = 0
    settings.solution.file.write = False
    settings.solution.sensors.writePeriod = SAMPLE
    return mbs, settings, sensors, keep


def midpoint_deflection(p_O, p_mid, p_C):
    """``u2_mid`` from the positions (rows) of O, the midpoint and C."""
    i = (p_C - p_O) / np.linalg.norm(p_C - p_O, axis=1)[:, None]
    j = np.column_stack([-i[:, 1], i[:, 0]])
    return np.sum((p_mid - 0.5 * (p_O + p_C)) * j, axis=1)


def worker(out, elements, step, repeats):
    """Build and solve ``repeats`` times (a fresh system each); save the series and the timings to ``out``."""
    t0 = time.perf_counter()
    import exudyn as exu

    load = time.perf_counter() - t0
    solve, run = [], []
    for _ in range(repeats):
        t0 = time.perf_counter()
        mbs, settings, sensors, keep = build_exudyn(exu, elements, step)  # keep: alive during the solve
        t1 = time.perf_counter()
        if not mbs.SolveDynamic(settings):
            sys.exit(f"Exudyn: SolveDynamic failed ({elements} elements, h = {step})")
        solve.append(time.perf_counter() - t1)
        data = [mbs.GetSensorStoredData(s) for s in sensors]
        t, u2 = data[0][:, 0], midpoint_deflection(*(d[:, 1:3] for d in data))
        run.append(time.perf_counter() - t0)
    np.savez(out, t=t, u2_mid=u2, solve=solve, run=run, load=load, version=exu.__version__)


# --------------------------------------------------------------------------- driver (lubelink's interpreter)
def run_exudyn(python, elements, step, repeats):
    """Run the worker in ``python``; returns its arrays as a dict."""
    with tempfile.TemporaryDirectory() as tmp:  # also the working directory: nothing lands in the repo
        out = Path(tmp) / "result.npz"
        cmd = [python, os.path.abspath(__file__), "--worker", str(out), "--elements", str(elements),
               "--step", repr(step), "--repeats", str(repeats)]
        done = subprocess.run(cmd, cwd=tmp, capture_output=True, text=True)
        if done.returncode:
            sys.exit(f"Exudyn worker failed ({' '.join(cmd)}):\n{done.stderr}")
        with np.load(out) as f:
            return {k: f[k] for k in f.files}


def run_lubelink(repeats, tolerance=None, method=None):
    """``simulate("paper-dry", {"beam.modes": 5})``: one warm-up, then ``repeats`` timed calls;
    ``tolerance``: ``solver.rtol`` (``atol`` a tenth of it in metres), default lubelink's own;
    ``method``: ``solver.method``, default lubelink's choice."""
    import lubelink

    overrides = {"beam.modes": 5}
    if tolerance is not None:
        overrides.update({"solver.rtol": tolerance, "solver.atol": tolerance / 10})
    if method is not None:
        overrides["solver.method"] = method
    lubelink.simulate("paper-dry", overrides)
    walls = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        ds = lubelink.simulate("paper-dry", overrides)
        walls.append(time.perf_counter() - t0)
    if ds.attrs["status"] != "complete":
        sys.exit(f"lubelink run incomplete: {ds.attrs['status']}")
    return ds.time.values, ds.u2_mid.values, walls, f"{lubelink.__version__} ({ds.attrs['solver_method']})"


def solve_lubelink(repeats, tolerance=None):
    """Wall times of ``lubelink.simulate.run`` alone (the integration and its 2001 samples, no results):
    the counterpart of Exudyn's ``SolveDynamic``."""
    import importlib

    from lubelink.config import resolve

    run = importlib.import_module("lubelink.simulate").run
    overrides = {"beam.modes": 5}
    if tolerance is not None:
        overrides.update({"solver.rtol": tolerance, "solver.atol": tolerance / 10})
    config = resolve("paper-dry", overrides)
    run(config)
    walls = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        run(config)
        walls.append(time.perf_counter() - t0)
    return walls


def spread(walls, unit, scale, digits):
    """``median X unit of N (min-max)`` for wall times in seconds shown in ``unit`` (``scale`` per s)."""
    lo, mid, hi = (f"{scale * w:.{digits}f}" for w in (min(walls), statistics.median(walls), max(walls)))
    return f"median {mid} {unit} of {len(walls)} ({lo}-{hi})"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--exudyn-python", default="/tmp/exuenv/bin/python",
                        help="interpreter with exudyn 1.13.6 and numpy (default: %(default)s)")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs of each code (default: %(default)s)")
    parser.add_argument("--quick", action="store_true", help="skip the Exudyn convergence runs")
    parser.add_argument("--tolerances", type=lambda text: [float(v) for v in text.split(",")], default=[1e-6, 1e-5],
                        help="also time lubelink at these solver.rtol values (atol = rtol/10 m), with their "
                             "integration error against DOP853 at rtol 1e-11 (default: 1e-6,1e-5)")
    parser.add_argument("--worker", metavar="OUT", help=argparse.SUPPRESS)
    parser.add_argument("--elements", type=int, default=BASE[0], help=argparse.SUPPRESS)
    parser.add_argument("--step", type=float, default=BASE[1], help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.repeats < 1:
        parser.error("--repeats must be at least 1")
    if args.worker:
        return worker(args.worker, args.elements, args.step, args.repeats)

    print(f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f} at start")
    ref = run_exudyn(args.exudyn_python, *BASE, args.repeats)
    t, u2, walls, version = run_lubelink(args.repeats)
    u2_exu = np.interp(t, ref["t"], ref["u2_mid"])
    peak = np.abs(u2_exu).max()
    diff = np.abs(u2 - u2_exu).max()
    ratio = statistics.median(ref["solve"]) / statistics.median(walls)

    print(f"Exudyn {ref['version']}: {BASE[0]} ANCFCable2D elements, generalized-alpha rho_inf = 1, "
          f"index 3, h = {BASE[1]:g} s, 0-{T_END:g} s")
    print(f"  SolveDynamic: {spread(ref['solve'], 's', 1, 3)}")
    print(f"  with model building and output: {spread(ref['run'], 's', 1, 3)}; import exudyn: {ref['load']:.2f} s")
    print(f"lubelink {version}: simulate('paper-dry', {{'beam.modes': 5}}), warm, end to end: "
          f"{spread(walls, 'ms', 1e3, 1)}")
    print(f"ratio (Exudyn solve / lubelink): {ratio:.0f}x  (target >= {TARGET_RATIO:.0f}x: "
          f"{'met' if ratio >= TARGET_RATIO else f'not met, {TARGET_RATIO / ratio:.1f}x short'})")
    solve = solve_lubelink(args.repeats)
    print(f"  lubelink's integration alone (simulate.run, no results): {spread(solve, 'ms', 1e3, 1)}; "
          f"solve against solve {statistics.median(ref['solve']) / statistics.median(solve):.0f}x")
    print(f"peak |u2_mid|: Exudyn {1e3 * peak:.4f} mm, lubelink {1e3 * np.abs(u2).max():.4f} mm")
    rel = 100.0 * diff / peak
    print(f"max |u2_mid difference| over 0-{T_END:g} s: {1e6 * diff:.1f} µm = {rel:.2f} % of Exudyn's peak  "
          f"(target <= {TARGET_DIFF:g} %: {'met' if rel <= TARGET_DIFF else 'not met'})")
    tight_t, tight, _, _ = run_lubelink(1, 1e-11, "DOP853")
    err = np.abs(u2 - np.interp(t, tight_t, tight)).max()
    print(f"lubelink's integration error at its defaults (against DOP853 at rtol 1e-11): {1e6 * err:.4f} µm")
    own = EXUDYN_ERROR  # the Exudyn model's distance from its converged solution (measured below unless --quick)
    if not args.quick:
        print(f"Exudyn convergence: max |u2_mid difference| against {BASE[0]} elements, h = {BASE[1]:g} s")
        changes = []
        for elements, step in CONVERGENCE:
            run = run_exudyn(args.exudyn_python, elements, step, 1)
            u = np.interp(t, run["t"], run["u2_mid"])
            changes.append(np.abs(u - u2_exu).max())
            print(f"  {elements:2d} elements, h = {step:g} s (solve {run['solve'][0]:.2f} s): "
                  f"{1e6 * changes[-1]:.2f} µm; lubelink against it: {1e6 * np.abs(u2 - u).max():.1f} µm")
        # the largest change under refinement (refining both h and the mesh, their errors partly cancel)
        own = max(changes)
    matched = [(ratio, None, err)] if err <= own and rel <= TARGET_DIFF else []
    for tol in args.tolerances:
        tt, uu, ww, _ = run_lubelink(args.repeats, tol)
        e = np.abs(uu - np.interp(tt, tight_t, tight)).max()
        d = 100.0 * np.abs(uu - np.interp(tt, ref["t"], ref["u2_mid"])).max() / peak
        r = statistics.median(ref["solve"]) / statistics.median(ww)
        rs = statistics.median(ref["solve"]) / statistics.median(solve_lubelink(args.repeats, tol))
        print(f"lubelink at rtol {tol:g}, atol {tol / 10:g} m: {spread(ww, 'ms', 1e3, 1)}; integration error "
              f"{1e6 * e:.3f} µm; against Exudyn {d:.2f} %; ratio {r:.0f}x (solve against solve {rs:.0f}x)")
        if e <= own and d <= TARGET_DIFF:
            matched.append((r, tol, e))
    # the like-for-like reading: lubelink no less accurate than the Exudyn model it is compared with
    if matched:
        r, tol, e = max(matched, key=lambda m: m[0])
        source = " (the issue's figure; measured without --quick)" if args.quick else ""
        print(f"at matched accuracy (lubelink's integration error {1e6 * e:.2f} µm <= the Exudyn model's own "
              f"{1e6 * own:.1f} µm{source}): "
              f"{r:.0f}x at {'the defaults' if tol is None else f'rtol {tol:g}'}  (target >= {TARGET_RATIO:.0f}x: "
              f"{'met' if r >= TARGET_RATIO else 'not met'})")


if __name__ == "__main__":
    main()

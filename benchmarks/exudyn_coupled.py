"""The crank and the elastic link coupled both ways (drive.coupling) against Exudyn's model of the same mechanism.

lubelink: ``paper-dry`` with a free crank (``drive.law = "torque"``, no motor torque) on a flywheel of ``J_f``
(``--flywheel``, default 0.1 kg m^2), a massless slider, ``beam.modes`` (``--modes``, default 5), one-way and
two-way (``lubelink.coupling``). Exudyn (1.13.6, run in its own interpreter as ``exudyn_rod.py`` says): the rod
of ``exudyn_rod.py`` (``ObjectANCFCable2D`` elements: geometrically exact, extensible, with axial inertia), but
the crank pin not prescribed: a rigid crank (``NodeRigidBody2D``, ``ObjectRigidBody2D`` of inertia ``J_f``)
turning about the origin on a revolute joint to ground, its pin ``OA`` from the axis joined to the rod's first
node by a revolute joint, the rod's last node on the X axis (a massless slider); at t = 0 the crank turns at
``omega0`` and the rod moves rigidly with the mechanism. Generalized-alpha (spectral radius 1), index-3
constraints, ``--step`` (default 1e-4 s), ``--elements`` (default 8).

Printed: the largest difference of the crank speed and of ``u2_mid`` between lubelink (one-way, two-way) and
Exudyn over ``--t-end`` (default 1 s), and Exudyn's own change when its step is halved and its mesh doubled
(``--no-convergence`` skips it); then a table of the prescribed speed (KED), the one-way and two-way driven
crank and Exudyn: peak ``|u2_mid|``, the crank speed's fluctuation ``(max - min) / mean`` and the wall time
(lubelink: ``simulate`` warm, the second of two calls; Exudyn: its ``SolveDynamic`` call).

    python -m venv /tmp/exuenv && /tmp/exuenv/bin/pip install exudyn==1.13.6 numpy   # once
    PYTHONPATH=src python benchmarks/exudyn_coupled.py [--exudyn-python /tmp/exuenv/bin/python]

Without an Exudyn interpreter it says so and exits with status 0 (skipped).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from exudyn_rod import CRANK, DENSITY, OMEGA0, ROD, SAMPLE, SIDE, YOUNG, midpoint_deflection  # noqa: E402


# --------------------------------------------------------------------------- Exudyn (side interpreter)
def build_exudyn(exu, elements, step, flywheel, t_end):
    """The coupled mechanism in a new Exudyn system; returns (mbs, settings, sensors of P_O, P_mid, P_C, omega)."""
    from exudyn.itemInterface import (MarkerBodyPosition, MarkerNodeCoordinate, MarkerNodePosition,
                                      NodePoint2DSlope1, NodePointGround, NodeRigidBody2D, ObjectANCFCable2D,
                                      ObjectConnectorCoordinate, ObjectGround, ObjectJointRevolute2D,
                                      ObjectRigidBody2D, SensorNode)

    area, inertia = SIDE ** 2, SIDE ** 4 / 12.0
    mbs = exu.SystemContainer().AddSystem()
    omega_rod = -CRANK / ROD * OMEGA0  # the rod's rotation rate at phi = 0
    v_O = np.array([0.0, CRANK * OMEGA0])
    nodes = []
    for k in range(elements + 1):
        x = k * ROD / elements
        v = v_O + omega_rod * np.array([0.0, x])
        nodes.append(mbs.AddNode(NodePoint2DSlope1(referenceCoordinates=[CRANK + x, 0.0, 1.0, 0.0],
                                                   initialVelocities=[v[0], v[1], 0.0, omega_rod])))
    for k in range(elements):
        mbs.AddObject(ObjectANCFCable2D(length=ROD / elements, massPerLength=DENSITY * area,
                                        bendingStiffness=YOUNG * inertia, axialStiffness=YOUNG * area,
                                        nodeNumbers=[nodes[k], nodes[k + 1]]))
    crank_node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[0.0, 0.0, 0.0],
                                             initialVelocities=[0.0, 0.0, OMEGA0]))
    crank = mbs.AddObject(ObjectRigidBody2D(physicsMass=1.0, physicsInertia=flywheel, nodeNumber=crank_node))
    ground = mbs.AddObject(ObjectGround(referencePosition=[0.0, 0.0, 0.0]))
    axis = [mbs.AddMarker(MarkerBodyPosition(bodyNumber=b, localPosition=[0.0, 0.0, 0.0])) for b in (ground, crank)]
    mbs.AddObject(ObjectJointRevolute2D(markerNumbers=axis))
    pin = [mbs.AddMarker(MarkerBodyPosition(bodyNumber=crank, localPosition=[CRANK, 0.0, 0.0])),
           mbs.AddMarker(MarkerNodePosition(nodeNumber=nodes[0]))]
    mbs.AddObject(ObjectJointRevolute2D(markerNumbers=pin))
    fixed = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=mbs.AddNode(NodePointGround()), coordinate=0))
    slider = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nodes[-1], coordinate=1))
    mbs.AddObject(ObjectConnectorCoordinate(markerNumbers=[fixed, slider]))  # Y_C = 0

    def sensor(node, kind):
        return mbs.AddSensor(SensorNode(nodeNumber=node, outputVariableType=kind, storeInternal=True,
                                        writeToFile=False))

    sensors = [sensor(n, exu.OutputVariableType.Position) for n in (nodes[0], nodes[elements // 2], nodes[-1])]
    sensors.append(sensor(crank_node, exu.OutputVariableType.AngularVelocity))
    mbs.Assemble()
    settings = exu.SimulationSettings()
    settings.timeIntegration.endTime = t_end
    settings.timeIntegration.numberOfSteps = round(t_end / step)
    settings.timeIntegration.generalizedAlpha.spectralRadius = 1.0
    settings.timeIntegration.verboseMode = 0
    settings.solution.file.write = False
    settings.solution.sensors.writePeriod = SAMPLE
    return mbs, settings, sensors


def worker(out, elements, step, flywheel, t_end):
    import exudyn as exu

    if elements % 2:
        raise ValueError("an even number of elements puts a node at the midpoint")
    import time

    mbs, settings, sensors = build_exudyn(exu, elements, step, flywheel, t_end)
    start = time.perf_counter()
    if not mbs.SolveDynamic(settings):
        sys.exit(f"Exudyn: SolveDynamic failed ({elements} elements, h = {step})")
    solve = time.perf_counter() - start
    data = [mbs.GetSensorStoredData(s) for s in sensors]
    np.savez(out, t=data[0][:, 0], u2_mid=midpoint_deflection(*(d[:, 1:3] for d in data[:3])),
             speed=data[3][:, 3], solve=solve, version=exu.__version__)


# --------------------------------------------------------------------------- driver (lubelink's interpreter)
def run_exudyn(python, elements, step, flywheel, t_end):
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "result.npz"
        cmd = [python, os.path.abspath(__file__), "--worker", str(out), "--elements", str(elements),
               "--step", repr(step), "--flywheel", repr(flywheel), "--t-end", repr(t_end)]
        done = subprocess.run(cmd, cwd=tmp, capture_output=True, text=True)
        if done.returncode:
            sys.exit(f"Exudyn worker failed ({' '.join(cmd)}):\n{done.stderr}")
        with np.load(out) as f:
            return {k: f[k] for k in f.files}


def exudyn_available(python):
    try:
        return subprocess.run([python, "-c", "import exudyn"], capture_output=True).returncode == 0
    except OSError:
        return False


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--exudyn-python", default="/tmp/exuenv/bin/python")
    parser.add_argument("--elements", type=int, default=8)
    parser.add_argument("--step", type=float, default=1e-4)
    parser.add_argument("--flywheel", type=float, default=0.1)
    parser.add_argument("--modes", type=int, default=5)
    parser.add_argument("--t-end", type=float, default=1.0)
    parser.add_argument("--no-convergence", action="store_true")
    parser.add_argument("--worker", metavar="OUT", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        return worker(args.worker, args.elements, args.step, args.flywheel, args.t_end)
    if not exudyn_available(args.exudyn_python):
        print(f"skipped: no Exudyn at {args.exudyn_python} (python -m venv /tmp/exuenv && "
              "/tmp/exuenv/bin/pip install exudyn==1.13.6 numpy)")
        return 0
    import lubelink

    ref = run_exudyn(args.exudyn_python, args.elements, args.step, args.flywheel, args.t_end)
    print(f"Exudyn {ref['version']}: {args.elements} elements, h = {args.step:g} s; J_f = {args.flywheel} kg m^2, "
          f"{args.modes} modes, 0-{args.t_end} s")
    import time

    peak = np.abs(ref["u2_mid"]).max()
    table = []
    base = {"beam.modes": args.modes, "solver.t_end": args.t_end}
    ds = lubelink.simulate("paper-dry", base)
    start = time.perf_counter()
    ds = lubelink.simulate("paper-dry", base)
    table.append(("prescribed speed (KED)", np.abs(ds.u2_mid.values).max(), 0.0, time.perf_counter() - start))
    for coupling in ("one-way", "two-way"):
        sets = {**base, "drive.law": "torque", "drive.flywheel_inertia": args.flywheel, "drive.coupling": coupling}
        lubelink.simulate("paper-dry", sets)
        start = time.perf_counter()
        ds = lubelink.simulate("paper-dry", sets)
        w = ds.crank_speed.values
        table.append((f"driven, {coupling}", np.abs(ds.u2_mid.values).max(), np.ptp(w) / np.mean(w),
                      time.perf_counter() - start))
        t = ds.time.values
        speed = np.interp(t, ref["t"], ref["speed"])
        u2 = np.interp(t, ref["t"], ref["u2_mid"])
        print(f"  lubelink {coupling}: crank speed differs by {np.abs(ds.crank_speed.values - speed).max():.3g} rad/s, "
              f"u2_mid by {np.abs(ds.u2_mid.values - u2).max() * 1e6:.3g} um ({np.abs(ds.u2_mid.values - u2).max() / peak:.2%} "
              f"of {peak * 1e3:.3g} mm)")
    w = ref["speed"]
    table.append((f"Exudyn, {args.elements} ANCF elements", peak, np.ptp(w) / np.mean(w), float(ref["solve"])))
    print(f"{'model':<28}{'peak |u2_mid| mm':>18}{'fluctuation':>13}{'wall s':>9}")
    for name, u, f, wall in table:
        print(f"{name:<28}{u * 1e3:>18.4f}{f:>13.4f}{wall:>9.3f}")
    if not args.no_convergence:
        fine = run_exudyn(args.exudyn_python, 2 * args.elements, args.step / 2, args.flywheel, args.t_end)
        t = ref["t"]
        print(f"  Exudyn refined ({2 * args.elements} elements, h/2): speed changes by "
              f"{np.abs(np.interp(t, fine['t'], fine['speed']) - ref['speed']).max():.3g} rad/s, u2_mid by "
              f"{np.abs(np.interp(t, fine['t'], fine['u2_mid']) - ref['u2_mid']).max() * 1e6:.3g} um")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Mode-1 frequency shifts of the paper's rod in Exudyn against lubelink's modal terms (docs/model.md §1.5).

Set-ups that isolate one term each, every one with an independent closed or modal answer:

* ``axial``: O pinned, C on a guide along the chord, gravity along the chord (the axial inertia of an
  accelerating O, by equivalence): the axial force ``rho A g_1 (L - x)``;
* ``spin``: O pinned at a fixed point, the rod spun about it at ``omega`` by an arm along which C slides
  (a ``NodeRigidBody2D`` whose angle is driven, an ``ObjectJointPrismatic2D`` without the rotation constraint):
  the centrifugal tension and the frame's softening, ``omega_1^2 - omega_10^2 = omega^2 (c_1 - 1)``;
* ``slider``: the rod inclined at ``psi``, O pinned, C on a horizontal guide (as the slider-crank's) or on a guide
  along the chord, gravity ``(0, -g)``: the slider's axial force ``N_C = F_C2 tan(psi)`` and the rotation of the
  chord it forces on the bent link (:func:`lubelink.link.axial.chord_rotation`).

The rod: ``--elements`` ANCF cable elements (default 8), generalized-alpha with spectral radius 1 at ``--step``
(1e-4 s), 0.3 s; a mode-1 velocity kick where nothing else excites it. ``omega_1`` is fitted to the midpoint's
deflection from the chord (a sinusoid plus a constant, and mode 3); printed are the shifts of ``omega_1^2``
against the unloaded rod's in the same set-up (so the discretisation's own error cancels), and lubelink's (10
sine modes, the eigenvalue about the static deflection). Exudyn runs in its side interpreter
(``exudyn_rod.py`` says how to set it up), each case in a new process::

    python benchmarks/exudyn_frequency.py               # all cases, about 3 minutes on 2 busy cores
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

SIDE, YOUNG, DENSITY, L = 0.01, 207e9, 7650.0, 1.0
RHO_A, EI = DENSITY * SIDE**2, YOUNG * SIDE**4 / 12.0


# --------------------------------------------------------------------------- Exudyn (side interpreter)
def exudyn_case(case):
    """Build and solve one set-up; returns (t, u2_mid, solve time)."""
    import exudyn as exu
    from exudyn.advancedUtilities import CreateSymbolicUserFunction
    from exudyn.itemInterface import (LoadMassProportional, MarkerBodyMass, MarkerBodyRigid, MarkerNodeCoordinate,
                                      NodePoint2DSlope1, NodePointGround, NodeRigidBody2D, ObjectANCFCable2D,
                                      ObjectConnectorCoordinate, ObjectJointPrismatic2D, ObjectRigidBody2D, SensorNode)

    n, psi, gamma, spin, g, kick = (case[k] for k in ("elements", "psi", "gamma", "spin", "gravity", "kick"))
    mbs = exu.SystemContainer().AddSystem()
    i = np.array([np.cos(psi), np.sin(psi)])
    j = np.array([-i[1], i[0]])
    nodes = []
    for k in range(n + 1):
        x = k * L / n
        v = (spin * x + kick * np.sin(np.pi * x / L)) * j  # rigid spin about O and a mode-1 kick
        rate = (spin + kick * np.pi / L * np.cos(np.pi * x / L)) * j
        nodes.append(mbs.AddNode(NodePoint2DSlope1(referenceCoordinates=[*(x * i), *i],
                                                   initialVelocities=[*v, *rate])))
    elements = [mbs.AddObject(ObjectANCFCable2D(length=L / n, massPerLength=RHO_A, bendingStiffness=EI,
                                                axialStiffness=YOUNG * SIDE**2, nodeNumbers=[nodes[k], nodes[k + 1]]))
                for k in range(n)]
    if any(g):
        for e in elements:
            mbs.AddLoad(LoadMassProportional(markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=e)),
                                             loadVector=[g[0], g[1], 0.0]))
    ground = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=mbs.AddNode(NodePointGround()), coordinate=0))

    def fix(node, coordinate):
        marker = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=node, coordinate=coordinate))
        return mbs.AddObject(ObjectConnectorCoordinate(markerNumbers=[ground, marker]))

    fix(nodes[0], 0)
    fix(nodes[0], 1)
    # the guide: a rigid body (at O when it spins, else at C) whose x axis C slides along, at angle gamma + spin t
    where = [0.0, 0.0] if spin else list(L * i)
    arm_node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[*where, gamma], initialVelocities=[0.0, 0.0, spin]))
    arm = mbs.AddObject(ObjectRigidBody2D(mass=1.0, inertia=1.0, nodeNumber=arm_node))
    fix(arm_node, 0)
    fix(arm_node, 1)
    turn = fix(arm_node, 2)
    keep = []
    if spin:
        def angle(mbs, t, itemNumber, lOffset):
            return spin * t

        keep.append(CreateSymbolicUserFunction(mbs, angle, "offsetUserFunction", turn))
        mbs.SetObjectParameter(turn, "offsetUserFunction", keep[-1])
    end = mbs.AddMarker(MarkerBodyRigid(bodyNumber=elements[-1], localPosition=[L / n, 0.0, 0.0]))
    guide = mbs.AddMarker(MarkerBodyRigid(bodyNumber=arm, localPosition=[0.0, 0.0, 0.0]))
    # the normal is taken in the second marker's frame: the guide's
    mbs.AddObject(ObjectJointPrismatic2D(markerNumbers=[end, guide], axisMarker0=[1.0, 0.0, 0.0],
                                         normalMarker1=[0.0, 1.0, 0.0], constrainRotation=False))
    sensors = [mbs.AddSensor(SensorNode(nodeNumber=k, outputVariableType=exu.OutputVariableType.Position,
                                        storeInternal=True, writeToFile=False))
               for k in (nodes[0], nodes[n // 2], nodes[-1])]
    mbs.Assemble()
    s = exu.SimulationSettings()
    s.timeIntegration.endTime = case["t_end"]
    s.timeIntegration.numberOfSteps = round(case["t_end"] / case["step"])
    s.timeIntegration.generalizedAlpha.spectralRadius = 1.0
    s.timeIntegration.verboseMode = 0
    s.solution.file.write = False
    s.solution.sensors.writePeriod = 2e-4
    t0 = time.perf_counter()
    if not mbs.SolveDynamic(s):
        sys.exit("Exudyn: SolveDynamic failed")
    solve = time.perf_counter() - t0
    pO, pm, pC = (mbs.GetSensorStoredData(k)[:, 1:3] for k in sensors)
    e1 = (pC - pO) / np.linalg.norm(pC - pO, axis=1)[:, None]
    u = np.sum((pm - 0.5 * (pO + pC)) * np.column_stack([-e1[:, 1], e1[:, 0]]), axis=1)
    return mbs.GetSensorStoredData(sensors[0])[:, 0], u, solve


def run_case(python, case):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "case.npz")
        done = subprocess.run([python, os.path.abspath(__file__), "--worker", json.dumps(case), out], cwd=tmp,
                              capture_output=True, text=True)
        if done.returncode:
            sys.exit(f"Exudyn worker failed:\n{done.stderr}")
        with np.load(out) as f:
            return f["t"], f["u"], float(f["solve"])


# --------------------------------------------------------------------------- lubelink's interpreter
def fitted_frequency(t, u, guess):
    """``omega_1`` [rad/s]: the least-squares fit of ``c + a cos(W t) + b sin(W t)`` (and mode 3 at 9 W)."""
    from scipy.optimize import minimize_scalar

    def residual(W):
        A = np.column_stack([np.ones_like(t), np.cos(W * t), np.sin(W * t), np.cos(9 * W * t), np.sin(9 * W * t)])
        return np.sum((A @ np.linalg.lstsq(A, u, rcond=None)[0] - u) ** 2)

    return minimize_scalar(residual, bounds=(0.97 * guess, 1.03 * guess), method="bounded",
                           options={"xatol": 1e-9}).x


def modal_shift(case, modes=10, rotation=True):
    """lubelink's mode-1 ``omega^2`` shift [1/s^2] for the set-up: 10 sine modes about the static deflection."""
    from scipy.linalg import eigh

    from lubelink.link import axial

    psi, gamma, spin, (gx, gy) = case["psi"], case["gamma"], case["spin"], case["gravity"]
    n = np.arange(1, modes + 1)
    beta = n * np.pi / L
    m = RHO_A * L / 2
    g1, g2 = gx * np.cos(psi) + gy * np.sin(psi), -gx * np.sin(psi) + gy * np.cos(psi)
    if gamma == 0.0:  # the horizontal guide: the slider's force and the chord's rotation
        terms = axial.rigid_axial_force(0.0, 0.0, spin, 0.0, psi, 0.0, L, (gx, gy), RHO_A, L)
    else:  # along the chord: C free along it
        terms = axial.axial_force_terms(-g1, spin, 0.0, RHO_A, L)
    K = np.diag(m * (EI / RHO_A * beta**4 - spin**2)) + axial.geometric_stiffness(axial.slope_moments(modes, L), terms)
    M = m * np.eye(modes)
    if rotation and gamma == 0.0 and psi != 0.0:
        q = np.linalg.solve(K, RHO_A * g2 * (1 - np.cos(n * np.pi)) / beta)  # the static deflection
        M = axial.chord_mass(q, (np.cos(psi), -np.sin(psi), 0.0), L, RHO_A)
    return eigh(K, M, eigvals_only=True)[0] - EI / RHO_A * beta[0] ** 4


CASES = [("unloaded", dict(kick=0.15)),
         ("axial, g_1 = -100 m/s^2 (compression)", dict(gravity=[-100.0, 0.0], kick=0.15)),
         ("axial, g_1 = +100 m/s^2 (tension)", dict(gravity=[100.0, 0.0], kick=0.15)),
         ("spin, omega = 5 rad/s", dict(spin=5.0, kick=0.15)),
         ("spin, omega = 10 rad/s", dict(spin=10.0, kick=0.15)),
         ("spin, omega = 20 rad/s", dict(spin=20.0, kick=0.15)),
         ("slider, psi = 0.4, g = 30, guide along the chord", dict(psi=0.4, gamma=0.4, gravity=[0.0, -30.0])),
         ("slider, psi = 0.4, g = 30, horizontal guide", dict(psi=0.4, gravity=[0.0, -30.0])),
         ("slider, psi = 0.4, g = 15, horizontal guide", dict(psi=0.4, gravity=[0.0, -15.0])),
         ("slider, psi = 0.2, g = 30, horizontal guide", dict(psi=0.2, gravity=[0.0, -30.0])),
         ("slider, psi = -0.4, g = 30, horizontal guide", dict(psi=-0.4, gravity=[0.0, -30.0]))]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--exudyn-python", default="/tmp/exuenv/bin/python")
    parser.add_argument("--elements", type=int, default=8)
    parser.add_argument("--step", type=float, default=1e-4)
    parser.add_argument("--worker", nargs=2, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        t, u, solve = exudyn_case(json.loads(args.worker[0]))
        np.savez(args.worker[1], t=t, u=u, solve=solve)
        return
    base = dict(elements=args.elements, step=args.step, t_end=0.3, psi=0.0, gamma=0.0, spin=0.0,
                gravity=[0.0, 0.0], kick=0.0)
    w0 = None
    print(f"Exudyn: {args.elements} ANCF cable elements, h = {args.step:g} s; shifts of omega_1^2 [1/s^2]")
    for name, change in CASES:
        case = {**base, **change}
        t, u, solve = run_case(args.exudyn_python, case)
        w = fitted_frequency(t, u, np.pi**2 * np.sqrt(EI / RHO_A))
        if w0 is None:
            w0 = w
            print(f"  {name}: omega_1 = {w:.5f} rad/s (beam theory {np.pi**2 * np.sqrt(EI / RHO_A):.5f})")
            continue
        line = f"  {name}: Exudyn {w**2 - w0**2:8.2f}, lubelink {modal_shift(case):8.2f}"
        if case["gamma"] == 0.0 and case["psi"] != 0.0:
            line += f" (without the chord's rotation {modal_shift(case, rotation=False):6.2f})"
        print(line + f"  (solve {solve:.1f} s)", flush=True)


if __name__ == "__main__":
    main()

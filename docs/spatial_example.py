"""The spatial link's example: the RSSP slider-crank, both bending directions (docs/spatial.md).

Runs the modal equations of ``lubelink.spatial`` directly on lubelink's exponential integrator (the
spatial model is not yet wired into ``lubelink.simulate``), dry joint, zero initial conditions, and
compares the planar case with the planar model. Writes docs/figures/spatial-rssp.png and prints
the figures quoted in docs/spatial.md.

    PYTHONPATH=src python docs/spatial_example.py [--t-end 0.5] [--modes 3]
"""

import argparse
from pathlib import Path

import numpy as np

from lubelink import integrate, spatial

E, RHO, B, H, L, OA, W0, GUIDE = 207e9, 7650.0, 0.01, 0.01, 1.0, 0.07, 10 * np.pi, 0.4


def mechanism(axis=(0.25, 0.2, 1.0), P=(0.0, 0.0, 0.05)):
    k = np.array(axis, float) / np.linalg.norm(axis)
    a = np.array([1.0, 0.0, 0.0]) - k[0] * k
    a /= np.linalg.norm(a)
    return k, a, np.array(P, float), np.array([1.0, 0.0, 0.0])


def run(modes, t_end, geometry, dt=1e-3):
    """``(t, y)`` of the spatial modal equations under the RSSP motion of ``geometry``."""
    W = spatial.frequencies(modes, L, E, RHO, B * H, B * H**3 / 12, H * B**3 / 12)
    m = RHO * B * H * L / 2
    F = np.zeros(3 * modes)

    def rhs(t, y, out, p):
        A_O, w, al, *_ = spatial.slider_crank_rssp(t, OA, L, W0, GUIDE, *geometry)
        spatial.accelerations(y, W, 0.0, A_O, w, al, F, m, L, out)

    t_eval = np.arange(dt, t_end + dt / 2, dt)
    seg = integrate.integrate(integrate.method("exponential"), rhs, None, None, 0.0, np.zeros(6 * modes), t_end,
                              t_eval, rtol=1e-10, atol=1e-14, compiled=False, options={"omega": W, "zeta": 0.0})
    return np.r_[0.0, seg.t], np.vstack([np.zeros(6 * modes), seg.y])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--t-end", type=float, default=0.5)
    ap.add_argument("--modes", type=int, default=3)
    ap.add_argument("-o", default=str(Path(__file__).parent / "figures" / "spatial-rssp.png"))
    args = ap.parse_args()
    import lubelink

    # planar case against the planar model
    t, y = run(args.modes, args.t_end, mechanism(axis=(0, 0, 1), P=(0, 0, 0)))
    u1, u2, u3 = spatial.deflections(y, [0.5 * L], L)
    ds = lubelink.simulate("paper-dry", set={"beam.modes": args.modes, "solver.t_end": args.t_end,
                                             "solver.rtol": 1e-10, "solver.atol": 1e-14})
    print(f"planar case: max |u3| = {np.max(np.abs(u3)):.3g} m, max |u2_mid - planar| = "
          f"{np.max(np.abs(u2[:, 0] - ds.u2_mid.values)):.3g} m (peak {np.max(np.abs(u2)):.4g} m), "
          f"max |u1_mid| = {np.max(np.abs(u1)):.3g} m")
    # the spatial mechanism
    t, y = run(args.modes, args.t_end, mechanism())
    u1, u2, u3 = spatial.deflections(y, [0.5 * L], L)
    print(f"RSSP: peak |u2_mid| = {np.max(np.abs(u2)):.4g} m, peak |u3_mid| = {np.max(np.abs(u3)):.4g} m, "
          f"peak |u1_mid| = {np.max(np.abs(u1)):.3g} m")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from lubelink._files import atomic_path

    fig, ax = plt.subplots(3, 1, figsize=(7, 6), sharex=True)
    for a, u, name in zip(ax, (u2, u3, u1), ("u2 (in the crank's plane)", "u3 (out of it)", "u1 (axial)")):
        a.plot(t, 1e3 * u[:, 0])
        a.set_ylabel(f"{name.split()[0]}(L/2) [mm]")
        a.set_title(name, fontsize=9)
    ax[-1].set_xlabel("time [s]")
    fig.suptitle("Spatial slider-crank (RSSP), crank axis 14 deg off the slider normal, dry", fontsize=10)
    fig.tight_layout()
    with atomic_path(args.o, overwrite=True) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    print("wrote", args.o)


if __name__ == "__main__":
    main()

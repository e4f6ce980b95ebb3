"""The summary ``lubelink run`` and ``lubelink show`` print: a line a row, read off a run's results."""

from __future__ import annotations

__all__ = ["summary"]


def _budget(r):
    """The finite wall-time budget the results were computed with, or None."""
    import math
    import tomllib

    try:
        budget = float(tomllib.loads(r.attrs["config"])["solver"]["max_wall_time"])
    except (KeyError, ValueError, TypeError):
        return None
    return budget if math.isfinite(budget) else None



def summary(r, source, path, wall):
    """The run's summary, a line a row, from its :class:`~lubelink.results.Results`."""
    import numpy as np

    a = r.attrs
    u = np.abs(np.asarray(r["u2_mid"]))
    i = int(np.argmax(u)) if u.size else 0
    t = np.asarray(r["time"])
    rows = [
        ("source", str(source)),
        ("status", a["status"] + ("" if a["status"] == "complete" else f": {a['message']}")),
        ("simulated", f"0 - {float(t[-1]):.4g} s, {r['mode'].size} mode(s), {t.size} samples"),
        ("peak |u2_mid|", f"{1e3 * u[i]:.4f} mm at t = {float(t[i]):.4f} s"),
    ]
    if "crank_speed" in r and np.size(r["crank_speed"]):  # a driven crank (drive.law other than "speed")
        w = np.asarray(r["crank_speed"])
        mean = float(np.mean(w))
        rows.append(("crank speed", f"{mean:.6g} rad/s on average, {float(w.min()):.6g} - {float(w.max()):.6g} rad/s "
                                    f"(fluctuation {float(w.max() - w.min()) / abs(mean):.3g}), motor torque "
                                    f"{float(np.mean(r['motor_torque'])):.4g} N m on average"))
    if "coupling_runs" in a:  # drive.coupling = "two-way" (lubelink.coupling)
        rows.append(("coupling", f"two-way, {int(a['coupling_runs'])} link runs, the crank speed's last change "
                                 f"{float(a['coupling_change']):.3g} rad/s (contraction "
                                 f"{float(a['coupling_contraction']):.3g})"))
    if "u3_mid" in r and r["u3_mid"].size:  # the spatial link: the out-of-plane peak too
        u3 = np.abs(np.asarray(r["u3_mid"]))
        j = int(np.argmax(u3))
        rows.append(("peak |u3_mid|", f"{1e3 * u3[j]:.4f} mm at t = {float(t[j]):.4f} s"))
    if "bending_stress" in r and np.size(r["bending_stress"]):
        s = np.asarray(r["bending_stress"])
        k = np.unravel_index(int(np.argmax(s)), s.shape)
        utilisation = a.get("stress_utilisation", np.nan)
        rows.append(("peak stress", f"{1e-6 * s[k]:.4g} MPa (bending) at x = {float(np.asarray(r['x'])[k[1]]):.4g} m, "
                                    f"t = {float(t[k[0]]):.4f} s" + (f", {100 * utilisation:.3g} % of the yield "
                                    f"strength beam.yield_strength" if np.isfinite(utilisation) else "")))
        if utilisation >= 1.0:
            rows.append(("warning", "the bending stress exceeds the yield strength: the link yields (the model is "
                                    "elastic and says no more past that)"))
    if "pressure" in r:
        rows.append(("film", f"thinnest {1e3 * float(r['film_min'].min()):.4f} mm, peak gauge pressure "
                             f"{1e-3 * float(np.abs(r['pressure']).max()):.4g} kPa, peak force "
                             f"{float(np.abs(r['film_force']).max()):.4g} N"))
    if "film_power_loss" in r and np.size(r["film_power_loss"]):
        loss = np.asarray(r["film_power_loss"])
        per_rev = (f", {float(np.mean(r['revolution_film_loss'])):.4g} J a revolution"
                   if "revolution_film_loss" in r and np.size(r["revolution_film_loss"]) else "")
        rows.append(("film losses", f"friction up to {float(np.abs(r['film_friction']).max()):.4g} N, power lost "
                                    f"{float(np.mean(loss)):.4g} W on average (peak {float(loss.max()):.4g} W){per_rev}"))
    if "slider_pin_force" in r and np.size(r["slider_pin_force"]):
        crank = np.hypot(np.asarray(r["crank_pin_force_X"]), np.asarray(r["crank_pin_force_Y"]))
        rows.append(("joint forces", f"peak crank pin {float(crank.max()):.4g} N, slider pin "
                                     f"{float(np.abs(r['slider_pin_force']).max()):.4g} N, collar "
                                     f"{float(np.abs(r['collar_force']).max()):.4g} N, guide "
                                     f"{float(np.abs(r['guide_force']).max()):.4g} N"))
    n_imp = int(a["impact_count"])
    times = ", ".join(f"{t:.4f}" for t in r["impact_time"][:5]) + (" ..." if n_imp > 5 else "")
    rows.append(("impacts", f"{n_imp}" + (f" (t = {times} s)" if n_imp else "")))
    if "energy" in r and r["energy"].size:
        works = ", ".join(f"{name[5:]} {float(r[name][-1]):+.3g}" for name in
                          ("work_rigid", "work_film", "work_asperity", "work_contact", "work_impacts", "work_damping")
                          if name in r and float(np.abs(r[name]).max()) > 0.0)
        rows.append(("energy", f"peak {float(r['energy'].max()):.4g} J; work to the end [J]: {works or 'none'}; "
                               f"balance residual {a['energy_residual_relative']:.1e} of the largest term"
                               + (" (the samples are too coarse for the budget: a smaller solver.output_step "
                                  "tightens it)" if a["energy_residual_relative"] > 1e-2 else "")))
    if a.get("contact_warning"):
        rows.append(("warning", a["contact_warning"]))
    backend = a["backend"] + (f" ({a['backend_note']})" if a["backend_note"] else "")
    note = f" ({a['solver_note']})" if a.get("solver_note") else ""
    rows.append(("solver", f"{a['solver_method']}{note}, {a['nsteps']} steps, {a['nfev']} right-hand-side "
                           f"evaluations, backend {backend}"))
    budget = _budget(r)
    rows.append(("wall time", f"{a['wall_time']:.3f} s integration" + (f", {wall:.3f} s in all" if wall is not None else "")
                 + (f" (budget solver.max_wall_time = {budget:g} s)" if budget is not None else "")))
    if path is not None:
        rows.append(("wrote", str(path)))
    width = max(len(k) for k, _ in rows)
    return "\n".join(f"{k:<{width}}  {v}" for k, v in rows)

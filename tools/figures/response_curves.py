"""Draw the figures of docs/periodic.md: response curves over the crank speed, and a period doubling.

    python tools/figures/response_curves.py [OUTDIR] [--keep]      # default docs/figures; about 1.5 min on 2 cores

Each curve is a branch of :func:`lubelink.continuation` (with ``--keep``, the branch files are
written beside the figures as ``response-*.nc``); the crosses are the peak midpoint deflection over the last turn of
long transients from rest at a few speeds, computed independently with :func:`lubelink.simulate`.
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

import lubelink
from lubelink.link.kinematics import slider_crank
from lubelink.netcdf import save
from lubelink.plots.units import log_scale

ZETA = 0.01
SPEEDS = (5.0, 60.0)


def transient_peak(scenario, settings, speed, seconds=8.0):
    """Peak |u2_mid| over the last crank turn of a run from rest of ``seconds`` (at least 20 turns) [m]."""
    T = 2 * math.pi / speed
    turns = max(20, math.ceil(seconds / T))
    ds = lubelink.simulate(scenario, {**settings, "mechanism.crank_speed": speed, "solver.t_end": turns * T,
                                      "solver.output_step": T / 400})
    last = ds.u2_mid.values[-401:]
    return float(np.max(np.abs(last))), ds.attrs["status"]


def quasi_static_peak(config, speed):
    """Peak of the one-mode quasi-static midpoint deflection ``f_1(t) / omega_1^2`` over a turn [m] (docs/model.md §10.2)."""
    m, b = config.mechanism, config.beam
    L = m.rod_length
    beta = math.pi / L
    w1 = beta**2 * math.sqrt(b.youngs_modulus * b.second_moment / (b.density * b.area))
    t = np.linspace(0, 2 * math.pi / speed, 2001)
    k = slider_crank(t, m.crank_length, L, speed, m.guide_distance)
    return float(np.max(np.abs(2 / (L * beta) * (2 * k["A_O2"] + k["alpha"] * L)))) / w1**2


def _save(fig, path):
    """Write a figure atomically (the project's writer)."""
    from lubelink.results import atomic_path

    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110)


def branch(name, scenario, settings, out, keep=False):
    began = time.perf_counter()
    ds = lubelink.continuation(scenario, settings, start=SPEEDS[0], stop=SPEEDS[1])
    if keep:
        save(ds, out / f"response-{name}.nc", overwrite=True)
    print(f"{name}: {ds.point.size} orbits in {time.perf_counter() - began:.1f} s, {ds.attrs['status']} "
          f"({ds.attrs['message']}); bifurcations: {ds.attrs['bifurcations']}")
    return ds


def main(out="docs/figures", keep=False):
    import matplotlib

    matplotlib.use("Agg")
    from lubelink.plots._style import MM, _figure, _style
    from lubelink.steady.plot import figure_branch, plot_branch, resonances, _mark_resonances

    out = Path(out)
    dry_settings = {"beam.damping_ratio": ZETA}
    dry = branch("dry", "paper-dry", dry_settings, out, keep)
    film = branch("film", "paper", dry_settings, out, keep)
    squeeze = branch("squeeze", "paper", {**dry_settings, "film.model": "wedge+squeeze"}, out, keep)

    # --- the dry link: response curve, transients, and the dynamic amplification --------------------
    speeds = [10.0, 25.0, 40.0, 49.4, 58.0]
    peaks = [transient_peak("paper-dry", dry_settings, w)[0] for w in speeds]
    config = lubelink.resolve_config("paper-dry", dry_settings)
    with _style():
        fig = _figure(8.0, 7.0)
        ax1, ax2 = fig.subplots(2, 1, sharex=True, height_ratios=[3, 2])
        plot_branch(dry, ax1, label=f"periodic response (continuation), zeta = {ZETA}")
        ax1.plot(speeds, np.array(peaks) * MM, "x", color="k", ms=7, mew=1.5, label="last turn of a transient")
        if log_scale(np.append(dry.peak_u2_mid.values, peaks)):
            ax1.set_yscale("log")
        ax1.set_xlabel("")
        ax1.legend(loc="lower right", fontsize=8)
        ratio = dry.peak_u2_mid.values / np.array([quasi_static_peak(config, w) for w in dry.parameter.values])
        ax2.plot(dry.parameter.values, ratio, color="C0", lw=1.4)
        ax2.set_ylabel("peak / quasi-static peak")
        ax2.set_xlabel("crank speed omega0 [rad/s]")
        for ax in (ax1, ax2):
            ax.set_xlim(SPEEDS)
            _mark_resonances(ax, resonances(dry))
        fig.suptitle("Dry link, 1 mode: periodic response against crank speed (resonances omega_1/k dotted)")
        _save(fig, out / "response-dry.png")

    # --- with the film ------------------------------------------------------------------------------
    film_speeds = [20.0, 36.0, 38.0, 45.0]
    film_peaks = [transient_peak("paper", dry_settings, w) for w in film_speeds]
    fig = figure_branch({"dry": dry, "wedge film (paper)": film, "wedge + squeeze film": squeeze},
                        transients={"wedge film: last turn of a transient": (film_speeds, [p for p, _ in film_peaks])},
                        title=f"Periodic response against crank speed, zeta = {ZETA}: dry, paper's film, full film")
    _save(fig, out / "response-film.png")
    print("film transients:", ", ".join(f"{w:g} rad/s {p * 1e3:.4f} mm ({s})" for w, (p, s) in
                                        zip(film_speeds, film_peaks)))

    # --- the period doubling at 38 rad/s ------------------------------------------------------------
    speed = 38.0
    T = 2 * math.pi / speed
    settings = {**dry_settings, "mechanism.crank_speed": speed, "solver.output_step": T / 200}
    one = lubelink.periodic("paper", settings)
    two = lubelink.periodic("paper", settings, periods=2, warmup=20)
    run = lubelink.simulate("paper", {**settings, "solver.t_end": 60 * T})
    mu1 = float(one.floquet_modulus[0] * np.cos(one.floquet_argument[0]))  # the real multiplier
    with _style():
        fig = _figure(8.0, 4.2)
        ax = fig.subplots()
        ax.plot(run.time.values[-401:] - 58 * T, run.u2_mid.values[-401:] * MM, color="0.6", lw=4,
                label="transient from rest, turns 59-60")
        t1 = one.time.values
        u1 = one.u2_mid.values * MM
        ax.plot(np.r_[t1, t1[1:] + T], np.r_[u1, u1[1:]], "--", color="C3", lw=1.3,
                label=f"period-1 response: unstable, multiplier {mu1:.3f}")
        ax.plot(two.time.values, two.u2_mid.values * MM, color="C0", lw=1.3,
                label=f"period-2 response: stable, |multipliers| {two.floquet_modulus.values[0]:.3f}")
        ax.set_xlabel("time in the response [s]")
        ax.set_ylabel("u2_mid [mm]")
        ax.legend(fontsize=8, loc="lower left")
        ax.set_title(f"Paper's film, zeta = {ZETA}, omega0 = {speed:g} rad/s: the steady state takes two crank turns")
        _save(fig, out / "period-doubling.png")
    print(f"period doubling at {speed} rad/s: period-1 multipliers {one.floquet_modulus.values}, "
          f"period-2 {two.floquet_modulus.values}")


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if a != "--keep"]
    main(*args[:1], keep="--keep" in sys.argv[1:])

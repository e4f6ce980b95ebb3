"""The study: every configuration of the paper's figures simulated once, and the lubrication effect.

A :class:`Study` runs simulations on demand and keeps their results, keyed by
the resolved configuration and the equation variant, so the figures that
share a run (Figs. 6 and 8, the lubrication table and Fig. 7, ...) compute
it once. :func:`lubrication_effect` compares the peak deflection with a film
against the dry joint over viscosity and clearance, and
:func:`lubrication_table` writes it as Markdown.
"""

from __future__ import annotations

import numpy as np

from .variants import simulate_variant

__all__ = ["Study", "lubrication_effect", "lubrication_table"]


class Study:
    """Runs simulations on demand, each distinct configuration and variant once.

    Parameters
    ----------
    overrides : dict, optional
        Applied to every configuration (e.g. the output resolution).
    progress : callable, optional
        ``progress(label)`` before every new simulation.
    """

    def __init__(self, overrides=None, progress=None):
        self.overrides = dict(overrides or {})
        self.progress = progress
        self._results = {}

    def config(self, source="paper", set=None):
        from ..config import resolve

        return resolve(source, {**self.overrides, **(set or {})})

    def dataset(self, source="paper", set=None, variant="corrected", label=None):
        """Results of ``source`` with ``set`` (after the study's overrides), computed once."""
        from ..config import to_toml

        config = self.config(source, set)
        key = (to_toml(config), variant)
        if key not in self._results:
            if self.progress is not None:
                self.progress(label or f"{source} {set or ''} {variant}".strip())
            self._results[key] = simulate_variant(config, variant=variant)
        return self._results[key]

    @property
    def runs(self) -> int:
        """Number of distinct simulations run so far."""
        return len(self._results)



def lubrication_effect(viscosities=(0.01, 0.1, 1.0), clearances=(3e-3, 6e-3),
                       models=("wedge", "wedge+squeeze"), study=None):
    """Peak midpoint deflection with a film against the dry joint.

    Parameters
    ----------
    viscosities : sequence of float
        ``mu`` [Pa s].
    clearances : sequence of float
        ``H`` [m].
    models : sequence of str
        Film models.
    study : Study, optional
        Reuses its runs (and its overrides).

    Returns
    -------
    xarray.Dataset
        On ``(model, viscosity, clearance)``: ``peak`` (peak ``|u2_mid|`` [m]),
        ``peak_dry`` [m], ``change`` (``peak / peak_dry - 1`` [-]),
        ``smaller_fraction`` (fraction of samples where ``|u2_mid|`` is
        smaller than dry [-]), ``rms_difference`` [m], ``film_min`` (thinnest
        film [m]) and ``status`` of each run.
    """
    import xarray as xr

    study = study or Study()
    dry = study.dataset("paper-dry", label="paper-dry")
    u_dry = np.abs(dry.u2_mid.values)
    shape = (len(models), len(viscosities), len(clearances))
    out = {k: np.full(shape, np.nan) for k in ("peak", "smaller_fraction", "rms_difference", "film_min")}
    status = np.empty(shape, dtype=object)
    for i, model in enumerate(models):
        for j, mu in enumerate(viscosities):
            for k, H in enumerate(clearances):
                ds = study.dataset("paper", {"film.model": model, "film.viscosity": float(mu),
                                             "film.clearance": float(H)},
                                   label=f"{model} mu={mu:g} H={H * 1e3:g}mm")
                u = np.abs(ds.u2_mid.values)
                n = min(u.size, u_dry.size)
                out["peak"][i, j, k] = u.max()
                out["smaller_fraction"][i, j, k] = np.mean(u[:n] < u_dry[:n])
                out["rms_difference"][i, j, k] = np.sqrt(np.mean((ds.u2_mid.values[:n] - dry.u2_mid.values[:n]) ** 2))
                out["film_min"][i, j, k] = float(ds.film_min.min())
                status[i, j, k] = ds.attrs["status"]
    dims = ("model", "viscosity", "clearance")
    peak_dry = float(u_dry.max())
    return xr.Dataset(
        {
            "peak": (dims, out["peak"], {"units": "m", "long_name": "peak |u2_mid| with the film"}),
            "peak_dry": ((), peak_dry, {"units": "m", "long_name": "peak |u2_mid| of the dry joint"}),
            "change": (dims, out["peak"] / peak_dry - 1.0, {"units": "1", "long_name": "peak / peak_dry - 1"}),
            "smaller_fraction": (dims, out["smaller_fraction"],
                                 {"units": "1", "long_name": "fraction of time |u2_mid| below the dry joint's"}),
            "rms_difference": (dims, out["rms_difference"], {"units": "m", "long_name": "rms of u2_mid - dry"}),
            "film_min": (dims, out["film_min"], {"units": "m", "long_name": "thinnest film"}),
            "status": (dims, status.astype(str)),
        },
        coords={"model": list(models), "viscosity": ("viscosity", list(viscosities), {"units": "Pa s"}),
                "clearance": ("clearance", list(clearances), {"units": "m"})},
        attrs={"t_end": float(dry.time[-1])},
    )


def lubrication_table(effect):
    """Markdown table of :func:`lubrication_effect` (mm, %, µm)."""
    rows = ["| film | mu [Pa s] | H [mm] | peak with film [mm] | dry [mm] | change | time below dry | "
            "rms difference [µm] | thinnest film [mm] |",
            "|---|---|---|---|---|---|---|---|---|"]
    dry = float(effect.peak_dry)
    for model in effect.model.values:
        for mu in effect.viscosity.values:
            for H in effect.clearance.values:
                e = effect.sel(model=model, viscosity=mu, clearance=H)
                note = "" if str(e.status.values) == "complete" else f" ({e.status.values})"
                rows.append(f"| {model} | {mu:g} | {H * 1e3:g} | {float(e.peak) * 1e3:.4f}{note} | {dry * 1e3:.4f} | "
                            f"{float(e.change) * 100:+.2f} % | {float(e.smaller_fraction) * 100:.0f} % | "
                            f"{float(e.rms_difference) * 1e6:.1f} | {float(e.film_min) * 1e3:.4f} |")
    return "\n".join(rows) + "\n"

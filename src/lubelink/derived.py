"""The series a run's results derive from its samples beside the state: stresses, the energy budget, the second
face pair of the spatial link, the contact force (called by :func:`lubelink.results.collect`)."""

from __future__ import annotations

import numpy as np

from .variables import entry as _entry


def _select(kernel, compiled):
    return kernel if compiled else kernel.py_func


def stress_field(result, q, y_state, x):
    """:func:`~lubelink.link.section.bending_stress` of the run's section (spatial: both directions, a corner) [Pa]."""
    from .link.section import bending_stress, taper

    model, cfg = result.model, result.model.config
    E, L = cfg.beam.youngs_modulus, cfg.mechanism.rod_length
    sec = result.section or taper(cfg.beam, L)
    stress = bending_stress(sec, E, q, x, L)
    if model.params.spatial is not None:
        q3 = np.asarray(model.block_state(y_state, 2))[:, :model.modes]
        stress += bending_stress(sec, E, q3, x, L, "second_moment_y")
    return stress


_ENERGY = ("energy", "work_rigid", "work_damping", "work_film", "work_asperity", "work_reaction", "work_contact",
           "work_impacts", "energy_residual", "impact_energy_change", "impact_dissipation", "impact_collar_work")


def energy_budget(result, want, t, y, data):
    """Add the energy budget's variables (:mod:`lubelink.energy`) to ``data``; return ``(note, largest residual [J],
    relative to the largest energy or work)``."""
    from . import energy

    if not any(name in want for name in _ENERGY):
        return "not asked for", np.nan, np.nan
    side = result.phase_side if result.phase_side is not None else np.zeros(t.size)
    series, (change, loss, collar), residual = energy.of_run(result, t, y, side)
    for name, value in series.items():
        if name in want:
            data[name] = _entry(name, value)
    for name, value in (("impact_energy_change", change), ("impact_dissipation", loss),
                        ("impact_collar_work", collar)):
        if name in want and result.model.config.contact.law == "restitution":
            data[name] = _entry(name, value)
    scale = max(float(np.max(np.abs(value))) for name, value in series.items() if name != "energy_residual")
    return ("works by Simpson's rule over the samples and the impacts; the residual is the integration error and "
            "the quadrature error of the sampling (refine solver.output_step if it matters)",
            residual, residual / scale if scale > 0.0 else 0.0)


def u3_faces(model, want, y_state, x_star, V_r):
    """The variables of the spatial model's film pair on the ``u3`` faces: the planar batched kernels on the ``q3`` block."""
    from . import film
    from .film.asperity import asperity_force_many
    from .link.model import thinnest_many

    p, N, cfg = model.params, model.modes, model.config
    L, compiled = cfg.mechanism.rod_length, model.compiled
    y3 = np.ascontiguousarray(model.block_state(y_state, 2))
    q3, q3_t = np.ascontiguousarray(y3[:, :N]), np.ascontiguousarray(y3[:, N:])
    out = {}
    if (cfg.film.enabled or cfg.contact.law != "none") and "film_min_u3" in want:
        out["film_min_u3"] = _entry("film_min_u3", _select(thinnest_many, compiled)(x_star, y3, p))
    if cfg.film.enabled and "film_force_u3" in want:
        out["film_force_u3"] = _entry("film_force_u3", _select(film.film_force_many, compiled)(
            q3, q3_t, x_star, V_r, p.film, p.beam.height, p.pad, L))
    if cfg.film.roughness > 0.0 and "asperity_force_u3" in want:
        out["asperity_force_u3"] = _entry("asperity_force_u3", _select(asperity_force_many, compiled)(
            q3, x_star, p.film, p.beam.height, p.pad, L))
    return out


def contact_force(result, model, t, y, side):
    """Contact force at every sample [N]: the sustained contact's multiplier or the compliant force, 0 when free."""
    force = np.zeros(t.size)
    inside = np.flatnonzero(side != 0)
    if inside.size == 0:
        return force
    if model.config.contact.law == "restitution":
        force[inside] = model.sustained_force(t[inside], y[inside], side[inside], result.phase_point[inside])
    else:
        force[inside] = model.compliant_loads(t[inside], y[inside], side[inside], result.phase_v[inside])[0]
    return force

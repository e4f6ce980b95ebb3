"""The series a run's results derive from its samples beside the state: stresses, the energy budget, the second
face pair of the spatial link, the contact force (called by :func:`lubelink.results.collect`)."""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from .variables import entry as _entry


def _select(kernel, compiled):
    return kernel if compiled else kernel.py_func


#: Pieces of the pad between the points where :func:`film_losses` takes the pressure (even): the extrapolated
#: midpoint rule's error falls as their number to the fourth, 2e-7 of the friction and the power loss at 16 on a
#: squeeze film deflected by three modes (tests/test_shear.py).
LOSS_PIECES = 16


def film_losses(model, q, q_dot, x_star, V_r):
    """``(friction [N], power loss [W], moment [N m])`` of the films: their viscous shear on the link along +i, shape
    ``(sides, T)``, the power they dissipate and the moment of their pressure on the link about O (+k), both sides
    summed (:func:`lubelink.film.shear.film_losses_many`; the 1-D film only)."""
    from .film import pad_pressure_many, pressure_points
    from .film.shear import film_losses_many, midpoint_tables

    cfg, p, compiled = model.config, model.params, model.compiled
    fm, L, N = cfg.film, cfg.mechanism.rod_length, model.modes
    X = np.linspace(0.0, fm.pad_length, LOSS_PIECES + 1)
    tables = pressure_points(X, N, L, 4, fm.grid_points if fm.cavitation == "reynolds" else 0)
    mid = midpoint_tables(X, N, L)
    friction, loss, moment = [], np.zeros(q.shape[0]), np.zeros(q.shape[0])
    for side in model.sides:
        pressure = _select(pad_pressure_many, compiled)(X, q, q_dot, x_star, V_r, float(side), p.film, L, *tables)
        f, d, m = _select(film_losses_many, compiled)(X, pressure, q, x_star, V_r, float(side), p.film, p.beam.width,
                                                      L, *mid)
        friction.append(f)
        loss += d
        moment += m
    return np.array(friction), loss, moment


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
        out["film_min_u3"] = _entry("film_min_u3", _select(thinnest_many, compiled)(x_star, y3, p)[:, 0])
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


@lru_cache(maxsize=16)
def _uniform_inertia(beam, rod_length, modes):
    """:func:`~lubelink.link.reactions.link_inertia` of the link of ``beam`` (its taper), once per configuration."""
    from .link.reactions import link_inertia
    from .link.section import taper

    return link_inertia(taper(beam, rod_length), beam.density, rod_length, modes)


#: The joint reactions' variables (:func:`joint_reactions`).
REACTIONS = ("crank_pin_force_X", "crank_pin_force_Y", "slider_pin_force", "collar_force", "guide_force")


def reactions_apply(model):
    """Why the joint reactions are not computed for ``model``, or ``""``: the planar slider-crank with a 1-D film."""
    from .link.kinematics import SLIDER_CRANK

    table = model.motion.table()
    if model.params.spatial is not None:
        return "the spatial link"
    if table is None or table.kind != SLIDER_CRANK:
        return "a motion other than the slider-crank's"
    if model.config.film.enabled and model.config.film.reynolds != "1d":
        return "a film of finite width"
    return ""


def modal_accelerations(result, t, y):
    """``q_ddot`` [m/s^2] ``(T, N)`` of the sine modes at the samples ``t`` of ``result`` (a
    :class:`~lubelink.results.Run`) with states ``y`` ``(T, 2N)``: its right-hand side, in the contact phase of each
    sample."""
    from .link.model import rates_many

    model = result.model
    rates = _select(rates_many, model.compiled)(t, np.ascontiguousarray(model.to_state(y)), model.params)
    side = result.phase_side if result.phase_side is not None else np.zeros(t.size)
    v = result.phase_v if result.phase_v is not None else np.zeros(t.size)
    point = result.phase_point if result.phase_point is not None else np.zeros(t.size)
    for i in np.flatnonzero(side):
        rates[i] = model.rhs(t[i], model.to_state(y[i]), (side[i], v[i], point[i]))
    return model.to_physical(rates)[:, model.modes:]


def joint_reactions(result, t, y, losses, data, thinnest=None):
    """The forces of the crank pin, the slider pin and the collar on the link and the guide's force on the collar's
    member [N] at the samples (:func:`lubelink.link.reactions.joint_reactions`), for the variables of :data:`REACTIONS`.

    ``y``: sine-mode states; ``losses``: :func:`film_losses`' ``(friction per side, loss, moment)`` (None without a
    film); ``data`` holds ``film_force``, ``asperity_force`` and ``contact_force`` where they apply. The collar's loads:
    the film's pressure (its resultant and moment), the films' shear at the faces ``+-c`` from the axis (``c``, the
    outer fibre), the asperity and contact forces at the thinnest film's point (a sustained contact's at its point)
    and the joint reaction of the collar's mass at ``x_star``. ``thinnest``: :func:`~lubelink.link.model.thinnest_many`
    at the samples when the caller has it (computed here where it is needed otherwise).
    """
    from .link.kinematics import motion_at
    from .link.model import thinnest_many
    from .link.reactions import crank_pin_acceleration, joint_reactions as reactions, link_inertia
    from .link.section import taper

    model, cfg = result.model, result.model.config
    N, L, m = model.modes, cfg.mechanism.rod_length, cfg.mechanism
    kin = motion_at(t, model.params.motion)  # (its Python source: the slider-crank's closed form, elementwise)
    q_ddot = modal_accelerations(result, t, y)
    side = result.phase_side if result.phase_side is not None else np.zeros(t.size)
    sec = result.section or taper(cfg.beam, L)
    normal = kin.reaction * np.ones(t.size)
    moment = normal * kin.x_star
    along = np.zeros(t.size)
    if losses is not None:
        fibre = np.sqrt(3.0 * sec.profile("second_moment")(kin.x_star) / sec.profile("area")(kin.x_star))
        friction, _, film_moment = losses
        for s, f in zip(model.sides, friction):
            along += f
            moment -= s * fibre * f
        normal = normal + data["film_force"][1]
        moment += film_moment
    point_loads = np.zeros(t.size)
    if "asperity_force" in data:
        point_loads += data["asperity_force"][1]
    if "contact_force" in data:
        point_loads -= side * data["contact_force"][1]
    if np.any(point_loads):  # at the thinnest film, or where a sustained contact holds
        lever = np.zeros(t.size)
        held = (side != 0) & (cfg.contact.law == "restitution")
        free = np.flatnonzero((point_loads != 0.0) & ~held)
        if thinnest is None:
            lever[free] = _select(thinnest_many, model.compiled)(np.ascontiguousarray(kin.x_star[free]),
                                                                  np.ascontiguousarray(y[free]), model.params)[:, 1]
        else:
            lever[free] = thinnest[free, 1]
        for i in np.flatnonzero(held):
            lever[i] = model.contact_position(t[i], (side[i], result.phase_v[i], result.phase_point[i]))
        normal = normal + point_loads
        moment += point_loads * lever
    inertia = (_uniform_inertia(cfg.beam, L, N) if result.section is None
               else link_inertia(sec, cfg.beam.density, L, N))
    X, Y, C = reactions(inertia, L, kin.angle, crank_pin_acceleration(t, m.crank_length, m.crank_speed), kin.omega,
                        kin.alpha, y[:, :N], y[:, N:], q_ddot, (along, normal, moment), m.gravity)
    c, s = np.cos(kin.angle), np.sin(kin.angle)
    return {"crank_pin_force_X": X, "crank_pin_force_Y": Y, "slider_pin_force": C, "collar_force": normal,
            "guide_force": along * c - normal * s}


def crank_period(model):
    """The crank's period [s] of a slider-crank (planar or spatial), or None for another motion."""
    from .link.kinematics import SliderCrank
    from .link.spatial_motion import SpatialSliderCrank

    if isinstance(model.motion, (SliderCrank, SpatialSliderCrank)):
        return 2.0 * np.pi / abs(model.config.mechanism.crank_speed)
    return None


#: The per-revolution variables (:func:`revolutions`) and the series each reads.
PER_REVOLUTION = {"revolution_peak_u2_mid": "u2_mid", "revolution_peak_stress": "bending_stress",
                  "revolution_film_min": "film_min", "revolution_film_loss": "film_power_loss",
                  "revolution_energy_lost": None}


def revolutions(t, period, data, impacts_lost):
    """Statistics of each whole revolution of the crank in the samples ``t`` [s]: ``{name: values}`` of
    :data:`PER_REVOLUTION` (those whose series ``data`` holds) and ``revolution_start`` [s].

    Peaks and the thinnest film over the samples of ``[(k - 1) T, k T)``; the film's loss is the integral of its power
    (trapezoidal rule, its cumulative integral interpolated at the revolution's ends); the energy lost adds the
    structural damping's dissipation (``-work_damping``) and the impacts' (``impacts_lost``: ``(time, loss)``).
    """
    count = int(np.floor(t[-1] / period * (1.0 + 1e-12))) if t.size > 1 else 0
    out = {"revolution_start": period * np.arange(count)}
    edges = period * np.arange(count + 1)
    starts = np.searchsorted(t, edges - 1e-12 * period)
    if count == 0 or np.any(np.diff(starts) < 2):  # samples sparser than the crank's turns: no statistics
        return out

    def over(series, reduce):
        return reduce.reduceat(series[:starts[-1]], starts[:-1])

    def integral(power):
        cumulative = np.concatenate([[0.0], np.cumsum(0.5 * (power[1:] + power[:-1]) * np.diff(t))])
        return np.diff(np.interp(edges, t, cumulative))

    for name, source in PER_REVOLUTION.items():
        if source is None or source not in data:
            continue
        series = np.asarray(data[source][1])
        if name == "revolution_peak_stress":
            out[name] = over(series.max(axis=-1) if series.ndim > 1 else series, np.maximum)
        elif name == "revolution_peak_u2_mid":
            out[name] = over(np.abs(series), np.maximum)
        elif name == "revolution_film_min":
            out[name] = over(series, np.minimum)
        else:
            out[name] = integral(series)
    lost = out.get("revolution_film_loss", np.zeros(count)).copy()
    if "work_damping" in data:
        lost -= np.diff(np.interp(edges, t, np.asarray(data["work_damping"][1])))
    when, loss = impacts_lost
    if len(when):
        lost += np.histogram(when, bins=edges, weights=loss)[0]
    out["revolution_energy_lost"] = lost
    return out

"""What a sweep stores and how its parameters are named: the shared vocabulary of the package.

The store format version, the summary quantities and time series a point can keep (with their
units), the parameters that can be swept (with units and long names read from
:mod:`lubelink.params`), :class:`SweepError` and the formatting of a value in messages.
No heavy imports.
"""

from __future__ import annotations

from dataclasses import fields

__all__ = ["SWEEP_FORMAT", "QUANTITIES", "DEFAULT_QUANTITIES", "ALWAYS", "SERIES", "SPATIAL_COMPANIONS",
           "SweepError", "with_spatial_companions"]

#: Version of the store layout; :func:`load_sweep` and resuming refuse other major versions.
SWEEP_FORMAT = "1.1"

#: Summary quantities per point: name -> (units, long name, kind). ``kind`` is
#: ``"f"`` (float, NaN when absent), ``"i"`` (integer, -1 when absent) or
#: ``"impacts"`` (floats along an extra ``impact`` dimension) or ``"s"`` (a string).
QUANTITIES = {
    "peak_u2_mid": ("m", "peak absolute midpoint deflection, max |u2_mid|", "f"),
    "impact_count": ("1", "number of impacts", "i"),
    "first_impact_time": ("s", "time of the first impact (NaN: no impact)", "f"),
    "peak_pressure": ("Pa", "peak absolute gauge film pressure, max |P - p_am| (NaN: no film)", "f"),
    "min_film": ("m", "thinnest film on the pad (NaN: gap not monitored)", "f"),
    "peak_film_force": ("N", "peak absolute film force on the link (NaN: no film)", "f"),
    "end_time": ("s", "simulated time reached (solver.t_end unless the run ended early)", "f"),
    "nfev": ("1", "right-hand-side evaluations", "i"),
    "impact_times": ("s", "times of the first store.max_impacts impacts (NaN: fewer impacts)", "impacts"),
    "peak_u3_mid": ("m", "peak absolute out-of-plane midpoint deflection, max |u3_mid| (NaN: planar model)", "f"),
    "peak_axial": ("m", "peak absolute axial displacement over the link, max |u1| (NaN: planar model)", "f"),
    "peak_asperity_force": ("N", "peak absolute asperity contact force on the link (NaN: smooth surfaces)", "f"),
    "peak_contact_force": ("N", "peak contact force of the collar on the link (NaN: no contact law)", "f"),
    "peak_stress": ("Pa", "peak bending stress in the link, max bending_stress", "f"),
    "peak_film_friction": ("N", "peak absolute viscous friction force of the films on the link (NaN: no 1-D film)",
                           "f"),
    "mean_film_power_loss": ("W", "power lost in the films, averaged over the samples (NaN: no 1-D film)", "f"),
    "peak_crank_pin_force": ("N", "peak crank pin force on the link, max |(R_OX, R_OY)| (NaN: not the planar "
                                  "slider-crank with a 1-D film or none)", "f"),
    "peak_slider_pin_force": ("N", "peak absolute slider pin force on the link (NaN: as peak_crank_pin_force)", "f"),
    "regime": ("1", "lubrication regime: full film, mixed (the asperities' peak force over 1 % of the film's), "
                    "contact (impacts, contact force or breakdown) or dry (no film)", "s"),
}
#: What a sweep with spatial points (``beam.model = "spatial"``) stores beside a quantity or time
#: series it stores: the out-of-plane (and axial) twins of the in-plane ones.
SPATIAL_COMPANIONS = {"peak_u2_mid": ("peak_u3_mid", "peak_axial"), "u2_mid": ("u3_mid",), "u2": ("u3",)}
#: Stored when ``[store] quantities`` is not given (and, with spatial points, their companions).
DEFAULT_QUANTITIES = tuple(q for q in QUANTITIES if q not in ("impact_times", "peak_asperity_force", "peak_contact_force",
                                                               "regime", "peak_stress", "peak_film_friction",
                                                               "mean_film_power_loss", "peak_crank_pin_force",
                                                               "peak_slider_pin_force")
                           and not any(q in c for c in SPATIAL_COMPANIONS.values()))
#: Always stored for every point, whatever ``quantities`` says.
ALWAYS = {
    "status": ("1", "outcome: complete, film_breakdown, chatter, penetration, solver_failure, timeout, out_of_domain, "
                    "error, worker_died or invalid"),
    "message": ("1", "why the point ended (the error for a failed point), then a penetration of the collar face"),
    "wall_time": ("s", "wall-clock time of the simulation on its worker"),
}
#: Time series that ``[store] time_series`` may keep: name -> extra dimension
#: (after ``time``) and the parameters that fix that dimension's coordinate.
SERIES = {
    "u2_mid": (None, ()),
    "x_star": (None, ()),
    "V_r": (None, ()),
    "film_min": (None, ()),
    "film_force": (None, ()),
    "q": ("mode", ("beam.modes",)),
    "q_dot": ("mode", ("beam.modes",)),
    "u2": ("x", ("mechanism.rod_length", "output.x_points")),
    "pressure": ("x_pad", ("film.pad_length", "output.pad_points")),
    "u3_mid": (None, ()),
    "u3": ("x", ("mechanism.rod_length", "output.x_points")),
    "u1": ("x", ("mechanism.rod_length", "output.x_points")),
}


def with_spatial_companions(names) -> tuple:
    """``names`` with each one's :data:`SPATIAL_COMPANIONS` after it (those not already there)."""
    out = []
    for name in names:
        out += [name] if name not in out else []
        out += [c for c in SPATIAL_COMPANIONS.get(name, ()) if c not in names and c not in out]
    return tuple(out)


class SweepError(RuntimeError):
    """A sweep that cannot start or go on: store of another sweep, store in use, no scheduler."""


# ====================================================================== parameters
def _parameters():
    """``{"section.key": (field type, units, long name)}`` of every parameter.

    Units and long names come from :data:`lubelink.fields.FIELDS`, the table ``lubelink config``
    comments its keys from.
    """
    from ..fields import FIELDS
    from ..params import SECTION_TYPES

    out = {}
    for section, cls in SECTION_TYPES.items():
        for f in fields(cls):
            units, _, long_name = FIELDS.get(f"{section}.{f.name}", ("", "", f.name))
            ftype = f.type if isinstance(f.type, str) else getattr(f.type, "__name__", str(f.type))
            out[f"{section}.{f.name}"] = (ftype, units, long_name or f.name)
    return out


def _fmt(v):
    """A value as it is written in messages and labels (floats to 6 significant digits; long
    values shortened as :func:`lubelink.config._fmt` does)."""
    if isinstance(v, float):
        return f"{v:.6g}"
    from ..config import _fmt as quoted

    return quoted(v)

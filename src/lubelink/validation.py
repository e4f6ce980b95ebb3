"""Validation of a configuration: the rule of every key (:data:`RULES`), the checks across keys
(:func:`validate`), and how messages quote values.

Every problem found is collected and reported together, one line each, naming the section, the
key, the value and the rule (:class:`ConfigError`). The rules' texts are also what ``lubelink
config`` prints beside each key (:mod:`lubelink.template`).
"""

from __future__ import annotations

import math

from .errors import ConfigError
from .params import CHOICES, Config

__all__ = ["ConfigError", "RULES", "validate", "MAX_SAMPLES"]


# ----------------------------------------------------------------- rules
def _bound(v):
    """A bound as rules show it: ``1e6`` for 1000000.0, otherwise as Python writes it."""
    if isinstance(v, float) and v.is_integer() and abs(v) >= 1e4:
        mantissa, exponent = f"{v:.6e}".split("e")
        return f"{mantissa.rstrip('0').rstrip('.')}e{int(exponent)}"
    return str(v)


def _num(lo=None, hi=None, lo_open=False, hi_open=False, integer=False, allow_inf=False):
    """A rule for a number in an interval; returns (check, text)."""
    left = "(" if lo_open else "["
    right = ")" if hi_open else "]"
    kind = "an integer" if integer else "a number"
    text = f"{kind} in {left}{'-inf' if lo is None else _bound(lo)}, {'inf' if hi is None else _bound(hi)}{right}"

    def check(v):
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            return False
        if integer and not isinstance(v, int):
            return False
        if isinstance(v, int) and abs(v) > _FLOAT_MAX:  # beyond any range here, and beyond a float
            return False
        if math.isnan(v) or (math.isinf(v) and not allow_inf):
            return False
        if lo is not None and (v < lo or (lo_open and v == lo)):
            return False
        if hi is not None and (v > hi or (hi_open and v == hi)):
            return False
        return True

    return check, text


#: Largest finite float; an integer beyond it cannot be converted (``OverflowError``).
_FLOAT_MAX = 1.7976931348623157e308


def _choice(options):
    def check(v):
        return not isinstance(v, bool) and isinstance(v, (str, int)) and v in options

    return check, "one of " + ", ".join(f'"{o}"' if isinstance(o, str) else str(o) for o in options)


RULES = {
    "mechanism": {
        "crank_length": _num(0, 100, lo_open=True),
        "rod_length": _num(0, 1000, lo_open=True),
        "crank_speed": _num(-1e4, 1e4),
        "guide_distance": _num(0, 1000, lo_open=True),
        "gravity": (lambda v: isinstance(v, tuple) and len(v) == 2 and all(_num(-1e3, 1e3)[0](c) for c in v),
                    "a pair [g_X, g_Y] of numbers in [-1000, 1000] m/s^2"),
        "crank_tilt": _num(-1.2, 1.2),
        "slider_offset": _num(-1000, 1000),
    },
    "beam": {
        "youngs_modulus": _num(1e6, 1e13),
        "density": _num(1, 1e5),
        "width": _num(0, 10, lo_open=True),
        "height": _num(0, 10, lo_open=True),
        "modes": _num(1, 200, integer=True),
        "damping_ratio": _num(0, 1, hi_open=True),
        "width_ratio": _num(0.01, 100),
        "height_ratio": _num(0.01, 100),
        "model": _choice(CHOICES["beam.model"]),
        "yield_strength": _num(0, None, lo_open=True, allow_inf=True),
        "axial_end": _choice(CHOICES["beam.axial_end"]),
        "axial_force": _choice(CHOICES["beam.axial_force"]),
    },
    "film": {
        "model": _choice(CHOICES["film.model"]),
        "viscosity": _num(0, 1e4, lo_open=True),
        "clearance": _num(0, 1, lo_open=True),
        "pad_length": _num(0, 1000, lo_open=True),
        "pad_reference": _choice(CHOICES["film.pad_reference"]),
        "ambient_pressure": _num(0, 1e9),
        "quadrature_nodes": _num(4, 512, integer=True),
        "sides": _choice((1, 2)),
        "cavitation": _choice(CHOICES["film.cavitation"]),
        "cavitation_pressure": _num(0, 1e9),
        "grid_points": _num(11, 100001, integer=True),
        "reynolds": _choice(CHOICES["film.reynolds"]),
        "width_modes": _num(1, 200, integer=True),
        "width_series": _choice(CHOICES["film.width_series"]),
        "width_points": _num(4, 4096, integer=True),
        "thickness_floor": _num(0, 1e-2),
        "roughness": _num(0, 1e-3),
        "summit_product": _num(0, 1, lo_open=True),
        "summit_ratio": _num(0, 1, lo_open=True),
        "contact_modulus": _num(0, 1e13, lo_open=True),
        "faces": _choice(CHOICES["film.faces"]),
    },
    "collar": {"mass": _num(0, 1e6)},
    "contact": {
        "law": _choice(CHOICES["contact.law"]),
        "restitution": _num(0, 1),
        "min_film": _num(0, 1),
        "chatter_interval": _num(0, 1, lo_open=True),
        "stiffness": _num(0, 1e16, lo_open=True),
        "exponent": _num(1, 3),
        "extent": _choice(CHOICES["contact.extent"]),
        "face_stiffness": _num(0, 1e18, lo_open=True),
    },
    "model": {"equations": _choice(CHOICES["model.equations"])},
    "solver": {
        "method": _choice(CHOICES["solver.method"]),
        "rtol": _num(1e-13, 0.1),
        "atol": _num(0, 1, lo_open=True),
        "t_end": _num(0, 1e5, lo_open=True),
        "output_step": _num(0, None, lo_open=True),
        "max_step": _num(0, None, lo_open=True, allow_inf=True),
        "max_wall_time": _num(0, None, lo_open=True, allow_inf=True),
        "backend": _choice(CHOICES["solver.backend"]),
        "max_deflection": _num(0, None, lo_open=True, allow_inf=True),
        "max_slope": _num(0, None, lo_open=True, allow_inf=True),
        "max_axial_strain": _num(0, None, lo_open=True, allow_inf=True),
    },
    "output": {
        "x_points": _num(2, 10001, integer=True),
        "pad_points": _num(2, 1001, integer=True),
    },
    "drive": {
        "law": _choice(CHOICES["drive.law"]),
        "flywheel_inertia": _num(0, 1e6, lo_open=True),
        "torque": _num(-1e7, 1e7),
        "stall_torque": _num(-1e7, 1e7),
        "no_load_speed": _num(-1e4, 1e4),
        "proportional_gain": _num(0, 1e7),
        "integral_gain": _num(0, 1e9),
        "slider_mass": _num(0, 1e6),
        "slider_force": _num(-1e9, 1e9),
        "slider_friction": _num(0, 1e9),
        "coupling": _choice(CHOICES["drive.coupling"]),
    },
}

MAX_SAMPLES = 50_000_000  # time samples x points of u2, ~400 MB of float64


#: Longest value quoted in a message [characters]; longer ones are shortened.
MAX_QUOTED = 60


def _name(name):
    """A key or section name as messages show it (unquoted, shortened)."""
    text = _fmt(str(name))[1:-1] if len(str(name)) <= MAX_QUOTED - 2 else _fmt(str(name))
    return text


def _fmt(v):
    """A value as messages quote it: strings repr'd, long values shortened (an integer of
    thousands of digits is not even converted: Python refuses beyond 4300 digits)."""
    if isinstance(v, int) and not isinstance(v, bool) and v.bit_length() > 200:
        digits = int(math.log10(abs(v))) + 1
        digits -= abs(v) < 10 ** (digits - 1)  # log10 rounds 99...9 up to the next power of ten
        return f"{'-' if v < 0 else ''}<an integer of about {digits} digits>"
    if isinstance(v, (tuple, list)):
        text = ", ".join(_fmt(c) for c in v[:10]) + (", ..." if len(v) > 10 else "")
        text = f"({text})" if isinstance(v, tuple) else f"[{text}]"
    elif isinstance(v, dict):
        text = "{" + ", ".join(f"{_fmt(k)}: {_fmt(c)}" for k, c in list(v.items())[:10]) \
            + (", ..." if len(v) > 10 else "") + "}"
    else:
        text = repr(v) if isinstance(v, str) else str(v)
    if len(text) > MAX_QUOTED:
        text = text[:MAX_QUOTED - 15] + f"... ({len(text)} characters)"
    return text


def validate(config: Config) -> Config:
    """Check every value and their consistency; raise :class:`ConfigError` listing all faults.

    Returns the configuration unchanged when it is valid.
    """
    problems = []
    for section, rules in RULES.items():
        values = getattr(config, section)
        for key, (check, text) in rules.items():
            v = getattr(values, key)
            if not check(v):
                problems.append(f"{section}.{key} = {_fmt(v)}: must be {text}")
    if problems:
        raise ConfigError(problems)

    m, b, fm, ct, s, o = (config.mechanism, config.beam, config.film, config.contact,
                          config.solver, config.output)
    spatial = b.model == "spatial"
    if spatial:
        problems += _spatial_problems(config)
    elif m.crank_tilt != 0.0 or m.slider_offset != 0.0:
        problems.append(f"mechanism.crank_tilt = {m.crank_tilt}, mechanism.slider_offset = {m.slider_offset}: "
                        "a mechanism out of its plane needs beam.model = 'spatial' (the planar model is "
                        "planar); set both to 0 or beam.model = 'spatial'")
    if not spatial and b.axial_end != "free":
        problems.append(f"beam.axial_end = {_fmt(b.axial_end)}: an axial end condition needs beam.model = 'spatial' "
                        "(the planar model has no u1); use beam.axial_end = 'free' or beam.model = 'spatial'")
    if b.axial_force == "inertial" and not b.uniform:
        problems.append(f"beam.axial_force = {_fmt(b.axial_force)}: the axial force is modelled on the uniform "
                        "link only (beam.width_ratio = beam.height_ratio = 1); use beam.axial_force = 'none' or 'auto'")
    if not spatial and fm.faces != "u2":
        problems.append(f"film.faces = {_fmt(fm.faces)}: a film pair on the u3 faces needs beam.model = 'spatial' "
                        "(the planar model has no u3); use film.faces = 'u2' or beam.model = 'spatial'")
    if m.crank_length >= m.rod_length:
        problems.append(f"mechanism.crank_length = {m.crank_length}: must be shorter than "
                        f"mechanism.rod_length = {m.rod_length}, or the crank cannot turn")
    elif spatial:
        from .link.spatial_motion import travel_problems

        problems += travel_problems(m, fm.pad_length, fm.pad_reference)
    else:
        from .link.kinematics import collar_travel

        x_lo, x_hi = collar_travel(m)
        start = -0.5 * fm.pad_length if fm.pad_reference == "centre" else 0.0
        first, last = x_lo + start, x_hi + start + fm.pad_length
        if not (first > 0.0 and last < m.rod_length):
            problems.append(
                f"mechanism.guide_distance = {m.guide_distance}: the collar pad (film.pad_length = "
                f"{fm.pad_length}) spans [{first:.4g}, {last:.4g}] m along the rod over a crank turn; "
                f"it must stay inside (0, {m.rod_length}) m")
    if max(b.width * max(1.0, b.width_ratio), b.height * max(1.0, b.height_ratio)) >= m.rod_length:
        problems.append(f"beam.height = {b.height}, beam.width = {b.width}: a slender link needs both "
                        f"much smaller than mechanism.rod_length = {m.rod_length}")
    if ct.min_film >= 0.5 * fm.clearance:
        problems.append(f"contact.min_film = {ct.min_film}: must be below half the clearance "
                        f"(film.clearance / 2 = {0.5 * fm.clearance})")
    if fm.cavitation != "none" and fm.cavitation_pressure > fm.ambient_pressure:
        problems.append(f"film.cavitation_pressure = {fm.cavitation_pressure}: must not exceed "
                        f"film.ambient_pressure = {fm.ambient_pressure}")
    if fm.enabled and fm.reynolds == "2d" and fm.cavitation == "reynolds":
        problems.append("film.cavitation = 'reynolds': not available with film.reynolds = '2d' (the 2-D film "
                        "is solved by terms across the width, each linear in the film, which cannot hold the "
                        "Swift-Stieber condition); use film.cavitation = 'half-sommerfeld', or film.reynolds = 'short' "
                        "(Swift-Stieber across the width) or '1d'; lubelink.film.pressure_2d solves one 2-D "
                        "film with it")
    if fm.enabled and fm.reynolds == "2d" and fm.width_series == "fitted":
        from .film.width_table import TERMS

        if fm.width_modes not in TERMS:
            problems.append(f"film.width_modes = {fm.width_modes}: must be an integer in [{min(TERMS)}, {max(TERMS)}] "
                            "with film.width_series = 'fitted' (the fitted terms); 'sine' takes up to 200")
    if fm.model == "wedge+squeeze" and ct.min_film <= 0.0:
        problems.append(f"contact.min_film = {ct.min_film}: must be > 0 with film.model = 'wedge+squeeze' "
                        "(a squeeze film never closes in finite time)")
    if m.crank_speed == 0.0:
        problems.append("mechanism.crank_speed = 0.0: must be non-zero (the paper's crank turns)")
    if s.output_step >= s.t_end:
        problems.append(f"solver.output_step = {s.output_step}: must be smaller than solver.t_end = {s.t_end}")
    elif (s.t_end / s.output_step + 1) * max(o.x_points, o.pad_points, b.modes) > MAX_SAMPLES:
        problems.append(f"solver.output_step = {s.output_step}: with solver.t_end = {s.t_end} and "
                        f"output.x_points = {o.x_points} the results would hold more than {MAX_SAMPLES:.0e} "
                        "values; use a larger output_step")
    problems += _drive_problems(config)
    if problems:
        raise ConfigError(problems)
    return config


def _drive_problems(config):
    """What a driven crank (``drive.law`` other than ``"speed"``) does not support yet, one message each."""
    d, out = config.drive, []
    if d.prescribed:
        if d.coupling != "one-way":
            out.append(f"drive.coupling = {_fmt(d.coupling)}: the prescribed crank speed (drive.law = 'speed') is "
                       "an infinite flywheel, nothing acts back on it; set drive.law = 'torque', 'torque-speed' or "
                       "'controller', or drive.coupling = 'one-way'")
        return out
    law = f"drive.law = {_fmt(d.law)}"
    if config.beam.model == "spatial":
        out.append(f"{law}: a driven crank is not supported with beam.model = 'spatial' yet; use drive.law = "
                   "'speed' or beam.model = 'planar'")
    loads = [f"drive.{k} = {getattr(d, k)}" for k in ("slider_mass", "slider_force", "slider_friction")
             if getattr(d, k) != 0.0]
    if config.beam.axial_force == "inertial" and loads:
        out.append(f"beam.axial_force = 'inertial' with {', '.join(loads)}: the slider's own loads on the link's "
                   "axial force are not modelled (its slider is massless and frictionless); set them to 0, or use "
                   "beam.axial_force = 'auto' or 'none'")
    if config.model.equations != "corrected":
        out.append(f"{law}: the paper's printed equations ({_fmt(config.model.equations)}) need the prescribed "
                   "crank speed; use model.equations = 'corrected'")
    if d.law == "torque-speed" and (d.no_load_speed == 0.0 or d.no_load_speed * config.mechanism.crank_speed < 0.0):
        out.append(f"drive.no_load_speed = {d.no_load_speed}: must be non-zero and of the sign of "
                   f"mechanism.crank_speed = {config.mechanism.crank_speed} with drive.law = 'torque-speed'")
    return out


def _spatial_problems(config):
    """What ``beam.model = "spatial"`` does not support yet, one message each (docs/spatial.md, "Limitations")."""
    why = "is not supported with beam.model = 'spatial' (docs/spatial.md, Limitations); "
    out = []
    b = config.beam
    if not b.uniform and config.film.faces == "u2+u3":
        out.append(f"film.faces = 'u2+u3' with beam.width_ratio = {b.width_ratio}, beam.height_ratio = "
                   f"{b.height_ratio}: the u3 film pair on a variable section {why}use film.faces = 'u2' or a "
                   "uniform link")
    if config.collar.mass != 0.0:
        out.append(f"collar.mass = {config.collar.mass}: the collar's joint reaction {why}set it to 0")
    if config.model.equations != "corrected":
        out.append(f"model.equations = {_fmt(config.model.equations)}: the paper's printed forms {why}"
                   "use 'corrected'")
    return out

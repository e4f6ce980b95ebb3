"""Configuration: TOML <-> :class:`~lubelink.params.Config`, scenarios, validation.

Validation happens here, once, at the boundary. Every problem found is
collected and reported together, one line each, naming the section, the key,
the value and the rule (:class:`ConfigError`).
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import asdict, fields, replace
from pathlib import Path

from .errors import suggest
from .params import CHOICES, SECTION_TYPES, Config

__all__ = [
    "ConfigError",
    "DEFAULT_MAX_WALL_TIME",
    "SCENARIOS",
    "scenario",
    "load",
    "from_dict",
    "to_dict",
    "to_toml",
    "parse_override",
    "resolve",
    "validate",
]

#: Pad length [m], viscosity [Pa s] and clearance [m] of the ``paper-impact`` scenario (paper Fig. 9):
#: the paper's model (wedge film, no cavitation, 1 mode) puts the first impact at its t = 1.273 s
#: (1.27324 s) with these values. The clearance is the centre of the window of clearances whose
#: first impact is within 2 ms of 1.273 s (5.49141-5.50537 mm, 14 um wide, 7 um from the jumps of
#: the first-impact time at either side), found with ``lubelink.paper.branch_map`` over the pad length
#: and the clearance (docs/branch_map.py); the reproduction needs tension in the oil. See docs/paper.md.
PAPER_IMPACT_PAD_LENGTH = 0.12
PAPER_IMPACT_VISCOSITY = 0.014
PAPER_IMPACT_CLEARANCE = 5.4984e-3

#: Wall-clock budget of every run [s] (``solver.max_wall_time`` of every scenario, hence of every
#: configuration read from a file, a dict or ``--set``): a run that would take longer stops with
#: status ``timeout`` and keeps its results so far. The CLI warns before starting a run whose
#: estimated cost (:mod:`lubelink.estimate`) exceeds it; ``max_wall_time = inf`` lifts it.
DEFAULT_MAX_WALL_TIME = 3600.0

#: Built-in scenarios as overrides of the defaults of :mod:`lubelink.params` (and of
#: :data:`DEFAULT_MAX_WALL_TIME`).
SCENARIOS: dict[str, dict] = {
    "paper": {
        "description": "Section 6 slider-crank, wedge film (paper Figs. 6-8), 1 mode, 0-2 s",
        "film": {"model": "wedge"},
        "contact": {"law": "none"},
    },
    "paper-dry": {
        "description": "Section 6 slider-crank without lubricant (paper Fig. 7, dry curve)",
        "film": {"model": "none"},
        "contact": {"law": "none"},
    },
    "paper-impact": {
        "description": "Film breakdown and impact, e = 0.7 (paper Fig. 9)",
        "film": {"model": "wedge", "clearance": PAPER_IMPACT_CLEARANCE,
                 "viscosity": PAPER_IMPACT_VISCOSITY, "pad_length": PAPER_IMPACT_PAD_LENGTH},
        "contact": {"law": "restitution", "restitution": 0.7},
    },
    "lubricated": {
        "description": "For engineering: the paper's mechanism with the full film (wedge and squeeze), "
                       "cavitation near ambient, rough surfaces (mixed lubrication), impacts and sustained contact",
        "film": {"model": "wedge+squeeze", "cavitation": "half-sommerfeld", "cavitation_pressure": 1.0e5,
                 "roughness": 1.0e-6, "thickness_floor": 1.0e-6},
        "contact": {"law": "restitution", "restitution": 0.7, "min_film": 2.0e-7},
    },
}



class ConfigError(ValueError):
    """Invalid configuration; ``problems`` lists one message per fault."""

    def __init__(self, problems):
        self.problems = list(problems)
        super().__init__("\n".join(self.problems))


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
        "width_points": _num(4, 4096, integer=True),
        "thickness_floor": _num(0, 1e-2),
        "roughness": _num(0, 1e-3),
        "summit_product": _num(0, 1, lo_open=True),
        "summit_ratio": _num(0, 1, lo_open=True),
        "contact_modulus": _num(0, 1e13, lo_open=True),
    },
    "collar": {"mass": _num(0, 1e6)},
    "contact": {
        "law": _choice(CHOICES["contact.law"]),
        "restitution": _num(0, 1),
        "min_film": _num(0, 1),
        "chatter_interval": _num(0, 1, lo_open=True),
        "stiffness": _num(0, 1e16, lo_open=True),
        "exponent": _num(1, 3),
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
    if m.crank_length >= m.rod_length:
        problems.append(f"mechanism.crank_length = {m.crank_length}: must be shorter than "
                        f"mechanism.rod_length = {m.rod_length}, or the crank cannot turn")
    else:
        from .kinematics import collar_travel

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
                        "is solved by a sine series across the width, which cannot hold the Swift-Stieber "
                        "condition); use film.cavitation = 'half-sommerfeld', or film.reynolds = 'short' "
                        "(Swift-Stieber across the width) or '1d'; lubelink.film.pressure_2d solves one 2-D "
                        "film with it")
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
    if problems:
        raise ConfigError(problems)
    return config


# ----------------------------------------------------------------- dicts and TOML
def to_dict(config: Config) -> dict:
    """Nested plain dict of a configuration (TOML-ready)."""
    return asdict(config)


def to_toml(config: Config) -> str:
    """TOML text that :func:`load` reads back to the same configuration."""
    import tomli_w

    return tomli_w.dumps(to_dict(config))


def _to_float(value):
    """``float(value)`` of an integer, or the integer itself when it is beyond a float (the rule
    check then refuses it, naming the key, instead of an ``OverflowError``)."""
    if isinstance(value, int) and not isinstance(value, bool):
        return float(value) if abs(value) <= _FLOAT_MAX else value
    return value


def _coerce(section, key, value, field_type):
    if field_type in ("tuple", tuple) and isinstance(value, list):
        return tuple(_to_float(c) for c in value)
    if field_type in ("float", float):
        return _to_float(value)
    return value


def _merge(config: Config, data: dict, origin: str, problems: list) -> Config:
    sections = {}
    for section, values in data.items():
        if section not in SECTION_TYPES:
            problems.append(f"{origin}: unknown section [{_name(section)}]{suggest(section, SECTION_TYPES)}")
            continue
        if not isinstance(values, dict):
            problems.append(f"{origin}: [{section}] must be a table of keys, got {_fmt(values)}")
            continue
        cls = SECTION_TYPES[section]
        known = {f.name: f.type for f in fields(cls)}
        updates = {}
        for key, value in values.items():
            if key not in known:
                problems.append(f"{origin}: unknown key {section}.{_name(key)}{suggest(key, known)}")
                continue
            updates[key] = _coerce(section, key, value, known[key])
        sections[section] = replace(getattr(config, section), **updates)
    return replace(config, **sections)


def scenario(name: str) -> Config:
    """The built-in scenario ``name`` (see :data:`SCENARIOS`), validated."""
    if name not in SCENARIOS:
        raise ConfigError([f"scenario = {_fmt(name)}: must be one of "
                           + ", ".join(repr(s) for s in SCENARIOS) + suggest(name, SCENARIOS)])
    data = {k: v for k, v in SCENARIOS[name].items() if k != "description"}
    data["solver"] = {"max_wall_time": DEFAULT_MAX_WALL_TIME, **data.get("solver", {})}
    return validate(_merge(Config(), data, f"scenario {name}", []))


def from_dict(data: dict, origin: str = "configuration") -> Config:
    """Configuration from a nested dict (a parsed TOML document).

    A top-level ``scenario`` key names the base that the sections override;
    the default base is ``paper``.
    """
    data = dict(data)
    problems = []
    base_name = data.pop("scenario", "paper")
    if not isinstance(base_name, str) or base_name not in SCENARIOS:
        problems.append(f"{origin}: scenario = {_fmt(base_name)}: must be one of "
                        + ", ".join(repr(s) for s in SCENARIOS) + suggest(str(base_name), SCENARIOS))
        base = Config()
    else:
        base = scenario(base_name)
    return _validated(_merge(base, data, origin, problems), problems)


def _validated(config: Config, problems: list) -> Config:
    """Validate ``config`` and report its faults together with ``problems`` found earlier."""
    try:
        validate(config)
    except ConfigError as exc:
        problems = problems + exc.problems
    if problems:
        raise ConfigError(problems)
    return config


def load(path) -> Config:
    """Read and validate a TOML configuration file."""
    path = Path(path)
    return from_dict(read_toml(path, "configuration file"), origin=str(path))


def read_toml(path, what="configuration file") -> dict:
    """The parsed TOML document at ``path``; every fault is a one-line :class:`ConfigError`.

    UTF-8 text, with or without a byte-order mark. A folder, an unreadable file, bytes that are
    not UTF-8 and invalid TOML (a duplicated key named) are reported without quoting the file.
    """
    path = Path(path)
    if path.is_dir():
        raise ConfigError([f"{path}: is a folder, not a {what}"])
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise ConfigError([f"{path}: cannot read the {what} ({exc.strerror or exc})"]) from None
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ConfigError([f"{path}: not UTF-8 text (byte 0x{raw[exc.start]:02x} at offset {exc.start}); "
                           f"a {what} is TOML, in UTF-8"]) from None
    return parse_toml(text, str(path))


def parse_toml(text: str, origin: str) -> dict:
    """``tomllib.loads(text)`` with faults as a one-line :class:`ConfigError` naming ``origin``
    (a duplicated key by its name; an integer too long for Python to read)."""
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError([f"{origin}: not valid TOML ({_toml_fault(exc, text)})"]) from None
    except ValueError:  # int() refuses more than sys.get_int_max_str_digits() digits
        raise ConfigError([f"{origin}: not valid TOML (an integer of thousands of digits, too long to "
                           "read)"]) from None
    except RecursionError:
        raise ConfigError([f"{origin}: not valid TOML (nested too deeply)"]) from None


def _toml_fault(exc, text):
    """tomllib's message, naming the key for "Cannot overwrite a value" (which it does not)."""
    import re

    message = str(exc)
    if not message.startswith("Cannot overwrite a value"):
        return message
    m = re.search(r"at line (\d+)", message)
    lines = text.splitlines()
    n = int(m.group(1)) if m else len(lines)
    while n > 1 and (n > len(lines) or not lines[n - 1].strip()):
        n -= 1
    table = ""
    for line in lines[:n]:
        header = re.match(r"\s*\[\[?\s*([^\]]+?)\s*\]\]?\s*(#.*)?$", line)
        if header:
            table = header.group(1).replace(" ", "")
    assignment = re.match(r"\s*([^=]+?)\s*=", lines[n - 1]) if 0 < n <= len(lines) else None
    if not assignment:
        return message
    key = assignment.group(1)
    key = f"{table}.{key}" if table else key
    return f"key {_fmt(key)} is given twice, at line {n}"


def parse_override(text: str) -> tuple[str, object]:
    """Split ``"section.key=value"``; the value is read as TOML, else as a string.

    The value must be on one line (text after a line break would otherwise be lost); section
    and key must both be named.
    """
    shown = _fmt(text)
    if "=" not in text or "." not in text.split("=", 1)[0]:
        raise ConfigError([f"--set {shown}: must look like section.key=value, e.g. beam.modes=5"])
    name, raw = (part.strip() for part in text.split("=", 1))
    section, _, key = name.partition(".")
    if not section.strip() or not key.strip():
        raise ConfigError([f"--set {shown}: must look like section.key=value, e.g. beam.modes=5 "
                           f"(the {'section' if not section.strip() else 'key'} is missing)"])
    if any(c in raw for c in "\n\r\x0b\x0c\x1c\x1d\x1e\x85\u2028\u2029"):
        raise ConfigError([f"--set {shown}: the value must be on one line"])
    try:
        value = tomllib.loads(f"v = {raw}")["v"]
    except tomllib.TOMLDecodeError:
        value = raw
    except ValueError:  # an integer of more digits than Python reads (sys.get_int_max_str_digits)
        raise ConfigError([f"--set {_name(name)}=...: the value is an integer of {len(raw)} digits, "
                           "too long to read"]) from None
    return name, value


def _apply_overrides(config: Config, overrides: dict) -> Config:
    nested: dict[str, dict] = {}
    problems = []
    for name, value in overrides.items():
        section, _, key = str(name).partition(".")
        if not section or not key:
            problems.append(f"override {_fmt(name)}: must be section.key, e.g. beam.modes")
            continue
        nested.setdefault(section, {})[key] = value
    return _validated(_merge(config, nested, "override", problems), problems)


def resolve(source="paper", overrides=None) -> Config:
    """A validated configuration from a scenario name, a TOML path, a dict or a Config.

    Parameters
    ----------
    source : str, os.PathLike, dict or Config
        Scenario name (``"paper"``, ...), path of a TOML file, parsed TOML
        dict, or a configuration.
    overrides : dict, optional
        ``{"section.key": value}`` applied last.
    """
    if isinstance(source, Config):
        config = validate(source)
    elif isinstance(source, dict):
        config = from_dict(source)
    elif isinstance(source, str) and source in SCENARIOS:
        config = scenario(source)
    elif isinstance(source, (str, Path)) and (str(source).endswith(".toml") or Path(source).exists()):
        config = load(source)
    else:
        raise ConfigError([f"source = {_fmt(source)}: not a scenario ("
                           + ", ".join(SCENARIOS) + f"), a TOML file, a dict or a Config"
                           + (suggest(source, SCENARIOS) if isinstance(source, str) else "")])
    if overrides:
        config = _apply_overrides(config, dict(overrides))
    return config

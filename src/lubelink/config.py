"""Configuration: TOML <-> :class:`~lubelink.params.Config`, scenarios, ``--set`` overrides.

Validation happens once, at this boundary (:mod:`lubelink.validation`, re-exported here): every
problem found is collected and reported together, one line each, naming the section, the key, the
value and the rule (:class:`ConfigError`).
"""

from __future__ import annotations

import tomllib
from dataclasses import asdict, fields, replace
from functools import lru_cache
from pathlib import Path

from .errors import suggest
from .params import SECTION_TYPES, Config
from .scenarios import DEFAULT_MAX_WALL_TIME, SCENARIOS
from .validation import (_FLOAT_MAX, MAX_QUOTED, MAX_SAMPLES, RULES, ConfigError, _bound, _choice,  # noqa: F401
                         _fmt, _name, _num, validate)

__all__ = [
    "ConfigError",
    "DEFAULT_MAX_WALL_TIME",
    "SCENARIOS",
    "scenario",
    "load",
    "from_dict",
    "from_stored",
    "to_dict",
    "to_toml",
    "parse_override",
    "resolve",
    "validate",
]




# ----------------------------------------------------------------- dicts and TOML
def to_dict(config: Config) -> dict:
    """Nested plain dict of a configuration (TOML-ready)."""
    return asdict(config)


def to_toml(config: Config) -> str:
    """TOML text that :func:`load` reads back to the same configuration."""
    try:
        return _remembered_toml(config)
    except TypeError:  # a field made unhashable by hand (a list): not remembered
        return _toml(config)


def _toml(config):
    import tomli_w

    return tomli_w.dumps(to_dict(config))


#: Every result carries its configuration's text, and a study runs a few configurations many times.
_remembered_toml = lru_cache(maxsize=16)(_toml)


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
    return validate(_scenario(name))


def _scenario(name: str) -> Config:
    """The built-in scenario ``name``, not validated (a base that overrides follow: validated with them)."""
    data = {k: v for k, v in SCENARIOS[name].items() if k != "description"}
    data["solver"] = {"max_wall_time": DEFAULT_MAX_WALL_TIME, **data.get("solver", {})}
    return _merge(Config(), data, f"scenario {name}", [])


def from_dict(data: dict, origin: str = "configuration") -> Config:
    """Configuration from a nested dict (a parsed TOML document).

    A top-level ``scenario`` key names the base that the sections override;
    the default base is ``paper``.
    """
    return _validated(*_from_dict(data, origin))


def from_stored(data: dict, origin: str) -> Config:
    """:func:`from_dict` of a configuration stored beside its results (a results file, a sweep's base).

    A stored spatial configuration (``beam.model = "spatial"``) without ``beam.axial_end`` was computed with
    the axial end fixed (docs/spatial.md, "Boundary conditions"): it is read with ``"fixed"``; one without
    ``beam.axial_force`` was computed without the axial force (the only model then): it is read with
    ``"none"``, not the later default ``"auto"``. So it computes again what it computed then.
    """
    beam = data.get("beam") if isinstance(data, dict) else None
    if isinstance(beam, dict) and beam.get("model") == "spatial" and "axial_end" not in beam:
        beam = {**beam, "axial_end": "fixed"}
    if isinstance(beam, dict) and "axial_force" not in beam:
        beam = {**beam, "axial_force": "none"}
    if isinstance(beam, dict):
        data = {**data, "beam": beam}
    return from_dict(data, origin)


def _from_dict(data: dict, origin: str):
    """``(config, problems)`` of :func:`from_dict` before validation: the base scenario is validated only
    once, with the sections over it (the spatial model's check of the mechanism turns the crank 721 times)."""
    data = dict(data)
    problems = []
    base_name = data.pop("scenario", "paper")
    if not isinstance(base_name, str) or base_name not in SCENARIOS:
        problems.append(f"{origin}: scenario = {_fmt(base_name)}: must be one of "
                        + ", ".join(repr(s) for s in SCENARIOS) + suggest(str(base_name), SCENARIOS))
        base = Config()
    else:
        base = _scenario(base_name)
    return _merge(base, data, origin, problems), problems


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


#: The longest configuration or sweep file read [bytes] (the largest real one is a few kilobytes).
MAX_TOML_BYTES = 2**20


def read_toml(path, what="configuration file") -> dict:
    """The parsed TOML document at ``path``; every fault is a one-line :class:`ConfigError`.

    UTF-8 text, with or without a byte-order mark. A folder, an unreadable file, bytes that are
    not UTF-8 and invalid TOML (a duplicated key named) are reported without quoting the file.
    """
    path = Path(path)
    if path.is_dir():
        raise ConfigError([f"{path}: is a folder, not a {what}"])
    try:
        with open(path, "rb") as f:  # at most MAX_TOML_BYTES: /dev/zero or a huge file is refused, not read
            raw = f.read(MAX_TOML_BYTES + 1)
    except OSError as exc:
        raise ConfigError([f"{path}: cannot read the {what} ({exc.strerror or exc})"]) from None
    if len(raw) > MAX_TOML_BYTES:
        raise ConfigError([f"{path}: longer than {MAX_TOML_BYTES // 2**20} MiB, too long for a {what}"])
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


def _apply_overrides(config: Config, overrides: dict, problems: list) -> Config:
    """``config`` with ``overrides`` merged (not validated); their faults appended to ``problems``."""
    nested: dict[str, dict] = {}
    for name, value in overrides.items():
        section, _, key = str(name).partition(".")
        if not section or not key:
            problems.append(f"override {_fmt(name)}: must be section.key, e.g. beam.modes")
            continue
        nested.setdefault(section, {})[key] = value
    return _merge(config, nested, "override", problems)


def resolve(source="paper", overrides=None) -> Config:
    """A validated configuration from a scenario name, a TOML path, a dict or a Config.

    A scenario name with overrides of plain values (``str``, ``bool``, ``int``, ``float``) is
    resolved once per process and the same (frozen) configuration returned after that
    (:func:`_named`): a study that runs a scenario many times does not validate it each time.

    Parameters
    ----------
    source : str, os.PathLike, dict or Config
        Scenario name (``"paper"``, ...), path of a TOML file, parsed TOML
        dict, or a configuration.
    overrides : dict, optional
        ``{"section.key": value}`` applied last (the configuration is validated once, with them
        applied: the faults of the source and of the overrides are reported together).

    Returns
    -------
    Config
        The validated configuration.
    """
    if isinstance(source, str) and source in SCENARIOS:
        key = _plain_items(overrides)
        if key is not None:
            return _named(source, key)
    return _resolve(source, overrides)


def _plain_items(overrides):
    """``overrides`` as a hashable key ``((name, type, value), ...)``, or None if a value is not a plain scalar.

    The type is part of the key: ``1``, ``1.0`` and ``True`` are equal in Python but not to validation.
    """
    if not overrides:
        return ()
    try:
        items = tuple(dict(overrides).items())
    except (TypeError, ValueError):
        return None
    if not all(type(name) is str and type(value) in (str, bool, int, float) for name, value in items):
        return None
    return tuple((name, type(value), value) for name, value in items)


@lru_cache(maxsize=64)
def _named(name, key):
    """:func:`resolve` of the scenario ``name`` with the overrides of :func:`_plain_items` ``key``, remembered."""
    return _resolve(name, {item[0]: item[2] for item in key})


def _resolve(source, overrides):
    problems = []
    if isinstance(source, Config):
        config = source
    elif isinstance(source, dict):
        config, problems = _from_dict(source, "configuration")
    elif isinstance(source, str) and source in SCENARIOS:
        config = _scenario(source)
    elif isinstance(source, (str, Path)) and (str(source).endswith(".toml") or Path(source).exists()):
        path = Path(source)
        config, problems = _from_dict(read_toml(path, "configuration file"), str(path))
    else:
        raise ConfigError([f"source = {_fmt(source)}: not a scenario ("
                           + ", ".join(SCENARIOS) + "), a TOML file, a dict or a Config"
                           + (suggest(source, SCENARIOS) if isinstance(source, str) else "")])
    if overrides:
        config = _apply_overrides(config, dict(overrides), problems)
    return _validated(config, problems)

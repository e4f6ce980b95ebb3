"""The commented configuration file that ``lubelink config`` prints.

Every key is written with its value, then a comment: its symbol, unit and meaning
(:data:`lubelink.fields.FIELDS`) and the values it accepts, which is the text of the very rule
that :func:`lubelink.config.validate` applies (:data:`lubelink.config.RULES`), so the comments
cannot drift from the checks. The text loads back to the same configuration (every key is given,
so the base scenario does not matter).
"""

from __future__ import annotations

from dataclasses import fields

__all__ = ["template", "comment"]

#: Column at which the comments start (the README's template).
COMMENT_COLUMN = 31

HEADER = """\
# lubelink configuration, SI units. After each key: its symbol [unit], what it is; the values it
# accepts. Run it with: lubelink run FILE.toml. A key left out takes the value of the base scenario
# (top-level key `scenario`: {scenarios}; default "paper")."""


def comment(name: str) -> str:
    """The comment of parameter ``name`` (``"section.key"``): ``symbol [unit] meaning; valid values``.

    The valid values are the text of the rule of :data:`lubelink.config.RULES` ("a number in"
    left out); counts (integers) show no unit.
    """
    from .config import RULES
    from .fields import FIELDS
    from .params import SECTION_TYPES

    section, key = name.split(".", 1)
    unit, symbol, meaning = FIELDS.get(name, ("", "", ""))
    kind = next((f.type for f in fields(SECTION_TYPES[section]) if f.name == key), None)
    if unit == "1":
        unit = "" if kind in ("int", int) else "-"
    text = " ".join(part for part in (symbol, f"[{unit}]" if unit else "", meaning) if part)
    rule = RULES.get(section, {}).get(key)
    if rule is not None:
        valid = rule[1].removeprefix("a number in ").replace("an integer in ", "integer in ")
        text = f"{text}; {valid}" if text else valid
    return text


#: Longest line; a longer comment goes on the lines above its key.
WIDTH = 120


def _line(assignment: str, text: str) -> str:
    if not text:
        return assignment
    line = f"{assignment:<{COMMENT_COLUMN - 1}} # {text}"
    if len(line) <= WIDTH:
        return line
    import textwrap

    return "\n".join(textwrap.wrap(text, WIDTH - 2, initial_indent="# ", subsequent_indent="#   ")
                     + [assignment])


def _value(v) -> str:
    """A TOML value: floats shortest (``2.07e11`` rather than ``207000000000.0``), exactly as read
    back; arrays on one line."""
    import math

    if isinstance(v, (tuple, list)):
        return "[" + ", ".join(_value(c) for c in v) + "]"
    if isinstance(v, float) and math.isfinite(v) and v != 0.0 and not 1e-4 <= abs(v) < 1e6:
        mantissa, exponent = f"{v:.17e}".split("e")
        for digits in range(1, 18):  # the shortest mantissa that reads back exactly
            text = f"{float(f'{v:.{digits - 1}e}'):.{digits - 1}e}"
            if float(text) == v:
                mantissa, exponent = text.split("e")
                break
        return f"{mantissa}e{int(exponent)}"
    import tomli_w

    return tomli_w.dumps({"v": v}).split("=", 1)[1].strip()


def template(config, scenario: str | None = None) -> str:
    """TOML text of ``config`` with a comment for every key (see the module docstring).

    Parameters
    ----------
    config : Config
        A validated configuration.
    scenario : str, optional
        Written as the top-level ``scenario`` key (the base the file overrides); omitted by default.
    """
    from .config import SCENARIOS, to_dict

    lines = [HEADER.format(scenarios=", ".join(f'"{s}"' for s in SCENARIOS))]
    if scenario is not None:
        lines += ["", _line(f"scenario = {_value(scenario)}",
                            "the base scenario: " + ", ".join(SCENARIOS))]
    for section, values in to_dict(config).items():
        lines += ["", f"[{section}]"]
        for key, value in values.items():
            lines.append(_line(f"{key} = {_value(value)}", comment(f"{section}.{key}")))
    return "\n".join(lines) + "\n"

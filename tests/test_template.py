"""The commented configuration of ``lubelink config`` (issue 16 item 8): it loads back to the same
configuration, and every key carries its unit and the valid values the validation applies."""

import math
import re
import tomllib
from dataclasses import fields

import pytest
from hypothesis import given
from hypothesis import strategies as st

import lubelink
from lubelink.cli import main
from lubelink.config import RULES, SCENARIOS, from_dict, resolve
from lubelink.fields import FIELDS
from lubelink.params import SECTION_TYPES
from lubelink.template import comment, template


def _loads(text):
    return from_dict(tomllib.loads(text), origin="template")


def _keys():
    return [(section, f) for section, cls in SECTION_TYPES.items() for f in fields(cls)]


@pytest.mark.parametrize("name", list(SCENARIOS))
def test_every_scenario_loads_back_to_itself(name):
    config = resolve(name)
    assert _loads(template(config, scenario=name)) == config
    assert _loads(template(config)) == config  # every key is given: the base does not matter


def test_awkward_values_load_back():
    config = resolve("paper", {"mechanism.gravity": [0.0, -9.81], "solver.max_step": math.inf,
                               "solver.max_wall_time": math.inf, "beam.youngs_modulus": 2.0000000000000004e11,
                               "contact.min_film": 1.2345678901234567e-7, "mechanism.crank_speed": -31.41592653589793,
                               "contact.stiffness": 1e16, "film.cavitation": "reynolds", "film.sides": 2,
                               "solver.rtol": 1e-13})
    assert _loads(template(config)) == config


@given(st.floats(1e6, 1e13), st.floats(0.0, 1.0, exclude_max=True), st.floats(1e-13, 0.1),
       st.floats(1e-300, 1.0, exclude_min=True), st.integers(1, 200))
def test_any_valid_numbers_load_back_exactly(E, zeta, rtol, atol, modes):
    config = resolve("paper", {"beam.youngs_modulus": E, "beam.damping_ratio": zeta, "solver.rtol": rtol,
                               "solver.atol": atol, "beam.modes": modes})
    assert _loads(template(config)) == config


def test_the_field_table_names_every_field_and_no_other():
    assert set(FIELDS) == {f"{section}.{f.name}" for section, f in _keys()}


def test_every_key_has_its_unit_and_the_rule_of_the_validation():
    """The comment of each key quotes the text of the rule that :func:`validate` applies; floats
    show their unit in brackets (``[-]`` dimensionless), choices their values."""
    text = template(resolve("paper"))
    section = None
    seen = set()
    lines = text.splitlines()
    for i, line in enumerate(lines):
        m = re.fullmatch(r"\[(\w+)\]", line)
        if m:
            section = m.group(1)
            continue
        m = re.match(r"(\w+) = ", line)
        if not m or section is None:
            continue
        key = m.group(1)
        # the comment is on the line, or on the comment lines just above it
        said = line.split(" # ", 1)[1] if " # " in line else ""
        j = i - 1
        while " # " not in line and j >= 0 and lines[j].startswith("#"):
            said = lines[j][2:].strip() + " " + said
            j -= 1
        said = " ".join(said.split())
        assert said == comment(f"{section}.{key}"), (section, key)
        rule = RULES[section][key][1]
        assert rule.split(" in ")[-1] in said or rule in said, (section, key, said)
        unit = FIELDS[f"{section}.{key}"][0]
        ftype = next(f.type for f in fields(SECTION_TYPES[section]) if f.name == key)
        if ftype in ("float", float, "tuple", tuple):
            shown = "-" if unit == "1" else unit
            assert unit and f"[{shown}]" in said, (section, key, said)
        seen.add(f"{section}.{key}")
    assert seen == set(FIELDS)


def test_the_field_units_agree_with_the_docstrings():
    """The units of FIELDS are those the dataclass docstrings give (cf-units compares them)."""
    cf_units = pytest.importorskip("cf_units")
    checked = 0
    for section, cls in SECTION_TYPES.items():
        doc = cls.__doc__ or ""
        for m in re.finditer(r"^ {4}([\w, ]+) : [\w ]+\n((?: {8}.*\n?)+)", doc, re.M):
            found = re.search(r"\[([^\]]+)\]", " ".join(m.group(2).split()))
            for name in (n.strip() for n in m.group(1).split(",")):
                unit = FIELDS[f"{section}.{name}"][0]
                if not found or unit in ("", "N m-n") or "," in found.group(1):
                    continue
                written = "1" if found.group(1) == "-" else found.group(1)
                assert cf_units.Unit(written) == cf_units.Unit(unit), (section, name, written, unit)
                checked += 1
    assert checked > 25


def test_the_command_prints_the_template(tmp_path, capsys):
    assert main(["config", "--scenario", "paper-impact", "--set", "beam.modes=3"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("# lubelink configuration, SI units.")
    assert 'scenario = "paper-impact"' in out
    assert "modes = 3                      # N number of sine modes kept; integer in [1, 200]" in out
    path = tmp_path / "c.toml"
    path.write_text(out)
    assert lubelink.load_config(path) == resolve("paper-impact", {"beam.modes": 3})

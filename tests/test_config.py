"""Configuration: scenarios, TOML round trip, overrides and validation messages."""

import math

import pytest

from lubelink import config as cfgmod
from lubelink.config import ConfigError, from_dict, load, parse_override, resolve, scenario, to_toml
from lubelink.params import Config


def test_paper_scenario_holds_the_papers_values():
    c = scenario("paper")
    assert (c.mechanism.crank_length, c.mechanism.rod_length, c.mechanism.guide_distance) == (0.07, 1.0, 0.4)
    assert c.mechanism.crank_speed == pytest.approx(10 * math.pi)
    assert (c.beam.youngs_modulus, c.beam.density, c.beam.width, c.beam.height) == (207e9, 7650.0, 0.01, 0.01)
    assert c.beam.modes == 1 and c.solver.t_end == 2.0 and c.film.model == "wedge"
    assert scenario("paper-dry").film.model == "none"
    assert scenario("paper-impact").contact.law == "restitution"
    assert scenario("paper-impact").contact.restitution == 0.7


@pytest.mark.parametrize("name", list(cfgmod.SCENARIOS))
def test_toml_round_trip(tmp_path, name):
    c = scenario(name)
    path = tmp_path / "c.toml"
    path.write_text(to_toml(c))
    assert load(path) == c


def test_file_overrides_its_base(tmp_path):
    path = tmp_path / "c.toml"
    path.write_text('scenario = "paper-dry"\n[beam]\nmodes = 5\n[solver]\nt_end = 1\n')
    c = load(path)
    assert c.film.model == "none" and c.beam.modes == 5 and c.solver.t_end == 1.0
    assert isinstance(c.solver.t_end, float)


def test_overrides_parse_toml_values():
    assert parse_override("beam.modes=5") == ("beam.modes", 5)
    assert parse_override("film.model = wedge") == ("film.model", "wedge")
    assert parse_override('film.model="none"') == ("film.model", "none")
    assert parse_override("solver.max_wall_time=inf") == ("solver.max_wall_time", math.inf)
    with pytest.raises(ConfigError, match="section.key=value"):
        parse_override("modes5")


def test_resolve_accepts_every_source(tmp_path):
    base = scenario("paper")
    assert resolve(base) == base
    assert resolve({"beam": {"modes": 3}}).beam.modes == 3
    assert resolve("paper", {"beam.modes": 7}).beam.modes == 7
    with pytest.raises(ConfigError, match="did you mean 'paper-dry'"):
        resolve("paper-dri")


def problems_of(data):
    with pytest.raises(ConfigError) as info:
        from_dict(data)
    return info.value.problems


def test_all_problems_are_reported_together_with_key_value_and_rule():
    probs = problems_of({"beam": {"modes": 0, "density": -1.0}, "solver": {"rtol": float("nan")},
                         "film": {"viscositty": 1.0}, "contact": {"law": "sticky"}})
    text = "\n".join(probs)
    assert len(probs) == 5
    assert "beam.modes = 0: must be an integer in [1, 200]" in text
    assert "beam.density = -1.0" in text and "solver.rtol = nan" in text
    assert "unknown key film.viscositty (did you mean 'viscosity'?)" in text
    assert 'contact.law = \'sticky\': must be one of "none", "restitution"' in text


@pytest.mark.parametrize("data, needle", [
    ({"mechanism": {"crank_length": 1.2}}, "cannot turn"),
    ({"mechanism": {"guide_distance": 0.95}}, "must stay inside"),
    ({"film": {"pad_length": 0.6}}, "must stay inside"),
    ({"solver": {"output_step": 3.0}}, "smaller than solver.t_end"),
    ({"contact": {"min_film": 0.01}}, "below half the clearance"),
    ({"film": {"model": "wedge+squeeze"}, "contact": {"min_film": 0.0}}, "never closes"),
    ({"beam": {"modes": 2.0}}, "integer"),
    ({"beam": {"modes": True}}, "integer"),
    ({"film": {"clearance": "1mm"}}, "film.clearance = '1mm'"),
    ({"solver": {"method": "euler"}}, "solver.method = 'euler'"),
    ({"mechanism": {"crank_speed": 0.0}}, "non-zero"),
    ({"bem": {"modes": 2}}, "unknown section [bem] (did you mean 'beam'?)"),
    ({"beam": 3}, "must be a table"),
    ({"scenario": "nope"}, "scenario = 'nope'"),
    ({"solver": {"output_step": 1e-9, "t_end": 100.0}}, "would hold more than"),
])
def test_consistency_rules(data, needle):
    assert any(needle in p for p in problems_of(data))


def test_unreadable_and_malformed_files(tmp_path):
    with pytest.raises(ConfigError, match="cannot read"):
        load(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[beam\nmodes = 1")
    with pytest.raises(ConfigError, match="not valid TOML"):
        load(bad)


def test_defaults_validate():
    assert cfgmod.validate(Config()) == Config()

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
    ({"beam": {"model": "spatial", "axial_end": "pinned"}},
     'beam.axial_end = \'pinned\': must be one of "fixed", "free"'),
    ({"beam": {"axial_end": "fixed"}}, "beam.axial_end = 'fixed': an axial end condition needs beam.model = 'spatial'"),
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


# ====================================================================== issue 15
HUGE = 10**400


@pytest.mark.parametrize("data, needle", [
    ({"beam": {"modes": HUGE}}, "beam.modes = <an integer of about 401 digits>: must be an integer in [1, 200]"),
    ({"film": {"viscosity": -HUGE}}, "film.viscosity = -<an integer of about 401 digits>: must be a number"),
    ({"mechanism": {"gravity": [0, HUGE]}}, "mechanism.gravity = (0.0, <an integer of about 401 digits>)"),
    ({"solver": {"t_end": 10**5000}}, "solver.t_end = <an integer of about 5001 digits>"),
    ({"film": {"model": "x" * 10000}}, "film.model = 'xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx... (10002 characters)"),
])
def test_values_beyond_a_float_or_very_long_are_named_errors(data, needle):
    problems = problems_of(data)
    assert any(needle in p for p in problems), problems
    assert all(len(p) < 300 for p in problems)


def test_overrides_must_be_one_line_and_name_section_and_key():
    with pytest.raises(ConfigError, match="on one line"):
        parse_override("beam.modes=5\nsolver.t_end = 0.1")
    with pytest.raises(ConfigError, match="the section is missing"):
        parse_override(".modes=5")
    with pytest.raises(ConfigError, match="the key is missing"):
        parse_override("beam. = 5")
    with pytest.raises(ConfigError, match="must be section.key"):
        resolve("paper", {".modes": 5})
    with pytest.raises(ConfigError, match="too long to read"):
        parse_override("beam.modes=" + "9" * 5000)


@pytest.mark.parametrize("content, needle", [
    (b"\xff\xfe[beam]\nmodes = 2\n", "not UTF-8 text (byte 0xff at offset 0)"),
    (b"[beam]\nmodes = 2\n\n[film]\nviscosity = 0.1\n\n[beam]\n", "Cannot declare ('beam',) twice"),
    (b"[beam]\nmodes = 2\ndensity = 1.0\nmodes = 3\n", "key 'beam.modes' is given twice, at line 4"),
    (b"scenario = 'paper'\nscenario = 'paper'\n", "key 'scenario' is given twice, at line 2"),
    (b"v = " + b"9" * 5000 + b"\n", "too long to read"),
])
def test_unreadable_files_are_one_line_errors(tmp_path, content, needle):
    path = tmp_path / "c.toml"
    path.write_bytes(content)
    with pytest.raises(ConfigError) as info:
        load(path)
    assert len(info.value.problems) == 1 and needle in info.value.problems[0], info.value.problems


def test_a_byte_order_mark_and_a_folder(tmp_path):
    path = tmp_path / "c.toml"
    path.write_bytes(b"\xef\xbb\xbf[beam]\nmodes = 2\n")
    assert load(path).beam.modes == 2
    with pytest.raises(ConfigError, match="is a folder, not a configuration file"):
        load(tmp_path)


def test_every_configuration_gets_a_finite_wall_time_budget(tmp_path):
    """Item 14: a default budget, written in the configuration (so in every results file)."""
    for name in cfgmod.SCENARIOS:
        assert scenario(name).solver.max_wall_time == cfgmod.DEFAULT_MAX_WALL_TIME < math.inf
    assert resolve({"beam": {"modes": 3}}).solver.max_wall_time == cfgmod.DEFAULT_MAX_WALL_TIME
    assert resolve("paper", {"solver.max_wall_time": math.inf}).solver.max_wall_time == math.inf
    path = tmp_path / "c.toml"
    path.write_text("[solver]\nmax_wall_time = 10\n")
    assert load(path).solver.max_wall_time == 10.0


@pytest.mark.parametrize("source", ["spatial-slider-crank", "dict", "toml", "config"])
def test_resolve_validates_once_with_the_overrides_applied(source, tmp_path, monkeypatch):
    """The base is not validated on its own before the overrides (the spatial model's check of the
    mechanism costs 721 crank positions): one validation per resolve, of the final configuration."""
    import lubelink.config as cfgmod

    base = {"scenario": "spatial-slider-crank", "beam": {"modes": 2}}
    sources = {"spatial-slider-crank": "spatial-slider-crank", "dict": base, "toml": tmp_path / "c.toml",
               "config": scenario("spatial-slider-crank")}
    (tmp_path / "c.toml").write_text('scenario = "spatial-slider-crank"\n[beam]\nmodes = 2\n')
    seen = []
    real = cfgmod.validate
    monkeypatch.setattr(cfgmod, "validate", lambda c: seen.append(c) or real(c))
    cfgmod._named.cache_clear()  # (a scenario resolved before in this process is not validated again)
    config = resolve(sources[source], {"mechanism.crank_tilt": 0.25})
    assert seen == [config] and config.mechanism.crank_tilt == 0.25
    seen.clear()
    with pytest.raises(ConfigError) as info:  # the faults of the source and of the overrides together
        resolve({**base, "beam": {"modes": 0}} if source == "dict" else sources[source], {"film.viscosity": -1.0})
    assert len(seen) == 1 and "film.viscosity = -1.0" in str(info.value)
    assert ("beam.modes = 0" in str(info.value)) == (source == "dict")


def test_a_scenario_with_plain_overrides_is_resolved_once(monkeypatch):
    """The same frozen configuration for the same scenario and overrides, validated once; overrides that
    Python finds equal but validation does not (``2``, ``2.0``, ``True``) are told apart; a value that is
    not a plain scalar is resolved every time; a fault is raised every time."""
    import lubelink.config as cfgmod

    seen = []
    real = cfgmod.validate
    monkeypatch.setattr(cfgmod, "validate", lambda c: seen.append(c) or real(c))
    cfgmod._named.cache_clear()
    first = resolve("paper-dry", {"beam.modes": 2})
    assert resolve("paper-dry", {"beam.modes": 2}) is first and len(seen) == 1
    assert resolve("paper-dry") is resolve("paper-dry") and len(seen) == 2
    with pytest.raises(ConfigError, match="beam.modes"):
        resolve("paper-dry", {"beam.modes": 2.0})
    with pytest.raises(ConfigError, match="beam.modes"):
        resolve("paper-dry", {"beam.modes": True})
    with pytest.raises(ConfigError, match="beam.modes"):  # a fault is not remembered
        resolve("paper-dry", {"beam.modes": True})
    assert len(seen) == 5
    listed = {"mechanism.crank_length": 0.07, "film.viscosity": [0.1]}  # (a list: not a plain value)
    with pytest.raises(ConfigError):
        resolve("paper", listed)
    with pytest.raises(ConfigError):
        resolve("paper", listed)
    assert len(seen) == 7


def test_a_stored_spatial_configuration_without_the_axial_end_reads_fixed():
    """A configuration stored with results (a results file's or a sweep's) lacking beam.axial_end was computed with the
    fixed axial end (docs/spatial.md, "Boundary conditions"); one that has it, and a planar one, read as written."""
    from lubelink.config import from_stored, to_dict

    data = to_dict(resolve("spatial-slider-crank"))
    assert data["beam"]["axial_end"] == "free"  # the default
    assert from_stored(data, "stored").beam.axial_end == "free"
    del data["beam"]["axial_end"]
    assert from_stored(data, "stored").beam.axial_end == "fixed"
    assert "axial_end" not in data["beam"]  # the caller's dict is left as it was
    planar = to_dict(resolve("paper"))
    del planar["beam"]["axial_end"]
    assert from_stored(planar, "stored").beam.axial_end == "free"


def test_a_stored_configuration_without_the_axial_force_reads_none():
    """A stored configuration lacking beam.axial_force was computed without the axial force (the only model before
    the key): read with "none", not the later default "auto"; one that has the key reads as written."""
    from lubelink.config import from_stored, to_dict

    data = to_dict(resolve("lubricated"))
    assert data["beam"]["axial_force"] == "auto"  # the default (the paper's scenarios set "none")
    assert from_stored(data, "stored").beam.axial_force == "auto"
    del data["beam"]["axial_force"]
    assert from_stored(data, "stored").beam.axial_force == "none"
    assert "axial_force" not in data["beam"]  # the caller's dict is left as it was

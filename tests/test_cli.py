"""End to end through the command line: run, file written and reloadable, bad input -> status 2."""

import subprocess
import sys

import pytest

import lubelink

SHORT_ARGS = ["--set", "solver.t_end=0.2", "--set", "output.x_points=11", "--set", "output.pad_points=5"]


def cli(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "lubelink", *args], capture_output=True, text=True,
                          cwd=cwd, timeout=300)


def test_run_writes_a_reloadable_file(tmp_path):
    out = tmp_path / "paper.nc"
    r = cli("run", *SHORT_ARGS, "-o", str(out))
    assert r.returncode == 0, r.stderr
    assert "peak |u2_mid|" in r.stdout and "status         complete" in r.stdout
    ds = lubelink.load(out)
    assert ds.attrs["status"] == "complete" and float(ds.time[-1]) == pytest.approx(0.2)
    assert lubelink.results.config_of(ds).solver.t_end == 0.2


def test_default_run_is_the_paper_scenario_and_names_its_file(tmp_path):
    r = cli("run", "-q", *SHORT_ARGS, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    ds = lubelink.load(tmp_path / "paper.nc")
    assert lubelink.results.config_of(ds).film.model == "wedge"
    again = cli("run", "-q", *SHORT_ARGS, cwd=tmp_path)
    assert again.returncode == 2 and "--overwrite" in again.stderr


def test_a_scenario_by_name_in_place_of_the_file(tmp_path):
    r = cli("run", "paper-dry", "-q", *SHORT_ARGS, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert lubelink.results.config_of(lubelink.load(tmp_path / "paper-dry.nc")).film.model == "none"


def test_toml_file_and_overrides(tmp_path):
    conf = tmp_path / "mine.toml"
    conf.write_text('scenario = "paper-dry"\n[beam]\nmodes = 3\n')
    r = cli("run", str(conf), "-q", *SHORT_ARGS, "--set", "beam.damping_ratio=0.02", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    c = lubelink.results.config_of(lubelink.load(tmp_path / "mine.nc"))
    assert (c.beam.modes, c.beam.damping_ratio, c.film.model) == (3, 0.02, "none")


@pytest.mark.parametrize("args, needle", [
    (["run", "--set", "beam.modes=0"], "beam.modes = 0"),
    (["run", "--set", "film.viscositty=1"], "did you mean 'viscosity'"),
    (["run", "--set", "modes"], "section.key=value"),
    (["run", "--scenario", "papper"], "did you mean 'paper'"),
    (["run", "missing.toml"], "no such file"),
    (["run", "paper-dri"], "did you mean 'paper-dry'"),
    (["run", "-o", "/nonexistent-dir/x.nc"], "does not exist"),
    (["config", "--set", "mechanism.crank_length=2.0"], "cannot turn"),
])
def test_bad_input_exits_2_with_one_clear_line(args, needle, tmp_path):
    r = cli(*args, cwd=tmp_path)
    assert r.returncode == 2
    assert needle in r.stderr
    assert "Traceback" not in r.stderr
    assert all(line.startswith("lubelink: error: ") for line in r.stderr.strip().splitlines())
    assert list(tmp_path.iterdir()) == []


def test_help_and_listing():
    for args in (["--help"], ["run", "--help"], ["config", "--help"], ["scenarios", "--help"]):
        r = cli(*args)
        assert r.returncode == 0 and "usage: lubelink" in r.stdout
    assert "--set SECTION.KEY=VALUE" in cli("run", "--help").stdout
    listing = cli("scenarios").stdout
    assert all(name in listing for name in lubelink.SCENARIOS)


def test_config_prints_valid_toml(tmp_path):
    r = cli("config", "--scenario", "paper-impact")
    assert r.returncode == 0
    path = tmp_path / "c.toml"
    path.write_text(r.stdout)
    assert lubelink.load_config(path) == lubelink.resolve_config("paper-impact")

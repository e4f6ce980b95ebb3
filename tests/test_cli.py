"""End to end through the command line: run, file written and reloadable, bad input -> status 2."""

import subprocess
import sys
from pathlib import Path

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


def test_a_run_through_the_collar_face_exits_1_and_its_file_says_why(tmp_path):
    """``paper-impact`` with 3 modes stops with status ``penetration`` (docs/model.md 5.3): exit status 1, the
    summary's status line and the file's attributes say so; the summary prints the energy budget."""
    out = tmp_path / "impact.nc"
    r = cli("run", "--scenario", "paper-impact", "--set", "beam.modes=3", "--set", "solver.t_end=1.1",
            "-o", str(out))
    assert r.returncode == 1, r.stderr
    assert "status         penetration: at t = 1.0728" in r.stdout and "second point" in r.stdout
    assert "energy         peak" in r.stdout and "2/N" in r.stdout
    ds = lubelink.load(out)
    assert ds.attrs["status"] == "penetration" and ds.attrs["complete"] == 0


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


def test_summary_names_the_overrides_of_its_source(tmp_path):
    r = cli("run", "paper-dry", *SHORT_ARGS, "--set", "solver.t_end=0.1", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    source = next(line for line in r.stdout.splitlines() if line.startswith("source"))
    # solver.t_end given twice counts once, with the value that was used
    assert source.split(None, 1)[1] == ("paper-dry + 3 overrides: output.x_points=11, output.pad_points=5, "
                                        "solver.t_end=0.1")
    plain = cli("run", "paper-dry", "-o", "plain.nc", *SHORT_ARGS[:2], cwd=tmp_path)
    assert "source         paper-dry + 1 override: solver.t_end=0.2\n" in plain.stdout
    many = [arg for k in ("youngs_modulus=2e11", "density=7800", "width=0.011", "height=0.011", "modes=2")
            for arg in ("--set", f"beam.{k}")]
    r = cli("run", "-o", "many.nc", "-q", *SHORT_ARGS, *many, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    from lubelink.cli import _source_label

    label = _source_label("paper", [many[i] for i in range(1, len(many), 2)])
    assert label.startswith("paper + 5 overrides: beam.youngs_modulus=2e11, ") and "(5 in all;" in label
    assert _source_label("paper", []) == "paper"


@pytest.mark.parametrize("args, needle", [
    (["run", "--set", "beam.modes=0"], "beam.modes = 0"),
    (["run", "--set", "film.viscositty=1"], "did you mean 'viscosity'"),
    (["run", "--set", "modes"], "section.key=value"),
    (["run", "--scenario", "papper"], "did you mean 'paper'"),
    (["run", "missing.toml"], "no such file"),
    (["run", "paper-dri"], "did you mean 'paper-dry'"),
    (["run", "-o", "/nonexistent-dir/x.nc"], "does not exist"),
    (["run", "-o", ""], "-o '': an empty file name"),  # issue 37 item 8: used to write paper.nc
    (["run", "-o", "r.nc", "--no-output"], "-o r.nc and --no-output: give one of them"),  # used to ignore -o
    (["config", "--set", "mechanism.crank_length=2.0"], "cannot turn"),
])
def test_bad_input_exits_2_with_one_clear_line(args, needle, tmp_path):
    r = cli(*args, cwd=tmp_path)
    assert r.returncode == 2
    assert needle in r.stderr
    assert "Traceback" not in r.stderr
    assert all(line.startswith("lubelink: error: ") for line in r.stderr.strip().splitlines())
    assert list(tmp_path.iterdir()) == []


def test_unbounded_input_is_refused_and_its_faults_are_counted_not_all_printed(tmp_path):
    """Issue 37 item 5: ``run /dev/zero`` read until memory ran out, and a file of 200,000 unknown keys printed
    200,000 lines. A configuration file over 1 MiB is refused unread; faults past 50 are counted in one line."""
    import os

    if os.path.exists("/dev/zero"):
        r = cli("run", "/dev/zero", cwd=tmp_path)
        assert r.returncode == 2 and "longer than 1 MiB, too long for a configuration file" in r.stderr
    many = tmp_path / "many.toml"
    many.write_text("[beam]\n" + "".join(f"unknown_{k} = {k}\n" for k in range(120)))
    r = cli("run", str(many), cwd=tmp_path)
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2 and len(lines) == 51 and lines[-1] == "lubelink: error: ... and 70 more", lines[-3:]
    assert all(line.startswith("lubelink: error: ") for line in lines)


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


# ====================================================================== issue 15: reliability II
HUGE = "9" * 400  # an integer far beyond a float


@pytest.mark.parametrize("args, needle", [
    # item 1: the output is checked before the run (this run would otherwise take half an hour)
    (["run", "--set", "solver.max_step=1e-9", "--set", "solver.t_end=0.2", "-o", "/proc/x.nc"],
     "cannot create files in folder /proc"),
    (["run", "-o", "folder.nc", "--overwrite"], "is a folder; only a regular file is ever replaced"),
    (["run", "-o", "pipe.nc", "--overwrite"], "is a FIFO (named pipe); only a regular file is ever replaced"),
    # item 4: integers beyond a float, non-UTF-8 files
    (["run", "--set", f"beam.modes={HUGE}"], "beam.modes = <an integer of about 400 digits>: must be an integer"),
    (["run", "--set", f"film.viscosity={HUGE}"], "film.viscosity = <an integer of about 400 digits>"),
    (["run", "--set", f"mechanism.gravity=[{HUGE}, 0]"], "mechanism.gravity = (<an integer of about 400 digits>"),
    (["run", "--set", "beam.modes=" + "9" * 5000], "too long to read"),
    (["run", "random.toml"], "random.toml: not UTF-8 text"),
    (["config", "random.toml"], "random.toml: not UTF-8 text"),
    # item 7: --set
    (["run", "--set", "beam.modes=5\nsolver.t_end=0.1"], "the value must be on one line"),
    (["run", "--set", ".modes=5"], "(the section is missing)"),
    (["run", "--set", "beam.=5"], "(the key is missing)"),
    # item 12
    (["run", "dup.toml"], "key 'beam.modes' is given twice, at line 3"),
    (["run", "-o", "out.zarr"], "results are written as NetCDF; name the file *.nc (e.g. out.nc)"),
    (["run", "-o", "results"], "name the file results.nc"),
    (["run", "folder.nc"], "is a folder, not a configuration file"),
])
def test_bad_input_of_issue_15_exits_2_with_one_clear_line(args, needle, tmp_path):
    import os

    (tmp_path / "folder.nc").mkdir()
    os.mkfifo(tmp_path / "pipe.nc")
    (tmp_path / "random.toml").write_bytes(bytes(range(128, 256)) * 2)
    (tmp_path / "dup.toml").write_text("[beam]\nmodes = 2\nmodes = 3\n")
    before = sorted(p.name for p in tmp_path.iterdir())
    r = cli(*args, cwd=tmp_path)
    assert r.returncode == 2, r.stderr
    assert needle in r.stderr
    assert "Traceback" not in r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("lubelink: error: ") and len(lines[0]) < 400
    assert sorted(p.name for p in tmp_path.iterdir()) == before


def test_a_utf8_bom_is_accepted(tmp_path):
    conf = tmp_path / "bom.toml"
    conf.write_bytes("\ufeff[beam]\nmodes = 3\n".encode())
    r = cli("config", str(conf))
    assert r.returncode == 0, r.stderr
    assert lubelink.load_config(conf).beam.modes == 3


def run_in_process(args, tmp_path, monkeypatch, capsys):
    from lubelink.cli import main

    monkeypatch.chdir(tmp_path)
    status = main(args)
    return status, capsys.readouterr()


def test_an_output_that_appears_during_the_run_is_kept_and_the_results_go_beside_it(tmp_path, monkeypatch, capsys):
    """Item 3 (no silent replacement) and item 1 (results kept when the final write fails)."""
    simulate_module = sys.modules["lubelink.simulate"]  # lubelink.simulate is also the function
    real = simulate_module.run

    def run_while_another_writes(config, **kw):
        out = real(config, **kw)
        (tmp_path / "r.nc").write_text("another run's results")
        return out

    monkeypatch.setattr(simulate_module, "run", run_while_another_writes)
    status, out = run_in_process(["run", "-q", *SHORT_ARGS, "-o", "r.nc"], tmp_path, monkeypatch, capsys)
    assert status == 1
    assert (tmp_path / "r.nc").read_text() == "another run's results"
    kept = [p for p in tmp_path.iterdir() if p.name.startswith("r.unsaved-")]
    assert len(kept) == 1 and lubelink.load(kept[0]).attrs["status"] == "complete"
    assert "r.nc appeared while the results were computed; it was not replaced" in out.err
    assert f"the results were written to {kept[0].name}" in out.err or str(kept[0]) in out.err
    assert len(out.err.strip().splitlines()) == 1 and "Traceback" not in out.err


def test_a_failing_final_write_keeps_the_results_elsewhere(tmp_path, monkeypatch, capsys):
    import lubelink.results

    real = lubelink.netcdf.write
    target = tmp_path / "sub" / "r.nc"
    target.parent.mkdir()

    def write(results, path, overwrite=False):
        if Path(path).parent == target.parent:
            raise OSError(28, "No space left on device")
        return real(results, path, overwrite=overwrite)

    monkeypatch.setattr(lubelink.netcdf, "write", write)
    status, out = run_in_process(["run", "-q", *SHORT_ARGS, "-o", str(target)], tmp_path, monkeypatch, capsys)
    assert status == 1
    kept = [p for p in tmp_path.iterdir() if p.name.startswith("r.unsaved-")]
    assert len(kept) == 1 and lubelink.load(kept[0]).attrs["complete"] == 1
    assert "could not be written (No space left on device)" in out.err and str(kept[0].name) in out.err
    assert list(target.parent.iterdir()) == []


def test_sigterm_during_the_write_removes_the_temporary_and_exits_143(tmp_path, monkeypatch, capsys):
    """Item 10: SIGTERM is handled like Ctrl-C (clean-up, one line), with status 128 + 15."""
    import os
    import signal

    import netCDF4

    real = netCDF4.Dataset

    def dataset_then_sigterm(*a, **k):
        nc = real(*a, **k)
        os.kill(os.getpid(), signal.SIGTERM)
        return nc

    monkeypatch.setattr(netCDF4, "Dataset", dataset_then_sigterm)
    previous = signal.getsignal(signal.SIGTERM)
    status, out = run_in_process(["run", "-q", *SHORT_ARGS, "-o", "r.nc"], tmp_path, monkeypatch, capsys)
    assert status == 143
    assert out.err.strip() == "lubelink: terminated by SIGTERM; nothing was written"
    assert list(tmp_path.iterdir()) == []
    assert signal.getsignal(signal.SIGTERM) == previous  # the handler is the CLI's only while it runs


def sigterm_caught(pid):
    """True once process ``pid`` catches SIGTERM (its handler installed)."""
    try:
        text = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return False
    mask = int(next(line.split()[1] for line in text.splitlines() if line.startswith("SigCgt:")), 16)
    return bool(mask >> (15 - 1) & 1)


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="reads /proc")
def test_sigterm_during_a_run_is_a_clean_exit_143(tmp_path):
    import signal
    import time

    p = subprocess.Popen([sys.executable, "-m", "lubelink", "run", "-q", "--set", "solver.max_step=1e-9",
                          "--set", "solver.t_end=0.2", "--set", "solver.max_wall_time=120"], cwd=tmp_path,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while not sigterm_caught(p.pid) and p.poll() is None and time.monotonic() < deadline:
        time.sleep(0.01)
    p.send_signal(signal.SIGTERM)
    _, err = p.communicate(timeout=60)
    assert p.returncode == 143, err
    assert err.strip().splitlines()[-1] == "lubelink: terminated by SIGTERM; nothing was written"
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("delay", [0.05, 0.15, 0.3, 0.6, 1.2])
def test_ctrl_c_at_any_moment_of_the_start_is_one_line_and_130(tmp_path, delay):
    """Ctrl-C while the interpreter starts, the package and the libraries load, the command is parsed or
    the kernels load: one line and status 130, never a traceback (a signal before Python has installed
    its handler ends the process silently, as for any program)."""
    import signal
    import time

    p = subprocess.Popen([sys.executable, "-m", "lubelink", "run", "-q", "--set", "solver.max_step=1e-9",
                          "--set", "solver.t_end=0.2", "--set", "solver.max_wall_time=120"], cwd=tmp_path,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    time.sleep(delay)
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=60)
    if p.returncode == -signal.SIGINT:
        assert err == ""
    elif p.returncode == 1 and ("init_import_site" in err or "Could not import runpy module" in err):
        pass  # (on a loaded machine 0.05 s can fall in the interpreter's own start: its fatal error, before any lubelink)
    else:
        assert p.returncode == 130, err
        assert "Traceback" not in err and err.strip().splitlines()[-1].startswith("lubelink: interrupted"), err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("interrupt", [True, False])
def test_ctrl_c_that_surfaces_as_another_exception_is_still_an_interruption(interrupt):
    """A Ctrl-C inside the interpreter's import machinery can surface as another exception (CI saw
    ``TypeError: expected a message argument`` from SciPy's import at 0.15 s): one line and 130. The same
    exception without a Ctrl-C is a bug and keeps its traceback."""
    code = ("import os, signal, time\n"
            "import lubelink.cli as cli\n"
            "def main():\n"
            "    try:\n"
            f"        {'os.kill(os.getpid(), signal.SIGINT)' if interrupt else 'raise KeyboardInterrupt'}\n"
            "        time.sleep(10)\n"
            "    except KeyboardInterrupt:\n"
            "        raise TypeError('expected a message argument') from None\n"
            "cli.main = main\n"
            "cli.console()\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    if interrupt:
        assert r.returncode == 130 and r.stderr == "lubelink: interrupted\n", r.stderr
    else:
        assert r.returncode == 1 and "Traceback" in r.stderr and "TypeError: expected a message" in r.stderr


@pytest.mark.parametrize("umask", [0o002, 0o022, 0o077])
def test_results_files_honour_the_umask(tmp_path, umask):
    import os
    import stat

    r = subprocess.run(["sh", "-c", f"umask {umask:03o} && exec {sys.executable} -m lubelink run -q "
                        + " ".join(SHORT_ARGS) + " -o r.nc"], cwd=tmp_path, capture_output=True, text=True,
                       timeout=300)
    assert r.returncode == 0, r.stderr
    assert stat.S_IMODE(os.stat(tmp_path / "r.nc").st_mode) == 0o666 & ~umask


# ====================================================================== issue 16 item 2: backends
def test_a_backend_that_cannot_run_is_status_2_naming_the_setting(tmp_path):
    """Numba absent (here: disabled): ``backend = "numba"`` is refused in one line, ``"auto"``
    runs on NumPy and says why in the summary's solver line."""
    import os

    env = {**os.environ, "LUBELINK_DISABLE_JIT": "1"}
    r = subprocess.run([sys.executable, "-m", "lubelink", "run", "--no-output", "--set", "solver.backend='numba'",
                        "--set", "film.cavitation='reynolds'"], capture_output=True, text=True, env=env,
                       cwd=tmp_path, timeout=300)
    assert r.returncode == 2, r.stderr
    assert r.stderr.strip().splitlines() == [
        "lubelink: error: solver.backend = 'numba': not available, LUBELINK_DISABLE_JIT is set; "
        "use solver.backend = 'auto' or 'numpy'"]
    r = subprocess.run([sys.executable, "-m", "lubelink", "run", "--no-output", "--set", "solver.t_end=0.02",
                        "--set", "output.x_points=5"], capture_output=True, text=True, env=env, cwd=tmp_path,
                       timeout=300)
    assert r.returncode == 0, r.stderr
    solver = next(line for line in r.stdout.splitlines() if line.startswith("solver"))
    assert solver.endswith("backend numpy (compiled path not used: LUBELINK_DISABLE_JIT is set)"), solver


@pytest.mark.parametrize("backend", ["numba", "auto"])
def test_a_compile_failure_is_status_2_with_numba_and_a_named_fallback_with_auto(backend, monkeypatch, capsys):
    from numba.core.errors import TypingError

    from lubelink import integrate
    from lubelink.cli import main

    real = integrate.integrate

    def failing(*args, **kwargs):
        if kwargs["options"].compiled:
            raise TypingError("a kernel that does not type")
        return real(*args, **kwargs)

    monkeypatch.setattr(integrate, "integrate", failing)
    args = ["run", "--no-output", "--set", f"solver.backend='{backend}'", "--set", "solver.t_end=0.02",
            "--set", "output.x_points=5"]
    if backend == "numba":
        assert main(args) == 2
        err = capsys.readouterr().err
        assert err.startswith("lubelink: error: solver.backend = 'numba': compiling the kernels failed "
                              "(TypingError: ") and "Traceback" not in err
    else:
        with pytest.warns(RuntimeWarning, match="compiled path failed"):
            assert main(args) == 0
        assert "backend numpy (compile failed: TypingError)" in capsys.readouterr().out


# ====================================================================== the command as a process
def test_the_command_flushes_its_output_and_runs_the_exit_handlers_before_its_fast_exit():
    """``console`` ends the process without the interpreter's teardown: what was printed (into a
    pipe, block-buffered) and what the exit handlers do must still happen, and the status be main's."""
    code = ("import atexit, sys; atexit.register(lambda: print('handler ran')); "
            "from lubelink.cli import console; sys.argv = ['lubelink', *sys.argv[1:]]; console()")
    listed = subprocess.run([sys.executable, "-c", code, "scenarios"], capture_output=True, text=True, timeout=300)
    assert listed.returncode == 0, listed.stderr
    lines = listed.stdout.splitlines()
    assert lines[-1] == "handler ran" and len(lines) == len(lubelink.config.SCENARIOS) + 1
    bad = subprocess.run([sys.executable, "-c", code, "run", "--no-output", "--set", "beam.modes=0"],
                         capture_output=True, text=True, timeout=300)
    assert bad.returncode == 2 and "beam.modes" in bad.stderr and bad.stdout == "handler ran\n"


def test_run_says_which_method_ran_and_why(tmp_path):
    """The ``guide`` scenario is stiff: the summary's solver line names RODAS4 and the reason."""
    r = cli("run", "--scenario", "guide", "--no-output", "--set", "solver.t_end=0.02", "--set", "output.x_points=11",
            "--set", "output.pad_points=5", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    line = next(ln for ln in r.stdout.splitlines() if ln.startswith("solver"))
    assert "rodas (auto: stiff: the squeeze film damps at" in line and "Jacobian analytic" in line


def test_a_results_file_shows_itself_and_runs_again(tmp_path):
    """``lubelink show FILE.nc`` prints the summary ``run`` printed (the lines that do not depend on the wall
    clock) and the configuration, which loads back to the file's; ``lubelink run FILE.nc`` runs that configuration
    again into FILE-rerun.nc with the same numbers (to the bit), with --set on top of it; a file that is not
    results is status 2 with one line."""
    import numpy as np
    import tomllib

    out = tmp_path / "paper.nc"
    first = cli("run", *SHORT_ARGS, "--set", "beam.modes=2", "-o", str(out))
    assert first.returncode == 0, first.stderr
    shown = cli("show", str(out))
    assert shown.returncode == 0, shown.stderr
    steady = [line for line in first.stdout.splitlines() if line.split()[0] in ("status", "simulated", "peak", "film",
                                                                                 "impacts", "energy", "solver")]
    for line in steady:
        assert line in shown.stdout
    text = shown.stdout.split("runs it again):\n", 1)[1]
    ds = lubelink.load(out)
    assert tomllib.loads(text) == tomllib.loads(ds.attrs["config"])
    again = cli("run", str(out), "-q", cwd=tmp_path)
    assert again.returncode == 0, again.stderr
    rerun = lubelink.load(tmp_path / "paper-rerun.nc")
    np.testing.assert_array_equal(rerun.u2_mid, ds.u2_mid)
    changed = cli("run", str(out), "-q", "--set", "beam.modes=3", "-o", str(tmp_path / "three.nc"))
    assert changed.returncode == 0, changed.stderr
    three = lubelink.load(tmp_path / "three.nc")
    assert three.sizes["mode"] == 3 and float(three.time[-1]) == float(ds.time[-1])
    foreign = tmp_path / "foreign.nc"
    foreign.write_bytes(b"CDF\x01" + b"\x00" * 64)
    for args in (("show", str(foreign)), ("run", str(foreign)), ("show", str(tmp_path / "none.nc"))):
        bad = cli(*args)
        assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "lubelink: error:" in bad.stderr, (args, bad.stderr)


@pytest.mark.parametrize("command", ["run", "config", "animate", "periodic", "continue"])
def test_help_names_every_scenario(command, capsys):
    """The help of every command that takes a scenario lists the scenario table, not a copy of it."""
    from lubelink.cli import main
    from lubelink.scenarios import SCENARIOS

    with pytest.raises(SystemExit):
        main([command, "--help"])
    text = " ".join(capsys.readouterr().out.split())
    for name in SCENARIOS:
        assert name in text, (command, name)

"""The README's reliability table, produced from the behaviour itself.

Each fault case is run here; the rendered table must equal the one in the
README between the markers. ``LUBELINK_UPDATE_README=1 pytest
tests/test_reliability.py`` rewrites it after a deliberate change.
"""

import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import lubelink
from lubelink.link.kinematics import PrescribedMotion

README = Path(__file__).resolve().parents[1] / "README.md"
START, END = "<!-- reliability-table:start -->", "<!-- reliability-table:end -->"


def zero(t):
    return 0.0 * np.asarray(t)


def motion(A_O2):
    return PrescribedMotion(A_O2=A_O2, omega=zero, alpha=zero, x_star=lambda t: 0.4 + zero(t), V_r=zero)


def simulated(set_, motion=None):
    set_ = dict(set_)
    ds = lubelink.simulate(set_.pop("scenario", "paper"), set=set_, motion=motion)
    return ds.attrs["status"], ds.attrs["message"]


def cli(*args, cwd, env=None):
    r = subprocess.run([sys.executable, "-m", "lubelink", *args], capture_output=True, text=True, cwd=cwd,
                       timeout=300, env=None if env is None else {**os.environ, **env})
    return f"exit {r.returncode}", r.stderr.strip().splitlines()[-1]


def in_process(args, cwd, patch=None):
    """Exit status and last error line of ``lubelink ARGS`` run in this process, with ``patch`` applied."""
    import contextlib
    import io
    from unittest import mock

    from lubelink.cli import main

    err = io.StringIO()
    here = Path.cwd()
    os.chdir(cwd)
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()), \
                (patch or contextlib.nullcontext()):
            status = main(list(args))
    finally:
        os.chdir(here)
    line = err.getvalue().strip().splitlines()[-1]
    return f"exit {status}", re.sub(r"unsaved-\d{8}-\d{6}-\d+", "unsaved-<time>-<pid>", line)


def another_run_writes(target):
    """A patch of the simulation that writes ``target`` meanwhile, as a concurrent run would."""
    from unittest import mock

    module = sys.modules["lubelink.simulate"]
    real = module.run

    def run(config, **kw):
        out = real(config, **kw)
        Path(target).write_text("")
        return out

    return mock.patch.object(module, "run", run)


def sigterm_during_a_run(cwd):
    """SIGTERM to ``lubelink run`` once its handler is installed."""
    import signal
    import time

    p = subprocess.Popen([sys.executable, "-m", "lubelink", "run", "-q", "--set", "solver.max_step=1e-9",
                          "--set", "solver.t_end=0.2"], cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True)
    deadline = time.monotonic() + 60
    while p.poll() is None and time.monotonic() < deadline:
        status = Path(f"/proc/{p.pid}/status").read_text()
        mask = int(next(line.split()[1] for line in status.splitlines() if line.startswith("SigCgt:")), 16)
        if mask >> 14 & 1:
            break
        time.sleep(0.01)
    p.send_signal(signal.SIGTERM)
    _, err = p.communicate(timeout=60)
    return f"exit {p.returncode}", err.strip().splitlines()[-1]


HUGE_SWEEP = """[vary]
"film.viscosity" = { start = 0.01, stop = 1.0, num = 10000 }
"mechanism.crank_speed" = { start = 10.0, stop = 40.0, num = 1000 }
"""


def cases(tmp):
    (tmp / "exists.nc").write_text("")
    (tmp / "folder.toml").mkdir()
    os.mkfifo(tmp / "pipe.nc")
    (tmp / "random.toml").write_bytes(bytes(range(128, 256)))
    (tmp / "dup.toml").write_text("[beam]\nmodes = 2\nmodes = 3\n")
    (tmp / "huge.toml").write_text(HUGE_SWEEP)
    (tmp / "empty.toml").write_text("[[points]]\n")
    (tmp / "secrets.toml").write_text('[DB_PASSWORD]\nvalue = "hunter2"\n')
    (tmp / "evil.toml").write_text('base = "secrets.toml"\n[vary]\n"film.viscosity" = [0.1]\n')
    (tmp / "s.toml").write_text('[vary]\n"film.viscosity" = [0.1]\n')
    dry_gap = {"film.model": "none", "film.clearance": 3.6e-3, "solver.t_end": 0.1}
    short = ["-q", "--set", "solver.t_end=0.1", "--set", "output.x_points=5"]
    return [
        ("invalid value", "`lubelink run --set beam.modes=0`", cli("run", "--set", "beam.modes=0", cwd=tmp)),
        ("unknown key", "`lubelink run --set film.viscositty=1`",
         cli("run", "--set", "film.viscositty=1", cwd=tmp)),
        ("output exists", "`lubelink run -o exists.nc`", cli("run", "-o", "exists.nc", cwd=tmp)),
        ("film breakdown, no contact law", "wedge film, `film.viscosity = 1e-3`, `film.clearance = 4.6e-3`",
         simulated({"film.viscosity": 1e-3, "film.clearance": 4.6e-3, "solver.t_end": 0.5})),
        ("impacts accumulate (Zeno): sustained contact", "dry, `contact.restitution = 0`, `film.clearance = 3.6e-3`",
         simulated({**dry_gap, "contact.law": "restitution", "contact.restitution": 0.0})),
        ("impacts at one instant (several points of the pad)",
         "`paper-impact`, `beam.modes = 7`, `solver.method = \"DOP853\"`",
         simulated({"scenario": "paper-impact", "beam.modes": 7, "solver.method": "DOP853"})),
        ("beyond the linear theory", "`paper-impact`, `mechanism.crank_speed = -3000`, `solver.t_end = 0.2`",
         simulated({"scenario": "paper-impact", "mechanism.crank_speed": -3000, "solver.t_end": 0.2})),
        ("wall-time budget", "`solver.max_wall_time = 1e-9`", simulated({"solver.max_wall_time": 1e-9})),
        ("film force unbounded", "`paper-impact`, `film.thickness_floor = 0`, `contact.law = \"compliant\"`",
         simulated({"scenario": "paper-impact", "film.thickness_floor": 0.0, "contact.law": "compliant",
                    "solver.t_end": 1.5})),
        ("step-size underflow", "user motion with `A_O2 = 1/(0.01 - t)^3`, domain limits off",
         simulated({"film.model": "none", "solver.t_end": 0.02, "solver.max_deflection": np.inf,
                    "solver.max_slope": np.inf, "solver.max_axial_strain": np.inf},
                   motion(lambda t: 1.0 / (0.01 - np.asarray(t)) ** 3))),
        ("non-finite load", "user motion returning NaN after 5 ms",
         simulated({"film.model": "none", "solver.t_end": 0.02},
                   motion(lambda t: np.where(np.asarray(t) > 0.005, np.nan, 0.0)))),
        # issue 15
        ("unwritable output, found before the run", "`lubelink run -o /proc/x.nc`",
         cli("run", "-o", "/proc/x.nc", cwd=tmp)),
        ("output not a regular file", "`lubelink run -o pipe.nc --overwrite` (a FIFO)",
         cli("run", "-o", "pipe.nc", "--overwrite", cwd=tmp)),
        ("output not NetCDF", "`lubelink run -o out.zarr`", cli("run", "-o", "out.zarr", cwd=tmp)),
        ("output appears during the run", "another run writes `r.nc` meanwhile",
         in_process(["run", *short, "-o", "r.nc"], tmp, another_run_writes(tmp / "r.nc"))),
        ("integer beyond a float", "`lubelink run --set beam.modes=99...9` (400 digits)",
         cli("run", "--set", "beam.modes=" + "9" * 400, cwd=tmp)),
        ("not UTF-8", "`lubelink run random.toml` (random bytes)", cli("run", "random.toml", cwd=tmp)),
        ("duplicated key", "`modes` twice in `[beam]`", cli("run", "dup.toml", cwd=tmp)),
        ("line break in --set", "`lubelink run --set $'beam.modes=5\\nx'`",
         cli("run", "--set", "beam.modes=5\nx", cwd=tmp)),
        ("no section in --set", "`lubelink run --set .modes=5`", cli("run", "--set", ".modes=5", cwd=tmp)),
        ("configuration is a folder", "`lubelink run folder.toml`", cli("run", "folder.toml", cwd=tmp)),
        ("SIGTERM", "`kill -TERM` during `lubelink run`", sigterm_during_a_run(tmp)),
        ("a run that would take long", "`--set solver.max_step=1e-9 --set solver.t_end=0.2 --set "
         "solver.max_wall_time=2`",
         cli("run", "--no-output", "--set", "solver.max_step=1e-9", "--set", "solver.t_end=0.2", "--set",
             "solver.max_wall_time=2", cwd=tmp)),
        ("10^7-point sweep", "`lubelink sweep huge.toml --workers 2`", cli("sweep", "huge.toml", "--workers", "2",
                                                                            cwd=tmp)),
        ("empty `[[points]]`", "`lubelink sweep empty.toml`", cli("sweep", "empty.toml", cwd=tmp)),
        ("sweep base not a configuration", "`base = \"secrets.toml\"`", cli("sweep", "evil.toml", "--check", cwd=tmp)),
        ("unreachable scheduler (no store left)", "`lubelink sweep s.toml --scheduler tcp://127.0.0.1:9`",
         cli("sweep", "s.toml", "--scheduler", "tcp://127.0.0.1:9", cwd=tmp,
             env={"DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT": "1s"})),
    ]


def round_numbers(text):
    return re.sub(r"\d+\.\d{5,}(e-?\d+)?", lambda m: f"{float(m.group()):.4g}", text)


def render(rows):
    lines = ["| case | input | outcome | message |", "|---|---|---|---|"]
    for case, how, (outcome, message) in rows:
        lines.append(f"| {case} | {how} | `{outcome}` | {round_numbers(message).replace('|', '/')} |")
    return "\n".join(lines)


def test_readme_reliability_table_matches_behaviour(tmp_path):
    table = render(cases(tmp_path))
    text = README.read_text()
    assert START in text and END in text, "README lacks the reliability table markers"
    head, rest = text.split(START)
    _, tail = rest.split(END)
    current = rest.split(END)[0].strip()
    if os.environ.get("LUBELINK_UPDATE_README"):
        README.write_text(f"{head}{START}\n{table}\n{END}{tail}")
        pytest.skip("README table rewritten")
    assert current == table


def test_partial_results_are_written_and_marked(tmp_path):
    out = tmp_path / "r.nc"
    r = subprocess.run([sys.executable, "-m", "lubelink", "run", "-q", "--set", "film.viscosity=1e-3",
                        "--set", "film.clearance=4.6e-3", "-o", str(out)], capture_output=True, text=True,
                       timeout=300)
    assert r.returncode == 1
    ds = lubelink.load(out)
    assert ds.attrs["status"] == "film_breakdown" and ds.attrs["complete"] == 0
    assert float(ds.time[-1]) < 2.0 and np.all(np.isfinite(ds.u2_mid))

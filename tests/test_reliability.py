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
from lubelink.kinematics import PrescribedMotion

README = Path(__file__).resolve().parents[1] / "README.md"
START, END = "<!-- reliability-table:start -->", "<!-- reliability-table:end -->"


def zero(t):
    return 0.0 * np.asarray(t)


def motion(A_O2):
    return PrescribedMotion(A_O2=A_O2, omega=zero, alpha=zero, x_star=lambda t: 0.4 + zero(t), V_r=zero)


def simulated(set_, motion=None):
    ds = lubelink.simulate("paper", set=set_, motion=motion)
    return ds.attrs["status"], ds.attrs["message"]


def cli(*args, cwd):
    r = subprocess.run([sys.executable, "-m", "lubelink", *args], capture_output=True, text=True, cwd=cwd,
                       timeout=300)
    return f"exit {r.returncode}", r.stderr.strip().splitlines()[-1]


def cases(tmp):
    (tmp / "exists.nc").write_text("")
    dry_gap = {"film.model": "none", "film.clearance": 3.6e-3, "solver.t_end": 0.1}
    return [
        ("invalid value", "`lubelink run --set beam.modes=0`", cli("run", "--set", "beam.modes=0", cwd=tmp)),
        ("unknown key", "`lubelink run --set film.viscositty=1`",
         cli("run", "--set", "film.viscositty=1", cwd=tmp)),
        ("output exists", "`lubelink run -o exists.nc`", cli("run", "-o", "exists.nc", cwd=tmp)),
        ("film breakdown, no contact law", "wedge film, `film.viscosity = 1e-3`, `film.clearance = 4.6e-3`",
         simulated({"film.viscosity": 1e-3, "film.clearance": 4.6e-3, "solver.t_end": 0.5})),
        ("chattering impacts", "dry, `contact.restitution = 0`, `film.clearance = 3.6e-3`",
         simulated({**dry_gap, "contact.law": "restitution", "contact.restitution": 0.0})),
        ("wall-time budget", "`solver.max_wall_time = 1e-9`", simulated({"solver.max_wall_time": 1e-9})),
        ("step-size underflow", "user motion with `A_O2 = 1/(0.01 - t)^3`",
         simulated({"film.model": "none", "solver.t_end": 0.02},
                   motion(lambda t: 1.0 / (0.01 - np.asarray(t)) ** 3))),
        ("non-finite load", "user motion returning NaN after 5 ms",
         simulated({"film.model": "none", "solver.t_end": 0.02},
                   motion(lambda t: np.where(np.asarray(t) > 0.005, np.nan, 0.0)))),
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

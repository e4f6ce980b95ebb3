"""The progress line of ``lubelink run`` (issue 16 item 6): on a terminal only, the time left from
the simulated-time rate once a few reports are in, every phase covered, including the write. The
bars of ``figures``, ``sweep`` and ``animate`` (issue 35): tqdm's on a terminal, plain lines in a log."""

import io
import os
import pty
import subprocess
import sys
import threading
import time

import pytest

from lubelink import progress as progress_module
from lubelink.progress import Progress, clock

SHORT_ARGS = ["--set", "solver.t_end=0.3", "--set", "output.x_points=11", "--set", "output.pad_points=5"]


class Terminal(io.StringIO):
    """A stream that says it is a terminal."""

    def isatty(self):
        return True


class Clock:
    def __init__(self, now=100.0):
        self.now = now

    def __call__(self):
        return self.now


@pytest.fixture
def fake_clock(monkeypatch):
    c = Clock()
    monkeypatch.setattr(progress_module.time, "monotonic", c)
    return c


def test_the_time_left_comes_from_the_simulated_time_rate_after_a_few_reports(fake_clock):
    """Start-up takes 10 s (compiling), then 0.01 s of simulated time every 0.1 s of wall time:
    the rate is 0.1, so with 2 - t simulated seconds to go, (2 - t) / 0.1 s are left. The
    start-up does not enter (from the start, the rate would look 10 times slower)."""
    bar = Progress(2.0, Terminal(), delay=0.0, min_reports=5, min_seconds=1.0)
    fake_clock.now += 10.0
    t = 0.02
    bar.update(t)  # the first report: after compiling
    assert bar.remaining() is None and "estimating time left" in bar.line()
    for k in range(1, 12):
        fake_clock.now += 0.1
        t += 0.01
        bar.update(t)
        if k < 5:
            assert bar.remaining() is None  # too few reports
    assert bar.remaining() == pytest.approx((2.0 - 0.13) / 0.1)
    assert "~0:19 left" in bar.line() and "% |#" in bar.line()
    # the time since the first report is required too: 5 fast reports are not enough
    quick = Progress(2.0, Terminal(), delay=0.0)
    quick.update(0.0)
    for _ in range(6):
        fake_clock.now += 0.01
        quick.update(quick.t + 0.01)
    assert quick.remaining() is None


def test_clock_format():
    assert [clock(s) for s in (0, 59.4, 61, 3600 + 62)] == ["0:00", "0:59", "1:01", "1:01:02"]


def test_nothing_is_written_to_a_stream_that_is_not_a_terminal():
    log = io.StringIO()
    with Progress(1.0, log, delay=0.0, interval=0.01) as bar:
        assert bar._thread is None
        bar.update(0.5)
        bar.phase("writing r.nc")
        time.sleep(0.05)
    assert log.getvalue() == ""


def test_a_long_write_is_covered_and_the_line_erased_at_the_end():
    term = Terminal()
    with Progress(1.0, term, delay=0.0, interval=0.02) as bar:
        bar.update(0.0)
        bar.update(1.0)
        bar.phase("writing r.nc")
        time.sleep(0.3)  # a write that reports nothing: the thread redraws the line
    text = term.getvalue()
    frames = text.split("\r")
    writing = [f for f in frames if f.startswith("writing r.nc ... 0:00")]
    assert len(writing) >= 3, frames[:8]
    assert text.endswith("\r" + " " * len(frames[-2]) + "\r")  # erased


def _read_all(fd, sink):
    while True:
        try:
            data = os.read(fd, 4096)
        except OSError:  # the other side closed (EIO)
            return
        if not data:
            return
        sink.append(data)


def test_on_a_terminal_every_phase_shows_and_the_summary_stays_clean(tmp_path, monkeypatch, capsys):
    """``lubelink run`` with a pseudo-terminal as stderr: the phases of the run, the write among
    them (made slow here), then the line erased; the summary on stdout has no trace of it."""
    from lubelink import cli, netcdf

    master, slave = pty.openpty()
    chunks = []
    reader = threading.Thread(target=_read_all, args=(master, chunks), daemon=True)
    reader.start()
    real_write = netcdf.write

    def slow_write(*args, **kwargs):
        time.sleep(0.6)
        return real_write(*args, **kwargs)

    monkeypatch.setattr(netcdf, "write", slow_write)
    monkeypatch.setattr(cli, "PROGRESS_DELAY", 0.0)
    with os.fdopen(slave, "w", closefd=True) as tty:
        monkeypatch.setattr(sys, "stderr", tty)
        assert cli.main(["run", *SHORT_ARGS, "-o", str(tmp_path / "r.nc")]) == 0
        monkeypatch.undo()
    time.sleep(0.2)
    os.close(master)
    reader.join(timeout=5)
    shown = b"".join(chunks).decode()
    frames = [f.strip() for f in shown.split("\r") if f.strip()]
    assert any(f.startswith("simulating ") for f in frames), frames
    assert any(f.startswith("writing r.nc ... 0:00") for f in frames), frames
    assert shown.rstrip(" ").endswith("\r")  # the last thing written is the erasing of the line
    out = capsys.readouterr().out
    assert "\r" not in out and out.startswith("source")


def test_a_redirected_run_writes_no_progress(tmp_path):
    """stderr to a pipe (a log): not one progress character, though the run takes seconds."""
    r = subprocess.run([sys.executable, "-m", "lubelink", "run", *SHORT_ARGS, "-o", "r.nc"], cwd=tmp_path,
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert r.stderr == ""
    assert "wrote" in r.stdout


def test_a_real_terminal_sees_the_phases(tmp_path):
    """A separate process with a pseudo-terminal as its stderr draws its phases and erases them.

    The run goes as Python (``solver.backend = "numpy"``, about 3 s here) so that it outlasts the
    delay before the first frame whatever the state of the compiled cache: a warm compiled run of
    the same configuration can end within the delay and rightly draw nothing."""
    master, slave = pty.openpty()
    chunks = []
    reader = threading.Thread(target=_read_all, args=(master, chunks), daemon=True)
    reader.start()
    p = subprocess.Popen([sys.executable, "-m", "lubelink", "run", "--set", "solver.t_end=2",
                          "--set", "solver.backend=numpy", "-o", "r.nc"],
                         cwd=tmp_path, stdout=subprocess.PIPE, stderr=slave, text=True)
    os.close(slave)
    out, _ = p.communicate(timeout=300)
    reader.join(timeout=10)
    os.close(master)
    shown = b"".join(chunks).decode()
    assert p.returncode == 0 and "wrote" in out
    frames = [f.strip() for f in shown.split("\r") if f.strip()]
    assert frames and all(f.startswith(("starting (compiling on a first run)", "simulating", "sampling",
                                        "writing")) for f in frames), frames
    assert shown.endswith("\r")


# ----------------------------------------------------------------------------- the other commands' bars
def test_a_bar_writes_plain_lines_to_a_stream_that_is_not_a_terminal(fake_clock):
    """Not a terminal: one line per item and stage, the details only in the closing line, no ``\\r``."""
    from lubelink.progress import Bar

    log = io.StringIO()
    bar = Bar(2, "figures", "fig", stream=log, leave=False)
    assert bar.plain and bar.tqdm is None
    bar.describe("fig6")
    bar.stage("simulating paper")
    bar.note("calibrating: H = 4.45 mm")  # often: not a line of its own
    bar.update(1)
    bar.describe("fig9")
    bar.note("calibrating: H = 4.46 mm")
    fake_clock.now += 75.0
    bar.update(1)
    bar.close()
    bar.close()  # (once)
    assert log.getvalue() == ("figures: fig6 (1/2)\n"
                              "figures: fig6: simulating paper\n"
                              "figures: fig9 (2/2)\n"
                              "figures: 2/2 fig in 1:15, calibrating: H = 4.46 mm\n")
    quiet = io.StringIO()
    with Bar(3, "sweep", "pt", stream=quiet, enabled=False) as off:
        off.stage("3 points")
        off.update(3)
    assert quiet.getvalue() == ""


def test_a_bar_on_a_terminal_is_tqdms(fake_clock):
    from lubelink.progress import Bar

    term = Terminal()
    with Bar(4, "sweep", "pt", stream=term) as bar:
        assert not bar.plain and bar.tqdm is not None
        bar.stage("4 point(s) to compute")
        bar.update(2)
        bar.note("failed 0, remaining 2")
    assert "\r" in term.getvalue() and "sweep" in term.getvalue()


def test_animate_to_a_log_writes_lines_not_frames(tmp_path):
    """``lubelink animate`` with stderr to a pipe: the simulation's and the drawing's start and end,
    one line each, and no redrawn frame."""
    r = subprocess.run([sys.executable, "-m", "lubelink", "animate", "--scenario", "paper-dry", "--duration", "0.02",
                        "-o", "a.gif"], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert "\r" not in r.stderr
    lines = r.stderr.splitlines()
    assert lines[0] == "simulating: 0.02 s of motion" and lines[1].startswith("simulating: 0.02/0.02 s in 0:")
    assert lines[2] == "animating: drawing 5 frames into a.gif" and lines[3].startswith("animating: 5/5 frame in 0:")
    assert len(lines) == 4 and r.stdout.strip() == "wrote a.gif"


def test_figures_to_a_log_write_a_line_per_figure_and_simulation(tmp_path, capsys):
    from lubelink.paper import make_figures

    make_figures(tmp_path, low_res=True, only=["fig8"], progress=True, formats=("png",))
    err = capsys.readouterr().err
    assert "\r" not in err
    lines = err.splitlines()
    assert lines[:2] == ["figures: fig8 (1/1)", "figures: fig8: simulating paper"], lines
    assert lines[-1].startswith("figures: 1/1 fig in 0:") and len(lines) == 3


def test_a_sweep_to_a_log_writes_its_start_and_end(tmp_path, capsys):
    distributed = pytest.importorskip("distributed")
    pytest.importorskip("zarr")
    from lubelink.sweep import run_sweep

    sweep = {"base": "paper", "set": {"solver.t_end": 0.05, "output.x_points": 5, "output.pad_points": 5},
             "vary": {"film.viscosity": [0.05, 0.1, 0.2]}}
    with distributed.Client(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=":0") as client:
        ds = run_sweep(sweep, tmp_path / "s.zarr", client=client, progress=True)
    assert bool(ds.done.all())
    err = capsys.readouterr().err
    assert "\r" not in err
    lines = [line for line in err.splitlines() if line.startswith("sweep: ")]
    assert lines[0] == "sweep: 3 point(s) to compute, 0 stored; 1 worker(s)"
    assert lines[1].startswith("sweep: 3/3 pt in 0:") and lines[1].endswith(", failed 0, remaining 0")
    assert len(lines) == 2

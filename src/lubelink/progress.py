"""The progress line of ``lubelink run`` on a terminal: phase, simulated time, time left.

:class:`Progress` draws one line on a terminal, and nothing at all on anything else (a file, a
pipe, a log: :func:`on_terminal`). It names the phase the run is in (starting, which includes
compiling on a first run; simulating; sampling the results; writing the file), shows the
simulated fraction while simulating, and estimates the time left from the rate at which the
simulated time advances, once a few reports have come in after the start (so that compiling or
loading the compiled code does not enter the rate). A background thread redraws the line while
no report comes, so a long write or a compilation still shows the time passing.
"""

from __future__ import annotations

import io
import os
import shutil
import threading
import time

__all__ = ["Progress", "on_terminal"]


#: The phase before the first report: imports, the model, compiling (first run) or loading the
#: compiled code from the cache.
STARTING = "starting (compiling on a first run)"


def on_terminal(stream) -> bool:
    """Whether ``stream`` is a terminal (a progress line there is seen, not logged)."""
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError, OSError):
        return False


def clock(seconds: float) -> str:
    """``m:ss`` (``h:mm:ss`` from an hour on)."""
    seconds = int(round(max(seconds, 0.0)))
    h, rest = divmod(seconds, 3600)
    m, s = divmod(rest, 60)
    return f"{h}:{m:02d}:{s:02d}" if h else f"{m}:{s:02d}"


class Progress:
    """A one-line progress display of a run of ``total`` seconds of simulated time.

    Use as a context manager; call :meth:`phase` when the run moves on and :meth:`update` with
    the simulated time as it advances (it is the ``progress`` callback of
    :func:`lubelink.simulate.run`). On leaving, the line is erased. On a stream that is not a
    terminal every method does nothing.

    Parameters
    ----------
    total : float
        Simulated time of the run [s].
    stream : file
        Where to draw (``sys.stderr``).
    delay : float
        Nothing is drawn during the first ``delay`` seconds [s] (a quick run shows no line).
    min_reports, min_seconds : int, float
        The time left is estimated once this many reports have come after the first one, over
        at least this long [s].
    interval : float
        Redraw interval of the background thread [s].
    """

    def __init__(self, total, stream, delay=0.5, min_reports=5, min_seconds=1.0, interval=0.25):
        self.total = float(total)
        self.stream = stream
        self.enabled = on_terminal(stream)
        self.delay, self.min_reports, self.min_seconds, self.interval = delay, min_reports, min_seconds, interval
        self.began = time.monotonic()
        self.label, self.phase_began = STARTING, self.began
        self.t = 0.0
        self._first = None  # (wall time, simulated time) of the first report
        self._reports = 0
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._thread = None
        self._drawn = 0  # characters of the line on screen
        self._last = 0.0  # when it was last drawn

    # ------------------------------------------------------------------ reports
    def phase(self, label):
        """Enter the phase ``label`` (e.g. ``"writing r.nc"``)."""
        with self._lock:
            self.label, self.phase_began = label, time.monotonic()
        self._draw()

    def update(self, t):
        """The simulation has reached ``t`` [s] of simulated time."""
        now = time.monotonic()
        with self._lock:
            if self._first is None:
                self._first = (now, float(t))
                self.label, self.phase_began = "simulating", now
            else:
                self._reports += 1
            self.t = float(t)
        self._draw()

    def remaining(self, now=None):
        """Estimated wall time left in the simulation [s], or None while there is too little to go on.

        The rate is the simulated time covered since the first report over the wall time since
        then, so it leaves out what came before the first report (compiling, loading).
        """
        if self._first is None or self._reports < self.min_reports:
            return None
        now = time.monotonic() if now is None else now
        wall = now - self._first[0]
        covered = self.t - self._first[1]
        if wall < self.min_seconds or covered <= 0.0:
            return None
        return (self.total - self.t) * wall / covered

    # ------------------------------------------------------------------ drawing
    def line(self, now=None) -> str:
        """The text of the progress line at ``now``."""
        now = time.monotonic() if now is None else now
        elapsed = clock(now - self.began)
        if self.label != "simulating":
            return f"{self.label} ... {clock(now - self.phase_began)}  [{elapsed} elapsed]"
        fraction = min(max(self.t / self.total, 0.0), 1.0) if self.total > 0 else 1.0
        width = 16
        filled = int(round(fraction * width))
        left = self.remaining(now)
        eta = "estimating time left" if left is None else f"~{clock(left)} left"
        return (f"simulating {100 * fraction:3.0f}% |{'#' * filled}{'.' * (width - filled)}| "
                f"{self.t:.3g}/{self.total:.3g} s  [{elapsed} elapsed, {eta}]")

    def _draw(self, force=False):
        if not self.enabled:
            return
        now = time.monotonic()
        if now - self.began < self.delay:
            return
        with self._lock:
            if not force and self._thread is not None and now - self._last < 0.1:
                return
            self._last = now
            width = self._columns() - 1
            text = self.line(now)[:width]
            pad = max(self._drawn - len(text), 0)
            try:
                self.stream.write("\r" + text + " " * pad)
                self.stream.flush()
            except (OSError, ValueError):
                self.enabled = False
                return
            self._drawn = len(text)

    def _columns(self):
        """Width of the terminal of the stream (80 when it does not say)."""
        try:
            columns = os.get_terminal_size(self.stream.fileno()).columns
        except (AttributeError, ValueError, OSError, io.UnsupportedOperation):
            columns = 0
        return columns if columns > 0 else shutil.get_terminal_size((80, 24)).columns

    def _run(self):
        while not self._stop.wait(self.interval):
            self._draw(force=True)

    def __enter__(self):
        if self.enabled:
            self._thread = threading.Thread(target=self._run, name="lubelink-progress", daemon=True)
            self._thread.start()
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def close(self):
        """Stop redrawing and erase the line."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join()
            self._thread = None
        if self.enabled and self._drawn:
            try:
                self.stream.write("\r" + " " * self._drawn + "\r")
                self.stream.flush()
            except (OSError, ValueError):
                pass
            self._drawn = 0

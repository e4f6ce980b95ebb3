"""Progress on a terminal, and plain lines in a log: the run's line and the other commands' bars.

:class:`Progress` is the line of ``lubelink run``: drawn on a terminal, nothing at all on anything
else (a file, a pipe, a log: :func:`on_terminal`). It names the phase the run is in (starting,
which includes compiling on a first run; simulating; sampling the results; writing the file),
shows the simulated fraction while simulating, and estimates the time left from the rate at which
the simulated time advances, once a few reports have come in after the start (so that compiling or
loading the compiled code does not enter the rate). A background thread redraws the line while
no report comes, so a long write or a compilation still shows the time passing.

:class:`Bar` is the progress bar of ``figures``, ``sweep``, ``animate`` and ``simulate(...,
progress=True)``: tqdm's bar on a terminal (or a notebook's widget), and on anything else one
plain line per stage and one at the end, never the carriage returns of a redrawn bar.
"""

from __future__ import annotations

import io
import os
import shutil
import sys
import threading
import time

__all__ = ["Progress", "Bar", "on_terminal"]


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


def _notebook() -> bool:
    """Whether tqdm.auto draws a notebook's widget here (an IPython kernel with ipywidgets), not text."""
    if "ipykernel" not in sys.modules:
        return False
    from tqdm.auto import tqdm

    return any(c.__module__ == "tqdm.notebook" for c in tqdm.__mro__)


class Bar:
    """A progress bar of ``total`` units: tqdm's on a terminal, plain lines anywhere else.

    On a terminal (or in a notebook) it is a tqdm bar on ``stream``. On a stream that is not a
    terminal (a file, a pipe, a log) it writes one line per :meth:`stage` (``"figures: fig9:
    simulating paper-impact"``) and one on :meth:`close` (``"figures: 8/8 fig in 2:41"``), each
    ended by a newline and flushed, so that a log reads as a list of what was done. With
    ``enabled`` false it writes nothing.

    Parameters
    ----------
    total : int or float
        Units to do.
    desc, unit : str
        What the bar counts (``"sweep"``, ``"pt"``).
    stream : file, optional
        Where to write (default ``sys.stderr``).
    enabled : bool
        False: nothing is written.
    initial : int or float
        Units already done.
    **tqdm_options
        Passed to tqdm (``bar_format``, ``leave``, ``mininterval``, ...).
    """

    def __init__(self, total, desc, unit, *, stream=None, enabled=True, initial=0, **tqdm_options):
        self.stream = sys.stderr if stream is None else stream
        self.total, self.desc, self.unit, self.n = total, desc, unit, initial
        self.enabled = bool(enabled)
        self.began = time.monotonic()
        self.name = ""  # the item being done (:meth:`describe`)
        self.noted = ""  # the last :meth:`note`, quoted in the closing line
        self.tqdm = None
        if self.enabled and (on_terminal(self.stream) or _notebook()):
            from tqdm.auto import tqdm

            self.tqdm = tqdm(total=total, initial=initial, desc=desc, unit=unit, file=self.stream, **tqdm_options)

    @property
    def plain(self) -> bool:
        """Whether it writes plain lines (enabled, not on a terminal)."""
        return self.enabled and self.tqdm is None

    def _line(self, text):
        try:
            self.stream.write(f"{self.desc}: {text}\n")
            self.stream.flush()
        except (OSError, ValueError):
            self.enabled = False

    def describe(self, name):
        """Start item ``name`` (a figure): the bar's description, or a line ``desc: name (k/total)``."""
        self.name = name
        if self.tqdm is not None:
            self.tqdm.set_description(name)
        elif self.plain:
            self._line(f"{name} ({self.n + 1:g}/{self.total:g})")

    def stage(self, text):
        """A stage worth a line in a log (a simulation starting): beside the bar, or a line."""
        if self.tqdm is not None:
            self.tqdm.set_postfix_str(text)
        elif self.plain:
            self._line(f"{self.name}: {text}" if self.name else text)

    def note(self, text, refresh=True):
        """A detail that changes often (counts, the latest trial): beside the bar only; a log gets
        the last one in the closing line."""
        self.noted = text
        if self.tqdm is not None:
            self.tqdm.set_postfix_str(text, refresh=refresh)

    def update(self, n=1):
        """``n`` more units done."""
        self.n += n
        if self.tqdm is not None:
            self.tqdm.update(n)

    def advance_to(self, value):
        """``value`` units done in all (the simulated time reached); the bar redrawn a hundred times at most."""
        if self.tqdm is not None:
            self.tqdm.n = value
            if value - self.tqdm.last_print_n > 0.01 * (self.total or 1):
                self.tqdm.refresh()
        self.n = value

    def close(self):
        """End: the bar closed, or the closing line ``desc: n/total unit in m:ss[, note]``."""
        if self.tqdm is not None:
            self.tqdm.close()
            self.tqdm = None
        elif self.plain:
            self._line(f"{self.n:g}/{self.total:g} {self.unit} in {clock(time.monotonic() - self.began)}"
                       + (f", {self.noted}" if self.noted else ""))
            self.enabled = False

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

"""A cold first run compiles on two cores.

Numba compiles one function at a time, in one thread: a first run in a new installation (or after
an upgrade) spends most of its time compiling the kernels it needs, one after the other. When the
right-hand side of a run is not yet in the on-disk cache, :func:`start` launches a helper
process (``python -m lubelink._prewarm``, the run's configuration on its standard input) that
compiles the right-hand side, then the gap, while this process compiles the integration method,
its driver (:func:`lubelink.integrate.driver.precompile`, from the types alone) and the batched
results (:func:`compile_results`); :func:`wait` then waits for the helper's right-hand side and
gap, which Numba loads from the cache instead of compiling them again. Each kernel is compiled
once, the work split over two processes in two halves of about the same cost (for ``paper``: the
model's kernels 55 %, the rest 45 % of the CPU time). The helper is stopped when this process
exits; with one core, a user motion (Python callables cannot be sent to another process), a warm
cache, or ``LUBELINK_PREWARM=0`` nothing is started.

The helper reports on its standard output, one line per kernel done: ``rhs``, ``gap`` (or
``nocache`` when Numba cannot cache here, and the waiting stops).

A cold *short* run does better still (:func:`first_run`, for :func:`lubelink.simulate` and
``lubelink run``): the numpy backend runs the very functions Numba would compile, so when the run
and its results would take a few seconds as Python (:mod:`lubelink.estimate`), it runs as Python
at once while a background process (``python -m lubelink._background``) runs the same
configuration compiled, for the cache only: the first ``paper`` run takes about 6 s instead of
25-40 s, the next runs load the compiled kernels. The summary line and the results' ``backend``
attributes say so. One background compile runs at a time per cache (a lock file beside the
cache); runs started meanwhile run as Python too, or compile themselves when that would be long.
``LUBELINK_FIRST_RUN=compile`` (or ``LUBELINK_PREWARM=0``) compiles in the foreground instead.
"""

from __future__ import annotations

import atexit
import contextlib
import os
import select
import subprocess
import sys
import time

from ._jit import compile_errors, cores

__all__ = ["start", "wait", "first_run", "kernels_ready", "announcing", "compile_on_two_cores", "ctrl_c_while_compiling"]

#: Longest wait for the helper [s]: beyond it this process compiles what it still needs itself.
WAIT_LIMIT = 120.0
#: Longest estimated run as Python, results included [s], that a cold first run takes at once
#: instead of compiling first (compiling ``paper``'s kernels: 25-40 s on two cores).
FIRST_RUN_LIMIT = 6.0


def _cached(dispatcher, args) -> bool:
    """Whether ``dispatcher`` has machine code for argument types ``args`` in its on-disk cache."""
    try:
        index = dispatcher._cache._cache_file._load_index()
    except Exception:  # noqa: BLE001 - a Numba without this internal: assume warm, start nothing
        return True
    return any(key[0] == args for key in index)


def _is_warm(dispatcher, args) -> bool:
    """Whether ``dispatcher`` is compiled for ``args`` in this process or in the on-disk cache."""
    return args in dispatcher.overloads or _cached(dispatcher, args)


#: Parameter types whose right-hand side is known to be compiled or cached, by identity.
_WARM: dict = {}


def _helped(model, motion) -> bool:
    """Whether a helper process may compile ``model``'s kernels: compiled planar kernels of a
    configuration that TOML carries (not Python callables), POSIX (select(), flock()), and not
    ``LUBELINK_PREWARM=0``."""
    return (model.compiled and motion is None and model.params.spatial is None and os.name == "posix"
            and os.environ.get("LUBELINK_PREWARM", "1") != "0")


def start(model, motion=None):
    """The helper process compiling ``model``'s kernels, or None (nothing to gain; see the module)."""
    if not _helped(model, motion) or cores() < 2:
        return None
    from .config import to_toml
    from .integrate.driver import signatures
    from .link.model import rhs

    p_type = model.params_type
    if id(p_type) in _WARM:  # (by identity: Numba types are interned, hashing this one walks all of it)
        return None
    if _is_warm(rhs, signatures(p_type)[0].args):
        _WARM[id(p_type)] = p_type
        return None
    env = dict(os.environ, LUBELINK_PREWARM="0")
    try:
        proc = subprocess.Popen([sys.executable, "-m", "lubelink._prewarm"], stdin=subprocess.PIPE,
                                stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, env=env)
        proc.stdin.write(to_toml(model.config).encode())
        proc.stdin.close()
    except OSError:
        return None
    atexit.register(_stop, proc)
    return proc


def wait(proc, what=("rhs", "gap"), limit=WAIT_LIMIT):
    """Wait until the helper ``proc`` has compiled ``what`` (or ended, or ``limit`` seconds passed)."""
    if proc is None:
        return
    left, deadline = set(what), time.monotonic() + limit
    fd = proc.stdout.fileno()
    buffer = b""
    while left and time.monotonic() < deadline:
        ready, _, _ = select.select([fd], [], [], max(0.0, deadline - time.monotonic()))
        if not ready:
            break
        chunk = os.read(fd, 256)
        if not chunk:  # the helper ended
            break
        buffer += chunk
        *lines, buffer = buffer.split(b"\n")
        words = {line.decode() for line in lines}
        if "nocache" in words:
            break
        left -= words


def _lock_path(dispatcher):
    """The lock file of background compiles into ``dispatcher``'s on-disk cache."""
    try:
        folder = dispatcher._cache._cache_path
    except AttributeError:  # pragma: no cover - a Numba without this internal
        import tempfile

        folder = tempfile.gettempdir()
    return os.path.join(folder, "lubelink-compile.lock")


def _compiling(path) -> bool:
    """Whether a background compile holds the lock ``path``."""
    import fcntl

    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:
        return False
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
    except OSError:
        return True
    finally:
        os.close(fd)
    return False


#: The background compile this process started (kept to reap it).
_BACKGROUND: list = []


def first_run(model, motion=None, say=None):
    """The model a first run uses, with what it needs compiled: the one policy of :func:`lubelink.simulate`
    and ``lubelink run`` (:func:`lubelink.simulate.run` itself only runs; a kernel not compiled yet is
    compiled where it is first called, in one process).

    With compiled kernels that are neither loaded nor in the on-disk cache: a run estimated within
    :data:`FIRST_RUN_LIMIT` as Python (``solver.backend = "auto"``) gets ``model``'s ``numpy``-backend
    copy while a background process compiles (see the module); any other is compiled here, on two cores
    (:func:`compile_on_two_cores`), after ``say(line)`` has told how long that takes. Planar models and the
    slider-crank only, on POSIX, unless ``LUBELINK_PREWARM=0``; ``LUBELINK_FIRST_RUN=compile`` always
    compiles first.
    """
    config = model.config
    from . import integrate
    from .choice import method_name

    if (not _helped(model, motion) or not model.compiled
            or method_name(config) not in integrate.COMPILED_METHODS):
        return model
    p_type = model.params_type
    if id(p_type) in _WARM:
        return model
    from .integrate.driver import signatures
    from .link.model import rhs

    for proc in list(_BACKGROUND):  # reap the ones that ended
        if proc.poll() is not None:
            _BACKGROUND.remove(proc)
    lock = _lock_path(rhs)
    busy = _compiling(lock)
    if _is_warm(rhs, signatures(p_type)[0].args) and (not busy or _run_is_cached(config, p_type)):
        _WARM[id(p_type)] = p_type
        return model
    if config.solver.backend == "auto" and os.environ.get("LUBELINK_FIRST_RUN", "python") != "compile":
        chosen = _as_python(model, lock, busy)
        if chosen is not None:
            return chosen
    if say is not None:
        say(COMPILING)
    compile_on_two_cores(model, motion)
    return model


def kernels_ready(config) -> bool:
    """Whether a run of ``config`` in this process would find its compiled kernels, loaded or in the on-disk
    cache (the right-hand side, the method's step and the driver): then it costs what a warm run costs, and
    timing it measures the run (a sweep's pilot points, :func:`lubelink.sweep.execute.choose_executor`). The
    ``numpy`` backend compiles nothing: True. The spatial link: False (not checked here)."""
    from .build import build_model
    from .integrate.driver import signatures
    from .link.model import rhs

    model = build_model(config)
    if not model.compiled:
        return True
    if model.params.spatial is not None:
        return False
    p_type = model.params_type
    if id(p_type) in _WARM:
        return True
    return _is_warm(rhs, signatures(p_type)[0].args) and _run_is_cached(config, p_type)


def _run_is_cached(config, p_type) -> bool:
    """Whether the integration of a run of ``config`` is in the on-disk cache beyond its right-hand side: its
    method's step and the driver for ``p_type``. A background compile builds the right-hand side first, so
    while one holds the lock a cached right-hand side alone does not say that the run is cached; this does
    (the results' kernels, if missing, then compile in the run, in seconds)."""
    from . import integrate
    from .choice import method_name
    from .integrate.driver import advance, advance_types, signatures

    method = integrate.method(method_name(config))
    return _is_warm(method.step, signatures(p_type)[3].args) and _is_warm(advance, advance_types(p_type))


#: What a first run that compiles says before it does.
COMPILING = "compiling the kernels, once for this configuration's kind (about 30-60 s; cached on disk)"


@contextlib.contextmanager
def announcing(say):
    """Within the block, ``say(COMPILING)`` once, when Numba starts compiling a function.

    Yields the once-only ``say`` (for :func:`first_run`, so a compile it announces is not announced
    twice), or None when ``say`` is None. Numba's ``numba:compile`` event fires on a compilation, not on a
    load from the on-disk cache, so a warm run says nothing; every path that compiles (the spatial model,
    a user motion, the results' kernels) is announced, in whichever thread it compiles.
    """
    if say is None:
        yield None
        return
    said = []

    def once(line=COMPILING):
        if not said:
            said.append(line)
            say(line)

    try:
        from numba.core import event
    except ImportError:
        yield once
        return

    class _Announce(event.Listener):
        def on_start(self, ev):
            once()

        def on_end(self, ev):
            pass

    with event.install_listener("numba:compile", _Announce()):
        yield once


def _as_python(model, lock, busy):
    """``model``'s ``numpy``-backend copy for a short cold run (a background compile started unless ``busy``),
    or None when the run would be long as Python."""
    from dataclasses import replace

    from .assembly import interpreted
    from .estimate import duration, results_cost, run_cost

    config = model.config
    as_python = replace(config, solver=replace(config.solver, backend="numpy"))
    seconds = run_cost(as_python).seconds + results_cost(as_python)
    if seconds > FIRST_RUN_LIMIT:
        return None
    if busy:
        return interpreted(model, "the compiled kernels are being built in the background; later runs use them")
    from .config import to_toml

    env = dict(os.environ, LUBELINK_PREWARM="0")
    try:
        proc = subprocess.Popen([sys.executable, "-m", "lubelink._background", lock],
                                stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                env=env, start_new_session=True)
        proc.stdin.write(to_toml(config).encode())
        proc.stdin.close()
    except OSError:
        return None
    _BACKGROUND.append(proc)
    return interpreted(model, f"a first run: Python, about {duration(seconds)}, while the compiled kernels are "
                              f"built in the background, pid {proc.pid}; later runs use them")


def compile_on_two_cores(model, motion=None):
    """Compile ``model``'s integration method, its driver and the results here while a helper process
    compiles the right-hand side and the gap (:func:`start`); nothing with one core or a warm cache."""
    helper = start(model, motion)
    if helper is None:
        return
    from . import integrate
    from .choice import method_name
    from .integrate.driver import precompile

    with ctrl_c_while_compiling():
        try:
            precompile(integrate.method(method_name(model.config)), model.params_type)
            compile_results(model)
        except compile_errors():
            return  # the run itself meets the error and falls back
        wait(helper)


#: Interval [s] at which an interruption lost inside a compilation is raised again.
AGAIN = 0.05


@contextlib.contextmanager
def ctrl_c_while_compiling():
    """Make one Ctrl-C interrupt a compilation.

    Numba calls back into Python while LLVM compiles (its object cache, through ctypes); a
    KeyboardInterrupt raised there is printed as "Exception ignored on calling ctypes callback
    function" and lost, and the compilation goes on, or fails later on a half-built library. While
    this block runs in the main thread, Ctrl-C raises KeyboardInterrupt as usual and again every
    :data:`AGAIN` seconds (SIGALRM) until one leaves the block, without the report of the lost ones;
    an exception that leaves it after a Ctrl-C becomes a KeyboardInterrupt. Nothing changes where the program has its own SIGINT or
    SIGALRM handler, or outside the main thread.
    """
    import signal
    import threading

    if (threading.current_thread() is not threading.main_thread() or not hasattr(signal, "setitimer")
            or signal.getsignal(signal.SIGINT) is not signal.default_int_handler
            or signal.getsignal(signal.SIGALRM) is not signal.SIG_DFL):
        yield
        return
    pressed = []

    def on_ctrl_c(signum, frame):
        pressed.append(signum)
        signal.setitimer(signal.ITIMER_REAL, AGAIN)
        raise KeyboardInterrupt

    def again(signum, frame):
        if not isinstance(sys.exc_info()[1], KeyboardInterrupt):  # not already on its way out
            on_ctrl_c(signum, frame)

    def unraisable(report):  # the lost one is raised again: no "Exception ignored" report for it
        if not (pressed and issubclass(report.exc_type, KeyboardInterrupt)):
            hook(report)

    hook, sys.unraisablehook = sys.unraisablehook, unraisable
    signal.signal(signal.SIGALRM, again)
    signal.signal(signal.SIGINT, on_ctrl_c)
    try:
        yield
    except KeyboardInterrupt:
        raise
    except BaseException as exc:
        if pressed:
            raise KeyboardInterrupt from exc
        raise
    else:
        if pressed:
            raise KeyboardInterrupt
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGINT, signal.default_int_handler)
        signal.signal(signal.SIGALRM, signal.SIG_DFL)
        sys.unraisablehook = hook


def _stop(proc):
    if proc.poll() is None:
        proc.kill()
    proc.wait()


def _say(word):
    sys.stdout.write(word + "\n")
    sys.stdout.flush()


def main():
    """The helper: compile the right-hand side and the gap of the configuration on stdin."""
    from .config import from_dict, parse_toml
    from .integrate.driver import first_class, signatures
    from .build import build_model
    from .link.model import gap, rhs

    model = build_model(from_dict(parse_toml(sys.stdin.read(), "<prewarm>")))
    sigs = signatures(model.params_type)
    first_class(rhs, sigs[0])
    if not _cached(rhs, sigs[0].args):  # no on-disk cache here: the other process cannot profit
        _say("nocache")
        return
    _say("rhs")
    if model.watched:
        first_class(gap, sigs[1])
    _say("gap")


def compile_results(model):
    """Compile the batched results kernels of ``model``: the results of three samples of the rest state, the last in
    a contact phase where the model has a contact law (its force kernels are only called for such samples)."""
    import numpy as np

    from .results import Run, collect

    n = model.initial_state().size
    inside = np.array([0.0, 0.0, 1.0 if model.config.contact.law != "none" else 0.0])
    with np.errstate(all="ignore"):
        collect(Run(model=model, t=np.array([0.0, 1e-3, 2e-3]), y=np.zeros((3, n)), phase_side=inside,
                    phase_v=np.zeros(3), phase_point=np.full(3, 0.5 * model.config.film.pad_length)))


if __name__ == "__main__":
    main()

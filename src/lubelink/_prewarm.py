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
"""

from __future__ import annotations

import atexit
import os
import select
import subprocess
import sys
import time

__all__ = ["start", "wait"]

#: Longest wait for the helper [s]: beyond it this process compiles what it still needs itself.
WAIT_LIMIT = 120.0


def _cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - macOS, Windows
        return os.cpu_count() or 1


def _cached(dispatcher, args) -> bool:
    """Whether ``dispatcher`` has machine code for argument types ``args`` in its on-disk cache."""
    try:
        index = dispatcher._cache._cache_file._load_index()
    except Exception:  # noqa: BLE001 - a Numba without this internal: assume warm, start nothing
        return True
    return any(key[0] == args for key in index)


#: Parameter types whose right-hand side is known to be compiled or cached, by identity.
_WARM: dict = {}


def start(model, motion=None):
    """The helper process compiling ``model``'s kernels, or None (nothing to gain; see the module)."""
    if (not model.compiled or motion is not None or os.environ.get("LUBELINK_PREWARM", "1") == "0" or _cores() < 2
            or os.name != "posix" or model.params.spatial is not None):  # select() on a pipe; planar kernels only
        return None
    from .config import to_toml
    from .integrate.driver import signatures
    from .model import rhs

    p_type = model.params_type
    if id(p_type) in _WARM:  # (by identity: Numba types are interned, hashing this one walks all of it)
        return None
    args = signatures(p_type)[0].args
    if args in rhs.overloads or _cached(rhs, args):  # compiled in this process, or on disk
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
    from .assembly import build_model
    from .model import gap, rhs

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
    """Compile the batched results kernels of ``model`` (a results of two samples of the rest state)."""
    import numpy as np

    from .results import collect
    from .simulate import Run

    collect(Run(model=model, t=np.array([0.0, 1e-3]), y=np.zeros((2, model.initial_state().size))))


if __name__ == "__main__":
    main()

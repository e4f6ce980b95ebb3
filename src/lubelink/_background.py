"""The background compile of a cold first run (:func:`lubelink._prewarm.first_run` starts it).

``python -m lubelink._background LOCK`` reads a configuration (TOML) on its standard input and runs
it compiled, for Numba's on-disk cache only, at a lower priority, holding ``LOCK`` so that a second
one does not start. A module of its own: it is the one place of the first-run policy that runs a
simulation, so the policy itself (:mod:`lubelink._prewarm`) sits below :mod:`lubelink.simulate`.
"""

import os
import sys


def main(lock):
    """The background compile: run the configuration on stdin compiled, for the cache only."""
    import fcntl

    text = sys.stdin.read()
    fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:  # another one compiles
        return
    try:
        os.nice(5)
    except OSError:  # pragma: no cover
        pass
    from dataclasses import replace

    from .config import from_dict, parse_toml
    from .results import collect
    from .simulate import run

    config = from_dict(parse_toml(text, "<background>"))
    collect(run(replace(config, solver=replace(config.solver, backend="numba"))))


if __name__ == "__main__":
    main(sys.argv[1])

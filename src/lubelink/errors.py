"""Exceptions shared by the library and the command line, and the "did you mean" hint.

``ConfigError`` is invalid parameters (raised by :mod:`lubelink.validation` and
:mod:`lubelink.config`, which also serves the name); ``UsageError`` is bad command-line input
that is not a parameter. Both are reported by the CLI as one line per problem with exit status 2.
This module imports nothing heavy: the command line catches these from its first line on.
"""

from __future__ import annotations

import difflib

__all__ = ["ConfigError", "UsageError", "BackendError", "Terminated", "suggest", "exit_status", "interrupted",
           "catch_interrupts", "was_interrupted"]


class ConfigError(ValueError):
    """Invalid configuration; ``problems`` lists one message per fault."""

    def __init__(self, problems):
        self.problems = list(problems)
        super().__init__("\n".join(self.problems))


class UsageError(Exception):
    """Bad command-line input, reported as one line per problem with status 2."""


class BackendError(ValueError):
    """``solver.backend`` asks for a backend that cannot run this configuration; the message names
    the setting, why, and the alternative. The CLI reports it as one line with status 2."""


class Terminated(KeyboardInterrupt):
    """A termination signal (SIGTERM, SIGHUP) raised as an interruption, so that it gets the same
    clean-up as Ctrl-C; ``signum`` is the signal."""

    def __init__(self, signum):
        super().__init__(signum)
        self.signum = int(signum)


#: The Ctrl-C signals this process received since :func:`catch_interrupts`.
_INTERRUPTS: list = []


def catch_interrupts():
    """Let Ctrl-C raise ``KeyboardInterrupt`` as Python's own handler does, and remember that it came
    (:func:`was_interrupted`); nothing changes where SIGINT is not Python's default handler.

    A Ctrl-C that lands inside the interpreter's import machinery can surface as another exception:
    ``TypeError: expected a message argument`` was seen while SciPy's import looked for an optional
    module. The command line then still reports an interruption, not that exception.
    """
    import signal

    if signal.getsignal(signal.SIGINT) is not signal.default_int_handler:
        return

    def handler(signum, frame):
        _INTERRUPTS.append(signum)
        raise KeyboardInterrupt

    signal.signal(signal.SIGINT, handler)


def was_interrupted() -> bool:
    """Whether Ctrl-C came since :func:`catch_interrupts`."""
    return bool(_INTERRUPTS)


def exit_status(exc) -> int:
    """Exit status of an interruption: 130 for Ctrl-C, 128 + the signal number for the others."""
    return 128 + exc.signum if isinstance(exc, Terminated) else 130


def interrupted(exc) -> str:
    """``"interrupted"`` (Ctrl-C) or ``"terminated by SIGTERM"``."""
    if isinstance(exc, Terminated):
        import signal

        try:
            return f"terminated by {signal.Signals(exc.signum).name}"
        except ValueError:
            return f"terminated by signal {exc.signum}"
    return "interrupted"


def suggest(name, options) -> str:
    """``" (did you mean 'x'?)"`` for the option closest to ``name``, or ``""``."""
    close = difflib.get_close_matches(str(name), [str(o) for o in options], n=1)
    return f" (did you mean '{close[0]}'?)" if close else ""

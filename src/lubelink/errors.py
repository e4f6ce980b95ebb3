"""Exceptions shared by the library and the command line, and the "did you mean" hint.

``ConfigError`` (invalid parameters) lives in :mod:`lubelink.config`, where validation happens;
``UsageError`` is bad command-line input that is not a parameter. Both are reported by the CLI as
one line per problem with exit status 2.
"""

from __future__ import annotations

import difflib

__all__ = ["UsageError", "suggest"]


class UsageError(Exception):
    """Bad command-line input, reported as one line per problem with status 2."""


def suggest(name, options) -> str:
    """``" (did you mean 'x'?)"`` for the option closest to ``name``, or ``""``."""
    close = difflib.get_close_matches(str(name), [str(o) for o in options], n=1)
    return f" (did you mean '{close[0]}'?)" if close else ""

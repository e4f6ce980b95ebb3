"""``python -m lubelink``: the command, :func:`lubelink.cli.console`."""

import sys

from .errors import catch_interrupts, was_interrupted

catch_interrupts()
try:
    from .cli import console
except BaseException as exc:  # Ctrl-C while the command's module loads (console's own guard is not there yet)
    if not (isinstance(exc, KeyboardInterrupt) or (isinstance(exc, Exception) and was_interrupted())):
        raise
    sys.stderr.write("lubelink: interrupted\n")
    raise SystemExit(130) from None

console()

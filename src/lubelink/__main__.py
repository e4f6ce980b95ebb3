"""``python -m lubelink``: the command, :func:`lubelink.cli.console`."""

try:
    from .cli import console
except KeyboardInterrupt:  # Ctrl-C while the command's module loads (console's own guard is not there yet)
    import sys

    sys.stderr.write("lubelink: interrupted\n")
    raise SystemExit(130) from None

console()

"""Parameter studies on Dask (placeholder until issue 6 lands)."""


def register_cli(subparsers, add_config_args):
    """Add the ``sweep`` and ``plot-sweep`` subcommands (none yet)."""

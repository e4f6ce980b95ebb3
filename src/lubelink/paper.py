"""Reproduction of the paper's Section 6 figures (placeholder until issue 4 lands)."""


def register_cli(subparsers, add_config_args):
    """Add the ``figures`` and ``animate`` subcommands (none yet)."""

"""Subcommands of the ``rocking`` command line (see :mod:`rocking.cli`)."""

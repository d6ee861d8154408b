"""Subcommands of the tabletop command line, one module each."""

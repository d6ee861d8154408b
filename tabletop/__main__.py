from tabletop.cli import entry

entry()

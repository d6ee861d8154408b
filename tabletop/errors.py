"""The error every layer's bad input is told with, in a module that imports nothing.

:class:`InputError` lives here rather than in :mod:`tabletop.frames` (which re-exports it) so
that what is told before anything is computed (``tabletop --help``, ``--version``, a usage
error, ``tabletop status``, a kiosk's supervisor) loads no numpy: 0.2 of the 0.32 CPU s of a
``tabletop --version``.
"""

from __future__ import annotations


class InputError(ValueError):
    """Bad input from outside (a file, a packet, a CLI argument, a config value).

    Every layer raises a subclass of this with a message that names what is wrong and where; the
    command line turns it into one line on stderr and a non-zero exit.
    """

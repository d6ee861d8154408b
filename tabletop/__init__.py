"""Tabletop: the runtime that wires tracked pucks, engines and the projector view together."""

# first, before anything else loads: a stop signal from here on is one line and status 130
from tabletop import early_stop

early_stop.install()

import os  # noqa: E402

# The engines' matrix products are small (a Puppet Master step is one 24,000 x 8 product) and
# the loop already keeps both cores busy (camera, detection, view): a threaded BLAS made one
# such product take ~50 ms instead of ~0.13 ms on a 2-core machine. Set before numpy loads;
# an explicit setting in the environment wins.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

# numba, when a command loads it, started without importing SciPy (behaviors/numba_start.py)
from behaviors import numba_start  # noqa: E402

numba_start.install()

__version__ = "0.1.0"

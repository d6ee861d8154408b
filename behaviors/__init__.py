"""behaviors: the three engines, as pure functions over numpy arrays with thin stateful engines."""

# numba, when an engine loads it, started without importing SciPy (numba_start.py)
from behaviors import numba_start  # noqa: E402

numba_start.install()

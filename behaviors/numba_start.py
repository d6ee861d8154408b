"""numba started without SciPy, which it imports only to look at, where nothing here needs it.

``import numba`` imports ``scipy`` to check its version, and the first kernel a process loads
or compiles imports ``numba.np.arraymath``, which imports ``scipy.linalg`` to learn whether
compiled ``np.dot`` may call BLAS: what it learns decides only how ``np.convolve`` and
``np.correlate`` are compiled, which no kernel here calls (nor ``np.dot`` or ``np.linalg``).
That import was 0.3 of the 1.5 CPU s a `tabletop run` takes to start (numpy's lazy submodules,
f2py's regular expressions), paid by every start, kiosk restart, spare and test subprocess; the
installation itself never imports SciPy. :func:`install` hides SciPy while those two modules
run (unless something imported it before), so both find it absent, as on a machine without
it. A kernel that did call ``np.dot`` still compiles: numba imports SciPy's BLAS then. (While
those two modules run, another thread's import of SciPy would fail: the installation has none.)
"""

from __future__ import annotations

import importlib.machinery
import sys
from types import ModuleType
from typing import Any, Sequence

#: the modules of numba that import SciPy only to look at it
LOOKING = frozenset({"numba", "numba.np.arraymath"})


class _WithoutScipy:
    """Finds the :data:`LOOKING` modules as the path finder does, their code run with SciPy
    hidden (``sys.modules['scipy'] = None``: its import fails at once) where it is not
    imported yet (a finder of ``sys.meta_path``; importlib.abc's base class left out: importing
    it is 0.02 CPU s, for every command)."""

    def find_spec(self, name: str, path: Sequence[str] | None,
                  target: ModuleType | None = None) -> Any:
        if name not in LOOKING or "scipy" in sys.modules:
            return None
        spec = importlib.machinery.PathFinder.find_spec(name, path)
        if spec is None or not hasattr(spec.loader, "exec_module"):
            return None
        run = spec.loader.exec_module

        def exec_module(module: ModuleType) -> None:
            hidden = "scipy" not in sys.modules
            if hidden:
                sys.modules["scipy"] = None  # type: ignore[assignment]
            try:
                run(module)
            finally:
                if hidden and sys.modules.get("scipy", 0) is None:
                    del sys.modules["scipy"]

        spec.loader.exec_module = exec_module  # type: ignore[union-attr]
        return spec


def install() -> None:
    """The finder first on ``sys.meta_path`` (once; nothing when numba is in already)."""
    if "numba.np.arraymath" in sys.modules:
        return
    if not any(isinstance(f, _WithoutScipy) for f in sys.meta_path):
        sys.meta_path.insert(0, _WithoutScipy())

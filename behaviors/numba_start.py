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

numba's cache also refreshes its target before every load of a cached kernel: it imports and
installs every lowering and typing registry numba has, which machine code loaded from a cache
does not use (:func:`quick_loads`), parses the LLVM bitcode stored with the machine code,
which only a compile that links the kernel in uses (:func:`_unparsed_links`), and imports the
numba modules whose helpers were compiled into it, which only object-mode code would read
(:func:`_environments_unimported`); and its runtime's own functions, which numba compiled at
every start, are loaded from the kernel cache (:func:`_runtime`). These change numba's
internals: another numba than the one pinned (:data:`NUMBA`) is refused with a clear message
as it is imported.
"""

from __future__ import annotations

import importlib.machinery
import os
import sys
from types import ModuleType
from typing import Any, Sequence

#: the modules of numba that import SciPy only to look at it
LOOKING = frozenset({"numba", "numba.np.arraymath"})
#: the numba whose internals this module changes (pyproject.toml pins it)
NUMBA = "0.68.1"


class _WithoutScipy:
    """Finds the :data:`LOOKING` modules as the path finder does, their code run with SciPy
    hidden (``sys.modules['scipy'] = None``: its import fails at once) where it is not
    imported yet (a finder of ``sys.meta_path``; importlib.abc's base class left out: importing
    it is 0.02 CPU s, for every command)."""

    def find_spec(self, name: str, path: Sequence[str] | None,
                  target: ModuleType | None = None) -> Any:
        if name not in LOOKING:
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
            if name == "numba":
                quick_loads()

        spec.loader.exec_module = exec_module  # type: ignore[union-attr]
        return spec


def install() -> None:
    """The finder first on ``sys.meta_path`` (once; nothing when numba is in already)."""
    if "numba.np.arraymath" in sys.modules:
        return
    if not any(isinstance(f, _WithoutScipy) for f in sys.meta_path):
        sys.meta_path.insert(0, _WithoutScipy())


def quick_loads() -> None:
    """numba's load of a cached kernel without its refresh of the target (once a process).

    numba refreshes the target before every load: the first one imports and installs every
    lowering and typing registry it has, 0.2 of the ~1.3 CPU s a `tabletop run` takes to start
    (the drawing's first kernel 0.50 -> 0.28 CPU s in-process). Machine code loaded from a
    cache needs none of them, only numba's runtime (NRT: the symbols of the arrays a kernel
    makes), initialised here: a compile refreshes the target itself (numba's compiler does,
    before typing), and the modules a loaded kernel's globals live in are imported as its
    environment is unpickled. A load that fails so is made again as numba's own (refreshed)."""
    import numba
    from numba.core import caching
    from numba.core.runtime import rtsys

    full = caching.Cache.load_overload
    if getattr(full, "quick", False):
        return
    if numba.__version__ != NUMBA:
        raise ImportError(f"numba {numba.__version__} is installed, but behaviors/numba_start.py "
                          f"changes the internals of numba {NUMBA} (its cache loads): install "
                          f"numba=={NUMBA}, as pyproject.toml pins it (make run or make test "
                          "after `make clean`)")

    def load_overload(self: Any, sig: Any, target_context: Any) -> Any:
        if not rtsys._init:
            _runtime(target_context)
        try:
            with self._guard_against_spurious_io_errors():
                return self._load_overload(sig, target_context)
        except Exception:   # (a symbol only a registry adds; or damage, which numba's says)
            return full(self, sig, target_context)

    load_overload.quick = True  # type: ignore[attr-defined]
    caching.Cache.load_overload = load_overload
    _unparsed_links()
    _environments_unimported()


def _unparsed_links() -> None:
    """A cached kernel's machine code loaded without parsing the LLVM bitcode stored beside it.

    numba parses that bitcode as it loads the kernel, for two uses: another kernel compiled
    later that calls this one links it in (its inlining), and numba lists the symbols it
    defines, to answer whether a name is defined before asking the machine code's address of
    it. Neither is needed to run it: the bitcode is parsed when a compile links the kernel
    (:meth:`_get_module_for_linking`), and a loaded kernel's address is asked of the machine
    code itself, which gives 0 for a name it does not define, as numba's own answer is then.
    The parse and the listing were 0.11-0.17 of the 1.4-1.7 CPU s a `tabletop run` of
    config.yaml takes to start (22 kernels loaded, their bitcode declaring every function
    they call)."""
    import llvmlite.binding as ll
    from numba.core import codegen

    lib = codegen.JITCodeLibrary
    unserialize, linking = lib._unserialize.__func__, lib._get_module_for_linking
    pointer = lib.get_pointer_to_function

    def _unserialize(cls: Any, code: Any, state: Any) -> Any:
        name, kind, data = state
        if kind != "object" or cls is not lib:
            return unserialize(cls, code, state)
        self = code.create_library(name)
        self.enable_object_caching()
        self._set_compiled_object(data[0])
        self._unparsed = data[1]
        self._finalize_final_module()
        return self

    def _get_module_for_linking(self: Any) -> Any:
        bitcode = self.__dict__.pop("_unparsed", None)
        if bitcode is not None:
            self._shared_module = ll.parse_bitcode(bitcode)
            self._codegen._engine._load_defined_symbols(self._shared_module)
        return linking(self)

    def get_pointer_to_function(self: Any, name: str) -> int:
        if "_unparsed" not in self.__dict__:
            return pointer(self, name)
        self._ensure_finalized()
        return self._codegen._engine.get_function_address(name)

    lib._unserialize = classmethod(_unserialize)  # type: ignore[assignment]
    lib._get_module_for_linking = _get_module_for_linking  # type: ignore[method-assign]
    lib.get_pointer_to_function = get_pointer_to_function  # type: ignore[method-assign]


def _environments_unimported() -> None:
    """A cached kernel loaded without importing the numba modules its inlined helpers come from.

    The machine code of a kernel keeps, for every function compiled into it, an environment:
    the globals of that function's module, read only by object-mode code (a nopython kernel's
    code reads only the constants stored with it). Unpickling one imports its module: numba's
    array, ufunc and sorting implementations (numba.np.arrayobj, npyimpl, arraymath,
    misc.quicksort and what they import; 0.15 of the ~1.3 CPU s a `tabletop run` of
    config.yaml takes to start), which a load never runs. An environment of a numba module not
    imported yet gets globals naming the module only (what pickling it again stores); one of
    an imported module, or of the project's, is numba's own. A compile later in the process
    imports those modules itself (its target's refresh)."""
    from numba.core import environment

    rebuild, Environment = environment._rebuild_env, environment.Environment

    def _rebuild_env(modname: str, consts: Any, env_name: str) -> Any:
        if modname in sys.modules or not modname.startswith("numba."):
            return rebuild(modname, consts, env_name)
        env = environment.lookup_environment(env_name)
        if env is None:
            env = Environment({"__name__": modname})
            env.consts[:] = consts
            env.env_name = env_name
            Environment._memo[env_name] = env
        return env

    environment._rebuild_env = _rebuild_env


def _runtime(target_context: Any) -> None:
    """numba's runtime (NRT) initialised with its own functions' machine code from the kernel
    cache, compiled there once per numba and CPU: numba compiles them at every start (the
    first kernel a process loads), 0.027-0.035 of the ~1.2 CPU s a `tabletop run` takes to
    start. What its initialisation does otherwise is done as numba does it."""
    import pickle

    import llvmlite.binding as ll
    from numba.core import config
    from numba.core.compiler_lock import global_compiler_lock
    from numba.core.runtime import _nrt_python as _nrt
    from numba.core.runtime import nrtdynmod, rtsys

    from behaviors.kernel_cache import SHARED

    with global_compiler_lock:
        if rtsys._init:
            return
        if config.NRT_STATS:
            _nrt.memsys_enable_stats()
        for py_name, address in _nrt.c_helpers.items():
            ll.add_symbol(py_name if py_name.startswith("_") else "NRT_" + py_name, address)
        codegen, path = target_context.codegen(), runtime_file(target_context)
        library = None
        try:
            with open(path, "rb") as f:
                library = codegen.unserialize_library(pickle.loads(f.read()))
        except Exception:   # none yet, or damaged: compiled as numba does, and saved
            ir_module, library = nrtdynmod.create_nrt_module(target_context)
            library.enable_object_caching()
            library.add_ir_module(ir_module)
            library.finalize()
            tmp = f"{path}.{os.getpid()}"
            try:
                os.makedirs(SHARED, exist_ok=True)
                with open(tmp, "wb") as f:
                    f.write(pickle.dumps(library.serialize_using_object_code()))
                os.replace(tmp, path)
            except OSError:
                pass
        rtsys._library = library
        rtsys._init = True


def runtime_file(target_context: Any) -> str:
    """Where :func:`_runtime` keeps NRT's machine code: the kernel cache's file for this numba,
    llvmlite, CPU (numba's own key of compiled code: triple, CPU name, features) and NRT's
    debugging settings."""
    import hashlib

    import llvmlite
    import numba
    from numba.core import config

    from behaviors.kernel_cache import SHARED

    key = repr((numba.__version__, llvmlite.__version__, target_context.codegen().magic_tuple(),
                config.DEBUG_NRT, config.DEBUG_NRT_STACK_LIMIT))
    return os.path.join(SHARED, f"nrt-{hashlib.sha256(key.encode()).hexdigest()[:20]}")

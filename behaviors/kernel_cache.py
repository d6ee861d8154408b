"""How compiled kernels (numba) are built and cached, kept fresh across files.

A kernel is ``numba.njit(nogil=True)``: no fast-math unless its caller asks (each value's
arithmetic is fixed, so a kernel gives its Python definition's bits and keeps its NaN checks;
MOP's forward and group kernels ask only for fused multiply-adds), the interpreter lock
released, numpy's error model (a float divided by zero is an infinity or NaN, as in the numpy
rules the kernels twin: with Python's, MOP's group fed two samples of 1e30 in a row raised
ZeroDivisionError on every tick from there on while its followers went on), the machine code
cached (in :data:`SHARED` under its stamp, else beside the source, else in numba's user-wide
folder: the first that can be written) so that neither the installation's start nor a test
worker compiles it (``make kernels`` builds the caches, and removes old versions of them from
:data:`SHARED`: :mod:`behaviors.kernel_prune`). A kernel declared with a signature is loaded
from its cache when an engine that calls it is built (:func:`load`), not when it is imported.

numba's cache trusts itself while the kernel's own file is unchanged, yet every compiled
function the kernel calls from another file, and every constant it reads from one, is built
into it: after that file changed, the cache would keep the old callee. :func:`compiled`
stamps the cache with the contents of the kernel's file, of this file and of the files it
names instead (numba's own cache classes, ``numba.core.caching``: the version is pinned in
pyproject.toml), so a change to any of them builds the kernel again.
"""

from __future__ import annotations

import functools
import hashlib
import logging
import os
from types import ModuleType
from typing import Any, Callable, Iterable, Union

import numba
from numba.core import caching
from numba.core.compiler_lock import global_compiler_lock

log = logging.getLogger("tabletop")

Source = Union[ModuleType, str, "os.PathLike[str]"]

#: The project's folder: kernels all of whose files lie in it are cached in :data:`SHARED`.
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
#: The user's cache of the project's kernels, one folder per stamp (:func:`stamp`), shared by
#: every copy of the project on the machine: a fresh clone (CI's, each ``make``) loads what
#: another copy with the same files built (a cold build of all of them is about 70 CPU s).
SHARED = os.path.join(os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"),
                      "tabletop", "kernels")


def _path(source: Source) -> str:
    return os.path.abspath(source.__file__ if isinstance(source, ModuleType) else source)


def files(sources: Iterable[Source]) -> tuple[str, ...]:
    """The files a stamp covers: ``sources`` (modules or paths) and this file, each once, in
    order."""
    return tuple(sorted({_path(s) for s in sources} | {os.path.abspath(__file__)}))


@functools.lru_cache(maxsize=64)
def _digest(paths: tuple[str, ...], stats: tuple) -> bytes:
    h = hashlib.sha256()
    for path in paths:
        with open(path, "rb") as f:
            h.update(f.read())
    return h.digest()


def stamp(sources: Iterable[Source]) -> bytes:
    """SHA-256 of the contents of :func:`files` of ``sources`` (read again only when one's size
    or time changed)."""
    paths = files(sources)
    return _digest(paths, tuple((st.st_mtime_ns, st.st_size) for st in map(os.stat, paths)))


class StampedCache(caching.FunctionCache):
    """numba's cache of one function, its index stamped with :func:`stamp` of ``covers``."""
    covers: tuple[str, ...] = ()

    def load_overload(self, sig: Any, target_context: Any) -> Any:
        """numba's load; a damaged cache file (cut short by a power cut or a full disk) is
        a miss: its index is removed and the kernel is compiled again and saved afresh. numba
        raised the unpickling error, so nothing started: "internal error: UnpicklingError:
        pickle data was truncated" at every start (a kiosk restarting it for ever)."""
        try:
            return super().load_overload(sig, target_context)
        except Exception as exc:   # what unpickling damaged bytes raises is open-ended
            index = self._cache_file._index_path
            log.warning("the compiled cache of %s in %s is damaged (%s: %s); compiling it "
                        "again", self._py_func.__qualname__, os.path.dirname(index),
                        type(exc).__name__, exc)
            try:
                os.unlink(index)
            except OSError:
                pass
            return None


@functools.lru_cache(maxsize=None)
def used(folder: str) -> None:
    """``folder`` of :data:`SHARED` marked used now (its time), once a process, as a kernel
    cached there is loaded: :mod:`behaviors.kernel_prune` keeps the folders used lately."""
    try:
        os.utime(folder)
    except OSError:     # not built yet (its first save makes it), or a read-only cache
        pass


@functools.lru_cache(maxsize=None)
def _cache_class(covers: tuple[str, ...]) -> type[StampedCache]:
    class Stamped:
        def get_source_stamp(self) -> bytes:
            return stamp(covers)

    class Shared(Stamped, caching.InTreeCacheLocator):
        def __init__(self, py_func: Callable, py_file: str) -> None:
            super().__init__(py_func, py_file)
            self._cache_path = os.path.join(SHARED, stamp(covers).hex()[:20])
            used(self._cache_path)

        @classmethod
        def from_function(cls, py_func: Callable, py_file: str) -> Any:
            if not all(os.path.commonpath((ROOT, c)) == ROOT for c in covers):
                return None
            return super().from_function(py_func, py_file)

    class InTree(Stamped, caching.InTreeCacheLocator):
        pass

    class UserWide(Stamped, caching.UserWideCacheLocator):
        pass

    class Impl(caching.CompileResultCacheImpl):
        _locator_classes = [Shared, InTree, UserWide]

    return type("StampedCache", (StampedCache,), {"_impl_class": Impl, "covers": covers})


def compiled(signature: Any = None, *calls_into: Source,
             **options: Any) -> Callable[[Callable], Any]:
    """``numba.njit(nogil=True, error_model="numpy", **options)``, cached under :func:`stamp`
    of the function's own file and ``calls_into``: every module (or file) whose compiled
    functions or constants it takes in, directly or through another. With a ``signature`` it
    is compiled for that one at once and never again (a call with other types raises)."""
    def build(fn: Callable) -> Any:
        dispatcher = numba.njit(nogil=True, **{"error_model": "numpy", **options})(fn)
        covers = files((fn.__code__.co_filename, *calls_into))
        dispatcher._cache = _cache_class(covers)(fn)   # (what ``cache=True`` sets: numba's stamp)
        if signature is not None:
            _defer(dispatcher, signature)
        return dispatcher
    return build


#: The kernels declared with a signature and not loaded yet (:func:`load`).
PENDING: dict[Any, Any] = {}


def _defer(dispatcher: Any, signature: Any) -> None:
    """``dispatcher`` compiled for ``signature`` (from its cache) on its first need, not at
    import: when :func:`load` names it (an engine's build, so that no tick waits), when Python
    calls it, or when a kernel that calls it is compiled. A kernel whose callers are loaded
    from their caches is never loaded itself: their code holds its own. (CPU s, medians of 3:
    importing the Puppet Master's engine 0.93 -> 0.40, MOP's follower 0.85 -> 0.39; one second
    of ``tabletop run`` of the Puppet Master's lover 1.45 -> 1.27, 42 -> 12 of its behaviour's
    kernels loaded; of examples/mop.yaml 1.74 -> 1.69, 48 -> 22.)"""
    PENDING[dispatcher] = signature

    def compile_for_args(*args: Any, **kws: Any) -> Any:
        load(dispatcher)
        return dispatcher   # (what numba then calls with the arguments: now matched, or not)

    def get_call_template(args: Any, kws: Any) -> Any:
        load(dispatcher)
        return dispatcher.get_call_template(args, kws)

    # (numba's dispatcher looks both up on the instance: the call of an unmatched type, and
    # the typing of a call from another kernel)
    dispatcher._compile_for_args = compile_for_args
    dispatcher.get_call_template = get_call_template


def load(*dispatchers: Any) -> None:
    """Each of ``dispatchers`` made of :func:`compiled` with a signature compiled for it (loaded
    from its cache) and closed to others, if not yet: once, whichever thread asks first.

    The first-need hooks stay until the signature is compiled: another thread calling the
    kernel meanwhile waits in them (for numba's lock) and then finds it. Removed first, that
    call went to numba's own compile, which waited for the same lock and then raised
    "compilation disabled" (a studio training on its worker while the studio's view loaded
    the same kernel: 1 run in 3 of test_studio_keys' MOP slot on a loaded machine)."""
    with global_compiler_lock:    # numba's: a kernel compiled on one thread may load another
        for dispatcher in dispatchers:
            signature = PENDING.pop(dispatcher, None)
            if signature is None:
                continue
            try:
                dispatcher.compile(signature)
            except BaseException:
                PENDING[dispatcher] = signature   # (the next need tries again, and says why)
                raise
            del dispatcher._compile_for_args, dispatcher.get_call_template
            dispatcher.disable_compile()

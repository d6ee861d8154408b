"""Compiled kernels are cached under a stamp of every file they take code or constants from
(behaviors/kernel_cache.py), so that a kernel never runs a stale copy of a compiled function it
took in from another file; the drawing's shape kernels share one stamp of all their files."""

from __future__ import annotations

import ast
import dis
import functools
import importlib
import os
import shutil
from pathlib import Path
from types import ModuleType

import numba

from behaviors import kernel_cache as shared
from tabletop.drawing import kernel_cache

DRAWING = Path(kernel_cache.__file__).parent


def test_every_module_compiling_with_the_shared_stamp_is_stamped_and_every_kernel_uses_it():
    users = sorted(p.name for p in DRAWING.glob("*.py")
                   if "from tabletop.drawing.kernel_cache import kernel" in p.read_text())
    assert users and set(users) <= set(kernel_cache.FILES)
    for name in users:
        mod = importlib.import_module(f"tabletop.drawing.{name[:-3]}")
        text = (DRAWING / name).read_text()
        assert "numba.njit" not in text, name          # every compiled function via `kernel`
        found = [v for v in vars(mod).values() if isinstance(v, numba.core.registry.CPUDispatcher)
                 and v.__module__ == mod.__name__]
        assert found, name
        for disp in found:
            assert isinstance(disp._cache, shared.StampedCache), (name, disp.__name__)
            assert disp._cache._impl.locator.get_source_stamp() == kernel_cache.stamp()


def test_the_stamp_changes_when_any_of_the_files_changes(tmp_path, monkeypatch):
    for name in kernel_cache.FILES:
        shutil.copy(DRAWING / name, tmp_path / name)
    monkeypatch.setattr(kernel_cache, "_HERE", str(tmp_path))
    first = kernel_cache.stamp()
    assert kernel_cache.stamp() == first
    seen = {first}
    for name in kernel_cache.FILES:
        p = tmp_path / name
        text = p.read_text()
        p.write_text(text + "\n# changed\n")
        os.utime(p, ns=(1, 10 ** 18 + len(seen)))   # a time of its own (coarse clocks)
        now = kernel_cache.stamp()
        assert now not in seen, name
        seen.add(now)
        p.write_text(text)
        os.utime(p, ns=(1, 2 * 10 ** 18 + len(seen)))
        assert kernel_cache.stamp() == first, name     # the same contents: the same stamp


def _statements(nodes: list[ast.stmt]):
    """Every statement of ``nodes`` and of the blocks within them: an import is always a
    statement, so the expressions, most of a module's nodes, are not walked."""
    for node in nodes:
        yield node
        for block in ("body", "orelse", "finalbody", "handlers", "cases"):
            yield from _statements(getattr(node, block, None) or ())


@functools.cache
def _imported(mod) -> dict[str, str]:
    """Each name ``mod`` takes from another of the project's modules, with that module's file
    (once a module: every kernel of it asks, 559 times for 178 kernels)."""
    found = {}
    for node in _statements(ast.parse(Path(mod.__file__).read_text()).body):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0 \
                and node.module.split(".")[0] in ("tabletop", "behaviors"):
            source = importlib.import_module(node.module)
            for a in node.names:
                obj = getattr(source, a.name)
                found[a.asname or a.name] = getattr(obj, "__file__", None) or source.__file__
    return found


def _takes_in(disp, seen: set) -> set[str]:
    """The files whose compiled functions or constants ``disp`` builds into itself, through the
    kernels it calls by name or as an attribute of a module (``halts.halts``) alike."""
    mod = importlib.import_module(disp.__module__)
    imported, files = _imported(mod), {os.path.abspath(mod.__file__)}
    codes = [disp.py_func.__code__]
    while codes:
        code = codes.pop()
        codes += [c for c in code.co_consts if hasattr(c, "co_names")]
        called = [vars(mod).get(name) for name in code.co_names]
        held = None     # the module the instruction before loaded, if any
        for ins in dis.get_instructions(code):
            if held is not None and ins.opname in ("LOAD_ATTR", "LOAD_METHOD"):
                called.append(getattr(held, ins.argval, None))
            held = vars(mod).get(ins.argval) if ins.opname == "LOAD_GLOBAL" else None
            held = held if isinstance(held, ModuleType) else None
        for obj in called:
            if isinstance(obj, numba.core.registry.CPUDispatcher) and obj not in seen:
                seen.add(obj)
                files |= _takes_in(obj, seen)
        files |= {os.path.abspath(imported[name]) for name in code.co_names if name in imported}
    return files


def test_every_cached_kernel_is_stamped_with_every_file_it_takes_in():
    checked = 0
    for folder in ("tabletop/drawing", "behaviors/mop", "behaviors/puppet_master"):
        for p in sorted((DRAWING.parents[1] / folder).glob("*.py")):
            if "numba" not in p.read_text():
                continue
            mod = importlib.import_module(f"{folder.replace('/', '.')}.{p.stem}")
            for disp in vars(mod).values():
                if not isinstance(disp, numba.core.registry.CPUDispatcher) \
                        or disp.__module__ != mod.__name__ \
                        or isinstance(disp._cache, numba.core.caching.NullCache):
                    continue
                needs = _takes_in(disp, {disp})
                covers = set(getattr(disp._cache, "covers", (os.path.abspath(p),)))
                assert needs <= covers, (mod.__name__, disp.__name__, sorted(needs - covers))
                checked += 1
    assert checked >= 40


KERNEL = '''
from behaviors.kernel_cache import compiled


def twice(x):
    return 2.0 * x
'''


def test_a_damaged_cache_file_is_compiled_again(tmp_path, caplog):
    """A cache file cut short (a power cut, a full disk) stopped every start with numba's
    UnpicklingError; now the kernel is compiled again, saved afresh, and later starts load it."""
    import importlib.util
    from behaviors.kernel_cache import compiled
    (tmp_path / "tiny_kernel.py").write_text(KERNEL)
    spec = importlib.util.spec_from_file_location("tiny_kernel", tmp_path / "tiny_kernel.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)

    def build():
        return compiled("float64(float64)")(mod.twice)

    assert build()(2.0) == 4.0                       # compiled and cached
    cache = tmp_path / "__pycache__"
    for damaged in ("nbc", "nbi"):                   # the machine code, then the index
        for path in cache.glob(f"*.{damaged}"):
            path.write_bytes(path.read_bytes()[:20])
        assert build()(3.0) == 6.0, damaged          # no UnpicklingError: compiled afresh
        assert build()(4.0) == 8.0                   # the cache written afresh loads
    said = [r.getMessage() for r in caplog.records if "damaged" in r.getMessage()]
    assert len(said) == 2, said


SLOW_KERNEL = '''
import numpy as np


def spread(x):
    out = np.empty(x.size)
    for i in range(x.size):
        out[i] = np.sqrt(abs(x[i])) + np.sin(x[i]) * np.cos(x[:i + 1]).sum() - x.mean()
    return out
'''


def test_a_kernel_called_on_one_thread_while_another_loads_it_waits_for_it(tmp_path):
    """A kernel loaded by one thread (an engine's build) and called meanwhile by another (a
    training on its worker): the call waits for the load and gets the kernel's result, not
    numba's "compilation disabled" (its own compile, closed by the load it waited for)."""
    import importlib.util
    import threading
    import numpy as np
    from behaviors.kernel_cache import compiled, load
    (tmp_path / "slow_kernel.py").write_text(SLOW_KERNEL)
    spec = importlib.util.spec_from_file_location("slow_kernel", tmp_path / "slow_kernel.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    x = np.linspace(-1.0, 1.0, 5)
    for attempt in range(2):    # compiled afresh, then loaded from its cache
        kernel = compiled("float64[::1](float64[::1])")(mod.spread)
        loading = threading.Thread(target=load, args=(kernel,))
        got: dict = {}

        def call() -> None:
            while kernel in shared.PENDING:   # until the load has begun
                pass
            try:
                got["value"] = kernel(x)
            except Exception as exc:   # what the race raised
                got["error"] = exc

        caller = threading.Thread(target=call)
        caller.start()
        loading.start()
        loading.join(120)
        caller.join(120)
        assert "error" not in got, (attempt, got.get("error"))
        assert np.array_equal(got["value"], mod.spread(x)), attempt

"""The drawing's shape kernels are cached under one stamp of all their files, so that a kernel
never runs a stale copy of a compiled function it took in from another file."""

from __future__ import annotations

import importlib
import os
import shutil
from pathlib import Path

import numba

from tabletop import kernel_cache as shared
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

"""Old versions of the compiled kernels are removed from their shared cache
(behaviors/kernel_prune.py): each kernel's last few, and any folder used lately, are kept."""

from __future__ import annotations

import os
import time

from behaviors import kernel_cache, kernel_prune

DAY = 86400.0


def _folder(root, name: str, kernels: tuple[str, ...], days: float, now: float) -> None:
    """A stamp folder as numba writes one (an index and its machine code per kernel), last
    used ``days`` ago."""
    d = root / name
    d.mkdir()
    for k in kernels:
        (d / f"{k}-12.py311.nbi").write_bytes(b"i" * 100)
        (d / f"{k}-12.py311.1.nbc").write_bytes(b"c" * 900)
    for p in (*d.iterdir(), d):
        os.utime(p, (now - days * DAY, now - days * DAY))


def test_old_versions_are_removed_the_last_three_and_those_used_lately_kept(tmp_path):
    now = time.time()
    ages = {"a1": 1, "a2": 10, "a3": 20, "a4": 30, "a5": 40}      # one kernel's five versions
    for n, days in ages.items():
        _folder(tmp_path, n * 10, ("members.spot", "members.shares"), days, now)
    _folder(tmp_path, "b1" * 10, ("groups.step",), 60, now)         # its only version
    _folder(tmp_path, "c1" * 10, ("members.spot", "groups.step"), 50, now)   # b1's newer
    _folder(tmp_path, "d1" * 10, (), 2, now)                        # made, nothing saved yet
    _folder(tmp_path, "e1" * 10, (), 9, now)                        # and long ago
    (tmp_path / ".pruned-ffff-12").mkdir()                          # a prune cut short
    (tmp_path / "notes").mkdir()                                    # not the cache's own
    removed, size = kernel_prune.prune(str(tmp_path), now=now)
    assert sorted(removed) == ["a4" * 10, "a5" * 10, "e1" * 10] and size == 2 * 2 * 1000
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        [n * 10 for n in ("a1", "a2", "a3", "b1", "c1", "d1")] + ["notes"])
    # two more versions of groups.step: its oldest, b1, has three newer; c1 two of them
    _folder(tmp_path, "f1" * 10, ("groups.step",), 0, now)
    _folder(tmp_path, "f2" * 10, ("groups.step",), 0, now)
    assert kernel_prune.prune(str(tmp_path), now=now)[0] == ["b1" * 10]
    assert kernel_prune.prune(str(tmp_path), keep=2, now=now)[0] == ["a3" * 10, "c1" * 10]
    assert kernel_prune.prune(str(tmp_path / "none"), now=now) == ([], 0)


def test_a_kernel_made_marks_its_cache_folder_used(tmp_path, monkeypatch):
    """Loading a kernel marks its stamp folder used (its time), so a version in use is kept."""
    monkeypatch.setattr(kernel_cache, "SHARED", str(tmp_path))
    folder = tmp_path / kernel_cache.stamp([__file__]).hex()[:20]
    folder.mkdir()
    os.utime(folder, (1e9, 1e9))

    def twice(x):
        return 2.0 * x

    before = time.time()
    kernel_cache.compiled()(twice)
    assert folder.stat().st_mtime >= before - 1.0   # (a file system's coarser clock)

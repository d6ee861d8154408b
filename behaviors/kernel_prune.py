"""Old versions of the compiled kernels removed from their shared cache
(:data:`behaviors.kernel_cache.SHARED`, ``~/.cache/tabletop/kernels``).

Each folder there holds the kernels of one set of files at one version (its stamp): a change
to any of those files builds new folders, and the old ones stayed, about 7 MB for every version
of the kernel files. A folder is marked used whenever a process loads its kernels
(:func:`behaviors.kernel_cache.used`). :func:`prune` removes a folder once every kernel in it
has :data:`KEEP` folders used more recently, and it was itself last used over
:data:`MIN_AGE_S` ago: so never a folder being built (its files are new), nor the one a
process started in the last week loads, nor any of the last few versions a copy of the project
may go back to. A folder is first renamed out of its stamp's name, then deleted: a process
finds either the whole cache or none (a miss: the kernel is compiled and saved afresh).
``make kernels`` runs it after each build (``python -m behaviors.kernel_prune``).
"""

from __future__ import annotations

import os
import re
import shutil
import sys
import time
from collections import Counter

from behaviors.kernel_cache import SHARED

KEEP = 3                  # the versions of each kernel kept, the most recently used
MIN_AGE_S = 7 * 86400.0   # a folder used within this (s) is kept whatever its version
_STAMP = re.compile(r"^[0-9a-f]{20}$")                    # a stamp folder's name
_KERNEL = re.compile(r"^(.+)-[^-]+\.py\d+[a-z]*\.nbi$")    # numba's index: module.qualname
_GONE = ".pruned-"        # a folder being deleted (left by a prune cut short: deleted next)


def last_used(folder: str) -> float:
    """When ``folder`` was last used or written (s, the epoch): its own time (a load marks
    it) or its newest file's."""
    times = [os.stat(folder).st_mtime]
    with os.scandir(folder) as it:
        times += [e.stat().st_mtime for e in it if e.is_file()]
    return max(times)


def prune(root: str = SHARED, keep: int = KEEP, min_age_s: float = MIN_AGE_S,
          now: float | None = None) -> tuple[list[str], int]:
    """Remove the old stamp folders of ``root`` (see the module docstring): (their names, the
    bytes they held)."""
    now = time.time() if now is None else now
    try:
        names = os.listdir(root)
    except OSError:          # no cache yet (or none readable): nothing to prune
        return [], 0
    folders = []
    for name in names:
        path = os.path.join(root, name)
        if name.startswith(_GONE):
            shutil.rmtree(path, ignore_errors=True)
        elif _STAMP.match(name) and os.path.isdir(path):
            try:
                kernels = {m.group(1) for f in os.listdir(path) if (m := _KERNEL.match(f))}
                folders.append((last_used(path), name, kernels))
            except OSError:  # removed meanwhile (another prune): not ours to count
                continue
    newer: Counter[str] = Counter()     # per kernel, the folders used more recently
    removed, size = [], 0
    for used, name, kernels in sorted(folders, reverse=True):
        old = now - used > min_age_s and all(newer[k] >= keep for k in kernels)
        newer.update(kernels)
        if old:
            gone = os.path.join(root, f"{_GONE}{name}-{os.getpid()}")
            try:
                os.rename(os.path.join(root, name), gone)
            except OSError:  # gone already (another prune), or not ours to remove
                continue
            size += sum(e.stat().st_size for e in os.scandir(gone) if e.is_file())
            shutil.rmtree(gone, ignore_errors=True)
            removed.append(name)
    return removed, size


def main() -> int:
    """One line on stderr when something was removed."""
    removed, size = prune()
    if removed:
        print(f"kernel cache: removed {len(removed)} folder(s) of old kernel versions "
              f"({size / 1e6:.1f} MB) from {SHARED}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())

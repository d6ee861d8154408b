"""Files a module reads, counted by name (a module's reading function replaced for a test)."""

from collections import Counter
from pathlib import Path
from types import ModuleType


def counting_reads(monkeypatch, module: ModuleType, name: str) -> Counter:
    """Counts each call of ``module.name`` (a reader whose first argument is the file's path)
    by the file's name, for the rest of the test."""
    reads: Counter = Counter()
    real = getattr(module, name)

    def counting(path, *args, **kwargs):
        reads[Path(path).name] += 1
        return real(path, *args, **kwargs)

    monkeypatch.setattr(module, name, counting)
    return reads

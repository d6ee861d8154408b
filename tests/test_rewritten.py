"""tests/rewritten.py: the installed pytest plugins' modules are rewritten ahead of a run, once,
into the cache pytest reads, so that no worker rewrites them again."""

import shutil
from importlib import metadata
from pathlib import Path

import pytest
from _pytest.assertion import rewrite

from tabletop import bytecode_cache
from tests import rewritten


@pytest.fixture(autouse=True)
def _own_cache(tmp_path, monkeypatch):
    """The machine's cache of byte-code in the test's own folder."""
    monkeypatch.setattr(bytecode_cache, "SHARED", str(tmp_path / "bytecode"))


class _Plugin:
    """A distribution with a ``pytest11`` entry point, installed in ``root``."""

    def __init__(self, root: Path) -> None:
        self.root = root
        self.entry_points = [metadata.EntryPoint("plug", "plug.main", "pytest11")]
        self.files = [metadata.PackagePath(p) for p in (
            "plug/__init__.py", "plug/main.py", "plug-1.0.dist-info/METADATA", "other.py")]
        for f in self.files:
            (root / f).parent.mkdir(parents=True, exist_ok=True)
            (root / f).write_text("assert True\n")

    def locate_file(self, f: metadata.PackagePath) -> Path:
        return self.root / f


def test_a_plugins_modules_are_listed_until_their_rewrite_is_cached(tmp_path, monkeypatch):
    plugin = _Plugin(tmp_path)
    monkeypatch.setattr(metadata, "distributions", lambda: [plugin])
    listed = rewritten.plugin_files()
    # (a top-level module of the distribution is marked for rewriting as its packages are)
    assert listed == [tmp_path / f for f in ("other.py", "plug/__init__.py", "plug/main.py")]
    assert all(rewritten.write(str(p)) for p in listed)
    assert rewritten.plugin_files() == []
    (tmp_path / "plug" / "main.py").write_text("assert 1 == 1\n")     # changed: listed again
    assert rewritten.plugin_files() == [tmp_path / "plug" / "main.py"]


def test_a_test_module_seen_before_elsewhere_is_not_rewritten_again(tmp_path, monkeypatch):
    """A fresh clone's test modules come from the machine's cache of byte-code where their
    contents are known: not rewritten again, yet pytest reads them as its own rewrite, named
    after the clone's file."""
    first, second = tmp_path / "one" / "test_x.py", tmp_path / "two" / "test_x.py"
    first.parent.mkdir()
    first.write_text("def test_x():\n    x = 2\n    assert x == 3\n")
    assert rewritten.write(str(first))
    shutil.copytree(first.parent, second.parent, ignore=shutil.ignore_patterns("__pycache__"))
    monkeypatch.setattr(rewrite, "_rewrite_test", None)      # a rewrite would fail
    assert rewritten.write(str(second))
    pyc = rewrite.get_cache_dir(second) / ("test_x" + rewrite.PYC_TAIL)
    code = rewrite._read_pyc(second, pyc)
    assert code is not None and code.co_filename == str(second)
    namespace: dict = {}
    exec(code, namespace)
    with pytest.raises(AssertionError, match="assert 2 == 3"):     # rewritten: says the values
        namespace["test_x"]()

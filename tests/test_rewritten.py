"""tests/rewritten.py: the installed pytest plugins' modules are rewritten ahead of a run, once,
into the cache pytest reads, so that no worker rewrites them again."""

from importlib import metadata
from pathlib import Path

from tests import rewritten


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

"""The machine's cache of byte-code (tabletop/bytecode_cache.py): a module's ``.pyc`` written from
it is the one compileall writes, is imported as current, and is never stale."""

from __future__ import annotations

import importlib.util
import marshal
import os
import py_compile
import subprocess
import sys
import time

from tabletop import bytecode_cache as bc

SOURCE = "def where():\n    raise ValueError('here')\n\nVALUE = {v}\n"


def _pyc(path) -> bytes:
    with open(importlib.util.cache_from_source(str(path)), "rb") as f:
        return f.read()


def test_a_module_compiled_through_the_cache_is_compileall_s_and_imported_as_current(tmp_path):
    cache = str(tmp_path / "cache")
    first, second = tmp_path / "a" / "mod.py", tmp_path / "b" / "mod.py"
    for p in (first, second):
        p.parent.mkdir()
        p.write_text(SOURCE.format(v=1))
    assert bc.compile_one(str(first), cache) == "compiled"
    assert bc.compile_one(str(first), cache) == "current"
    assert bc.compile_one(str(second), cache) == "cached"     # same contents elsewhere
    mine = _pyc(second)
    py_compile.compile(str(second), doraise=True)
    theirs = _pyc(second)
    assert mine[:16] == theirs[:16], "the header compileall writes (time and size)"
    assert marshal.loads(mine[16:]) == marshal.loads(theirs[16:])
    # valid as the interpreter checks it, and imported with its own file's name in the code
    # (compiled from the other file's path)
    st = os.stat(second)
    importlib._bootstrap_external._validate_timestamp_pyc(
        mine, int(st.st_mtime), st.st_size, "mod", {})
    bc.compile_one(str(second), cache)
    script = ("import mod\ntry:\n    mod.where()\nexcept ValueError as e:\n"
              "    print(e.__traceback__.tb_next.tb_frame.f_code.co_filename)\n")
    out = subprocess.run([sys.executable, "-c", script], cwd=second.parent, capture_output=True,
                         text=True, env={**os.environ, "PYTHONPATH": str(second.parent)},
                         timeout=60)
    assert out.returncode == 0, out.stderr
    assert out.stdout.splitlines()[-1] == str(second)


def test_a_changed_source_is_compiled_again_never_taken_stale(tmp_path):
    cache = str(tmp_path / "cache")
    path = tmp_path / "mod.py"
    path.write_text(SOURCE.format(v=1))
    assert bc.compile_one(str(path), cache) == "compiled"
    path.write_text(SOURCE.format(v=22))
    os.utime(path, (time.time() + 5, time.time() + 5))
    assert bc.compile_one(str(path), cache) == "compiled"
    ns: dict = {}
    exec(marshal.loads(_pyc(path)[16:]), ns)
    assert ns["VALUE"] == 22
    path.write_text(SOURCE.format(v=1))          # back: its first contents, from the cache
    os.utime(path, (time.time() + 9, time.time() + 9))
    assert bc.compile_one(str(path), cache) == "cached"
    exec(marshal.loads(_pyc(path)[16:]), ns)
    assert ns["VALUE"] == 1


def test_a_source_that_does_not_compile_is_skipped_and_the_folder_walked_as_compileall_x(
        tmp_path):
    (tmp_path / "tests").mkdir()
    (tmp_path / "tests" / "t.py").write_text("X = 1\n")
    (tmp_path / "bad.py").write_text("def (:\n")
    (tmp_path / "good.py").write_text("X = 1\n")
    counts = bc.compile_all([str(tmp_path)], "/tests?/", str(tmp_path / "cache"), workers=1)
    assert counts == {"current": 0, "cached": 0, "compiled": 1, "failed": 1}
    assert not os.path.exists(importlib.util.cache_from_source(str(tmp_path / "tests" / "t.py")))


def test_entries_unused_for_a_week_are_pruned(tmp_path):
    cache = tmp_path / "cache"
    path = tmp_path / "mod.py"
    path.write_text(SOURCE.format(v=1))
    bc.compile_one(str(path), str(cache))
    (entry,) = cache.iterdir()
    assert bc.prune(str(cache)) == 0
    os.utime(entry, (time.time() - bc.MIN_AGE_S - 60,) * 2)
    assert bc.fetch(entry.name, str(cache)) is not None      # a use marks it
    assert bc.prune(str(cache)) == 0
    os.utime(entry, (time.time() - bc.MIN_AGE_S - 60,) * 2)
    assert bc.prune(str(cache)) == 1 and not entry.exists()

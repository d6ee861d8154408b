"""A library on a disk with folder permissions: a folder whose files read one by one but that
cannot be opened or listed (execute only). Run as another user would (root's override of file
permissions dropped with ``capsh``), in real processes."""

import os
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = ROOT / "behaviors" / "library"


def unprivileged(argv: list[str], cwd: Path) -> subprocess.CompletedProcess:
    """Run ``argv`` without the permission override root has (a plain user runs it as is)."""
    if os.geteuid() == 0:
        capsh = shutil.which("capsh")
        if capsh is None:
            pytest.skip("needs capsh to run without root's permission override")
        argv = [capsh, "--drop=cap_dac_override,cap_dac_read_search", "--",
                "-c", shlex.join(argv)]
    return subprocess.run(argv, cwd=cwd, capture_output=True, text=True, timeout=240,
                          env={**os.environ, "OPENBLAS_NUM_THREADS": "1"})


def _library(tmp_path: Path, locked: str, mode: int) -> Path:
    lib = tmp_path / "lib"
    for name in ("lover", "locked", "ok"):
        shutil.copytree(SHIPPED / "lover", lib / name)
    os.chmod(tmp_path, 0o777)
    os.chmod(locked and lib / locked or lib, mode)
    probe = unprivileged([sys.executable, "-c", f"import os; os.listdir({str(lib / locked)!r})"],
                         tmp_path)
    if "PermissionError" not in probe.stderr:
        pytest.skip("folder permissions are not enforced here")
    return lib


def test_a_behaviour_folder_that_cannot_be_opened_is_named_and_the_rest_loads(tmp_path):
    """Execute only, its files read by name but it cannot be held open: it was read again and
    again as if a save swapped it, then refused as "changed while it was read, 20 times"."""
    lib = _library(tmp_path, "locked", 0o111)
    code = ("import sys; sys.path.insert(0, %r)\n"
            "from tabletop import library\n"
            "print(library.list_behaviors(%r))\n"
            "for n in ('lover', 'locked', 'ok'):\n"
            "    try:\n"
            "        print(n, library.load_behavior(%r + '/' + n).demonstration.shape)\n"
            "    except library.LibraryError as exc:\n"
            "        print(n, 'refused:', exc)\n") % (str(ROOT), str(lib), str(lib))
    out = unprivileged([sys.executable, "-c", code], tmp_path)
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert lines[0] == "['locked', 'lover', 'ok']"
    assert lines[1] == "lover (2400, 7)" and lines[3] == "ok (2400, 7)"
    assert lines[2] == (f"locked refused: {lib / 'locked'}: behaviour folder cannot be opened "
                        "(Permission denied); it must be readable as a folder (chmod a+rx)")


def test_a_designer_library_that_cannot_be_listed_is_one_line_and_the_installation_runs(
        tmp_path):
    """The designer's library at write and execute only: ``tabletop run`` stopped with
    "Permission denied" (the studio listed it at start); the behaviour the config names in it
    plays, and the library is named once."""
    lib = _library(tmp_path, "", 0o333)
    (tmp_path / "cfg.yaml").write_text(
        "sources: [{kind: scripted, name: s}]\nview: {enabled: false}\nengines:\n"
        "  - {kind: puppet_master, name: pet, behavior: lib/lover, main: {puck: 1},\n"
        "     designer: {enabled: true, library: lib}}\n")
    out = unprivileged([sys.executable, "-m", "tabletop", "run", "--config", "cfg.yaml",
                        "--headless", "--seconds", "0.5"], tmp_path)
    assert out.returncode == 0, out.stderr
    said = [ln for ln in out.stderr.splitlines() if str(lib) in ln]
    assert len(said) == 1 and "the library folder cannot be listed (Permission denied)" in said[0]
    assert "ran " in out.stderr

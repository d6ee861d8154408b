"""The behaviour library: round trips, atomic saves, corrupt files refused and left alone, and
the shipped examples exactly as their scripted designers make them."""

import shutil
from pathlib import Path

import numpy as np
import pytest
import yaml

from behaviors.puppet_master import designers
from behaviors.puppet_master.engine import Behavior
from tabletop import examples, library, swap
from tabletop.library import LibraryError

SHIPPED = Path(__file__).resolve().parents[2] / "behaviors" / "library"


@pytest.fixture(scope="module")
def demo() -> np.ndarray:
    return designers.demonstrate("stalker", seed=5, seconds=8)


def test_round_trip_is_exact(tmp_path, demo):
    folder = library.save_behavior(tmp_path, "shadow", demo, {"rate_hz": 40.0, "window": 40},
                                   description="follows", source="test")
    assert folder == tmp_path / "shadow"
    assert sorted(p.name for p in tmp_path.iterdir()
                  if not p.name.endswith(swap.LOCK_SUFFIX)) == ["shadow"]   # no temporary left
    assert sorted(p.name for p in folder.iterdir()) == ["behavior.yaml", "demonstration.csv"]
    stored = library.load_behavior(folder)
    assert stored.name == "shadow" and stored.kind == "puppet_master"
    assert stored.parameters == {"rate_hz": 40.0, "window": 40}
    assert stored.demonstration.tobytes() == demo.tobytes()
    assert stored.extra["samples"] == len(demo)
    header = (folder / "demonstration.csv").read_text().splitlines()[0]
    assert header == "t,main_x,main_y,main_dir,react_x,react_y,react_dir"
    assert library.list_behaviors(tmp_path) == ["shadow"]
    Behavior.train(stored.demonstration, **stored.parameters)     # trains as saved


def test_existing_behaviour_is_not_overwritten(tmp_path, demo):
    library.save_behavior(tmp_path, "lover", demo, {})
    before = (tmp_path / "lover" / "demonstration.csv").read_bytes()
    with pytest.raises(LibraryError, match="already exists"):
        library.save_behavior(tmp_path, "lover", demo[:100], {})
    assert (tmp_path / "lover" / "demonstration.csv").read_bytes() == before
    assert library.free_name(tmp_path, "lover") == "lover-2"
    library.save_behavior(tmp_path, "lover-2", demo, {})
    assert library.free_name(tmp_path, "lover") == "lover-3"
    assert library.free_name(tmp_path, "afraid") == "afraid"


def test_a_library_under_a_file_names_that_file(tmp_path, demo):
    """'python -m tabletop.examples --out notes.txt/lib' said only 'Not a directory'."""
    (tmp_path / "notes.txt").write_text("")
    with pytest.raises(LibraryError) as err:
        library.save_behavior(tmp_path / "notes.txt" / "lib", "lover", demo, {})
    assert str(err.value) == (f"{tmp_path / 'notes.txt' / 'lib' / 'lover'}: cannot save "
                              f"behaviour: {tmp_path / 'notes.txt'} is a file")


def test_replace_writes_the_new_take(tmp_path, demo):
    library.save_behavior(tmp_path, "b", demo, {"window": 40})
    library.save_behavior(tmp_path, "b", demo[:200], {"window": 20}, replace=True)
    stored = library.load_behavior(tmp_path / "b")
    assert len(stored.demonstration) == 200 and stored.parameters == {"window": 20}


@pytest.mark.parametrize("text, words", [
    ("format: tabletop-behavior\nversion: 1\nkind: [puppet_master\n", ["line 4", "corrupt YAML"]),
    ("format: tabletop-behavior\nversion: 1\nkind: dance\n", ["kind", "dance"]),
    ("version: 1\nkind: puppet_master\n", ["format", "missing"]),
    ("format: tabletop-behavior\nversion: 1\nkind: puppet_master\nwindow: 40\n",
     ["window", "unknown key"]),
    ("format: tabletop-behavior\nversion: 1\nkind: puppet_master\nparameters: {window: lots}\n",
     ["parameters.window", "number"]),
    ("format: tabletop-behavior\nversion: 1\nkind: puppet_master\nparameters: {ratio: 2e1}\n",
     ["parameters.ratio: expected a number, got '2e1'", "as text", "write 2.0e+1"]),
    ("format: tabletop-behavior\nversion: 1\nkind: puppet_master\nparameters: {windw: 40}\n",
     ["behavior.yaml: parameters.windw (window?): unknown parameter (known: balance_gain, ",
      " window)"]),
    ("- just\n- a list\n", ["expected a mapping"]),
    ("\x00\x01garbage", ["behavior.yaml"]),
    # cut short before its parameters (a copy interrupted): an internal error, a TypeError
    ("format: tabletop-behavior\nversion: 1\nkind: puppet_master\nname: lover\ndescription: Ap",
     ["behavior.yaml: parameters: missing; expected a mapping of parameter names to numbers"]),
])
def test_corrupt_description_is_refused_and_kept_byte_identical(tmp_path, demo, text, words):
    folder = library.save_behavior(tmp_path, "x", demo, {})
    target = folder / "behavior.yaml"
    target.write_text(text)
    before = target.read_bytes()
    with pytest.raises(LibraryError) as err:
        library.load_behavior(folder)
    msg = str(err.value)
    assert str(target) in msg
    for w in words:
        assert w in msg
    with pytest.raises(LibraryError):
        library.save_behavior(tmp_path, "x", demo, {}, replace=True)
    assert target.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir() if not p.name.endswith(swap.LOCK_SUFFIX)] == ["x"]


@pytest.mark.parametrize("line, said", [
    ("  windw: 40", "windw (window?): unknown parameter (known: "),
    ("  window: 1", "window: 1 must be an integer >= 2")])
def test_a_parameter_of_a_configured_behaviour_is_named_at_its_key(tmp_path, capfd, line, said):
    """A typo or a value training refuses in behavior.yaml's parameters: named at
    ``behavior.yaml: parameters.NAME`` (it named the behaviour's folder)."""
    from tabletop.cli import main as tabletop
    folder = shutil.copytree(SHIPPED / "lover", tmp_path / "lover")
    desc = folder / "behavior.yaml"
    desc.write_text(desc.read_text().replace("  window: 40", line, 1))
    cfg = tmp_path / "c.yaml"
    cfg.write_text("sources: [{kind: scripted, pucks: [1, 2]}]\nview: {enabled: false}\n"
                   "engines: [{kind: puppet_master, name: lover, behavior: lover, "
                   "main: {puck: 1}}]\n")
    code = tabletop(["run", "--config", str(cfg), "--seconds", "0.2", "--headless"])
    (err,) = capfd.readouterr().err.splitlines()
    assert code == 2 and err.startswith(
        f"tabletop run: error: {cfg}: engines[0].behavior: {desc}: parameters.{said}"), err


@pytest.mark.parametrize("mutate, words", [
    (lambda lines: [lines[0].replace("react_dir", "react_angle")] + lines[1:],
     ["react_dir", "missing"]),
    (lambda lines: lines[:5] + ["0.0,1,1,1,1,1,1"] + lines[6:], ["strictly increase", "line 6"]),
    (lambda lines: lines[:3] + ["0.05,nan,1,1,1,1,1"] + lines[4:], ["line 4", "finite"]),
    (lambda lines: lines[:3] + ["0.05,1,1,1"] + lines[4:], ["line 4", "4 values"]),
    (lambda lines: lines[:1], ["0 data row"]),
    # cut short by a power cut or a copy, the last number whole ("-2." of "-2.432631"): every
    # row reads, but fewer than behavior.yaml's samples
    (lambda lines: lines[:41] + [lines[41][:lines[41].rindex(".") + 1]],
     ["41 samples where behavior.yaml says 320", "cut short"]),
])
def test_corrupt_demonstration_is_refused(tmp_path, demo, mutate, words):
    folder = library.save_behavior(tmp_path, "x", demo, {})
    csv = folder / "demonstration.csv"
    csv.write_text("\n".join(mutate(csv.read_text().splitlines())) + "\n")
    with pytest.raises(LibraryError) as err:
        library.load_behavior(folder)
    assert str(csv) in str(err.value)
    for w in words:
        assert w in str(err.value)


def test_missing_and_escaping_data_files(tmp_path, demo):
    folder = library.save_behavior(tmp_path, "x", demo, {})
    (folder / "demonstration.csv").unlink()
    with pytest.raises(LibraryError, match="data.demonstration.*does not exist"):
        library.load_behavior(folder)
    (tmp_path / "outside.csv").write_text(library.demonstration_csv(demo))
    desc = yaml.safe_load((folder / "behavior.yaml").read_text())
    desc["data"]["demonstration"] = "../outside.csv"
    (folder / "behavior.yaml").write_text(yaml.safe_dump(desc))
    with pytest.raises(LibraryError, match="outside the behaviour folder"):
        library.load_behavior(folder)
    with pytest.raises(LibraryError, match="behaviour folder not found"):
        library.load_behavior(tmp_path / "nobody")
    (tmp_path / "empty").mkdir()
    with pytest.raises(LibraryError, match="needs a behavior.yaml"):
        library.load_behavior(tmp_path / "empty")


@pytest.mark.parametrize("name", ["", "../up", "a/b", ".hidden", "x" * 65, "sp ace"])
def test_bad_names_are_refused(tmp_path, demo, name):
    with pytest.raises(LibraryError, match="not usable as a folder name"):
        library.save_behavior(tmp_path, name, demo, {})
    assert list(tmp_path.iterdir()) == []


def test_bad_data_writes_nothing(tmp_path, demo):
    bad = demo.copy()
    bad[3, 2] = np.nan
    with pytest.raises(LibraryError, match="not finite"):
        library.save_behavior(tmp_path, "x", bad, {})
    assert list(tmp_path.iterdir()) == []


def test_shipped_examples_load_train_and_match_their_designers():
    assert library.list_behaviors(SHIPPED) == sorted(designers.PERSONALITIES)
    for name in designers.PERSONALITIES:
        stored = library.load_behavior(SHIPPED / name)
        n = round(designers.DURATION_S.get(name, 60.0) * 40)      # afraid: 80 s, else 60
        assert stored.kind == "puppet_master" and len(stored.demonstration) == n
        assert "scripted designer" in stored.source
        b = Behavior.train(stored.demonstration, **stored.parameters)
        assert b.samples >= n - 1
    assert examples.differences(SHIPPED) == []


def test_regeneration_is_deterministic(tmp_path):
    names = ("lover", "afraid")
    fresh = examples.example_demonstration.__wrapped__("afraid")     # not the cached one
    assert fresh.tobytes() == examples.example_demonstration("afraid").tobytes()
    examples.regenerate(tmp_path / "a", names)
    examples.regenerate(tmp_path / "b", names)
    for name in names:
        for f in ("behavior.yaml", "demonstration.csv"):
            got = (tmp_path / "a" / name / f).read_bytes()
            assert got == (tmp_path / "b" / name / f).read_bytes()
            assert got == (SHIPPED / name / f).read_bytes()


def test_examples_check_command(tmp_path, capsys):
    shutil.copytree(SHIPPED, tmp_path / "lib")
    quick = ["--fidelity-seconds", "0"]
    assert examples.main(["--out", str(tmp_path / "lib"), "--check", *quick]) == 0
    f = tmp_path / "lib" / "stalker" / "demonstration.csv"
    f.write_text(f.read_text().replace("0.025,", "0.0251,", 1))
    assert examples.main(["--out", str(tmp_path / "lib"), "--check", *quick]) == 1
    assert "stalker" in capsys.readouterr().out
    assert examples.main(["--out", str(tmp_path / "lib")]) == 0
    assert examples.main(["--out", str(tmp_path / "lib"), "--check", *quick]) == 0
    # the fidelity table: every behaviour, every unseen path, demonstration beside generation
    capsys.readouterr()
    assert examples.main(["--out", str(tmp_path / "lib"), "--check",
                          "--fidelity-seconds", "6"]) == 0
    out = capsys.readouterr().out
    out, _, engine = out.partition("misses of the generation where the designer's own "
                                   "character meets the threshold (the engine's):")
    for name in designers.PERSONALITIES:
        assert f"{name}:" in out
    # each unseen path: once in every behaviour's table, once in the designer's own line
    fidelity_paths = ("slow_pauses_30hz", "fast_reversals_60hz", "loops_spins_45hz",
                      "pursuit_50hz")
    for path in fidelity_paths[:3]:
        assert out.count(path) == 2 * len(designers.PERSONALITIES)
    # and the characters shown by chasing them, against a pursuing visitor
    assert out.count("pursuit_50hz") == 2 * len(designers.CHASED)
    assert out.count("  demonstration  ") == len(designers.PERSONALITIES) + len(designers.CHASED)
    assert "fidelity:" in out and "the designer's own character" in out
    # every figure of the issue, and the time at a table edge, in every row (the
    # demonstration's: 12; each path's: 12 and the three distances between distributions)
    head = [line.split() for line in out.splitlines() if line.strip().startswith("dist m")]
    assert len(head) == len(designers.PERSONALITIES) + len(designers.CHASED)
    assert all(h[-9:] == ["at", "edge", "dist", "W1", "sect", "TV", "speed", "W1", "misses"]
               for h in head), head[0]
    demos = [line.split() for line in out.splitlines() if line.startswith("  demonstration ")]
    assert all(len(d) == 13 for d in demos), demos[0]
    # the counts bench/fidelity.py reports, as many as the tables name: 5 behaviours x 3
    # paths x 8 thresholds on the open paths, 8 against the pursuer; the engine's own misses
    # are among them and listed
    rows = [line.split() for line in out.splitlines()
            if line.split()[:1] and line.split()[0] in fidelity_paths]
    assert all(len(r) == 17 for r in rows), rows[0]
    named = [r[-1] for r in rows if r[0] != "pursuit_50hz"]
    missed = sum(0 if m == "-" else len(m.split(",")) for m in named)
    sums = [line for line in out.splitlines() if line.startswith("fidelity: ")]
    assert len(sums) == 2, sums
    assert sums[0].startswith(f"fidelity: {120 - missed} of 120 thresholds met, "), sums[0]
    assert f"of the {missed} misses are the engine's alone" in sums[0], sums[0]
    assert " event thresholds met only through their floor " in sums[0], sums[0]
    assert " of 8 thresholds met, " in sums[1] and " of 1 behaviour/path pairs " in sums[1]
    assert engine and all(line.startswith("  ") for line in engine.splitlines()[1:])


def test_examples_check_refuses_fidelity_seconds_it_cannot_measure(capsys):
    """nan and -5 printed no table as if 0 was given; 0.01 and inf ended in a traceback, 1e9
    asked for 224 GiB: each is refused naming the option, before anything is read."""
    for bad in ("nan", "-5", "0.01", "inf", "1e9"):
        with pytest.raises(SystemExit) as exc:
            examples.main(["--check", "--fidelity-seconds", bad])
        assert exc.value.code == 2
        err = capsys.readouterr().err
        assert "argument --fidelity-seconds" in err and bad in err and "Traceback" not in err


def test_a_long_name_is_kept_again_and_again(tmp_path, demo):
    """A designer name of the longest length (64): the first keep took it, every later one
    was refused ('...-2' is not usable as a folder name); the number now takes its room."""
    name = "shy_" + "x" * 60
    kept = []
    for _ in range(11):
        free = library.free_name(tmp_path, name)
        library.save_behavior(tmp_path, free, demo, {})
        kept.append(free)
    assert kept[0] == name and kept[1] == name[:62] + "-2" and kept[10] == name[:61] + "-11"
    assert all(len(k) == 64 for k in kept) and len(set(kept)) == 11
    assert library.list_behaviors(tmp_path) == sorted(kept)

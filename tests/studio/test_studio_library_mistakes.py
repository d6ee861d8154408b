"""The designer studio's library as designers leave it: a broken behaviour among good ones,
folders named by hand, undo that cannot be done yet. Real folders, real engines."""

import shutil
from pathlib import Path

import numpy as np
import pytest

from tabletop import library
from tabletop.frames import Frame
from tests.studio.test_studio_keys import Bench, designer

SHIPPED = Path(__file__).resolve().parents[2] / "behaviors" / "library"


def shipped_library(tmp_path: Path, broken: str | None = None) -> Path:
    """``tmp_path/lib`` holding the shipped bully and lover, and with ``broken`` a behaviour
    folder of that name whose behavior.yaml is corrupt."""
    lib = tmp_path / "lib"
    for name in ("bully", "lover"):
        shutil.copytree(SHIPPED / name, lib / name)
    if broken is not None:
        (lib / broken).mkdir()
        (lib / broken / "behavior.yaml").write_text("kind: [\n")
    return lib


class Keys:
    """Commands to a studio, one frame each; returns the status line."""

    def __init__(self, bench: Bench) -> None:
        self.bench, self.t = bench, 1000.0

    def __call__(self, cmd: str = "") -> str:
        self.t += 1.0
        _, studio = self.bench.step(Frame(seq=int(self.t), t=self.t,
                                          commands=(cmd,) if cmd else ()))
        return studio.label


def test_switching_passes_over_a_behaviour_that_does_not_load(tmp_path):
    """A corrupt behaviour first in name order is passed over: ] plays the next that loads and
    says why the broken one was skipped (trying it again and again would play nothing and leave
    the others out of reach)."""
    lib = shipped_library(tmp_path, "aaa")
    (e,) = designer(tmp_path)
    keys = Keys(Bench([e], tmp_path))
    said = keys("designer.item_next")
    assert "playing bully (2 of 3)" in said and "skipped 1 that do not load" in said
    assert str(lib / "aaa" / "behavior.yaml") in said and e.behavior_name == "bully"
    assert "playing lover (3 of 3)" in keys("designer.item_next")
    said = keys("designer.item_next")                       # round again, past the broken one
    assert "playing bully (2 of 3)" in said and e.behavior_name == "bully"
    assert "playing lover (3 of 3)" in keys("designer.item_previous")
    shutil.rmtree(lib / "bully")
    shutil.rmtree(lib / "lover")
    said = keys("designer.item_next")
    assert "cannot: no item of the library loads" in said


def test_undo_gives_back_a_name_made_by_hand_and_waits_until_it_can_be_done(tmp_path):
    """A folder copied in by hand as "my lover", renamed in the studio: undo gives the old name
    back, though the studio would not make it ("not usable as a folder name"). An undo that
    cannot be done now (the deleted name taken again) stays in the undo list until it can."""
    lib = tmp_path / "lib"
    shutil.copytree(SHIPPED / "lover", lib / "my lover")
    shutil.copytree(SHIPPED / "bully", lib / "bully")
    (e,) = designer(tmp_path)
    keys = Keys(Bench([e], tmp_path))
    assert "playing bully" in keys("designer.item_next")
    assert "playing my lover" in keys("designer.item_next")
    assert "renamed my lover to shy" in keys("designer.rename:shy")
    assert "undone: rename my lover -> shy" in keys("designer.undo")
    assert sorted(p.name for p in lib.iterdir() if not p.name.startswith(".")) == \
        ["bully", "my lover"]
    assert e.behavior_name == "my lover"
    assert "deleted my lover" in keys("designer.delete")
    shutil.copytree(SHIPPED / "afraid", lib / "my lover")      # the name is taken again
    said = keys("designer.undo")
    assert "cannot" in said and "exists again" in said
    assert (lib / "my lover" / "behavior.yaml").read_text() == \
        (SHIPPED / "afraid" / "behavior.yaml").read_text()
    shutil.rmtree(lib / "my lover")
    assert "undone: delete my lover" in keys("designer.undo")
    assert (lib / "my lover" / "behavior.yaml").read_text() == \
        (SHIPPED / "lover" / "behavior.yaml").read_text()
    assert "nothing to undo" in keys("designer.undo")


OTHER_STUDIO = """
import os, sys, time
sys.path.insert(0, {root!r})
from pathlib import Path

import pytest

from tabletop import library
from tabletop import swap
from tabletop.files import new_folder
target = Path({target!r})
with swap.locked(target):
    print("held", flush=True)
    ino = os.stat(target.parent / ".pet.tabletop-lock").st_ino
    end = time.monotonic() + 120
    while not any("->" in ln and f":{{ino}} " in ln for ln in open("/proc/locks")):
        if time.monotonic() > end:
            sys.exit(3)
        time.sleep(0.01)
    shipped = Path({shipped!r})
    new_folder(target, {{n: (shipped / n).read_text() for n in
                         ("behavior.yaml", "demonstration.csv")}}, marker=swap.MARKER)
"""


def test_two_studios_keeping_one_name_in_one_library_both_keep(tmp_path):
    """Another studio's keep of "pet" saves while this one's waits for the name's lock: the
    name was free when this one looked, and its take is kept under the next free name (not
    refused as "already exists")."""
    import subprocess
    import sys
    from behaviors.puppet_master import designers
    from tests.studio.test_studio_keys import demo_frames
    if not Path("/proc/locks").exists():
        import pytest
        pytest.skip("needs /proc/locks to see the waiting save")
    lib = tmp_path / "lib"
    lib.mkdir()
    (e,) = designer(tmp_path)
    bench = Bench([e], tmp_path)
    demo = designers.demonstrate("lover", seed=8, seconds=6)
    for f in demo_frames(demo, {5: ("designer.record",), 200: ("designer.record",)}):
        _, studio = bench.step(f)
    assert studio.action == "trying"
    root = str(Path(__file__).resolve().parents[2])
    other = subprocess.Popen([sys.executable, "-c", OTHER_STUDIO.format(
        root=root, target=str(lib / "pet"), shipped=str(SHIPPED / "bully"))],
        stdout=subprocess.PIPE, text=True)
    try:
        assert other.stdout.readline().strip() == "held"
        said = Keys(bench)("designer.keep")
    finally:
        assert other.wait(timeout=120) == 0
    assert "kept as pet-2" in said, said
    assert (lib / "pet" / "behavior.yaml").read_text() == \
        (SHIPPED / "bully" / "behavior.yaml").read_text()
    from tabletop import library
    assert len(library.load_behavior(lib / "pet-2").demonstration) == 195
    assert e.behavior_name == "pet-2"


@pytest.mark.parametrize("needs, stop, said", [(2.0, 89, "1.9 s of both pucks, needs 2 s"),
                                                (3.0, 103, "2.3 s of both pucks, needs 3 s")])
def test_a_take_too_short_reads_its_length_in_whole_tenths(tmp_path, needs, stop, said):
    """A take's length is said in whole tenths rounded down, the float error of frame times left
    out: a take of 1.96 s against min_seconds 2 says 1.9 s (not "take too short (2.0 s of both
    pucks, needs 2 s)"), one of 2.3 s (93 rows at 40 Hz; 2.299999999999997 s between frame
    times near t = 100 s) says 2.3 s (not 2.2 s)."""
    from behaviors.puppet_master import designers
    from tests.studio.test_studio_keys import demo_frames
    (e,) = designer(tmp_path, min_seconds=needs)
    bench = Bench([e], tmp_path)
    demo = designers.demonstrate("lover", seed=8, seconds=4)     # 40 Hz rows
    labels = [bench.step(f)[1].label for f in demo_frames(
        demo, {10: ("designer.record",), stop: ("designer.record",)})]
    assert f"take too short ({said})" in labels[stop], labels[stop]


def test_switching_is_refused_during_a_take(tmp_path):
    """] is refused while a take is recorded and between its parts: switching the behaviour in
    play would train the take with the other behaviour's parameters (a take of the afraid
    character, edge_percentile 50, with another character's defaults)."""
    from behaviors.puppet_master import designers
    from tabletop.frames import Puck
    lib = tmp_path / "lib"
    for name in ("afraid", "bully", "lover"):
        shutil.copytree(SHIPPED / name, lib / name)
    (e,) = designer(tmp_path, sequential=True)
    bench = Bench([e], tmp_path)
    keys = Keys(bench)
    assert "playing afraid (1 of 3)" in keys("designer.item_next")
    demo = designers.demonstrate("afraid", seed=4, seconds=6)
    said = []
    for i, row in enumerate(demo):                            # the main part, ] halfway
        cmds = {0: ("designer.record",), 100: ("designer.item_next",),
                len(demo) - 1: ("designer.record",)}.get(i, ())
        _, studio = bench.step(Frame(seq=i, t=2000.0 + row[0], pucks=(Puck(1, *row[1:4]),),
                                     commands=cmds))
        said.append(studio.label)
    assert "no switching during a take" in said[100], said[100]
    assert e.behavior_name == "afraid"
    _, studio = bench.step(Frame(seq=1000, t=2010.0, commands=("designer.item_next",)))
    assert studio.action == "ready" and "no switching during a take" in studio.label
    assert e.behavior_name == "afraid"
    for i, row in enumerate(demo):                            # the reaction, to the playback's end
        _, studio = bench.step(Frame(seq=2000 + i, t=2020.0 + row[0],
                                     pucks=(Puck(2, *row[4:7]),),
                                     commands=("designer.record",) if i == 0 else ()))
    assert studio.action == "trying", studio.label
    assert bench.studio.target.pending.param_dict()["edge_percentile"] == 50.0
    keys.t = 3000.0
    assert "take discarded" in keys("designer.discard")
    assert "playing bully (2 of 3)" in keys("designer.item_next")          # after the take


def two_studios(tmp_path: Path) -> tuple:
    """Two designer studios (A and B) on one library holding bully and lover: their benches,
    key pressers and B's engine."""
    lib = shipped_library(tmp_path)
    (a,) = designer(tmp_path)
    (b,) = designer(tmp_path)
    bench_a, bench_b = Bench([a], tmp_path / "a"), Bench([b], tmp_path / "b")
    return bench_a, bench_b, Keys(bench_a), Keys(bench_b), b


def looks(bench: Bench, keys: Keys, listing: bool = True) -> str:
    """The studio's watchers look now (each every second while the loop runs, in its own
    tick): the behaviour in play's, and with ``listing`` the library's; what it says."""
    target = bench.studio.target
    target.lib_poller._next = 0.0 if listing else float("inf")
    if target.play_poller is not None:
        target.play_poller.every_s, target.play_poller._next = 0.0, 0.0
    bench.studio.poll()
    return keys()


def test_a_behaviour_deleted_by_another_studio_is_said_removed_and_the_studio_goes_on(tmp_path):
    """Two studios on one library play bully; one deletes it. The other says bully was removed
    (not "1 bad library file(s): ... behaviour folder not found"), plays on from memory,
    switches to another, and takes it back after the undo."""
    bench_a, bench_b, ka, kb, b = two_studios(tmp_path)
    lib = tmp_path / "lib"
    assert "playing bully (1 of 2)" in ka("designer.item_next")
    assert "playing bully (1 of 2)" in kb("designer.item_next")
    tb = bench_b.studio.target

    def look(listing: bool = True) -> str:
        return looks(bench_b, kb, listing)

    assert "deleted bully" in ka("designer.delete")
    said = look(listing=False)
    assert "bully was removed from the library" in said and "bad library file" not in said, said
    assert bench_b.studio.problems == [] and tb.current() is None
    assert b.behavior is not None                      # it plays on from memory
    assert "bad library file" not in look()
    assert "undone: delete bully" in ka("designer.undo")
    said = look()
    assert "bully is back in the library" in said and tb.current() == "bully", said
    assert b.behavior_name == "bully" and bench_b.studio.problems == []
    assert "deleted bully" in ka("designer.delete")
    look()
    assert "playing lover (1 of 1)" in kb("designer.item_next")    # goes on with another
    assert "undone: delete bully" in ka("designer.undo")
    assert "back in the library" not in look() and tb.current() == "lover"
    assert b.behavior_name == "lover" and bench_b.studio.problems == []


@pytest.mark.parametrize("background", [False, True])
def test_switching_is_refused_while_a_take_is_tried(tmp_path, background):
    """] is refused while a take is tried (or trained), and K keeps the take that plays
    (playing the library item there, the studio would still say "try it" and K keep the take
    under a name while the item played on)."""
    from behaviors.puppet_master import designers
    from tests.studio.test_studio_keys import demo_frames
    lib = shipped_library(tmp_path)
    (e,) = designer(tmp_path, background_training=background)
    bench = Bench([e], tmp_path)
    keys = Keys(bench)
    assert "playing bully (1 of 2)" in keys("designer.item_next")
    demo = designers.demonstrate("lover", seed=8, seconds=6)
    said = [bench.step(f)[1].label for f in demo_frames(
        demo, {5: ("designer.record",), 200: ("designer.record", "designer.item_next")},
        t0=2000.0)]
    assert "no switching while a take is tried" in said[200], said[200]
    keys.t = 3000.0
    label = keys()                                   # a background take swaps in by now
    assert bench.studio.state == "trying", label
    take, demo = bench.studio.target.pending, bench.studio.target.demo
    assert take is not None and e.behavior is take and e.behavior_name == "new take"
    said = keys("designer.item_previous")
    assert "no switching while a take is tried" in said, said
    assert e.behavior is take and bench.studio.state == "trying"
    assert "kept as pet" in keys("designer.keep")
    assert e.behavior is take and e.behavior_name == "pet"
    assert np.array_equal(library.load_behavior(lib / "pet").demonstration, demo)
    assert "playing bully (1 of 3)" in keys("designer.item_next")      # after the take


def test_a_behaviour_deleted_elsewhere_and_back_never_plays_over_a_take(tmp_path):
    """Two studios play bully. While B tries a take, A deletes bully and undoes it; deleted
    before the take and back after its keep, too. B's take plays until K or X, never bully
    over it (K would keep the take as pet while bully played under that name); after X, bully
    is reloaded."""
    from behaviors.puppet_master import designers
    from tests.studio.test_studio_keys import demo_frames
    bench_a, bench_b, ka, kb, b = two_studios(tmp_path)
    lib = tmp_path / "lib"
    assert "playing bully (1 of 2)" in ka("designer.item_next")
    assert "playing bully (1 of 2)" in kb("designer.item_next")
    tb = bench_b.studio.target
    demo = designers.demonstrate("lover", seed=8, seconds=6)

    def look() -> str:
        return looks(bench_b, kb)

    def take(t0: float):
        for f in demo_frames(demo, {5: ("designer.record",), 200: ("designer.record",)},
                             t0=t0):
            _, studio = bench_b.step(f)
        assert studio.action == "trying", studio.label
        kb.t = t0 + 100.0
        return tb.pending

    def plays(behavior, name: str) -> bool:
        return b.behavior is behavior and b.behavior_name == name

    tried = take(2000.0)                                 # A deletes bully and undoes it
    assert "deleted bully" in ka("designer.delete")
    look()
    assert "undone: delete bully" in ka("designer.undo")
    for _ in range(3):
        said = look()
        assert plays(tried, "new take"), (b.behavior_name, said)
    assert "try it" in said and bench_b.studio.state == "trying", said
    assert "take discarded" in kb("designer.discard")
    assert b.behavior_name == "bully"
    look()                                               # the change is seen after the take
    assert b.behavior_name == "bully" and b.behavior is not tried and tb.current() == "bully"
    tried = take(3000.0)
    assert "deleted bully" in ka("designer.delete")
    look()
    assert "undone: delete bully" in ka("designer.undo")
    look()
    assert plays(tried, "new take")
    assert "kept as pet" in kb("designer.keep") and plays(tried, "pet")
    for _ in range(2):
        look()
        assert plays(tried, "pet") and tb.current() == "pet"
    assert "playing bully (1 of 3)" in kb("designer.item_next")
    assert "deleted bully" in ka("designer.delete")      # deleted before the take, back after
    assert "bully was removed from the library" in look()
    tried = take(4000.0)
    assert "kept as pet-2" in kb("designer.keep") and plays(tried, "pet-2")
    assert "undone: delete bully" in ka("designer.undo")
    for _ in range(2):
        said = look()
        assert plays(tried, "pet-2") and tb.current() == "pet-2", (b.behavior_name, said)
        assert "is back" not in said, said


def test_a_problem_of_lover_2_stays_said_when_lover_reloads_or_goes(tmp_path):
    """lover-2's broken file stays said when lover is reloaded or deleted elsewhere: a problem
    is the behaviour in play's when it names that folder or a file in it (pm_shelf._about), so
    one of lover-2 is not lover's, though its file name starts the same."""
    import os
    lib = shipped_library(tmp_path, "lover-2")
    (a,) = designer(tmp_path)
    (b,) = designer(tmp_path)
    bench_a, bench_b = Bench([a], tmp_path / "a"), Bench([b], tmp_path / "b")
    ka, kb = Keys(bench_a), Keys(bench_b)
    for keys in (ka, kb):
        keys("designer.item_next")
        assert "playing lover (2 of 3)" in keys("designer.item_next")
    tb = bench_b.studio.target

    def problems() -> list[str]:
        """B's watcher of the behaviour in play looks now (not the library's)."""
        tb.lib_poller._next = float("inf")
        if tb.play_poller is not None:
            tb.play_poller.every_s, tb.play_poller._next = 0.0, 0.0
        bench_b.studio.poll()
        kb()
        return bench_b.studio.problems

    broken = str(lib / "lover-2" / "behavior.yaml")
    assert [p for p in problems() if p.startswith(broken)] and len(problems()) == 1
    csv, before = lib / "lover" / "demonstration.csv", b.behavior
    csv.write_text(csv.read_text())                 # lover edited: reloaded
    st = csv.stat()
    os.utime(csv, ns=(st.st_atime_ns, st.st_mtime_ns + 10**9))
    said = problems()
    assert b.behavior is not before and b.behavior_name == "lover"
    assert len(said) == 1 and said[0].startswith(broken), said
    assert "deleted lover" in ka("designer.delete")
    said = problems()
    assert tb.current() is None and "lover was removed" in bench_b.studio.message
    assert len(said) == 1 and said[0].startswith(broken), said


def test_a_behaviour_the_config_names_is_not_renamed_or_deleted(tmp_path):
    # F2 on the behaviour in play renamed the folder the config names: the next start failed
    # ("engines[0].behavior: 'lib/shy' does not exist"); the others rename and delete as ever
    from tabletop.config import validate_config
    from tabletop.studio.build import studio_targets
    from tabletop.studio.machine import Studio
    from tests.studio.test_studio_keys import build
    lib = tmp_path / "lib"
    shutil.copytree(SHIPPED / "afraid", lib / "shy")
    shutil.copytree(SHIPPED / "lover", lib / "pet")
    entries = [{"kind": "puppet_master", "name": "a", "behavior": "lib/shy",
                "designer": {"enabled": True, "library": "lib"}},
               {"kind": "puppet_master", "name": "b", "behavior": "lib/pet", "main": {"puck": 3},
                "designer": {"enabled": True, "library": "lib"}}]
    cfg = validate_config({"sources": [{"kind": "scripted"}], "engines": entries},
                          str(tmp_path / "c.yaml"), tmp_path)
    studio = Studio(studio_targets(build(entries, tmp_path), cfg, tmp_path, False), 0.0)
    assert studio.target.current() == "shy"
    for cmd in ("designer.rename:calm", "designer.delete"):
        studio.command(cmd)
        assert studio.message == ("cannot: the config names shy (engines[0].behavior), so the "
                                  "next start would fail without it; change the config first")
    studio.command("designer.item_next")             # pet: named by engine b's config
    studio.command("designer.rename:calm")
    assert "engines[1].behavior" in studio.message
    assert library.list_behaviors(lib) == ["pet", "shy"]
    (lib / "extra").mkdir()                          # one no config names: renamed
    shutil.copytree(SHIPPED / "lover", lib / "extra", dirs_exist_ok=True)
    studio.command("designer.item_previous")
    assert studio.target.current() == "extra", studio.message
    studio.command("designer.rename:calm")
    assert studio.message == "renamed extra to calm"
    assert library.list_behaviors(lib) == ["calm", "pet", "shy"]

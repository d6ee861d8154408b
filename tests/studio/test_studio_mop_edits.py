"""Rename, delete and undo of a MOP action kept through the studio: the library, the trash and
the engine follow each, with or without a library."""

import yaml

from tests.studio.mop_table import kept_line, kept_without_library


def test_a_kept_take_is_not_renamed_over_a_configured_action(tmp_path):
    """Renaming the face's kept take "circle" replaced its configured circle (talk) with the
    take on reload, and undo then took "circle" from the face altogether."""
    engine, table = kept_line(tmp_path)
    s = table.studio
    s.command("designer.item_next")
    s.command("designer.rename:circle")
    assert "already exists" in s.message
    s.poll()
    face = engine.puppets["face"].actions
    assert set(face) == {"circle", "take1"} and face["circle"].clip.name == "talk"
    s.command("designer.rename:  ")                    # a blank name is no name (the kept
    assert "rename needs a new name" in s.message      # action was skipped at reload)
    s.command("designer.rename:line")                  # a free name is still renamed to
    s.poll()
    assert set(face) == {"circle", "line"} and face["circle"].clip.name == "talk"
    s.command("designer.undo")
    s.poll()
    assert set(face) == {"circle", "take1"}

def deleted_take(tmp_path):
    """The kept take1 of a line, deleted in the studio: (engine, studio, the face's library
    folder, take1.csv's bytes before the delete)."""
    engine, table = kept_line(tmp_path)
    folder = tmp_path / "lib" / "face"
    kept = (folder / "take1.csv").read_bytes()
    s = table.studio
    s.command("designer.item_next")
    s.command("designer.delete")
    return engine, s, folder, kept

def test_a_deleted_action_goes_into_the_trash_and_undo_brings_it_back(tmp_path):
    """README: Delete moves the item into the library's .trash. A kept MOP take lost its entry
    only: its CSV stayed, and the next run's take1 wrote over it."""
    engine, s, folder, kept = deleted_take(tmp_path)
    s.poll()
    assert not (folder / "take1.csv").exists() and "take1" not in engine.puppets["face"].actions
    (trashed,) = (folder / ".trash").iterdir()
    assert trashed.name.startswith("take1.csv.") and trashed.read_bytes() == kept
    s.command("designer.undo")
    s.poll()
    assert (folder / "take1.csv").read_bytes() == kept and "take1" in engine.puppets["face"].actions

def test_an_undo_that_failed_half_way_is_done_on_the_next_try(tmp_path):
    """The undo of a delete put the template back, then could not write the entries (here
    actions.yaml stands as a folder): tried again, it said "take1.csv: exists again" forever
    and every older undo stayed out of reach."""
    engine, s, folder, kept = deleted_take(tmp_path)
    (folder / "actions.yaml").unlink()
    (folder / "actions.yaml").mkdir()
    s.command("designer.undo")
    assert s.message.startswith("cannot") and s.undo_stack[-1][0] == "delete take1", s.message
    assert (folder / "take1.csv").read_bytes() == kept    # half-way: the template is back
    (folder / "actions.yaml").rmdir()
    s.command("designer.undo")
    assert s.message == "undone: delete take1", s.message
    assert [u.what for u in s.undo_stack] == ["keep take1"]     # the older undo next
    entries = yaml.safe_load((folder / "actions.yaml").read_text())["actions"]
    assert [a["name"] for a in entries] == ["take1"]
    assert (folder / "take1.csv").read_bytes() == kept and "take1" in engine.puppets["face"].actions

def test_delete_undo_and_rename_are_followed_on_their_own_tick(tmp_path):
    """They were followed when the library's watcher next looked (wall-clock time), so a
    replay changed the characters on other ticks than the live run (371 of 1147 frames
    differed); and after undoing a delete, F2 said "nothing to rename"."""
    engine, table = kept_line(tmp_path)
    s, target = table.studio, table.targets[0]
    target._poller.every_s = 1e9                 # the watcher does not look again
    s.command("designer.item_next")
    s.command("designer.delete")
    assert "take1" not in engine.puppets["face"].actions
    s.command("designer.undo")
    assert "take1" in engine.puppets["face"].actions and s.message == "undone: delete take1"
    s.command("designer.rename:wave")
    assert s.message == "renamed take1 to wave"
    assert set(engine.puppets["face"].actions) == {"circle", "wave"}
    target._poller.every_s = 0.0
    assert not target._poller.changed()          # nothing left for the watcher to apply

def test_undo_delete_and_rename_of_a_take_kept_for_this_run_only(tmp_path):
    """Without a library, U, Del and F2 after a keep raised AssertionError out of the studio;
    the keep's undo entry stayed and every later U raised again, for every character."""
    engine, table, _ = kept_without_library(tmp_path)
    s, face = table.studio, engine.puppets["face"].actions
    table.tick(["designer.rename:wave"])
    assert "has no library" in table.status and set(face) == {"circle", "take1"}
    table.tick(["designer.delete"])
    assert "deleted take1" in table.status and "take1" not in face
    table.tick(["designer.undo"])
    assert table.status.endswith("undone: delete take1") and "take1" in face
    table.tick(["designer.undo"])
    assert table.status.endswith("undone: keep take1") and "take1" not in face
    assert s.undo_stack == []
    table.tick(["designer.undo"])
    assert table.status.endswith("nothing to undo")

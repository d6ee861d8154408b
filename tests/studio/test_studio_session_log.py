"""The studio's session log and its review sheet: keeps, renames, undone keeps, deletes and
restores each written as the library holds them, and a log or sheet that cannot be written said
in one line while the studio goes on."""

import json

from behaviors.puppet_master import designers
from tabletop import library
from tabletop.studio.session import SessionLog
from tests.studio.test_studio_keys import kept_pet


def test_a_rename_after_the_keep_is_in_the_session_log_and_its_review(tmp_path):
    """The session log named the kept take "pet" after F2 had renamed its folder "brave": the
    contact sheet and the log pointed at a folder that was gone."""
    from tabletop.studio.review import read_session, summary
    bench = kept_pet(tmp_path)
    bench.studio.command("designer.rename:brave")
    bench.studio.command("designer.undo")              # back to pet
    bench.studio.command("designer.rename:shy")
    assert library.list_behaviors(tmp_path / "lib") == ["shy"]
    lines = [json.loads(x) for x in bench.session.path.read_text().splitlines()]
    assert [(x["outcome"], x["name"], x.get("renamed_from", "")) for x in lines] == [
        ("kept", "pet", ""), ("renamed", "brave", "pet"), ("renamed", "pet", "brave"),
        ("renamed", "shy", "pet")]
    assert all(x["review"] == "" and x["samples"] == 0 for x in lines[1:])
    assert "renamed_from" not in lines[0]               # a try's line: its keys alone
    tries = read_session(bench.session.path)
    assert [(t["outcome"], t["name"]) for t in tries] == [("kept", "shy")]
    assert summary(tries).startswith("1 try, 1 kept")
    assert len(bench.studio.tries) == 1                # a rename is no try


def test_an_undone_keep_is_in_the_session_log_and_its_review_counts_it_not_kept(tmp_path):
    """U after K writes a "keep undone" line (no samples, no sheet), and the review counts the
    take not kept (without it, "1 kept" for a take whose folder is in the trash)."""
    from tabletop.studio.review import read_session, summary
    bench = kept_pet(tmp_path)
    bench.studio.command("designer.undo")
    assert library.list_behaviors(tmp_path / "lib") == []
    lines = [json.loads(x) for x in bench.session.path.read_text().splitlines()]
    assert [(x["outcome"], x["name"]) for x in lines] == [("kept", "pet"), ("keep undone", "pet")]
    assert lines[1]["review"] == "" and lines[1]["samples"] == 0
    tries = read_session(bench.session.path)
    assert [(t["outcome"], t["name"]) for t in tries] == [("keep undone", "pet")]
    assert summary(tries).startswith("1 try, 0 kept (nothing kept)")
    assert len(bench.studio.tries) == 1                # an undone keep is no try


def test_a_kept_take_deleted_and_restored_is_in_the_session_log_and_its_review(tmp_path):
    """Delete of a kept take writes a "deleted" line and its undo a "restored" one, and the
    review counts the take kept, not kept, kept again (without them the log said "kept"
    while the take's folder was in the trash)."""
    from tabletop.studio.review import read_session, summary
    bench = kept_pet(tmp_path)
    bench.studio.command("designer.delete")
    assert library.list_behaviors(tmp_path / "lib") == []

    def logged() -> tuple[list[tuple[str, str]], list[tuple[str, str]], str]:
        lines = [json.loads(x) for x in bench.session.path.read_text().splitlines()]
        assert all(x["review"] == "" and x["samples"] == 0 for x in lines[1:])
        tries = read_session(bench.session.path)
        return ([(x["outcome"], x["name"]) for x in lines],
                [(t["outcome"], t["name"]) for t in tries], summary(tries))

    lines, tries, said = logged()
    assert lines == [("kept", "pet"), ("deleted", "pet")]
    assert tries == [("deleted", "pet")] and said.startswith("1 try, 0 kept (nothing kept)")
    bench.studio.command("designer.undo")
    assert library.list_behaviors(tmp_path / "lib") == ["pet"]
    lines, tries, said = logged()
    assert lines == [("kept", "pet"), ("deleted", "pet"), ("restored", "pet")]
    assert tries == [("kept", "pet")] and said.startswith("1 try, 1 kept")
    assert len(bench.studio.tries) == 1                # a delete or restore is no try


def test_a_session_log_that_cannot_be_written_is_said_once_and_the_studio_goes_on(tmp_path,
                                                                                   caplog):
    # a folder that is gone or a full disk: one warning line (it was a traceback per try)
    from types import SimpleNamespace

    from tabletop.studio.take import Try
    (tmp_path / "file").write_text("not a folder")
    log_ = SessionLog(tmp_path / "file" / "studio", review=False)
    target = SimpleNamespace(what="behaviour")
    with caplog.at_level("WARNING", logger="tabletop"):
        for k in range(3):
            log_.log_try(Try("pet", "behaviour", 1e9 + k, outcome="kept"), target)
    said = [r for r in caplog.records if "session log not written" in r.getMessage()]
    assert len(said) == 1 and said[0].exc_info is None and log_.lines == 0
    # the file in the way is named (the system said "Not a directory", or "File exists")
    assert f"{tmp_path / 'file'} is a file, not a folder" in said[0].getMessage()
    assert log_.failing
    with caplog.at_level("WARNING", logger="tabletop"):
        assert log_.save_take(".csv", "t\n0\n") == ""      # a take tried at quit: said
    assert f"the take was not saved: {tmp_path / 'file'} is a file, not a " \
        "folder" in caplog.records[-1].getMessage()
    log_.folder = tmp_path / "studio"             # back: written, and said again if it fails
    log_.path = log_.folder / log_.path.name
    log_.log_try(Try("pet", "behaviour", 1e9, outcome="kept"), target)
    assert log_.lines == 1 and not log_.failing


def test_a_review_sheet_that_cannot_be_written_is_one_line(tmp_path, caplog):
    """The studio folder replaced by a file while running: the sheet's failure was a
    traceback ("FileExistsError: [Errno 17] File exists"); it is one line naming the file."""
    from types import SimpleNamespace

    from tabletop.studio.take import Try
    (tmp_path / "studio").write_text("not a folder")
    log_ = SessionLog(tmp_path / "studio", review=True)
    target = SimpleNamespace(what="behaviour",
                             demo=designers.demonstrate("lover", seed=3, seconds=3))
    log_.wait()                     # the plotting library loaded: the sheet is drawn
    with caplog.at_level("WARNING", logger="tabletop"):
        log_.log_try(Try("pet", "behaviour", 1e9, outcome="discarded"), target)
        log_.wait()
    said = [r for r in caplog.records if "review sheet" in r.getMessage()]
    assert len(said) == 1 and said[0].exc_info is None, caplog.text
    assert f"{tmp_path / 'studio'} is a file, not a folder" in said[0].getMessage()

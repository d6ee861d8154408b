"""A take kept under a free name when its name is taken meanwhile (tabletop.names)."""

from pathlib import Path

import pytest

from tabletop.frames import InputError
from tabletop.files import NameTaken, keep_under_free_name


def saver(folder: Path, take: dict):
    """Save the take as ``folder/NAME`` (a file), refusing a name the folder holds."""
    def save() -> Path:
        path = folder / take["name"]
        try:
            with open(path, "x") as f:
                f.write("take")
        except FileExistsError:
            raise NameTaken(f"{path}: taken") from None
        return path
    return save


def test_a_taken_name_is_kept_under_the_next_free_one(tmp_path):
    (tmp_path / "take1").write_text("other run")
    take = {"name": "take1"}
    free = iter(["take2", "take3"])
    saved = keep_under_free_name(saver(tmp_path, take), lambda n: take.update(name=n),
                                 lambda: next(free))
    assert saved == tmp_path / "take2" and take["name"] == "take2"
    assert (tmp_path / "take1").read_text() == "other run"


def test_a_keep_refused_every_time_says_so_and_saves_nothing(tmp_path):
    """After 1000 refusals the retry loops fell through: the take was said "kept as X" and
    nothing was saved."""
    (tmp_path / "take1").write_text("other run")
    take = {"name": "take1"}
    with pytest.raises(InputError, match="name was taken 5 times"):
        keep_under_free_name(saver(tmp_path, take), lambda n: take.update(name=n),
                             lambda: "take1", tries=5)
    assert [p.name for p in tmp_path.iterdir()] == ["take1"]

"""F2's prompt renames the item it named: a control marker may switch the item (or the target)
while the name is typed; Enter then renames nothing, and says so. Real folders, real engines."""

import shutil
from pathlib import Path

import pygame

from tabletop.studio.draw import NamePrompt
from tests.studio.test_studio_keys import Bench, designer
from tests.studio.test_studio_library_mistakes import Keys

SHIPPED = Path(__file__).resolve().parents[2] / "behaviors" / "library"


def key(k: int, text: str = "") -> pygame.event.Event:
    return pygame.event.Event(pygame.KEYDOWN, key=k, unicode=text, mod=0)


def typed(prompt: NamePrompt, name: str) -> str | None:
    """``name`` typed into the open prompt, then Enter: the command sent."""
    for c in name:
        prompt.handle(key(pygame.K_a, c))
    return prompt.handle(key(pygame.K_RETURN))


def test_enter_renames_the_item_the_prompt_named_not_the_one_switched_to(tmp_path):
    lib = tmp_path / "lib"
    for name in ("bully", "lover"):
        shutil.copytree(SHIPPED / name, lib / name)
    (e,) = designer(tmp_path)
    bench = Bench([e], tmp_path)
    keys = Keys(bench)
    assert "playing bully" in keys("designer.item_next")
    prompt = NamePrompt()
    prompt.ask = bench.studio.may_rename
    prompt.handle(key(pygame.K_F2))
    assert prompt.line.startswith("rename bully as")
    assert "playing lover" in keys("designer.item_next")     # a marker's ] meanwhile
    cmd = typed(prompt, "brave")
    assert cmd == "designer.rename:bully=brave"
    said = keys(cmd)
    assert "nothing renamed: lover plays now, not bully" in said, said
    assert sorted(p.name for p in lib.iterdir() if not p.name.startswith(".")) == \
        ["bully", "lover"] and e.behavior_name == "lover"
    prompt.handle(key(pygame.K_F2))                          # named what plays: renamed
    assert "renamed lover to brave" in keys(typed(prompt, "brave"))
    assert sorted(p.name for p in lib.iterdir() if not p.name.startswith(".")) == \
        ["brave", "bully"] and e.behavior_name == "brave"
    assert "undone: rename lover -> brave" in keys("designer.undo")

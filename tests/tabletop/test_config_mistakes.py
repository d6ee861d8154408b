"""A config with several mistakes is refused once, naming every mistake found with its key
path: the first as a refusal of it alone says it, then ``(and N more: PATH: WHAT; ...)``."""

from pathlib import Path

import pytest
import yaml

from tabletop.cli import main as tabletop
from tabletop.config import validate_config
from tabletop.schema import ConfigError

# four mistakes in four places: a top-level section, a source's options (a plugin's schema), a
# list item and an unknown key beside them
FOUR = """\
loop: {rate_hz: 0}
sources:
  - kind: scripted
    pucks: [1, 2]
    bogus: 1
view: {enabled: false, size: [10, 720], fps: 3}
"""
FIRST = "loop.rate_hz: expected a number of Hz in [1.0, 1000.0], got 0.0 (out of range)"
MORE = ["sources[0].bogus: unknown key", "view.fps: unknown key",
        "view.size[0]: expected an integer number of pixels in [64, 8192], got 10"]


def test_every_mistake_is_named_on_the_one_line(tmp_path: Path, capfd) -> None:
    cfg = tmp_path / "table.yaml"
    cfg.write_text(FOUR)
    code = tabletop(["run", "--config", str(cfg), "--seconds", "0.2", "--headless"])
    lines = capfd.readouterr().err.strip().splitlines()
    assert code == 2 and len(lines) == 1, lines
    head, _, rest = lines[0].partition(" (and 3 more: ")
    assert head == f"tabletop run: error: {cfg}: {FIRST}"
    for said in MORE:
        assert said in rest, rest
    assert str(cfg) not in rest and "Traceback" not in rest


def test_each_mistake_is_kept_with_its_path() -> None:
    with pytest.raises(ConfigError) as refused:
        validate_config(yaml.safe_load(FOUR), "table.yaml")
    found = [e.at for e in refused.value.found]
    assert found[0] == FIRST and len(found) == 4
    for at, said in zip(found[1:], MORE):
        assert at.startswith(said)


def test_a_check_of_keys_all_right_runs_beside_a_mistake_elsewhere() -> None:
    """The tracking section's own check (a marker id key) still speaks when the view is wrong;
    the checks across sections wait for every key to be right."""
    text = FOUR.replace("loop: {rate_hz: 0}", "tracking: {puck_ids: {one: 1}}")
    with pytest.raises(ConfigError) as refused:
        validate_config(yaml.safe_load(text), "table.yaml")
    found = [e.at for e in refused.value.found]
    assert found[0] == "tracking.puck_ids.one: expected a marker id (a whole number) as the key"
    assert len(found) == 4



# six mistakes: the first, three said after it, two counted
SIX = FOUR + "recorder: {bogus: 2}\n"


def test_many_mistakes_say_the_first_few_and_count_the_rest() -> None:
    """A config copied away from its files refuses every file it names: the line says the first
    mistakes and counts the others; every one is kept."""
    with pytest.raises(ConfigError) as refused:
        validate_config(yaml.safe_load(SIX + "tracking: {bogus: 1}\n"), "table.yaml")
    found, said = refused.value.found, str(refused.value)
    assert len(found) == 6
    assert " (and 5 more: " in said and said.endswith("; 2 more not shown)"), said
    for e in found[1:4]:
        assert e.at in said
    for e in found[4:]:
        assert e.at not in said

"""The takes the studio's MOP tests start from (a face's take tried, kept, kept without a
library)."""

from tabletop.plugins.mop_table import build, designer_config
from tabletop.studio.mop_table import StudioTable


def face_take(tmp_path, gesture: str = "line"):
    """A run with the face's take of ``gesture`` being tried; (engine, table), the library
    read at once."""
    engine = build(designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib")
    for t in table.targets:
        t._poller.every_s = 0.0
    table.rest(1.0)
    table.tick(["designer.record"])
    table.perform(gesture)
    table.stop_take()
    return engine, table

def kept_line(tmp_path):
    """The face's take of a line, kept as take1; (engine, table), the library read at once."""
    engine, table = face_take(tmp_path)
    table.tick(["designer.keep"])
    return engine, table

def kept_without_library(tmp_path, cfg: dict | None = None):
    """A face's take of a line kept "for this run only" by an engine without a library
    (``cfg``: the designer config by default, its library taken away). Returns (the engine,
    its studio table, the config)."""
    cfg = cfg or designer_config(tmp_path)
    cfg["engines"][0].pop("library", None)
    engine = build(cfg, tmp_path)
    table = StudioTable(engine, None)
    table.rest(1.0)
    table.tick(["designer.record"])
    table.perform("line")
    table.stop_take()
    table.tick(["designer.keep"])
    assert "for this run only" in table.status
    return engine, table, cfg

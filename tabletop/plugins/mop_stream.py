"""Start-up checks of a MOP ``stream`` input's columns (``tabletop.plugins.mop``'s schema)."""

from __future__ import annotations

from tabletop.schema import Context


def check_stream(value: dict, path: str, ctx: Context) -> None:
    """Refuse a stream input without its name or columns, and ``relative_to`` columns that do
    not split the chosen columns into groups, repeat a column, or are chosen too: a chosen
    column less itself reads 0 at every sample (columns [0, 1, 2, 3] relative to [0, 1] gave
    two constant features, and the follower's mean log-likelihood on one path went 0.98 ->
    2.36), and a repeated one subtracts one coordinate from every other (y - x)."""
    if not value["name"]:
        raise ctx.error(f"{path}.name", "a stream input needs the stream's name")
    if value["columns"] is None:
        raise ctx.error(f"{path}.columns", "a stream input needs its columns, e.g. [0, 1, 2]")
    rel, cols = value["relative_to"], value["columns"]
    if rel is None:
        return
    if len(set(rel)) != len(rel):
        raise ctx.error(f"{path}.relative_to", f"{rel} repeats a column: give the root's or "
                        "head's x, y[, z] columns once each")
    both = sorted(set(rel) & set(cols))
    if both:
        raise ctx.error(f"{path}.relative_to", f"column(s) {both} are chosen in columns too and "
                        "would read 0 at every sample: choose only the columns read relative "
                        "to them")
    if len(cols) % len(rel):
        raise ctx.error(f"{path}.relative_to", f"{len(rel)} column(s) are subtracted from each "
                        f"group of as many of columns' {len(cols)}: give columns in groups of "
                        f"{len(rel)}")

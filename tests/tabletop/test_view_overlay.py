"""The operator overlay: its refresh, spread over frames, yet showing the new figures and notices;
its stage figures (numpy's median and p99, one sort); its panel, placed clear of characters and
the studio's marks; the halo rings' cache forgets its oldest ring."""

import dataclasses
import time

import numpy as np
import pygame
import pytest

import tabletop.view as view_module

from tabletop.config import validate_config
from tabletop.frames import CharacterState, Frame, SourceHealth
from tabletop.loop import LoopStats
from tabletop.view import (OVERLAY_REFRESH_S, ProjectorView, overlay_lines, overlay_steps,
                           panel_tail)
from tests.tabletop.test_view import SIZE, TABLE, at, new_renderer, rgb

pytestmark = pytest.mark.usefixtures("pygame_display")


def stats_with_stages(n_stages: int) -> LoopStats:
    stats = LoopStats()
    for i in range(n_stages):
        for k in range(200):
            stats.record(f"stage{i}", 0.001 * (k % 7 + i))
    return stats


def test_overlay_steps_yield_per_stage_and_end_with_the_head_of_overlay_lines():
    stats = stats_with_stages(6)
    frame = Frame(seq=12, t=3.0)
    steps = list(overlay_steps(frame, stats))
    assert all(s is None for s in steps[:-1]) and len(steps) - 1 == len(stats.samples)
    assert steps[-1] + panel_tail(frame, ["a notice"]) == overlay_lines(frame, stats,
                                                                        ["a notice"])
    assert any("stage5" in line and "ms p99" in line for line in steps[-1])


def test_the_view_refreshes_its_overlay_over_a_few_frames_with_new_figures_and_notices(monkeypatch):
    monkeypatch.setattr(view_module, "OVERLAY_SLICE_S", 0.0)   # one step of the refresh per frame
    cfg = validate_config({"sources": [{"kind": "scripted"}],
                           "view": {"size": [320, 200], "headless": True, "overlay": True}})
    stats = stats_with_stages(40)
    view = ProjectorView((1.2, 0.8), cfg["view"], stats=stats)
    try:
        view.consume(Frame(seq=1, t=0.0))
        assert view._overlay[0].startswith("tick 1 ")          # the first one at once
        view.notices.append(lambda: ["config refused: test"])
        time.sleep(OVERLAY_REFRESH_S + 0.01)
        seen = []
        for seq in range(2, 200):
            view.consume(Frame(seq=seq, t=seq / 60))
            seen.append(view._overlay[0])
            if "config refused: test" in view._overlay:
                break
        assert "config refused: test" in view._overlay
        assert view._overlay[0].startswith("tick 2 ")          # the figures of the refresh's frame
        # one frame per stage's percentiles and per line: the old lines until all was done
        assert len(seen) >= 40 and all(s.startswith("tick 1 ") for s in seen[:-1])
        assert pygame.display.get_surface() is not None
    finally:
        view.close()


def test_stage_figures_are_numpys_median_and_p99():
    import numpy as np
    stats = LoopStats()
    rng = np.random.default_rng(3)
    for n in (1, 2, 7, 240, 600):
        stats.samples.pop("x", None)
        values = rng.random(n) * 0.02
        for v in values:
            stats.record("x", float(v))
        med, p99 = stats.stage_ms("x")
        assert abs(med - np.median(values) * 1e3) < 1e-9
        assert abs(p99 - np.percentile(values, 99) * 1e3) < 1e-9
    assert stats.stage_ms("never") is None


def test_a_full_light_cache_forgets_its_oldest_light_only():
    from tabletop.drawing import primitives as P
    P._rings.clear()
    P._ring_calls.clear()
    first = P.ring_surface(20, 4, (255, 0, 0), 1.0)
    for k in range(P._CACHE_MAX + 5):
        P.ring_surface(20, 4, (k % 256, k // 256, 7), 1.0)
    assert len(P._rings) == P._CACHE_MAX
    assert (20, 4.0, (255, 0, 0), 1.0) not in P._rings          # the oldest went
    assert (20, 4.0, (255 % 256, 0, 7), 1.0) in P._rings         # recent ones stay
    again = P.ring_surface(20, 4, (255, 0, 0), 1.0)
    assert pygame.image.tobytes(again, "RGB") == pygame.image.tobytes(first, "RGB")


def test_a_view_asked_to_run_headless_does_not_say_there_is_no_display(caplog, monkeypatch):
    monkeypatch.setenv("DISPLAY", ":99")          # a display there, not opened: headless asked
    cfg = validate_config({"sources": [{"kind": "scripted"}],
                           "view": {"size": [320, 200], "headless": True}})
    view = ProjectorView((1.2, 0.8), cfg["view"])
    try:
        with caplog.at_level("INFO", logger="tabletop"):
            view.consume(Frame(seq=1, t=0.0))
    finally:
        view.close()
    said = [r.getMessage() for r in caplog.records if "headless" in r.getMessage()]
    assert len(said) == 1 and "no display" not in said[0] and "asked" in said[0], said
    assert said[0].startswith("the view runs headless"), said   # what first, then why


def test_an_overlay_line_wider_than_the_window_wraps_inside_it():
    """The studio's line naming a bad library file ran past the window's right edge."""
    from tabletop.renderer import Renderer
    renderer = Renderer((1.2, 0.8), (480, 270), margin=24)
    target = pygame.Surface((480, 270))
    short = renderer.draw_overlay(target, ["tick 1", "studio: [lover] R record"])
    long = renderer.draw_overlay(target, ["tick 1", "studio: [lover] R record, [ ] switch, "
                                          "F2 rename | 1 bad library file(s): /tmp/studio/lib/"
                                          "bully/behavior.yaml: corrupt YAML at line 3"])
    assert long.right <= 480 - 8 and long.left >= 8
    pad = 2 * 10 - 2                           # the panel's padding less one line gap
    line = (short.height - pad) / 2
    assert long.height - pad >= 3 * line       # the long line wrapped (measured: 3 lines)


def test_overlay_text_sits_on_a_translucent_panel():
    r = new_renderer()
    s = pygame.Surface(SIZE)
    r.draw(s, Frame(seq=0, t=0.0), ["tick 1", "60.0 fps"])
    img = rgb(s)
    panel = r._overlay_img.get_rect(topleft=(8, 8))
    region = img[panel.top:panel.bottom, panel.left:panel.right].sum(axis=2)
    assert region.max() > 500                                  # light text
    corner = img[panel.bottom - 4, panel.right - 4]             # panel over the black margin
    assert corner.sum() < 30


def test_overlay_panel_moves_away_from_a_character_in_its_corner():
    r = new_renderer()
    s = pygame.Surface(SIZE)
    c = CharacterState("lover", 0.1, 0.75, 0.0, size=0.15, color=(240, 110, 150))
    lines = ["tick 1", "60.0 fps   skipped 0   errors 0", "source camera: ok"]
    for k in range(3):
        r.draw(s, Frame(seq=k, t=k * 0.3, characters=(c,)), lines)
    x, y = r.map.point(0.1, 0.75)
    assert at(rgb(s), (x, y))[0] > 200     # the character is not hidden under the panel
    assert r._room.corner != 0                  # which has left the top-left corner


@pytest.mark.parametrize("action,least", [("recording", 450), ("trying", 1100)])
def test_overlay_panel_leaves_the_studios_rec_seconds_and_try_keys_visible(action, least):
    """The designer records with the overlay on (it marks the selected target): the panel sat
    top-left over the studio's "REC 4.6 s" and "TRY: K keep ..." (seen in an Xvfb walk)."""
    r = new_renderer()
    s = pygame.Surface(SIZE)
    studio = CharacterState("studio", 0.0, 0.0, 0.0, kind="studio", size=0.0, action=action,
                            progress=4.6, label=f"[lover] {action}", color=(255, 60, 60))
    lines = ["tick 1", "60.0 fps   skipped 0   errors 0"] + [f"  stage{i}  1.00 ms"
                                                            for i in range(10)]
    for k in range(3):
        r.draw(s, Frame(seq=k, t=k * 0.3, characters=(studio,)), lines)
    x, y = map(int, r.map.point(0.04, TABLE[1] - 0.04))   # where the studio puts its mark
    mark = pygame.Rect(x - 14, y - 18, 236, 36)               # its dot and words
    panel = r.panel
    assert not panel.colliderect(mark), (panel, mark)         # top-left over it before
    word = rgb(s)[mark.top:mark.bottom, mark.left:mark.right].astype(int)
    colour = np.array((255, 60, 60) if action == "recording" else (90, 220, 120))
    bright = int((np.abs(word - colour).sum(axis=2) < 20).sum())   # its own colour, unveiled
    assert bright > least, bright   # measured REC 548, TRY 1540; under the panel 323, 749


def test_overlay_panel_leaves_the_studio_status_line_even_for_a_corner_with_a_character():
    """Seen in an Xvfb walk: the panel, moved bottom-left while the status line was short,
    stayed over "cannot save behaviour: No space left on device" (characters elsewhere)."""
    r = new_renderer()
    s = pygame.Surface(SIZE)
    w, h = TABLE
    chars = tuple(CharacterState(f"c{i}", x, y, 0.0, size=0.15, color=(240, 110, 150))
                  for i, (x, y) in enumerate([(0.1, h - 0.1), (w - 0.1, h - 0.1),
                                              (w - 0.1, 0.1)]))
    lines = ["tick 1", "60.0 fps   skipped 0   errors 0"] + [f"  stage{i}  1.00 ms"
                                                            for i in range(10)]
    for k in range(3):                                  # no studio words: bottom-left is free
        r.draw(s, Frame(seq=k, t=k * 0.3, characters=chars), lines)
    assert r._room.corner == 2
    said = ("[lover] cannot: /media/library/lover-2: cannot save behaviour: No space left on "
            "device")
    studio = CharacterState("studio", 0.0, 0.0, 0.0, kind="studio", size=0.0, action="trying",
                            label=said, color=(255, 60, 60))
    for k in range(3, 6):
        r.draw(s, Frame(seq=k, t=k * 0.3, characters=chars + (studio,)), lines)
    x, y = map(int, r.map.point(0.02, 0.02))           # the status line's start
    panel = r.panel
    assert not panel.collidepoint(x + 5, y - 10), r._room.corner   # stayed in corner 2 before


def test_overlay_lists_rates_and_sources():

    st = LoopStats()
    for i in range(10):
        st.record("engines", 0.001)
        st.tick_times.append(i / 60.0)
    f = Frame(seq=5, t=1.0, health=(SourceHealth("camera", False, "reconnecting in 2 s", 3.0),))
    assert "-.- fps" in "\n".join(overlay_lines(f, st))   # 0.15 s of ticks: no rate yet
    for i in range(10, 61):
        st.tick_times.append(i / 60.0)
    text = "\n".join(overlay_lines(f, st))
    assert "60.0 fps" in text and "engines" in text and "1.00 ms" in text
    assert "camera: DOWN" in text and "reconnecting" in text


def test_overlay_names_the_latency_capture_to_render_as_the_readme_and_run_log_do():

    st = LoopStats()
    for i in range(10):
        st.record("capture_age", 0.012)
        st.record("engines", 0.001)
    lines = overlay_lines(Frame(seq=5, t=1.0), st)
    latency = [line for line in lines if "12.00 ms median" in line]
    assert len(latency) == 1 and "capture-to-render" in latency[0], lines  # said capture_age
    assert not any("capture_age" in line for line in lines)
    engines = next(line for line in lines if "engines" in line)
    assert engines.index("ms median") == latency[0].index("ms median")   # columns kept


def test_a_long_overlay_line_leaves_a_corner_clear_of_the_studios_words():
    """Seen in an Xvfb snapshot: one long overlay line (the studio's, naming a bad library file)
    made the panel as wide as the window, and every corner then hid the REC mark (top-left) or
    the wrapped status line (bottom)."""
    from tabletop.renderer import Renderer
    size = (1280, 720)
    r = Renderer(TABLE, size, margin=24)
    s = pygame.Surface(size)
    label = ("[lover] behaviour (none): R record, [ ] switch, F2 rename, Del delete, U undo | 1 "
             "bad library file(s): /home/gallery/studio/library/bully-3/behavior.yaml: corrupt "
             "YAML at line 3 (mapping values are not allowed here)")
    studio = CharacterState("studio", 0.0, 0.0, 0.0, kind="studio", size=0.0, action="recording",
                            progress=4.6, label=label, color=(255, 60, 60))
    lines = ["tick 1", "60.0 fps   skipped 0   errors 0"] + [
        f"  stage{i}   1.00 ms median   2.00 ms p99" for i in range(9)] + ["studio: " + label]
    for k in range(3):
        r.draw(s, Frame(seq=k, t=k * 0.3, characters=(studio,)), lines)
    (W, H), (w, h), panel = size, r._overlay_img.get_size(), r.panel
    assert len(r._studio_marks) >= 3                      # the REC mark, two status lines
    assert panel.collidelist(r._studio_marks) == -1, (panel, r._studio_marks)
    assert w <= W // 2                                     # was 1245 px wide


def test_overlay_names_each_part_failing_at_run_time():
    """A raising engine showed only as a growing "errors N" (seen in an Xvfb snapshot with the
    fault engine): the overlay names the part and its count."""
    st = LoopStats()
    st.errors["engine broken"] += 242
    st.errors["sink tuio"] += 1
    lines = overlay_lines(Frame(seq=5, t=1.0), st)
    assert "errors 243" in lines[1]
    assert lines[2:4] == ["engine broken failed 242 times (see the log)",
                          "sink tuio failed once (see the log)"], lines


def test_the_stage_figures_stand_in_columns_on_the_panel():
    """Padded with spaces in the proportional font, each stage line's "ms p99" ended where its
    label and digits happened to (up to 30 px apart, seen in an Xvfb snapshot): the panel lines
    every row's figures up, whatever the label's length or the number's digits."""
    from tabletop.drawing import screens
    st = LoopStats()
    for stage, s in (("capture_age", 0.004), ("engine:playful_friend", 0.00006),
                     ("engine:lover", 0.0148), ("sink:view", 0.1234), ("tick", 0.0011)):
        for _ in range(10):
            st.record(stage, s)
    lines = overlay_lines(Frame(seq=5, t=1.0), st)
    img = pygame.surfarray.array3d(screens.panel(lines, keep=False)).astype(int).sum(axis=2)
    ends, y = [], 10            # each row's rightmost text pixel (x), rows as the panel stacks
    for line in lines:
        h = screens.panel_line(screens.cells(line)[0], keep=False).get_height()
        lit = np.nonzero(img[:, y:y + h].max(axis=1) > 300)[0]
        if "ms p99" in line:
            ends.append(int(lit.max()))
        y += h + 2
    assert len(ends) == 5 and max(ends) - min(ends) <= 1, ends


def test_the_stage_table_fits_a_very_small_window_every_figure_shown():
    """A 320x200 window's panel may be 304 px wide, the stage table is ~370 px: its rows ran past
    the window's right edge, the p99 column cut off. Each row then takes two lines (the label,
    then its figures right-aligned in their columns) and every lit pixel of the panel is seen."""
    from tabletop.renderer import Renderer
    st = LoopStats()
    for stage, s in (("capture_age", 0.004), ("engine:playful_friend", 0.00006),
                     ("engine:lover", 0.0148), ("sink:view", 0.1234)):
        for _ in range(10):
            st.record(stage, s)
    lines = overlay_lines(Frame(seq=5, t=1.0), st)
    W, H = 320, 200
    renderer = Renderer((1.2, 0.8), (W, H), margin=24)
    wide = pygame.Surface((1600, 1000))
    target = pygame.Surface((W, H))
    rect = renderer.draw_overlay(target, lines, avoid=[], must=[])
    panel_img = rgb(renderer._overlay_img).sum(axis=2)
    assert rect.width <= W - 16, rect           # measured: 304 px (413 unwrapped)
    wide.blit(renderer._overlay_img, (0, 0))
    seen = rgb(target)[rect.top:rect.bottom, rect.left:rect.right].sum(axis=2)
    lit_panel = int((rgb(wide)[:rect.height, :].sum(axis=2) > 300).sum())
    assert lit_panel > 2000 and int((seen > 300).sum()) == lit_panel   # unwrapped: 4088 of 5328
    lit_cols = np.nonzero((panel_img > 300).any(axis=0))[0]
    assert lit_cols.max() >= rect.width - 10 - 2           # figures right-aligned at the padding


def overlay_of_the_shipped_config() -> list[str]:
    """13 lines: tick, fps, 9 stage rows, a source's health, a character's status."""
    st = LoopStats()
    for stage in ("capture_age", "inputs", "engines", "sinks", "tick", "engine:lover",
                  "sink:view", "source", "queued"):
        for k in range(20):
            st.record(stage, 0.001 * (k % 5 + 1))
    frame = Frame(seq=280, t=4.7, health=(SourceHealth("camera", True, "synthetic camera "
                                                       "1280x720 open", 0.006),),
                  characters=(CharacterState("lover", 0.3, 0.3, 0.0,
                                             label="playing lover, coherence 49%"),))
    return overlay_lines(frame, st)


@pytest.mark.parametrize("size, shrinks, cut", [((400, 225), True, False),
                                                ((320, 120), True, True),
                                                ((1280, 720), False, False)])
def test_an_overlay_taller_than_the_window_fits_it_first_lines_kept(size, shrinks, cut):
    """In a 400x225 window the overlay panel (256 px tall) ran off the window's top, its
    first lines, tick, fps and errors, unseen: its font gets smaller until it fits, and in a
    window too small even for that the last lines give way to one saying how many."""
    from tabletop.renderer import Renderer
    lines = overlay_of_the_shipped_config()
    W, H = size
    renderer = Renderer((1.2, 0.8), size, margin=24)
    target = pygame.Surface(size)
    rect = renderer.draw_overlay(target, lines, avoid=[], must=[])
    img = renderer._overlay_img
    assert img.get_height() <= H - 16 and rect.top >= 8 and rect.bottom <= H - 8, rect
    assert (renderer._overlay_px < 20) == shrinks
    # the panel's lit pixels are all in the window, its first line at its top
    wide = pygame.Surface((2000, 2000))
    wide.blit(img, (0, 0))
    lit_panel = int((rgb(wide).sum(axis=2) > 300).sum())
    seen = rgb(target)[rect.top:rect.bottom, rect.left:rect.right].sum(axis=2)
    assert lit_panel > 1000 and int((seen > 300).sum()) == lit_panel
    lit_rows = np.flatnonzero((rgb(img).sum(axis=2) > 300).any(axis=1))
    assert lit_rows[0] < 16                            # a line ("tick ...") at the panel's top
    from tabletop.drawing import screens
    whole = screens.panel(lines, renderer._overlay_px, width=max(W // 2, min(W - 16, 480)))
    assert (whole.get_height() > img.get_height()) == cut   # lines left out only when cut


@pytest.mark.parametrize("lines_n", [4, 12])
def test_in_a_small_window_the_panel_never_lies_over_the_try_words(lines_n):
    """800x450, the overlay on, the TRY words moved to the far right corner (a character at the
    far left): every window corner of the panel lay over the studio's words (the TRY words at
    the top, the status line at the bottom), and it covered part of the TRY words. It stands
    in the rows they leave free: the TRY words' pixels are those drawn without the panel."""
    from tabletop.renderer import Renderer
    size = (800, 450)
    label = "[pet] trained 317 samples (6.2 s); try it: K keep, X discard, R redo"
    studio = CharacterState("studio", 0.0, 0.0, 0.0, kind="studio", size=0.0, action="trying",
                            label=label)
    bird = CharacterState("bird", 0.12, 0.72, 0.0, size=0.1, color=(120, 180, 255))
    lines = [f"overlay line {i}: fps 60.0, sources ok, capture to render 1.9 ms median"
             for i in range(lines_n)]
    seen = []
    for overlay in (None, lines):
        r, s = Renderer(TABLE, size, margin=24), pygame.Surface(size)
        for k in range(40):
            r.draw(s, Frame(seq=k, t=k / 20, characters=(bird, studio)), overlay)
        seen.append((rgb(s).astype(int), r))
    (bare, _), (shown, r) = seen
    mark = r._studio_marks[0]
    assert mark.centerx > 400                                # the TRY words moved right
    assert r.panel.collidelist(r._studio_marks) == -1, (r.panel, r._studio_marks)
    cut = (slice(mark.top, mark.bottom), slice(mark.left, mark.right))
    assert (shown[cut] == bare[cut]).all()
    assert r.panel.height > 100                              # and still says a few lines
    # the studio falls silent (no words to keep clear of): the panel goes back to the window
    # corner on its side, the frame drawn
    quiet = dataclasses.replace(studio, label="")
    r.draw(pygame.Surface(size), Frame(seq=40, t=2.0, characters=(bird, quiet)), lines)
    assert r.panel.topleft in ((8, 8), (size[0] - r.panel.w - 8, 8),
                               (8, size[1] - r.panel.h - 8),
                               (size[0] - r.panel.w - 8, size[1] - r.panel.h - 8)), r.panel

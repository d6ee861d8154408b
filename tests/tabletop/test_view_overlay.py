"""The operator overlay's refresh: spread over frames, yet it shows the new figures and notices;
its stage figures (numpy's median and p99, one sort); the halo rings' cache forgets its oldest ring."""

import time

import pygame

import tabletop.view as view_module

from tabletop.config import validate_config
from tabletop.frames import Frame
from tabletop.loop import LoopStats
from tabletop.view import OVERLAY_REFRESH_S, ProjectorView, overlay_lines, overlay_steps


def stats_with_stages(n_stages: int) -> LoopStats:
    stats = LoopStats()
    for i in range(n_stages):
        for k in range(200):
            stats.record(f"stage{i}", 0.001 * (k % 7 + i))
    return stats


def test_overlay_steps_yield_per_stage_and_end_with_the_same_lines_as_overlay_lines():
    stats = stats_with_stages(6)
    frame = Frame(seq=12, t=3.0)
    steps = list(overlay_steps(frame, stats))
    assert all(s is None for s in steps[:-1]) and len(steps) - 1 == len(stats.samples)
    assert steps[-1] == overlay_lines(frame, stats)
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

"""Snapshots: on the wall clock (also while a camera is down), numbered on from earlier runs or
in a folder per run, bounded in count and size, with the health of that moment, with a window."""

import os
import shutil
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pygame
import pytest

from tabletop.config import validate_config
from tabletop.frames import Frame, Observation, SourceHealth
from tabletop.loop import LatestMeasurements, LiveInputs, Loop, LoopStats
from tabletop.snapshots import Snapshots, next_number, prune, save_png
from tabletop.view import ProjectorView, overlay_lines

ROOT = Path(__file__).resolve().parents[2]


class Clock:
    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def surface() -> pygame.Surface:
    s = pygame.Surface((64, 48))
    s.fill((200, 30, 30))
    return s


def take(snaps: Snapshots, clock: Clock, seconds: float, step: float = 0.05) -> list[Path]:
    paths = []
    end = clock.now + seconds
    while clock.now < end:
        clock.now += step
        if snaps.due():
            paths.append(snaps.save(surface()))
            snaps.close()  # wait for the writer thread
    return paths


def test_due_on_the_clock_and_numbering_continues_across_runs(tmp_path):
    clock = Clock()
    first = Snapshots(tmp_path, every_s=1.0, clock=clock)
    paths = take(first, clock, 4.0)
    assert [p.name for p in paths] == [f"snapshot-0000{i}.png" for i in range(4)]
    assert all(pygame.image.load(str(p)).get_size() == (64, 48) for p in paths)
    (tmp_path / "snapshot-00009.png").write_bytes(paths[0].read_bytes())  # an older, higher one
    second = Snapshots(tmp_path, every_s=1.0, clock=clock)
    again = take(second, clock, 2.0)
    assert [p.name for p in again] == ["snapshot-00010.png", "snapshot-00011.png"]
    assert next_number(tmp_path) == 12


def test_two_runs_sharing_a_folder_never_write_the_same_snapshot(tmp_path):
    """Two runs numbering on from the same folder's highest snapshot took the same numbers, and
    each overwrote the other's: each number is claimed by making its file, so they take turns."""
    clock = Clock()
    runs = [Snapshots(tmp_path, every_s=1.0, clock=clock) for _ in range(2)]
    colours = {}
    for k in range(6):
        clock.now += 1.0
        snaps = runs[k % 2]
        assert snaps.due()
        s = surface()
        s.fill((k * 40, 0, 0))
        path = snaps.save(s)
        snaps.close()
        assert path not in colours, path
        colours[path] = k * 40
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(p.name for p in colours)
    for path, red in colours.items():      # every run's snapshot as it took it
        assert pygame.image.load(str(path)).get_at((1, 1))[0] == red, path
    assert len(colours) == 6 and next_number(tmp_path) == 6


def test_a_snapshot_that_could_not_be_written_leaves_no_empty_file(tmp_path, caplog):
    """Its number claimed (its file made empty), the encoder refuses the image (0 x 0 pixels):
    no empty snapshot-NNNNN.png is left for a technician to open."""
    clock = Clock()
    snaps = Snapshots(tmp_path, every_s=1.0, clock=clock)
    clock.now += 1.0
    assert snaps.due()
    path = snaps.save(pygame.Surface((0, 0)))
    snaps.close()
    assert snaps.failing and path.name == "snapshot-00000.png"
    assert not list(tmp_path.iterdir())


def test_a_snapshot_is_written_whole_or_not_at_all(tmp_path):
    s = surface()
    s.set_at((3, 4), (10, 220, 90))
    assert save_png(s, tmp_path / "snapshot-00001.png") == ""
    back = pygame.image.load(str(tmp_path / "snapshot-00001.png"))
    assert back.get_size() == (64, 48) and back.get_at((3, 4))[:3] == (10, 220, 90)
    assert [p.name for p in tmp_path.iterdir()] == ["snapshot-00001.png"]  # no temporary left
    error = save_png(s, Path("/proc/no-such-folder/snapshot-00002.png"))
    assert error and "no-such-folder" in error


def test_per_run_folders(tmp_path):
    clock = Clock()
    for _ in range(2):  # two runs in the same second
        snaps = Snapshots(tmp_path, every_s=0.5, per_run=True, clock=clock)
        assert [p.name for p in take(snaps, clock, 1.0)] == ["snapshot-00000.png",
                                                              "snapshot-00001.png"]
    folders = sorted(p for p in tmp_path.iterdir())
    assert len(folders) == 2 and all(f.name.startswith("run-") for f in folders)


def test_retention_by_count_and_by_size(tmp_path):
    clock = Clock()
    snaps = Snapshots(tmp_path, every_s=0.2, keep=5, clock=clock)
    take(snaps, clock, 3.0)
    left = sorted(p.name for p in tmp_path.iterdir())
    assert len(left) == 5 and left[-1] == f"snapshot-{snaps.number - 1:05d}.png"
    size = (tmp_path / left[0]).stat().st_size
    removed = prune(tmp_path, keep=100, max_bytes=2.5 * size)
    assert len(removed) == 3 and len(list(tmp_path.iterdir())) == 2


def test_retention_by_number_not_by_the_clock(tmp_path):
    """Snapshots taken while the clock was a day ahead, then the clock set back: each new
    snapshot has the oldest modification time, and the numbers, not the clock, decide what a
    full folder removes (by the clock the new one would go at once and the stale ones stay);
    in per-run folders the current run's snapshots are the newest."""
    clock = Clock()
    snaps = Snapshots(tmp_path, every_s=0.2, keep=3, clock=clock)
    take(snaps, clock, 0.6)
    day = time.time() + 86400
    for p in tmp_path.iterdir():
        os.utime(p, (day, day))
    take(snaps, clock, 0.4)
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        f"snapshot-{n:05d}.png" for n in range(snaps.number - 3, snaps.number)]
    runs = tmp_path / "runs"
    first = Snapshots(runs, every_s=0.2, keep=3, per_run=True, clock=clock)
    take(first, clock, 0.6)
    for p in first.folder.iterdir():
        os.utime(p, (day, day))
    os.rename(first.folder, runs / "run-29991231-235959")   # a name of the clock ahead, too
    second = Snapshots(runs, every_s=0.2, keep=3, per_run=True, clock=clock)
    made = take(second, clock, 0.6)
    assert sorted(second.folder.iterdir()) == sorted(made) and len(made) == 3


class StalledCamera:
    """A source whose newest observation stays the one of its first moment (a camera that
    delivered a frame, then stalled): every frame's time stands still."""

    name = "camera"

    def __init__(self) -> None:
        self.obs = Observation("camera", time.monotonic(), 1)

    def open(self) -> None:
        pass

    def latest(self) -> Observation:
        return self.obs

    def health(self) -> SourceHealth:
        age = time.monotonic() - self.obs.t
        return SourceHealth(self.name, age < 0.5, f"no frame for {age:.1f} s", age)

    def close(self) -> None:
        pass


def _written_at_once(view: ProjectorView) -> None:
    """Each snapshot written before the loop goes on: none skipped because the one before was
    still being written (the saver thread, slow on a loaded machine)."""
    save = view.snapshots.save

    def save_and_wait(surface):
        path = save(surface)
        view.snapshots._saver.join()
        return path

    view.snapshots.save = save_and_wait


def _snapshotting_loop(tmp_path, every_s: float) -> Loop:
    """A headless 320x200 view snapshotting every ``every_s`` s into tmp_path/snaps, fed by a
    stalled camera."""
    cfg = validate_config({"sources": [{"kind": "scripted"}],
                           "view": {"headless": True, "size": [320, 200],
                                    "snapshot_every_s": every_s, "snapshot_folder": "snaps"}},
                          "test", tmp_path)
    stats = LoopStats()
    view = ProjectorView((1.2, 0.8), cfg["view"], stats=stats, headless=True)
    _written_at_once(view)
    return Loop(LiveInputs([StalledCamera()], LatestMeasurements()), [], [view], stats=stats)


def test_headless_snapshots_go_on_while_the_camera_is_down(tmp_path):
    loop = _snapshotting_loop(tmp_path, 0.3)
    loop.run(seconds=1.6)
    snaps = sorted((tmp_path / "snaps").glob("snapshot-*.png"))
    # the first after 0.3 s, then every 0.3 s: 5 in 1.6 s (the last may still be being written)
    assert 4 <= len(snaps) <= 5, snaps
    # The last one shows the health of its moment (the overlay drawn in the top-left corner).
    first, last = (pygame.image.load(str(p)) for p in (snaps[0], snaps[-1]))
    corner = (0, 0, 300, 60)
    assert pygame.image.tobytes(first.subsurface(corner), "RGB") != \
        pygame.image.tobytes(last.subsurface(corner), "RGB")


class SilentDevice:
    """A camera that opens but has not delivered a frame yet (read blocks until released)."""

    paced_fps = None

    def __init__(self) -> None:
        self.released = threading.Event()

    def read(self):
        self.released.wait(5.0)
        return None

    def release(self) -> None:
        self.released.set()


def test_a_camera_without_a_frame_yet_is_down_but_not_inf_seconds_late():
    from tracking.camera import CameraSettings, CameraSource
    device = SilentDevice()
    source = CameraSource("overhead", CameraSettings(device=0, stall_s=0.2),
                          opener=lambda settings: device)
    source.open()
    try:
        time.sleep(0.5)
        health = source.health()
    finally:
        device.release()
        source.close()
    assert not health.ok and health.message == "no frame yet"
    line = overlay_lines(Frame(seq=0, t=0.0, health=(health,)), None)[-1]
    assert "DOWN" in line and "inf" not in line


def _installation_under(wrapper: subprocess.Popen) -> int:
    """The pid of the ``tabletop`` process that ``xvfb-run`` (``wrapper``) started."""
    kids = Path(f"/proc/{wrapper.pid}/task/{wrapper.pid}/children").read_text().split()
    for pid in kids:
        if b"tabletop" in Path(f"/proc/{pid}/cmdline").read_bytes():
            return int(pid)
    raise LookupError(f"no tabletop process under xvfb-run (children {kids})")


@pytest.mark.skipif(shutil.which("xvfb-run") is None, reason="needs xvfb-run (a virtual X display)")
def test_snapshots_with_a_window(tmp_path):
    """A run with a real window snapshots on and on: it runs until 4 snapshots are there (a
    loaded machine takes longer, the 120 s cap only ends a hung run), then SIGTERM ends it."""
    cfg = tmp_path / "window.yaml"
    cfg.write_text("sources: [{kind: scripted}]\n"
                   "view: {size: [320, 200], snapshot_every_s: 0.25, snapshot_folder: snaps}\n")
    env = {k: v for k, v in os.environ.items() if k != "SDL_VIDEODRIVER"}
    p = subprocess.Popen(["xvfb-run", "-a", sys.executable, "-m", "tabletop", "run", "--config",
                          str(cfg)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env=env, cwd=ROOT)
    try:
        deadline = time.monotonic() + 120
        while p.poll() is None and time.monotonic() < deadline and \
                len(list((tmp_path / "snaps").glob("snapshot-*.png"))) < 4:
            time.sleep(0.05)
        if p.poll() is None:
            os.kill(_installation_under(p), signal.SIGTERM)
        _, err = p.communicate(timeout=60)
    finally:
        if p.poll() is None:
            p.kill()
            p.communicate()
    assert p.returncode == 0, err
    assert "SIGTERM received" in err and "Traceback" not in err, err
    assert "headless" not in err  # a real window
    snaps = sorted((tmp_path / "snaps").glob("snapshot-*.png"))
    assert len(snaps) >= 4
    img = pygame.image.load(str(snaps[-1]))   # written whole: the run waited for its writer
    assert img.get_size() == (320, 200)


def test_a_folder_that_cannot_be_written_is_said_once(tmp_path, caplog):
    import logging
    clock = Clock()
    snaps = Snapshots(tmp_path / "snaps", every_s=0.2, clock=clock)
    (tmp_path / "snaps").rmdir()  # taken away while running: a file in its place
    (tmp_path / "snaps").write_text("a file where the snapshot folder should be")
    with caplog.at_level(logging.INFO, logger="tabletop"):
        take(snaps, clock, 1.5)
    warnings = [r for r in caplog.records if "not saved" in r.getMessage()]
    assert snaps.taken >= 6 and len(warnings) == 1 and snaps.failing
    assert not list(tmp_path.glob("**/*.png"))


def test_a_snapshots_health_panel_keeps_clear_of_the_characters_and_pucks(tmp_path):
    """With the overlay hidden (a visitor's view) a snapshot still shows the health of its
    moment: its panel is placed as the shown overlay would be, off the character and the puck
    in the top-left corner (it was always drawn top-left, over them)."""
    from tabletop.frames import CharacterState, Puck
    cfg = validate_config({"sources": [{"kind": "scripted"}],
                           "view": {"headless": True, "size": [1280, 720], "snapshot_every_s": 0.05,
                                    "snapshot_folder": "snaps"}}, "test", tmp_path)
    view = ProjectorView((1.2, 0.8), cfg["view"], stats=LoopStats(), headless=True)
    # due on a clock of the frames' own (1/16 s a frame, exact in binary): a snapshot every
    # 0.375 s, 5 in the 30 frames whatever the load (on the wall clock, 0.01 s slept a frame,
    # 6-26 were written, the test's own checks of each 0.1-0.2 CPU s)
    clock = Clock()
    view.snapshots = Snapshots(tmp_path / "snaps", every_s=0.375, clock=clock)
    _written_at_once(view)
    saved = []   # (the view as shown, the snapshot) at each snapshot
    save = view.snapshots.save

    def keep(surface):
        saved.append((pygame.surfarray.array3d(view.screen), pygame.surfarray.array3d(surface)))
        return save(surface)

    view.snapshots.save = keep
    lover = CharacterState("lover", 0.1, 0.75, 0.0, size=0.15, color=(240, 110, 150))
    puck = Puck(1, 0.25, 0.7, 0.0, state="seen")
    try:
        for k in range(30):
            clock.now += 0.0625
            view.consume(Frame(seq=k, t=k * 0.05, pucks=(puck,), characters=(lover,)))
    finally:
        view.close()
    assert len(saved) == 5 and len(list((tmp_path / "snaps").glob("snapshot-*.png"))) == len(saved)
    bare = pygame.surfarray.array3d(view.renderer._background(pygame.Surface((1280, 720))))
    top_left = np.zeros((1280, 720), bool)
    top_left[:640, :360] = True
    for shown, snapshot in saved:
        panel = (shown != snapshot).any(axis=2)           # (x, y): where the panel was drawn
        # characters, pucks, glows (int16: a channel's difference within +-255, a sum's 765)
        drawn = np.abs(shown.astype(np.int16) - bare).sum(axis=2, dtype=np.int16) > 30
        assert panel.sum() > 2000                          # there is one (text on it)
        assert not (panel & drawn).any()
    assert (drawn & top_left).sum() > 5000                # the panel's first corner is taken


def test_a_snapshots_health_panel_leaves_the_overlays_line_cache_alone(tmp_path):
    """A snapshot's panel (figures of that moment, once a minute in a kiosk) is not kept line
    by line: kept, the overlay's line cache grew by each snapshot's lines to its 257 renders
    and was cleared, again and again, for nothing seen twice."""
    from tabletop.drawing import screens
    loop = _snapshotting_loop(tmp_path, 0.2)
    screens._panel_lines.clear()
    loop.run(seconds=1.1)
    assert len(list((tmp_path / "snaps").glob("snapshot-*.png"))) >= 3
    assert not screens._panel_lines


def test_a_snapshot_folder_naming_a_file_says_so(tmp_path, capfd):
    """mkdir's own words were "cannot be used: File exists" for a file where the folder goes."""
    from tests.tabletop.test_validation import BASE, one_line, run_config
    (tmp_path / "snaps").write_text("notes\n")
    code, err = run_config(tmp_path, BASE.replace("view: {enabled: false}", "view: {"
                           "snapshot_every_s: 1, snapshot_folder: snaps}"), capfd)
    line = one_line(err)
    assert code == 2 and line.endswith(f"view.snapshot_folder: {tmp_path / 'snaps'}: cannot be "
                                       "used: a file, not a folder"), line
    assert (tmp_path / "snaps").read_text() == "notes\n"


def test_a_snapshots_panel_has_the_lines_the_shown_overlay_has(tmp_path):
    """A kiosk's overlay is hidden: its snapshots are how it is checked from afar. Their panel
    left out the notices (a refused config edit) that the shown overlay carries."""
    cfg = validate_config({"sources": [{"kind": "scripted"}],
                           "view": {"headless": True, "size": [640, 360], "snapshot_every_s": 0.05,
                                    "snapshot_folder": "snaps"}}, "test", tmp_path)
    view = ProjectorView((1.2, 0.8), cfg["view"], stats=LoopStats(), headless=True)
    view.notices.append(lambda: ["config refused: cfg.yaml: view.sise: unknown key"])
    drawn = []   # the lines of every panel drawn
    draw = view.renderer.draw_overlay

    def spy(surface, lines, *args, **kw):
        drawn.append(list(lines))
        return draw(surface, lines, *args, **kw)

    view.renderer.draw_overlay = spy
    try:
        for k in range(6):
            view.consume(Frame(seq=k, t=k * 0.05))
            time.sleep(0.06)
        assert drawn and not view.show_overlay
        assert all(lines[-1] == "config refused: cfg.yaml: view.sise: unknown key"
                   for lines in drawn)
        view.show_overlay = True                               # as the service key shows it
        view.consume(Frame(seq=6, t=0.3))
        assert drawn[-1][-1] == drawn[0][-1]
    finally:
        view.close()

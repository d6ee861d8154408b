"""A kiosk's installation run in a thread while a test watches it: its loop, a sink that keeps
what the last frame drew, and the replay of its recording compared with it."""

import contextlib
import io
import json
import subprocess
import threading
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Iterator

from tabletop.kiosk import last_good
from tabletop.kiosk.runner import Runner
from tests.tabletop.test_replay_exact import frames


class Latest:
    """A sink keeping the last frame's characters."""
    name = "latest"

    def __init__(self):
        self.characters = ()

    def consume(self, frame):
        self.characters = frame.characters

    def close(self):
        pass


def kiosk_built(cfg_path: Path, **runner: Any) -> tuple[Any, str | None]:
    """The installation a kiosk builds at its start from ``cfg_path`` (the last good config,
    headless; ``runner``: more of :class:`Runner`'s keywords), and the refusal of the config
    file read (None: it is the one started)."""
    cfg, refused = last_good.load(cfg_path, kiosk=True)
    built = Runner(cfg_path, cfg, headless=True, kiosk=True, **runner)
    return built._build(built.cfg), refused


class Ticked:
    """``inst``'s loop stepped on the simulated ``clock`` (1/30 s a tick) while a test watches
    it, its action reloader looking at every tick: :func:`running` without waiting for the
    table's seconds (a real-time drill waited 10-13 s for its gestures). Used as a context: the
    loop is closed after."""

    DT = 1 / 30

    def __init__(self, inst: Any, clock: Any) -> None:
        self.inst, self.clock = inst, clock
        from tabletop.kiosk.actions import ActionReloader
        (reloader,) = [f for f in inst.loop.filters if isinstance(f, ActionReloader)]
        reloader.every_s = 0.0  # (it looks once a second of the wall clock, left behind here)

    def __enter__(self) -> "Ticked":
        self.inst.loop.inputs.open()
        return self

    def __exit__(self, *exc: Any) -> None:
        self.inst.loop.close()

    def tick(self) -> None:
        """One tick of the loop, then the clock on by :attr:`DT`."""
        self.inst.loop.tick()
        self.clock.advance(self.DT)

    def until(self, done: Any, seconds: float) -> bool:
        """Tick until ``done()`` holds, looked at after every tick (True), or ``seconds`` of
        table time pass (False)."""
        for _ in range(int(round(seconds / self.DT))):
            self.tick()
            if done():
                return True
        return bool(done())


def ticked_with_edits(inst: Any, clock: Any, ticks: int, edits: dict[int, tuple[Path, str]]
                      ) -> None:
    """Tick ``inst``'s loop ``ticks`` times on the simulated ``clock`` (:class:`Ticked`),
    writing ``edits[k]`` (a file and its new text) after tick k; the loop is closed after."""
    with Ticked(inst, clock) as table:
        for k in range(ticks):
            table.tick()
            if k in edits:
                edits[k][0].write_text(edits[k][1])


@contextmanager
def running(inst: Any, seconds: float, run_out: bool = False,
            ticks: int | None = None) -> Iterator[None]:
    """``inst``'s loop run for at most ``seconds`` (and ``ticks`` ticks) in a thread while the
    block runs; after the block the loop is stopped (``run_out``: left to run out, so its
    recording holds all of them) and the thread joined (30 s at most, ``seconds`` when run
    out). A run that must hold some frames counts ticks: a loaded machine skips the slots of
    late ticks (a 2 s kiosk run at 30 Hz made 19 frames at load 14-16 on 2 cores), and
    ``seconds`` then only ends a loop that hangs."""
    th = threading.Thread(target=inst.loop.run, kwargs={"seconds": seconds, "max_ticks": ticks})
    th.start()
    try:
        yield
    finally:
        if run_out:
            th.join(max(30.0, seconds))
        inst.loop.stop.set()
        th.join(30)


def replay_cli(session: Path, out: Path) -> subprocess.CompletedProcess:
    """``tabletop replay SESSION --fast --no-view --out OUT`` from ``session``'s folder, as
    tests.tabletop.test_replay_exact.replay_cli runs it, here in the test's process: its exit
    status and stderr (the log lines go to pytest's log capture). A replay process spent
    1.2-1.4 of its 0.8-2.0 CPU s on its interpreter's start, imports and kernel loads
    (tests/kiosk: 16 replays); the replay in a fresh process is test_replay_exact's."""
    from tabletop.cli import main
    args = ["replay", str(session), "--fast", "--no-view", "--out", str(out)]
    err = io.StringIO()
    with contextlib.chdir(session.parent), contextlib.redirect_stderr(err):
        code = main(args)
    return subprocess.CompletedProcess(["tabletop", *args], code, "", err.getvalue())


def replays_alike(session: Path, out: Path, least: int = 30,
                  aside: tuple[str, ...] = ("label",)) -> list[dict]:
    """The frames of ``session`` (more than ``least``), which ``tabletop replay`` (into ``out``)
    made again with the same characters, their ``aside`` keys apart (a label naming a bad file
    names it where each run read it)."""
    done = replay_cli(session, out)
    assert done.returncode == 0, done.stderr
    live, again = frames(session), frames(out)
    assert len(live) == len(again) > least

    def drawn(f: dict) -> list[dict]:
        return [{k: v for k, v in c.items() if k not in aside} for c in f["characters"]]
    assert [drawn(f) for f in live] == [drawn(f) for f in again]
    return live


def started_without(session: Path) -> set[str]:
    """The characters (or engines) ``session``'s header says the run started without: those
    whose behaviour or action files were refused at its start."""
    return set(json.loads(session.read_text().splitlines()[0])["started_without"])


def replays_without(session: Path, out: Path, names: set[str], **alike: Any) -> list[dict]:
    """:func:`replays_alike` (``alike``: its keywords) of a ``session`` that started without
    ``names`` (:func:`started_without`): the replay starts without them too."""
    assert started_without(session) == names
    return replays_alike(session, out, **alike)

"""The recorder sink: session recordings a kiosk can rely on (format: :mod:`tabletop.session`).

- Self-contained: the header carries the config as written and every file it refers to
  (:func:`session_header`), so a recording replays on another machine.
- Never overwrites and never collides: a folder gets ``session-DATE-TIME-MICROSECONDS.jsonl``
  and an exact ``path`` that exists already continues as ``NAME-2.jsonl``, ``NAME-3.jsonl``...;
  files are created exclusively, so two runs starting at once get two names.
- Bounded: a file reaching ``max_mb`` continues in a new file (the next part, its own header,
  times still counted from the session's start); ``keep`` removes the oldest recordings of the
  same naming in that folder.
- A write that fails (a full disk) stops recording with one clear log line; the installation
  keeps running and :attr:`Recorder.failed` says why (``tabletop run`` then exits non-zero).

Every line is handed to the operating system as it is written (a killed process loses at most
the line being written); a background thread syncs the file to disk every ``flush_every_s``
(a power cut loses at most that much) and each file is fsynced when it is closed.
"""

from __future__ import annotations

import datetime as _dt
import errno
import json
import logging
import os
import threading
from pathlib import Path
from typing import Any

from tabletop import __version__
from tabletop.frames import Frame
# The format lives in tabletop.session; its names are re-exported for callers of this module.
from tabletop.session import (FORMAT, VERSION, SessionError, frame_from_dict,  # noqa: F401
                              frame_to_dict, jsonable, read_frames, read_header)

log = logging.getLogger("tabletop")

MB = 2**20
DISK_FULL = (errno.ENOSPC, errno.EDQUOT, errno.EFBIG)


def session_header(config: Any, calibration: dict[str, Any] | None = None,
                   **extra: Any) -> dict[str, Any]:
    """The header of a recording of an installation built from ``config``: a validated
    :class:`tabletop.config.Config` is carried as written with its files embedded; any other
    mapping is written as it is."""
    from tabletop.bundle import portable
    raw, refs = getattr(config, "raw", None), getattr(config, "refs", None)
    if raw is not None and refs is not None:
        written, files, external = portable(raw, refs)
    else:
        written, files, external = config or {}, {}, []
    header = {"format": FORMAT, "version": VERSION, "tabletop": __version__,
              "config_file": getattr(config, "file", None), "config": jsonable(written),
              "files": files, "calibration": jsonable(calibration)}
    if external:
        header["external"] = external
    header.update(extra)
    return header


def _stamp() -> str:
    return _dt.datetime.now().strftime("%Y%m%d-%H%M%S-%f")


class Recorder:
    """Sink writing every frame to session files (JSON Lines); see the module docstring.

    Exactly one of ``path`` (a file name) or ``folder`` is given. ``header``: from
    :func:`session_header` (built once, written at the top of every part).
    """

    name = "recorder"

    def __init__(self, path: str | Path | None = None, header: dict[str, Any] | None = None,
                 folder: str | Path | None = None, max_mb: float | None = None,
                 keep: int | None = None, flush_every_s: float = 0.5, config: Any = None,
                 calibration: dict[str, Any] | None = None) -> None:
        if (path is None) == (folder is None):
            raise ValueError("give exactly one of path or folder")
        if header is None:
            header = session_header(config, calibration)
        self._header = dict(header)
        if path is not None:
            p = Path(path)
            if p.is_dir():
                raise SessionError(f"{p}: is a folder; expected a file name for the recording")
            self.folder, self.stem, self.suffix = p.parent, p.stem, p.suffix
        else:
            self.folder, self.stem, self.suffix = Path(folder), None, ".jsonl"
        self.max_bytes = None if max_mb is None else max(1, int(max_mb * MB))
        self.keep, self.flush_every_s = keep, flush_every_s
        self.paths: list[Path] = []      # every file of this session, in order
        self.frames = 0
        self.failed: str | None = None   # why recording stopped early, if it did
        self._f: Any = None
        self._size = 0
        self._t0: float | None = None
        self._first_in_file = True
        self._dirty = threading.Event()
        self._closing = threading.Event()
        try:
            self._open_part()
        except OSError as exc:
            if exc.errno not in DISK_FULL:
                raise SessionError(f"{self.folder}: cannot start a recording there: "
                                   f"{exc.strerror or exc}") from None
            self._fail(exc)  # a full disk: the installation runs, without recording
        self._syncer = threading.Thread(target=self._sync, name="recorder-sync", daemon=True)
        self._syncer.start()

    def _sync(self) -> None:
        """Sync written lines to disk at most every ``flush_every_s``, off the frame loop."""
        while not self._closing.is_set():
            if self._dirty.wait(0.5) and not self._closing.is_set():
                self._dirty.clear()
                try:
                    f = self._f
                    if f is not None and not f.closed:
                        os.fdatasync(f.fileno())
                except (OSError, ValueError) as exc:   # ValueError: closed meanwhile
                    log.debug("recording %s: sync skipped: %s", self.paths[-1], exc)
                self._closing.wait(self.flush_every_s)

    @property
    def path(self) -> Path:
        """The file being written (the last one when finished)."""
        return self.paths[-1]

    # -- files --------------------------------------------------------------------------------

    def _candidates(self):
        if self.stem is None:
            base = f"session-{_stamp()}"
            yield self.folder / f"{base}{self.suffix}"
        else:
            base = self.stem
            yield self.folder / f"{base}{self.suffix}"
        for n in range(2, 1_000_000):
            yield self.folder / f"{base}-{n}{self.suffix}"

    def _open_part(self) -> None:
        self.folder.mkdir(parents=True, exist_ok=True)
        for candidate in self._candidates():
            try:
                f = open(candidate, "xb")
            except FileExistsError:
                continue
            break
        if self.paths:
            log.info("recording continues in %s (%s reached %g MB)", candidate, self.path.name,
                     self.max_bytes / MB)
        elif self.stem is not None and candidate.name != f"{self.stem}{self.suffix}":
            log.info("recording to %s (%s%s exists and is never overwritten)", candidate,
                     self.stem, self.suffix)
        self._f, self._size, self._first_in_file = f, 0, True
        self.paths.append(candidate)
        header = dict(self._header, part=len(self.paths),
                      created=_dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"))
        self._write((json.dumps(header, separators=(",", ":"), default=str) + "\n").encode())
        self._prune()

    def _mine(self, p: Path) -> bool:
        """Is ``p`` a recording of this recorder's naming (the ones ``keep`` counts)?"""
        if p.suffix != self.suffix or not p.is_file():
            return False
        if self.stem is None:
            return p.name.startswith("session-")
        rest = p.stem[len(self.stem):]
        return p.stem.startswith(self.stem) and (rest == "" or (rest[0] == "-" and rest[1:].isdigit()))

    def _prune(self) -> None:
        if self.keep is None:
            return
        try:
            mine = [p for p in self.folder.iterdir() if self._mine(p)]
            mine.sort(key=lambda p: (p.stat().st_mtime, p.name))
            current = self.path
            for old in mine[:max(0, len(mine) - self.keep)]:
                if old != current:
                    old.unlink()
                    log.info("removed old recording %s (recorder.keep: %d)", old, self.keep)
        except OSError as exc:
            log.warning("old recordings in %s not removed: %s", self.folder, exc.strerror or exc)

    def _write(self, data: bytes) -> None:
        self._f.write(data)
        self._size += len(data)

    def _fail(self, exc: OSError) -> None:
        where = self.paths[-1] if self.paths else self.folder
        self.failed = f"{where}: {exc.strerror or exc}"
        log.error("recording stopped after %d frames: %s; the installation keeps running",
                  self.frames, self.failed)
        try:
            if self._f is not None:
                self._f.close()
        except OSError:
            pass
        if self.paths and self._first_in_file:  # a file without a frame is of no use
            try:
                self.paths[-1].unlink()
            except OSError:
                pass

    # -- the sink -----------------------------------------------------------------------------

    def consume(self, frame: Frame) -> None:
        if self.failed is not None or self._f is None or self._f.closed:
            return
        d = frame_to_dict(frame, self._t0 if self._t0 is not None else frame.t)
        if self._t0 is None:
            self._t0 = frame.t
        if self._first_in_file:
            d["t0"] = self._t0
        if self._t0 + d["t"] != frame.t:
            d["t_mono"] = frame.t   # exactness: t0 + t would round differently
        line = (json.dumps(d, separators=(",", ":"), allow_nan=False) + "\n").encode()
        try:
            if self.max_bytes is not None and not self._first_in_file and \
                    self._size + len(line) > self.max_bytes:
                self._close_file()
                self._open_part()
                d["t0"] = self._t0
                line = (json.dumps(d, separators=(",", ":"), allow_nan=False) + "\n").encode()
            self._write(line)
            self._first_in_file = False
            self.frames += 1
            self._f.flush()
            self._dirty.set()
        except OSError as exc:
            self._fail(exc)

    def _close_file(self) -> None:
        self._f.flush()
        os.fsync(self._f.fileno())
        self._f.close()

    def discard(self) -> None:
        """Close and remove what was written (the installation did not start)."""
        self._stop_syncer()
        try:
            if self._f is not None:
                self._f.close()
        except OSError:
            pass
        for p in self.paths:
            try:
                p.unlink()
            except OSError:
                pass

    def _stop_syncer(self) -> None:
        self._closing.set()
        if getattr(self, "_syncer", None) is not None:
            self._syncer.join()

    def close(self) -> None:
        self._stop_syncer()
        if self.failed is not None or self._f is None or self._f.closed:
            return
        try:
            self._close_file()
        except OSError as exc:
            self._fail(exc)
            return
        log.info("recording %s: %d frames", self.path, self.frames)

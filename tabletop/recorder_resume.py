"""A recording that stops and goes on (:class:`~tabletop.recorder.Recorder`'s stops): a write
that fails (a full disk) stops it with one log line while the installation keeps running; every
:data:`RESUME_EVERY_S` of frame time a new part is tried, and once the disk takes its header the
recording goes on there. A disk that could not keep up is tried alike once its syncs caught up,
each stop waiting twice the last (up to :data:`SLOW_RESUME_MAX_S`); a part whose file was removed
from disk stops alike and goes on at once in a new part (looked at every
:data:`REMOVED_CHECK_S`). :attr:`Resuming.incomplete` says why a session's recording is not
whole.
"""

from __future__ import annotations

import logging
import os

from tabletop.file_io import close_quietly
from tabletop.recordings import keep_held, release

log = logging.getLogger("tabletop")

# Seconds of frame time between two tries to resume a recording a full disk stopped: without
# tries it stays stopped until the installation restarts (a gallery soak whose recordings
# folder filled and was cleared two minutes later recorded nothing for the remaining 20
# minutes; for weeks, on a kiosk left alone). A failed try costs one file created and removed.
RESUME_EVERY_S = 60.0
#: A disk that keeps falling behind again: each stop waits twice the last, up to this (seconds
#: of frame time); a part that then keeps up this long starts the count again.
SLOW_RESUME_MAX_S = 3600.0
#: Seconds of frame time between two looks at whether the part being written is still on disk
#: (one fstat): a part whose file or folder was removed (a technician clearing the disk) went
#: on taking every frame into a file no one could open again, lost for the rest of the run.
REMOVED_CHECK_S = 2.0


class Resuming:
    """Mixin of :class:`~tabletop.recorder.Recorder` (its files, sink and syncer): stopping,
    trying new parts and going on, and why the recording is not whole."""

    @property
    def incomplete(self) -> str | None:
        """Why this session's recording is not whole, one line, or None when it is: the
        reason it stopped (the last stop's, never blank), how many times it went on in a new
        part and which part the last is (``tabletop run``, ``replay --out`` and a kiosk's
        config edit say it)."""
        if self.failed is None and not self.gaps:
            return None
        why = self.failed or self.gaps[-1] or "a write failed"
        if not self.gaps:
            return why
        n = len(self.gaps)
        times = f"{n} time{'s' if n > 1 else ''}"
        if self.failed is not None:
            return f"{why} (it had stopped {times} before and gone on in a new part)"
        return (f"{why} (it stopped {times} and went on in a new part each time, the last "
                f"{self.path.name}: frames are missing between the parts)")

    def _fail(self, exc: OSError | str, resumable: bool = False,
              wait_s: float = RESUME_EVERY_S) -> None:
        """Stop recording because of ``exc``; ``resumable`` (also every write error: a full
        disk, a folder that stopped taking files, a disk remounted read-only after an error):
        new parts are tried from ``wait_s`` of frame time on. Every write error is tried
        again, as a folder that stops taking files may take them again (a drive mounted back,
        a permission restored) and a try costs one failed file creation a minute; a
        recording stopped for good would miss the rest of a weeks-long run."""
        where = self.paths[-1] if self.paths else self.folder
        why = exc if isinstance(exc, str) else (exc.strerror or str(exc))
        empty = bool(self.paths) and self._first_in_file   # removed below: say so, not a
        self.failed = f"{where}: {why}" + (" (it held no frame: removed)" if empty else "")
        resumable = resumable or isinstance(exc, OSError)
        self._resumable = resumable
        self._resume_at = None if self._last_t is None else self._last_t + wait_s
        log.error("recording stopped after %d frames: %s; the installation keeps running%s",
                  self.frames, self.failed, f" (a new part is tried in {wait_s:g} s, then every "
                  f"{RESUME_EVERY_S:g} s)" if resumable else "")
        if self._f is not None:
            if empty:
                release(self._f)
            elif self._stopped is None:   # the run resumes this session: another run's keep
                self._stopped = keep_held(self._f)   # leaves the stopped part (recordings)
            self._retired.append(self._f)   # the syncer syncs what it can and closes it
            self._f = None
        if empty:                        # a file without a frame is of no use
            try:
                self.paths[-1].unlink()
            except OSError:
                pass

    def _check_removed(self) -> None:
        """Stop the part (and so start a new one at once, its folder made again) when its file
        is no longer on disk: the frames since the last look are lost with it, no more."""
        try:
            gone = os.fstat(self._f.fileno()).st_nlink == 0
        except OSError:
            return
        if gone:
            with self._cv:
                self._first_in_file = False     # nothing to remove: it is gone already
                gone_too = "" if self.folder.exists() else ", with its folder"
                self._fail(f"removed from disk{gone_too}", resumable=True, wait_s=0.0)
                self._cv.notify()

    def _resume(self, t: float) -> bool:
        """After a full disk or a disk that could not keep up, at ``_resume_at`` or the first
        frame after it that finds the syncer caught up: a new part, if the disk takes its
        header, so that a disk that stalled past ``max_queue`` lines and whose syncs came back
        records the rest of a weeks-long run. A disk that falls behind again and again waits
        twice as long before each try (up to ``SLOW_RESUME_MAX_S``): each stop and resume is
        logged and starts a part, and with a fixed wait a disk slow for good stopped and
        resumed every 77 s at 60 Hz (1,024 lines, then 60 s)."""
        if not self._resumable or self._closing:
            return False
        if self._resume_at is None:      # stopped before the first frame
            self._resume_at = t + RESUME_EVERY_S
        if t < self._resume_at or not self.caught_up:
            return False
        with self._cv:
            n = len(self.paths)
            try:
                self._open_part(resumed=self.failed)
            except OSError:              # still full: nothing of the try is left
                if len(self.paths) > n:
                    part = self.paths.pop()
                    if self._f is not None:
                        close_quietly(self._f)
                        self._f = None
                    try:
                        part.unlink()
                    except OSError:
                        pass
                self._resume_at = t + RESUME_EVERY_S
                return False
            self.gaps.append(self.failed or "")
            self.failed, self._resumable, self._resume_at = None, False, None
            self._resumed_t = t
            self._cv.notify()
        return True

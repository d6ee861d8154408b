"""The kiosk's shared log (tabletop.kiosk.logfile) with real processes and files: a writer frozen
inside its write holds no other process's logging, the lock file is found again after the log
folder is recreated, a log whose lock cannot be taken still follows rotations, and a closed
handler never raises out of the logger."""

import logging
import shutil
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from tabletop.kiosk.logfile import SharedRotatingFileHandler
from tracking.scenes import wait_for

FROZEN_WRITER = """
import logging, os, signal, sys
from pathlib import Path
from tabletop.kiosk.logfile import SharedRotatingFileHandler
class Freeze(logging.Formatter):   # formatting runs inside emit, under the log's lock
    def format(self, record):
        os.kill(os.getpid(), signal.SIGSTOP)
        return super().format(record)
h = SharedRotatingFileHandler(Path(sys.argv[1]), 10_000, 2)
h.setFormatter(Freeze())
h.emit(logging.LogRecord("t", logging.INFO, "", 0, "frozen", None, None))
"""


def stopped(proc: subprocess.Popen) -> bool:
    """Whether the process is stopped (state T in /proc)."""
    stat = Path(f"/proc/{proc.pid}/stat").read_text()
    return stat[stat.rindex(")") + 2] == "T"


def record(msg: str) -> logging.LogRecord:
    return logging.LogRecord("t", logging.INFO, "", 0, msg, None, None)


@pytest.mark.parametrize("recreated", [False, True])
def test_a_writer_frozen_holding_the_lock_does_not_hold_anothers_logging(tmp_path, recreated):
    """An installation stopped (SIGSTOP) inside its write: the supervisor's line is written
    after the bounded wait, without the lock (its logging waited for ever, its stall restart
    too). With the log folder removed and recreated under the supervisor, it locks the same
    new lock file as the process started since (it locked the deleted folder)."""
    path = tmp_path / "logs" / "tabletop.log"
    path.parent.mkdir()
    sup = SharedRotatingFileHandler(path, 10_000, 2)
    sup.emit(record("supervisor first"))
    if recreated:
        shutil.rmtree(path.parent)
        path.parent.mkdir()
    child = subprocess.Popen([sys.executable, "-c", FROZEN_WRITER, str(path)])
    try:
        assert wait_for(lambda: stopped(child), 30.0)
        done = threading.Event()
        threading.Thread(target=lambda: (sup.emit(record("supervisor: restarting")),
                                         done.set()), daemon=True).start()
        assert done.wait(10.0)
        assert sup.unlocked == 1
        assert "supervisor: restarting" in path.read_text()
    finally:
        child.kill()
        child.wait()
        sup.close()
    sup = SharedRotatingFileHandler(path, 10_000, 2)   # the holder died: the lock is free
    sup.emit(record("supervisor last"))
    assert sup.unlocked == 0 and "supervisor last" in path.read_text()
    sup.close()


def test_a_log_whose_lock_cannot_be_taken_still_follows_rotations(tmp_path, capfd):
    """No lock (here a folder where the lock file goes; NFS without write-lockable files alike):
    each writer still reopens the log another rotated, so the supervisor's lines written while
    the kept installation lines were are all kept (none were where the fallback skipped that),
    and it is said once on stderr."""
    path = tmp_path / "tabletop.log"
    (tmp_path / ".tabletop.log.lock").mkdir()
    sup, inst = (SharedRotatingFileHandler(path, 10_000, 3) for _ in range(2))
    for i in range(1500):
        inst.emit(record(f"installation {i:05d} " + "x" * 40))
        if i % 25 == 0:
            sup.emit(record(f"SUPERVISOR {i:05d}"))
    sup.close()
    inst.close()
    text = "".join(f.read_text() for f in tmp_path.iterdir() if f.is_file())
    first = min(int(line.split()[1]) for line in text.splitlines()
                if line.startswith("installation"))
    due = [i for i in range(0, 1500, 25) if i >= first]
    assert len(due) >= 10 and all(f"SUPERVISOR {i:05d}" in text for i in due)
    err = capfd.readouterr().err
    assert err.count("cannot open") == 2 and str(tmp_path) in err   # once per handler


def test_logging_after_the_handler_is_closed_does_not_raise(tmp_path):
    """A daemon thread logging during teardown, after logging.shutdown closed the handler
    that is still attached: the record is written (ValueError raised out of logger.error)."""
    log = logging.getLogger("tabletop.test_logfile")
    log.propagate = False
    handler = SharedRotatingFileHandler(tmp_path / "tabletop.log", 10_000, 2)
    log.addHandler(handler)
    try:
        handler.close()
        log.error("after close")
    finally:
        log.removeHandler(handler)
        handler.close()
    assert "after close" in (tmp_path / "tabletop.log").read_text()


FULL_DISK_WRITER = """
import logging, resource, signal, sys
from pathlib import Path
from tabletop.kiosk.logfile import SharedRotatingFileHandler
log = logging.getLogger("tabletop")
log.setLevel(logging.INFO)
log.addHandler(SharedRotatingFileHandler(Path(sys.argv[1]), 10_000_000, 2))
signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
soft, hard = resource.getrlimit(resource.RLIMIT_FSIZE)
log.info("before the disk fills")
resource.setrlimit(resource.RLIMIT_FSIZE, (4096, hard))   # a full disk: writes fail (EFBIG)
for k in range(200):
    log.info("line %d of a long run", k)
resource.setrlimit(resource.RLIMIT_FSIZE, (soft, hard))   # space again
log.info("after the disk was freed")
"""


def test_a_log_that_cannot_be_written_is_said_once_and_its_return_once(tmp_path):
    """A kiosk log on a full disk: one line on stderr (not logging's traceback per record), one
    when it is written again, and the later lines reach the file."""
    path = tmp_path / "tabletop.log"
    done = subprocess.run([sys.executable, "-c", FULL_DISK_WRITER, str(path)],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 0
    lines = done.stderr.splitlines()
    assert "Logging error" not in done.stderr and "Traceback" not in done.stderr
    assert len(lines) == 2, done.stderr[:2000]
    assert lines[0].startswith(f"tabletop log: cannot write {path}: File too large")
    assert lines[1].startswith(f"tabletop log: {path} written again (")
    text = path.read_text()
    assert "before the disk fills" in text and "after the disk was freed" in text

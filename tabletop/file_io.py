"""Files read and written safely, the layer under :mod:`tabletop.files`' formats: bounded reads
(text capped at :data:`MAX_TEXT_BYTES`, regular files only where a frame loop reads) and atomic
writes.

Saved data is never lost: every write goes to a temporary file in the same folder, is fsynced,
then renamed over the target; a folder is made whole or not at all (:func:`new_folder`).
"""

from __future__ import annotations

from errno import EDQUOT, EFBIG, EIO, ENOENT, ENOSPC, EPIPE
import json
import os
import shutil
import stat
import tempfile
from pathlib import Path
from contextlib import contextmanager, suppress
from typing import IO, Any, Iterator, Mapping

from tabletop.errors import InputError


class FileFormatError(InputError):
    """A file is missing, empty or malformed; the message names the file and the line."""


MAX_TEXT_BYTES = 128 * 2**20   # a config, calibration or CSV input longer is refused: an hour's
# demonstration at 120 Hz is 30 MB; /dev/zero or /dev/full named as one (a calibrate --out
# whose previous file is read first) filled the machine's 23 GB and was killed


# The most bytes each kind of input holds, said before it is read whole and parsed: a wrong
# file is refused at once (YAML parses about 2 MB a second). Measured: a calibration 0.4 kB;
# behavior.yaml 0.5 kB; actions.yaml about 0.1 kB an action; a template 2 kB (an hour of
# t,dx,dy at 60 Hz written full precision: 13 MB); a demonstration at 60 Hz written full
# precision 4.7 MB for 10 minutes, 28 MB for an hour (the longest trained); a DeepMimic clip
# at most 0.2 MB; a designed touch-pose action 1.2 kB a pose (a minute at 60 Hz: 4.2 MB).
MAX_CALIBRATION_BYTES = 2**20
MAX_DESCRIPTION_BYTES = 2**20       # behavior.yaml, actions.yaml
MAX_TEMPLATE_BYTES = 16 * 2**20     # a template or gesture CSV
MAX_DEMONSTRATION_BYTES = 64 * 2**20   # an hour at 120 Hz
MAX_CLIP_BYTES = 32 * 2**20         # a clip, sprite sheet or designed action (JSON)


class UnreadableText(Exception):
    """A text input refused whole: over :data:`MAX_TEXT_BYTES` bytes, or not text in the
    encoding read (the message names the line of the first byte that is not)."""


def line_of(data: bytes, offset: int) -> int:
    """The line (from 1) holding byte ``offset`` of ``data``, lines ending as universal
    newlines end them: CR LF, LF, or CR alone (a file saved with classic Mac line ends)."""
    crlf = data.count(b"\r\n", 0, offset)
    return data.count(b"\n", 0, offset) + data.count(b"\r", 0, offset) - crlf + 1


def json_loads(text: str) -> Any:
    """``json.loads``, a document nested too deep for Python's recursion (``[[[[...``, a
    RecursionError, an internal error else) raised as the ``json.JSONDecodeError`` its readers
    already turn into one line naming the file."""
    try:
        return json.loads(text)
    except RecursionError:
        raise json.JSONDecodeError("nested too deep", text, 0) from None


def read_text(path: Path, encoding: str = "utf-8") -> str:
    """``path.read_text(encoding)`` (universal newlines), refusing (UnreadableText) what is
    longer than any input file of ours (an endless device or a wrong file is not read into
    memory whole) or is not text in ``encoding`` (UTF-8, with or without its mark), naming the
    line and byte where it stops being text. Read once, in binary: a named pipe or device
    gives its bytes once (a second open waits for ever on a pipe whose writer is gone)."""
    with open(path, "rb") as f:
        data = _read_capped(f)
    try:
        text = data.decode(encoding)
    except UnicodeDecodeError as exc:
        line = line_of(exc.object, exc.start)
        raise UnreadableText(f"line {line}: byte 0x{exc.object[exc.start]:02x} is not UTF-8 "
                             "text (a binary file, or text saved in another encoding?)") from None
    return text.replace("\r\n", "\n").replace("\r", "\n")


def read_text_within(path: Path, max_bytes: int, kind: str,
                     error: type[Exception] = UnreadableText, encoding: str = "utf-8") -> str:
    """:func:`read_text` of a ``kind`` of file that never holds over ``max_bytes``: one over it
    raises ``error`` naming the file and its size, before it is read (a regular file) or parsed
    (a pipe or a device: its text counted)."""
    size = path.stat().st_size if path.is_file() else 0
    if size <= max_bytes:
        text = read_text(path, encoding)
        size = len(text)
    if size > max_bytes:
        raise error(too_big(path, size, max_bytes, kind))
    return text


def too_big(p: Path, size: int, max_bytes: int, kind: str) -> str:
    """A file over what its kind holds, in one line naming it and its size."""
    return (f"{p}: {size:,} bytes, more than a {kind} holds (at most {max_bytes:,}); not read "
            "(another file given?)")


def _read_capped(f: IO[bytes]) -> bytes:
    """At most :data:`MAX_TEXT_BYTES` of ``f``, else UnreadableText."""
    data = f.read(MAX_TEXT_BYTES + 1)
    if len(data) > MAX_TEXT_BYTES:
        raise _too_long()
    return data


def _too_long() -> UnreadableText:
    return UnreadableText(f"over {MAX_TEXT_BYTES // 2**20} MB, more than any such file holds "
                          "(a device or another kind of file?)")


def read_regular_bytes(path: Path) -> bytes:
    """The bytes of the regular file ``path``, read once and capped as :func:`read_text` caps
    them. Anything else (a named pipe, a device, a folder) is refused (UnreadableText) without
    waiting: the file is opened non-blocking and checked on the open descriptor, so a named
    pipe put there after a look cannot hold a frame loop reading it (an open of a pipe waits
    for a writer). OSError for a file that cannot be opened."""
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    try:
        st = os.fstat(fd)
    except OSError:
        os.close(fd)
        raise
    if not stat.S_ISREG(st.st_mode) or st.st_size > MAX_TEXT_BYTES:   # (nothing read)
        os.close(fd)
        raise (UnreadableText("not a regular file (a folder, a named pipe or a device?)")
               if not stat.S_ISREG(st.st_mode) else _too_long())
    with open(fd, "rb") as f:
        return _read_capped(f)


def file_on_path(folder: Path) -> Path | None:
    """The file standing where ``folder`` or one of the folders above it would be, if any (no
    folder can then be made there, now or later)."""
    return next((p for p in (folder, *folder.parents) if p.exists() and not p.is_dir()), None)


def folder_failure(folder: Path, exc: OSError) -> str:
    """Why ``folder`` could not be made or a file made in it: "X is a file" when a file stands
    on its path (the system says only "File exists" or "Not a directory"); a folder that is
    there but takes no new file (``/proc``, ``/sys``: the system says "No such file or
    directory" of the folder it just listed) said to be one; else the system's reason."""
    blocker = file_on_path(folder)
    if blocker is not None:
        return f"{blocker} is a file"
    if exc.errno == ENOENT and folder.is_dir():
        return ("the folder exists but no file can be made in it (a system folder such as "
                f"/proc?; the system says: {exc.strerror or exc})")
    return str(exc.strerror or exc)


def is_stream(path: str | Path) -> bool:
    """Is ``path`` a device or pipe, or a name of one: ``/dev/stdout``, ``/proc/self/fd/1``, a
    link to either (also while they lead on to a regular file: a shell's ``> out.jsonl``)?
    Such a name is written through, never renamed over (that replaced the link or device with
    a file). ``/dev/shm`` holds ordinary files; a name not there yet is none."""
    p = Path(os.path.abspath(path))
    for _ in range(40):                       # a link loop ends here, as the system's does
        name = str(p)
        if name.startswith(("/dev/", "/proc/")) and not name.startswith("/dev/shm/") \
                and os.path.lexists(p):
            return True
        if not p.is_symlink():
            break
        p = Path(os.path.abspath(os.path.join(p.parent, os.readlink(p))))
    return p.exists() and not p.is_file()


@contextmanager
def atomic_writer(path: str | Path, binary: bool = False) -> Iterator[IO[Any]]:
    """A file to write ``path`` through atomically: the data go to a temporary file in the same
    folder, which replaces ``path`` (after fsync) only when the block ends without an error;
    on an error the temporary file is removed and ``path`` is untouched.

    A ``path`` that :func:`is_stream` (``/dev/stdout``, a pipe, ``/dev/null``) is written to as
    it is: renaming over it replaced the device or pipe (or the link to it) with a regular file,
    so ``--out /dev/stdout | next-step`` (or ``> file``) got nothing and, run as root,
    /dev/stdout itself became a file until the next boot."""
    target = Path(path)
    if target.is_dir():
        raise FileFormatError(f"{target}: is a folder; expected a file name to write")
    if is_stream(target):
        try:
            f = open(target, "wb" if binary else "w", encoding=None if binary else "utf-8")
        except OSError as exc:  # an OSError still, naming the target, as runtime writers expect
            raise OSError(exc.errno, exc.strerror or str(exc), str(target)) from None
        with _naming(target), f:
            yield f
        return
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise FileFormatError(f"{target}: cannot make its folder: "
                              f"{folder_failure(target.parent, exc)}") from None
    _remove_stale(target)
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.{os.getpid()}.", suffix=".tmp",
                                   dir=target.parent)
    except OSError as exc:  # still an OSError (callers catch it), naming the target
        raise OSError(exc.errno, folder_failure(target.parent, exc), str(target)) from None
    try:
        os.chmod(tmp, _new_file_mode(target))
        with _naming(target), \
                os.fdopen(fd, "wb" if binary else "w", encoding=None if binary else "utf-8") as f:
            yield f
            f.flush()
            os.fsync(f.fileno())
        try:
            os.replace(tmp, target)
        except OSError as exc:
            raise FileFormatError(f"{target}: cannot be written: {exc.strerror or exc}") from None
    except BaseException:
        with suppress(FileNotFoundError):
            os.unlink(tmp)
        raise
    fsync_folder(target.parent)


@contextmanager
def _naming(target: Path) -> Iterator[None]:
    """A write's OSError while ``target`` is written (a full disk: the write, flush or fsync
    says only "No space left on device") is raised again naming ``target``, its errno kept for
    the callers that tell a full disk from other errors; others (reading a source) are kept."""
    try:
        yield
    except OSError as exc:
        if exc.filename is not None or exc.errno not in (ENOSPC, EDQUOT, EFBIG, EIO, EPIPE):
            raise
        raise OSError(exc.errno, exc.strerror or str(exc), str(target)) from None


def _remove_stale(target: Path) -> None:
    """Remove the temporary files of ``target`` that a process which has ended left behind (a
    crash or a power cut between their making and their renaming). The kiosk's status file is
    written every second: a crash drill of 50 restarts left 3 of them, a crashing table weeks
    of them. A temporary file names its writer's process id; one still running keeps its own."""
    prefix = f".{target.name}."
    try:
        names = [n for n in os.listdir(target.parent)
                 if n.startswith(prefix) and n.endswith(".tmp")]
    except OSError:
        return
    for name in names:
        pid = name[len(prefix):].split(".", 1)[0]
        if not pid.isdigit() or int(pid) == os.getpid() or alive(int(pid)):
            continue
        with suppress(OSError):
            os.unlink(target.parent / name)


def alive(pid: int) -> bool:
    """Is process ``pid`` running (or not ours to ask about)?"""
    try:
        with suppress(PermissionError):   # another user's: running
            os.kill(pid, 0)
    except ProcessLookupError:
        return False
    return True


def _umask() -> int:
    """The process's file-creation mask, read without changing it where the system tells."""
    with suppress(OSError, ValueError, IndexError), \
            open("/proc/self/status", encoding="ascii") as f:
        for line in f:
            if line.startswith("Umask:"):
                return int(line.split()[1], 8)
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _new_file_mode(target: Path) -> int:
    """Permission bits for a file written over ``target``: the existing file's, else those a
    plain ``open`` would give (0o666 less the umask), never mkstemp's owner-only 0o600."""
    try:
        return target.stat().st_mode & 0o7777
    except OSError:
        return 0o666 & ~_umask()


def atomic_write_bytes(path: str | Path, data: bytes) -> None:
    """Write ``data`` to ``path`` atomically (temp file, fsync, rename, fsync the folder)."""
    with atomic_writer(path, binary=True) as f:
        f.write(data)


def close_quietly(f: Any) -> None:
    """Close ``f``, dropping what its buffer could not write (a full disk)."""
    try:
        f.close()
    except OSError:
        try:
            f.close()   # the buffer is dropped by the failed close; this closes the descriptor
        except OSError:
            pass


def fsync_folder(folder: Path) -> None:
    """Make a rename in ``folder`` durable (where the platform allows)."""
    with suppress(OSError):
        dir_fd = os.open(folder, os.O_RDONLY)
        try:
            os.fsync(dir_fd)
        finally:
            os.close(dir_fd)


def write_synced(path: Path, text: str) -> None:
    """Write UTF-8 ``text`` to a new file ``path`` and fsync it."""
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
        f.flush()
        os.fsync(f.fileno())


def new_folder(target: Path, files: Mapping[str, str], marker: str = "") -> None:
    """Make the folder ``target`` holding ``files`` (name -> text) whole or not at all: written
    and synced in a hidden temporary folder beside it (``.<name>.<marker>-<random>.tmp``, or
    ``.<name>.<process id>.<random>.tmp`` without a marker), then renamed (OSError on failure)."""
    mark = f"{marker}-" if marker else f"{os.getpid()}."
    tmp = Path(tempfile.mkdtemp(prefix=f".{target.name}.{mark}", suffix=".tmp",
                                dir=target.parent))
    try:
        for name, text in files.items():
            write_synced(tmp / name, text)
        fsync_folder(tmp)
        os.chmod(tmp, 0o755)
        os.rename(tmp, target)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    fsync_folder(target.parent)


def atomic_write_text(path: str | Path, text: str) -> None:
    """Write UTF-8 text to ``path`` atomically."""
    atomic_write_bytes(path, text.encode("utf-8"))


def tree_signature(path: Path) -> tuple:
    """(relative name, mtime ns, size) of a file, or of every file below a folder (hidden
    names skipped); changes whenever any of them is written, renamed or removed."""
    out = []
    try:
        if path.is_file():
            st = path.stat()
            return ((path.name, st.st_mtime_ns, st.st_size),)
        for root, dirs, files in os.walk(path):
            dirs[:] = sorted(d for d in dirs if not d.startswith("."))
            for f in sorted(files):
                if f.startswith("."):
                    continue
                p = Path(root) / f
                try:
                    st = p.stat()
                except OSError:
                    continue
                out.append((str(p.relative_to(path)), st.st_mtime_ns, st.st_size))
    except OSError:
        return ()
    return tuple(out)


def file_signature(path: Path) -> tuple:
    """:func:`tree_signature` and what ``path`` is (file, folder or nothing): a config file
    removed and then replaced by an empty folder changes it (the tree signature alone is
    ``()`` for both, and the kiosk would keep saying "config file not found" of a folder)."""
    kind = "file" if path.is_file() else "folder" if path.is_dir() else None
    return (kind, tree_signature(path))

"""Files read and written safely (tabletop/file_io.py): the atomic writer's permissions as a plain
write gives them, clear refusals; bounded reads of text, of pipes and devices, through the CSV
and YAML readers too."""

from __future__ import annotations

import os
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from tabletop.file_io import FileFormatError, atomic_write_text
from tabletop.files import read_csv_lines, read_yaml

ROOT = Path(__file__).resolve().parents[2]


def _mode(path: Path) -> int:
    return stat.S_IMODE(path.stat().st_mode)


def test_new_file_gets_the_umask_mode_not_owner_only(tmp_path):
    """A status file or a calibration written atomically must be readable by the others a
    plain write lets read it (a monitoring user, the operator's account), not mkstemp's 0o600."""
    old = os.umask(0o022)
    try:
        atomic_write_text(tmp_path / "status.json", "{}")
        plain = tmp_path / "plain.txt"
        plain.write_text("{}")
    finally:
        os.umask(old)
    assert _mode(tmp_path / "status.json") == _mode(plain) == 0o644


def test_rewrite_keeps_the_existing_files_mode(tmp_path):
    target = tmp_path / "calibration.yaml"
    target.write_text("a: 1\n")
    os.chmod(target, 0o640)
    atomic_write_text(target, "a: 2\n")
    assert target.read_text() == "a: 2\n"
    assert _mode(target) == 0o640


def test_unwritable_folder_names_the_target_not_a_temporary_file():
    target = Path("/proc/tabletop-out.csv")  # exists, cannot hold new files, even for root
    with pytest.raises(OSError) as err:  # an OSError still, as runtime writers expect
        atomic_write_text(target, "x")
    assert err.value.filename == str(target) and ".tmp" not in str(err.value)


def test_cli_output_into_an_unwritable_folder_is_one_line(tmp_path):
    main = tmp_path / "main.csv"
    main.write_text("t,main_x,main_y,main_dir\n" + "".join(
        f"{i / 40},{0.5 + 0.001 * i},0.4,0\n" for i in range(40)))
    demo = ROOT / "behaviors" / "library" / "lover" / "demonstration.csv"
    r = subprocess.run([sys.executable, "-m", "tabletop", "behave", "--train", str(demo),
                        "--input", str(main), "--out", "/proc/tabletop-react.csv"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(
        "tabletop behave: error: /proc/tabletop-react.csv: "), r.stderr


def test_a_file_where_the_output_folder_should_be_is_named(tmp_path):
    """It said "cannot make its folder: File exists" (which folder, what exists?)."""
    from tabletop.frames import InputError
    (tmp_path / "runs").write_text("a file")
    with pytest.raises(InputError) as err:
        atomic_write_text(tmp_path / "runs" / "day1" / "out.csv", "x")
    assert str(err.value) == (f"{tmp_path / 'runs' / 'day1' / 'out.csv'}: cannot make its "
                              f"folder: {tmp_path / 'runs'} is a file")


def test_a_temporary_file_left_by_a_killed_writer_is_removed_by_the_next_write(tmp_path):
    """A kiosk killed while writing its status file (every second) left the temporary file
    for ever: 3 in a drill of 50 crashes. A writer still running keeps its own."""
    import signal

    target = tmp_path / "status.json"
    killed = ("import os, signal, sys\nfrom tabletop.file_io import atomic_writer\n"
              "with atomic_writer(sys.argv[1]) as f:\n    f.write('{\"half')\n    f.flush()\n"
              "    os.kill(os.getpid(), signal.SIGKILL)\n")
    p = subprocess.run([sys.executable, "-c", killed, str(target)], timeout=60)
    assert p.returncode == -signal.SIGKILL
    assert len(list(tmp_path.glob(".status.json.*.tmp"))) == 1     # what the crash left
    running = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        theirs = tmp_path / f".status.json.{running.pid}.abc123.tmp"   # being written now
        theirs.write_text("{")
        atomic_write_text(target, '{"n": 1}')
        assert target.read_text() == '{"n": 1}'
        assert list(tmp_path.glob(".status.json.*.tmp")) == [theirs]   # 2 before
    finally:
        running.kill()
        running.wait()


@pytest.mark.parametrize("read", [read_yaml, read_csv_lines])
def test_an_endless_device_is_refused_not_read_whole(read):
    # /dev/zero as a config (or /dev/full as calibrate's --out, whose previous file is read
    # first) filled the machine's memory and was killed
    with pytest.raises(FileFormatError, match=r"/dev/zero: cannot read.*over 128 MB"):
        read("/dev/zero")


def test_a_full_disk_names_the_file_being_written(tmp_path, capsys):
    # the write said only "No space left on device": which file, of which command?
    import errno
    import resource
    import signal

    from tabletop.cli import main as tabletop
    gesture = ROOT / "examples" / "mop" / "gestures" / "circle.csv"
    code = tabletop(["follow", "--template", f"c={gesture}", "--input", str(gesture),
                     "--out", "/dev/full"])
    assert code == 2
    assert capsys.readouterr().err.strip() == ("tabletop follow: error: /dev/full: No space "
                                               "left on device")
    soft, hard = resource.getrlimit(resource.RLIMIT_FSIZE)   # a regular file on a full disk
    ignored = signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (4096, hard))
    try:
        with pytest.raises(OSError) as err:
            atomic_write_text(tmp_path / "out.csv", "x" * 100_000)
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, (soft, hard))
        signal.signal(signal.SIGXFSZ, ignored)
    assert err.value.errno == errno.EFBIG and err.value.filename == str(tmp_path / "out.csv")
    assert list(tmp_path.iterdir()) == []


def test_an_error_reading_a_source_while_writing_keeps_its_own_message(tmp_path):
    # the writer names its target only for a write's own errors (a full disk); a failed read
    # of a source inside the block is the source's error, not "out.csv: Is a directory"
    from tabletop.file_io import atomic_writer
    source = os.open(tmp_path, os.O_RDONLY)
    try:
        with pytest.raises(IsADirectoryError) as err:
            with atomic_writer(tmp_path / "out.csv") as f:
                f.write(os.read(source, 100).decode())
    finally:
        os.close(source)
    assert err.value.filename is None and "out.csv" not in str(err.value)
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("name, data, line", [
    ("config.yaml", b"table:\n  width: 1.2\nsources: [{kind: scripted, name: 'v\xe9'}]\n", 3),
    ("demo.csv", b"\xef\xbb\xbft,x\n0,1\n0.1,\xe92\n", 3),
    ("calibration.yaml", b"\x89PNG\r\n\x1a\n\x00\x00", 1),
    ("demo.csv", b"t,x\r0,1\r0.1,\xe92\r", 3),                       # CR-only line ends
    ("config.yaml", b"a: 1\r\nb: 2\rc: 3\nd: '\xe9'\r\n", 4),          # mixed line ends
])
def test_a_file_that_is_not_utf8_text_is_refused_naming_its_line(tmp_path, name, data, line):
    # (the message was Python's "'utf-8' codec can't decode byte 0xe9 in position 38")
    path = tmp_path / name
    path.write_bytes(data)
    read = read_csv_lines if name.endswith(".csv") else read_yaml
    with pytest.raises(FileFormatError) as err:
        read(path)
    text = str(err.value)
    assert text.startswith(f"{path}: cannot read") and f": line {line}: byte 0x" in text, text
    assert "is not UTF-8 text" in text and "codec" not in text, text


def test_the_line_of_a_bad_byte_is_counted_across_pieces(tmp_path):
    path = tmp_path / "long.yaml"
    path.write_bytes(b"# a comment line\n" * 200_000 + b"a: '\xff'\n")   # 3.4 MB
    with pytest.raises(FileFormatError) as err:
        read_yaml(path)
    assert ": line 200001: byte 0xff is not UTF-8 text" in str(err.value), err.value


def test_a_named_pipe_that_is_not_text_is_read_once_and_refused_naming_its_line(tmp_path):
    """The bytes of a pipe come once: the line of the bad byte is found in the bytes read (a
    second open of the pipe, its writer gone, waited for ever)."""
    import subprocess
    import sys
    import threading
    fifo = tmp_path / "config.yaml"
    os.mkfifo(fifo)

    def write() -> None:
        with open(fifo, "wb") as f:          # (waits for the reader)
            f.write(b"table:\n  width: 1.2\nname: '\xe9'\n")
    writer = threading.Thread(target=write, daemon=True)
    writer.start()
    reader = subprocess.Popen(
        [sys.executable, "-c", "import sys; from tabletop.files import read_yaml\n"
         "try:\n    read_yaml(sys.argv[1])\nexcept Exception as exc:\n    print(exc)\n", str(fifo)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)
    try:
        out, err = reader.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        reader.kill()
        out, err = reader.communicate()
    writer.join(5)
    assert out.strip() == (f"{fifo}: cannot read: line 3: byte 0xe9 is not UTF-8 text (a "
                           "binary file, or text saved in another encoding?)"), (out, err)


def test_regular_bytes_are_read_whole_and_anything_else_refused_at_once(tmp_path):
    """A pipe (no writer: an open of it would wait), a device, a folder, and a file longer
    than any input (sparse: refused by its size, none of it read) are refused in one line."""
    from tabletop.file_io import MAX_TEXT_BYTES, UnreadableText, read_regular_bytes
    good = tmp_path / "line.csv"
    good.write_bytes(b"t,x\r\n0,1\r\n")
    assert read_regular_bytes(good) == b"t,x\r\n0,1\r\n"
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    for other in (fifo, Path("/dev/zero"), tmp_path):
        with pytest.raises(UnreadableText, match="^not a regular file"):
            read_regular_bytes(other)
    huge = tmp_path / "huge.csv"
    with open(huge, "wb") as f:
        f.truncate(MAX_TEXT_BYTES + 1)
    with pytest.raises(UnreadableText, match="^over 128 MB"):
        read_regular_bytes(huge)


def test_a_json_file_given_for_a_csv_is_said_to_be_json(tmp_path, capsys):
    """A sprite sheet given as a template, or the studio's session log as a demonstration,
    said "line 1: duplicate column(s)" with 40 pieces of its JSON as column names (or "missing
    column(s) t"): it is said to be JSON, in one line."""
    from tabletop.cli import main as tabletop
    sheet = ROOT / "examples" / "mop" / "bird.json"
    gesture = ROOT / "examples" / "mop" / "gestures" / "circle.csv"
    log = tmp_path / "session-20260101-120000.jsonl"
    log.write_text('{"target": "pet", "outcome": "quit", "duration_s": 4.0}\n')
    for command, given in ((["follow", "--template", f"c={sheet}", "--input", str(gesture)],
                            f"{sheet}: line 1: JSON, not a template 'c' CSV file"),
                           (["behave", "--train", str(log), "--input", str(gesture)],
                            f"{log}: line 1: JSON, not a demonstration CSV")):
        assert tabletop([*command, "--out", str(tmp_path / "o.csv")]) == 2
        err = capsys.readouterr().err.splitlines()
        assert len(err) == 1 and given in err[0], err
    assert read_csv_lines(gesture)[1].shape[1] == 3      # a CSV is read as before


# what a folder that is there but takes no new file was said to be: "No such file or directory"
NO_NEW_FILE = "the folder exists but no file can be made in it"


def test_a_recording_into_a_folder_that_takes_no_file_says_so(capfd):
    """``run --record /proc/x.jsonl`` said "/proc: ... No such file or directory" of a folder
    that exists."""
    from tabletop.cli import main as tabletop
    code = tabletop(["run", "--headless", "--seconds", "0.2", "--record", "/proc/x.jsonl"])
    line = capfd.readouterr().err.strip()
    assert code == 2 and line.startswith(
        f"tabletop run: error: /proc: cannot start a recording there: {NO_NEW_FILE}"), line


def test_a_written_file_in_a_folder_that_takes_no_file_says_so():
    with pytest.raises(OSError) as err:
        atomic_write_text(Path("/proc/tabletop-out.csv"), "x")
    assert err.value.strerror.startswith(NO_NEW_FILE)

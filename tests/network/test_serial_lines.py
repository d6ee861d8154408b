"""The ``serial`` source's lines: how they parse and split, and what they put on the bus through
a real pseudo-terminal and pyserial's ``loop://``."""

import math
import os

import pytest

from tracking.pucks import TrackerSettings
from tracking.serial_input import (MAX_LINE, Command, LineError, LineSplitter, SerialInput,
                                   parse_line)

from tests.network.helpers import wait_for
from tests.network.serial_pty import tracked_pty


@pytest.mark.parametrize("line, command", [
    (b"puck 3 0.5 0.25 -1.5", Command("puck", 3, values=(0.5, 0.25, -1.5))),
    (b"touch 12  0.1\t0.2\r", Command("touch", 12, values=(0.1, 0.2))),
    (b"lift 12", Command("lift", 12)),
    (b"stream hand 1 2.5 -3e-2", Command("stream", name="hand", values=(1.0, 2.5, -0.03))),
    (b"# a comment", None),
    (b"lift 4   # the finger left", Command("lift", 4)),
    (b"puck 2 0.5 0.25 7.0", Command("puck", 2, values=(0.5, 0.25, 7.0 - 2 * math.pi))),
    (b"", None),
    (b"touch 1 +.5 -3.", Command("touch", 1, values=(0.5, -3.0))),
    (b"stream hand 1E2 -0.25e+1 7", Command("stream", name="hand", values=(100.0, -2.5, 7.0))),
])
def test_lines_parse(line, command):
    assert parse_line(line) == command


@pytest.mark.parametrize("line, kind", [
    (b"puck 3 0.5 0.25", "wrong_arguments"),
    (b"puck x 0.5 0.25 0", "wrong_arguments"),
    (b"puck 3 0.5 nan 0", "non_finite"),
    (b"touch 1 inf 0", "non_finite"),
    (b"touch 1 1e9 0", "out_of_range"),
    (b"stream 1", "wrong_arguments"),
    (b"stream b@d 1", "wrong_arguments"),
    (b"stream hand 1 -1e200", "out_of_range"),   # a followed stream became NaN
    (b"jump 1 2", "unknown_command"),
    (b"\x00\x01\x02", "garbage"),
    (b"puck \xff 1 2 3", "garbage"),
    (b"puck 3 1_0 0 0", "wrong_arguments"),    # float() reads 10
    (b"touch 1 0x1 0", "wrong_arguments"),
    (b"touch 1 1e 0", "wrong_arguments"),
    (b"stream hand 1 1__2", "wrong_arguments"),
    (b"stream hand 1 0_.5", "wrong_arguments"),
    (b"touch 1 -nan 0", "non_finite"),
    (b"touch 1 +Infinity 0", "non_finite"),
])
def test_bad_lines_name_their_kind(line, kind):
    with pytest.raises(LineError) as info:
        parse_line(line)
    assert info.value.kind == kind


def test_the_splitter_holds_at_most_one_line_and_skips_overlong_ones():
    s = LineSplitter()
    assert s.feed(b"puck 1 0 0 0\r\npartial") == [b"puck 1 0 0 0\r"]
    assert s.feed(b" line\n") == [b"partial line"]
    for _ in range(500):                           # a line without a newline, for minutes
        assert s.feed(b"x" * 100) == []
        assert len(s._buf) <= MAX_LINE + 1          # the line and the \r of a \r\n
    assert s.overlong == 1
    assert s.feed(b"tail of it\nlift 1\n") == [b"lift 1"]
    assert s.feed(b"y" * (MAX_LINE + 1) + b"\nlift 2\n") == [b"lift 2"]
    assert s.overlong == 2


def test_the_splitter_marks_where_a_read_s_last_overlong_line_ends():
    """The bytes of a read that the "lines ending in \\r alone?" question is asked of: up to the
    end of its overlong line (not the next line's, read with it: a \\r there asked it about a
    plain overlong line when the reads were chunked so), the whole read where the line runs on."""
    s = LineSplitter()
    data = b"x" * (MAX_LINE + 10) + b"\n" + b"puck 1\r0.5 0.4"
    assert s.feed(data) == [] and s.overlong == 1
    assert s.overlong_upto == MAX_LINE + 10 and b"\r" not in data[:s.overlong_upto]
    assert s.feed(b"lift 1\n") == [b"puck 1\r0.5 0.4lift 1"] and s.overlong_upto == 0
    running = b"puck 1 0.5 0.4 0\r" * 80                  # \r alone: one line for ever
    assert s.feed(running) == [] and s.overlong == 2 and s.overlong_upto == len(running)


@pytest.mark.parametrize("ending", [b"\n", b"\r\n"])
def test_a_line_of_exactly_max_line_bytes_passes_with_either_ending(ending):
    """DESIGN: at most 1024 bytes a line, ended by \\n or \\r\\n (an Arduino's println
    sends \\r\\n): the ending does not count, whole or fed byte by byte."""
    line = b"stream hand " + b"0.5 " * ((MAX_LINE - 12) // 4)
    line = line + b"1" * (MAX_LINE - len(line))
    assert len(line) == MAX_LINE and parse_line(line.rstrip(b"\r")) is not None
    for chunks in ([line + ending], [bytes([b]) for b in line + ending]):
        s = LineSplitter()
        got = [out for c in chunks for out in s.feed(c)]
        assert got == [line + ending[:-1]] and s.overlong == 0
    s = LineSplitter()                                   # one byte more is too long
    assert s.feed(b"x" + line + ending + b"lift 1\n") == [b"lift 1"] and s.overlong == 1


def test_lines_through_a_pty_become_pucks_touches_and_streams():
    with tracked_pty(0.3) as (master, src, inputs):
        os.write(master, b"puck 4 0.5 0.25 1.0\ntouch 2 0.1 0.2\r\nstream hand 1 2 3\n"
                         b"# note\nnonsense here\n")
        assert wait_for(lambda: src.lines == 3, 5.0)
        f = inputs.next(0, 0.0)
        assert [(p.id, p.x, p.y, p.angle) for p in f.pucks] == [(4, 0.5, 0.25, 1.0)]
        assert [(c.id, c.x, c.y) for c in f.touches] == [(2, 0.1, 0.2)]
        assert f.streams["hand"].tolist() == [1.0, 2.0, 3.0]
        assert src.bad.counts() == {"unknown_command": 1}
        assert "1 unknown command" in src.health().message
        os.write(master, b"lift 2\n")
        assert wait_for(lambda: src.lines == 4, 5.0)
        assert inputs.next(1, 0.0).touches == ()
        # Not repeated for timeout_s: the puck leaves the bus (not coasting), the stream too.
        assert wait_for(lambda: inputs.next(2, 0.0).pucks == (), 5.0)
        assert dict(inputs.next(3, 0.0).streams) == {}


def test_lines_padded_with_nul_bytes_are_read_and_a_nul_inside_a_line_is_garbage():
    """A board writing its whole fixed buffer (``Serial.write(buf, sizeof buf)``): NULs after
    each newline start the next line, and before a ``\r\n``. Both lines were refused as bad
    numbers / unknown commands; a NUL inside a line is still refused."""
    with tracked_pty(5.0) as (master, src, inputs):
        os.write(master, b"puck 4 0.5 0.25 1.0\n" + b"\0" * 12
                 + b"touch 2 0.1 0.2\0\0\0\r\n" + b"\0" * 16
                 + b"pu\0ck 5 0.5 0.25 1.0\n" + b"puck 6 0.5\0 0.25 1.0\n")
        assert wait_for(lambda: sum(src.bad.counts().values()) == 2, 5.0)
        f = inputs.next(0, 0.0)
        assert [(p.id, p.x, p.y, p.angle) for p in f.pucks] == [(4, 0.5, 0.25, 1.0)]
        assert [(c.id, c.x, c.y) for c in f.touches] == [(2, 0.1, 0.2)]
        assert src.bad.counts() == {"garbage": 1, "wrong_arguments": 1}


def test_numbers_in_other_spellings_are_malformed_lines_counted_and_logged_once(caplog):
    """Numbers are plain decimal or float spellings (DESIGN): a board's ``1_0`` (Python's
    float() reads 10) puts no puck at x = 10 m; such lines are counted and said once, as
    other malformed lines are."""
    caplog.set_level("WARNING", logger="tabletop")
    with tracked_pty(5.0) as (master, src, inputs):
        os.write(master, b"puck 4 0_1 0.25 1.0\npuck 5 0.5 0.25 1_0\ntouch 2 0.1 0.2\n")
        assert wait_for(lambda: src.lines == 1 and src.bad.total() == 2, 5.0)
        f = inputs.next(0, 0.0)
        assert f.pucks == () and [c.id for c in f.touches] == [2]
        assert src.bad.counts() == {"wrong_arguments": 2}
    said = [r.getMessage() for r in caplog.records if "ignored" in r.getMessage()]
    assert said == ["mcu: ignored wrong arguments input (1 so far): puck 4 value '0_1' is not "
                    "a number: b'puck 4 0_1 0.25 1.0'"], said


def test_what_is_not_repeated_for_timeout_s_leaves_the_bus_and_what_is_repeated_stays():
    """DESIGN: a puck or touch not repeated for ``timeout_s`` leaves the bus. It leaves, not
    coasts (the tracker here would coast a lost puck for 30 s), and a touch leaves without a
    ``lift``; a puck and a touch repeated all along stay past ``timeout_s``."""
    import time
    with tracked_pty(0.3, TrackerSettings(smooth=False, coast_s=30.0)) as (master, src, inputs):
        os.write(master, b"puck 4 0.5 0.25 1.0\ntouch 2 0.1 0.2\n")
        start, seq, frames = time.monotonic(), 0, []
        while time.monotonic() - start < 10.0:
            os.write(master, b"puck 5 0.9 0.5 0\r\ntouch 6 0.3 0.3\r\n")
            time.sleep(0.03)
            f = inputs.next(seq, 0.0)
            seq += 1
            frames.append(f)
            if time.monotonic() - start > 1.0 and 4 not in {p.id for p in f.pucks} \
                    and 2 not in {c.id for c in f.touches}:
                break
        assert any(4 in {p.id for p in f.pucks} for f in frames)
        assert any(2 in {c.id for c in f.touches} for f in frames)
        last = frames[-1]
        assert [p.id for p in last.pucks] == [5] and [c.id for c in last.touches] == [6]
        assert all(p.state == "seen" for f in frames for p in f.pucks)   # never coasting
        assert src.bad.counts() == {}


def test_huge_puck_angles_through_a_pty_leave_the_tracker_running():
    """An angle is any finite number of radians: 1e308 and then -1e308 (a board sending
    garbage that parses) are wrapped, not an infinite turn that stopped the installation."""
    with tracked_pty(5.0) as (master, src, inputs):
        for seq, angle in enumerate((b"1e308", b"-1e308", b"3.0")):
            os.write(master, b"puck 4 0.5 0.25 " + angle + b"\n")
            assert wait_for(lambda: src.lines == seq + 1, 5.0)
            (p,) = inputs.next(seq, 0.0).pucks
            assert -math.pi < p.angle <= math.pi
        assert p.angle == 3.0


def test_lines_ending_in_a_bare_cr_are_said_as_such(caplog):
    """Firmware ending its lines with ``\\r`` alone ran every line into the next: the only word
    was "line over 1024 bytes". The line now asks about the ending; an overlong line of
    ``\\n``-ended input does not."""
    caplog.set_level("WARNING", logger="tabletop")
    noise = bytes(b for b in range(256) if b != 10) * 5   # line noise with a \r: not asked
    for ending, asked in ((b"\r", True), (b"\n", False), (noise, False)):
        src = SerialInput(f"cr{asked}{len(ending)}", "loop://")
        src.open()
        try:
            assert wait_for(lambda: src.port_object is not None, 5.0)
            data = b"".join(b"puck 1 0.5 0.4 %d" % i + ending for i in range(100))
            if ending == noise:
                data = noise + b"\n"
            src.port_object.write(data if asked else b"x" * (MAX_LINE + 10) + b"\n" + data)
            assert wait_for(lambda: src.bad.counts().get("overlong", 0) >= 1, 5.0)
            assert wait_for(lambda: src.lines == (100 if ending == b"\n" else 0), 5.0)
        finally:
            src.close()
        said = [r.getMessage() for r in caplog.records
                if f"cr{asked}{len(ending)}: ignored overlong" in r.getMessage()]
        assert len(said) == 1 and ("lines ending in \\r alone? end them with \\n or \\r\\n"
                                   in said[0]) == asked, said


def test_line_noise_read_in_parts_is_not_asked_about_its_line_endings(caplog):
    """An overlong line is judged whole: noise whose last read alone is plain ASCII with a
    ``\r`` in it (its earlier read not) is not taken for lines ending in ``\r``."""
    caplog.set_level("WARNING", logger="tabletop")
    src = SerialInput("noise-in-parts", "loop://")
    src.open()
    try:
        assert wait_for(lambda: src.port_object is not None, 5.0)
        src.port_object.write(bytes(range(128, 256)) * 5)           # no line ends: held
        assert wait_for(lambda: src.port_object.in_waiting == 0, 5.0)
        src.port_object.write(b"puck 1 0.5 0.4 0\r" * 40 + b"\n")   # read after it
        assert wait_for(lambda: src.bad.counts().get("overlong", 0) >= 1, 5.0)
    finally:
        src.close()
    said = [r.getMessage() for r in caplog.records if "noise-in-parts: ignored" in r.getMessage()]
    assert len(said) == 1 and "alone?" not in said[0], said


def test_an_overlong_line_is_not_asked_about_a_cr_of_the_next_line_read_with_it(caplog):
    """An overlong line of plain text, then the start of a line with a \\r in it, written at
    once to a real terminal (read together): "line over 1024 bytes", without the question
    about lines ending in \\r alone, which is about the overlong line's own bytes."""
    caplog.set_level("WARNING", logger="tabletop")
    with tracked_pty(0.3) as (master, src, _):
        os.write(master, b"x" * (MAX_LINE + 10) + b"\npuck 1\r0.5 0.4 0")
        assert wait_for(lambda: src.bad.counts().get("overlong", 0) >= 1, 5.0)
    said = [r.getMessage() for r in caplog.records if "ignored overlong" in r.getMessage()]
    assert len(said) == 1 and "line over 1024 bytes" in said[0], said
    assert "alone?" not in said[0], said

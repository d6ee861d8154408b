"""The OSC and TUIO codecs as pure functions, checked against python-osc's own builder and
parser."""

import math

import numpy as np
import pytest
from pythonosc.osc_message_builder import OscMessageBuilder
from pythonosc.osc_packet import OscPacket

from tracking.osc_codec import OscError, decode_packet, encode_bundle, encode_message
from tracking.tuio import Entity, TuioError, from_table, parse_set, to_table

from tests.network.helpers import bundle, message


def test_python_osc_packets_decode_with_their_types():
    b = OscMessageBuilder("/x")
    for value, kind in [(7, "i"), (2.5, "f"), ("hé", "s"), (b"\x01\x02\x03", "b"), (True, "T"),
                        (False, "F"), (None, "N"), (1.25e300, "d"), (2**40, "h")]:
        b.add_arg(value, kind)
    (address, args), = decode_packet(b.build().dgram).messages
    assert address == "/x"
    assert args == (7, 2.5, "hé", b"\x01\x02\x03", True, False, None, 1.25e300, 2**40)


def test_our_packets_parse_in_python_osc():
    data = encode_bundle([encode_message("/tuio/2Dobj", ("set", 3, 9, 0.25, 0.5, 1.5)),
                          encode_message("/b", (b"xyz", True, None, "")),
                          encode_bundle([encode_message("/inner", (1,))])])
    msgs = [(m.message.address, list(m.message.params)) for m in OscPacket(data).messages]
    assert msgs == [("/tuio/2Dobj", ["set", 3, 9, 0.25, 0.5, 1.5]),
                    ("/b", [b"xyz", True, None, ""]), ("/inner", [1])]


def test_nested_bundles_are_flattened_in_order_up_to_a_depth():
    inner = bundle(message("/a", 1), bundle(message("/b", 2)))
    packet = decode_packet(bundle(inner, message("/c", 3)).dgram)
    assert [m[0] for m in packet.messages] == ["/a", "/b", "/c"]
    assert packet.depth == 3
    deep = encode_message("/z", (1,))
    for _ in range(9):
        deep = encode_bundle([deep])
    with pytest.raises(OscError, match="nested deeper"):
        decode_packet(deep)


@pytest.mark.parametrize("data", [
    b"", b"/", b"abc\x00", b"/a\x00\x00,i\x00\x00", b"/a\x00\x00,q\x00\x00\x00\x00\x00\x00",
    b"/a\x00\x00,s\x00\x00abcd", b"/a\x00\x00,b\x00\x00\x00\x00\x00\x09abc",
    b"#bundle\x00\x00\x00", b"#bundle\x00" + bytes(8) + b"\x00\x00\x00\x08/a\x00\x00",
    b"#bundle\x00" + bytes(8) + b"\xff\xff\xff\xf0", b"/a\x00\x00,s\x00\x00\xff\xfe\x00\x00",
])
def test_malformed_packets_raise_one_error_type(data):
    with pytest.raises(OscError):
        decode_packet(data)


def test_set_arguments_are_checked():
    e = parse_set("2Dobj", (3, 9, 0.25, 0.5, 1.5, 0.1, 0.2, 0.3, 0.0, 0.0))
    assert e == Entity("2Dobj", 3, 9, 0.25, 0.5, 1.5, 0.1, 0.2, 0.3)
    assert parse_set("2Dcur", (4, 1, 0, 0.0, 0.0, 0.0)).x == 1.0  # ints where floats belong
    blob = parse_set("2Dblb", (5, 0.1, 0.2, 0.3, 0.01, 0.02, 0.001, 0.4, 0.5, 0.6, 0.0, 0.0))
    assert (blob.x, blob.y, blob.angle, blob.vx, blob.vy, blob.rotation) == (0.1, 0.2, 0.3, 0.4,
                                                                              0.5, 0.6)
    for args, kind in [((3, 9, 0.25), "wrong_arguments"),
                       ((3.0, 9, 0.2, 0.5, 1.5, 0.0, 0.0, 0.0, 0.0, 0.0), "wrong_arguments"),
                       ((3, 9, "x", 0.5, 1.5, 0.0, 0.0, 0.0, 0.0, 0.0), "wrong_arguments"),
                       ((3, 9, math.nan, 0.5, 1.5, 0.0, 0.0, 0.0, 0.0, 0.0), "non_finite"),
                       ((3, 9, 1e9, 0.5, 1.5, 0.0, 0.0, 0.0, 0.0, 0.0), "out_of_range")]:
        with pytest.raises(TuioError) as info:
            parse_set("2Dobj", args)
        assert info.value.kind == kind


def test_table_mapping_and_its_inverse():
    rng = np.random.default_rng(3)
    table = (1.2, 0.8)
    for x, y, a, vx, vy, w in rng.uniform(-3, 3, size=(200, 6)):
        tx, ty, ta, tvx, tvy, tw = from_table(x, y, a, vx, vy, w, table)
        assert 0 <= ta < 2 * math.pi
        back = to_table(Entity("2Dobj", 1, 1, tx, ty, ta, tvx, tvy, tw), table)
        assert back[:2] == pytest.approx((x, y), abs=1e-12)
        assert math.remainder(back[2] - a, math.tau) == pytest.approx(0.0, abs=1e-12)
        assert back[3:] == pytest.approx((vx, vy, w), abs=1e-12)
    # DESIGN.md: (x * W, (1 - y) * H); angle -a; top left of the screen is the far left corner.
    assert to_table(Entity("2Dobj", 1, 1, 0.0, 0.0, math.pi / 2), table)[:3] == pytest.approx(
        (0.0, 0.8, -math.pi / 2))

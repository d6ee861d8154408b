"""Frame.with_characters (tabletop/frames.py): a copy of the frame, every field kept, the
characters appended; its frozen streams shared, not copied."""

import dataclasses

import numpy as np
import pytest

from tabletop.frames import CharacterState, Frame, Puck, SourceHealth, Touch


def test_with_characters_keeps_every_field_and_appends_the_characters():
    first = CharacterState(name="a", x=0.1, y=0.2, heading=0.0)
    added = (CharacterState(name="b", x=0.3, y=0.4, heading=1.0),)
    frame = Frame(seq=7, t=1.5, pucks=(Puck(id=1, x=0.2, y=0.3, angle=0.5),),
                  touches=(Touch(id=2, x=0.5, y=0.5),), streams={"s": np.arange(3.0)},
                  characters=(first,), commands=("designer.record",),
                  health=(SourceHealth(name="cam", ok=True),), focus="pet",
                  status="attract", consumed={"studio": {"pucks": ()}})
    out = frame.with_characters(added)
    assert type(out) is Frame and out is not frame
    for f in dataclasses.fields(Frame):
        if f.name not in ("characters", "streams"):
            assert getattr(out, f.name) is getattr(frame, f.name), f.name
    assert out.characters == (first, *added) and frame.characters == (first,)
    assert out.streams is frame.streams and not out.streams["s"].flags.writeable
    assert out.with_characters(iter(added)).characters == (first, *added, *added)
    with pytest.raises(dataclasses.FrozenInstanceError):
        out.seq = 8

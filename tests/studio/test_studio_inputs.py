"""The studio's inputs in a recording: what the studio stage takes from a frame (control-marker
pucks, designer commands) is kept in ``Frame.consumed``, survives the session format, and
:func:`studio_input` gives the studio back the frame it was given live."""

import json

import pytest

from tabletop.frames import Frame, Puck
from tabletop.session import SessionError, frame_from_dict, frame_to_dict, read_frames
from tabletop.studio.build import Markers, StudioStage, studio_input
from tabletop.studio.machine import Studio


class Slot:
    """A target that records nothing (the stage's bookkeeping is what is tested)."""

    name, what, started_problems = "slot", "action", ()

    def __getattr__(self, name):
        return lambda *a, **k: "" if name != "items" else []


def test_what_the_stage_takes_is_recorded_and_given_back(tmp_path):
    studio = Studio([Slot()], countdown_s=1.0)
    stage = StudioStage(Markers({"record": 45, "keep": 47}, studio, debounce_s=0.0), studio)
    given = Frame(seq=3, t=10.0, pucks=(Puck(1, 0.2, 0.3, 0.1), Puck(47, 0.05, 0.05, 0.0),
                                        Puck(7, 0.9, 0.4, 2.0)),
                  commands=("camera.left", "designer.record"))
    out = stage(given)
    assert [p.id for p in out.pucks] == [1, 7] and out.commands == ("camera.left",)
    assert studio.state == "countdown"
    taken = out.consumed["studio"]
    assert [p.id for p in taken["pucks"]] == [47] and taken["commands"] == given.commands
    # through the session format and back to what the studio was given
    again = studio_input(frame_from_dict(json.loads(json.dumps(frame_to_dict(out)))))
    assert again.commands == given.commands
    assert sorted(again.pucks, key=lambda p: p.id) == sorted(given.pucks, key=lambda p: p.id)
    assert again.consumed == {}
    # a frame the studio took nothing from carries nothing more
    plain = stage(Frame(seq=4, t=10.1, pucks=(Puck(1, 0.2, 0.3, 0.1),)))
    assert plain.consumed == {} and "consumed" not in frame_to_dict(plain)
    assert studio_input(plain) is plain


@pytest.mark.parametrize("bad, words", [
    (5, "consumed: expected a mapping"),
    ({"studio": {"commands": [1]}}, "consumed.studio.commands"),
    ({"studio": {"pucks": [{"id": 1, "x": "nan", "y": 0, "angle": 0}]}}, "x is"),
])
def test_a_damaged_consumed_is_refused_naming_file_and_line(tmp_path, bad, words):
    path = tmp_path / "s.jsonl"
    frame = dict(frame_to_dict(Frame(seq=0, t=0.0)), consumed=bad)
    path.write_text(json.dumps({"format": "tabletop-session", "version": 2}) + "\n"
                    + json.dumps(frame_to_dict(Frame(seq=0, t=0.0))) + "\n"
                    + json.dumps(dict(frame, seq=1, t=0.1)) + "\n")
    with pytest.raises(SessionError) as exc:
        list(read_frames(path))
    assert "s.jsonl: line 3" in str(exc.value) and words in str(exc.value)

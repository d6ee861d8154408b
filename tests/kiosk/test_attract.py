"""Attract mode (scripted pucks when nobody is at the table, a smooth hand-over) and the
"one moment" screen while an input that worked is down."""

import numpy as np
import pygame

from tabletop.frames import Frame, Puck, SourceHealth
from tabletop.kiosk.attract import Attract, OneMoment
from tracking.visitor import ScriptedVisitor

TABLE = (1.2, 0.8)


def scripted():
    v = ScriptedVisitor(TABLE, [1, 2], seed=4)
    return v.poses


def test_attract_starts_after_idle_and_hands_over_smoothly():
    now = [0.0]
    a = Attract(scripted(), idle_s=10.0, handover_s=1.0, clock=lambda: now[0])
    rate = 30.0
    frames = []
    for i in range(int(25 * rate)):
        t = now[0] = 100 + i / rate
        if t < 102:               # a visitor plays for 2 s, then leaves the puck still
            pucks = (Puck(1, 0.2 + 0.05 * (t - 100), 0.3, 0.5),)
        elif t < 120:             # the puck lies still: nobody is playing
            pucks = (Puck(1, 0.3, 0.3, 0.5),)
        else:                     # a visitor moves puck 1 from its resting place
            pucks = (Puck(1, 0.3 + 0.1 * (t - 120), 0.3, 0.5),)
        frames.append(a(Frame(seq=i, t=t, pucks=pucks)))
    status = [f.status for f in frames]
    first = status.index("attract")
    assert 111.7 < frames[first].t <= 112.0 + 1 / rate   # 10 s after the last centimetre moved
    assert a.sessions == 1
    during = [f for f in frames if f.status == "attract"]
    assert all({p.id for p in f.pucks} == {1, 2} for f in during)
    assert all(p.state == "coasting" for f in during for p in f.pucks)
    # the scripted pucks move (the characters play by themselves)
    xs = np.array([f.puck(1).x for f in during])
    assert np.ptp(xs) > 0.1
    last = status.index("", first)
    assert abs(frames[last].t - 120.0) < 2 * 0.01 / 0.1 + 2 / rate   # the visitor is noticed
    # hand-over: puck 1 glides from its scripted pose to the visitor's: no jump
    track = np.array([(f.puck(1).x, f.puck(1).y) for f in frames[first:]])
    steps = np.hypot(*np.diff(track, axis=0).T)
    assert steps.max() < 0.05                            # metres per tick, a jump would be larger
    end = frames[last + int(1.0 * rate) + 1]
    assert end.puck(1).x == 0.3 + 0.1 * (end.t - 120) and end.puck(2) is None


def test_one_moment_while_a_source_that_worked_is_down():
    now = [0.0]
    om = OneMoment(grace_s=1.0, clock=lambda: now[0])
    seen = []
    for i in range(120):
        t = now[0] = i / 10.0
        ok = not (2.0 <= t < 7.0)
        h = (SourceHealth("camera", ok), SourceHealth("osc", False, "never sent"))
        seen.append(om(Frame(seq=i, t=t, health=h)).status)
    down = [i / 10.0 for i, s in enumerate(seen) if s == "one_moment"]
    assert down[0] == 3.0 and down[-1] == 6.9 and len(down) == 40
    # a source that never worked (osc) does not hold the screen
    assert seen[-1] == ""


def test_the_view_draws_the_calm_screen_instead_of_the_table():
    from tabletop.frames import CharacterState
    from tabletop.view import Renderer
    r = Renderer(TABLE, (320, 180))
    s1, s2 = pygame.Surface((320, 180)), pygame.Surface((320, 180))
    c = CharacterState("lover", 0.6, 0.4, 0.0, size=0.2, color=(240, 110, 150))
    for i in range(60):        # two seconds on the table: the character has faded in
        r.draw(s1, Frame(seq=i, t=i / 30, characters=(c,)))
    for i in range(60, 150):   # three seconds of "one moment"
        r.draw(s2, Frame(seq=i, t=i / 30, characters=(c,), status="one_moment"))
    a1, a2 = pygame.surfarray.array3d(s1), pygame.surfarray.array3d(s2)
    pink = lambda a: ((a[..., 0] > 200) & (a[..., 1] < 140)).sum()
    assert pink(a1) > 100 and pink(a2) == 0       # no frozen character on the calm screen
    calm = (a2[..., 2] > 120) & (a2[..., 2] > a2[..., 0])
    assert calm.sum() > 40                         # the ring of lights and "One moment" are drawn
    assert ((a1[..., 2] > 120) & (a1[..., 2] > a1[..., 0])).sum() < calm.sum() / 4


def test_attract_plays_the_mop_characters_actions_when_nobody_is_there(tmp_path):
    """examples/mop.yaml with nobody at the table: after idle_s, scripted performers draw the
    characters' own gestures and the characters play them (simulated time)."""
    from pathlib import Path

    import yaml

    from tabletop.config import validate_config
    from tabletop.kiosk.simulate import SimClock, simulated
    examples = Path(__file__).resolve().parents[2] / "examples"
    data = yaml.safe_load((examples / "mop.yaml").read_text())
    data["sources"] = [{"kind": "scripted", "pucks": []}]
    data["view"] = {"size": [320, 180]}
    data["kiosk"] = {"idle_s": 2.0, "heartbeat": {"enabled": False},
                     "status_file": str(tmp_path / "status.json"),
                     "log_file": str(tmp_path / "tabletop.log")}
    cfg = validate_config(data, str(examples / "mop.yaml"), examples)
    clock = SimClock()
    runner, inst = simulated(cfg, tmp_path / "config.yaml", clock, kiosk=True, studio=False)
    playing, status = set(), []

    def both_play() -> bool:   # both pucks' characters (which ones depends on the gestures)
        return bool(len(playing) >= 3 and playing & {"dancer", "bird"}
                    and playing & {"salamander", "face"})
    for _ in range(int(25 * 30)):   # at most 25 s; measured: they all play within 5 s
        frame = inst.loop.tick()
        clock.advance(1 / 30)
        status.append(frame.status)
        playing |= {c.name for c in frame.characters if c.valid and c.action}
        if len(status) > 3 * 30 and both_play():
            break
    inst.loop.close()
    assert status[int(1.5 * 30)] == "" and status[int(3 * 30)] == "attract"
    assert both_play(), playing

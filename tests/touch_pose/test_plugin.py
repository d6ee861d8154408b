"""The ``touch_pose`` engine on the bus: config, touches from any source, mouse fingers, camera
keys, and the projector view drawing the humanoid."""

import numpy as np
import pygame
import pytest

from tabletop.config import validate_config
from tabletop.frames import Frame, Touch
from tabletop.plugins import touch_pose
from tabletop.pointer import POINTER, with_mouse_fingers
from tabletop.registry import BuildContext
from tabletop.schema import ConfigError
from tabletop.view import Renderer

TABLE = (1.2, 0.8)


def _config(tmp_path, **engine):
    data = {"sources": [{"kind": "scripted", "pucks": []}],
            "engines": [{"kind": "touch_pose", "name": "poser", **engine}]}
    return validate_config(data, str(tmp_path / "c.yaml"), tmp_path)


@pytest.fixture
def engine(tmp_path, models):
    cfg = _config(tmp_path, view=[90, 15], physics=False, mouse=True)
    e = touch_pose.build(cfg["engines"][0], BuildContext(TABLE, 30.0, cfg, tmp_path))
    yield e
    e.close()
    POINTER.release()


def test_bad_engine_config_is_refused_with_its_key(tmp_path):
    with pytest.raises(ConfigError, match=r"engines\[0\]\.height"):
        _config(tmp_path, height=-1)
    with pytest.raises(ConfigError, match=r"engines\[0\]\.view"):
        _config(tmp_path, view=[1, 2, 3])


@pytest.mark.parametrize("elevation", [90, -90, 1000])
def test_a_view_elevation_pose_refuses_is_refused_in_the_config_too(tmp_path, elevation):
    with pytest.raises(ConfigError, match=r"c\.yaml: engines\[0\]\.view\[1\]: elevation "
                                          rf"{elevation} degrees is out of range; expected -89 "
                                          "to 89"):
        _config(tmp_path, view=[90, elevation])
    assert _config(tmp_path, view=[-30, 89])["engines"][0]["view"] == [-30.0, 89.0]


def _seen(tmp_path, azimuth: float) -> tuple[tuple[float, float, float], int]:
    """The humanoid at rest seen from ``azimuth`` (elevation 15): where its head faces
    (``facing``) and the pixels of its eyes' whites and pupils (white or black: channels
    within 40, mean above 180 or below 70) drawn at 1280x720 on a red ground."""
    cfg = _config(tmp_path, view=[azimuth, 15], physics=False)
    e = touch_pose.build(cfg["engines"][0], BuildContext(TABLE, 30.0, cfg, tmp_path))
    try:
        (c,) = e.step(Frame(0, 0.0))
    finally:
        e.close()
    surf = pygame.Surface((1280, 720))
    surf.fill((150, 30, 0))
    Renderer(TABLE, (1280, 720)).draw_character(surf, c)
    img = pygame.surfarray.array3d(surf).astype(int)
    mean = img.mean(axis=2)
    eyes = (img.max(axis=2) - img.min(axis=2) <= 40) & ((mean > 180) | (mean < 70))
    return c.facing, int(eyes.sum())


def test_the_humanoid_is_drawn_with_the_face_its_view_sees(tmp_path, models):
    """Its head's forward as the camera sees it: toward the viewer from the front (azimuth 0),
    across the screen in profile (90: the example's figure faces right), away from behind.
    Measured (toward the viewer; eye pixels): 0.97, 143 / -0.03, 70 / -0.97, 0; two eyes of
    134-143 px at each of them before."""
    (_, _, front), two = _seen(tmp_path, 0)
    (px, _, profile), one = _seen(tmp_path, 90)
    (_, _, back), none = _seen(tmp_path, 180)
    assert front > 0.9 and abs(profile) < 0.2 and px > 0.9 and back < -0.9
    assert 0.35 * two < one < 0.65 * two and none == 0


def test_touches_from_the_bus_pose_the_drawn_humanoid(engine):
    hand = np.array(engine.core.describe()["parts"]["right_hand"])
    for k in range(45):
        t = k / 30
        goal = hand + np.array([0.0, 0.03]) * min(t, 1.0)
        (c,) = engine.step(Frame(k, t, touches=(Touch(11, *goal),)))
    assert c.name == "poser" and c.points.shape == (19, 2) and len(c.bones) == 17
    assert c.label == "posing view 90,15 touches 1"      # the overlay's line said "posing  view"
    assert engine.core.fingers[11].part == "right_hand"
    drawn = c.points[len(engine.core.body.names) + 3]  # the right hand's point
    assert np.linalg.norm(drawn - goal) < 0.005
    # the renderer draws it (fully present, as once faded in): its limbs light the dark table
    # along the bones, the right hand included
    pygame.display.init()
    r = Renderer(TABLE, (960, 640))
    surface = pygame.Surface((960, 640))
    r.draw_character(surface, c)
    lit = pygame.surfarray.array3d(surface).sum(axis=2) > 120
    assert lit.sum() > 200
    x, y = r.map.point(*drawn)
    assert lit[int(x) - 4:int(x) + 5, int(y) - 4:int(y) + 5].any()


def test_mouse_fingers_and_camera_keys(engine):
    head = engine.core.describe()["parts"]["head"]
    POINTER.press(*head)
    engine.step(with_mouse_fingers(Frame(0, 0.0)))
    assert list(engine.core.fingers.values())[0].part == "head"
    POINTER.release()
    engine.step(with_mouse_fingers(Frame(1, 1 / 30)))
    assert engine.core.fingers == {}
    az = engine.core.camera.azimuth
    engine.step(Frame(2, 2 / 30, commands=("camera.left", "camera.left")))
    assert engine.core.camera.azimuth == pytest.approx((az - 30) % 360)


def test_two_fingers_on_empty_table_turn_the_camera(engine):
    az = engine.core.camera.azimuth
    for k in range(10):
        engine.step(Frame(k, k / 30, touches=(Touch(1, 0.1 + 0.01 * k, 0.1),
                                              Touch(2, 0.15 + 0.01 * k, 0.1))))
    assert engine.core.fingers[1].part is None
    turned = (engine.core.camera.azimuth - az + 180) % 360 - 180
    assert turned == pytest.approx(-0.09 * 300.0, abs=1.0)


def test_the_view_turns_the_mouse_into_fingers_and_arrows_into_camera_commands(tmp_path):
    from tabletop.config import VIEW
    from tabletop.loop import CommandQueue
    from tabletop.schema import Context
    from tabletop.view import ProjectorView
    options = VIEW.validate({"size": [640, 400], "headless": True}, "view",
                            Context(str(tmp_path / "c.yaml"), tmp_path))
    commands = CommandQueue()
    view = ProjectorView(TABLE, options, commands=commands, headless=True)
    try:
        x, y = view.renderer.map.point(0.3, 0.5)
        pygame.event.post(pygame.event.Event(pygame.MOUSEBUTTONDOWN,
                                             pos=(int(x), int(y)), button=1))
        view._events()
        (f,) = POINTER.touches()
        assert abs(f.x - 0.3) < 0.005 and abs(f.y - 0.5) < 0.005
        x2, y2 = view.renderer.map.point(0.4, 0.45)
        pygame.event.post(pygame.event.Event(pygame.MOUSEMOTION, pos=(int(x2), int(y2)),
                                             rel=(0, 0), buttons=(1, 0, 0)))
        view._events()
        (f,) = POINTER.touches()
        assert abs(f.x - 0.4) < 0.005 and abs(f.y - 0.45) < 0.005
        pygame.event.post(pygame.event.Event(pygame.MOUSEBUTTONUP,
                                             pos=(int(x2), int(y2)), button=1))
        pygame.event.post(pygame.event.Event(pygame.KEYDOWN, key=pygame.K_LEFT, mod=0))
        view._events()
        assert POINTER.touches() == ()
        assert commands.drain() == ("camera.left",)
    finally:
        view.close()
        POINTER.release()


@pytest.mark.parametrize("x", [float("nan"), 1e200])
def test_a_broken_touch_is_ignored_and_the_engine_keeps_going(engine, x):
    hand = engine.core.describe()["parts"]["right_hand"]
    for k in range(5):
        (c,) = engine.step(Frame(k, k / 30, touches=(Touch(1, x, 0.4), Touch(2, *hand))))
    assert 1 not in engine.core.fingers and engine.core.fingers[2].part == "right_hand"
    assert np.all(np.isfinite(c.points))


def test_a_session_posed_with_the_mouse_is_recorded_and_replays_the_same(tmp_path, models):
    """The mouse's fingers are touches of the frame, so the recording holds them and its replay
    poses the character as the live run did (read by the engine alone, a recording would have
    no touches and its replay stand still)."""
    import json
    import subprocess
    import sys

    from tabletop.app import build_live
    data = {"sources": [{"kind": "scripted", "pucks": []}], "view": {"enabled": False},
            "loop": {"rate_hz": 30},
            "engines": [{"kind": "touch_pose", "name": "poser", "view": [90, 15],
                         "physics": False, "mouse": True}]}
    cfg = validate_config(data, str(tmp_path / "c.yaml"), tmp_path)
    path = tmp_path / "live.jsonl"
    inst = build_live(cfg, headless=True, record_path=path)
    hand = np.array(inst.engines[0].core.describe()["parts"]["right_hand"])
    import threading
    import time
    run = threading.Thread(target=inst.loop.run, kwargs={"seconds": 2.0})
    run.start()
    try:
        time.sleep(0.3)
        POINTER.press(*hand)
        for k in range(1, 21):
            POINTER.move(*(hand + [0.003 * k, 0.004 * k]))
            time.sleep(0.04)
    finally:
        POINTER.release()
        run.join()
    live = [json.loads(x) for x in path.read_text().splitlines()[1:]]
    held = [f for f in live if f["touches"]]
    assert len(held) >= 15 and all(t["id"] >= 90_000 for f in held for t in f["touches"])
    out = subprocess.run([sys.executable, "-m", "tabletop", "replay", str(path), "--fast",
                          "--no-view", "--out", str(tmp_path / "again.jsonl")],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr[-500:]
    again = [json.loads(x) for x in (tmp_path / "again.jsonl").read_text().splitlines()[1:]]
    assert [f["characters"] for f in again] == [f["characters"] for f in live]
    moved = [f["characters"][0]["points"] for f in (live[4], live[-1])]
    assert moved[0] != moved[1]                   # the mouse did pose it

"""The view's treatment of action-following characters and of each configuration: a hinted pose
(early feedback) drawn faintly, hybrid characters with their face, the idle look's invitation."""

import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pygame
import pytest

from behaviors.mop.creatures import FaceModel, creature_skeleton, hybrid_clips
from behaviors.mop.puppetry import FaceRig, HybridRig, PlanarRig
from behaviors.motion.skeleton import place
from tabletop.config import load_config
from tabletop.drawing.topology import hybrid_parts
from tabletop.frames import CharacterState, Frame
from tabletop.plugins.mop_rigs import HYBRID_HEAD
from tabletop.view import INVITATIONS, Renderer, invitation

from tests.tabletop.test_view import SIZE, TABLE, at, ground, rgb

pytestmark = pytest.mark.usefixtures("pygame_display")

ROOT = Path(__file__).resolve().parents[2]


def stick(x: float, **kw) -> CharacterState:
    """A creature lying along x: three points from ``x`` to ``x + 0.2`` m at y = 0.4."""
    pts = np.array([[x, 0.4], [x + 0.1, 0.4], [x + 0.2, 0.4]])
    return CharacterState("stick", x + 0.1, 0.4, 0.0, kind="creature", size=0.3, points=pts,
                          bones=((0, 1), (1, 2)), color=(90, 220, 120), **kw)


def edge_on(surface: pygame.Surface, xy: tuple[float, float], reach: int = 20) -> int:
    """The brightest pixel (sum of its channels) on the window column through ``xy`` within
    ``reach`` px: across a limb lying along x, its outline (a hinted pose is drawn outlined,
    its inside faint). Read from that column alone (the whole image copied to read 41 pixels
    was most of a per-frame check)."""
    x, y = int(round(xy[0])), int(round(xy[1]))
    column = pygame.surfarray.pixels3d(surface)[x, y - reach:y + reach + 1].astype(int)
    return int(column.sum(axis=1).max())


def test_a_hinted_pose_is_drawn_faintly_fades_in_and_goes():
    r = Renderer(TABLE, SIZE)
    s = pygame.Surface(SIZE)
    rest = stick(0.2, valid=False)
    hinted = stick(0.2, valid=False, hints=(("wave", 0.9, 0.4),),
                   hint_points=np.array([[0.2, 0.6], [0.3, 0.6], [0.4, 0.6]]))
    where = r.map.point(0.35, 0.6)       # on the hinted pose, far from the character itself
    body = r.map.point(0.35, 0.4)
    seen = []
    for k in range(40):     # resting for two thirds of a second, then an action is suspected
        r.draw(s, Frame(seq=k, t=1.0 + k / 30, characters=(hinted if k >= 20 else rest,)))
        seen.append(edge_on(s, where))
    img = rgb(s)
    g = ground(r, where)
    assert abs(seen[19] - g) <= 12                  # nothing hinted yet
    assert seen[20] < seen[22] < seen[39]           # fades in, no pop
    assert seen[39] > g + 60                        # its outline
    assert seen[39] < int(at(img, body).sum()) - 80  # faint: well below the character's body
    for k in range(40, 70):                          # the hint goes: so does the faint pose
        r.draw(s, Frame(seq=k, t=1.0 + k / 30, characters=(rest,)))
    assert abs(edge_on(s, where) - g) <= 12


def test_a_hinted_pose_goes_at_once_when_its_action_drives_the_character():
    """Once the action is recognised the character itself acts: the hinted pose, frozen where
    it was last suspected, is not left beside it (a grey copy of the salamander's tail)."""
    r = Renderer(TABLE, SIZE)
    s = pygame.Surface(SIZE)
    hinted = stick(0.2, valid=False, hints=(("wave", 0.9, 0.4),),
                   hint_points=np.array([[0.2, 0.6], [0.3, 0.6], [0.4, 0.6]]))
    acting = stick(0.2, valid=True, action="wave")
    where = r.map.point(0.35, 0.6)       # on the hinted pose, far from the character itself
    g = ground(r, where)
    for k in range(20):                  # a third of a second suspected, at 60 Hz
        r.draw(s, Frame(seq=k, t=1.0 + k / 60, characters=(hinted,)))
    assert edge_on(s, where) > g + 60
    seen = []
    for k in range(20, 30):              # recognised: it acts
        r.draw(s, Frame(seq=k, t=1.0 + k / 60, characters=(acting,)))
        seen.append(edge_on(s, where) - g)
    # measured: gone 7 frames after (at 9: 0 above the table's light); fading as slowly as it
    # comes (0.15 s), 79 above it at 9 frames and gone after 29
    assert seen[0] > 0 and abs(seen[8]) <= 12, seen


def gecko(progress: float = 0.4, heading: float = math.pi,
          head: int = 5) -> tuple[CharacterState, HybridRig]:
    rig = HybridRig(PlanarRig(creature_skeleton()), FaceRig(FaceModel()), head)
    clip = hybrid_clips()["walk_talk"]
    pts = place(rig.pose(clip, progress), 0.6, 0.4, heading, 0.25)
    return CharacterState("gecko", 0.6, 0.4, heading, kind="hybrid", size=0.25,
                          color=(200, 140, 230), points=pts, bones=rig.bones), rig


@pytest.mark.parametrize("heading", [0.0, math.pi / 2, -2.5])
def test_a_hybrids_face_has_its_mouth_at_the_snout_and_its_eyes_behind(heading):
    """Seen from above, a creature's mouth is at its snout: the face rides on the nose (the
    example's point) with its eye whites behind the face's middle, toward the neck."""
    c, rig = gecko(0.0, heading, head=HYBRID_HEAD)
    k = len(rig.body.rest())
    r = Renderer(TABLE, SIZE)
    s = pygame.Surface(SIZE)
    for j in range(8):
        r.draw(s, Frame(seq=j, t=j / 10, characters=(c,)))
    img = rgb(s).astype(int)
    face = r.map.points(c.points[k:])
    lo, hi = face.min(axis=0).astype(int), face.max(axis=0).astype(int)
    box = img[lo[1]:hi[1], lo[0]:hi[0]]
    ys, xs = np.nonzero(np.all(box > 200, axis=2))             # the eye whites
    assert len(xs) > 5
    eyes = np.array([xs.mean() + lo[0], ys.mean() + lo[1]])
    snout = np.subtract(r.map.point(c.x + 0.1 * math.cos(heading), c.y + 0.1 * math.sin(heading)),
                        r.map.point(c.x, c.y))
    forward = snout / np.linalg.norm(snout)
    ahead = float((eyes - face.mean(axis=0)) @ forward)       # px, + toward the snout
    # measured: 5.2-5.4 px ahead with the face upright along the heading, -8.8 to -9.0 turned
    assert ahead < -3.0


def test_a_hybrid_is_its_body_with_its_face_on_the_head():
    c, rig = gecko()
    n_body = len(rig.body.rest())
    k, body_bones, face_bones = hybrid_parts(len(c.points), c.bones)
    assert k == n_body and body_bones == tuple(rig.body.bones)
    assert face_bones == tuple(rig.face.bones)
    r = Renderer(TABLE, SIZE)
    s = pygame.Surface(SIZE)
    for j in range(8):
        r.draw(s, Frame(seq=j, t=j / 10, characters=(c,)))
    img = rgb(s)
    face = r.map.points(c.points[k:])
    lo, hi = face.min(axis=0).astype(int), face.max(axis=0).astype(int)
    box = img[lo[1]:hi[1], lo[0]:hi[0]]
    white = np.all(box > 225, axis=2).sum()      # the face's eye whites
    dark = np.all(box < 60, axis=2).sum()        # pupils, mouth, brows
    body = (box[..., 0] > 120) & (box[..., 2] > 150)
    assert white > 10 and dark > 10 and body.mean() > 0.3   # a filled face, not strokes


@pytest.mark.parametrize("config, expected", [("config.yaml", "puck"),
                                              ("examples/mop.yaml", "puck"),
                                              ("examples/touch_pose.yaml", "touch")])
def test_the_idle_invitation_fits_the_configuration(config, expected):
    cfg = load_config(ROOT / config)
    assert invitation(cfg["engines"]) == INVITATIONS[expected]
    assert "puck" not in invitation([{"kind": "touch_pose"}])
    assert invitation([{"kind": "mop", "performers": [
        {"inputs": [{"kind": "stream"}]}]}]) == INVITATIONS["stream"]
    assert invitation([{"kind": "fault"}]) == ""


def test_the_idle_look_shows_the_invitation_it_is_given():
    def idle_text(words: str) -> np.ndarray:
        r = Renderer(TABLE, SIZE)
        r.invitation = words
        s = pygame.Surface(SIZE)
        # ends at 9.8 s, where the invitation breathes brightest; drawn every 0.3 s (the last
        # image is the one a frame every 0.1 s makes, to the pixel, with and without words)
        for k in (*range(0, 98, 3), 98):
            r.draw(s, Frame(seq=k, t=k * 0.1))
        assert r.idle == 1.0
        return rgb(s)
    a, b = idle_text(INVITATIONS["touch"]), idle_text("")
    lower = (slice(SIZE[1] // 2 + 100, SIZE[1] - 60), slice(300, SIZE[0] - 300))
    diff = np.abs(a[lower] - b[lower]).sum(axis=2)
    assert (diff > 60).sum() > 200                 # the words, where the invitation stands


WINDOW_SCRIPT = """
import os
from tabletop.config import validate_config
from tabletop.view import ProjectorView
cfg = validate_config({"sources": [{"kind": "scripted"}], "view": {"size": [320, 200]}})
view = ProjectorView((1.2, 0.8), cfg["view"])
import pygame
pygame.display.flip()
print(pygame.display.get_driver(), os.environ.get("SDL_FRAMEBUFFER_ACCELERATION"))
view.close()
"""


@pytest.mark.skipif(shutil.which("xvfb-run") is None, reason="needs xvfb-run (a virtual X display)")
@pytest.mark.parametrize("operator, expected", [(None, "0"), ("1", "1")])
def test_an_x11_window_presents_straight_unless_the_operator_says_otherwise(operator, expected):
    env = {k: v for k, v in os.environ.items()
           if k not in ("SDL_VIDEODRIVER", "SDL_FRAMEBUFFER_ACCELERATION")}
    if operator is not None:
        env["SDL_FRAMEBUFFER_ACCELERATION"] = operator
    r = subprocess.run(["xvfb-run", "-a", sys.executable, "-c", WINDOW_SCRIPT],
                       capture_output=True, text=True, env=env, cwd=ROOT, timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split()[-2:] == ["x11", expected]


def test_the_example_characters_never_overlap_on_the_table():
    """examples/mop.yaml's bird flapped its wings over the dancer's head (an Xvfb snapshot):
    every character's footprint, over its rest pose and every action's poses, stays clear of
    the others' by a limb's width and inside the table."""
    from behaviors.motion.skeleton import place
    from tabletop.plugins.mop import MotionLoader
    from tabletop.plugins.mop_rigs import make_rig, motion_kind
    cfg = load_config(ROOT / "examples" / "mop.yaml")
    boxes = {}
    for c in cfg["engines"][0]["characters"]:
        rig = make_rig(c)
        load = MotionLoader(motion_kind(c), ROOT / "examples", rig)
        clips = [load(a["motion"]) for a in c["actions"]]
        poses = [rig.rest()] + [rig.pose(clip, float(q)) for clip in clips
                                for q in np.linspace(0, 1, 21)]
        pts = np.concatenate([place(q, *c["at"], c["heading"], c["size"]) for q in poses])
        boxes[c["name"]] = (pts.min(axis=0) - 0.015, pts.max(axis=0) + 0.015)   # a limb's width
    for name, (lo, hi) in boxes.items():
        assert (lo > 0).all() and (hi < (1.2, 0.8)).all(), (name, lo, hi)
    names = sorted(boxes)
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            (alo, ahi), (blo, bhi) = boxes[a], boxes[b]
            assert (ahi < blo).any() or (bhi < alo).any(), (a, b, boxes[a], boxes[b])


def mime(face: str, progress: float = 0.5) -> tuple[CharacterState, int]:
    """A hybrid humanoid (the example's mime) walking, its face playing ``face``'s expression,
    at 0.26 m tall, upright on the table; and its number of body points."""
    from behaviors.motion.deepmimic import load_motion, motion_path
    from behaviors.mop.creatures import face_clips, merge_clips
    from tabletop.plugins.mop_rigs import make_rig
    rig = make_rig({"kind": "hybrid", "body": "humanoid", "skeleton": None,
                    "view_yaw": math.pi / 2, "elevation": 0.25, "travel": False})
    clip = merge_clips(face, load_motion(motion_path("walk")), face_clips()[face])
    pts = place(rig.pose(clip, progress), 0.6, 0.25, math.pi / 2, 0.26)
    return CharacterState("mime", 0.6, 0.25, math.pi / 2, kind="hybrid", size=0.26,
                          color=(250, 200, 160), points=pts, bones=rig.bones), len(rig.body.rest())


def test_a_humanoids_face_is_drawn_on_its_body_and_plays_its_expression():
    """MOP section 3's humanoid with a face: the face is drawn as a face on the body's neck
    (its eye whites above it), and the same body with another expression changes the face's
    pixels alone."""
    from tabletop.plugins.mop_rigs import HUMANOID_NECK

    def drawn(face: str) -> tuple[np.ndarray, CharacterState, int, Renderer]:
        c, k = mime(face)
        r = Renderer(TABLE, SIZE)
        s = pygame.Surface(SIZE)
        for j in range(8):
            r.draw(s, Frame(seq=j, t=j / 10, characters=(c,)))
        return rgb(s).astype(int), c, k, r
    talk, c, k, r = drawn("talk")
    surprise = drawn("surprise")[0]
    face = r.map.points(c.points[k:])
    lo, hi = face.min(axis=0).astype(int), face.max(axis=0).astype(int)
    box = (slice(lo[1], hi[1]), slice(lo[0], hi[0]))
    whites = (talk[box].min(axis=2) > 200) & (np.ptp(talk[box], axis=2) < 12)
    ys, xs = np.nonzero(whites)
    eyes = np.array([xs.mean(), ys.mean()]) + lo
    neck = r.map.points(c.points[HUMANOID_NECK:HUMANOID_NECK + 1])[0]
    h, cx = hi[1] - lo[1], int(face[:, 0].min() + face[:, 0].max()) // 2
    middle = talk[lo[1] + h // 10:hi[1] - h // 10, cx - 3:cx + 4]   # down the face's middle:
    ink = np.nonzero(middle.sum(axis=2) < 150)[0].mean() + lo[1] + h // 10   # nose and mouth
    changed = np.abs(talk - surprise).sum(axis=2) > 60
    body = r.map.points(c.points[:k])
    # the body under the face (a surprised jaw drops 0.08 of the face past its chin)
    below = slice(int(hi[1] + 0.25 * (hi[1] - lo[1])), int(body[:, 1].max()))
    # measured: 32 px of eye whites in the face (68 px tall), 32 px above the neck and 1.4 px
    # beside it, the nose and mouth 16 px under them (23 px above them with the face turned
    # half round on the crown, as the gecko's); 372 px of the face change with its expression
    # (the dropped chin 9 more, under it), none of the body under that
    assert whites.sum() > 10
    assert 20 < neck[1] - eyes[1] < 45 and abs(eyes[0] - neck[0]) < 6
    assert ink - eyes[1] > 8.0                  # upright on the neck: the mouth under the eyes
    assert changed[box].sum() > 150
    assert not changed[below].any()

"""The projector view, rendered offscreen: halos around pucks, characters where and how their
state says, anti-aliased bodies, fades, dirty rectangles (the "one moment" and idle looks:
test_view_screens.py)."""

import dataclasses
import math

import numpy as np
import pygame
import pytest

from tabletop.drawing import primitives as P
from tabletop.drawing.palette import PUCK_COASTING, PUCK_SEEN
from tabletop.frames import CharacterState, Frame, Puck
from tabletop.view import Renderer, TableToScreen

TABLE = (1.2, 0.8)
SIZE = (1280, 720)


pytestmark = pytest.mark.usefixtures("pygame_display")


def new_renderer(**kw):
    return Renderer(TABLE, SIZE, margin=24, puck_radius=0.03, **kw)


def settled(renderer, frame, seconds=1.0, steps=6):
    """Draw ``frame`` repeatedly over ``seconds`` (so fades finish); returns the last image as
    an (H, W, 3) int array."""
    surface = pygame.Surface(SIZE)
    for k in range(steps + 1):
        f = Frame(seq=k, t=frame.t + seconds * k / steps, pucks=frame.pucks,
                  characters=frame.characters, health=frame.health, touches=frame.touches)
        renderer.draw(surface, f)
    return rgb(surface)


def rgb(surface):
    """The surface's pixels as an (H, W, 3) int array (C order). Read through pixels3d, whose
    rows are the surface's own: array3d's copy, transposed and widened, came out in column
    order (46 -> 12 ms at 1280x720, every later whole-image operation on it faster too)."""
    return pygame.surfarray.pixels3d(surface).transpose(1, 0, 2).astype(int)


def at(img, xy):
    return img[int(round(xy[1])), int(round(xy[0]))]


def brightness(img, xy):
    return int(at(img, xy).sum())


def ground(renderer, xy):
    """Brightness of the bare table at ``xy`` (pixels)."""
    return brightness(rgb(renderer._background(pygame.Surface(SIZE))), xy)


def test_table_fit_puts_origin_bottom_left_and_y_up():
    m = TableToScreen(TABLE, SIZE, margin=24)
    x0, y0 = m.point(0.0, 0.0)
    x1, y1 = m.point(1.2, 0.8)
    assert x0 < x1 and y0 > y1  # x right, y up the screen
    assert min(x0, SIZE[0] - x1) >= 24 - 1e-9 and min(SIZE[1] - y0, y1) >= 24 - 1e-9
    assert (x1 - x0) / 1.2 == pytest.approx((y0 - y1) / 0.8)
    assert m.screen_angle(0.5, 0.5, math.pi / 2) == pytest.approx(-math.pi / 2)  # table +y is up


@pytest.mark.parametrize("angle", [0.0, 2.5])
def test_halo_surrounds_the_puck_and_leaves_its_centre_dark(angle):
    r = new_renderer()
    img = settled(r, Frame(seq=0, t=0.0, pucks=(Puck(3, 0.4, 0.3, angle),)))
    m = r.map
    cx, cy = m.point(0.4, 0.3)
    R = 0.03 * m.scale_at(0.4, 0.3) * 1.35 + 3.0        # the halo's radius (halo_kernel.halos)
    ring = [brightness(img, (cx + R * math.cos(a), cy + R * math.sin(a)))
            for a in np.linspace(0, 2 * math.pi, 16, endpoint=False)]
    table = ground(r, (cx, cy))
    assert min(ring) > table + 200                      # lit all the way round
    for k in (0.0, 0.3, 0.6):                           # the puck itself is not painted
        for a in (0.0, 2.0, 4.0):
            q = (cx + k * R * math.cos(a), cy + k * R * math.sin(a))
            assert brightness(img, q) < table + 40
    # the heading notch: brightest on the ring along the puck's angle
    ax = m.screen_angle(0.4, 0.3, angle)
    ahead = brightness(img, (cx + R * math.cos(ax), cy + R * math.sin(ax)))
    behind = brightness(img, (cx - R * math.cos(ax), cy - R * math.sin(ax)))
    assert ahead > behind + 60


def test_a_halo_drawn_from_the_cached_ring_is_the_freshly_rendered_one():
    """The ring is rendered once per (radius, width, colour, strength) and blitted after that:
    the cached blit leaves exactly the fresh ring's pixels, still dark at the puck's centre, and a
    coasting puck at the same place is not given the seen one's cached ring."""
    P._rings.clear()
    P._ring_calls.clear()
    frame = Frame(seq=0, t=0.0, pucks=(Puck(3, 0.4, 0.3, 1.0),))
    r = new_renderer()
    a = settled(r, frame)                               # rings rendered as the puck fades in
    rendered = len(P._rings)
    assert rendered >= 1
    b = settled(new_renderer(), frame)
    assert len(P._rings) == rendered                    # nothing rendered again: cache hits
    assert np.abs(a - b).max() == 0
    cx, cy = r.map.point(0.4, 0.3)
    R = 0.03 * r.map.scale_at(0.4, 0.3) * 1.35 + 3.0
    assert brightness(b, (cx, cy)) < ground(r, (cx, cy)) + 40
    assert min(brightness(b, (cx + R * math.cos(t), cy + R * math.sin(t)))
               for t in np.linspace(0.3, 6.0, 12)) > ground(r, (cx, cy)) + 200
    c = settled(new_renderer(), Frame(seq=0, t=0.0, pucks=(Puck(3, 0.4, 0.3, 1.0,
                                                                state="coasting"),)))
    assert len(P._rings) > rendered                     # its own ring, in its own colour
    q = (cx + R * math.cos(3.5), cy + R * math.sin(3.5))
    assert np.abs(at(c, q) - at(b, q)).max() > 30


def test_coasting_puck_is_coloured_apart_from_a_seen_one():
    out = {}
    for state in ("seen", "coasting"):
        r = new_renderer()
        img = settled(r, Frame(seq=0, t=0.0, pucks=(Puck(2, 0.6, 0.4, math.pi / 2, state=state),)))
        cx, cy = r.map.point(0.6, 0.4)
        R = 0.03 * r.map.scale_at(0.6, 0.4) * 1.35 + 3.0
        out[state] = np.mean([at(img, (cx + R * math.cos(a), cy + R * math.sin(a)))
                              for a in (0.0, 1.0, 2.0, 3.0)], axis=0)
    seen, coasting = out["seen"], out["coasting"]
    assert seen[2] > seen[0] + 30            # cold: more blue than red, like PUCK_SEEN
    assert coasting[0] > coasting[2] + 30    # warm: amber, like PUCK_COASTING
    assert PUCK_SEEN[2] > PUCK_SEEN[0] and PUCK_COASTING[0] > PUCK_COASTING[2]


def test_a_puck_that_leaves_shows_lost_then_fades_and_its_trail_follows_its_path():
    r = new_renderer()
    s = pygame.Surface(SIZE)
    for k in range(30):      # moving right at 0.3 m/s
        x = 0.3 + 0.01 * k
        r.draw(s, Frame(seq=k, t=k / 30, pucks=(Puck(1, x, 0.4, 0.0, vx=0.3),)))
    img = rgb(s)
    # behind the puck, on its path, beyond its halo: the trail
    on, off = r.map.point(0.52, 0.4), r.map.point(0.52, 0.45)
    assert brightness(img, on) > ground(r, on) + 30
    assert brightness(img, off) < ground(r, off) + 10                    # off the path: dark
    for dx in (0.0, -0.01, -0.02):                                       # the trail stops at
        c = r.map.point(0.59 + dx, 0.4)                                  # the halo: the moving
        assert brightness(img, c) < ground(r, c) + 40                    # puck stays unlit
    r.draw(s, Frame(seq=30, t=1.05))                                       # the puck is gone
    img = rgb(s)
    cx, cy = r.map.point(0.59, 0.4)
    R = 0.03 * r.map.scale_at(0.59, 0.4) * 1.35 + 3.0
    lost = np.mean([at(img, (cx + R * math.cos(a), cy + R * math.sin(a))) for a in (0, 1.5, 3)],
                   axis=0)
    assert lost[0] > lost[2] + 30                                          # red: lost
    r.draw(s, Frame(seq=31, t=3.0))
    assert brightness(rgb(s), (cx + R, cy)) < ground(r, (cx + R, cy)) + 10  # and then gone


def eye_centroids(img, box, reach):
    """Centroids (x, y) of the eye-white pixels inside ``box`` (x0, y0, x1, y1), and of the dark
    pupil pixels within ``reach`` pixels of them."""
    x0, y0, x1, y1 = box
    sub = img[y0:y1, x0:x1]
    ys, xs = np.nonzero(sub.min(axis=2) > 235)
    whites = np.array([xs.mean(), ys.mean()])
    yy, xx = np.mgrid[0:sub.shape[0], 0:sub.shape[1]]
    near = np.hypot(xx - whites[0], yy - whites[1]) < reach
    py, px = np.nonzero((sub.sum(axis=2) < 120) & near)
    return whites + (x0, y0), np.array([px.mean(), py.mean()]) + (x0, y0)


@pytest.mark.parametrize("heading", [0.0, math.pi / 2, math.pi, -2.2])
def test_reactor_drawn_where_its_state_says_facing_its_heading(heading):
    r = new_renderer()
    c = CharacterState("lover", 0.6, 0.4, heading, size=0.1, color=(240, 110, 150))
    img = settled(r, Frame(seq=0, t=0.0, characters=(c,)))
    m = r.map
    cx, cy = m.point(0.6, 0.4)
    body = at(img, m.point(0.6 - 0.02 * math.cos(heading), 0.4 - 0.02 * math.sin(heading)))
    assert body[0] > 200                                                    # filled body
    far = m.point(0.6 + 0.2, 0.4 + 0.2)
    assert brightness(img, far) < ground(r, far) + 10                      # nothing far away
    L = 0.1 * m.scale_at(0.6, 0.4)
    box = (int(cx - L), int(cy - L), int(cx + L), int(cy + L))
    whites, _ = eye_centroids(img, box, 0.2 * L)
    a = m.screen_angle(0.6, 0.4, heading)
    along = (whites - (cx, cy)) @ np.array([math.cos(a), math.sin(a)])
    assert along > 0.12 * L                                                # the eyes are in front


def test_reactor_eyes_look_at_what_it_attends_to():
    pupils = {}
    for side in (-1, 1):
        r = new_renderer()
        c = CharacterState("lover", 0.6, 0.4, math.pi / 2, size=0.12, color=(240, 110, 150),
                           look_at=(0.6 + side * 0.4, 0.4))
        img = settled(r, Frame(seq=0, t=0.0, characters=(c,)))
        cx, cy = r.map.point(0.6, 0.4)
        L = 0.12 * r.map.scale_at(0.6, 0.4)
        whites, ink = eye_centroids(img, (int(cx - L), int(cy - L), int(cx + L), int(cy + L)),
                                    0.22 * L)
        pupils[side] = ink[0] - whites[0]
    assert pupils[1] > 1.0 and pupils[-1] < -1.0   # pupils turn right, then left (screen x)


def test_bodies_have_anti_aliased_edges():
    """Across a body's edge there are pixels between the body's colour and the ground's."""
    s = pygame.Surface((200, 200))
    s.fill((0, 0, 0))
    P.polygon(s, (240, 120, 60), np.array([(30.0, 40.0), (170.0, 70.0), (90.0, 170.0)]))
    P.disc(s, (240, 120, 60), (150.3, 150.6), 20.4)
    red = rgb(s)[..., 0]
    partial = np.count_nonzero((red > 25) & (red < 215))
    assert partial > 60     # a hard-edged fill would have none


def test_figure_limbs_have_thickness_and_joints():
    r = new_renderer()
    pts = np.array([[0.5, 0.4], [0.6, 0.4], [0.7, 0.45]])
    c = CharacterState("stick", 0.6, 0.4, 0.0, kind="creature", size=0.3, points=pts,
                       bones=((0, 1), (1, 2)), color=(90, 220, 120))
    img = settled(r, Frame(seq=0, t=0.0, characters=(c,)))
    m = r.map
    for dy_px in (-3, 0, 3):      # not a one-pixel line: body colour 3 px either side of the axis
        x, y = m.point(0.55, 0.4)
        assert at(img, (x, y + dy_px))[1] > 150
    assert at(img, m.point(0.6, 0.4))[1] > 150     # the joint is covered


def test_characters_fade_in_and_out_nothing_pops():
    r = new_renderer()
    s = pygame.Surface(SIZE)
    c = CharacterState("lover", 0.6, 0.4, 0.0, size=0.1, color=(240, 110, 150))
    where = r.map.point(0.58, 0.4)
    seen = []
    for k, t in enumerate((0.0, 0.1, 0.2, 0.3, 0.6)):
        r.draw(s, Frame(seq=k, t=t, characters=(c,)))
        seen.append(brightness(rgb(s), where))
    assert seen[0] < seen[2] < seen[4]           # grows in over a few tenths of a second
    gone = []
    for k, t in enumerate((0.7, 0.85, 1.0, 1.6)):
        r.draw(s, Frame(seq=10 + k, t=t))
        gone.append(brightness(rgb(s), where))
    assert seen[4] > gone[1] > gone[3]           # fades out instead of vanishing
    assert gone[1] > ground(r, where) + 60
    assert gone[3] < ground(r, where) + 10


def test_a_played_back_take_is_drawn_as_the_mains_puck_not_a_second_reactor():
    """The studio's sequential take plays the main back as NAME.main of kind "playback", with
    the reactor's colour. It was drawn as a faint copy of the reactor: two of the character on
    the table. It is a neutral ring with a notch (the main's puck's ghost): nothing of the
    reactor's colour, its centre left bare, the ring and its "main" drawn."""
    lit = {}
    for kind in ("reactor", "playback"):
        r = new_renderer()
        c = CharacterState("pet", 0.6, 0.4, 0.0, size=0.1, color=(240, 110, 150), kind=kind)
        img = settled(r, Frame(seq=0, t=0.0, characters=(c,)))
        x, y = (int(v) for v in r.map.point(0.6, 0.4))
        patch = img[y - 60:y + 60, x - 60:x + 60]
        pink = (patch[..., 0] > patch[..., 1] + 50) & (patch[..., 0] > 120)
        lit[kind] = (int(np.count_nonzero(pink)),
                     int(np.count_nonzero(patch.sum(axis=2) - ground(r, (x, y)) > 150)),
                     brightness(img, (x, y)) - ground(r, (x, y)))
    assert lit["reactor"][0] > 500, lit                   # (the reactor is pink)
    assert lit["playback"][0] == 0, lit                   # the ghost is not
    assert lit["playback"][1] > 150, lit                  # yet drawn: ring, notch, word
    assert abs(lit["playback"][2]) < 15, lit              # its centre bare, as a puck's ring


def test_resting_character_is_calmer_but_does_not_vanish():
    r = new_renderer()
    c = CharacterState("face", 0.6, 0.4, 0.0, size=0.1, color=(120, 180, 255), valid=False)
    img = settled(r, Frame(seq=0, t=0.0, characters=(c,)))
    body = at(img, r.map.point(0.58, 0.4))
    assert body.sum() > 350 and body.sum() < 120 + 180 + 255 + 60


def channel_gaps(a: pygame.Surface, b: pygame.Surface) -> np.ndarray:
    """Each pixel's largest channel difference between two surfaces of one size (x, y): as
    ``np.abs(rgb(a) - rgb(b)).max(axis=2)``, transposed, in 16 bits and without numpy's
    reduction over an axis of 3 (which goes pixel by pixel)."""
    x, y = (pygame.surfarray.pixels3d(s).astype(np.int16) for s in (a, b))
    d = np.abs(x - y)
    return np.maximum(np.maximum(d[..., 0], d[..., 1]), d[..., 2])


def test_dirty_rectangles_give_the_same_image_as_full_redraws():
    from tabletop.scene_frames import busy_frames
    frames = busy_frames(16, rate_hz=20.0)
    full, inc = new_renderer(), new_renderer()
    inc.incremental = True
    a, b = pygame.Surface(SIZE), pygame.Surface(SIZE)
    for f in frames:
        full.draw(a, f, ["overlay"])
        inc.draw(b, f, ["overlay"])
        diff = channel_gaps(a, b)
        # No ghost of an earlier frame, no missing piece: at most a stray anti-aliased pixel.
        assert np.count_nonzero(diff) <= 8 and diff.max() <= 16, f"frame {f.seq}"
    sparse = Frame(seq=100, t=frames[-1].t + 0.05, pucks=frames[-1].pucks[:2],
                   characters=frames[-1].characters[:1])
    for k in range(30):     # the others fade out (0.6 s), the pucks that left too (1.2 s)
        sparse = Frame(seq=100 + k, t=sparse.t + 0.05, pucks=sparse.pucks,
                       characters=sparse.characters)
        full.draw(a, sparse)
        inc.draw(b, sparse)
    assert np.count_nonzero(channel_gaps(a, b)) <= 8
    area = sum(r.w * r.h for r in inc.dirty)
    assert 0 < area < 0.2 * SIZE[0] * SIZE[1]          # only what changed is presented


def test_sprite_is_drawn_rotated_to_the_heading(tmp_path):
    """A sprite facing +x, half red (front) half blue (back), turned to face +y on the table."""
    img = pygame.Surface((40, 20))
    img.fill((0, 0, 255))
    img.fill((255, 0, 0), pygame.Rect(20, 0, 20, 20))
    path = tmp_path / "bug.png"
    pygame.image.save(img, str(path))
    r = new_renderer(sprites={"bug": path})
    c = CharacterState("bug", 0.6, 0.4, math.pi / 2, size=0.1)
    out = settled(r, Frame(seq=0, t=0.0, characters=(c,)))
    front = at(out, r.map.point(0.6, 0.4 + 0.022))
    back = at(out, r.map.point(0.6, 0.4 - 0.022))
    assert front[0] > 200 and front[2] < 120
    assert back[2] > 200 and back[0] < 120


def test_broken_states_are_skipped_and_never_raise():
    nan = math.nan
    r = new_renderer()
    r.incremental = True
    s = pygame.Surface(SIZE)
    good = CharacterState("ok", 0.6, 0.4, 0.0, size=0.1, color=(240, 110, 150))
    broken = (CharacterState("a", nan, 0.3, 0.0), CharacterState("b", 0.3, 0.3, nan),
              CharacterState("c", 1e9, 0.3, 0.0), CharacterState("d", 0.3, 0.3, 0.0, size=50.0),
              CharacterState("e", 0.3, 0.3, 0.0, kind="skeleton",
                             points=np.array([[nan, 0.1], [0.2, 0.2]]), bones=((0, 1), (1, 7))),
              CharacterState("f", 0.3, 0.3, 0.0, kind="face", points=np.zeros((3, 2)),
                             bones=((0, 1), (1, 2), (2, 0))),
              CharacterState("g", 0.3, 0.3, 0.0, look_at=(nan, nan)))
    pucks = (Puck(1, nan, 0.2, 0.0), Puck(2, 0.2, 0.2, nan), Puck(3, 1e8, 0.2, 0.0))
    for k in range(12):
        r.draw(s, Frame(seq=k, t=k * 0.1, characters=broken + (good,), pucks=pucks), ["x"])
    # the good character is drawn all the same, and recovers after a broken pose
    img = rgb(s)
    assert at(img, r.map.point(0.58, 0.4))[0] > 200


def test_a_mouse_finger_is_ringed_and_a_real_one_is_not():
    """The mouse's fingers (a desk without a touch table) were drawn nowhere: a finger pinned
    with Shift + click held a part unseen, and lifting it needed a Shift + click on it. Each,
    the one held under the button too, is ringed; a touch table's finger, seen for itself, is
    not, whatever its id (a TUIO tracker's session ids pass any range after days of play)."""
    from tabletop.frames import Touch
    from tabletop.pointer import FIRST_ID, PointerFingers

    def ringed(touch: Touch, pointer: PointerFingers) -> bool:
        r = new_renderer()
        r.pointer = pointer
        img = settled(r, Frame(seq=0, t=0.0, touches=(touch,)))
        cx, cy = r.map.point(touch.x, touch.y)
        ring = max(brightness(img, (cx + dx, cy + dy)) for dx, dy in
                   ((9, 0), (-9, 0), (0, 9), (0, -9)))
        assert brightness(img, (cx, cy)) < ground(r, (cx, cy)) + 30   # the finger's spot dark
        return ring > ground(r, (cx, cy)) + 300

    held, pinned = PointerFingers(), PointerFingers()
    held.press(0.6, 0.4)
    pinned.press(0.6, 0.4, pin=True)
    (h,), (p,) = held.touches(), pinned.touches()
    assert h.id == FIRST_ID and p.id == FIRST_ID + 1
    assert ringed(h, held) and ringed(p, pinned)
    for ident in (3, FIRST_ID + 1, 123_456):      # a touch table's: the mouse holds none
        assert not ringed(Touch(ident, 0.6, 0.4), PointerFingers()), ident


@pytest.mark.parametrize("at_xy", [(1.2, 0.4), (0.6, 0.0), (0.0, 0.8), (1.25, -0.1)])
def test_a_character_on_the_tables_edge_is_drawn_whole_on_the_table(at_xy):
    """A reactor whose centre is on the table's edge (Puppet Master keeps its centre within the
    table's bounds) was drawn half into the margin, where a real table has none: its body
    stands inside the edge, all of it, and as big as in the middle of the table."""
    def body(r, img):
        pink = (img[..., 0] > 150) & (img[..., 0] > img[..., 1] + 50)
        (x0, y1), (x1, y0) = r.map.point(0.0, 0.0), r.map.point(1.2, 0.8)
        inside = np.zeros(pink.shape, bool)
        inside[int(y0):int(y1) + 1, int(x0):int(x1) + 1] = True
        return int(np.count_nonzero(pink & inside)), int(np.count_nonzero(pink & ~inside))

    r = new_renderer()
    c = CharacterState("pet", *at_xy, 0.3, size=0.12, color=(240, 110, 150))
    on, off = body(r, settled(r, Frame(seq=0, t=0.0, characters=(c,))))
    r = new_renderer()
    middle = dataclasses.replace(c, x=0.6, y=0.4)
    whole, _ = body(r, settled(r, Frame(seq=0, t=0.0, characters=(middle,))))
    assert off == 0, (on, off)
    assert on > 0.9 * whole, (on, whole)

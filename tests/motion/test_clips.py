"""Clips: interpolation by channel type, the JSON form, time alignment, clear errors."""

import json
import math

import numpy as np
import pytest

from behaviors.motion.clips import (Channel, Clip, ClipError, TimeWarp,
                                 clip_from_mapping, clip_to_mapping, quat_from_axis_angle,
                                 quat_slerp, quat_to_matrix)


def _mixed_clip() -> Clip:
    chans = [Channel("w", "scalar"), Channel("a", "angle"), Channel("q", "quat"),
             Channel("f", "frame")]
    q0 = quat_from_axis_angle([0, 0, 1], 0.0)
    q1 = quat_from_axis_angle([0, 0, 1], 2.0)
    q2 = quat_from_axis_angle([1, 0, 0], 1.0)
    values = np.array([[0.0, 3.0, *q0, 0], [1.0, -3.0, *q1, 1], [0.5, -2.0, *q2, 2]])
    return Clip("mixed", chans, [0.0, 1.0, 3.0], values)


def test_scalar_is_linear_in_progress_over_uneven_keys():
    clip = _mixed_clip()
    # key times 0, 1, 3 s: progress 1/6 is half way to the second key
    v = clip.sample(1 / 6)
    assert abs(clip.channel(v, "w")[0] - 0.5) < 1e-12
    v = clip.sample(2 / 3)  # t = 2 s, half way between keys 1 and 2
    assert abs(clip.channel(v, "w")[0] - 0.75) < 1e-12


def test_angle_takes_the_short_way_round():
    clip = _mixed_clip()
    a = clip.channel(clip.sample(1 / 6), "a")[0]
    # 3 -> -3 rad goes through pi (0.283 rad apart), not through 0
    assert abs(abs(math.remainder(a, 2 * math.pi)) - math.pi) < 1e-9


def test_quaternion_slerp_turns_at_constant_rate_and_stays_unit():
    clip = _mixed_clip()
    for k, p in enumerate(np.linspace(0.0, 1 / 3, 9)):
        q = clip.channel(clip.sample(p), "q")
        assert abs(np.linalg.norm(q) - 1.0) < 1e-12
        rot = quat_to_matrix(q)
        angle = math.atan2(rot[1, 0], rot[0, 0])
        assert abs(angle - 2.0 * k / 8) < 1e-9


def test_slerp_takes_the_shorter_hemisphere():
    q0 = quat_from_axis_angle([0, 1, 0], 0.1)
    q1 = -quat_from_axis_angle([0, 1, 0], 0.3)   # the same rotation as +q1
    mid = quat_slerp(q0, q1, 0.5)
    rot = quat_to_matrix(mid)
    assert abs(math.atan2(rot[0, 2], rot[0, 0]) - 0.2) < 1e-9


def test_frame_channel_holds_until_next_key():
    clip = _mixed_clip()
    frames = [clip.channel(clip.sample(p), "f")[0] for p in (0.0, 0.1, 0.33, 1 / 3, 0.5, 0.99, 1.0)]
    assert frames == [0, 0, 0, 1, 1, 1, 2]


def test_progress_is_clamped_and_nan_is_the_start():
    clip = _mixed_clip()
    assert np.allclose(clip.sample(-0.5), clip.sample(0.0))
    assert np.allclose(clip.sample(7.0), clip.sample(1.0))
    assert np.allclose(clip.sample(float("nan")), clip.sample(0.0))


def test_sample_many_matches_sample():
    clip = _mixed_clip()
    p = np.random.default_rng(3).uniform(0, 1, 50)
    many = clip.sample_many(p)
    for i in range(50):
        assert np.allclose(many[i], clip.sample(p[i]), atol=1e-12)


def test_json_round_trip(tmp_path):
    clip = _mixed_clip()
    path = tmp_path / "c.json"
    path.write_text(json.dumps(clip_to_mapping(clip)))
    back = clip_from_mapping(json.loads(path.read_text()), str(path))
    assert back.names == clip.names and back.loop == clip.loop
    p = np.linspace(0, 1, 31)
    assert np.allclose(back.sample_many(p), clip.sample_many(p), atol=1e-12)


def test_json_rate_instead_of_times():
    clip = clip_from_mapping({"channels": ["a", "b"], "rate": 10,
                              "values": [[0, 0], [1, 2], [2, 4]]})
    assert abs(clip.duration - 0.2) < 1e-12
    assert np.allclose(clip.sample(0.25), [0.5, 1.0])


@pytest.mark.parametrize("data, words", [
    ({"channels": ["a"], "values": [[0.0]]}, "at least 2 keyframes"),
    ({"channels": ["a"], "values": [[0.0], [float("nan")]]}, "keyframe 1"),
    # (a face's weight of 1e300 loaded, then failed the view at every frame)
    ({"channels": ["a"], "values": [[0.0], [1e300]]}, "keyframe 1 holds 1e+300; at most 1e+06"),
    ({"channels": ["a", "b"], "values": [[0.0], [1.0]]}, "2 columns"),
    ({"channels": [{"name": "a", "type": "spline"}], "values": [[0.0], [1.0]]}, "type 'spline'"),
    ({"channels": ["a"], "times": [0.0, 0.0], "values": [[0.0], [1.0]]}, "must increase"),
    ({"channels": ["a"], "times": [0.0], "values": [[0.0], [1.0]]}, "1 times but 2 rows"),
    ({"channels": ["a", "a"], "values": [[0, 0], [1, 1]]}, "appears twice"),
    ({"channels": ["a"], "values": [[0.0], [1.0]], "speed": 2}, "unknown key 'speed'"),
    ({"format": "other", "channels": ["a"], "values": [[0.0], [1.0]]}, "format"),
    ([1, 2], "JSON object"),
])
def test_bad_clips_are_named(data, words):
    with pytest.raises(ClipError) as exc:
        clip_from_mapping(data, "faces/wink.json")
    assert "faces/wink.json" in str(exc.value) and words in str(exc.value)


def test_time_warp_lines_up_key_moments():
    warp = TimeWarp([[0, 0], [0.5, 0.2], [1, 1]])
    assert abs(warp(0.5) - 0.2) < 1e-12 and abs(warp(0.75) - 0.6) < 1e-12
    assert warp(-1.0) == 0.0 and warp(2.0) == 1.0
    clip = Clip("ramp", [Channel("v")], [0.0, 1.0], [[0.0], [10.0]])
    rows = clip.sample_many(warp(np.linspace(0.0, 1.0, 3)))
    assert np.allclose(rows[:, 0], [0.0, 2.0, 10.0])
    with pytest.raises(ClipError, match="start at"):
        TimeWarp([[0.1, 0], [1, 1]])
    with pytest.raises(ClipError, match="must increase"):
        TimeWarp([[0, 0], [0.5, 0.6], [0.5, 0.7], [1, 1]])


def test_time_warp_of_one_progress_is_its_value_in_an_array():
    # a float (a puppet's tick) takes a path of its own: the same values to the bit, a float
    warp = TimeWarp([[0, 0], [0.3, 0.5], [0.7, 0.6], [1, 1]])
    ps = [-0.5, -0.0, 0.0, 0.3, 0.31, 0.7, 0.999, 1.0, 1.5, math.inf, -math.inf, math.nan]
    many = warp(np.array(ps))
    for p, want in zip(ps, many):
        for got in (warp(p), warp(np.float64(p))):
            assert type(got) is float and got == want, (p, got, want)


def test_resampled_keeps_the_motion():
    clip = _mixed_clip()
    r = clip.resampled(301)
    p = np.linspace(0, 1, 97)
    err = np.abs(r.sample_many(p) - clip.sample_many(p))
    w = clip.slices["w"]
    assert err[:, w].max() < 0.01
    with pytest.raises(ClipError):
        clip.resampled(1)


def test_a_rigs_columns_sampled_alone_are_the_whole_samples():
    clip = _mixed_clip()
    slots, _ = clip.driven(("x", "w", "q"), 0.5)
    assert slots.tolist() == [1, 2]                      # w and q (a quat: the whole sample)
    slots, _ = clip.driven(("f", "w"), 0.5)
    assert slots.tolist() == [0, 1]                      # f: a frame
    slots, _ = clip.driven(("w", "nothing"), 0.5)
    assert slots.tolist() == [0]                         # w alone: interpolated by itself
    for p in [*np.linspace(-0.1, 1.1, 53), math.nan]:
        for names in (("w",), ("a", "w"), ("q", "f", "w"), ("x", "w", "q")):
            slots, values = clip.driven(names, p)
            cols = [clip.slices[names[i]].start for i in slots]
            assert np.array_equal(values, clip.sample(p)[cols])

"""The learned models kept on disk: same output as learned ones, rebuilt when the file is bad."""

import numpy as np

from behaviors.touch_pose.engine import TouchPose
from behaviors.touch_pose.models import PREFIX, input_key, load, load_or_build, save


def _session(models, view=(90.0, 15.0)):
    """Output rotations and roots of a character whose hand is dragged in a circle (3 s)."""
    e = TouchPose(azimuth=view[0], elevation=view[1], physics=True, models=models)
    hand = np.array(e.describe()["parts"]["right_hand"])
    out = []
    for k in range(90):
        a = 2 * np.pi * k / 45
        e.step(k / 30, {1: tuple(hand + 0.03 * np.array([np.cos(a) - 1, np.sin(a)]))})
        out.append(np.concatenate([e.output.root, e.output.rots.ravel()]))
    e.close()
    return np.array(out)


def test_cached_models_give_identical_output(models, tmp_path):
    save(models, tmp_path / "m.npz", "k")
    cached = load(models.body, tmp_path / "m.npz", "k")
    assert cached is not None
    assert load(models.body, tmp_path / "m.npz", "other inputs") is None
    assert np.array_equal(cached.posing.latent, models.posing.latent)
    assert [a.name for a in cached.actions] == [a.name for a in models.actions]
    assert np.array_equal(_session(cached), _session(models))


def test_a_corrupt_cache_file_is_refused(models, tmp_path):
    path = tmp_path / "m.npz"
    save(models, path, "k")
    data = path.read_bytes()
    for bad in (data[: len(data) // 2], b"not a cache", data[:100] + b"\0" * 50 + data[150:], b""):
        path.write_bytes(bad)
        assert load(models.body, path, "k") is None
    save(models, path, "k")
    with np.load(path, allow_pickle=False) as stored:
        arrays = dict(stored)
    assert load(models.body, path, "k") is not None
    arrays["posing_latent"][3, 0] = np.nan  # a readable file holding a non-finite number
    np.savez(path, **arrays)
    assert load(models.body, path, "k") is None
    del arrays["posing_latent"]  # or lacking an array
    np.savez(path, **arrays)
    assert load(models.body, path, "k") is None


def test_a_corrupt_cache_file_is_learned_again(models, tmp_path):
    key = input_key()
    save(models, tmp_path / f"{PREFIX}{key[:32]}.npz", key)
    (tmp_path / f"{PREFIX}stale.npz").write_bytes(b"models of other inputs")
    assert load_or_build(tmp_path)[1] == "cache"
    files = list(tmp_path.glob(f"{PREFIX}*{key[:32]}.npz"))
    assert len(files) == 1
    data = files[0].read_bytes()
    files[0].write_bytes(data[: len(data) // 3])
    again, how = load_or_build(tmp_path)
    assert how == "built"
    assert load_or_build(tmp_path)[1] == "cache"  # rewritten whole
    assert [f.name for f in tmp_path.glob(f"{PREFIX}*.npz")] == [files[0].name]  # stale removed
    assert np.array_equal(_session(again), _session(models))
    assert list(tmp_path.glob("*.tmp")) == []

"""A motion-capture stream read relative to its root (``relative_to``): a body stream in world
coordinates followed wherever its performer walks (MOP's paper, 3.1.1)."""

import numpy as np

from tabletop.plugins.mop_table import G, RATE, Table, build

#: Where the performer stands while recording (metres, world), and how far the walked
#: performance moves sideways while it is performed.
ROOT = np.array([1.0, 0.4])
WALK_M = 0.5


def _hand(name: str) -> tuple[np.ndarray, np.ndarray]:
    """Times (s) and the hand's path relative to the root (metres) of gesture ``name``."""
    g = G.gesture(name)
    return g[:, 0], g[:, 1:3] + [0.0, 0.3]


def _config(tmp_path, relative: bool) -> dict:
    for name in ("circle", "wave"):
        t, hand = _hand(name)
        cols = hand if relative else hand + ROOT     # recorded in place, as the input reads it
        np.savetxt(tmp_path / f"{name}.csv", np.column_stack([t, cols]), delimiter=",",
                   header="t,body_2-0,body_3-1" if relative else "t,body_2,body_3", comments="")
    stream = {"kind": "stream", "name": "body", "columns": [2, 3]}
    if relative:
        stream["relative_to"] = [0, 1]
    return {"sources": [{"kind": "scripted"}], "engines": [{
        "kind": "mop", "rate_hz": 30,
        "performers": [{"name": "body", "inputs": [stream]}],
        "characters": [{"name": "face", "kind": "face", "performer": "body", "actions": [
            {"name": "circle", "template": "circle.csv", "motion": "laugh"},
            {"name": "wave", "template": "wave.csv", "motion": "angry"}]}]}]}


def _followed(engine, name: str, walk: float) -> float:
    """The share of the second half of gesture ``name`` during which it drives the character,
    performed with the root walking ``walk`` metres along x meanwhile (stream: root x, y, hand
    x, y in world metres)."""
    t, hand = _hand(name)
    table = Table(engine)
    table.streams = {"body": np.r_[ROOT, ROOT + hand[0]]}
    table.rest(1.0)
    seen = []
    for k in range(int(t[-1] * RATE)):
        tau = k / RATE
        u = tau / t[-1]
        root = ROOT + [walk * u, 0.0]
        h = np.array([np.interp(tau, t, hand[:, 0]), np.interp(tau, t, hand[:, 1])])
        table.streams = {"body": np.r_[root, root + h]}
        c = table.tick()["face"]
        if u >= 0.5:
            seen.append(c.valid and c.action == name)
    return float(np.mean(seen))


def test_a_body_stream_read_relative_to_its_root_follows_a_walked_performance(tmp_path):
    relative = build(_config(tmp_path, True), tmp_path)
    world = build(_config(tmp_path, False), tmp_path)
    assert relative.performers["body"].names == ("body_2-0", "body_3-1")
    assert world.performers["body"].names == ("body_2", "body_3")
    for name in ("circle", "wave"):
        in_place = _followed(relative, name, 0.0)
        walked = _followed(relative, name, WALK_M)
        assert in_place >= 0.9 and walked >= 0.9, (name, in_place, walked)
        # the same stream read as recorded: in place followed, walked not
        assert _followed(world, name, 0.0) >= 0.9, name
        assert _followed(world, name, WALK_M) <= 0.2, name


def test_relative_to_columns_must_divide_the_chosen_columns(tmp_path):
    import pytest
    from tabletop.schema import ConfigError
    data = _config(tmp_path, True)
    data["engines"][0]["performers"][0]["inputs"][0]["relative_to"] = [0, 1, 4]
    with pytest.raises(ConfigError, match=r"performers\[0\]\.inputs\[0\]\.relative_to: 3 column"):
        build(data, tmp_path)
    data["engines"][0]["performers"][0]["inputs"][0] = {"kind": "puck", "id": 1,
                                                       "relative_to": [0, 1]}
    with pytest.raises(ConfigError, match=r"inputs\[0\]\.relative_to: only a stream input"):
        build(data, tmp_path)


def test_relative_to_columns_may_not_be_chosen_too_or_repeated(tmp_path):
    """A chosen column less itself reads 0 at every sample; a repeated root column subtracts
    one coordinate from the other: both refused at start-up, naming the key."""
    import pytest
    from tabletop.schema import ConfigError
    data = _config(tmp_path, True)
    stream = data["engines"][0]["performers"][0]["inputs"][0]
    for columns, rel, why in (([0, 1, 2, 3], [0, 1], r"column\(s\) \[0, 1\] are chosen"),
                              ([2, 3], [0, 0], r"\[0, 0\] repeats a column")):
        stream.update(columns=columns, relative_to=rel)
        with pytest.raises(ConfigError, match=r"performers\[0\]\.inputs\[0\]\.relative_to: "
                           + why) as err:
            build(data, tmp_path)
        assert "\n" not in str(err.value)


def test_a_template_recorded_without_relative_to_is_refused_by_its_column_names(tmp_path):
    """Recorded in world coordinates (columns body_2, body_3), a template would load for the
    relative features and never match: the feature names differ, so it is refused."""
    import pytest
    from tabletop.schema import ConfigError
    _config(tmp_path, False)                      # circle.csv, wave.csv in world coordinates
    data = _config(tmp_path, True)
    _config(tmp_path, False)
    with pytest.raises(ConfigError, match=r"actions\[0\]\.template: .*circle\.csv: template "
                       r"columns body_2,body_3 do not match the performer's features "
                       r"body_2-0,body_3-1"):
        build(data, tmp_path)

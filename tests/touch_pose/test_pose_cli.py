"""``tabletop pose``: describe, a recorded session replayed causally and reproducibly, bad
inputs."""

import json

import numpy as np
import pytest

from tabletop.cli import main


def _write(path, rows, header="t,id,x,y"):
    path.write_text(header + "\n" + "".join(",".join(str(v) for v in r) + "\n" for r in rows))
    return path


def test_describe_lists_the_actions_with_their_trajectories(tmp_path, capsys):
    out = tmp_path / "d.json"
    assert main(["pose", "--describe", "--view", "90,15", "--out", str(out)]) == 0
    d = json.loads(out.read_text())
    assert d["height_m"] == pytest.approx(0.3)
    assert {"head", "pelvis", "left_hand", "right_hand", "left_foot", "right_foot"} \
        <= set(d["parts"])
    names = {a["name"]: a for a in d["actions"]}
    assert {"punch", "kick", "jump", "spinkick", "wave", "bow"} <= set(names)
    for a in d["actions"]:
        traj = np.array(a["trajectory"])
        assert traj.shape[1] == 2 and len(traj) >= 10
        assert np.allclose(traj[0], d["parts"][a["part"]], atol=1e-4)  # starts at the part
        assert a["duration_s"] > 0.5 and 0.2 < a["stroke_s"] < a["duration_s"]
    assert names["punch"]["part"] == "right_hand" and names["punch"]["excluded"] is False
    # the character stands at the centre of the table, height_m tall
    ys = [p[1] for p in d["parts"].values()]
    assert max(ys) - min(ys) == pytest.approx(0.3, rel=0.25)
    assert main(["pose", "--describe", "--view", "0,15"]) == 0
    front = json.loads(capsys.readouterr().out)
    assert {a["name"]: a for a in front["actions"]}["punch"]["excluded"] is True


def test_a_recorded_session_is_replayed_causally_and_reproducibly(tmp_path):
    d_path = tmp_path / "d.json"
    main(["pose", "--describe", "--view", "90,15", "--out", str(d_path)])
    d = json.loads(d_path.read_text())
    hand = np.array(d["parts"]["right_hand"])
    rows = [(round(k / 20, 3), 4, *np.round(hand + [0.0, 0.002 * k], 5)) for k in range(20)]
    rows += [(1.0, 4, *np.round(hand + [0.0, 0.04], 5)), (1.0, 5, 0.05, 0.05)]
    touches = _write(tmp_path / "touches.csv", rows)
    a, b = tmp_path / "a.jsonl", tmp_path / "b.jsonl"
    assert main(["pose", "--input", str(touches), "--out", str(a), "--view", "90,15"]) == 0
    assert main(["pose", "--input", str(touches), "--out", str(b), "--view", "90,15"]) == 0
    assert a.read_text() == b.read_text()
    recs = [json.loads(line) for line in a.read_text().splitlines()]
    assert len(recs) == 91  # 0 .. 1 s + 2 s at 30 Hz
    assert recs[0]["touches"] == {"4": "right_hand"}
    assert recs[30]["touches"] == {"4": "right_hand", "5": None}
    assert recs[-1]["touches"] == {}
    for r in recs:
        assert r["mode"] in ("posing", "action") and len(r["joints"]) >= 13
        assert all(np.isfinite(v).all() for v in r["joints"].values())
    # causal: a prefix of the input gives the same records up to its end
    short = _write(tmp_path / "short.csv", rows[:10])
    c = tmp_path / "c.jsonl"
    assert main(["pose", "--input", str(short), "--out", str(c), "--view", "90,15"]) == 0
    first = [json.loads(line) for line in c.read_text().splitlines()]
    n = int(rows[9][0] * 30) + 1
    assert first[:n] == recs[:n]


@pytest.mark.parametrize("content, args, needle", [
    ("t,id,x\n0,1,0.5\n", [], "missing column(s) y"),
    ("t,id,x,y\n0.5,1,0.5,0.4\n0.2,1,0.5,0.4\n", [], "goes back"),
    ("t,id,x,y\n0,1,nan,0.4\n", [], "not a finite number"),
    ("t,id,x,y\n0,1,0.5,0.4\n0.1,1,1e200,0.4\n", [], "line 3: column 'x': 1e+200 m is beyond"),
    ("t,id,x,y\n0,1,0.5,0.4\n", ["--view", "front"], "--view"),
    ("t,id,x,y\n0,1,0.5,0.4\n", ["--view", "0,95"], "elevation"),
    ("t,id,x,y\n0,1.5,0.5,0.4\n", [], "whole number"),
    # beyond 2**53 a float does not hold every whole number: 99999999999999999999 was read as 1e20
    ("t,id,x,y\n0,99999999999999999999,0.5,0.4\n", [],
     "line 2: id 1e+20 must be a whole number from 0 to 9007199254740991"),
    ("t,id,x,y\n0,9007199254740993,0.5,0.4\n0,9007199254740992,0.6,0.4\n", [],
     "line 2: id 9.0072e+15 must be a whole number from 0 to 9007199254740991"),
    ("t,id,x,y\n0,1,0.5,0.4\n", ["--rate", "-3"], "--rate"),
])
def test_bad_inputs_give_one_clear_line(tmp_path, capsys, content, args, needle):
    f = tmp_path / "t.csv"
    f.write_text(content)
    out = tmp_path / "o.jsonl"
    assert main(["pose", "--input", str(f), "--out", str(out), *args]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and needle in err and "Traceback" not in err
    assert not out.exists()


def test_a_recorded_quick_punch_is_replayed_as_a_punch(tmp_path, models):
    """Dragged along --describe's trajectory over its stroke_s (the stroke's own pace); over
    duration_s, the only time --describe gave, the drag was too slow to start the punch."""
    d_path = tmp_path / "d.json"
    main(["pose", "--describe", "--view", "270,20", "--out", str(d_path)])
    punch = next(a for a in json.loads(d_path.read_text())["actions"] if a["name"] == "punch")
    traj = np.array(punch["trajectory"])
    times = np.linspace(0.0, punch["stroke_s"], len(traj))
    ts = np.arange(0.0, times[-1], 1 / 60)  # a 60 Hz touch recording
    rows = [(round(t, 5), 2, round(float(np.interp(t, times, traj[:, 0])), 5),
             round(float(np.interp(t, times, traj[:, 1])), 5)) for t in ts]
    touches = _write(tmp_path / "punch.csv", rows)
    out = tmp_path / "p.jsonl"
    assert main(["pose", "--input", str(touches), "--out", str(out), "--view", "270,20"]) == 0
    recs = [json.loads(line) for line in out.read_text().splitlines()]
    acts = [r for r in recs if r["mode"] == "action"]
    assert acts and {r["action"] for r in acts} == {"punch"}
    assert all(r["action_time"] is not None for r in acts)
    assert recs[-1]["mode"] == "posing"  # finished after the finger lifted, back to posing


def test_the_output_lines_as_a_process_writes_them(tmp_path, models, models_cache,
                                                   monkeypatch):
    """As outside scripts call it (a process): one line per step at ``--rate`` from the first
    input time to the last + 2 s on the input's own time base, every contract key with its
    type (``action`` and ``action_time`` null while posing), the six named parts as [x, y]
    table metres around the character standing at the centre of the default 1.2 x 0.8 table,
    joints as [x, y, z], touches keyed by the finger id as a string. The process uses the
    session's learned models: it read (and on a cold machine filled) the user's cache."""
    import os
    import subprocess
    import sys
    user = tmp_path / "user_cache"       # the user's cache, as their environment names it
    monkeypatch.setenv("XDG_CACHE_HOME", str(user))
    touches = _write(tmp_path / "touches.csv", [(5.0, 1, 0.05, 0.05), (5.5, 1, 0.06, 0.05)])
    out = tmp_path / "poses.jsonl"
    r = subprocess.run([sys.executable, "-m", "tabletop", "pose", "--input", str(touches),
                        "--out", str(out), "--rate", "10"], capture_output=True, text=True,
                       timeout=120, env={**os.environ, "XDG_CACHE_HOME": str(models_cache)})
    assert r.returncode == 0 and r.stdout == "" and r.stderr == "", r.stderr
    assert not user.exists() and list((models_cache / "tabletop").glob("*.npz"))
    recs = [json.loads(line) for line in out.read_text().splitlines()]
    assert [x["t"] for x in recs] == pytest.approx([5.0 + k / 10 for k in range(26)], abs=1e-9)
    for x in recs:
        assert list(x) == ["t", "mode", "action", "action_time", "parts", "joints", "touches"]
        assert x["mode"] == "posing" and x["action"] is None and x["action_time"] is None
        assert {"head", "pelvis", "left_hand", "right_hand", "left_foot",
                "right_foot"} <= set(x["parts"])
        assert all(len(v) == 2 for v in x["parts"].values())
        assert all(len(v) == 3 for v in x["joints"].values())
    assert recs[0]["touches"] == {"1": None} and recs[-1]["touches"] == {}   # off the body
    parts = np.array(list(recs[0]["parts"].values()))
    centre = (parts.min(axis=0) + parts.max(axis=0)) / 2
    assert centre == pytest.approx((0.6, 0.4), abs=0.03)
    assert parts[:, 1].max() - parts[:, 1].min() == pytest.approx(0.3, rel=0.25)


def test_touches_in_millimetres_or_milliseconds_are_warned_of(tmp_path, capsys):
    """Millimetres given for metres put every finger off the table (the character only
    stands) and milliseconds for seconds make a 20 s recording 600,000 steps: each said in one
    warning line; the poses are still written. Table metres and seconds: no word."""
    out = tmp_path / "o.jsonl"
    mm = _write(tmp_path / "mm.csv", [(0, 1, 600, 400), (33, 1, 0.61, 0.4), (66, 1, 620, 400)])
    assert main(["pose", "--input", str(mm), "--out", str(out), "--rate", "1"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 2 and "mm.csv: 2 of 3 touches lie off the 1.2 x 0.8 m table (the first " \
        "at 600, 400)" in err[0] and "frames are 33 s apart (median)" in err[1], err
    assert len(out.read_text().splitlines()) == 69
    long = _write(tmp_path / "long.csv", [(i * 100.0, 1, 0.6, 0.4) for i in range(400)])
    assert main(["pose", "--input", str(long), "--out", str(out)]) == 2   # 39,900 s at 30 Hz
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "steps are made; its frames are 100 s apart (median); times are " \
        "seconds (milliseconds given?)" in err[0], err
    ok = _write(tmp_path / "ok.csv", [(0, 1, 0.6, 0.4), (0.1, 1, 0.62, 0.4), (0.2, 1, 1.2, 0.8)])
    assert main(["pose", "--input", str(ok), "--out", str(out), "--rate", "1"]) == 0
    assert capsys.readouterr().err == ""

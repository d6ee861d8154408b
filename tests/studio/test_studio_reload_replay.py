"""A hot reload recorded and replayed: ``tabletop replay`` plays a reload from the frame it
played from live, a bad one's labels too; a replayed reload that fails to train or whose record
is unreadable or refused says so in one line naming its engine, the frame's others reloaded."""

from behaviors.puppet_master import designers
from behaviors.puppet_master.engine import Behavior
from tabletop import library
from tabletop.frames import Frame


def _record_and_replay(tmp_path, edit) -> tuple[list[dict], list[dict]]:
    """A 90-frame recorded session of a hot-reloading engine whose folder ``edit(folder)``
    changes at frame 30, and its ``tabletop replay``: (live frames, replayed frames)."""
    import json

    from tabletop.cli import main as cli
    from tabletop.config import validate_config
    from tabletop.kiosk.runner import Runner
    from tabletop.kiosk.simulate import SimClock
    from tabletop.studio.reloader import BehaviorReloader
    folder = library.save_behavior(tmp_path / "lib", "x",
                                   designers.demonstrate("lover", seconds=4), {})
    cfg = validate_config({
        "loop": {"rate_hz": 30}, "sources": [{"kind": "scripted", "pucks": [1]}],
        "engines": [{"kind": "puppet_master", "name": "pet", "behavior": "lib/x",
                     "main": {"puck": 1}}], "view": {"enabled": False}},
        str(tmp_path / "c.yaml"), tmp_path)
    clock, live = SimClock(), tmp_path / "live.jsonl"
    runner = Runner(tmp_path / "c.yaml", cfg, headless=True, kiosk=False, studio=False,
                    record_path=live, clock=clock)
    inst = runner._build(cfg)
    (hook,) = [f for f in inst.loop.filters if isinstance(f, BehaviorReloader)]
    hook.poller.every_s = 0.0
    inst.loop.inputs.open()
    for i in range(90):
        if i == 30:
            edit(folder)
        if hook.loading:
            hook.worker.wait()        # (played from the next tick, whenever the worker is done)
        inst.loop.tick()
        clock.advance(1 / 30)
    inst.loop.close()
    out = tmp_path / "replayed.jsonl"
    assert cli(["replay", str(live), "--fast", "--no-view", "--out", str(out)]) == 0
    a, b = ([json.loads(x) for x in p.read_text().splitlines()[1:]] for p in (live, out))
    assert len(a) == len(b) == 90
    return a, b


def test_a_recorded_session_with_a_hot_reload_replays_exactly(tmp_path):
    """The reload happens on the wall clock; the frame it plays from carries what it trained
    from, so ``tabletop replay`` plays it from the same frame, to the last digit."""
    a, b = _record_and_replay(tmp_path, lambda folder: library.save_behavior(
        folder.parent, "x", designers.demonstrate("stalker", seconds=5), {}, replace=True))
    assert sum("behaviors" in f.get("consumed", {}).get("reload", {}) for f in a) == 1
    assert [fa["seq"] for fa, fb in zip(a, b) if fa["characters"] != fb["characters"]] == []


def test_a_recorded_session_with_a_bad_hot_reload_replays_its_labels(tmp_path):
    """A reload that fails says so in the character's label from the frame it fails in; the
    recording carries the note, so the replayed labels say it from the same frame."""
    a, b = _record_and_replay(
        tmp_path, lambda folder: (folder / "behavior.yaml").write_text("format: [\n"))
    labels = [[c.get("label") for c in f["characters"]] for f in a]
    assert any("bad file" in str(x) for x in labels[-1]), labels[-1]
    assert sum("notes" in f.get("consumed", {}).get("reload", {}) for f in a) == 1
    assert [fa["seq"] for fa, fb in zip(a, b) if fa["characters"] != fb["characters"]] == []


def two_engines(tmp_path):
    """Puppet Master engines "a" and "b" playing one saved behaviour "x", and the recorded
    reload of "x" (:func:`tabletop.studio.reloader.load_and_train`'s source)."""
    from tabletop.config import validate_config
    from tabletop.plugins import puppet_master as pm
    from tabletop.registry import BuildContext
    from tabletop.studio.reloader import load_and_train
    folder = library.save_behavior(tmp_path, "x", designers.demonstrate("lover", seconds=4), {})
    cfg = validate_config({"sources": [{"kind": "scripted"}], "engines": [
        {"kind": "puppet_master", "name": n, "behavior": str(folder)} for n in ("a", "b")]},
        "t.yaml", tmp_path)
    ctx = BuildContext((1.2, 0.8), 60.0, cfg, tmp_path)
    a, b = (pm.build(c, ctx) for c in cfg["engines"])
    return a, b, load_and_train(folder, a.rate_hz, a.table)[2]


def test_a_replayed_reload_that_fails_to_train_leaves_the_frames_other_reloads(
        tmp_path, monkeypatch, caplog):
    from tabletop.studio.reloader import RecordedReloads
    a, b, source = two_engines(tmp_path)
    first_a, first_b = a.behavior, b.behavior
    real = Behavior.train.__func__
    seen: list[int] = []

    def train(cls, *args, **kwargs):      # the first training fails as no bad file would
        seen.append(1)
        if len(seen) == 1:
            raise RuntimeError("out of memory")
        return real(cls, *args, **kwargs)

    monkeypatch.setattr(Behavior, "train", classmethod(train))
    a.note = b.note = "bad file, still playing the previous behaviour: x"
    frame = Frame(seq=0, t=1.0, consumed={"reload": {"behaviors": {"a": source, "b": source}}})
    assert RecordedReloads([a, b])(frame) is frame
    assert a.behavior is first_a and a.note                   # a plays on, its note kept
    assert b.behavior is not first_b and b.note == ""          # b reloaded all the same
    assert caplog.text.count("out of memory") == 1 and "for a" in caplog.text


def _replay_lines(caplog) -> list[str]:
    """The replay's log lines (starting "replay:"); exactly one is expected."""
    said = [r.getMessage() for r in caplog.records if r.getMessage().startswith("replay:")]
    assert len(said) == 1, said
    return said


def test_a_replayed_reload_whose_record_is_unreadable_names_its_engine_and_leaves_the_others(
        tmp_path, caplog):
    """A bad record and a failed training are logged alike: one line naming the behaviour,
    the engine and why; the frame's other engines reload all the same."""
    from tabletop.studio.reloader import RecordedReloads
    a, b, source = two_engines(tmp_path)
    first_a, first_b = a.behavior, b.behavior
    bad = {k: v for k, v in source.items() if k != "demonstration"}
    frame = Frame(seq=0, t=1.0, consumed={"reload": {"behaviors": {"a": bad, "b": source}}})
    assert RecordedReloads([a, b])(frame) is frame
    assert a.behavior is first_a and b.behavior is not first_b
    said = _replay_lines(caplog)
    assert "recorded reload of x for a not trained" in said[0], said
    assert "KeyError" in said[0] and "demonstration" in said[0], said


def _refused(tmp_path, caplog, change) -> str:
    """Replay a frame reloading engine "a" from ``change(source)`` of a recorded reload; "a"
    plays on with its behaviour. The replay's one log line about it."""
    from tabletop.studio.reloader import RecordedReloads
    a, b, source = two_engines(tmp_path)
    first_a = a.behavior
    frame = Frame(seq=0, t=1.0, consumed={"reload": {"behaviors": {"a": change(source)}}})
    assert RecordedReloads([a, b])(frame) is frame
    assert a.behavior is first_a
    return _replay_lines(caplog)[0]


def test_a_replayed_reload_refused_by_training_says_why_not_unreadable(tmp_path, caplog):
    """A readable record whose demonstration training refuses (too short) is logged with
    training's own reason, not as an unreadable record."""
    import base64

    import numpy as np

    def short(source):
        rows = np.frombuffer(base64.b64decode(source["demonstration"]), "<f8").reshape(
            source["shape"])[:3]
        return dict(source, shape=list(rows.shape),
                    demonstration=base64.b64encode(rows.tobytes()).decode("ascii"))

    said = _refused(tmp_path, caplog, short)
    assert "for a not trained: demonstration lasts" in said, said
    assert "unreadable" not in said, said


def test_a_replayed_reload_naming_an_unknown_parameter_says_which(tmp_path, caplog):
    """A recorded reload whose parameters hold ``demo`` (the name of training's own argument)
    is refused by training's parameter check: one line naming the parameter, the behaviour in
    play goes on."""
    said = _refused(tmp_path, caplog, lambda source: dict(
        source, parameters={**source["parameters"], "demo": 1}))
    assert "for a not trained: unknown behaviour parameter(s) demo;" in said, said
    assert "TypeError" not in said, said

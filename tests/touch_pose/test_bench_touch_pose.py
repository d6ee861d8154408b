"""bench/touch_pose.py, the measure of DESIGN.md's per-frame budget, runs on the engine as it is
(it drives the control stages through the engine's own methods, whose signatures change)."""

import json
import sys

from bench import touch_pose as bench


def test_the_budget_bench_runs_its_stages_and_prints_its_figures(models, monkeypatch, capsys):
    monkeypatch.setattr(bench, "ROUNDS", 2)
    monkeypatch.setattr(bench, "build_models", lambda: models)   # learned once per session
    monkeypatch.setattr(sys, "argv", ["bench/touch_pose.py"])
    bench.main()
    last = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    figures = last["figures"]
    assert last["bench"] == "touch_pose"
    for stage in ("posing_3_touches", "action_control", "tracking_physics",
                  "frame_posing_3_touches", "frame_action"):
        assert figures[f"{stage}_cpu_p99_ms"] > 0.0
    assert figures["physics_resets"] == 0

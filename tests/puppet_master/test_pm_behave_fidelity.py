"""``tabletop behave --fidelity``: a designer's own demonstration's fidelity table on the unseen
main paths (the figures of bench/fidelity.py, --param applied), the scripted designer's
reference only where there is one, and wrong use refused with one line and status 2."""

import pytest

from behaviors.puppet_master import fidelity, visitors
from behaviors.puppet_master.engine import Behavior
from tabletop import examples
from tabletop.commands import behave_fidelity
from tabletop.files import write_csv
from tests.puppet_master import demos as pm_demos
from tests.puppet_master.behave_cli import DEMO_HEADER, SHIPPED, behave

PATHS = ("slow_pauses_30hz", "fast_reversals_60hz", "loops_spins_45hz")
COLUMNS = [k for k, _ in examples.FIDELITY_COLUMNS]


def table_of(out: str) -> dict[str, dict]:
    """{row name: {"figures": [floats], "misses": [names]}} of the printed fidelity table."""
    rows = {}
    for line in out.splitlines():
        words = line.split()
        if words and words[0] in ("demonstration", *PATHS, visitors.PURSUIT) \
                and line.startswith("  "):
            n = len(COLUMNS) + (0 if words[0] == "demonstration" else 3)
            rows[words[0]] = {"figures": [float(w) for w in words[1:1 + n]],
                              "misses": words[1 + n:2 + n]}
    return rows


def test_a_shipped_folder_prints_the_benchs_table_with_its_designer(capsys):
    assert behave("--train", SHIPPED / "lover", "--fidelity") == 0
    out = capsys.readouterr().out
    rows = table_of(out)
    assert set(rows) == {"demonstration", *PATHS}
    # the same figures as python -m tabletop.examples --check at 20 s (seed 0)
    bench = examples.fidelity_table(SHIPPED, ["lover"], seconds=20.0, seed=0)["lover"]
    for path in PATHS:
        got = dict(zip(COLUMNS, rows[path]["figures"]))
        for k in COLUMNS:
            assert got[k] == pytest.approx(bench[path][f"gen_{k}"], abs=6e-4, nan_ok=True), k
    # the lover's measured figures on seeds 0-3 (12 paths): facing 0.993-1.0 (demonstration
    # 1.0), distance W1 0.005-0.039 m, texture 0.371-0.422 rad (0.397), saturation 0.010-0.043
    for path in PATHS:
        got = dict(zip(COLUMNS, rows[path]["figures"]))
        assert got["facing"] >= 0.95 and got["saturation"] <= 0.1
        assert 0.33 <= got["texture_rad"] <= 0.46 and rows[path]["figures"][-3] <= 0.06
    assert "the scripted designer's own lover on the same paths" in out
    assert "(the engine's):" in out and "thresholds met" in out


def test_pursuit_adds_the_benchs_row_against_a_pursuing_visitor(capsys):
    assert behave("--train", SHIPPED / "afraid", "--fidelity", "--pursuit") == 0
    out = capsys.readouterr().out
    rows = table_of(out)
    assert set(rows) == {"demonstration", *PATHS, visitors.PURSUIT}
    bench = examples.pursuit_table(SHIPPED, ["afraid"], seconds=20.0, seed=0)["afraid"]
    got = dict(zip(COLUMNS, rows[visitors.PURSUIT]["figures"]))
    for k in COLUMNS:
        assert got[k] == pytest.approx(bench[visitors.PURSUIT][f"gen_{k}"], abs=6e-4,
                                       nan_ok=True), k
    # chased, the afraid keeps away (seed 0 at 20 / 40 s: mean 0.354 / 0.281 m, contact 0,
    # against its demonstration's 0.366 m)
    assert 0.2 <= got["distance_mean_m"] <= 0.45 and got["contact"] <= 0.02
    assert "of 32 thresholds met" in out and f"{visitors.PURSUIT}: " in out


def test_an_own_demonstration_with_param_has_no_designer_columns(tmp_path, capsys):
    demo = pm_demos.follow_behind(pm_demos.main_path(41, 30))
    write_csv(tmp_path / "mine.csv", DEMO_HEADER, demo.tolist())
    assert behave("--train", tmp_path / "mine.csv", "--fidelity", "--seconds", "8", "--seed",
                  "3", "--param", "window=20", "--pursuit") == 0
    out = capsys.readouterr().out
    rows = table_of(out)
    assert set(rows) == {"demonstration", *PATHS, visitors.PURSUIT}
    assert "designer" not in out and "engine's" not in out
    assert "8 s each, seed 3" in out and "of 32 thresholds met" in out
    # --param applied: the figures are those of the behaviour trained with window=20, on the
    # demonstration's area (the paths and the pursuing visitor drawn on it)
    behavior = Behavior.train(demo, window=20)
    table = tuple(float(v) for v in behavior.bounds)
    assert table[0] > 0.0 and table[1] > 0.0        # the visitor's moves shifted onto it
    want = behave_fidelity.fidelity_rows(behavior, behave_fidelity.unseen_paths(3, 8.0, table),
                                         table, (3, 8.0))
    for path in (*PATHS, visitors.PURSUIT):
        got = dict(zip(COLUMNS, rows[path]["figures"]))
        assert got["distance_mean_m"] == pytest.approx(want[path]["gen_distance_mean_m"],
                                                       abs=6e-4)
        assert rows[path]["misses"] == [",".join(fidelity.failures(want[path])) or "-"]
    # a follower 0.3 m behind keeps its distance (seeds 0, 1, 3 with window=20: mean
    # 0.305-0.336 m against the demonstration's 0.328, distance W1 0.008-0.023 m), never in
    # contact
    for path in PATHS:
        got = dict(zip(COLUMNS, rows[path]["figures"]))
        assert 0.25 <= got["distance_mean_m"] <= 0.4 and rows[path]["figures"][-3] <= 0.05
        assert got["contact"] == 0.0


@pytest.mark.parametrize("args, said", [
    (["--fidelity"], "give either --train"),
    (["--train", "LOVER", "--fidelity", "--seconds", "0"], "--seconds '0' must be"),
    (["--train", "LOVER", "--fidelity", "--seconds", "nan"], "--seconds 'nan' must be"),
    (["--train", "LOVER", "--fidelity", "--seconds", "ten"], "is not a number"),
    (["--train", "LOVER", "--fidelity", "--seed", "-1"], "--seed '-1' must be"),
    (["--train", "LOVER", "--fidelity", "--input", "m.csv"], "give it without --input"),
    (["--train", "LOVER", "--fidelity", "--out", "r.csv"], "give it without --out"),
    (["--train", "LOVER", "--seconds", "5"], "--seconds goes with --fidelity"),
    (["--train", "LOVER", "--pursuit", "--input", "m.csv"], "--pursuit goes with --fidelity"),
    (["--train", "LOVER"], "required: --input, --out (or --fidelity"),
    (["--train", "LOVER", "--fidelity", "--param", "ratio=-3"], "--param"),
    (["--train", "LOVER", "--fidelity", "--table", "0.4,0.8"], "need 0.5 m a side"),
])
def test_wrong_use_is_one_line_and_status_2(args, said, capsys):
    args = [str(SHIPPED / "lover") if a == "LOVER" else a for a in args]
    assert behave(*args) == 2
    cap = capsys.readouterr()
    assert cap.out == "" and said in cap.err and len(cap.err.strip().splitlines()) == 1

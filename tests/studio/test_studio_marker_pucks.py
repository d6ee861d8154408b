"""An engine bound to a studio control marker's puck is refused at load, naming its key and
the marker's role: the studio takes control markers out of the frame, so the character never
saw its puck and setting it down stopped or kept a take."""

from pathlib import Path

import pytest

from tabletop.cli import main as tabletop

BULLY = Path(__file__).resolve().parents[2] / "behaviors" / "library" / "bully"
MOP = ("  - kind: mop\n    performers: [{name: p, inputs: [{kind: puck, id: 1, features: "
       "[dx, dy]}, {kind: puck, id: 47, features: [dx, dy]}]}]\n    characters: [{name: c, "
       "kind: creature, performer: p, actions: [{name: a, template: two.csv, motion: walk}]}]\n")


def pm(main: str) -> str:
    return f"  - {{kind: puppet_master, name: bully, behavior: {BULLY}, main: {main}}}\n"


@pytest.mark.parametrize("engines, key, words", [
    (pm("{puck: 46}"), "engines[0].main.puck", "puck 46 is the studio's control marker "
     "studio.markers.stop"),
    (pm("{first: [{character: c}, {puck: 48}]}")
     + MOP.replace("id: 47", "id: 2").replace("two.csv", "two_2.csv"),
     "engines[0].main.first[1].puck", "puck 48 is the studio's control marker "
     "studio.markers.redo"),
    (pm("{nearest: [{puck: 1}, {puck: 45}]}"), "engines[0].main.nearest[1].puck",
     "puck 45 is the studio's control marker studio.markers.record"),
    (pm("{puck: 1}") + MOP, "engines[1].performers[0].inputs[1].id",
     "puck 47 is the studio's control marker studio.markers.keep"),
])
def test_an_engine_bound_to_a_control_marker(tmp_path, capfd, engines, key, words):
    code, err = run(tmp_path, capfd, "engines:\n" + engines)
    assert code == 2 and f"kiosk.yaml: {key}: {words}" in err


def test_a_control_marker_mapped_onto_an_engine_puck(tmp_path, capfd):
    # marker 49 read as puck 3: the "next" marker would move the character instead
    code, err = run(tmp_path, capfd, "engines:\n" + pm("{puck: 3}")
                    + "tracking: {puck_ids: {'49': 3}}\n")
    assert code == 2 and ("kiosk.yaml: engines[0].main.puck: puck 3 is marker 49 "
                          "(tracking.puck_ids.49), the studio's control marker "
                          "studio.markers.next") in err


@pytest.mark.parametrize("puck_ids, words", [
    ("{'10': 46}", "tracking.puck_ids.10: marker 10 would arrive as puck 46, the studio's "
     "control marker studio.markers.stop"),     # marker 10 set down would stop every take
    ("{'46': 3}", "tracking.puck_ids.46: marker 46 is the studio's control marker "
     "studio.markers.stop; as puck 3"),         # the stop marker, never seen by the studio
])
def test_a_puck_map_onto_or_off_a_control_marker(tmp_path, capfd, puck_ids, words):
    code, err = run(tmp_path, capfd, "engines:\n" + pm("{puck: 1}")
                    + f"tracking: {{puck_ids: {puck_ids}}}\n")
    assert code == 2 and f"kiosk.yaml: {words}" in err
    code, err = run(tmp_path, capfd, "engines:\n" + pm("{puck: 1}")
                    + f"tracking: {{puck_ids: {puck_ids}}}\nstudio: {{markers: {{stop: null}}}}\n")
    assert code == 0, err                       # with no stop marker, both maps are harmless


def test_a_control_marker_set_aside_frees_its_puck(tmp_path, capfd):
    # studio.markers.stop: null: puck 46 is no control marker and may be a main
    code, err = run(tmp_path, capfd, "engines:\n" + pm("{puck: 46}")
                    + "studio: {markers: {stop: null}}\n")
    assert code == 0, err


def run(tmp_path: Path, capfd, text: str) -> tuple[int, str]:
    for name, puck in (("two", 47), ("two_2", 2)):
        (tmp_path / f"{name}.csv").write_text(f"t,puck1_dx,puck1_dy,puck{puck}_dx,puck{puck}_dy"
                                              "\n0,0,0,0,0\n1,0.1,0,0,0.1\n")
    cfg = tmp_path / "kiosk.yaml"
    cfg.write_text("sources: [{kind: scripted, pucks: [1, 2]}]\nview: {enabled: false}\n" + text)
    code = tabletop(["run", "--config", str(cfg), "--seconds", "0.2", "--headless"])
    err = capfd.readouterr().err
    assert "Traceback" not in err
    return code, err

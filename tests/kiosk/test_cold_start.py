"""What a start loads: the kiosk supervisor validates the config and starts the installation
without loading the engines' compiled kernels (it loaded Puppet Master's, seconds of a boot on a
busy machine, then held them for weeks); a studio without Puppet Master engines never loads
them. Seen in ``python -X importtime``'s list of the modules a real process imported."""

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
HEAVY = ("numba", "behaviors.puppet_master.engine", "behaviors.puppet_master.step_kernel")


def imported(args: list[str]) -> tuple[set[str], subprocess.CompletedProcess]:
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    p = subprocess.run([sys.executable, "-X", "importtime", *args], cwd=ROOT, env=env,
                       capture_output=True, text=True, timeout=300)
    names = {line.rsplit("|", 1)[1].strip() for line in p.stderr.splitlines()
             if line.startswith("import time:") and line.count("|") == 2}
    return names, p


def test_the_supervisor_loads_no_compiled_kernels(tmp_path):
    blocker = tmp_path / "blocked"
    blocker.write_text("a file where the log folder should be: the supervisor stops there")
    cfg = tmp_path / "config.yaml"
    cfg.write_text("sources: [{kind: scripted, name: s, pucks: [1]}]\nview: {enabled: false}\n"
                   "engines: [{kind: puppet_master, name: lover, main: {puck: 1}, behavior: "
                   f"{ROOT / 'behaviors' / 'library' / 'lover'}}}]\n"
                   f"kiosk: {{log_file: {blocker / 'logs' / 'k.log'}, "
                   "heartbeat: {enabled: false}}\n")
    names, p = imported(["-m", "tabletop", "run", "--config", str(cfg), "--kiosk"])
    assert p.returncode == 2 and "kiosk.log_file" in p.stderr   # stopped in the supervisor
    assert "tabletop.kiosk.supervisor" in names  # and the engine validated:
    assert "tabletop.plugins.puppet_master_mains" in names   # (importlib's own: not listed)
    assert not names & set(HEAVY), sorted(names & set(HEAVY))    # all three before


def test_a_studio_without_puppet_master_engines_never_loads_them():
    names, p = imported(["-c", "import tabletop.kiosk.runner, tabletop.studio.build"])
    assert p.returncode == 0, p.stderr[-2000:]
    assert "tabletop.studio.targets" in names
    assert not any(n.startswith("behaviors.puppet_master.") and n != "behaviors.puppet_master."
                   "sequential" for n in names), sorted(n for n in names if "puppet" in n)

"""Compiled kernels load when an engine that calls them is built: not when their modules are
imported (``tabletop`` commands, a kiosk's restart), and not on the engine's first step; and
loading them imports neither SciPy nor OpenCV where the installation has no use for them."""

from __future__ import annotations

from pathlib import Path

from tests.children import python_json

ROOT = Path(__file__).resolve().parents[2]

IMPORTED = """
import json
import tabletop.cli, tabletop.plugins.puppet_master, tabletop.plugins.mop
from behaviors import kernel_cache
from behaviors.mop import follower, group, group_steps, sharing, window_kernel
from behaviors.puppet_master import engine, search_kernel, step_kernel, step_math
kernels = (step_kernel.step, step_kernel.moved_on, step_math.hypot, search_kernel.situation_push,
           window_kernel.step_windows, group_steps.map_inputs, sharing._shared_until)
print(json.dumps({"pending": len(kernel_cache.PENDING),
                  "loaded": [k.__name__ for k in kernels if k.signatures]}))
"""

STEPPED = """
import json
import numpy as np
from behaviors import kernel_cache
from behaviors.mop.follower import ActionFollower
from behaviors.mop.group import FollowerGroup
from behaviors.puppet_master.behavior import Behavior
from behaviors.puppet_master.engine import Reactor
from tabletop import library
stored = library.load_behavior("behaviors/library/lover")
reactor = Reactor(Behavior.train(stored.demonstration, **stored.parameters), (0, 0, 1.2, 0.8))
line = np.c_[np.linspace(0, 0.3, 30), np.zeros(30)]
arc = np.c_[np.linspace(0, 0.3, 30), np.sin(np.linspace(0, 3, 30)) * 0.1]
followers = [ActionFollower({"line": line}), ActionFollower({"arc": arc})]
grouped = FollowerGroup([ActionFollower({"line": line}), ActionFollower({"arc": arc})])
built = set(kernel_cache.PENDING)
reactor.start(0.0, 0.3, 0.3, 0.0)
for i in range(1, 90):
    reactor.update(i / 60, 0.3 + 0.004 * i, 0.3, 0.0)
    for f in followers:
        f.step(np.array([0.01 * i, 0.0]))
    grouped.step([np.array([0.01 * i, 0.0]), np.array([0.01 * i, 0.002 * i])])
print(json.dumps({"built": len(built), "stepped": len(kernel_cache.PENDING),
                  "loaded": sorted(k.__name__ for k in built - set(kernel_cache.PENDING))}))
"""


RUN_SCRIPTED = """
import json, os, sys
import llvmlite.binding as ll
import numpy as np
from tabletop import cli
parse, parsed = ll.parse_bitcode, []
ll.parse_bitcode = lambda b: parsed.append(len(b)) or parse(b)
from behaviors import kernel_cache, numba_start
nrt_kept = {p for p in os.listdir(kernel_cache.SHARED) if p.startswith("nrt-")}
code = cli.main(["run", "--config", sys.argv[1], "--headless", "--seconds", "0.3"])
from numba.core.registry import cpu_target
from numba.core.runtime import rtsys
nrt = os.path.basename(numba_start.runtime_file(cpu_target.target_context))
nrt = [nrt in nrt_kept, "_unparsed" in rtsys.library.__dict__, os.path.exists(
    numba_start.runtime_file(cpu_target.target_context))]
imported = sorted({m.split(".")[0] for m in sys.modules} & {"scipy", "cv2"})
from behaviors.puppet_master import search_kernel
loaded = bool(search_kernel.situation_reset.signatures)
helpers = sorted(m for m in ("numba.np.arrayobj", "numba.np.npyimpl", "numba.np.arraymath",
                             "numba.misc.quicksort") if m in sys.modules)
studio = "tabletop.studio.build" in sys.modules
supervisor = "tabletop.kiosk.supervisor" in sys.modules
refreshed = "numba.np.polynomial.polynomial_core" in sys.modules   # a registry only
in_run = len(parsed)
import numba
from behaviors.puppet_master.search_kernel import least
@numba.njit
def dot(a, b):
    return np.dot(a, b)
@numba.njit
def least_twice(x):                  # links the loaded kernel in: its bitcode parsed then
    return 2.0 * least(x, 0, x.size)
x = np.array([0.9, 0.3, 0.7, 0.2, 0.6])
print(json.dumps({"code": code, "imported": imported, "loaded": loaded, "refreshed": refreshed,
                  "helpers": helpers, "studio": studio, "supervisor": supervisor, "nrt": nrt,
                  "dot": dot(np.ones(3), np.arange(3.0)), "parsed_in_run": in_run,
                  "linked": [least_twice(x), 2.0 * least.py_func(x, 0, x.size),
                             len(parsed) > in_run]}))
"""


def test_importing_the_engines_and_the_cli_loads_no_kernel():
    found = python_json(IMPORTED)
    assert found["loaded"] == []
    # (92 kernels are declared with a signature: 43 of the Puppet Master, 49 of MOP)
    assert found["pending"] >= 80


def test_an_engine_built_loads_the_kernels_its_steps_call_none_on_the_steps():
    found = python_json(STEPPED)
    assert found["loaded"] == []
    # what the steps' own kernels call is in their code: most of them never load
    assert found["stepped"] == found["built"] >= 50


def test_a_run_without_a_camera_imports_neither_scipy_nor_opencv(tmp_path):
    """A run with the Puppet Master and the view, its pucks scripted: its kernels loaded (numba's
    array functions in), yet neither SciPy, which numba imported only to look at (0.3 of the
    run's 1.5 CPU s start; behaviors/numba_start.py), nor OpenCV, imported to check the default
    marker dictionary (0.06 s). A kernel calling np.dot still compiles after (numba imports
    SciPy's BLAS then). Nor were numba's registries refreshed for those loads (0.2 CPU s a
    start: behaviors/numba_start.quick_loads), nor the LLVM bitcode stored with their machine
    code parsed (0.11-0.17 CPU s: numba_start._unparsed_links), nor numba's array helpers
    imported to unpickle the environments stored with it (0.15 CPU s:
    numba_start._environments_unimported); the kernel compiled after refreshes them, and one
    calling a loaded kernel parses that kernel's bitcode to link it. The studio's modules are
    not imported either (0.03 CPU s: tabletop/kiosk/runner.py), and numba's runtime functions
    are loaded from the kernel cache, not compiled (0.03 CPU s: numba_start._runtime)."""
    cfg = tmp_path / "scripted.yaml"
    cfg.write_text(f"""sources: [{{kind: scripted, pucks: [1, 2]}}]
engines:
  - {{kind: puppet_master, name: lover, behavior: {ROOT}/behaviors/library/lover,
     main: {{puck: 1}}}}
view: {{size: [320, 180]}}
""")
    found = python_json(RUN_SCRIPTED, str(cfg))
    assert found["code"] == 0 and found["loaded"]
    assert found["imported"] == []
    assert found["refreshed"] is False
    assert found["helpers"] == [], "numba's array helpers imported to unpickle environments"
    assert found["studio"] is False, "the studio's modules imported by a run without it"
    assert found["supervisor"] is False, "the kiosk supervisor's module imported by a run"
    kept, loaded, saved = found["nrt"]
    assert saved and loaded == kept, "NRT's machine code saved to the kernel cache, loaded there"
    assert found["dot"] == 3.0
    assert found["parsed_in_run"] == 0
    twice, python, parsed = found["linked"]
    assert twice == python and parsed


def test_the_numba_whose_internals_are_changed_is_the_one_pinned():
    """behaviors/numba_start.py changes numba's internals (its cache loads) and refuses to start
    with another numba than the one it names: that one is pyproject.toml's pin, installed."""
    from importlib.metadata import version

    from behaviors import numba_start
    assert f'"numba=={numba_start.NUMBA}"' in (ROOT / "pyproject.toml").read_text()
    assert version("numba") == numba_start.NUMBA

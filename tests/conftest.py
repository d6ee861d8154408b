"""Test-wide settings: SDL runs on its dummy driver (no display here) and quiet; under
pytest-xdist the longest test files start first, shared between the workers."""

import os

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
os.environ.setdefault("SDL_AUDIODRIVER", "dummy")
os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")

# The longest test files, seconds of one worker (measured with `pytest -n 2 --durations=0` on a
# busy machine: relative weights only). A file missing here is simply not moved.
LONG_FILES = {
    "tests/mop/test_follower.py": 178, "tests/mop/test_live.py": 109,
    "tests/kiosk/test_soak.py": 100, "tests/tabletop/test_replay_exact.py": 60,
    "tests/puppet_master/test_pm_behaviors.py": 51, "tests/tabletop/test_cli.py": 48,
    "tests/mop/test_plugin.py": 46, "tests/puppet_master/test_pm_fidelity.py": 42,
    "tests/mop/test_hmm.py": 34, "tests/tabletop/test_fuzz.py": 33,
    "tests/kiosk/test_supervisor.py": 31, "tests/puppet_master/test_library.py": 27,
}


def halves_long_first(items: list, weights: dict[str, float]) -> list:
    """``items`` reordered as two halves of equal count, each starting with its share of the
    long files (heaviest first, each to the lighter half, a file's tests kept together and in
    order), then the other tests in their order. xdist's ``worksteal`` hands each of two
    workers one half, and a worker that runs out takes the tail of the other's queue: the long
    tests run first, side by side, and the short ones even out the end."""
    files: dict[str, list] = {}
    for item in items:
        files.setdefault(item.nodeid.split("::")[0], []).append(item)
    heads: list[list] = [[], []]
    load = [0.0, 0.0]
    for name in sorted((f for f in files if f in weights), key=lambda f: -weights[f]):
        side = 0 if load[0] <= load[1] else 1
        heads[side] += files[name]
        load[side] += weights[name]
    rest = [item for item in items if item.nodeid.split("::")[0] not in weights]
    half = len(items) // 2
    if len(heads[0]) > half or len(heads[1]) > len(items) - half:
        return heads[0] + heads[1] + rest
    fill = half - len(heads[0])
    return heads[0] + rest[:fill] + heads[1] + rest[fill:]


def pytest_collection_modifyitems(config, items):
    # in a worker (whose own --dist is "no"), when the run was started with worksteal
    argv = getattr(config, "workerinput", {}).get("mainargv", [])
    if any(a == "worksteal" or a.endswith("=worksteal") for a in argv):
        items[:] = halves_long_first(items, LONG_FILES)

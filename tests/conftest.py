"""Test-wide settings: SDL runs on its dummy driver (no display here) and quiet; under
pytest-xdist the longest test files start first, shared between the workers."""

import os
import sys

import pytest

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
os.environ.setdefault("SDL_AUDIODRIVER", "dummy")
os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")



@pytest.fixture(scope="module")
def pygame_display():
    """pygame's display and font modules initialised for a test module (on SDL's dummy driver
    unless the test names another), shut down after it."""
    import pygame
    pygame.display.init()
    pygame.font.init()
    yield
    pygame.display.quit()


@pytest.fixture
def unprivileged() -> tuple[str, ...]:
    """The prefix that runs a command without root's override of file permissions (none when
    not root), so that a folder or file the test made read-only is one; skips the test where
    it cannot."""
    import shutil
    if os.geteuid() != 0:
        return ()
    if shutil.which("setpriv") is None:
        pytest.skip("root, and no setpriv to start a process without write override")
    return ("setpriv", "--bounding-set", "-dac_override,-dac_read_search",
            "--inh-caps", "-dac_override,-dac_read_search")


# The longest test files: CPU seconds of the whole file (its tests' processes included),
# measured with `pytest -n 2` on a busy machine, so relative weights only. A file missing here
# is simply not moved.
LONG_FILES = {
    "tests/mop/test_quality.py": 17, "tests/kiosk/test_supervisor.py": 9,
    "tests/kiosk/test_supervisor_stop.py": 7,
    "tests/tabletop/test_cli.py": 11, "tests/mop/test_refusal.py": 10,
    "tests/puppet_master/test_pm_fidelity.py": 8, "tests/tabletop/test_replay_exact.py": 8,
    "tests/mop/test_resume.py": 7.5, "tests/kiosk/test_soak.py": 5,
    "tests/kiosk/test_bad_action_start.py": 7.3, "tests/mop/test_spotting.py": 7.2,
    "tests/kiosk/test_live_config.py": 6.6, "tests/puppet_master/test_pm_character_reading.py": 5.9,
    "tests/mop/test_live.py": 5.4, "tests/mop/test_follower.py": 5.4,
    "tests/tabletop/test_view_reading.py": 5.4, "tests/mop/test_group.py": 5.2,
}


def chunk_sizes(total: int, parts: int) -> list[int]:
    """How many tests xdist's ``worksteal`` first hands each of ``parts`` workers: the queue
    cut in order, each worker ``remaining // workers left``."""
    sizes = []
    for i in range(parts):
        sizes.append((total - sum(sizes)) // (parts - i))
    return sizes


def parts_long_first(items: list, weights: dict[str, float], parts: int = 2) -> list:
    """``items`` reordered as ``parts`` consecutive chunks of xdist's sizes, each starting with
    its share of the long files (heaviest first, each to the lightest chunk, a file's tests kept
    together and in order), then the other tests in their order. ``worksteal`` hands each worker
    one chunk, and a worker that runs out takes the tail of another's queue: the long tests run
    first, side by side, and the short ones even out the end."""
    files: dict[str, list] = {}
    for item in items:
        files.setdefault(item.nodeid.split("::")[0], []).append(item)
    heads: list[list] = [[] for _ in range(parts)]
    load = [0.0] * parts
    for name in sorted((f for f in files if f in weights), key=lambda f: -weights[f]):
        side = load.index(min(load))
        heads[side] += files[name]
        load[side] += weights[name]
    rest = [item for item in items if item.nodeid.split("::")[0] not in weights]
    sizes = chunk_sizes(len(items), parts)
    if any(len(h) > n for h, n in zip(heads, sizes)):
        return [item for h in heads for item in h] + rest
    out: list = []
    for head, n in zip(heads, sizes):
        fill = n - len(head)
        out += head + rest[:fill]
        rest = rest[fill:]
    return out + rest


class _LocalConstantsWhereUsed:
    """Hypothesis' plugin reads the literals of every project module imported so far (its
    "local constants", for its strategies) as each process ends its collection: every xdist
    worker collects test_fuzz.py, so all four did (a collection 6.5-6.8 -> 5.1-5.7 CPU s where
    ``.hypothesis/constants`` is cold: a fresh clone), though only a worker that runs a
    ``@given`` test uses them. Left to that worker's first example, where Hypothesis reads
    them anyway with the modules imported since: the same constants, the same search."""

    @pytest.hookimpl(hookwrapper=True)
    def pytest_collection_modifyitems(self):
        providers = sys.modules.get("hypothesis.internal.conjecture.providers")
        read = getattr(providers, "_get_local_constants", None)
        if read is None:     # no @given test collected (or Hypothesis renamed it)
            yield
            return
        providers._get_local_constants = lambda: providers._local_constants
        try:
            yield
        finally:
            providers._get_local_constants = read


def pytest_configure(config):
    config.pluginmanager.register(_LocalConstantsWhereUsed(), "local-constants-where-used")


def pytest_collection_modifyitems(config, items):
    # in a worker (whose own --dist is "no"), when the run was started with worksteal
    worker = getattr(config, "workerinput", {})
    argv = worker.get("mainargv", [])
    if any(a == "worksteal" or a.endswith("=worksteal") for a in argv):
        items[:] = parts_long_first(items, LONG_FILES, int(worker.get("workercount", 2)))

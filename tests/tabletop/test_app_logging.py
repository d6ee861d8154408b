"""``configure_logging`` (tabletop/app.py): what ``run --verbose`` and ``replay --verbose``
print."""

import subprocess
import sys

SCRIPT = """
import logging
from tabletop.app import configure_logging
configure_logging({verbose})
logging.getLogger("matplotlib.font_manager").debug("findfont: a library's debug")
logging.getLogger("matplotlib").info("a library's info")
logging.getLogger("tabletop").debug("the project's debug")
logging.getLogger("tabletop.studio.mop_target").debug("a project module's debug")
logging.getLogger("tabletop").info("the project's info")
"""


def _said(verbose: bool) -> list[str]:
    out = subprocess.run([sys.executable, "-c", SCRIPT.format(verbose=verbose)],
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    return out.stderr.splitlines()


def test_verbose_adds_the_projects_debug_lines_not_the_libraries():
    # --verbose put 146 lines of matplotlib's font search ("tabletop: DEBUG: findfont: ...")
    # before a studio's first take, and no line of the project's own
    assert _said(True) == ["tabletop: INFO: a library's info",
                           "tabletop: DEBUG: the project's debug",
                           "tabletop: DEBUG: a project module's debug",
                           "tabletop: INFO: the project's info"]
    assert _said(False) == ["tabletop: INFO: a library's info",
                            "tabletop: INFO: the project's info"]

"""Loads the shared demonstration generators as ``pm_demos`` (a unique module name, so another
test folder's helper module of the same file name cannot shadow it)."""

import importlib.util
import sys
from pathlib import Path

if "pm_demos" not in sys.modules:
    _spec = importlib.util.spec_from_file_location("pm_demos", Path(__file__).with_name("demos.py"))
    _module = importlib.util.module_from_spec(_spec)
    sys.modules["pm_demos"] = _module
    _spec.loader.exec_module(_module)

"""Loads the shared gesture generators as ``mop_gestures`` (a unique module name, so another
test folder's helper module of the same file name cannot shadow it)."""

import importlib.util
import sys
from pathlib import Path

if "mop_gestures" not in sys.modules:
    _spec = importlib.util.spec_from_file_location("mop_gestures", Path(__file__).with_name("gestures.py"))
    _module = importlib.util.module_from_spec(_spec)
    sys.modules["mop_gestures"] = _module
    _spec.loader.exec_module(_module)

"""Fixtures of the MOP tests."""

import numpy as np
import pytest

from bench.motions import gesture_templates
from tabletop.config import load_config
from tabletop.plugins.mop_table import EXAMPLES


@pytest.fixture(scope="module")
def gestures() -> dict[str, np.ndarray]:
    """The example installation's six puck gestures (dx, dy metres at 30 Hz)."""
    return gesture_templates()


@pytest.fixture(scope="module")
def example_cfg():
    """The example installation's config (examples/mop.yaml), validated."""
    return load_config(EXAMPLES / "mop.yaml")

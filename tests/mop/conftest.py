"""Fixtures of the MOP tests."""

import numpy as np
import pytest

from bench.motions import gesture_templates


@pytest.fixture(scope="module")
def gestures() -> dict[str, np.ndarray]:
    """The example installation's six puck gestures (dx, dy metres at 30 Hz)."""
    return gesture_templates()

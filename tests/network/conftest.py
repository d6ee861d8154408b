"""Fixtures of the network tests."""

import pytest

from tracking.osc_input import OscInput

from tests.network.helpers import TABLE


@pytest.fixture
def source():
    """An ``osc`` source listening on a free loopback port."""
    src = OscInput("osc", port=0, table=TABLE)
    src.open()
    assert src.wait_listening()
    yield src
    src.close()

import pytest

from .fan import heft4k_schedule


@pytest.fixture
def fan(api, cluster):
    """The fan DAG scheduled with HEFT4K on the test cluster (tests/heft4k/fan.py)."""
    return heft4k_schedule(api, cluster)

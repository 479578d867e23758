import pytest
from django.core.cache import cache


@pytest.fixture(autouse=True)
def _fresh_rate_counts():
    """Rate-limit counters live in the cache (local memory in tests): each test starts with none."""
    cache.clear()
    yield
    cache.clear()

"""The jobs tests use the real worker fixtures of tests/services (Redis on a private queue, a celery worker
process on the test database) and the browser fixtures of tests/dashboard."""

from tests.dashboard.test_browser import browser, page  # noqa: F401
from tests.services.conftest import celery_broker, redis_url, start_worker  # noqa: F401

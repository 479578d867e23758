"""A real Celery worker process against real Redis and the test database."""

import os
import signal
import subprocess
import sys
import time
import uuid
from pathlib import Path

import pytest
import redis
from django.conf import settings

ROOT = Path(__file__).resolve().parents[2]
REDIS_URL = os.environ.get("CONTINUUM_TEST_REDIS_URL", "redis://127.0.0.1:6379/15")


@pytest.fixture(scope="session")
def redis_url() -> str:
    try:
        redis.Redis.from_url(REDIS_URL, socket_connect_timeout=2).ping()
    except redis.RedisError as exc:
        pytest.fail(f"Redis is not reachable at {REDIS_URL} ({exc}); scripts/test starts it")
    return REDIS_URL


def database_url() -> str:
    db = settings.DATABASES["default"]
    if db["ENGINE"].endswith("sqlite3"):
        return f"sqlite:///{db['NAME']}"
    user = db.get("USER") or ""
    password = f":{db['PASSWORD']}" if db.get("PASSWORD") else ""
    auth = f"{user}{password}@" if user else ""
    return f"postgres://{auth}{db.get('HOST') or '127.0.0.1'}:{db.get('PORT') or 5432}/{db['NAME']}"


class Worker:
    """A ``celery worker`` process on a private queue; ``kill()`` is a SIGKILL, as a crash would be."""

    def __init__(self, broker: str, queue: str, visibility_timeout: int, pool: str = "solo", env: dict | None = None):
        extra = env or {}
        env = dict(
            os.environ,
            CELERY_BROKER_URL=broker,
            CELERY_QUEUE=queue,
            DATABASE_URL=database_url(),
            CELERY_VISIBILITY_TIMEOUT=str(visibility_timeout),
            CELERY_RESTORE_INTERVAL="1",
            CELERY_RESTORE_THROTTLE="1",
            CONTINUUM_JOBS_EAGER="0",
            **extra,
        )
        self.log = Path(f"/tmp/continuum-worker-{queue}-{uuid.uuid4().hex[:6]}.log")
        self.proc = subprocess.Popen(
            [
                sys.executable,
                "-m",
                "celery",
                "-A",
                "continuum",
                "worker",
                "-P",
                pool,
                "-c",
                "1",
                "-Q",
                queue,
                "--without-gossip",
                "--without-mingle",
                "--loglevel=INFO",
            ],
            cwd=ROOT,
            env=env,
            stdout=self.log.open("w"),
            stderr=subprocess.STDOUT,
            start_new_session=True,
        )
        deadline = time.monotonic() + 60
        while "ready." not in self.log.read_text():
            if self.proc.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError(f"the worker did not start:\n{self.log.read_text()[-3000:]}")
            time.sleep(0.2)

    def kill(self) -> None:
        if self.proc.poll() is None:
            os.killpg(self.proc.pid, signal.SIGKILL)
            self.proc.wait(10)

    def stop(self) -> None:
        if self.proc.poll() is None:
            os.killpg(self.proc.pid, signal.SIGTERM)
            try:
                self.proc.wait(20)
            except subprocess.TimeoutExpired:
                self.kill()


def fresh_pools() -> None:
    """Drop this process's broker connections: the next message opens one to the broker configured now (tests
    point the app at several brokers: Redis, a Redis of their own, a file broker)."""
    from continuum.celery import app

    # Dropped, not closed: kombu's producer pools (one per broker, process-wide) share these connections, and
    # a closed pool answers "Acquire on closed pool" to the next test on that broker.
    app._pool = None
    app.amqp._producer_pool = None


@pytest.fixture
def celery_broker(redis_url, settings):
    """Point this process's Celery app at Redis on a private queue (no eager execution)."""
    from continuum.celery import app

    queue = f"test-{uuid.uuid4().hex[:8]}"
    saved = {k: app.conf[k] for k in ("broker_url", "task_always_eager", "task_default_queue")}
    app.conf.update(broker_url=redis_url, task_always_eager=False, task_default_queue=queue)
    fresh_pools()
    settings.CELERY_TASK_ALWAYS_EAGER = False
    with app.connection_for_write() as conn:
        conn.ensure_connection(max_retries=3)
    yield queue
    app.conf.update(saved)
    fresh_pools()


@pytest.fixture
def start_worker(celery_broker, redis_url):
    workers: list[Worker] = []

    def start(visibility_timeout: int = 3600, pool: str = "solo", env: dict | None = None) -> Worker:
        """A worker; ``pool="prefork"`` for what only a prefork child has (time limits, memory cap)."""
        worker = Worker(redis_url, celery_broker, visibility_timeout, pool, env=env)
        workers.append(worker)
        return worker

    yield start
    for worker in workers:
        worker.stop()

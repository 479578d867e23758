"""The quick start's broker in files (continuum/filebroker.py; issues 25 and 30): empty or garbage message files
are skipped, quarantined and logged while the worker keeps consuming (kombu's own transport crashed the worker
at every start on a 0-byte file), and a full disk under var/broker/ loses nothing: the job waits, said in its
log, and runs once there is room again, with no hand."""

import json
import os
import subprocess
import time
import uuid

import pytest

from apps.jobs.models import Job
from apps.scheduling.models import Schedule
from tests.services.conftest import Worker, fresh_pools
from tests.services.test_celery_worker import make_app, wait_for

from .test_fair_dispatch import schedule

pytestmark = [pytest.mark.services, pytest.mark.django_db(transaction=True)]


def broker_options(root) -> dict:
    """The quick start's transport options (continuum/settings.py) for a broker under ``root``, folders made."""
    folders = {"data_folder_in": "queue", "data_folder_out": "queue", "control_folder": "control",
               "processed_folder": "processed", "quarantine_folder": "quarantine"}  # fmt: skip
    options = {name: str(root / sub) for name, sub in folders.items()}
    for folder in options.values():
        os.makedirs(folder, exist_ok=True)
    return options


@pytest.fixture
def file_broker(tmp_path, settings):
    """This process's Celery app on a file broker in ``tmp_path`` (the quick start's), on a private queue."""
    from continuum.celery import app

    root = tmp_path / "broker"
    options = broker_options(root)
    queue = f"test-{uuid.uuid4().hex[:8]}"
    keys = ("broker_url", "broker_transport_options", "task_always_eager", "task_default_queue")
    saved = {k: app.conf[k] for k in keys}
    app.conf.update(broker_url="continuumfs://", broker_transport_options={**options, "polling_interval": 0.2},
                    task_always_eager=False, task_default_queue=queue)  # fmt: skip
    fresh_pools()
    settings.CELERY_TASK_ALWAYS_EAGER = False
    yield root, queue
    app.conf.update(saved)
    fresh_pools()


def worker_on(root, queue) -> Worker:
    # No CELERY_BROKER_URL: the quick start's settings (continuumfs:// under CONTINUUM_BROKER_DIR).
    env = {"CONTINUUM_BROKER_DIR": str(root), "CONTINUUM_JOB_CHECK_S": "1", "CONTINUUM_JOB_RESEND_AFTER_S": "1"}
    return Worker("", queue, visibility_timeout=3600, env=env)


def message_file(root, queue, body: bytes, at: int = 0) -> str:
    name = f"{at}_{uuid.uuid4()}.{queue}.msg"  # sorted first: read before any real message
    (root / "queue" / name).write_bytes(body)
    return name


def test_empty_and_garbage_message_files_are_skipped_and_logged_and_the_worker_keeps_consuming(fleet, file_broker):
    root, queue = file_broker
    broken = [message_file(root, queue, b""), message_file(root, queue, b"{not json"),
              message_file(root, queue, b"\xff\xfe\x00binary"), message_file(root, queue, b"[1, 2]")]  # fmt: skip
    app = make_app(fleet, 20)
    jobs = [schedule(fleet, app) for _ in range(2)]
    worker = worker_on(root, queue)  # kombu's own transport died here, at its start, and again at every restart
    try:
        for job in jobs:
            job = wait_for(job.pk, lambda j: j.done, timeout=120)
            assert job.state == Job.State.SUCCEEDED and job.attempts == 1, job.error
        # More broken files while it runs: skipped too, and later jobs still run.
        broken.append(message_file(root, queue, b"", at=int(time.monotonic() * 1000)))
        later = wait_for(schedule(fleet, app).pk, lambda j: j.done, timeout=120)
        assert later.state == Job.State.SUCCEEDED
        assert worker.proc.poll() is None
        assert sorted(os.listdir(root / "quarantine")) == sorted(broken)  # kept to look at, out of the queue
        log = worker.log.read_text()
        for name in broken:
            assert f"broker message file {name} skipped" in log, log[-3000:]
        assert "0 bytes" in log
        assert not [n for n in os.listdir(root / "queue") if n.endswith(".msg")]
    finally:
        worker.stop()


def test_a_message_is_written_whole_or_not_at_all_and_taken_by_one_reader(file_broker):
    """No reader sees a partial file: the writer fills a hidden name and renames it in; and of two channels
    reading the same queue, one gets each message."""
    from continuum.celery import app

    root, queue = file_broker
    with app.connection_for_write() as a, app.connection_for_read() as b:
        producer, consumers = a.default_channel, [a.default_channel, b.default_channel]
        for i in range(50):
            producer._put(queue, {"body": str(i), "properties": {}, "headers": {}})
        assert producer._size(queue) == 50
        got = []
        while True:
            try:
                got.append(consumers[len(got) % 2]._get(queue)["body"])
            except Exception:
                break
    assert sorted(got, key=int) == [str(i) for i in range(50)]
    assert os.listdir(root / "queue") == []


@pytest.fixture
def tiny_disk(tmp_path):
    """A 1 MiB tmpfs: a disk that fills up (needs root to mount; skipped where it cannot be mounted)."""
    mount = tmp_path / "disk"
    mount.mkdir()
    done = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1m,mode=0700", "tmpfs", str(mount)],
                          capture_output=True, text=True)  # fmt: skip
    if done.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {done.stderr.strip()}")
    yield mount
    subprocess.run(["umount", "-l", str(mount)], check=False)


def test_a_full_disk_loses_no_job_and_recovers_by_itself(fleet, tiny_disk, settings):
    from continuum.celery import app

    root = tiny_disk / "broker"
    options = {**broker_options(root), "polling_interval": 0.2}
    queue = f"test-{uuid.uuid4().hex[:8]}"
    keys = ("broker_url", "broker_transport_options", "task_always_eager", "task_default_queue")
    saved = {k: app.conf[k] for k in keys}
    app.conf.update(broker_url="continuumfs://", broker_transport_options=options, task_always_eager=False,
                    task_default_queue=queue)  # fmt: skip
    fresh_pools()
    settings.CELERY_TASK_ALWAYS_EAGER = False
    worker = worker_on(root, queue)
    filler = tiny_disk / "filler"
    try:
        application = make_app(fleet, 20)
        first = wait_for(schedule(fleet, application).pk, lambda j: j.done, timeout=120)
        assert first.state == Job.State.SUCCEEDED
        with open(filler, "wb") as f:  # the disk fills up
            try:
                while True:
                    f.write(b"\0" * 65536)
                    f.flush()
            except OSError as exc:
                assert exc.errno == 28  # ENOSPC
        stuck = [schedule(fleet, application) for _ in range(3)]  # answered, never a 500
        for job in stuck:
            job.refresh_from_db()
            assert job.state == Job.State.PENDING
            assert any(line.text.startswith("not queued yet: the broker refused the message")
                       for line in job.log_lines.all())  # fmt: skip
        assert not [n for n in os.listdir(root / "queue") if not n.startswith(".lock")]  # nothing partial
        time.sleep(2)
        assert worker.proc.poll() is None, worker.log.read_text()[-3000:]
        filler.unlink()  # room again: nobody touches anything else
        freed = time.monotonic()
        done = [wait_for(j.pk, lambda j: j.done, timeout=120) for j in stuck]
        recovered = time.monotonic() - freed
        for job in done:
            assert job.state == Job.State.SUCCEEDED and job.attempts == 1, job.error
        assert Schedule.objects.filter(job__in=done).count() == 3
        print(f"disk full: 3 of 3 jobs ran once, {recovered:.1f} s after space was freed")
    finally:
        worker.stop()
        app.conf.update(saved)
        fresh_pools()


def test_the_quick_start_uses_the_hardened_broker():
    from django.conf import settings

    if os.environ.get("CELERY_BROKER_URL"):
        pytest.skip("a broker is configured: not the quick start's")
    assert settings.CELERY_BROKER_URL == "continuumfs://"
    assert json.dumps(settings.CELERY_BROKER_TRANSPORT_OPTIONS)  # the folders, as plain strings


def test_a_message_taken_by_a_reader_that_died_goes_back_to_the_queue(file_broker):
    """A reader takes a file by renaming it; one killed before reading it must not lose the message."""
    from continuum import filebroker
    from continuum.celery import app

    root, queue = file_broker
    gone = subprocess.Popen(["true"])
    gone.wait()
    name = f"1_{uuid.uuid4()}.{queue}.msg"
    (root / "queue" / f".{name}.{gone.pid}.taken").write_text(json.dumps({"body": "kept", "headers": {}}))
    filebroker.Channel._last_tidy = 0.0  # the tidy-up is due
    with app.connection_for_read() as conn:
        assert conn.default_channel._get(queue)["body"] == "kept"
    assert os.listdir(root / "queue") == []

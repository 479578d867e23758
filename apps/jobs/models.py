"""Jobs: every long operation, recorded in the database so history survives worker restarts."""

import uuid

from django.conf import settings
from django.db import models

from apps.tenancy.models import FleetOwned


class Job(FleetOwned):
    class State(models.TextChoices):
        PENDING = "pending"
        RUNNING = "running"
        SUCCEEDED = "succeeded"
        FAILED = "failed"

    id = models.UUIDField(primary_key=True, default=uuid.uuid4, editable=False)
    kind = models.CharField(max_length=50)
    arguments = models.JSONField(default=dict, blank=True)
    created_by = models.ForeignKey(settings.AUTH_USER_MODEL, null=True, blank=True, on_delete=models.SET_NULL)
    state = models.CharField(max_length=16, choices=State.choices, default=State.PENDING)
    progress = models.PositiveSmallIntegerField(default=0)
    message = models.CharField(max_length=300, blank=True)
    result = models.JSONField(null=True, blank=True, help_text="summary of what the job produced")
    result_url = models.CharField(max_length=300, blank=True)
    error = models.TextField(blank=True)
    attempts = models.PositiveSmallIntegerField(default=0)
    # Liveness of the run (apps/jobs/liveness.py): who runs it and its last sign of life.
    worker = models.CharField(max_length=200, blank=True, help_text="host:pid of the process running the job")
    heartbeat = models.DateTimeField(
        null=True, blank=True, help_text="last sign of life of a worker's run (in-process runs send none)"
    )
    interruption = models.CharField(
        max_length=300, blank=True, help_text="why an earlier attempt ended unfinished (e.g. its worker was lost)"
    )
    created = models.DateTimeField(auto_now_add=True)
    started = models.DateTimeField(null=True, blank=True)
    finished = models.DateTimeField(null=True, blank=True)

    class Meta:
        ordering = ["-created"]
        indexes = [models.Index(fields=["fleet", "state"]), models.Index(fields=["kind"])]

    def __str__(self) -> str:
        return f"{self.kind} {self.id}"

    @property
    def done(self) -> bool:
        return self.state in (self.State.SUCCEEDED, self.State.FAILED)

    @property
    def duration(self) -> float | None:
        if self.started and self.finished:
            return (self.finished - self.started).total_seconds()
        return None

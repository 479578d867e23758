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
        CANCELLED = "cancelled"

    #: The states a job ends in.
    FINAL = (State.SUCCEEDED, State.FAILED, State.CANCELLED)

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
    cancel_requested = models.DateTimeField(
        null=True, blank=True, help_text="when a cancel of the running job was asked (its run stops at its next step)"
    )
    retry_of = models.ForeignKey(
        "self", null=True, blank=True, on_delete=models.SET_NULL, related_name="retries",
        help_text="the job this one runs again, with the same arguments",
    )  # fmt: skip
    created = models.DateTimeField(auto_now_add=True)
    queued = models.DateTimeField(
        null=True, blank=True, help_text="when the job's message was last sent to the workers' queue"
    )
    started = models.DateTimeField(null=True, blank=True)
    finished = models.DateTimeField(null=True, blank=True)

    class Meta:
        ordering = ["-created"]
        indexes = [
            models.Index(fields=["fleet", "state"]),
            models.Index(fields=["kind"]),
            # The fair dispatch's question (apps/jobs/dispatch.py): when was each fleet last served.
            models.Index(fields=["fleet", "started"], name="jobs_fleet_served"),
        ]

    def __str__(self) -> str:
        return f"{self.kind} {self.id}"

    @property
    def done(self) -> bool:
        return self.state in self.FINAL

    @property
    def title(self) -> str:
        """What the job does, in words (registered with its kind)."""
        from .registry import kind_title

        return kind_title(self.kind)

    def cancel_unavailable(self) -> str:
        """Why this job cannot be cancelled now ('' when it can)."""
        if self.done:
            return f"the job has {self.state}"
        if self.cancel_requested:
            return "a cancel was already asked: the job stops at its next step"
        return ""

    def retry_unavailable(self) -> str:
        """Why this job cannot be run again ('' when it can): a job that has ended (failed, cancelled, or
        succeeded: a re-run with the same arguments, issue 30) runs again as a new job."""
        if not self.done:
            return f"the job is {self.state}: cancel it first, or wait for its end"
        return ""

    def waiting_notice(self, now=None) -> str:
        """What a pending job no worker has picked up for a while says ('' otherwise): how long, and what is ahead
        of it or that no worker runs anything (a worker down, or consuming another queue)."""
        from .dispatch import waiting_notice

        return waiting_notice(self, now)

    @property
    def duration(self) -> float | None:
        if self.started and self.finished:
            return (self.finished - self.started).total_seconds()
        return None


class JobLogLine(models.Model):
    """One line of a job's log: its progress messages and what happened to it (queued, started, cancelled,
    failed...). Bounded per job (:data:`apps.jobs.joblog.LIMIT`): the oldest lines go first."""

    job = models.ForeignKey(Job, on_delete=models.CASCADE, related_name="log_lines")
    at = models.DateTimeField(auto_now_add=True)
    progress = models.PositiveSmallIntegerField(null=True, blank=True)
    text = models.CharField(max_length=300)

    class Meta:
        ordering = ["id"]
        indexes = [models.Index(fields=["job", "id"])]

    def __str__(self) -> str:
        return self.text

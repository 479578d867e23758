"""A job's log: bounded lines of what happened to it, written by whoever acts on the job (the web process that
queued or cancelled it, the worker's run that reports its progress)."""

from __future__ import annotations

from .models import JobLogLine

#: Lines kept per job: the newest. A 10,000-task schedule reports a few dozen steps; a stuck loop cannot grow
#: the table without end.
LIMIT = 200
#: Prune once every this many lines a process writes for a job (not on every line: a delete per line costs).
PRUNE_EVERY = 20


def write(job_id, text: str, progress: float | None = None) -> None:
    """Append a line to the job's log (text cut to 300 characters)."""
    line = JobLogLine.objects.create(
        job_id=job_id, text=(text or "")[:300], progress=None if progress is None else max(0, min(100, int(progress)))
    )
    if line.pk % PRUNE_EVERY == 0:
        prune(job_id)


def prune(job_id, keep: int = LIMIT) -> int:
    """Delete all but the newest ``keep`` lines of a job; how many were deleted."""
    ids = JobLogLine.objects.filter(job_id=job_id).order_by("-id").values_list("id", flat=True)
    cut = list(ids[keep : keep + 1])
    if not cut:
        return 0
    return JobLogLine.objects.filter(job_id=job_id, id__lte=cut[0]).delete()[0]


def lines(job_id, limit: int = LIMIT) -> list[JobLogLine]:
    """The job's newest ``limit`` lines, oldest first."""
    newest = JobLogLine.objects.filter(job_id=job_id).order_by("-id")[:limit]
    return list(reversed(newest))

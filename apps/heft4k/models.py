"""Remap events: every run of HEFT4K's event-driven remapping (thesis 3.3.2, Algorithm 2), applied or not."""

from django.db import models

from apps.tenancy.models import FleetOwned


class RemapEvent(FleetOwned):
    """Nodes of a schedule failed (or were supposed to, for a what-if): what Algorithm 2 decided and did.

    ``schedule`` is the schedule remapped, ``new_schedule`` the one the remap produced (a new row, so the
    old one stays as it was pushed). ``pods`` lists what changed in Kubernetes when it was applied.
    """

    class Trigger(models.TextChoices):
        WATCH = "watch", "node watcher"
        API = "api", "API / dashboard"
        WHAT_IF = "what-if", "what-if"

    class Decision(models.TextChoices):
        PARTIAL = "partial"
        TOTAL = "total"

    class Status(models.TextChoices):
        WHAT_IF = "what-if", "computed, nothing pushed"
        APPLYING = "applying", "being applied"
        APPLIED = "applied", "applied in Kubernetes"
        NOT_PUSHED = "not-pushed", "stored; nothing in Kubernetes to change"
        FAILED = "failed", "push failed"

    application = models.ForeignKey("workloads.Application", on_delete=models.CASCADE, related_name="remaps")
    schedule = models.ForeignKey("scheduling.Schedule", on_delete=models.CASCADE, related_name="remaps")
    new_schedule = models.OneToOneField(
        "scheduling.Schedule", null=True, blank=True, on_delete=models.SET_NULL, related_name="remap_origin"
    )
    job = models.OneToOneField("jobs.Job", null=True, blank=True, on_delete=models.SET_NULL, related_name="remap_event")
    trigger = models.CharField(max_length=16, choices=Trigger.choices)
    decision = models.CharField(max_length=8, choices=Decision.choices)
    reason = models.CharField(max_length=300, blank=True)
    failed_nodes = models.JSONField(default=list)
    lost_tasks = models.JSONField(default=list, help_text="tasks that were on the failed nodes (OT)")
    moved_tasks = models.JSONField(default=list, help_text="tasks whose node changed")
    reniced_tasks = models.JSONField(default=list, help_text="tasks kept on their node with a new niceness")
    critical_lost = models.JSONField(default=list)
    lost_share = models.FloatField(help_text="lost HEFT-rank share (0-1)")
    threshold = models.FloatField(help_text="total remap above this lost rank share (0-1)")
    makespan_before = models.FloatField()
    makespan_after = models.FloatField()
    elapsed_ms = models.FloatField(help_text="time Algorithm 2 took (decision and new mapping)")
    status = models.CharField(max_length=16, choices=Status.choices, default=Status.WHAT_IF)
    pods = models.JSONField(default=list, blank=True, help_text="pods deleted and recreated when applied")
    push_ms = models.FloatField(null=True, blank=True, help_text="time the changes took in Kubernetes")
    message = models.CharField(max_length=500, blank=True)
    created = models.DateTimeField(auto_now_add=True)
    applied = models.DateTimeField(null=True, blank=True)

    class Meta:
        ordering = ["-created", "-pk"]
        indexes = [models.Index(fields=["application", "created"])]

    def __str__(self) -> str:
        return f"{self.decision} remap of schedule {self.schedule_id} ({', '.join(self.failed_nodes)})"

    @property
    def changed_tasks(self) -> list[str]:
        """Tasks whose pod must be recreated: moved to another node or given another niceness."""
        return [*self.moved_tasks, *self.reniced_tasks]

    @property
    def makespan_change(self) -> float:
        """Relative change of the predicted makespan (0.1 = 10% longer)."""
        return self.makespan_after / self.makespan_before - 1.0 if self.makespan_before > 0 else 0.0

    @property
    def pods_moved(self) -> int:
        return sum(1 for p in self.pods if p.get("created"))


class ScheduleSimulation(models.Model):
    """What the schedule page shows of a HEFT4K schedule beside its plan, computed once by a job: the plan's
    run under the Linux CFS simulator (pods started at once, CPUs shared by nice weight) and the simulated
    makespans of the schedulers HEFT4K is compared with (thesis 4.3.2), on the same DAG and nodes.

    The job that stores a HEFT4K schedule computes it (``schedule``, ``compare`` and ``remap`` jobs); a
    ``heft4k_simulate`` job computes it for a schedule stored before. ``note`` says why nothing was
    simulated (too many tasks, several frames), with ``simulated`` then empty.
    """

    schedule = models.OneToOneField("scheduling.Schedule", on_delete=models.CASCADE, related_name="heft4k_simulation")
    note = models.CharField(max_length=300, blank=True, help_text="why the schedule was not simulated")
    simulated = models.JSONField(default=dict, blank=True, help_text="the CFS-simulated run, as continuum.schedule/v1")
    sharing = models.JSONField(
        default=list, blank=True, help_text="[task, frame, text]: time each simulated task lost to CPU sharing"
    )
    baselines = models.JSONField(default=list, blank=True, help_text="simulated makespans: [{name, makespan, vs_plan}]")
    created = models.DateTimeField(auto_now_add=True)

    def __str__(self) -> str:
        return f"CFS simulation of schedule {self.schedule_id}"

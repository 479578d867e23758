"""Assertion-based verification (thesis §3.5): STL assertions, their monitors, the monitor handlers of a
cluster's nodes, the violations and verdicts the monitors report, the MILP allocation runs and the buffer
migrations they caused. The algorithms live in continuum.engine (stl_parser, stl_monitor, monitor_milp,
abv_simulation) and the handler processes in continuum.verification_runtime."""

from __future__ import annotations

import uuid
from datetime import timedelta

from django.conf import settings
from django.core.exceptions import ValidationError
from django.core.validators import MaxValueValidator, MinValueValidator
from django.db import models
from django.utils import timezone

from apps.tenancy.models import FleetOwned
from continuum.engine.core.errors import InputError
from continuum.engine.verification.stl_monitor import Program, synthesize


class Verdict(models.TextChoices):
    PENDING = "pending", "no verdict yet"
    PASS = "pass"
    FAIL = "fail"
    INCONCLUSIVE = "inconclusive"


class Assertion(FleetOwned):
    """An assertion of the Fig. 3.40 grammar, e.g. ``G(speed > 0 -> F[0,5000](arrived))``; ``constants``
    names numbers used in it (``timeout``). Saving parses it: a syntax error names the column."""

    name = models.CharField(max_length=100)
    text = models.TextField(help_text="e.g. G(speed > 0 -> F[0,5000](arrived)); intervals in ms")
    constants = models.JSONField(default=dict, blank=True, help_text='named numbers, e.g. {"timeout": 5000}')
    description = models.TextField(blank=True)
    skeleton = models.TextField(editable=False, help_text="the monitor's form with placeholders (Fig. 3.41)")
    placeholders = models.JSONField(default=dict, editable=False)
    variables = models.JSONField(default=list, editable=False, help_text="the signals the monitor subscribes to")
    created = models.DateTimeField(auto_now_add=True)
    updated = models.DateTimeField(auto_now=True)

    class Meta:
        ordering = ["name"]
        constraints = [models.UniqueConstraint(fields=["fleet", "name"], name="unique_assertion_name_per_fleet")]

    def __str__(self) -> str:
        return self.name

    def program(self) -> Program:
        """The synthesised monitor program; InputError (naming the column) for a malformed assertion."""
        constants = self.constants or {}
        if not isinstance(constants, dict) or not all(
            isinstance(k, str) and isinstance(v, (int, float)) and not isinstance(v, bool) for k, v in constants.items()
        ):
            raise InputError("constants must map names to numbers", "constants")
        return synthesize(self.text, constants)

    def compile(self) -> Program:
        program = self.program()
        self.skeleton = program.skeleton
        self.placeholders = {p.name: p.text for p in program.placeholders}
        self.variables = sorted(program.variables)
        return program

    def clean(self) -> None:
        try:
            self.compile()
        except InputError as exc:
            raise ValidationError({exc.field if exc.field in ("text", "constants") else "text": str(exc)}) from None

    def save(self, *args, **kwargs) -> None:
        self.compile()  # never store an assertion that does not parse
        super().save(*args, **kwargs)

    @property
    def status(self) -> str:
        """fail if a monitor of it failed, pass if all passed, else pending / inconclusive."""
        verdicts = {m.verdict for m in self.monitors.all()}
        if not verdicts:
            return "no monitors"
        for v in (Verdict.FAIL, Verdict.PENDING, Verdict.INCONCLUSIVE):
            if v in verdicts:
                return v
        return Verdict.PASS


class Monitor(FleetOwned):
    """A monitor synthesised from an assertion, running on one node of a cluster (its handler)."""

    assertion = models.ForeignKey(Assertion, on_delete=models.CASCADE, related_name="monitors")
    cluster = models.ForeignKey("clusters.Cluster", on_delete=models.CASCADE, related_name="monitors")
    name = models.CharField(max_length=100)
    tolerant = models.BooleanField(
        default=False, help_text="may drop old events and reset under overload (soft properties only, §11.2)"
    )
    node = models.ForeignKey(
        "clusters.ComputeNode",
        null=True,
        blank=True,
        on_delete=models.SET_NULL,
        related_name="monitors",
        help_text="the node whose handler runs it",
    )
    state = models.JSONField(null=True, blank=True, editable=False, help_text="in-process monitor state")
    verdict = models.CharField(max_length=16, choices=Verdict.choices, default=Verdict.PENDING)
    events = models.PositiveBigIntegerField(default=0)
    violation_count = models.PositiveIntegerField(default=0)
    active_instances = models.PositiveIntegerField(default=0)
    cpu = models.JSONField(default=dict, blank=True, help_text="last measured % CPU per node")
    created = models.DateTimeField(auto_now_add=True)
    updated = models.DateTimeField(auto_now=True)

    class Meta:
        ordering = ["cluster", "name"]
        constraints = [models.UniqueConstraint(fields=["cluster", "name"], name="unique_monitor_name_per_cluster")]

    def __str__(self) -> str:
        return self.name

    def clean(self) -> None:
        errors = {}
        if self.assertion_id and self.fleet_id and self.assertion.fleet_id != self.fleet_id:
            errors["assertion"] = "the assertion belongs to another fleet"
        if self.cluster_id and self.fleet_id and self.cluster.fleet_id != self.fleet_id:
            errors["cluster"] = "the cluster belongs to another fleet"
        if self.node_id and self.cluster_id and self.node.cluster_id != self.cluster_id:
            errors["node"] = f"node {self.node.name!r} is not in cluster {self.cluster.name!r}"
        if errors:
            raise ValidationError(errors)


class Handler(models.Model):
    """The monitor handler of one compute node (§3.5, Fig. 3.42): its liveness and CPU statistics, as its
    process last reported them on the cluster's verification network (Redis)."""

    node = models.OneToOneField("clusters.ComputeNode", on_delete=models.CASCADE, related_name="handler")
    cluster = models.ForeignKey("clusters.Cluster", on_delete=models.CASCADE, related_name="handlers")
    threshold = models.FloatField(
        default=100.0,
        validators=[MinValueValidator(0), MaxValueValidator(100)],
        help_text="% CPU the node may reach with the monitors (MILP capacity)",
    )
    delay_ms = models.FloatField(default=0.0, validators=[MinValueValidator(0)], help_text="topic delay to this node")
    free_cpu = models.FloatField(null=True, blank=True)
    verification_cpu = models.FloatField(null=True, blank=True)
    monitor_cpu = models.JSONField(default=dict, blank=True)
    active = models.JSONField(default=list, blank=True, help_text="monitors running here")
    is_coordinator = models.BooleanField(default=False)
    last_seen = models.DateTimeField(null=True, blank=True)

    class Meta:
        ordering = ["cluster", "node__name"]

    def __str__(self) -> str:
        return f"handler {self.node.name}"

    @property
    def name(self) -> str:
        return self.node.name

    @property
    def alive(self) -> bool:
        if self.last_seen is None:
            return False
        return timezone.now() - self.last_seen <= timedelta(seconds=settings.CONTINUUM_HANDLER_LIVENESS_S)


class Violation(models.Model):
    """An instance of a monitor that failed: when, where it started, the event that decided it."""

    monitor = models.ForeignKey(Monitor, on_delete=models.CASCADE, related_name="violations")
    time_ms = models.FloatField()
    instance_start_ms = models.FloatField()
    event = models.JSONField(null=True, blank=True, help_text="[variable, value, timestamp] of the deciding event")
    handler = models.CharField(max_length=253, blank=True, help_text="node whose handler found it, or in-process")
    created = models.DateTimeField(auto_now_add=True)

    class Meta:
        ordering = ["-time_ms", "-pk"]
        constraints = [
            models.UniqueConstraint(fields=["monitor", "time_ms", "instance_start_ms"], name="unique_violation")
        ]


class MonitorVerdict(models.Model):
    """A monitor's verdict over a finished stream (its final state at SHUTDOWN, or ``finish`` in-process)."""

    monitor = models.ForeignKey(Monitor, on_delete=models.CASCADE, related_name="verdicts")
    verdict = models.CharField(max_length=16, choices=Verdict.choices)
    counters = models.JSONField(default=dict)
    pending = models.JSONField(default=list, help_text="start times of the instances still pending")
    handler = models.CharField(max_length=253, blank=True)
    created = models.DateTimeField(auto_now_add=True)

    class Meta:
        ordering = ["-created", "-pk"]


class AllocationRun(FleetOwned):
    """One solve of the monitor-allocation MILP (Eqs. 3.21-3.22): its input, result and migrations.

    A simulation stores one run per period, grouped by ``series`` with ``t`` the period's time and
    ``nodes`` the timeline figures (CPU, monitors per node) that Fig. 4.24 plots."""

    class Source(models.TextChoices):
        API = "api", "API / dashboard"
        SIMULATION = "simulation"

    cluster = models.ForeignKey(
        "clusters.Cluster", null=True, blank=True, on_delete=models.SET_NULL, related_name="allocation_runs"
    )
    job = models.ForeignKey("jobs.Job", null=True, blank=True, on_delete=models.SET_NULL, related_name="+")
    source = models.CharField(max_length=16, choices=Source.choices, default=Source.API)
    scenario = models.CharField(max_length=100, blank=True)
    series = models.UUIDField(null=True, blank=True, db_index=True)
    t = models.FloatField(null=True, blank=True, help_text="seconds into the series")
    stats = models.JSONField(null=True, blank=True, help_text="the continuum.monitorstats/v1 input")
    n_monitors = models.PositiveIntegerField(default=0)
    n_nodes = models.PositiveIntegerField(default=0)
    n_topics = models.PositiveIntegerField(default=0)
    status = models.CharField(max_length=16, blank=True)
    feasible = models.BooleanField(default=True)
    objective = models.FloatField(null=True, blank=True, help_text="total delay of the topics received (ms)")
    solve_time_ms = models.FloatField(null=True, blank=True)
    result = models.JSONField(null=True, blank=True, help_text="the engine's Allocation.to_dict()")
    nodes = models.JSONField(default=dict, blank=True, help_text="per node: cpu, background, monitors, ...")
    makespan_ms = models.FloatField(null=True, blank=True)
    applied = models.BooleanField(default=False)
    created = models.DateTimeField(auto_now_add=True)

    class Meta:
        ordering = ["-created", "series", "t", "-pk"]
        indexes = [models.Index(fields=["series", "t"])]

    def __str__(self) -> str:
        return f"allocation {self.pk}"

    @staticmethod
    def new_series() -> uuid.UUID:
        return uuid.uuid4()


class MigrationEvent(FleetOwned):
    """A monitor moved between handlers (Fig. 3.43): from, to, when, and how many buffered events moved."""

    run = models.ForeignKey(AllocationRun, on_delete=models.CASCADE, related_name="migrations")
    monitor = models.ForeignKey(Monitor, null=True, blank=True, on_delete=models.SET_NULL, related_name="migrations")
    monitor_name = models.CharField(max_length=100)
    source = models.CharField(max_length=253)
    target = models.CharField(max_length=253)
    t = models.FloatField(null=True, blank=True, help_text="seconds into the series (simulations)")
    events_moved = models.PositiveIntegerField(null=True, blank=True)
    created = models.DateTimeField(auto_now_add=True)

    class Meta:
        ordering = ["run", "t", "monitor_name", "pk"]

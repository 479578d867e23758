"""RT-Kube's resources in the database (thesis 3.4; spec 03 sections 3, 5, 16.1).

- :class:`RealTime` + :class:`RealTimeWcet`: the RealTime custom resource of Listing 3.33 (times in ms, as in
  the CRD), mirrored both ways with ``realtimes.rt.scheduling`` objects of the cluster's Kubernetes API.
- :class:`Monitoring`: the latest Monitoring object of Listing 3.37 per monitored container; every report
  is also kept as a :class:`MonitoringReport` row (the timelines need them).
- :class:`RTPolicy`: per cluster, the monitor's thresholds and victim policy (spec 03 5.3) and the
  scheduler's Eq. 3.18 parameters.
- :class:`RTPod`: the pods the RT scheduler sees (the ledger the reconcile phase reads).
- :class:`RTPlan` / :class:`RTDecision`: placement runs (what-if jobs, scheduler cycles) as the engine's
  ``PlacementPlan.to_dict()``, and one row per scheduler decision with its per-node verdicts.
- :class:`RTEvent` / :class:`NodeTaint`: what the reconcile phase did (evictions, alerts) with the
  timestamps of Eq. 3.19, and the timed node taints.

Validation is the engine's (``continuum.engine.rtkube.rt_model``): every form, serializer and importer calls
:func:`engine_container`, so the rules (positive numbers, ``WCET <= D <= P``, known nodes, criticality
A-C) and their messages are the same everywhere.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence

from django.core.exceptions import ValidationError
from django.core.validators import MaxValueValidator, MinValueValidator, RegexValidator
from django.db import models

from apps.clusters.models import Cluster, ComputeNode
from continuum.engine.core.errors import InputError
from continuum.engine.core.placement import PlacementPlan
from continuum.engine.rtkube.rt_kube import RTKubeParams
from continuum.engine.rtkube.rt_model import (
    RTContainer,
    container_from_dict,
    realtime_resource,
    realtime_to_yaml,
)
from continuum.engine.rtkube.rt_victims import POLICIES, VIOLATION_TAINT_KEY, MonitorPolicy

DNS_SUBDOMAIN = re.compile(r"^[a-z0-9]([-a-z0-9]*[a-z0-9])?(\.[a-z0-9]([-a-z0-9]*[a-z0-9])?)*$")
dns_name = RegexValidator(
    DNS_SUBDOMAIN, "lower-case letters, digits, '-' and '.', starting and ending with a letter or digit"
)


def engine_container(
    name: str,
    criticality: str,
    period: float | None,
    deadline: float | None,
    wcets: Sequence[tuple[str, float | None]],
    *,
    stateless: bool = False,
    cpu: float | None = None,
    memory_mib: float | None = None,
    known_nodes: Iterable[str] | None = None,
) -> RTContainer:
    """The engine's RT container for these fields, or :class:`InputError` naming the bad field.

    An RT container must be real-time here (criticality A-C): ``NONE`` is for plain pods, not RealTime objects.
    """
    if not criticality:
        raise InputError(f"RealTime {name!r}: criticality is required (A, B or C)", "criticality")
    if not wcets:
        raise InputError(f"RealTime {name!r}: give at least one node WCET", "wcets")
    seen: set[str] = set()
    for node, _ in wcets:
        if node in seen:
            raise InputError(f"RealTime {name!r}: node {node!r} has two WCETs", "wcets")
        seen.add(node)
    doc = {
        "name": name,
        "criticality": criticality,
        "period": period,
        "deadline": deadline,
        "wcet": dict(wcets),
        "stateless": stateless,
        "cpu": cpu or None,
        "memory_mib": memory_mib or None,
    }
    container = container_from_dict(doc, 0, known_nodes)
    if not container.is_rt:
        raise InputError(f"RealTime {name!r}: criticality must be A, B or C", "criticality")
    return container


class RTPolicy(models.Model):
    """Per cluster: the cluster-level monitor's policy (spec 03 5.3) and the RT scheduler's parameters."""

    class Eviction(models.TextChoices):
        LINEAR = "linear", "linear (one resource, O(n))"
        LINEARITHMIC = "linearithmic", "linearithmic (two resources, O(n log n))"
        QUADRATIC = "quadratic", "quadratic (communication, O(n²))"

    cluster = models.OneToOneField(Cluster, on_delete=models.CASCADE, related_name="rt_policy")
    threshold_period = models.PositiveIntegerField(
        null=True, blank=True, default=10, help_text="evict when a report's missed deadlines in the period exceed this"
    )
    threshold_total = models.PositiveIntegerField(
        null=True, blank=True, help_text="evict when the missed deadlines in total exceed this (empty: off)"
    )
    update_frequency_hz = models.FloatField(default=10.0, validators=[MinValueValidator(0.001)])
    eviction_policy = models.CharField(max_length=16, choices=Eviction.choices, default=Eviction.LINEAR)
    linear_resource = models.CharField(
        max_length=8, choices=[("cpu", "cpu"), ("memory", "memory")], default="cpu", help_text="linear policy only"
    )
    taint_duration_s = models.FloatField(
        default=60.0, validators=[MinValueValidator(0.0)], help_text="how long a violating node stays tainted"
    )
    cooldown_s = models.FloatField(
        null=True, blank=True, validators=[MinValueValidator(0.0)], help_text="empty: the taint duration"
    )
    recreate_orphans = models.BooleanField(
        default=True,
        help_text="recreate an evicted pod that no controller owns (a Deployment's ReplicaSet recreates its own)",
    )
    traffic = models.JSONField(
        default=dict, blank=True, help_text='quadratic policy: traffic between containers, {"a|b": bytes/s}'
    )
    k = models.FloatField(default=2.0, validators=[MinValueValidator(1e-9)], help_text="Eq. 3.18's K")
    b_score_argument = models.CharField(
        max_length=8, choices=[("free", "free capacity (Eq. 3.18)"), ("load", "load (prose)")], default="free"
    )
    sort_tiebreak = models.CharField(
        max_length=12, choices=[("arrival", "arrival"), ("utilization", "utilization")], default="arrival"
    )

    class Meta:
        verbose_name = "RT policy"
        verbose_name_plural = "RT policies"

    def __str__(self) -> str:
        return f"RT policy of {self.cluster}"

    @classmethod
    def for_cluster(cls, cluster: Cluster) -> RTPolicy:
        policy, _ = cls.objects.get_or_create(cluster=cluster)
        return policy

    def monitor_policy(self) -> MonitorPolicy:
        return MonitorPolicy(
            threshold_period=self.threshold_period,
            threshold_total=self.threshold_total,
            update_frequency_hz=self.update_frequency_hz,
            eviction_policy=self.eviction_policy,
            linear_resource=self.linear_resource,
            taint_duration=self.taint_duration_s,
            cooldown=self.cooldown_s,
            taint_key=VIOLATION_TAINT_KEY,
        )

    def scheduler_params(self) -> RTKubeParams:
        return RTKubeParams(k=self.k, b_score_argument=self.b_score_argument, sort_tiebreak=self.sort_tiebreak)

    def clean(self) -> None:
        try:
            self.monitor_policy()
            self.scheduler_params()
        except InputError as exc:
            raise ValidationError({exc.field if exc.field in _field_names(self) else "__all__": str(exc)}) from exc
        if self.eviction_policy not in POLICIES:
            raise ValidationError({"eviction_policy": "unknown policy"})


def _field_names(obj: models.Model) -> set[str]:
    return {f.name for f in obj._meta.get_fields()}


class RealTime(models.Model):
    """A RealTime object (Listing 3.33): one RT container's criticality, period, deadline and per-node WCETs."""

    class SyncState(models.TextChoices):
        LOCAL = "local", "not in Kubernetes"
        SYNCED = "synced", "in sync"
        ERROR = "error", "sync failed"

    cluster = models.ForeignKey(Cluster, on_delete=models.CASCADE, related_name="realtimes")
    namespace = models.CharField(max_length=63, validators=[dns_name])
    name = models.CharField(max_length=253, validators=[dns_name], help_text="pods link to it by label rt-scheduling")
    criticality = models.CharField(max_length=1, choices=ComputeNode.Criticality.choices)
    period = models.FloatField(help_text="rtPeriod, ms")
    deadline = models.FloatField(help_text="rtDeadline, ms")
    stateless = models.BooleanField(default=False, help_text="may be evicted and re-created elsewhere")
    cpu = models.FloatField(default=0.0, validators=[MinValueValidator(0.0)], help_text="CPU request, cores")
    memory_mib = models.FloatField(default=0.0, validators=[MinValueValidator(0.0)], help_text="memory request, MiB")
    warmup_ms = models.FloatField(
        null=True, blank=True, validators=[MinValueValidator(0.0), MaxValueValidator(3_600_000.0)],
        help_text="ms after exec whose overruns are start-up, not misses (null: the agent's default, 20 periods)",
    )  # fmt: skip
    # Kubernetes mirror: the custom object's identity and version as last written or read.
    uid = models.CharField(max_length=64, blank=True)
    resource_version = models.CharField(max_length=64, blank=True)
    dirty = models.BooleanField(default=True, help_text="changed here since the last push to Kubernetes")
    sync_state = models.CharField(max_length=8, choices=SyncState.choices, default=SyncState.LOCAL)
    sync_error = models.CharField(max_length=500, blank=True)
    created = models.DateTimeField(auto_now_add=True)
    updated = models.DateTimeField(auto_now=True)

    class Meta:
        ordering = ["cluster", "namespace", "name"]
        constraints = [models.UniqueConstraint(fields=["cluster", "namespace", "name"], name="unique_realtime")]
        verbose_name = "RealTime"

    def __str__(self) -> str:
        return f"{self.namespace}/{self.name}"

    @property
    def fleet_id(self) -> int:
        return self.cluster.fleet_id

    def wcet_pairs(self) -> list[tuple[str, float]]:
        return [(w.node.name, w.wcet) for w in self.wcets.all()]

    def to_engine(self, known_nodes: Iterable[str] | None = None) -> RTContainer:
        return engine_container(
            self.name,
            self.criticality,
            self.period,
            self.deadline,
            self.wcet_pairs(),
            stateless=self.stateless,
            cpu=self.cpu,
            memory_mib=self.memory_mib,
            known_nodes=known_nodes,
        )

    def to_resource(self, with_namespace: bool = True) -> dict:
        """The custom object (Listing 3.33 field names, through the engine)."""
        return realtime_resource(self.to_engine(), self.namespace if with_namespace else None)

    def to_yaml(self) -> str:
        """The object as Listing 3.33 prints it (no namespace, key order of the listing)."""
        return realtime_to_yaml([self.to_engine()])

    def utilization(self) -> dict[str, float]:
        return {node: w / self.period for node, w in self.wcet_pairs()} if self.period else {}


class RealTimeWcet(models.Model):
    realtime = models.ForeignKey(RealTime, on_delete=models.CASCADE, related_name="wcets")
    node = models.ForeignKey(ComputeNode, on_delete=models.CASCADE, related_name="+")
    wcet = models.FloatField(help_text="rtWcet on this node, ms")
    #: Order of ``spec.rtWcets``, kept so that the YAML comes back as it went in.
    position = models.PositiveSmallIntegerField(default=0)

    class Meta:
        ordering = ["realtime", "position", "pk"]
        constraints = [models.UniqueConstraint(fields=["realtime", "node"], name="unique_wcet_node")]
        verbose_name = "WCET"

    def __str__(self) -> str:
        return f"{self.node.name}: {self.wcet:g} ms"


class RTPod(models.Model):
    """A pod of the namespaces the RT scheduler serves, as it last saw it (the ledger of the reconcile phase)."""

    cluster = models.ForeignKey(Cluster, on_delete=models.CASCADE, related_name="rt_pods")
    namespace = models.CharField(max_length=63)
    name = models.CharField(max_length=253)
    uid = models.CharField(max_length=64, blank=True)
    node = models.CharField(max_length=253, blank=True, db_index=True, help_text="empty while pending")
    container_name = models.CharField(max_length=253, blank=True)
    scheduler_name = models.CharField(max_length=253, blank=True)
    realtime = models.ForeignKey(RealTime, null=True, blank=True, on_delete=models.SET_NULL, related_name="pods")
    criticality = models.CharField(max_length=4, default="NONE")
    stateless = models.BooleanField(default=False)
    cpu = models.FloatField(default=0.0)
    memory_mib = models.FloatField(default=0.0)
    utilization = models.FloatField(null=True, blank=True, help_text="WCET(node)/P where bound")
    owned = models.BooleanField(default=False, help_text="a controller (ReplicaSet, ...) owns it")
    phase = models.CharField(max_length=16, blank=True)
    #: The pod's newest event, stored by the cluster's watcher (``watch_cluster``) with ``phase``.
    pod_event = models.CharField(max_length=500, blank=True, help_text="the pod's newest event: reason: message")
    pod_state_at = models.DateTimeField(null=True, blank=True, help_text="when the watcher last stored a change")
    bound_at = models.DateTimeField(null=True, blank=True)
    deleted_at = models.DateTimeField(null=True, blank=True)
    seen = models.DateTimeField(auto_now=True)

    class Meta:
        ordering = ["cluster", "namespace", "name"]
        constraints = [models.UniqueConstraint(fields=["cluster", "namespace", "name"], name="unique_rt_pod")]
        indexes = [models.Index(fields=["cluster", "node", "deleted_at"])]
        verbose_name = "RT pod"

    def __str__(self) -> str:
        return f"{self.namespace}/{self.name}"

    @property
    def key(self) -> str:
        return f"{self.namespace}/{self.name}"


class RTPlan(models.Model):
    """One placement run: a what-if job over a set of containers, or one cycle of the scheduler process."""

    class Kind(models.TextChoices):
        WHATIF = "whatif", "what-if"
        SCHEDULER = "scheduler", "scheduler cycle"

    cluster = models.ForeignKey(Cluster, on_delete=models.CASCADE, related_name="rt_plans")
    kind = models.CharField(max_length=10, choices=Kind.choices)
    job = models.OneToOneField("jobs.Job", null=True, blank=True, on_delete=models.SET_NULL, related_name="rt_plan")
    plan = models.JSONField(
        help_text="the engine's PlacementPlan.to_dict() with its decisions' (bounded) explanation and the "
        "explain table of their verdicts"
    )
    placed = models.PositiveIntegerField(default=0)
    pending = models.PositiveIntegerField(default=0)
    created = models.DateTimeField(auto_now_add=True, db_index=True)

    class Meta:
        ordering = ["-created", "-pk"]
        verbose_name = "RT plan"

    def __str__(self) -> str:
        return f"{self.get_kind_display()} on {self.cluster} ({self.placed} placed, {self.pending} pending)"

    def engine_plan(self) -> PlacementPlan:
        """The stored plan read back as the engine's type (the ``explain`` stored beside it is left out)."""
        return PlacementPlan.from_dict(self.plan, ignore=("explain",))


class RTDecision(models.Model):
    """One pod's decision by the scheduler process, explained per node (the engine's ``Decision.to_dict()``)."""

    class Outcome(models.TextChoices):
        BOUND = "bound"
        PENDING = "pending"
        FAILED = "failed", "bind failed"

    cluster = models.ForeignKey(Cluster, on_delete=models.CASCADE, related_name="rt_decisions")
    plan = models.ForeignKey(RTPlan, null=True, blank=True, on_delete=models.SET_NULL, related_name="decisions")
    namespace = models.CharField(max_length=63)
    pod = models.CharField(max_length=253)
    pod_uid = models.CharField(max_length=64, blank=True)
    realtime = models.ForeignKey(RealTime, null=True, blank=True, on_delete=models.SET_NULL, related_name="+")
    criticality = models.CharField(max_length=4, default="NONE")
    outcome = models.CharField(max_length=8, choices=Outcome.choices)
    node = models.CharField(max_length=253, blank=True)
    score = models.FloatField(null=True, blank=True)
    message = models.CharField(max_length=1000, blank=True)
    decision = models.JSONField(
        help_text="Decision.to_dict(): every node's filter or score on a small cluster, else the top candidates, "
        "an example per filter and the count of nodes per filter (rejections)"
    )
    created = models.DateTimeField(auto_now_add=True, db_index=True)

    class Meta:
        ordering = ["-created", "-pk"]
        indexes = [models.Index(fields=["cluster", "namespace", "pod"])]
        verbose_name = "RT decision"

    def __str__(self) -> str:
        return f"{self.namespace}/{self.pod}: {self.outcome} {self.node}".strip()


class Monitoring(models.Model):
    """The latest Monitoring object (Listing 3.37) of one monitored container."""

    cluster = models.ForeignKey(Cluster, on_delete=models.CASCADE, related_name="monitorings")
    name = models.CharField(max_length=253, help_text="metadata.name (default <pod>-<container>)")
    node = models.ForeignKey(ComputeNode, on_delete=models.CASCADE, related_name="+")
    container_name = models.CharField(max_length=253)
    pod = models.CharField(max_length=253, blank=True)
    missed_period = models.PositiveIntegerField(default=0)
    missed_total = models.PositiveIntegerField(default=0)
    received_at = models.DateTimeField()
    kube_synced = models.BooleanField(default=False, help_text="the custom object shows these counters")
    resource_version = models.CharField(max_length=64, blank=True)

    class Meta:
        ordering = ["cluster", "name"]
        constraints = [models.UniqueConstraint(fields=["cluster", "name"], name="unique_monitoring")]

    def __str__(self) -> str:
        return self.name

    def to_resource(self, namespace: str) -> dict:
        spec = {
            "node": self.node.name,
            "containerName": self.container_name,
            "missedDeadlinesPeriod": self.missed_period,
            "missedDeadlinesTotal": self.missed_total,
        }
        if self.pod:
            spec["pod"] = self.pod
        return {
            "apiVersion": "rt.monitoring/v1alpha1",
            "kind": "Monitoring",
            "metadata": {"name": self.name, "namespace": namespace},
            "spec": spec,
        }


class MonitoringReport(models.Model):
    """Every report received (REST or custom object), for the timelines; written in bulk."""

    class Source(models.TextChoices):
        REST = "rest"
        KUBE = "kube", "custom object"

    cluster = models.ForeignKey(Cluster, on_delete=models.CASCADE, related_name="+")
    name = models.CharField(max_length=253)
    node = models.CharField(max_length=253)
    container_name = models.CharField(max_length=253)
    pod = models.CharField(max_length=253, blank=True)
    missed_period = models.PositiveIntegerField()
    missed_total = models.PositiveIntegerField()
    violation = models.CharField(max_length=8, blank=True, help_text="period or total when over the threshold")
    miss_at = models.DateTimeField(null=True, blank=True, help_text="the miss that crossed the threshold (monitor)")
    sent_at = models.DateTimeField(null=True, blank=True, help_text="when the monitor sent it (its clock)")
    received_at = models.DateTimeField()
    source = models.CharField(max_length=4, choices=Source.choices, default=Source.REST)
    #: The report's idempotency key: the client's ``id``/``report_id``, else a digest of its content. A report
    #: whose key the cluster has seen is a replay (a robot retrying a batch): acknowledged, not acted on again.
    report_id = models.CharField(max_length=160, null=True, blank=True)
    #: A report over a threshold is stored first and reconciled after (off the web request: the
    #: ``continuum.rt_reconcile`` task); the reconcile claims it by setting this, in the transaction that records
    #: its eviction, so it is acted on exactly once. Null on a violation: not reconciled yet.
    reconciled_at = models.DateTimeField(null=True, blank=True)
    #: Overruns before the command was ready (the agent's warm-up): not missed deadlines, never a violation.
    startup_overruns = models.PositiveIntegerField(default=0)

    class Meta:
        ordering = ["-received_at", "-pk"]
        indexes = [
            models.Index(fields=["cluster", "received_at"]),
            # The violations still to reconcile (the sweep's query): a handful among millions of reports.
            models.Index(
                fields=["received_at"],
                name="rt_report_pending",
                condition=~models.Q(violation="") & models.Q(reconciled_at__isnull=True),
            ),
        ]
        constraints = [models.UniqueConstraint(fields=["cluster", "report_id"], name="unique_report_id")]

    def __str__(self) -> str:
        return f"{self.container_name}@{self.node}: {self.missed_period}/{self.missed_total}"


class RTEvent(models.Model):
    """An action of the reconcile phase (an eviction, or an alert when nobody may be evicted), with the
    timestamps of Eq. 3.19: the crossing miss and the report's sending (monitor clock, when reported), its
    reception, the end of the reconcile, and the eviction request sent to and answered by the API."""

    class Kind(models.TextChoices):
        EVICTION = "eviction"
        ALERT = "alert"

    cluster = models.ForeignKey(Cluster, on_delete=models.CASCADE, related_name="rt_events")
    kind = models.CharField(max_length=8, choices=Kind.choices)
    node = models.CharField(max_length=253)
    container = models.CharField(max_length=253, help_text="the violating container")
    pod = models.CharField(max_length=253, blank=True, help_text="the violating pod (namespace/name)")
    trigger = models.CharField(max_length=8, blank=True)
    missed_period = models.PositiveIntegerField(default=0)
    missed_total = models.PositiveIntegerField(default=0)
    victim = models.CharField(max_length=320, blank=True, help_text="evicted pod (namespace/name)")
    policy = models.CharField(max_length=16, blank=True)
    candidates = models.JSONField(default=list, blank=True)
    message = models.CharField(max_length=1000, blank=True)
    decision = models.JSONField(default=dict, blank=True, help_text="the engine's ReconcileDecision.to_dict()")
    miss_at = models.DateTimeField(null=True, blank=True)
    sent_at = models.DateTimeField(null=True, blank=True)
    received_at = models.DateTimeField()
    reconcile_done_at = models.DateTimeField(null=True, blank=True)
    eviction_sent_at = models.DateTimeField(null=True, blank=True)
    eviction_done_at = models.DateTimeField(null=True, blank=True)
    eviction_error = models.CharField(max_length=1000, blank=True)
    recreated = models.CharField(max_length=253, blank=True, help_text="the replacement pod we created, if any")
    response = models.JSONField(default=dict, blank=True, help_text="Eq. 3.19 components in ms")
    response_ms = models.FloatField(null=True, blank=True, help_text="report received to eviction sent, ms")
    created = models.DateTimeField(auto_now_add=True, db_index=True)

    class Meta:
        ordering = ["-received_at", "-pk"]
        indexes = [models.Index(fields=["cluster", "container", "received_at"])]
        verbose_name = "RT event"

    def __str__(self) -> str:
        what = f"evicted {self.victim}" if self.kind == self.Kind.EVICTION else "alert"
        return f"{self.container}@{self.node}: {what}"


class NodeTaint(models.Model):
    """A timed taint the monitor put on a node; lifted (in the API and here) once ``expires_at`` passes."""

    cluster = models.ForeignKey(Cluster, on_delete=models.CASCADE, related_name="rt_taints")
    node = models.ForeignKey(ComputeNode, on_delete=models.CASCADE, related_name="rt_taints")
    key = models.CharField(max_length=253, default=VIOLATION_TAINT_KEY)
    value = models.CharField(max_length=63, default="true")
    effect = models.CharField(max_length=16, default="NoSchedule")
    event = models.ForeignKey(RTEvent, null=True, blank=True, on_delete=models.SET_NULL, related_name="taints")
    created = models.DateTimeField(auto_now_add=True)
    expires_at = models.DateTimeField(db_index=True)
    applied_at = models.DateTimeField(null=True, blank=True, help_text="when the API accepted it")
    lifted_at = models.DateTimeField(null=True, blank=True)
    error = models.CharField(max_length=500, blank=True)

    class Meta:
        ordering = ["-created", "-pk"]
        verbose_name = "node taint"

    def __str__(self) -> str:
        return f"{self.node.name}: {self.key}={self.value}:{self.effect}"

    def as_dict(self) -> dict:
        return {"key": self.key, "value": self.value, "effect": self.effect}

"""Clusters of compute nodes and the network links between them (``continuum.cluster/v1``)."""

from django.conf import settings
from django.core.validators import MinValueValidator
from django.db import models

from apps.kube.credentials import EncryptedTextField
from apps.tenancy.models import FleetOwned
from continuum.engine.core.cluster import Cluster as EngineCluster
from continuum.engine.core.cluster import default_rt_threshold
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Platform
from continuum.engine.core.taints import status_taint


class Cluster(FleetOwned):
    name = models.CharField(max_length=100)
    description = models.TextField(blank=True)
    # Encrypted at rest; validated where it is saved (serializers, admin) and again where it is loaded
    # (apps.clusters.kube.target_for). Setting it needs the clusters.change_cluster_credentials permission.
    kubeconfig = EncryptedTextField(
        blank=True, help_text="kubeconfig (YAML) of this cluster's Kubernetes API; empty for a model-only cluster"
    )
    kube_context = models.CharField(max_length=200, blank=True)
    namespace = models.CharField(max_length=63, default="continuum")
    default_bandwidth_mbps = models.FloatField(
        null=True,
        blank=True,
        validators=[MinValueValidator(0.001)],
        help_text="bandwidth between nodes with no link path; empty means free transfers",
    )
    default_latency_ms = models.FloatField(default=0.0, validators=[MinValueValidator(0.0)])
    last_synced = models.DateTimeField(null=True, blank=True)
    created = models.DateTimeField(auto_now_add=True)

    class Meta:
        ordering = ["name"]
        constraints = [models.UniqueConstraint(fields=["fleet", "name"], name="unique_cluster_name_per_fleet")]
        permissions = [
            ("change_cluster_credentials", "Can set a cluster's Kubernetes credentials (kubeconfig, context)")
        ]

    def __str__(self) -> str:
        return self.name

    def to_engine(self) -> EngineCluster:
        """This cluster as the engine sees it (``continuum.cluster/v1``, read by the engine's one parser).

        The one rule for nodes that are not Ready: every node is in it (name order), and a node that is not
        Ready carries the NoSchedule taint Kubernetes gives such a node (``node.kubernetes.io/not-ready`` when
        NotReady, ``node.kubernetes.io/unreachable`` when Unknown; ``continuum.engine.core.taints.STATUS_TAINTS``),
        so it is excluded from placement by every placer that honours taints (super-clustering, RT-Kube), with
        that taint as the reason, while the pods already bound there still count. The DAG schedulers, which
        know no taints, get the cluster without those nodes (:meth:`to_platform`, ``EngineCluster.ready``).
        """
        nodes = list(self.nodes.order_by("name"))
        if not nodes:
            raise InputError(f"cluster {self.name!r} has no nodes", "cluster")
        doc = {
            "name": self.name,
            "nodes": [n.to_document() | _kernel_threshold(n) for n in nodes],
            "links": [
                {
                    "src": lk.src.name,
                    "dst": lk.dst.name,
                    "bandwidth_mbps": lk.bandwidth_mbps,
                    "latency_ms": lk.latency_ms,
                }
                for lk in self.links.select_related("src", "dst")
            ],
            "default_bandwidth_mbps": self.default_bandwidth_mbps,
            "default_latency_ms": self.default_latency_ms,
        }
        return EngineCluster.from_dict(doc)

    def to_platform(self, ready_only: bool = True) -> Platform:
        """The cluster graph the DAG schedulers use: one multi-core processor per node their pods may be placed
        on (Ready, no untolerated taint, not RT-only: the filter every placement method shares,
        ``EngineCluster.schedulable``; the pods Continuum pushes for DAG tasks carry no toleration); every node
        with ``ready_only=False``, e.g. to draw the cluster. Times in ms and data in Mbit."""
        engine = self.to_engine()
        return (engine.schedulable() if ready_only else engine).to_platform(settings.CONTINUUM_CLUSTER_ROUTING)


class ComputeNode(models.Model):
    class Arch(models.TextChoices):
        AMD64 = "amd64"
        ARM64 = "arm64"
        RISCV64 = "riscv64"

    class Status(models.TextChoices):
        READY = "Ready"
        NOT_READY = "NotReady"
        UNKNOWN = "Unknown"

    class Capacity(models.TextChoices):
        #: cpu/memory_mib/storage_mib were declared (cluster file, API, admin): the planning input, kept by sync.
        DECLARED = "declared"
        #: The node was found by node sync: its planning capacity follows what Kubernetes reports.
        REPORTED = "reported"

    class Criticality(models.TextChoices):
        A = "A"
        B = "B"
        C = "C"
        D = "D"

    cluster = models.ForeignKey(Cluster, on_delete=models.CASCADE, related_name="nodes")
    name = models.CharField(max_length=253)
    arch = models.CharField(max_length=16, choices=Arch.choices, default=Arch.AMD64)
    cpu = models.FloatField(default=1.0, validators=[MinValueValidator(0.0)], help_text="CPU cores")
    memory_mib = models.PositiveIntegerField(default=1024)
    storage_mib = models.PositiveIntegerField(default=0)
    # Planning uses cpu/memory_mib/storage_mib. A declared capacity is never overwritten by node sync (a kubemark
    # hollow node reports 1 CPU / 3840 MiB whatever the board is); what Kubernetes reports is kept beside it.
    capacity_source = models.CharField(
        max_length=16,
        choices=Capacity.choices,
        default=Capacity.DECLARED,
        help_text="declared: cpu/memory/storage as declared (node sync keeps them); reported: as Kubernetes reports",
    )
    reported_cpu = models.FloatField(null=True, blank=True, help_text="CPU cores Kubernetes reports (capacity)")
    reported_memory_mib = models.PositiveIntegerField(null=True, blank=True, help_text="memory Kubernetes reports")
    reported_storage_mib = models.PositiveIntegerField(null=True, blank=True, help_text="storage Kubernetes reports")
    accelerators = models.JSONField(default=list, blank=True, help_text='e.g. ["igpu"]')
    processor_class = models.CharField(
        max_length=32, default="cpu", help_text="class that DAG task costs name (cpu, gpu, ...)"
    )
    speed = models.FloatField(default=1.0, validators=[MinValueValidator(0.001)], help_text="class cost / speed")
    rt = models.BooleanField(default=False, help_text="real-time capable")
    criticality = models.CharField(max_length=1, choices=Criticality.choices, blank=True)
    rt_threshold = models.FloatField(null=True, blank=True, help_text="admissible RT utilization (M x 0.95)")
    #: What the node's kernel admits (``python -m continuum.agent admission``, ``POST /api/v1/rt-admissions/``):
    #: the RT filter's threshold when the cluster file gives no ``rt_threshold`` (which still wins).
    kernel_rt_capacity = models.FloatField(null=True, blank=True, help_text="deadline bandwidth its kernel admits")
    kernel_rt_source = models.CharField(max_length=300, blank=True, help_text="how the node read it")
    kernel_reported_at = models.DateTimeField(null=True, blank=True)
    labels = models.JSONField(default=dict, blank=True)
    taints = models.JSONField(default=list, blank=True, help_text='[{"key", "value", "effect"}]')
    status = models.CharField(max_length=16, choices=Status.choices, default=Status.READY)

    class Meta:
        ordering = ["cluster", "name"]
        constraints = [models.UniqueConstraint(fields=["cluster", "name"], name="unique_node_name_per_cluster")]

    def __str__(self) -> str:
        return self.name

    @property
    def rt_capacity(self) -> float:
        """The admissible RT utilization: ``rt_threshold`` (the cluster file's), else what the node's kernel
        reported, else ``M x 0.95`` (the thesis' default, the engine's default_rt_threshold)."""
        if self.rt_threshold is not None:
            return self.rt_threshold
        if self.kernel_rt_capacity is not None:
            return self.kernel_rt_capacity
        return default_rt_threshold(self.cpu)

    def rt_capacity_or(self, default: float) -> float:
        """:attr:`rt_capacity` with ``default`` instead of the thesis' M x 0.95 of this row's CPUs."""
        if self.rt_threshold is not None:
            return self.rt_threshold
        return self.kernel_rt_capacity if self.kernel_rt_capacity is not None else default

    @property
    def rt_capacity_source(self) -> str:
        """Where :attr:`rt_capacity` comes from, in words."""
        if self.rt_threshold is not None:
            return "the cluster file's rt_threshold"
        if self.kernel_rt_capacity is not None:
            return f"the node's kernel ({self.kernel_rt_source or 'reported'})"
        return "the thesis' default M x 0.95: the node reported nothing"

    def to_document(self) -> dict:
        """This node as a ``continuum.cluster/v1`` node; one that is not Ready carries its status taint
        (see :meth:`Cluster.to_engine`). A storage capacity of 0 means "not known", not "full"."""
        taints = [dict(t) for t in self.taints or []]
        status = status_taint(self.status)
        if status is not None and not any(t.get("key") == status.key for t in taints):
            taints.append({"key": status.key, "value": status.value, "effect": status.effect})
        doc = {
            "name": self.name,
            "arch": self.arch,
            "cpu": self.cpu,
            "memory_mib": self.memory_mib,
            "storage_mib": self.storage_mib or None,
            "labels": self.labels,
            "taints": taints,
            "rt": self.rt,
            "class": self.processor_class,
            "speed": self.speed,
        }
        if self.criticality:
            doc["criticality"] = self.criticality
        if self.rt_threshold is not None:
            doc["rt_threshold"] = self.rt_threshold
        if self.accelerators:
            doc["accelerators"] = self.accelerators
        return doc


def _kernel_threshold(node: ComputeNode) -> dict:
    """The engine's ``rt_threshold`` from the node's kernel when the cluster file gave none (not exported with the
    cluster file: :meth:`ComputeNode.to_document` stays what the operator wrote)."""
    if node.rt_threshold is None and node.kernel_rt_capacity is not None:
        return {"rt_threshold": node.kernel_rt_capacity}
    return {}


class Link(models.Model):
    cluster = models.ForeignKey(Cluster, on_delete=models.CASCADE, related_name="links")
    src = models.ForeignKey(ComputeNode, on_delete=models.CASCADE, related_name="+")
    dst = models.ForeignKey(ComputeNode, on_delete=models.CASCADE, related_name="+")
    bandwidth_mbps = models.FloatField(validators=[MinValueValidator(0.001)])
    latency_ms = models.FloatField(default=0.0, validators=[MinValueValidator(0.0)])

    class Meta:
        ordering = ["cluster", "src__name", "dst__name"]
        constraints = [models.UniqueConstraint(fields=["src", "dst"], name="unique_link")]

    def __str__(self) -> str:
        return f"{self.src}-{self.dst}"

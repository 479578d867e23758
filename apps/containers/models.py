"""ROS graphs, their clustering into containers (thesis 3.2.1) and the placement of containers on nodes (3.3.1).

Everything stored here is an engine document or an engine result as it comes out of the engine:
``RosGraph.document`` is ``continuum.rosgraph/v1``; ``Clustering.result`` is ``Clustering.to_dict()`` and
``Clustering.images`` is ``ImagePlan.to_dict()``; ``Placement.containers`` is the resolved
``continuum.containers/v1`` workload and ``Placement.plan`` is ``PlacementPlan.to_dict()`` with every node's
verdict. ``ContainerDeployment`` only records what pushing to Kubernetes did.
"""

from __future__ import annotations

from django.conf import settings
from django.db import models

from apps.tenancy.models import FleetOwned
from continuum.engine.containers.rosgraph import RosGraph as EngineRosGraph
from continuum.engine.containers.superclustering import Workload, load_workload
from continuum.engine.core.cluster import Cluster as EngineCluster
from continuum.engine.core.placement import PlacementPlan


class RosGraph(FleetOwned):
    """A robot's ROS 2 computation graph: ROS nodes, topics with rates and message sizes, levels."""

    class Format(models.TextChoices):
        ROSGRAPH = "rosgraph", "continuum.rosgraph/v1"
        AUTOWARE = "autoware", "Autoware reference system JSON"
        IROBOT = "irobot", "iRobot ros2-performance topology"
        DOT = "dot", "Graphviz .dot (rqt_graph)"

    name = models.CharField(max_length=200)
    description = models.TextField(blank=True)
    document = models.JSONField(help_text="the graph as continuum.rosgraph/v1")
    source_format = models.CharField(max_length=16, choices=Format.choices, default=Format.ROSGRAPH)
    node_count = models.PositiveIntegerField(default=0, editable=False)
    topic_count = models.PositiveIntegerField(default=0, editable=False)
    created_by = models.ForeignKey(settings.AUTH_USER_MODEL, null=True, blank=True, on_delete=models.SET_NULL)
    created = models.DateTimeField(auto_now_add=True)
    updated = models.DateTimeField(auto_now=True)

    class Meta:
        ordering = ["-created"]
        verbose_name = "ROS graph"

    def __str__(self) -> str:
        return self.name

    @property
    def graph(self) -> EngineRosGraph:
        return EngineRosGraph.from_dict(self.document)

    def set_graph(self, graph: EngineRosGraph) -> None:
        self.document = graph.to_dict()
        self.node_count = len(graph.nodes)
        self.topic_count = len(graph.topics)


class Clustering(FleetOwned):
    """ROS nodes grouped into containers by Listing 3.20, and the images planned for them (Fig. 3.24)."""

    rosgraph = models.ForeignKey(RosGraph, on_delete=models.CASCADE, related_name="clusterings")
    job = models.OneToOneField("jobs.Job", null=True, blank=True, on_delete=models.SET_NULL, related_name="clustering")
    requested_containers = models.PositiveIntegerField()
    container_count = models.PositiveIntegerField(default=0)
    params = models.JSONField(default=dict, blank=True, help_text="clustering and image options as given")
    graph_document = models.JSONField(help_text="the ROS graph as clustered (continuum.rosgraph/v1 snapshot)")
    result = models.JSONField(help_text="Clustering.to_dict(): containers with their ROS nodes, passes, bandwidth")
    inter_container_bandwidth = models.FloatField(help_text="bytes/s left between containers")
    intra_container_bandwidth = models.FloatField(help_text="bytes/s kept inside containers")
    images = models.JSONField(null=True, blank=True, help_text="ImagePlan.to_dict(), when ROS nodes list packages")
    disk_before_mib = models.FloatField(null=True, blank=True)
    disk_after_mib = models.FloatField(null=True, blank=True)
    created = models.DateTimeField(auto_now_add=True)

    class Meta:
        ordering = ["-created"]

    def __str__(self) -> str:
        return f"{self.rosgraph} in {self.container_count} containers"

    @property
    def graph(self) -> EngineRosGraph:
        return EngineRosGraph.from_dict(self.graph_document)

    @property
    def containers(self) -> list[dict]:
        return self.result.get("containers", [])

    def groups(self) -> dict[str, list[str]]:
        """Container name -> its ROS nodes."""
        return {c["name"]: list(c["nodes"]) for c in self.containers}


class Placement(FleetOwned):
    """Containers mapped to the nodes of a cluster (super-clustering or the default-Kubernetes baseline)."""

    clustering = models.ForeignKey(
        Clustering, null=True, blank=True, on_delete=models.CASCADE, related_name="placements"
    )
    rosgraph = models.ForeignKey(RosGraph, null=True, blank=True, on_delete=models.SET_NULL, related_name="placements")
    cluster = models.ForeignKey(
        "clusters.Cluster", null=True, blank=True, on_delete=models.SET_NULL, related_name="container_placements"
    )
    job = models.OneToOneField("jobs.Job", null=True, blank=True, on_delete=models.SET_NULL, related_name="placement")
    policy = models.CharField(max_length=32)
    params = models.JSONField(default=dict, blank=True)
    containers = models.JSONField(help_text="the resolved continuum.containers/v1 workload that was placed")
    cluster_document = models.JSONField(help_text="the nodes and links placed on (continuum.cluster/v1 snapshot)")
    plan = models.JSONField(help_text="PlacementPlan.to_dict(): placements, pending, every node's verdict, metrics")
    inter_node_bandwidth = models.FloatField(help_text="bytes/s between containers on different nodes")
    placed_count = models.PositiveIntegerField(default=0)
    pending_count = models.PositiveIntegerField(default=0)
    baseline = models.JSONField(
        null=True, blank=True, help_text="the other policy on the same input: policy, inter_node_bandwidth, placements"
    )
    created = models.DateTimeField(auto_now_add=True)

    class Meta:
        ordering = ["-created"]

    def __str__(self) -> str:
        return f"{self.policy} placement #{self.pk}"

    def workload(self) -> Workload:
        return load_workload(self.containers)

    def engine_cluster(self) -> EngineCluster:
        return EngineCluster.from_dict(self.cluster_document)

    def engine_plan(self) -> PlacementPlan:
        """The stored plan read back as the engine's type (``plan`` is ``PlacementPlan.to_dict()``)."""
        return PlacementPlan.from_dict(self.plan)

    def placed(self) -> dict[str, str]:
        # ``placements`` is derived from the decisions when stored: no need to read every verdict back.
        placements = (self.plan or {}).get("placements")
        if placements is None:
            return self.engine_plan().placed()
        return {p["container"]: p["node"] for p in placements}


class ContainerDeployment(models.Model):
    """What pushing one container of a placement to Kubernetes did (one Deployment per container)."""

    class State(models.TextChoices):
        NOT_PUSHED = "not_pushed"
        APPLIED = "applied"
        FAILED = "failed"
        #: Another placement of the same clustering was pushed since: its Deployment now runs elsewhere.
        SUPERSEDED = "superseded"

    placement = models.ForeignKey(Placement, on_delete=models.CASCADE, related_name="deployments")
    container = models.CharField(max_length=253)
    node = models.CharField(max_length=253, blank=True)
    deployment = models.CharField(max_length=253, blank=True)
    namespace = models.CharField(max_length=63, blank=True)
    state = models.CharField(max_length=16, choices=State.choices, default=State.NOT_PUSHED)
    #: created / updated / unchanged on the last push, or why it failed.
    message = models.CharField(max_length=500, blank=True)
    updated = models.DateTimeField(auto_now=True)
    #: The Deployment's newest pod, as stored by the cluster's watcher (``watch_cluster``).
    pod_name = models.CharField(max_length=253, blank=True)
    pod_phase = models.CharField(max_length=16, blank=True, help_text="Pending, Running, ..., Deleted")
    pod_node = models.CharField(max_length=253, blank=True, help_text="the node the pod is bound to")
    pod_event = models.CharField(max_length=500, blank=True, help_text="the pod's newest event: reason: message")
    pod_state_at = models.DateTimeField(null=True, blank=True, help_text="when the watcher last stored a change")

    class Meta:
        ordering = ["placement", "container"]
        constraints = [
            models.UniqueConstraint(fields=["placement", "container"], name="unique_deployment_per_container")
        ]

    def __str__(self) -> str:
        return f"{self.container}@{self.node or '-'}"

    @property
    def fleet_id(self) -> int:
        return self.placement.fleet_id

"""The ROS pages' forms. Clustering and placement requests are presentation layers over the API's request
contracts (:class:`~.serializers.ClusterRequestSerializer`, :class:`~.serializers.PlaceRequestSerializer`,
through :class:`apps.ui.forms.SerializerForm`), so a form and the API refuse the same input with the same
message and start the same job."""

from __future__ import annotations

import re

from django import forms
from django.conf import settings

from apps.clusters.models import Cluster
from apps.ui.forms import FleetSerializerForm, SerializerForm, contract_field, json_object
from continuum.engine.containers.rosgraph import LEVELS, MODES, READERS, RosGraph

from . import services
from .charts import LEVEL_LABELS
from .models import Clustering
from .models import RosGraph as RosGraphRow
from .serializers import (
    ClusterRequestSerializer,
    PlaceRequestSerializer,
    RosGraphEditSerializer,
    RosGraphImportSerializer,
    RosNodeEditSerializer,
    TopicEditSerializer,
)

FORMAT_LABELS = dict(RosGraphRow.Format.choices)
PLATFORMS = [("amd64", "amd64"), ("arm64", "arm64"), ("riscv64", "riscv64")]


class RosGraphUploadForm(FleetSerializerForm):
    """A ROS graph file: the API's import request (:class:`~.serializers.RosGraphImportSerializer`) as a form."""

    serializer_class = RosGraphImportSerializer

    file = forms.FileField(help_text="continuum.rosgraph/v1, Autoware reference system JSON, iRobot topology, .dot")
    format = contract_field(
        RosGraphImportSerializer,
        "format",
        choices=[("", "guess from the file"), *((f, FORMAT_LABELS.get(f, f)) for f in READERS)],
        help_text="",
    )
    name = contract_field(RosGraphImportSerializer, "name")
    fleet = forms.ModelChoiceField(queryset=None, required=True, empty_label=None)

    def serializer_data(self, data: dict) -> dict:
        return {k: data[k] for k in ("file", "format", "name") if data.get(k) not in (None, "")}


class LevelsForm(forms.Form):
    """One choice per ROS node: a Fig. 3.19 level, or the level proposed from the graph's structure."""

    def __init__(self, *args, graph: RosGraph, **kwargs):
        super().__init__(*args, **kwargs)
        self.graph = graph
        proposed = graph.levels()
        for name, node in sorted(graph.nodes.items()):
            field = forms.ChoiceField(
                label=name,
                required=False,
                initial=node.level or "",
                choices=[("", f"proposed: {LEVEL_LABELS[proposed[name]]}"), *((lv, LEVEL_LABELS[lv]) for lv in LEVELS)],
            )
            field.ros_node = name
            self.fields[f"level:{name}"] = field

    def levels(self) -> dict[str, str | None]:
        return {f.ros_node: self.cleaned_data.get(key) or None for key, f in self.fields.items()}


class _GraphEditForm(SerializerForm):
    """One row of the ROS graph page (a ROS node or a topic): the API's PATCH contract
    (:class:`~.serializers.RosGraphEditSerializer`) for that one item, so the page and PATCH refuse the same
    values with the same messages. ``auto_id`` is per row: the page holds one form per row."""

    serializer_class = RosGraphEditSerializer
    kind = ""

    def __init__(self, *args, rosgraph: RosGraphRow, item: str, **kwargs):
        slug = re.sub(r"[^A-Za-z0-9_-]", "_", item)
        kwargs.setdefault("auto_id", f"id_{self.kind}_{slug}_%s")
        super().__init__(*args, **kwargs)
        self.rosgraph, self.item = rosgraph, item
        # The row's inputs sit in table cells, outside the <form>: HTML's form attribute ties them to it.
        self.form_id = f"{self.kind}-form-{slug}"
        for field in self.fields.values():
            field.widget.attrs["form"] = self.form_id
            # Table cells are narrow: keep each value and each choice readable.
            width = "min-width: 9em" if isinstance(field, forms.ChoiceField) else "width: 8em"
            field.widget.attrs.setdefault("style", width)

    def serializer_context(self) -> dict:
        return {"rosgraph": self.rosgraph}

    def changes(self, data: dict) -> dict:
        raise NotImplementedError

    def serializer_data(self, data: dict) -> dict:
        return {f"{self.kind}s": {self.item: self.changes(data)}}

    def graph(self) -> RosGraph:
        return self.serializer.validated_data["graph"]


class TopicEditForm(_GraphEditForm):
    """A topic's publishing rate (every publisher) and message size."""

    kind = "topic"
    rate_hz = contract_field(TopicEditSerializer, "rate_hz", label="Rate (Hz)")
    msg_bytes = contract_field(TopicEditSerializer, "msg_bytes", label="Message (bytes)")

    def changes(self, data: dict) -> dict:
        # An empty rate keeps the current per-publisher rates (they may differ between publishers).
        return {k: data[k] for k in ("rate_hz", "msg_bytes") if data.get(k) is not None}


class RosNodeEditForm(_GraphEditForm):
    """A ROS node's level (Fig. 3.19), its pin to the robot, and its profile (CPU work, memory)."""

    kind = "node"
    level = forms.ChoiceField(required=False, label="Level")
    pin = contract_field(
        RosNodeEditSerializer,
        "pin",
        label="Pin",
        choices=[("", "by level"), ("robot", "on the robot"), ("free", "free (unpinned)")],
        help_text="",
    )
    cpu = contract_field(RosNodeEditSerializer, "cpu", label="CPU work (cores)")
    memory_mib = contract_field(RosNodeEditSerializer, "memory_mib", label="Profiled memory (MiB)")

    def __init__(self, *args, proposed: str, **kwargs):
        super().__init__(*args, **kwargs)
        self.fields["level"].choices = [
            ("", f"proposed: {LEVEL_LABELS[proposed]}"),
            *((lv, LEVEL_LABELS[lv]) for lv in LEVELS),
        ]

    def changes(self, data: dict) -> dict:
        return {
            "level": data.get("level") or None,
            "pin": data.get("pin") or None,
            "cpu": data.get("cpu") or 0.0,
            "memory_mib": data.get("memory_mib") or 0.0,
        }


class ClusterForm(SerializerForm):
    serializer_class = ClusterRequestSerializer
    C = ClusterRequestSerializer

    containers = contract_field(C, "containers", label="Containers (N)", help_text="")
    memory_mib = contract_field(C, "memory_mib", label="Memory for containers (MiB)", help_text="")
    overhead_mib = contract_field(
        C, "overhead_mib", label="Overhead per container (MiB)", help_text="29 Docker, 39 K3s (Table 4.17)"
    )
    mode = contract_field(
        C, "mode", choices=[(m, m.replace("_", " ")) for m in MODES], required=True, label="Eq. 3.12", help_text=""
    )
    max_cluster_share = contract_field(C, "max_cluster_share", label="Largest share of ROS nodes")
    max_cluster_memory_mib = contract_field(C, "max_cluster_memory_mib", label="Largest container memory (MiB)")
    distro_image = forms.CharField(initial=services.IMAGE_DEFAULTS["distro_image"], label="ROS base image")
    ros_distro = forms.CharField(initial=services.IMAGE_DEFAULTS["ros_distro"], label="ROS distribution")
    distro_mib = forms.FloatField(min_value=0, initial=0, label="Base image size (MiB)")
    platforms = forms.MultipleChoiceField(
        choices=PLATFORMS, initial=services.IMAGE_DEFAULTS["platforms"], widget=forms.CheckboxSelectMultiple
    )
    repository = forms.CharField(initial=services.IMAGE_DEFAULTS["repository"], required=False)
    tag = forms.CharField(initial=services.IMAGE_DEFAULTS["tag"])

    IMAGE_FIELDS = ("distro_image", "ros_distro", "distro_mib", "platforms", "repository", "tag")

    def serializer_data(self, data: dict) -> dict:
        payload = {k: v for k, v in data.items() if k not in self.IMAGE_FIELDS and v not in (None, "")}
        payload["images"] = {k: data[k] for k in self.IMAGE_FIELDS if data.get(k) not in (None, "")}
        return payload

    def job_arguments(self, rosgraph: RosGraphRow) -> dict:  # type: ignore[override]
        return self.serializer.job_arguments(rosgraph)


class PlaceForm(SerializerForm):
    POLICIES = [
        ("superclustering", "super-clustering (bandwidth, Eqs. 3.14-3.15)"),
        ("default-kubernetes", "default Kubernetes (least allocated + balanced)"),
    ]

    cluster = forms.ModelChoiceField(queryset=None, empty_label="— choose a cluster —")
    policy = forms.ChoiceField(choices=POLICIES, initial="superclustering", widget=forms.RadioSelect)
    overhead_mib = forms.FloatField(min_value=0, initial=0, label="Runtime memory per container (MiB)")
    seed = forms.IntegerField(initial=0, help_text="tie-break seed of the default-Kubernetes policy")
    compare = forms.BooleanField(required=False, initial=True, label="Also run the other policy for comparison")
    drivers_on_robot = forms.BooleanField(
        required=False,
        label="Keep driver-level ROS nodes on the robot",
        help_text="containers holding drivers (or ROS nodes pinned to the robot) only go to the robot's boards",
    )
    robot_label = contract_field(PlaceRequestSerializer, "robot_label", label="Robot boards' label")
    overrides = forms.CharField(
        required=False,
        widget=forms.Textarea(attrs={"rows": 3, "placeholder": '{"BehaviorPlanner": {"cpu": 1.5, "priority": 1}}'}),
        help_text="per container: cpu, memory_mib, priority, archs, node, node_selector, tolerations (JSON)",
    )

    def __init__(self, *args, clustering: Clustering, request, **kwargs):
        super().__init__(*args, **kwargs)
        self.clustering = clustering
        self.request = request
        self.fields["cluster"].queryset = Cluster.objects.filter(fleet_id=clustering.fleet_id).order_by("name")
        self.fields["drivers_on_robot"].initial = settings.CONTINUUM_DRIVERS_ON_ROBOT
        self.fields["robot_label"].initial = settings.CONTINUUM_ROBOT_LABEL

    def clean_overrides(self) -> dict:
        return json_object(self.cleaned_data.get("overrides"), "a JSON object: container name -> changes")

    serializer_class = PlaceRequestSerializer
    error_fields = {"containers": "overrides", "clustering": "cluster"}

    def serializer_context(self) -> dict:
        return {"request": self.request}

    def serializer_data(self, data: dict) -> dict:
        return {
            "cluster": data["cluster"].pk,
            "policy": data["policy"],
            "clustering": self.clustering.pk,
            "overrides": data.get("overrides") or {},
            "overhead_mib": data["overhead_mib"],
            "seed": data["seed"],
            "compare": data.get("compare", False),
            "drivers_on_robot": data.get("drivers_on_robot", False),
            "robot_label": data.get("robot_label") or settings.CONTINUUM_ROBOT_LABEL,
        }

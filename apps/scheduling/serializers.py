from django.urls import reverse
from drf_spectacular.utils import extend_schema_field
from rest_framework import serializers

from apps.clusters.serializers import VisibleClusterField
from apps.tenancy.api import ScopedModelSerializer, ScopedSerializer
from apps.tenancy.bounds import at_most
from continuum.engine.core import limits
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Platform
from continuum.engine.core.unique import duplicates
from continuum.engine.device.algorithms import SCHEDULERS
from continuum.engine.device.compare import DEFAULT_ALGORITHMS
from continuum.engine.device.heft import COMM_MODES, RANK_MODES

from .models import Assignment, Comparison, Schedule

#: Most frames one request may schedule (README, "Limits").
MAX_FRAMES = limits.get().frames
FRAME_OPTIONS = ("frames", "fps", "period", "batch")


#: The algorithms the API offers (one OpenAPI enum, AlgorithmEnum).
ALGORITHM_CHOICES = sorted(SCHEDULERS)
#: An unknown algorithm, in the engine's words (``continuum.engine.device.algorithms.run``).
UNKNOWN_ALGORITHM = {"invalid_choice": "unknown algorithm '{input}' (choose from " + ", ".join(ALGORITHM_CHOICES) + ")"}


FPS_OR_PERIOD = "give either FPS or a period, not both (either fps or period sets when frames are released)"


def positive(name: str, kind: str) -> dict[str, str]:
    """``error_messages`` for a count that must be positive, in the engine's words (and DRF's)."""
    return {"min_value": f"{name} must be a positive {kind} (greater than or equal to {{min_value}})"}


class TargetSerializer(ScopedSerializer):
    """A cluster (its Ready nodes) or a ``continuum.platform/v1`` document, and the frame options.

    The request contract of the API's schedule and compare actions and of the dashboard's forms
    (``apps/scheduling/forms.py``). ``context["application"]`` is the application to schedule; ``job_arguments()``
    gives the job's arguments.
    """

    cluster = VisibleClusterField(required=False)
    platform = serializers.JSONField(required=False, help_text="a continuum.platform/v1 document")
    frames = serializers.IntegerField(
        required=False,
        min_value=1,
        max_value=MAX_FRAMES,
        error_messages=at_most("frames") | positive("frames", "integer"),
        help_text="schedule this many frames (pipelined)",
    )
    fps = serializers.FloatField(
        required=False,
        min_value=1e-9,
        error_messages={"min_value": "fps must be a positive number"},
        help_text="camera rate: frame f released at f/fps",
    )
    period = serializers.FloatField(
        required=False, min_value=0, help_text="frame period in the DAG's time unit (instead of fps)"
    )
    batch = serializers.IntegerField(
        required=False,
        min_value=1,
        max_value=MAX_FRAMES,
        error_messages=at_most("batch") | positive("batch", "integer"),
        help_text="frames buffered and released together",
    )

    def validate_platform(self, value):
        try:
            Platform.from_dict(value)
        except InputError as exc:
            raise serializers.ValidationError(str(exc)) from exc
        return value

    def validate(self, attrs):
        attrs = super().validate(attrs)
        if ("cluster" in attrs) == ("platform" in attrs):
            raise serializers.ValidationError({"cluster": ["give exactly one of 'cluster' and 'platform'"]})
        if "fps" in attrs and "period" in attrs:
            raise serializers.ValidationError({"fps": [FPS_OR_PERIOD]})
        application, cluster = self.context.get("application"), attrs.get("cluster")
        if cluster is not None and application is not None and cluster.fleet_id != application.fleet_id:
            raise serializers.ValidationError({"cluster": ["the cluster belongs to another fleet"]})
        return attrs

    def frame_options(self) -> dict:
        return {k: self.validated_data[k] for k in FRAME_OPTIONS if k in self.validated_data}

    def target_args(self) -> dict:
        data = self.validated_data
        if data.get("cluster") is not None:
            return {"cluster": data["cluster"].pk}
        return {"platform": data["platform"]}

    def runnable_errors(self) -> dict[str | None, str]:
        """Why the job would fail on this target (a cluster without a Ready node, a task no processor can
        run), for a page that says so before starting it; the API starts the job, which fails saying so."""
        data = self.validated_data
        cluster = data.get("cluster")
        if cluster is not None:
            if not cluster.nodes.filter(status="Ready").exists():
                return {"cluster": f"cluster {cluster.name!r} has no Ready node"}
            try:
                platform = cluster.to_platform()
            except InputError as exc:  # Ready nodes, but all tainted or RT-only (the one taint filter)
                return {"cluster": str(exc)}
        else:
            platform = Platform.from_dict(data["platform"])
        try:
            platform.cost_table(self.context["application"].graph)
        except InputError as exc:
            return {None: f"cannot schedule on this target: {exc}"}
        return {}


class ScheduleRequestSerializer(TargetSerializer):
    """Schedule an application on a cluster (its Ready nodes) or on a platform document, for one frame or
    several (``frames``, ``fps`` or ``period``, ``batch``: thesis Eqs. 3.5-3.7)."""

    algorithm = serializers.ChoiceField(choices=ALGORITHM_CHOICES, default="heft", error_messages=UNKNOWN_ALGORITHM)
    params = serializers.DictField(required=False, default=dict, help_text="algorithm parameters, e.g. rank_mode")

    def validate(self, attrs):
        attrs = super().validate(attrs)
        clash = sorted(k for k in FRAME_OPTIONS if k in attrs and k in attrs["params"])
        if clash:
            message = f"{clash[0]} is given both as a field and in the parameters (params); give it once"
            raise serializers.ValidationError({clash[0]: [message]})
        # Frame options given in params are checked exactly like the fields (the same bounds).
        for key in FRAME_OPTIONS:
            if key in attrs["params"]:
                try:
                    attrs[key] = self.fields[key].run_validation(attrs["params"].pop(key))
                except serializers.ValidationError as exc:
                    raise serializers.ValidationError({"params": {key: exc.detail}}) from exc
        attrs["params"] = {**attrs["params"], **{k: attrs[k] for k in FRAME_OPTIONS if k in attrs}}
        return attrs

    def job_arguments(self) -> dict:
        """The schedule job's arguments (``apps/scheduling/jobs.py``)."""
        data = self.validated_data
        arguments = {"application": self.context["application"].pk, "algorithm": data["algorithm"]}
        return arguments | {"params": data["params"]} | self.target_args()


class CompareRequestSerializer(TargetSerializer):
    """Run several algorithms on one application and target and compare them (thesis Tables 4.1, 4.3)."""

    algorithms = serializers.ListField(
        child=serializers.ChoiceField(choices=ALGORITHM_CHOICES),
        default=list(DEFAULT_ALGORITHMS),
        min_length=1,
        max_length=len(SCHEDULERS),
    )
    rank_mode = serializers.ChoiceField(
        choices=RANK_MODES, default="max", help_text="upward-rank cost for every rank-based algorithm (thesis: max)"
    )
    comm_mode = serializers.ChoiceField(
        choices=COMM_MODES, default="impl", help_text="upward-rank transfer (thesis: impl)"
    )

    def validate_algorithms(self, value):
        dup = sorted(duplicates(value))
        if dup:
            raise serializers.ValidationError(f"{dup[0]!r} is listed twice")
        return value

    def job_arguments(self) -> dict:
        """The compare job's arguments (``apps/scheduling/jobs.py``)."""
        data = self.validated_data
        arguments = {
            "application": self.context["application"].pk,
            "algorithms": data["algorithms"],
            "rank_mode": data["rank_mode"],
            "comm_mode": data["comm_mode"],
        }
        return arguments | self.frame_options() | self.target_args()


class AssignmentSerializer(ScopedModelSerializer):
    class Meta:
        model = Assignment
        fields = [
            "task",
            "frame",
            "processor",
            "core",
            "start",
            "finish",
            "niceness",
            "placement",
            "placement_message",
            "pod_name",
            "pod_phase",
            "pod_node",
            "pod_event",
            "pod_state_at",
        ]
        #: Live state, stored by ``watch_cluster``.
        read_only_fields = ["pod_phase", "pod_node", "pod_event", "pod_state_at"]


class AssignmentFilterSerializer(ScopedSerializer):
    """Which assignments of one schedule to list: the request contract of ``GET
    /api/v1/schedules/{id}/assignments/`` and of the schedule page's table filter. ``context["processors"]``
    is the schedule's processors: naming another is a 400 rather than an empty page."""

    task = serializers.CharField(
        required=False, max_length=200, allow_blank=True, help_text="part of the task's id (case-insensitive)"
    )
    processor = serializers.CharField(
        required=False, max_length=253, allow_blank=True, help_text="the processor (node) it runs on, exactly"
    )
    frame = serializers.IntegerField(
        required=False, min_value=0, max_value=MAX_FRAMES, error_messages=at_most("frame"), help_text="the frame"
    )
    placement = serializers.ChoiceField(
        required=False, choices=Assignment.Placement.choices, help_text="its Kubernetes placement status"
    )

    def validate_processor(self, value: str) -> str:
        processors = self.context.get("processors")
        if value and processors is not None and value not in processors:
            raise serializers.ValidationError(f"no processor {value!r} in this schedule")
        return value

    def filter(self, queryset):
        """``queryset`` (assignments) narrowed to the validated filters."""
        data = self.validated_data
        if data.get("task"):
            queryset = queryset.filter(task__icontains=data["task"])
        if data.get("processor"):
            queryset = queryset.filter(processor=data["processor"])
        if data.get("frame") is not None:
            queryset = queryset.filter(frame=data["frame"])
        if data.get("placement"):
            queryset = queryset.filter(placement=data["placement"])
        return queryset


#: Assignments the schedule detail carries inline at most; the rest from its assignments endpoint (issue 15:
#: 10,000 inline assignments made a 1.9 MB answer).
MAX_INLINE_ASSIGNMENTS = 1000


class ScheduleSerializer(ScopedModelSerializer):
    """A stored schedule in the ``continuum.schedule/v1`` shape, plus its placement status per task.

    Bounded: ``assignments`` holds the first :data:`MAX_INLINE_ASSIGNMENTS` (in start order);
    ``assignment_count`` says how many there are, ``assignments_complete`` whether all are inline, and
    ``assignments_url`` lists them all, paginated and filterable."""

    format = serializers.SerializerMethodField()
    fleet = serializers.SlugRelatedField(slug_field="slug", read_only=True)
    assignments = serializers.SerializerMethodField()
    assignment_count = serializers.SerializerMethodField()
    assignments_complete = serializers.SerializerMethodField()
    assignments_url = serializers.SerializerMethodField()

    class Meta:
        model = Schedule
        fields = [
            "id",
            "format",
            "fleet",
            "application",
            "cluster",
            "job",
            "comparison",
            "algorithm",
            "params",
            "makespan",
            "ranks",
            "metrics",
            "platform",
            "assignments",
            "assignment_count",
            "assignments_complete",
            "assignments_url",
            "created",
        ]
        read_only_fields = fields

    def get_format(self, obj) -> str:
        return "continuum.schedule/v1"

    def _inline(self, obj) -> list:
        # One query for the first rows plus one over the limit: the count only when they do not all fit.
        if not hasattr(obj, "_inline_assignments"):
            rows = list(obj.assignments.all()[: MAX_INLINE_ASSIGNMENTS + 1])
            obj._inline_assignments = rows[:MAX_INLINE_ASSIGNMENTS]
            # Past the inline rows, the count stored with the schedule (every row counted was 530 ms of CPU at
            # 100,000 assignments); a schedule stored before the column was filled is counted.
            more = len(rows) > MAX_INLINE_ASSIGNMENTS
            obj._assignment_count = (obj.task_count or obj.assignments.count()) if more else len(rows)
        return obj._inline_assignments

    @extend_schema_field(AssignmentSerializer(many=True))
    def get_assignments(self, obj) -> list:
        return AssignmentSerializer(self._inline(obj), many=True, context=self.context).data

    def get_assignment_count(self, obj) -> int:
        self._inline(obj)
        return obj._assignment_count

    def get_assignments_complete(self, obj) -> bool:
        return len(self._inline(obj)) == obj._assignment_count

    def get_assignments_url(self, obj) -> str:
        url = reverse("api:schedule-assignments", args=[obj.pk])
        request = self.context.get("request")
        return request.build_absolute_uri(url) if request is not None else url


class ScheduleListSerializer(ScopedModelSerializer):
    """A stored schedule in a list: its small columns only (never its assignments, ranks or platform)."""

    fleet = serializers.SlugRelatedField(slug_field="slug", read_only=True)

    class Meta:
        model = Schedule
        fields = ["id", "fleet", "application", "cluster", "job", "algorithm", "makespan", "created"]
        read_only_fields = fields


class ComparisonScheduleSerializer(ScopedModelSerializer):
    url = serializers.HyperlinkedIdentityField(view_name="api:schedule-detail")

    class Meta:
        model = Schedule
        fields = ["id", "url", "algorithm", "makespan"]
        read_only_fields = fields


class ComparisonSerializer(ScopedModelSerializer):
    """A comparison: per algorithm makespan, SLR, speedup against VisionWorks, O/XO, idle time (``figures``),
    Table 4.3's relative speeds, and links to each algorithm's stored schedule."""

    fleet = serializers.SlugRelatedField(slug_field="slug", read_only=True)
    figures = serializers.SerializerMethodField()
    relative = serializers.SerializerMethodField()
    reference_makespan = serializers.SerializerMethodField()
    schedules = serializers.SerializerMethodField()

    class Meta:
        model = Comparison
        fields = [
            "id",
            "fleet",
            "application",
            "cluster",
            "job",
            "algorithms",
            "params",
            "best",
            "reference_makespan",
            "figures",
            "relative",
            "schedules",
            "platform",
            "created",
        ]
        read_only_fields = fields

    def get_figures(self, obj) -> dict:
        return obj.result.get("results", {})

    def get_relative(self, obj) -> dict:
        return obj.result.get("relative", {})

    def get_reference_makespan(self, obj) -> float | None:
        return obj.result.get("reference_makespan")

    def get_schedules(self, obj) -> list[dict]:
        return ComparisonScheduleSerializer(obj.ordered_schedules(), many=True, context=self.context).data


class ComparisonListSerializer(ComparisonSerializer):
    class Meta(ComparisonSerializer.Meta):
        fields = ["id", "fleet", "application", "cluster", "job", "algorithms", "params", "best", "created"]

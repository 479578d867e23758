"""Stored schedules: one row per assignment, with its Kubernetes placement status."""

import dataclasses
from collections.abc import Sequence
from typing import Any

from django.db import connection, models
from django.db.models import F, Func, IntegerField, Value

from apps.tenancy.models import FleetOwned
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import Assignment as EngineAssignment
from continuum.engine.core.schedule import Schedule as EngineSchedule

#: The fields an assignment row shares with the engine's Assignment (the rest is Kubernetes placement status).
ENGINE_FIELDS = tuple(f.name for f in dataclasses.fields(EngineAssignment))
#: Rows per INSERT when COPY is not available (SQLite allows 32,766 variables a statement; 15 columns a row).
STORE_BATCH = 2000


class JSONArrayLength(Func):
    """The length of the JSON array at ``path`` (one key) inside a JSON column, computed by the database so
    that the column itself is never sent to Python; NULL when the key is missing or not an array."""

    output_field = IntegerField()

    def __init__(self, expression, path: str, **extra):
        super().__init__(expression, Value(path), **extra)

    def as_sql(self, compiler, connection, **extra):  # SQLite (and MySQL): json_array_length(col, '$.key')
        column, _ = compiler.compile(self.source_expressions[0])
        path = self.source_expressions[1].value
        return f"json_array_length({column}, %s)", ["$." + path]

    def as_postgresql(self, compiler, connection, **extra):
        column, _ = compiler.compile(self.source_expressions[0])
        path = self.source_expressions[1].value
        # jsonb_array_length raises on a non-array: only call it on one.
        sql = f"CASE WHEN jsonb_typeof({column} -> %s) = 'array' THEN jsonb_array_length({column} -> %s) END"
        return sql, [path, path]


#: What a list page shows of a schedule's or comparison's fleet, application and cluster (never a DAG or a
#: kubeconfig).
RELATED_LIST_FIELDS = (
    "fleet__id",
    "fleet__name",
    "application__id",
    "application__name",
    "cluster__id",
    "cluster__name",
)


class ScheduleQuerySet(models.QuerySet):
    def for_list(self) -> "ScheduleQuerySet":
        """Schedules for a list page: only the small columns of the schedule and its application, fleet and
        cluster (never a DAG, platform, ranks, metrics or kubeconfig). ``task_count`` and ``time_unit`` are
        stored with the schedule: counting 10,000 assignment rows per listed schedule kept the list at 0.4 s
        with 100 large schedules, and the unit would otherwise come from the DAG JSON (issue 13).
        ``processor_count`` is read inside the database from the platform JSON."""
        return (
            self.select_related("fleet", "application", "cluster")
            .only(
                "id",
                "algorithm",
                "makespan",
                "task_count",
                "time_unit",
                "created",
                *RELATED_LIST_FIELDS,
            )
            .annotate(processor_count=JSONArrayLength(F("platform"), "processors"))
        )


class Schedule(FleetOwned):
    application = models.ForeignKey("workloads.Application", on_delete=models.CASCADE, related_name="schedules")
    cluster = models.ForeignKey(
        "clusters.Cluster", null=True, blank=True, on_delete=models.SET_NULL, related_name="schedules"
    )
    job = models.OneToOneField("jobs.Job", null=True, blank=True, on_delete=models.SET_NULL, related_name="schedule")
    comparison = models.ForeignKey(
        "Comparison",
        null=True,
        blank=True,
        on_delete=models.CASCADE,
        related_name="schedules",
        help_text="the comparison that made this schedule, if any",
    )
    platform = models.JSONField(help_text="the platform scheduled on, as continuum.platform/v1")
    algorithm = models.CharField(max_length=50)
    params = models.JSONField(default=dict, blank=True)
    makespan = models.FloatField()
    #: Stored with the assignments (``store``) so that list pages read neither the rows nor the DAG.
    task_count = models.PositiveIntegerField(default=0, editable=False, help_text="assignments stored")
    time_unit = models.CharField(max_length=16, default="ms", editable=False, help_text="the DAG's time unit")
    ranks = models.JSONField(default=dict, blank=True)
    metrics = models.JSONField(default=dict, blank=True)
    created = models.DateTimeField(auto_now_add=True)

    objects = ScheduleQuerySet.as_manager()

    class Meta:
        ordering = ["-created"]

    def __str__(self) -> str:
        return f"{self.algorithm} schedule of {self.application}"

    @classmethod
    def store(
        cls, result: EngineSchedule, *, application, platform: Platform, cluster=None, job=None, comparison=None
    ) -> "Schedule":
        """Persist an engine schedule (replacing the one an earlier attempt of ``job`` stored)."""
        if job is not None:
            cls.objects.filter(job=job).delete()
        row = cls.objects.create(
            fleet_id=application.fleet_id,
            application=application,
            cluster=cluster,
            job=job,
            comparison=comparison,
            platform=platform.to_dict(),
            algorithm=result.algorithm,
            params=result.params,
            makespan=result.makespan,
            task_count=len(result.assignments),
            time_unit=str((application.dag or {}).get("time_unit", "ms"))[:16],
            ranks=result.ranks,
            metrics=result.metrics,
        )
        Assignment.store_many(row, result.assignments)
        return row

    def to_engine(self) -> EngineSchedule:
        """The stored schedule as the engine's type: ``Schedule.store(s, ...).to_engine()`` gives ``s`` back,
        its assignments in the rows' order (start, processor, task)."""
        cached = getattr(self, "_prefetched_objects_cache", {}).get("assignments")
        if cached is not None:
            assignments = [a.to_engine() for a in cached]
        else:  # plain tuples from the database: no model instance per row (10,000 rows in tens of ms)
            rows = self.assignments.order_by(*Assignment._meta.ordering).values_list(*ENGINE_FIELDS)
            assignments = [EngineAssignment(*row) for row in rows]
        return EngineSchedule(
            self.algorithm,
            assignments,
            ranks=self.ranks,
            params=self.params,
            metrics=self.metrics,
        )

    def engine_platform(self) -> Platform:
        return Platform.from_dict(self.platform)


class ComparisonQuerySet(models.QuerySet):
    def for_list(self) -> "ComparisonQuerySet":
        """Comparisons for a list page: the small columns of the comparison, its application, fleet and cluster
        (never the result, the platform or a DAG) and ``processor_count`` read inside the database."""
        return (
            self.select_related("fleet", "application", "cluster")
            .only(
                "id",
                "algorithms",
                "params",
                "best",
                "created",
                *RELATED_LIST_FIELDS,
            )
            .annotate(processor_count=JSONArrayLength(F("platform"), "processors"))
        )


class Comparison(FleetOwned):
    """Several algorithms run on one application and target in one job (thesis Tables 4.1 and 4.3).

    ``result`` is :func:`continuum.engine.device.compare.compare`'s dict (makespan, SLR, speedup against
    VisionWorks, overlap, XO, idle time per algorithm, and the relative speeds); each algorithm's schedule is
    a normal :class:`Schedule` row pointing here.
    """

    application = models.ForeignKey("workloads.Application", on_delete=models.CASCADE, related_name="comparisons")
    cluster = models.ForeignKey(
        "clusters.Cluster", null=True, blank=True, on_delete=models.SET_NULL, related_name="comparisons"
    )
    job = models.OneToOneField("jobs.Job", null=True, blank=True, on_delete=models.SET_NULL, related_name="comparison")
    platform = models.JSONField(help_text="the platform compared on, as continuum.platform/v1")
    algorithms = models.JSONField(help_text="the algorithms compared, in the order asked")
    params = models.JSONField(default=dict, blank=True, help_text="frames, fps/period, batch, rank_mode, comm_mode")
    result = models.JSONField(help_text="continuum.engine.device.compare.compare()'s figures")
    best = models.CharField(max_length=50, blank=True)
    created = models.DateTimeField(auto_now_add=True)

    objects = ComparisonQuerySet.as_manager()

    class Meta:
        ordering = ["-created"]

    def __str__(self) -> str:
        return f"comparison of {', '.join(self.algorithms)} on {self.application}"

    def ordered_schedules(self) -> list["Schedule"]:
        """Its schedules in the order the algorithms were asked for."""
        rank = {name: i for i, name in enumerate(self.algorithms)}
        return sorted(self.schedules.all(), key=lambda s: (rank.get(s.algorithm, len(rank)), s.pk))


class Assignment(models.Model):
    class Placement(models.TextChoices):
        NOT_PUSHED = "not_pushed"
        BOUND = "bound"
        FAILED = "failed"

    schedule = models.ForeignKey(Schedule, on_delete=models.CASCADE, related_name="assignments")
    task = models.CharField(max_length=200)
    frame = models.PositiveIntegerField(default=0)
    processor = models.CharField(max_length=253)
    start = models.FloatField()
    finish = models.FloatField()
    niceness = models.SmallIntegerField(null=True, blank=True)
    core = models.PositiveSmallIntegerField(null=True, blank=True, help_text="CPU of a multi-core node")
    placement = models.CharField(max_length=16, choices=Placement.choices, default=Placement.NOT_PUSHED)
    placement_message = models.CharField(max_length=500, blank=True)
    pod_name = models.CharField(max_length=253, blank=True)
    #: Live state, stored by the cluster's watcher (``watch_cluster``) from the pod's watch and Events.
    pod_phase = models.CharField(max_length=16, blank=True, help_text="Pending, Running, ..., Deleted")
    pod_node = models.CharField(max_length=253, blank=True, help_text="the node the pod is bound to")
    pod_event = models.CharField(max_length=500, blank=True, help_text="the pod's newest event: reason: message")
    pod_state_at = models.DateTimeField(null=True, blank=True, help_text="when the watcher last stored a change")

    class Meta:
        ordering = ["start", "processor", "task"]
        constraints = [models.UniqueConstraint(fields=["schedule", "task", "frame"], name="unique_assignment")]
        # Keyset pages and the export (apps/scheduling/reads.py) read a schedule in this order from the index.
        indexes = [models.Index(fields=["schedule", "start", "processor", "task", "frame"], name="assignment_keyset")]

    def __str__(self) -> str:
        return f"{self.task}@{self.processor}"

    @classmethod
    def store_many(cls, schedule: Schedule, assignments: Sequence[EngineAssignment]) -> None:
        """Insert the rows of ``schedule``'s assignments in one bulk write: PostgreSQL's ``COPY`` (one
        statement, no per-row SQL: 10,000 rows in a few tens of ms), else ``bulk_create`` in batches of
        :data:`STORE_BATCH` (SQLite's limit on variables per statement). Row by row, a 1000-task x 10-frame
        job sat at "storing the schedule" for most of its run (issues 13 and 15)."""
        if connection.vendor != "postgresql":
            cls.objects.bulk_create((cls.from_engine(a, schedule) for a in assignments), batch_size=STORE_BATCH)
            return
        fields = [f for f in cls._meta.concrete_fields if not f.primary_key]
        # Every column that is not the schedule or an engine field gets the model's default, once.
        defaults = {f.attname: f.get_default() for f in fields}
        names = [f.attname for f in fields]
        engine = set(ENGINE_FIELDS)
        q = connection.ops.quote_name
        sql = f"COPY {q(cls._meta.db_table)} ({', '.join(q(f.column) for f in fields)}) FROM STDIN"
        # wrap_database_errors: a violated constraint raises Django's IntegrityError, as bulk_create would.
        with connection.wrap_database_errors, connection.cursor() as cursor, cursor.cursor.copy(sql) as copy:
            for a in assignments:
                copy.write_row(
                    [
                        schedule.pk if name == "schedule_id" else getattr(a, name) if name in engine else defaults[name]
                        for name in names
                    ]
                )

    #: Rows per statement of :meth:`store_placements` (4 parameters a row, below PostgreSQL's 65,535).
    PLACEMENT_BATCH = 10_000

    @classmethod
    def store_placements(cls, rows: Sequence["Assignment"]) -> int:
        """Write ``placement``, ``placement_message`` and ``pod_name`` of ``rows`` back, changing only the rows
        whose values differ; returns how many it changed. On PostgreSQL one ``UPDATE ... FROM (VALUES ...)``
        per :data:`PLACEMENT_BATCH` rows (``bulk_update`` built one ``CASE WHEN`` per row and column: most of a
        1,000-pod push's main thread, and all of a re-push that changes nothing); elsewhere ``bulk_update``."""
        if not rows:
            return 0
        if connection.vendor != "postgresql":
            cls.objects.bulk_update(rows, ["placement", "placement_message", "pod_name"], batch_size=STORE_BATCH)
            return len(rows)
        q = connection.ops.quote_name
        table = q(cls._meta.db_table)
        changed = 0
        with connection.cursor() as cursor:
            for at in range(0, len(rows), cls.PLACEMENT_BATCH):
                batch = rows[at : at + cls.PLACEMENT_BATCH]
                values = ", ".join(["(%s::bigint, %s::varchar, %s::varchar, %s::varchar)"] * len(batch))
                params: list[Any] = []
                for r in batch:
                    params += [r.pk, r.placement, r.placement_message, r.pod_name]
                cursor.execute(
                    f"UPDATE {table} AS a SET placement = v.placement, placement_message = v.message, "
                    f"pod_name = v.pod_name FROM (VALUES {values}) AS v(id, placement, message, pod_name) "
                    "WHERE a.id = v.id AND (a.placement, a.placement_message, a.pod_name) "
                    "IS DISTINCT FROM (v.placement, v.message, v.pod_name)",
                    params,
                )
                changed += cursor.rowcount
        return changed

    @classmethod
    def from_engine(cls, assignment: EngineAssignment, schedule: Schedule) -> "Assignment":
        """An (unsaved) row of ``schedule`` for one engine assignment; the fields are the engine's, by name."""
        return cls(schedule=schedule, **{name: getattr(assignment, name) for name in ENGINE_FIELDS})

    def to_engine(self) -> EngineAssignment:
        return EngineAssignment(**{name: getattr(self, name) for name in ENGINE_FIELDS})

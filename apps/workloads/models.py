"""Applications: DAGs of tasks stored in the ``continuum.dag/v1`` shape."""

from django.conf import settings
from django.db import models

from apps.tenancy.models import FleetOwned
from continuum.engine.core.dag import TaskGraph


class Application(FleetOwned):
    name = models.CharField(max_length=200)
    description = models.TextField(blank=True)
    dag = models.JSONField(help_text="the DAG as continuum.dag/v1")
    source_format = models.CharField(max_length=32, default="continuum")
    task_count = models.PositiveIntegerField(default=0, editable=False)
    edge_count = models.PositiveIntegerField(default=0, editable=False)
    #: SHA-256 of the uploaded file's bytes, format and reader options (``serializers.upload_digest``): a
    #: second upload of the same file to the fleet is refused unless asked for (``duplicate=allow``). Empty
    #: for applications not made from a file.
    content_sha256 = models.CharField(max_length=64, blank=True, default="", editable=False, db_index=True)
    created_by = models.ForeignKey(settings.AUTH_USER_MODEL, null=True, blank=True, on_delete=models.SET_NULL)
    created = models.DateTimeField(auto_now_add=True)
    updated = models.DateTimeField(auto_now=True)

    #: The columns a list shows (never the DAG JSON or the description).
    LIST_FIELDS = ("id", "fleet", "name", "source_format", "task_count", "edge_count", "created")

    class Meta:
        ordering = ["-created"]

    def __str__(self) -> str:
        return self.name

    @property
    def graph(self) -> TaskGraph:
        return TaskGraph.from_dict(self.dag)

    def set_graph(self, graph: TaskGraph) -> None:
        self.dag = graph.to_dict()
        self.task_count = len(graph.tasks)
        self.edge_count = len(graph.edges)

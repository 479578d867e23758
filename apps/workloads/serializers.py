import hashlib
import json

from rest_framework import serializers

from apps.tenancy.api import ChosenFleetMixin, DefaultFleetMixin, FleetField, FleetOwnedSerializer, ScopedSerializer
from apps.tenancy.bounds import BoundedFileField, at_most
from continuum.engine.core import limits
from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.errors import InputError
from continuum.engine.device import generators

from .importing import FORMATS, GENERATORS, generate_dag, parse_options, read_dag_file
from .models import Application

LIMITS = limits.get()
#: What an upload of a file the fleet holds already does (``ApplicationImportSerializer.duplicate``).
DUPLICATE_CHOICES = ["refuse", "allow"]


class ApplicationSerializer(FleetOwnedSerializer):
    """An application with its DAG in ``continuum.dag/v1``; a bad DAG is rejected whole, naming the culprit."""

    class Meta:
        model = Application
        fields = [
            "id",
            "fleet",
            "name",
            "description",
            "dag",
            "source_format",
            "task_count",
            "edge_count",
            "created",
            "updated",
        ]
        read_only_fields = ["source_format", "task_count", "edge_count", "created", "updated"]

    def validate_dag(self, value) -> TaskGraph:
        try:
            return TaskGraph.from_dict(value)
        except InputError as exc:
            raise serializers.ValidationError(str(exc)) from exc

    def create(self, validated):
        graph = validated.pop("dag")
        app = Application(**validated, created_by=self._user())
        app.set_graph(graph)
        app.save()
        return app

    def update(self, instance, validated):
        graph = validated.pop("dag", None)
        if graph is not None:
            instance.set_graph(graph)
        return super().update(instance, validated)

    def _user(self):
        user = self.context["request"].user
        return user if user.is_authenticated else None


class ApplicationListSerializer(ApplicationSerializer):
    """The list view leaves the (possibly large) DAG out."""

    class Meta(ApplicationSerializer.Meta):
        fields = [f for f in ApplicationSerializer.Meta.fields if f != "dag"]


class ApplicationImportResultSerializer(ApplicationSerializer):
    """The stored application plus what the reader flagged while accepting the file."""

    warnings = serializers.ListField(child=serializers.CharField(), read_only=True)

    class Meta(ApplicationSerializer.Meta):
        fields = [*ApplicationSerializer.Meta.fields, "warnings"]
        read_only_fields = [*ApplicationSerializer.Meta.read_only_fields, "warnings"]


class ApplicationImportSerializer(DefaultFleetMixin, ChosenFleetMixin, ScopedSerializer):
    """Upload a DAG file: continuum JSON, WfCommons WfFormat 1.5, Pegasus DAX, Kasahara STG or the thesis CSV.

    The format is ``format`` when given, else the file name's (``.stg``, ``.dax``/``.xml``, ``.csv``), else
    guessed from the content. ``options`` (a JSON object) go to the reader, e.g. STG's
    ``{"ccr": 1, "processors": 4, "heterogeneity": 0.5, "seed": 7}``.
    """

    fleet = FleetField(required=False)
    file = BoundedFileField()
    format = serializers.ChoiceField(
        choices=FORMATS, required=False, help_text="default: from the file name, else guessed from the content"
    )
    options = serializers.CharField(
        required=False,
        allow_blank=True,
        help_text='reader options as a JSON object, e.g. STG: {"ccr": 1, "processors": 4, "heterogeneity": 0.5}',
    )
    name = serializers.CharField(max_length=200, required=False)
    description = serializers.CharField(required=False, allow_blank=True, default="")
    duplicate = serializers.ChoiceField(
        choices=DUPLICATE_CHOICES,
        default="refuse",
        help_text="a file this fleet has uploaded already is refused (400, naming the application); "
        "allow: store it again as another application (also ?duplicate=allow)",
    )

    def validate_options(self, value) -> dict:
        try:
            return parse_options(value)
        except InputError as exc:
            raise serializers.ValidationError(str(exc)) from exc

    def validate(self, attrs):
        attrs = super().validate(attrs)
        upload = attrs["file"]
        content = upload.read()
        try:
            attrs["graph"], attrs["source_format"] = read_dag_file(
                content, upload.name, attrs.get("format"), attrs.get("options"), attrs.get("name")
            )
        except InputError as exc:
            raise serializers.ValidationError({exc.field: [str(exc)]}) from exc
        attrs["content_sha256"] = upload_digest(content, attrs["source_format"], attrs.get("options"))
        if not self._duplicates_allowed(attrs):
            self._refuse_duplicate(attrs["fleet"], attrs["content_sha256"])
        # what the reader accepted but flagged (e.g. an STG count that includes the dummies): reported in
        # the response, not stored with the DAG
        attrs["warnings"] = attrs["graph"].meta.pop("warnings", [])
        return attrs

    def _duplicates_allowed(self, attrs) -> bool:
        request = self.context.get("request")
        query = getattr(request, "query_params", None) or getattr(request, "GET", None) or {}
        return attrs.get("duplicate") == "allow" or query.get("duplicate") == "allow"

    def _refuse_duplicate(self, fleet, digest: str) -> None:
        """The same bytes uploaded to the same fleet before: say which application holds them (the page links
        to it through ``context["duplicate_of"]``) rather than silently storing a second copy."""
        existing = Application.objects.filter(fleet=fleet, content_sha256=digest).order_by("pk").first()
        if existing is None:
            return
        self.context["duplicate_of"] = existing
        raise serializers.ValidationError(
            {
                "file": [
                    f"this file was uploaded already: application {existing.name!r} (id {existing.pk}, "
                    f"/applications/{existing.pk}/); open it, or upload again with duplicate=allow to store "
                    "a second copy (give it a new name)"
                ]
            },
            code="duplicate",
        )

    def create(self, validated):
        v = validated
        app = _store(self._user(), v["fleet"], v["graph"], v["source_format"], v["description"], v["content_sha256"])
        return app


class ApplicationGenerateSerializer(DefaultFleetMixin, ChosenFleetMixin, ScopedSerializer):
    """A seeded synthetic DAG: the thesis' ``thesis`` generator (Tree/Linear OpenVX-like CPU/GPU DAGs,
    spec 01 section 8.2) or the HEFT literature's ``layered`` random graphs (Topcuoglu et al. 2002)."""

    fleet = FleetField(required=False)
    generator = serializers.ChoiceField(choices=GENERATORS)
    seed = serializers.IntegerField(default=0, min_value=0)
    n = serializers.IntegerField(
        required=False, min_value=2, max_value=LIMITS.tasks, error_messages=at_most("n"), help_text="tasks"
    )
    dag_class = serializers.ChoiceField(
        choices=generators.SHAPES, required=False, help_text="thesis: tree or linear (default: drawn from the seed)"
    )
    shape = serializers.FloatField(required=False, min_value=0.01, help_text="layered: height/width shape (alpha)")
    out_degree = serializers.FloatField(
        required=False,
        min_value=1,
        max_value=LIMITS.out_degree,
        error_messages=at_most("out_degree"),
        help_text="layered: mean out-degree",
    )
    ccr = serializers.FloatField(required=False, min_value=0, help_text="layered: communication-to-computation ratio")
    mean_cost = serializers.FloatField(required=False, min_value=0.001, help_text="layered: mean task cost")
    processors = serializers.IntegerField(
        required=False,
        min_value=1,
        max_value=LIMITS.processors,
        error_messages=at_most("processors"),
        help_text="layered: per-processor costs p0.. (unrelated)",
    )
    heterogeneity = serializers.FloatField(required=False, min_value=0, max_value=2, help_text="layered: beta")
    name = serializers.CharField(max_length=200, required=False)
    description = serializers.CharField(required=False, allow_blank=True, default="")

    PARAMS = ("seed", "n", "dag_class", "shape", "out_degree", "ccr", "mean_cost", "processors", "heterogeneity")
    #: The parameters only one generator takes.
    THESIS_ONLY = ("dag_class",)
    LAYERED_ONLY = ("shape", "out_degree", "ccr", "mean_cost", "processors", "heterogeneity")

    def validate(self, attrs):
        attrs = super().validate(attrs)
        if attrs["generator"] == "thesis":
            wrong = {k: ["the layered generator's; leave it empty for a thesis DAG"] for k in self.LAYERED_ONLY}
        else:
            wrong = {k: ["the thesis generator's; leave it empty for a layered DAG"] for k in self.THESIS_ONLY}
        wrong = {k: v for k, v in wrong.items() if k in attrs}
        if wrong:
            raise serializers.ValidationError(wrong)
        try:
            graph = generate_dag(attrs["generator"], **{k: attrs[k] for k in self.PARAMS if k in attrs})
        except InputError as exc:
            raise serializers.ValidationError({exc.field or "non_field_errors": [str(exc)]}) from exc
        if attrs.get("name"):
            graph.name = attrs["name"]
        attrs["graph"] = graph
        return attrs

    def create(self, validated):
        source = f"generator:{validated['generator']}"
        return _store(self._user(), validated["fleet"], validated["graph"], source, validated["description"])


def upload_digest(content: bytes, source_format: str, options: dict | None) -> str:
    """What makes two uploads the same application: the file's bytes read the same way (its format and the
    reader's options; an STG file read with another CCR is another DAG). SHA-256, hex."""
    digest = hashlib.sha256(content)
    digest.update(json.dumps([source_format, options or {}], sort_keys=True).encode())
    return digest.hexdigest()


def _store(
    user, fleet, graph: TaskGraph, source_format: str, description: str = "", content_sha256: str = ""
) -> Application:
    app = Application(
        fleet=fleet,
        content_sha256=content_sha256,
        name=graph.name,
        description=description,
        source_format=source_format,
        created_by=user if user is not None and user.is_authenticated else None,
    )
    app.set_graph(graph)
    app.save()
    return app

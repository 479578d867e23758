from rest_framework import serializers

from apps.tenancy.api import DefaultFleetMixin, FleetField, FleetOwnedSerializer
from continuum.engine.dag import TaskGraph
from continuum.engine.errors import InputError
from continuum.engine.formats import JSON_READERS, TEXT_READERS, load_dag

from .models import Application


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


FORMATS = sorted({*JSON_READERS, *TEXT_READERS})


class ApplicationImportSerializer(DefaultFleetMixin, serializers.Serializer):
    """Upload a DAG file in any supported format (continuum JSON, WfCommons WfFormat 1.5, ...)."""

    fleet = FleetField(required=False)
    file = serializers.FileField()
    format = serializers.ChoiceField(choices=FORMATS, required=False, help_text="default: guessed from the file")
    name = serializers.CharField(max_length=200, required=False)
    description = serializers.CharField(required=False, allow_blank=True, default="")

    def validate(self, attrs):
        attrs = super().validate(attrs)
        upload = attrs["file"]
        try:
            attrs["graph"] = load_dag(upload.read(), attrs.get("format"), name=attrs.get("name"))
        except InputError as exc:
            raise serializers.ValidationError({"file": [f"{upload.name}: {exc}"]}) from exc
        attrs["source_format"] = attrs.get("format") or attrs["graph"].meta.get("source_format", "continuum")
        return attrs

    def create(self, validated):
        user = self.context["request"].user
        app = Application(
            fleet=validated["fleet"],
            name=validated["graph"].name,
            description=validated["description"],
            source_format=validated["source_format"],
            created_by=user if user.is_authenticated else None,
        )
        app.set_graph(validated["graph"])
        app.save()
        return app

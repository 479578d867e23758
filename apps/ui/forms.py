"""Form helpers shared by the domain apps' dashboard forms.

**One request contract per action.** An action that the API and the dashboard both offer is validated by one
DRF serializer (the API's request serializer). Its dashboard form is a presentation layer on top:

- :class:`SerializerForm` validates with the serializer in ``clean()`` and puts the serializer's errors on
  the form's fields, so the page and the API refuse the same input with the same message;
- :func:`contract_field` builds a form field from the serializer's field (choices, default, help text and the
  bounds as HTML ``min``/``max`` attributes), so the form cannot offer what the API refuses, nor the reverse;
- the job a form starts takes its arguments from the serializer (``serializer.job_arguments()``), the same
  function the API view calls.

A form adds only what is about presentation: labels and widgets, and fields that the page decomposes a
request field into (N CPUs + M GPUs for a platform document, one field per STG reader option).
"""

from __future__ import annotations

from typing import Any

from django import forms
from rest_framework import serializers

from continuum.engine.core.errors import InputError
from continuum.engine.core.safeload import loads_json


def json_object(text: str | None, not_object: str) -> dict:
    """A form's optional JSON-object text field: {} when empty, a message naming line and column when broken."""
    text = (text or "").strip()
    if not text:
        return {}
    try:
        value = loads_json(text)
    except InputError as exc:
        message = str(exc)
        raise forms.ValidationError(f"not JSON ({message})" if message.startswith("malformed") else message) from exc
    if not isinstance(value, dict):
        raise forms.ValidationError(not_object)
    return value


class FleetChoiceMixin:
    """A fleet field asked for only when the user has several fleets."""

    fields: dict
    errors: Any

    def setup_fleet(self, fleets) -> None:
        self.fields["fleet"].queryset = fleets
        self.fleets = fleets
        self.single_fleet = fleets.count() == 1
        if self.single_fleet:
            # The only possible fleet: no question to ask.
            self.fields["fleet"].initial = fleets.first()
            self.fields["fleet"].required = False
            self.fields["fleet"].widget = forms.HiddenInput()

    def clean_fleet_choice(self, data: dict) -> None:
        if not self.fleets.exists():
            raise forms.ValidationError("you are not a member of any fleet, so there is nowhere to store it")
        if self.single_fleet and not data.get("fleet") and "fleet" not in self.errors:
            data["fleet"] = self.fleets.first()


def preselect_only(field: forms.ModelChoiceField, fallback=None) -> None:
    """Preselect the only choice of ``field`` (the fleet's only cluster, its only application), else
    ``fallback`` when given: a first attempt should not fail on a question with one possible answer."""
    choices = list(field.queryset.values_list("pk", flat=True)[:2])
    if len(choices) == 1:
        field.initial = choices[0]
    elif fallback is not None:
        field.initial = getattr(fallback, "pk", fallback)


def errors_onto(form: forms.Form, errors, names: dict[str, str] | None = None, prefix: str = "") -> None:
    """Put a serializer's errors onto ``form``: each on the field of the same name (or the one ``names`` maps
    it to), else on the form; nested errors (``{"params": {"frames": [...]}}``) on their innermost field."""
    names = names or {}
    if isinstance(errors, list):
        for message in errors:
            if isinstance(message, (dict, list)):
                errors_onto(form, message, names, prefix)
            else:
                form.add_error(None, str(message))
        return
    for field, messages in errors.items():
        if isinstance(messages, dict):
            errors_onto(form, messages, names, prefix)
            continue
        target = names.get(field, field)
        target = target if target in form.fields else None
        for message in messages if isinstance(messages, list) else [messages]:
            if isinstance(message, (dict, list)):
                errors_onto(form, message, names, prefix)
            else:
                form.add_error(target, str(message))


_FORM_FIELDS = {
    serializers.BooleanField: forms.BooleanField,
    serializers.IntegerField: forms.IntegerField,
    serializers.FloatField: forms.FloatField,
    serializers.CharField: forms.CharField,
}


def contract_field(serializer_class: type[serializers.Serializer], name: str, **presentation) -> forms.Field:
    """A form field for ``serializer_class``'s field ``name``: the same choices, default and help text, the
    bounds as HTML ``min``/``max`` (the serializer checks them, with its messages). ``presentation`` sets
    label, widget, required or choice labels (``choices``: a list of (value, label) whose values must be the
    serializer's own)."""
    field = serializer_class().fields[name]
    kwargs: dict[str, Any] = {"required": False, "help_text": field.help_text or ""}
    if field.default is not serializers.empty:
        kwargs["initial"] = field.default() if callable(field.default) else field.default
    if isinstance(field, serializers.ListField) and isinstance(field.child, serializers.ChoiceField):
        kwargs["choices"] = _choices(field.child, presentation.pop("choices", None))
        form_field: forms.Field = forms.MultipleChoiceField(**{**kwargs, **presentation})
    elif isinstance(field, serializers.ChoiceField):
        kwargs["choices"] = _choices(field, presentation.pop("choices", None))
        form_field = forms.ChoiceField(**{**kwargs, **presentation})
    else:
        cls = next((f for s, f in _FORM_FIELDS.items() if isinstance(field, s)), None)
        if cls is None:
            raise TypeError(f"no form field for {type(field).__name__} {name!r}")
        if cls is forms.CharField and getattr(field, "max_length", None):
            kwargs["max_length"] = field.max_length
        form_field = cls(**{**kwargs, **presentation})
    bounds = {
        attr: value
        for attr, value in (("min", getattr(field, "min_value", None)), ("max", getattr(field, "max_value", None)))
        if value is not None
    }
    if bounds and isinstance(form_field, (forms.IntegerField, forms.FloatField)):
        form_field.widget.attrs.update(bounds)
    return form_field


def _choices(field: serializers.ChoiceField, labels: list[tuple[str, str]] | None) -> list[tuple[str, str]]:
    offered = list(field.choices)
    if labels is None:
        return [(value, str(field.choices[value])) for value in offered]
    extra = sorted({value for value, _ in labels if value != ""} - {str(v) for v in offered})
    if extra:
        raise ValueError(f"the form offers {extra[0]!r}, which the API refuses")
    return labels


class SerializerForm(forms.Form):
    """A dashboard form validated by its API request serializer (``serializer_class``).

    ``serializer_data(cleaned)`` turns the form's cleaned fields into the API request; ``serializer_context()``
    gives the serializer what the API view would (the application, the device...). After ``is_valid()``,
    ``self.serializer`` is the validated serializer; ``job_arguments()`` returns its ``job_arguments()``.
    ``error_fields`` maps a serializer field to the form field its errors belong on.
    """

    serializer_class: type[serializers.Serializer]
    error_fields: dict[str, str] = {}

    def serializer_data(self, data: dict) -> dict:
        names = set(self.serializer_class().fields)
        return {k: v for k, v in data.items() if k in names and v not in (None, "")}

    def serializer_context(self) -> dict:
        return {}

    def clean(self):
        data = super().clean()
        if self.errors:
            self._more_field_errors(data)
            return data
        serializer = self.serializer_class(data=self.serializer_data(data), context=self.serializer_context())
        if not serializer.is_valid():
            self.add_serializer_errors(serializer.errors)
            return data
        self.serializer = serializer
        self.validated(serializer, data)
        return data

    def _more_field_errors(self, data: dict) -> None:
        """With some fields already refused, what the contract says about the other values given (a bound,
        a choice), so that one answer lists every bad value; what it says about the request as a whole waits
        until the refused fields are right."""
        try:
            payload = self.serializer_data(data)
            serializer = self.serializer_class(data=payload, context=self.serializer_context())
            if serializer.is_valid():
                return
        except (KeyError, AttributeError, TypeError, ValueError):  # a check that needs the refused fields
            return
        for field, messages in serializer.errors.items():
            target = self.error_fields.get(field, field)
            if field not in payload or target not in self.fields or target in self.errors:
                continue
            for message in messages if isinstance(messages, list) else []:
                if isinstance(message, str):
                    self.add_error(target, str(message))

    def add_serializer_errors(self, errors) -> None:
        errors_onto(self, errors, self.error_fields)

    def validated(self, serializer: serializers.Serializer, data: dict) -> None:
        """Checks a page makes beyond the contract (after the serializer accepted the request)."""

    def job_arguments(self) -> dict:
        return self.serializer.job_arguments()  # type: ignore[attr-defined]


class FleetSerializerForm(FleetChoiceMixin, SerializerForm):
    """A form that stores what it validated in the fleet the user chose (or their only one): its serializer
    takes the fleet from ``context["fleet"]`` and the user from ``context["user"]``
    (:class:`apps.tenancy.api.ChosenFleetMixin`)."""

    def __init__(self, *args, fleets, **kwargs):
        super().__init__(*args, **kwargs)
        self.setup_fleet(fleets)

    def clean(self):
        self.clean_fleet_choice(self.cleaned_data)
        return super().clean()

    def serializer_context(self) -> dict:
        return {"fleet": self.cleaned_data.get("fleet")}

    def save(self, user):
        self.serializer.context["user"] = user
        return self.serializer.save()

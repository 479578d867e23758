"""The deployment's ROS-node resource model: ``settings.CONTINUUM_RESOURCE_MODEL`` (a JSON object) over the
engine's defaults (:mod:`continuum.engine.containers.resource_model`, a proposal the thesis does not fix).
Every page, job and command that derives a container's CPU and memory from its ROS nodes reads it here."""

from __future__ import annotations

import json
from typing import Any

from django.conf import settings
from django.core import checks

from continuum.engine.containers.resource_model import ResourceModel
from continuum.engine.core.errors import InputError


def resource_model() -> ResourceModel:
    raw = settings.CONTINUUM_RESOURCE_MODEL
    return ResourceModel.from_dict(json.loads(raw) if isinstance(raw, str) else raw)


def check_resource_model(app_configs: Any = None, **kwargs: Any) -> list[checks.CheckMessage]:
    """A start-up check: a bad CONTINUUM_RESOURCE_MODEL stops the server with its reason, not a page later."""
    try:
        resource_model()
    except (ValueError, InputError) as exc:  # json.JSONDecodeError is a ValueError
        return [checks.Error(f"CONTINUUM_RESOURCE_MODEL: {exc}", id="containers.E001")]
    return []

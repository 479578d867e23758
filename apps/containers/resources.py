"""The deployment's ROS-node resource model: ``settings.CONTINUUM_RESOURCE_MODEL`` (a JSON object) over the
engine's defaults (:mod:`continuum.engine.containers.resource_model`, a proposal the thesis does not fix).
Every page, job and command that derives a container's CPU and memory from its ROS nodes reads it here."""

from __future__ import annotations

import json
from typing import Any

from django.conf import settings
from django.core import checks

from continuum.engine.containers.resource_model import ResourceModel
from continuum.engine.containers.ros_clustering import METHODS
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


def clustering_method() -> str:
    """The deployment's ROS clustering method (``settings.CONTINUUM_ROS_CLUSTERING``)."""
    return str(settings.CONTINUUM_ROS_CLUSTERING)


def check_clustering_method(app_configs: Any = None, **kwargs: Any) -> list[checks.CheckMessage]:
    """A start-up check: an unknown CONTINUUM_ROS_CLUSTERING stops the server, not the first clustering job."""
    if clustering_method() not in METHODS:
        return [
            checks.Error(
                f"CONTINUUM_ROS_CLUSTERING: unknown method {clustering_method()!r} (one of {', '.join(METHODS)})",
                id="containers.E002",
            )
        ]
    return []

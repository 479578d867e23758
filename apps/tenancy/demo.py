"""The demo data of ``python manage.py load_demo``, contributed by each domain app.

Tenancy is the lowest app, so its command cannot import the apps it seeds. Each app registers a step in its
``AppConfig.ready()`` instead (``register_demo(step)``); the command creates the administrator, the demo fleet
and its token, then runs the steps in registration order, which is ``INSTALLED_APPS`` order (every app is
listed after the apps it builds on). A step reads what earlier steps made from ``demo.objects`` and adds its
own; work that must see the committed data (starting a job) goes to ``demo.after_commit``.

Steps are idempotent like the command: running it again changes nothing that exists.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from django.conf import settings

from .models import Fleet

#: The sample files the demo loads (the test suite's data directory).
DATA = Path(settings.BASE_DIR) / "tests" / "data"


@dataclass
class Demo:
    """What a demo step works with: the demo fleet, the objects earlier steps made (by name) and the
    callables to run once the demo data is committed."""

    fleet: Fleet
    objects: dict[str, Any] = field(default_factory=dict)
    after_commit: list[Callable[[], None]] = field(default_factory=list)


DemoStep = Callable[[Demo], None]

_steps: list[DemoStep] = []


def register_demo(step: DemoStep) -> DemoStep:
    """Add ``step`` to the demo (once; registering it again is a no-op). Usable as a decorator."""
    if step not in _steps:
        _steps.append(step)
    return step


def demo_steps() -> list[DemoStep]:
    """The registered steps, in registration order."""
    return list(_steps)

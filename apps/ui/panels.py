"""Panels: how one app extends another app's page without the host importing it (NetBox's template
extensions).

A host page has a key (``"scheduling.schedule"``, ``"workloads.application"``...) and a few named slots in
its template. An extension registers a function and a template per slot for that key, usually when its
module is imported from its ``AppConfig.ready()``::

    register_panel("scheduling.schedule", "heft4k", schedule_panel,
                   templates={"after_gantt": "heft4k/schedule_panel.html"})

The host calls :func:`render_panels` with the object shown and whatever its contract passes (documented by
the host view), and includes every panel's template of a slot with ``{% include p.templates.slot %}``; the
panel's dict is in ``panel`` there. A function returns ``None`` when it has nothing to show for the object.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

PanelFunction = Callable[..., dict | None]


@dataclass(frozen=True)
class Panel:
    host: str
    name: str
    fn: PanelFunction
    templates: Mapping[str, str] = field(default_factory=dict)
    order: int = 100


@dataclass
class RenderedPanel:
    """A panel's context for one page: ``context`` is the function's dict, ``templates`` its slots."""

    name: str
    templates: Mapping[str, str]
    context: dict[str, Any]


_REGISTRY: dict[str, dict[str, Panel]] = {}


def register_panel(
    host: str, name: str, fn: PanelFunction, *, templates: Mapping[str, str] | None = None, order: int = 100
) -> Panel:
    """Register (or replace, so a re-import is harmless) the panel ``name`` of the host page ``host``."""
    panel = Panel(host, name, fn, dict(templates or {}), order)
    _REGISTRY.setdefault(host, {})[name] = panel
    return panel


def unregister_panel(host: str, name: str) -> None:
    _REGISTRY.get(host, {}).pop(name, None)


def panels_for(host: str) -> list[Panel]:
    """The panels registered for ``host``, by ``order`` then name."""
    return sorted(_REGISTRY.get(host, {}).values(), key=lambda p: (p.order, p.name))


def render_panels(host: str, *args: Any, **kwargs: Any) -> list[RenderedPanel]:
    """Call every panel of ``host`` with the host's arguments; the ones that have something to show."""
    shown = []
    for panel in panels_for(host):
        context = panel.fn(*args, **kwargs)
        if context is not None:
            shown.append(RenderedPanel(panel.name, panel.templates, context))
    return shown

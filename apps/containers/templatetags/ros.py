"""Template filters of the ROS pages: bandwidth for people, dictionary look-ups, level names."""

from django import template

from apps.containers.charts import LEVEL_LABELS, rate

register = template.Library()


@register.filter(name="rate")
def rate_filter(value) -> str:
    """Bytes per second as ``12.3 kB/s (0.098 Mbit/s)``."""
    try:
        return rate(float(value))
    except (TypeError, ValueError):
        return "—"


@register.filter
def get(mapping, key):
    return (mapping or {}).get(key)


@register.filter
def level_label(level: str) -> str:
    return LEVEL_LABELS.get(level, level or "")

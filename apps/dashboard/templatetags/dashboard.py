"""Template filters for numbers and documents shown to operators."""

import json
import math

from django import template

register = template.Library()


@register.filter
def num(value, digits: int = 3) -> str:
    """A number with at most ``digits`` decimals and no trailing zeros: 0.5, 1000, 54026.002."""
    if value is None or value == "":
        return "—"
    try:
        x = float(value)
    except (TypeError, ValueError):
        return str(value)
    if not math.isfinite(x):
        return str(x)
    text = f"{x:.{int(digits)}f}"
    if "." in text:
        text = text.rstrip("0").rstrip(".")
    return "0" if text == "-0" else text


@register.filter
def pretty_json(value) -> str:
    return json.dumps(value, indent=2, sort_keys=True, default=str)


@register.filter
def percent(value, digits: int = 1) -> str:
    """A fraction as a percentage: 0.193 -> 19.3%."""
    if value is None or value == "":
        return "—"
    try:
        return f"{num(100.0 * float(value), digits)}%"
    except (TypeError, ValueError):
        return str(value)


@register.filter
def change(value, digits: int = 1) -> str:
    """A relative change as a signed percentage: 0.209 -> +20.9%, -0.05 -> -5%, 0 -> 0%."""
    text = percent(value, digits)
    return text if text in ("—", "0%") or text.startswith("-") or not text[0].isdigit() else f"+{text}"

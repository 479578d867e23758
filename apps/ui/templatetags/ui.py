"""Template filters for numbers and documents shown to operators."""

import json
import math

from django import template
from django.utils.text import slugify

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
    """A fraction as a percentage: 0.414 -> 41.4 %."""
    if value is None or value == "":
        return "—"
    try:
        return f"{num(100.0 * float(value), digits)} %"
    except (TypeError, ValueError):
        return str(value)


@register.filter
def change(value, digits: int = 1) -> str:
    """A relative change as a signed percentage: 0.209 -> +20.9 %, -0.05 -> -5 %, 0 -> 0 %."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        return percent(value, digits)
    return ("+" if x > 0 else "") + percent(x, digits)


@register.filter
def speedup_pct(value) -> str:
    """A speedup factor as a change in per cent: 1.693 -> +69.3 %, 0.8 -> -20 %."""
    if value is None or value == "":
        return "—"
    return change(float(value) - 1.0)


@register.inclusion_tag("ui/includes/disabled_action.html")
def disabled_action(label: str, reason: str, fix_url: str = "", fix_label: str = "", primary: bool = False) -> dict:
    """An action that cannot run now, shown rather than hidden: a disabled button, why, and a link to what
    makes it possible (``{% disabled_action "Push to Kubernetes" "no API configured" url "import one" %}``)."""
    return {
        "label": label,
        "reason": reason,
        "fix_url": fix_url,
        "fix_label": fix_label,
        "primary": primary,
        "reason_id": "why-" + slugify(label),
    }


@register.inclusion_tag("ui/includes/form_errors.html")
def form_errors(form, heading: str = "") -> dict:
    """A refused form's errors at its top: every message, each linking to its field (which shows it too),
    under ``heading`` (default: "This could not be done:" or "These need fixing:")."""
    return {"form": form, "heading": heading}


@register.filter
def unit(value, name: str) -> str:
    """A number with its unit: ``80|unit:"ms"`` -> "80 ms" (no unit when the number is missing)."""
    text = num(value)
    return text if text == "—" or not name else f"{text} {name}"

"""Periodic tasks of RT-Kube (run by ``celery -A continuum beat``; see CELERY_BEAT_SCHEDULE in settings)."""

from celery import shared_task

from .monitoring import lift_expired_taints


@shared_task(name="continuum.rt_lift_taints")
def rt_lift_taints() -> int:
    """Lift the monitor's node taints whose time is up (the RT scheduler process does it too)."""
    return lift_expired_taints()

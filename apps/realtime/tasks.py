"""RT-Kube's Celery tasks: the reconcile of reported violations (off the web request) and the periodic ones
(run by ``celery -A continuum beat``; see CELERY_BEAT_SCHEDULE in settings)."""

from __future__ import annotations

import logging

from celery import shared_task
from django.conf import settings

from apps.clusters.models import Cluster

from .models import RTEvent
from .monitoring import event_summary, lift_expired_taints, reconcile_overdue, reconcile_stored

log = logging.getLogger(__name__)


@shared_task(name="continuum.rt_lift_taints")
def rt_lift_taints() -> int:
    """Lift the monitor's node taints whose time is up (the RT scheduler process does it too)."""
    return lift_expired_taints()


@shared_task(name="continuum.rt_reconcile", acks_late=True, reject_on_worker_lost=True)
def rt_reconcile(cluster_id: int, report_pks: list[int]) -> list[int]:
    """Reconcile the stored violations of one batch (evict, taint: the Kubernetes calls the report's request
    does not wait on); the events made. Each report is claimed in the transaction that records its eviction,
    so a redelivered message does nothing twice."""
    cluster = Cluster.objects.select_related("rt_policy").filter(pk=cluster_id).first()
    if cluster is None:  # deleted meanwhile, with its reports
        return []
    return [e.pk for e in reconcile_stored(cluster, report_pks)]


@shared_task(name="continuum.rt_reconcile_overdue")
def rt_reconcile_overdue() -> int:
    """The safety net: violations whose ``rt_reconcile`` message never ran (broker down, worker lost)."""
    return reconcile_overdue(settings.CONTINUUM_RT_RECONCILE_OVERDUE_S)


def queue_reconcile(cluster: Cluster, report_pks: list[int]) -> list[dict]:
    """Hand a batch's stored violations to the ``rt_reconcile`` task; the events when it ran here (the tests'
    in-process jobs, ``CONTINUUM_JOBS_EAGER``), else [] (the worker evicts; ``/api/v1/rt-events/`` shows it). A
    broker that refuses the message loses nothing: the reports are stored, and the overdue sweep reconciles
    them."""
    if settings.CELERY_TASK_ALWAYS_EAGER:
        result = rt_reconcile.apply(args=(cluster.pk, report_pks))
        if not result.successful():
            log.error("rt_reconcile of cluster %s failed: %r", cluster.pk, result.result)
            return []
        return [event_summary(e) for e in RTEvent.objects.filter(pk__in=result.result).order_by("pk")]
    try:
        rt_reconcile.apply_async(args=(cluster.pk, report_pks))
    except Exception:
        log.exception("could not queue the reconcile of %d reports of cluster %s", len(report_pks), cluster.pk)
    return []

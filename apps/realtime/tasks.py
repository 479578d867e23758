"""RT-Kube's Celery tasks: the reconcile of reported violations (off the web request) and the periodic ones
(run by ``celery -A continuum beat``; see CELERY_BEAT_SCHEDULE in settings).

``continuum.rt_reconcile`` runs on its own queue (``CONTINUUM_RT_QUEUE``, routed in settings), so an eviction
never waits behind a long job. The worker that consumes that queue keeps one Kubernetes client per cluster
(:func:`apps.realtime.kube.kube_for`) with its connections open; :func:`rt_warm` opens them before the first
eviction needs them (at the worker's start, and whenever asked), so no eviction pays a TLS handshake.
"""

from __future__ import annotations

import logging
import threading
import time
from functools import partial

from celery import shared_task
from celery.signals import worker_ready
from django.conf import settings
from django.db import transaction

from apps.clusters.models import Cluster

from .kube import has_api, warm
from .models import RTEvent
from .monitoring import event_summary, lift_expired_taints, policy_of, reconcile_overdue, reconcile_stored

log = logging.getLogger(__name__)
#: Clusters whose clients a starting RT worker warms at most (the others are built at their first eviction).
WARM_AT_START = 200


@shared_task(name="continuum.rt_lift_taints")
def rt_lift_taints() -> int:
    """Lift the monitor's node taints whose time is up (the RT scheduler process does it too)."""
    return lift_expired_taints()


@shared_task(name="continuum.rt_reconcile", acks_late=True, reject_on_worker_lost=True)
def rt_reconcile(cluster_id: int, report_pks: list[int], queued_at: float | None = None) -> list[int]:
    """Reconcile the stored violations of one batch (evict, taint: the Kubernetes calls the report's request
    does not wait on); the events made. Each report is claimed in the transaction that records its eviction,
    so a redelivered message does nothing twice. ``queued_at``: when the request published the message (epoch
    seconds), kept with the eviction's stage times (``RTEvent.response["stages"]``)."""
    picked = time.time()
    cluster = Cluster.objects.select_related("rt_policy").filter(pk=cluster_id).first()
    if cluster is None:  # deleted meanwhile, with its reports
        return []
    stamps = {"queued": queued_at, "picked": picked} if isinstance(queued_at, int | float) else {"picked": picked}
    # The policy came with the cluster (select_related): not read again on the clock.
    return [e.pk for e in reconcile_stored(cluster, report_pks, policy_of(cluster), stamps=stamps)]


@shared_task(name="continuum.rt_warm")
def rt_warm(cluster_ids: list[int] | None = None) -> int:
    """Build the Kubernetes clients of these clusters (None: every cluster with an RT policy) in this worker and
    open a connection to each API; how many answered. Nothing is changed anywhere."""
    clusters = Cluster.objects.all() if cluster_ids is not None else Cluster.objects.filter(rt_policy__isnull=False)
    if cluster_ids is not None:
        clusters = clusters.filter(pk__in=cluster_ids)
    # The kubeconfig is encrypted at rest: a model-only cluster is told apart once loaded.
    return sum(warm(c) for c in clusters.order_by("pk")[:WARM_AT_START] if has_api(c))


@worker_ready.connect
def warm_rt_worker(sender=None, **_) -> None:
    """A worker consuming the RT queue opens its clusters' API connections in the background as it starts."""
    queues = {q.name for q in getattr(getattr(sender, "task_consumer", None), "queues", None) or ()}
    if settings.CONTINUUM_RT_QUEUE in queues:
        threading.Thread(target=_warm_quietly, name="rt-warm", daemon=True).start()


def _warm_quietly() -> None:
    try:
        log.info("warmed the Kubernetes clients of %d clusters", rt_warm())
    except Exception:  # a cold client is slower, never wrong: the worker runs on
        log.exception("warming the Kubernetes clients failed")
    finally:
        from django.db import connection

        connection.close()


@shared_task(name="continuum.rt_reconcile_overdue")
def rt_reconcile_overdue() -> int:
    """The safety net: violations whose ``rt_reconcile`` message never ran (broker down, worker lost)."""
    return reconcile_overdue(settings.CONTINUUM_RT_RECONCILE_OVERDUE_S)


def queue_reconcile(cluster: Cluster, report_pks: list[int]) -> list[dict]:
    """Hand a batch's stored violations to the ``rt_reconcile`` task; the events when it ran here (the tests'
    in-process jobs, ``CONTINUUM_JOBS_EAGER``), else [] (the worker evicts; ``/api/v1/rt-events/`` shows it).

    The message is published once the reports are committed (``on_commit``: at once in autocommit, at the end of
    the caller's transaction otherwise), so the worker never looks for rows it cannot see yet. A broker that
    refuses the message loses nothing: the reports are stored, and the overdue sweep reconciles them."""
    if settings.CELERY_TASK_ALWAYS_EAGER:
        result = rt_reconcile.apply(args=(cluster.pk, report_pks))
        if not result.successful():
            log.error("rt_reconcile of cluster %s failed: %r", cluster.pk, result.result)
            return []
        return [event_summary(e) for e in RTEvent.objects.filter(pk__in=result.result).order_by("pk")]
    transaction.on_commit(partial(_publish, cluster.pk, list(report_pks)))
    return []


def _publish(cluster_id: int, report_pks: list[int]) -> None:
    try:
        rt_reconcile.apply_async(args=(cluster_id, report_pks), kwargs={"queued_at": time.time()})
    except Exception:
        log.exception("could not queue the reconcile of %d reports of cluster %s", len(report_pks), cluster_id)

"""The RT scheduler's writer of ledger rows: inline and from its thread, a row unchanged since the last write is
not written again, a pod gone is marked deleted, and a sync's rewrite reconciles what another writer changed."""

import pytest

from apps.realtime.ledger_writer import CycleWrite, LedgerWriter
from apps.realtime.models import RTPod
from apps.realtime.scheduler import view_pod

pytestmark = pytest.mark.django_db(transaction=True)  # the writer thread has a connection of its own


def pod(cluster, name, node="", phase="Running"):
    return {
        "metadata": {"namespace": cluster.namespace, "name": name, "uid": f"uid-{name}",
                     "creationTimestamp": "2026-11-24T10:00:00Z"},
        "spec": {"nodeName": node, "schedulerName": "RT-scheduler", "containers": [{"name": name}]},
        "status": {"phase": phase},
    }  # fmt: skip


def cycle(cluster, *pods, bound=None):
    views = [view_pod(p, {}, ["node0", "node1"]) for p in pods]
    return CycleWrite(cluster, views, bound or {}, None, [])


def live(cluster):
    return {r.name: r for r in RTPod.objects.filter(cluster=cluster, deleted_at__isnull=True)}


def test_inline_writes_mark_gone_pods_deleted(cluster):
    writer = LedgerWriter(None)
    writer.write(cycle(cluster, pod(cluster, "a", "node0"), pod(cluster, "b")))
    assert set(live(cluster)) == {"a", "b"} and live(cluster)["a"].node == "node0"
    writer.write(cycle(cluster, pod(cluster, "a", "node0")))
    assert set(live(cluster)) == {"a"}
    assert RTPod.objects.get(name="b").deleted_at is not None


def test_the_thread_skips_unchanged_rows_until_a_rewrite(cluster):
    writer = LedgerWriter(None)
    a, b = pod(cluster, "a"), pod(cluster, "b")
    try:
        writer.start()
        writer.write(cycle(cluster, a, b, bound={(cluster.namespace, "a"): ("node1", 0.25)}))
        writer.stop()
        rows = live(cluster)
        assert rows["a"].node == "node1" and rows["a"].bound_at is not None and rows["b"].phase == "Running"
        # Another writer changes b's row: unchanged in this process's view of the pod, it is not written again ...
        RTPod.objects.filter(name="b").update(phase="Failed")
        writer.start()
        writer.write(cycle(cluster, a, b))
        writer.stop()
        assert RTPod.objects.get(name="b").phase == "Failed"
        # ... until a sync asks for every row again.
        writer.rewrite_all()
        writer.start()
        writer.write(cycle(cluster, a, b))
        writer.stop()
        assert RTPod.objects.get(name="b").phase == "Running"
        # A pod gone from the views is marked deleted without reading the live rows back.
        writer.start()
        writer.write(cycle(cluster, a))
        writer.stop()
        assert set(live(cluster)) == {"a"} and RTPod.objects.get(name="b").deleted_at is not None
        assert writer.writes == 4 and writer.write_errors == 0
    finally:
        writer.stop()

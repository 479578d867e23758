"""What an RT cycle reads from the database: the cluster, its policy, its node rows and the next expiry of an
active monitor taint, in two queries; the monitor's active taints, read ahead by the rt-taints thread."""

import threading
import time
from datetime import timedelta

import pytest
from django.utils import timezone

from apps.realtime.cycle_state import CycleState
from apps.realtime.models import NodeTaint, RTPolicy

pytestmark = pytest.mark.django_db(transaction=True)  # the rt-taints thread has a connection of its own


def taint(cluster, node, seconds, lifted=False):
    now = timezone.now()
    return NodeTaint.objects.create(
        cluster=cluster, node=cluster.nodes.get(name=node), expires_at=now + timedelta(seconds=seconds),
        lifted_at=now if lifted else None,
    )  # fmt: skip


def test_the_state_in_two_queries_with_the_next_active_expiry(rt_cluster, django_assert_num_queries):
    RTPolicy.for_cluster(rt_cluster)
    state = CycleState(rt_cluster.pk, period=1.0)
    with django_assert_num_queries(2):
        cluster, policy, rows = state.get()
    assert cluster.pk == rt_cluster.pk and policy.cluster_id == rt_cluster.pk
    assert set(rows) == {"node0", "node1", "node2", "node3"} and state.expiry_at is None
    taint(rt_cluster, "node0", 5, lifted=True)  # lifted: no longer expires
    taint(rt_cluster, "node1", 60)
    taint(rt_cluster, "node2", 30)
    began = time.monotonic()
    state.get(fresh=True)
    assert state.expiry_at is not None and 25 < state.expiry_at - began <= 30


def test_a_cluster_without_a_policy_gets_the_default_one(rt_cluster):
    RTPolicy.objects.filter(cluster=rt_cluster).delete()
    _, policy, _ = CycleState(rt_cluster.pk, period=1.0).get()
    assert policy.pk is not None and RTPolicy.objects.filter(cluster=rt_cluster).count() == 1


def test_the_thread_reads_the_taints_asked_for(rt_cluster):
    state, stop = CycleState(rt_cluster.pk, period=0.5), threading.Event()
    thread = state.start(stop)
    try:
        assert state.active_taints(time.monotonic()) == []
        taint(rt_cluster, "node1", 60)
        asked = time.monotonic()
        state.ask_taints(asked)
        rows = state.active_taints(asked)  # a read started after the ask: it sees the new taint
        assert [r[0] for r in rows] == ["node1"]
    finally:
        stop.set()
        state.stop()
        thread.join(timeout=10)
    assert not thread.is_alive()

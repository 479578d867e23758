"""The RT scheduler's informer cache (apps/kube/informer.py): a list, then watch events, and the pods this
process bound assumed bound until deleted, so a stale or replayed event never makes a bound pod pending again."""

from apps.kube.informer import Informer
from apps.realtime.scheduler import node_relevant, pod_relevant, waits_for_us


def pod(name, uid="u1", node=None, scheduler="RT-scheduler", phase="Pending", rv="1"):
    spec = {"schedulerName": scheduler, "containers": [{"name": "c"}]}
    if node:
        spec["nodeName"] = node
    return {"metadata": {"namespace": "ns", "name": name, "uid": uid, "resourceVersion": rv}, "spec": spec,
            "status": {"phase": phase}}  # fmt: skip


def event(kind, obj):
    return {"type": kind, "raw_object": obj, "object": obj}


def by_name(informer):
    return {p["metadata"]["name"]: p for p in informer.snapshot()}


def test_list_then_events_keep_the_cache_current():
    cache = Informer(pod_relevant)
    assert not cache.synced
    cache.replace([pod("a"), pod("b", uid="u2", node="n1")])
    assert cache.synced and sorted(by_name(cache)) == ["a", "b"]
    assert cache.apply(event("ADDED", pod("c", uid="u3")))  # waits for the RT scheduler: relevant
    assert cache.apply(event("DELETED", pod("b", uid="u2", node="n1")))  # capacity freed: relevant
    assert sorted(by_name(cache)) == ["a", "c"]
    # A bound pod's status update (its kubelet) needs no scheduling cycle.
    cache.apply(event("ADDED", pod("d", uid="u4", node="n1")))
    assert not cache.apply(event("MODIFIED", pod("d", uid="u4", node="n1", phase="Running")))
    assert not cache.apply({"type": "BOOKMARK", "raw_object": {"metadata": {"resourceVersion": "9"}}})
    cache.unsynced()
    assert not cache.synced
    cache.replace([pod("a")])  # a fresh list replaces everything (what was deleted meanwhile is gone)
    assert sorted(by_name(cache)) == ["a"] and cache.synced


def test_a_pod_bound_here_stays_bound_through_a_stale_or_replayed_event():
    cache = Informer(pod_relevant)
    cache.replace([pod("a")])
    cache.assume("ns/a", "u1", "n2")
    assert by_name(cache)["a"]["spec"]["nodeName"] == "n2"  # before the watch reports the binding
    assert not waits_for_us(by_name(cache)["a"])
    cache.apply(event("MODIFIED", pod("a", node="n2", rv="2")))
    cache.apply(event("MODIFIED", pod("a", rv="1")))  # replayed from an older resourceVersion: unbound again
    assert by_name(cache)["a"]["spec"]["nodeName"] == "n2"
    assert cache.stats()["stale_events"] == 1
    cache.replace([pod("a", rv="1")])  # even a list cannot unbind it while the same pod exists
    assert by_name(cache)["a"]["spec"]["nodeName"] == "n2"
    # A new pod of the same name (another uid) is not the one bound here: it waits to be scheduled.
    cache.apply(event("DELETED", pod("a", node="n2")))
    cache.apply(event("ADDED", pod("a", uid="u9")))
    assert waits_for_us(by_name(cache)["a"]) and cache.assumed("ns/a") is None


def test_the_snapshot_is_a_copy_and_the_cache_is_never_mutated():
    cache = Informer(pod_relevant)
    original = pod("a")
    cache.replace([original])
    cache.assume("ns/a", "u1", "n1")
    snap = by_name(cache)["a"]
    assert snap["spec"]["nodeName"] == "n1" and "nodeName" not in original["spec"]


def test_node_changes_that_matter():
    node = {"metadata": {"name": "n1", "labels": {"a": "1"}}, "spec": {},
            "status": {"allocatable": {"cpu": "1", "memory": "1Gi"},
                       "conditions": [{"type": "Ready", "status": "True", "lastHeartbeatTime": "t1"}]}}  # fmt: skip
    heartbeat = {**node, "status": {**node["status"], "conditions": [
        {"type": "Ready", "status": "True", "lastHeartbeatTime": "t2"}]}}  # fmt: skip
    tainted = {**node, "spec": {"taints": [{"key": "k", "value": "v", "effect": "NoSchedule"}]}}
    assert not node_relevant(node, heartbeat)
    assert node_relevant(node, tainted)
    assert node_relevant(None, node) and node_relevant(node, None)

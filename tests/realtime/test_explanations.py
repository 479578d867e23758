"""Bounded stored explanations and the on-demand "why not this node?" (issue 15): the API action, the page,
the stored format on a large cluster and the data migration of the old (every node) format."""

import importlib
import json

import pytest

from apps.clusters.models import ComputeNode
from apps.realtime.models import RTDecision, RTPlan
from continuum.engine.rtkube import rt_kube, rt_kube_vec
from continuum.engine.rtkube.rt_model import RTNode

from .conftest import make_pod, make_rt

pytestmark = pytest.mark.django_db


def decision_of(cluster, pod, realtime=None, node="", outcome="pending", decision=None):
    return RTDecision.objects.create(
        cluster=cluster, namespace=cluster.namespace, pod=pod, realtime=realtime, criticality="A", outcome=outcome,
        node=node, message="0/4 nodes are available", decision=decision or {"item": pod, "node": None, "verdicts": []},
    )  # fmt: skip


def add_nodes(cluster, count):
    """``count`` more RT nodes (A, 4 cores) named big000..."""
    for i in range(count):
        ComputeNode.objects.create(cluster=cluster, name=f"big{i:03d}", rt=True, criticality="A", cpu=4)


# ---- why-not: API --------------------------------------------------------------------------------------------
def test_why_not_explains_every_node_or_one_from_the_scheduler_filters(api, rt_cluster):
    vision = make_rt(rt_cluster, "vision", "A", 100, 100, {"node3": 10, "node0": 20})
    make_pod(rt_cluster, "hog", "node0", "A", utilization=3.7)  # node0 is nearly full
    make_pod(rt_cluster, "vision", "", "A", realtime=vision)
    d = decision_of(rt_cluster, "vision", vision)
    r = api.get(f"/api/v1/rt-decisions/{d.pk}/why-not/")
    assert r.status_code == 200, r.data
    assert r.data["nodes"] == 4 and r.data["pod"] == f"{rt_cluster.namespace}/vision" and r.data["chosen"] is None
    why = {v["node"]: v for v in r.data["verdicts"]}
    assert list(why) == ["node0", "node1", "node2", "node3"]
    assert why["node3"]["rejected_by"] == "RealTimeNode" and why["node3"]["reason"] == "node has no real-time kernel"
    assert why["node1"]["reason"] == "no WCET given for this node"
    assert why["node0"]["rejected_by"] == "RealTimeAdmission"
    assert "projected RT utilization 3.9000 > threshold 3.8000" in why["node0"]["reason"]
    assert why["node2"]["rejected_by"] == "RealTimeWcet"
    one = api.get(f"/api/v1/rt-decisions/{d.pk}/why-not/", {"node": "node0"})
    assert one.status_code == 200 and [v["node"] for v in one.data["verdicts"]] == ["node0"]
    assert one.data["verdicts"][0] == why["node0"]


def test_why_not_of_a_node_that_passes_gives_its_score(api, rt_cluster):
    slam = make_rt(rt_cluster, "slam", "B", 100, 100, {"node0": 40, "node1": 25})
    d = decision_of(rt_cluster, "slam", slam, node="node1", outcome="bound")
    make_pod(rt_cluster, "slam", "node1", "B", realtime=slam, utilization=0.25)
    r = api.get(f"/api/v1/rt-decisions/{d.pk}/why-not/", {"node": "node0"})
    assert r.status_code == 200 and r.data["chosen"] == "node1"
    [v] = r.data["verdicts"]
    assert v["rejected_by"] is None and v["total"] == pytest.approx(rt_kube.rt_score("B", 3.8, 0.4))
    assert "newUT 0.4000 of 3.8000" in v["reason"]


@pytest.mark.parametrize(
    ("query", "field"),
    [({"node": "no-such-node"}, "node"), ({"node": "x" * 300}, "node"), ({"node": "node0\x00"}, "node")],
)
def test_why_not_answers_400_on_bad_input(api, rt_cluster, query, field):
    d = decision_of(rt_cluster, "vision")
    r = api.get(f"/api/v1/rt-decisions/{d.pk}/why-not/", query)
    assert r.status_code == 400, r.content
    assert field in r.json() or "NUL" in r.content.decode(), r.content  # NUL: refused before the view


def test_why_not_is_scoped_to_the_fleet(api, other_api, rt_cluster):
    d = decision_of(rt_cluster, "vision")
    assert other_api.get(f"/api/v1/rt-decisions/{d.pk}/why-not/").status_code == 404
    assert api.get(f"/api/v1/rt-decisions/{d.pk + 1000}/why-not/").status_code == 404


def test_why_not_of_a_pod_whose_realtime_became_invalid_is_a_400(api, rt_cluster):
    vision = make_rt(rt_cluster, "vision", "A", 100, 100, {"node3": 10})
    vision.wcets.all().delete()  # no WCET at all: not a valid RT container any more
    d = decision_of(rt_cluster, "vision", vision)
    r = api.get(f"/api/v1/rt-decisions/{d.pk}/why-not/")
    assert r.status_code == 400, r.data


# ---- why-not: page ----------------------------------------------------------------------------------------------
def test_decision_page_asks_why_not_a_node(member, rt_cluster):
    vision = make_rt(rt_cluster, "vision", "A", 100, 100, {"node3": 10})
    d = decision_of(rt_cluster, "vision", vision)
    page = member.get(f"/realtime/decisions/{d.pk}/", {"node": "node3"})
    assert page.status_code == 200
    assert "Why not node3?" in page.content.decode() and "node has no real-time kernel" in page.content.decode()
    every = member.get(f"/realtime/decisions/{d.pk}/", {"node": "*"}).content.decode()
    assert all(f"<strong>node{i}</strong>" in every for i in range(4))
    bad = member.get(f"/realtime/decisions/{d.pk}/", {"node": "nope"})
    assert bad.status_code == 400 and "has no node &#x27;nope&#x27;" in bad.content.decode()


# ---- the stored format ------------------------------------------------------------------------------------------
def test_whatif_on_a_large_cluster_stores_bounded_decisions(api, rt_cluster):
    add_nodes(rt_cluster, rt_kube_vec.FULL_UP_TO + 8)  # 44 nodes in all
    wcets = {n: 10 for n in rt_cluster.nodes.filter(rt=True).exclude(criticality="C").values_list("name", flat=True)}
    for i in range(6):
        make_rt(rt_cluster, f"t{i}", "A", 100, 100, wcets)
    make_rt(rt_cluster, "vision", "A", 100, 100, {"node3": 10})
    job = api.post("/api/v1/rt-plans/whatif/", {"cluster": rt_cluster.pk}, format="json").data
    row = RTPlan.objects.get(job_id=job["id"])
    assert (row.placed, row.pending) == (6, 1)
    limit = rt_kube_vec.TOP_K + rt_kube_vec.EXAMPLES * (len(rt_kube_vec.FILTERS) - 1)
    for d in row.plan["decisions"]:
        assert len(d["verdicts"]) <= limit
        kept = sum(1 for v in d["verdicts"] if not v["rejected_by"])
        assert sum(d["rejections"].values()) + (42 if d["node"] else 0) >= 43 - kept
    vision = next(d for d in row.plan["decisions"] if d["item"] == "vision")
    assert vision["rejections"] == {"RealTimeNode": 1, "RealTimeWcet": 43}
    assert len(row.plan["explain"]) <= 7 * limit
    # the stored decision reads back as the engine's type, rejections included
    assert row.engine_plan().decision("vision").rejections == vision["rejections"]


def test_the_migration_bounds_old_rows_and_keeps_small_ones(rt_cluster):
    migration = importlib.import_module("apps.realtime.migrations.0004_bounded_explanations")
    from django.apps import apps

    nodes = [RTNode(f"n{i:02d}", i % 4 != 0, "A", 4.0, float("inf"), 3.8, ()) for i in range(60)]
    containers = [rt_kube.RTContainer(f"c{j}", "A", 100.0, 100.0, {f"n{i:02d}": 30.0 for i in range(1, 60, 2)})
                  for j in range(8)]  # fmt: skip
    old = rt_kube.schedule(containers, nodes)  # the reference: every node's verdict
    doc = {**old.to_dict(), "explain": rt_kube.explain(old)}
    big = RTPlan.objects.create(cluster=rt_cluster, kind="whatif", plan=doc, placed=8, pending=0)
    small_doc = {**rt_kube.schedule(containers[:1], nodes[:8]).to_dict(), "explain": []}
    small = RTPlan.objects.create(cluster=rt_cluster, kind="whatif", plan=small_doc, placed=1, pending=0)
    d = decision_of(rt_cluster, "c0", decision=old.decisions[0].to_dict(), node=old.decisions[0].node)
    before = len(json.dumps(doc))

    migration.bound_explanations(apps, None)

    big.refresh_from_db()
    small.refresh_from_db()
    d.refresh_from_db()
    assert small.plan == small_doc
    assert len(json.dumps(big.plan)) < before / 4
    for new, ref in zip(big.plan["decisions"], old.decisions, strict=True):
        assert (new["node"], new["score"]) == (ref.node, ref.score)
        assert new["verdicts"][0]["node"] == ref.node
        assert new["rejections"] == {"RealTimeNode": 15, "RealTimeWcet": 15}
    assert {(r["container"], r["node"]) for r in big.plan["explain"]} == {
        (x["item"], v["node"]) for x in big.plan["decisions"] for v in x["verdicts"]
    }
    assert d.decision == rt_kube_vec.bound_decision(old.decisions[0].to_dict())
    migration.bound_explanations(apps, None)  # idempotent
    big2 = RTPlan.objects.get(pk=big.pk)
    assert big2.plan == big.plan

"""The vectorised RT-Kube (rt_kube_vec) against the reference (rt_kube): identical choices, scores and
verdicts on random instances (ties included), and explanations bounded whatever the cluster's size."""

import json
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from continuum.engine.rtkube import rt_kube, rt_kube_vec
from continuum.engine.rtkube.rt_kube import Binding, Ledger, RTKubeParams
from continuum.engine.rtkube.rt_model import RT_TAINT, RT_TOLERATION, RTContainer, RTNode, Taint, Toleration

TAINTS = [
    RT_TAINT,
    Taint("gpu", "yes", "NoSchedule"),
    Taint("monitor", "miss", "NoSchedule", until=50.0),  # timed: active before now=50, gone after
    Taint("soft", "", "PreferNoSchedule"),
    Taint("node.kubernetes.io/not-ready", "", "NoSchedule"),
]
TOLERATIONS = [RT_TOLERATION, Toleration("gpu", "Exists"), Toleration("monitor", "Equal", "miss", "NoSchedule")]
# Few distinct values, so that equal scores (ties) are common.
WCETS = [1.0, 2.0, 5.0, 10.0, 25.0, 40.0]
CPUS = [0.5, 1.0, 2.0, 4.0, 8.0]


@st.composite
def instances(draw, max_nodes=9, max_containers=12):
    n_nodes = draw(st.integers(1, max_nodes))
    names = [f"n{i:02d}" for i in draw(st.permutations(range(n_nodes)))]  # input order is not name order
    nodes = []
    for name in names:
        cpu = draw(st.sampled_from(CPUS))
        nodes.append(
            RTNode(
                name,
                rt=draw(st.booleans()),
                criticality=draw(st.sampled_from([None, "A", "B", "C"])),
                cpu=cpu,
                memory_mib=draw(st.sampled_from([math.inf, 512.0, 2048.0, 0.0])),
                rt_threshold=draw(st.sampled_from([cpu * 0.95, 0.5, 1.0, 0.0])),
                taints=tuple(draw(st.lists(st.sampled_from(TAINTS), max_size=2, unique=True))),
            )
        )
    containers = []
    for i in range(draw(st.integers(0, max_containers))):
        crit = draw(st.sampled_from(["NONE", "A", "B", "C"]))
        tolerations = tuple(draw(st.lists(st.sampled_from(TOLERATIONS), max_size=3, unique=True)))
        cpu = draw(st.sampled_from([0.0, 0.25, 1.0, 3.0]))
        mem = draw(st.sampled_from([0.0, 128.0, 1024.0]))
        arrival = float(draw(st.integers(0, 3)))
        if crit == "NONE":
            containers.append(RTContainer(f"c{i}", cpu=cpu, memory_mib=mem, tolerations=tolerations, arrival=arrival))
            continue
        period = draw(st.sampled_from([40.0, 50.0, 100.0]))
        wcet_nodes = draw(st.lists(st.sampled_from(names), unique=True))
        wcet = {n: min(period, draw(st.sampled_from(WCETS))) for n in wcet_nodes}
        containers.append(RTContainer(f"c{i}", crit, period, period, wcet, False, cpu, mem, tolerations, arrival))
    bindings = {}
    for j, name in enumerate(draw(st.lists(st.sampled_from(names), max_size=4))):
        bindings[f"old{j}"] = Binding(f"old{j}", name, draw(st.sampled_from([0.1, 0.25, 0.95])), 0.5, 64.0, "A")
    params = RTKubeParams(
        k=draw(st.sampled_from([2.0, 1.5, 4.0])),
        b_score_argument=draw(st.sampled_from(["free", "load"])),
        sort_tiebreak=draw(st.sampled_from(["arrival", "utilization"])),
        check_resources=draw(st.booleans()),
    )
    now = draw(st.sampled_from([None, 10.0, 60.0]))
    return containers, nodes, bindings, params, now


def both(containers, nodes, bindings, params, now, **kw):
    ref = rt_kube.schedule(containers, nodes, params, Ledger([n.name for n in nodes], dict(bindings)), now)
    book = Ledger([n.name for n in nodes], dict(bindings))
    vec = rt_kube_vec.schedule(containers, nodes, params, book, now, **kw)
    return ref, vec


@settings(max_examples=400, deadline=None)
@given(instances())
def test_identical_to_the_reference_with_every_verdict(inst):
    ref, vec = both(*inst, full="all")
    assert vec.decisions == ref.decisions  # node, score and every node's verdict
    assert vec.metrics == ref.metrics and vec.params == ref.params


@settings(max_examples=400, deadline=None)
@given(instances(), st.integers(1, 4), st.integers(0, 3))
def test_bounded_explanations_keep_the_choice_counts_and_top_candidates(inst, top_k, examples):
    ref, vec = both(*inst, top_k=top_k, examples=examples)
    for r, v in zip(ref.decisions, vec.decisions, strict=True):
        assert (v.item, v.node, v.score) == (r.item, r.node, r.score)
        full = {x.node: x for x in r.verdicts}
        assert all(full[x.node] == x for x in v.verdicts)  # each kept verdict is the reference's
        counts = {}
        for x in r.verdicts:
            if x.rejected_by:
                counts[x.rejected_by] = counts.get(x.rejected_by, 0) + 1
        assert dict(v.rejections) == counts
        scored = sorted((x for x in r.verdicts if not x.rejected_by), key=lambda x: (-x.total, x.node))
        kept = [x for x in v.verdicts if not x.rejected_by]
        assert len(kept) == min(top_k, len(scored))
        expected = [x.node for x in scored[:top_k]]
        if r.node is not None and r.node not in expected:  # a near tie (1e-12): the chosen node is kept first
            expected = [r.node, *expected[: top_k - 1]]
        assert [x.node for x in kept] == expected


def test_ties_go_to_the_lowest_name_like_the_reference():
    nodes = [RTNode(f"n{i}", True, "A", 8.0, math.inf, 7.6, (RT_TAINT,)) for i in (3, 1, 2)]
    c = RTContainer("x", "A", 100.0, 100.0, {"n1": 10.0, "n2": 10.0, "n3": 10.0}, tolerations=(RT_TOLERATION,))
    assert rt_kube_vec.schedule([c], nodes).placed() == rt_kube.schedule([c], nodes).placed() == {"x": "n1"}


def test_near_ties_follow_the_reference_scan():
    """Scores 1e-12 apart: the reference keeps the first unless a later one beats it by more than 1e-12."""
    import numpy as np

    s = np.array([0.5, 0.5 + 0.6e-12, 0.5 + 1.2e-12, -np.inf, 0.5 + 1.9e-12, 0.4])
    best = None
    for i, x in enumerate(s.tolist()):
        if x != -math.inf and (best is None or x > best[0] + 1e-12):
            best = (x, i)
    assert rt_kube_vec._choose(s) == best[1] == 2
    assert rt_kube_vec._choose(np.full(4, -np.inf)) is None


def test_explanations_stay_bounded_at_scale():
    """5,000 nodes x 200 pods: each decision keeps a bounded number of verdicts; the why-not of any node is the
    reference's verdict."""
    nodes = []
    for i in range(5000):
        rt = i % 2 == 0
        taints = (RT_TAINT,) if rt else ((Taint("gpu", "yes"),) if i % 7 == 0 else ())
        nodes.append(RTNode(f"node{i:05d}", rt, "C" if i % 10 == 0 else "A", 8.0, 16384.0, 7.6, taints))
    rt_names = [n.name for n in nodes if n.rt]
    containers = [
        RTContainer(
            f"pod{j}",
            "ABC"[j % 3],
            100.0,
            100.0,
            {n: 5.0 + j % 7 for n in rt_names[j % 5 :: 3]},
            cpu=0.5,
            memory_mib=256.0,
            tolerations=(RT_TOLERATION,),
        )
        for j in range(200)
    ]
    book = Ledger([n.name for n in nodes])
    plan = rt_kube_vec.schedule(containers, nodes, ledger=book)
    per_decision = max(len(json.dumps(d.to_dict())) for d in plan.decisions)
    limit = rt_kube_vec.TOP_K + rt_kube_vec.EXAMPLES * (len(rt_kube_vec.FILTERS) - 1)
    assert all(len(d.verdicts) <= limit for d in plan.decisions)
    assert all(sum(d.rejections.values()) + sum(1 for v in d.verdicts if not v.rejected_by) <= 5000
               for d in plan.decisions)  # fmt: skip
    assert per_decision < 8000  # bytes, against ~1 MB with every node's verdict
    assert len(json.dumps(plan.to_dict())) < 200 * 8000 + 500_000
    assert all(d.node for d in plan.decisions)
    d = plan.decisions[0]
    assert d.rejections["TaintToleration"] == sum(1 for n in nodes if n.taints and not n.rt)
    c = next(c for c in containers if c.name == d.item)
    (why,) = rt_kube_vec.why_not(c, nodes, book, node="node00001")
    assert why == rt_kube.node_verdict(c, nodes[1], book) and why.rejected_by == "RealTimeNode"


@pytest.mark.parametrize("full", ["bogus", ""])
def test_bad_full_mode_is_refused(full):
    with pytest.raises(ValueError):
        rt_kube_vec.schedule([], [RTNode("a")], full=full)


def test_bound_decision_of_a_stored_reference_decision():
    nodes = [RTNode(f"n{i}", i % 3 != 0, None, 4.0, math.inf, 3.8, ()) for i in range(20)]
    c = RTContainer("x", "A", 100.0, 100.0, {f"n{i}": 10.0 + i for i in range(0, 20, 2)})
    ref = rt_kube.schedule([c], nodes).decisions[0]
    doc = rt_kube_vec.bound_decision(ref.to_dict(), top_k=3, examples=2)
    assert doc["node"] == ref.node and doc["verdicts"][0]["node"] == ref.node
    assert doc["rejections"] == {"RealTimeNode": 7, "RealTimeWcet": 7}
    assert len(doc["verdicts"]) == 3 + 2 + 2
    assert rt_kube_vec.bound_decision(doc) == doc  # idempotent


def _h(z):
    return 0.3 * z + 0.6


def _g(z):
    return 1.2 - z * z


@settings(max_examples=100, deadline=None)
@given(instances())
def test_callable_curves_give_the_reference_choices(inst):
    containers, nodes, bindings, params, now = inst
    params = RTKubeParams(k=params.k, h=_h, g=_g, b_score_argument=params.b_score_argument)
    ref, vec = both(containers, nodes, bindings, params, now, full="all")
    assert vec.decisions == ref.decisions

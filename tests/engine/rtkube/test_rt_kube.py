"""RT-Kube's scheduler: Algorithm 3 (filter), Algorithm 4 / Eqs. 3.17-3.18 (score), sort and bind."""

import itertools
import random

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from continuum.engine import InputError
from continuum.engine.rtkube.rt_kube import (
    Ledger,
    RTKubeParams,
    b_curve,
    explain,
    kube_default,
    kube_score,
    n_rank,
    place_one,
    placements_by_node,
    rt_filter,
    rt_score,
    schedule,
    sort_queue,
)
from continuum.engine.rtkube.rt_model import RTContainer, Taint, cluster_from_dict, rtset_from_dict, untolerated


def node(name, cpu=8, crit="A", rt=True, **kw):
    return cluster_from_dict({"nodes": [{"name": name, "cpu": cpu, "rt": rt, "criticality": crit, **kw}]})[0]


def rtc(name, crit="A", wcet=None, period=100.0, arrival=0.0, **kw):
    doc = {"name": name, "criticality": crit, "period": period, "deadline": period, "wcet": wcet or {}}
    doc.update(arrival=arrival, **kw)
    return rtset_from_dict({"containers": [doc]})[0]


# ---- Eq. 3.17/3.18, Algorithm 4: the reference table of spec 03 section 4.3 ---------------------------------------
TABLE = [
    # newUT, nRank, s_A, s_B, s_C   (thresholdUT = 7.6)
    (0.00, 1.00, 0.00, 0.0000, 1.00),
    (0.76, 0.90, 0.10, 0.1333, 0.90),
    (1.90, 0.75, 0.25, 0.3958, 0.75),
    (3.80, 0.50, 0.50, 1.0000, 0.50),
    (5.70, 0.25, 0.75, 0.9500, 0.25),
    (6.84, 0.10, 0.90, 0.9200, 0.10),
    (7.60, 0.00, 1.00, 0.9000, 0.00),
]


@pytest.mark.parametrize(("new_ut", "rank", "s_a", "s_b", "s_c"), TABLE)
def test_scores_match_the_reference_table(new_ut, rank, s_a, s_b, s_c):
    assert n_rank(7.6, new_ut) == pytest.approx(rank, abs=1e-12)
    assert rt_score("A", 7.6, new_ut) == pytest.approx(s_a, abs=1e-4)
    assert rt_score("B", 7.6, new_ut) == pytest.approx(s_b, abs=1e-4)
    assert rt_score("C", 7.6, new_ut) == pytest.approx(s_c, abs=1e-4)


def test_b_curve_properties():
    assert b_curve(0.0) == pytest.approx(0.9)
    assert b_curve(0.5) == pytest.approx(1.0)  # h(1/2)
    g = (5 / 3, -9 / 2, 17 / 6)
    assert RTKubeParams().g == g
    assert pytest.approx(1.0) == 5 / 3 * 0.25 - 9 / 2 * 0.5 + 17 / 6  # g(1/2): continuous at 1/K
    assert b_curve(1.0) == pytest.approx(0.0, abs=1e-12)  # g(1)
    zs = [0.5 + i / 200 for i in range(1, 101)]
    values = [b_curve(z) for z in zs]
    assert all(a > b for a, b in itertools.pairwise(values))  # decreasing on (1/2, 1]
    assert RTKubeParams(g=g) == RTKubeParams()


def test_b_score_load_reading_and_custom_curves():
    load = RTKubeParams(b_score_argument="load")
    assert rt_score("B", 7.6, 7.6, load) == pytest.approx(0.0, abs=1e-12)  # full node scores g(1) = 0
    assert rt_score("B", 7.6, 0.0, load) == pytest.approx(0.9)
    # K -> 1 with increasing h: B packs like A.
    like_a = RTKubeParams(k=1.0, h=lambda z: 1 - z)
    for new_ut in (0.5, 2.0, 7.0):
        assert rt_score("B", 7.6, new_ut, like_a) == pytest.approx(rt_score("A", 7.6, new_ut))
    assert kube_score(rt_score("B", 7.6, 1.9)) == 40
    with pytest.raises(InputError, match="K must be positive"):
        RTKubeParams(k=0)
    with pytest.raises(InputError, match="b_score_argument"):
        RTKubeParams(b_score_argument="both")
    with pytest.raises(InputError, match="no RT score"):
        rt_score("NONE", 7.6, 1.0)


def loaded_pair(crit_nodes):
    """Two nodes of 8 cores whose newUT after adding a U = 0.1 container is 1.9 and 5.7."""
    n1, n2 = node("n1", crit=crit_nodes), node("n2", crit=crit_nodes)
    ledger = Ledger.for_nodes([n1, n2])
    crit = "C" if crit_nodes == "C" else "A"
    for name, total in (("n1", 1.8), ("n2", 5.6)):
        for i in range(round(total / 0.2)):
            ledger.reserve(rtc(f"{name}-f{i}", crit, {name: 2}, 10.0), name)  # U = 0.2 each
    return [n1, n2], ledger


@pytest.mark.parametrize(
    ("crit", "node_class", "params", "expected"),
    [
        ("A", "A", RTKubeParams(), "n2"),  # consolidates: 0.75 > 0.25
        ("C", "C", RTKubeParams(), "n1"),  # spreads
        ("B", "A", RTKubeParams(), "n2"),  # 0.95 > 0.3958 under the literal Eq. 3.18
        ("B", "A", RTKubeParams(b_score_argument="load"), "n1"),
    ],
)
def test_choice_between_newut_1_9_and_5_7(crit, node_class, params, expected):
    nodes, ledger = loaded_pair(node_class)
    x = rtc("x", crit, {"n1": 10, "n2": 10})
    d = place_one(x, nodes, ledger, params)
    assert d.node == expected
    news = {v.node: v.reason for v in d.verdicts}
    assert "newUT 1.9000" in news["n1"] and "newUT 5.7000" in news["n2"]


# ---- Algorithm 3 ---------------------------------------------------------------------------------------------------
def test_admission_uses_less_or_equal():
    n = node("j", cpu=8)
    cs = [rtc(f"t{i}", "A", {"j": 3.8}, 4.0, arrival=i) for i in range(9)]
    plan = schedule(cs, [n])
    assert [d.node for d in plan.decisions] == ["j"] * 8 + [None]
    assert plan.metrics["utilization"]["j"] == pytest.approx(7.6)
    [pending] = plan.to_dict()["pending"]
    assert pending == {"container": "t8", "reasons": {"j": "projected RT utilization 8.5500 > threshold 7.6000"}}
    assert plan.decisions[-1].verdicts[0].rejected_by == "RealTimeAdmission"


def test_xor_and_taints():
    c_node, ab_node, plain = node("c", crit="C"), node("ab", crit="B"), node("plain", rt=False, crit=None)
    nodes = [c_node, ab_node, plain]
    ledger = Ledger.for_nodes(nodes)
    wcet = {"c": 1, "ab": 1, "plain": 1}
    for crit, allowed in (("C", {"c"}), ("B", {"ab"}), ("A", {"ab"})):
        d = place_one(rtc("x", crit, wcet), nodes, ledger)
        assert {v.node for v in d.verdicts if v.rejected_by is None} == allowed
        assert {v.node: v.rejected_by for v in d.verdicts}["plain"] == "RealTimeNode"
    d = place_one(rtc("x", "A", wcet), nodes, ledger)
    assert d.reasons()["c"] == "non-C container on a C node"
    d = place_one(rtc("x", "C", wcet), nodes, ledger)
    assert d.reasons()["ab"] == "C container on a non-C node"
    web = RTContainer("web")
    d = place_one(web, nodes, ledger)
    assert d.node == "plain"
    assert d.reasons() == {
        "c": "untolerated taint RealTime=RT:NoSchedule",
        "ab": "untolerated taint RealTime=RT:NoSchedule",
    }


def test_missing_wcet_resources_and_timed_taints():
    n1, n2 = node("n1", cpu=2, memory_mib=1000), node("n2", cpu=2)
    ledger = Ledger.for_nodes([n1, n2])
    f = rt_filter(rtc("x", "A", {"n2": 1}), n1, ledger)
    assert (f.rejected_by, f.reason) == ("RealTimeWcet", "no WCET given for this node")
    f = rt_filter(rtc("x", "A", {"n1": 1}, cpu=3), n1, ledger)
    assert f.rejected_by == "NodeResourcesFit" and "insufficient cpu" in f.reason
    f = rt_filter(rtc("x", "A", {"n1": 1}, memory_mib=2000), n1, ledger)
    assert f.rejected_by == "NodeResourcesFit" and "insufficient memory" in f.reason
    tainted = n1.with_taint(Taint("rt.monitoring/violation", "true", "NoSchedule", until=60.0))
    x = rtc("x", "A", {"n1": 1})
    assert rt_filter(x, tainted, ledger, now=59.9).rejected_by == "TaintToleration"
    assert rt_filter(x, tainted, ledger, now=60.0).rejected_by is None


def test_pending_until_capacity_is_freed():
    n = node("n", cpu=1)
    ledger = Ledger.for_nodes([n])
    first = schedule([rtc("a", "A", {"n": 0.9}, 1.0)], [n], ledger=ledger)
    assert first.placed() == {"a": "n"}
    second = schedule([rtc("b", "A", {"n": 0.5}, 1.0)], [n], ledger=ledger)
    assert second.placed() == {} and ledger.where("b") is None
    ledger.release("a")
    third = schedule([rtc("b", "A", {"n": 0.5}, 1.0)], [n], ledger=ledger)
    assert third.placed() == {"b": "n"} and ledger.current_ut("n") == pytest.approx(0.5)


def test_sort_queue_orders():
    cs = [
        rtc("a_late", "A", {"n": 1}, arrival=5),
        RTContainer("std", arrival=0),
        rtc("c1", "C", {"n": 1}, arrival=9),
        rtc("b_big", "B", {"n": 50}, arrival=3),
        rtc("b_small", "B", {"n": 1}, arrival=1),
        rtc("a_early", "A", {"n": 1}, arrival=2),
    ]
    assert [c.name for c in sort_queue(cs)] == ["c1", "b_small", "b_big", "a_early", "a_late", "std"]
    assert [c.name for c in sort_queue(cs, "utilization")][:3] == ["c1", "b_big", "b_small"]


def test_bind_reserves_for_later_containers_in_the_same_pass():
    # Two C nodes; C spreads, so the second container sees the first one's reservation.
    nodes = [node("c1", crit="C"), node("c2", crit="C")]
    plan = schedule(
        [rtc("x", "C", {"c1": 10, "c2": 10}, arrival=0), rtc("y", "C", {"c1": 10, "c2": 10}, arrival=1)], nodes
    )
    assert plan.placed() == {"x": "c1", "y": "c2"}  # tie at first -> lowest name
    rows = explain(plan)
    assert len(rows) == 4 and sum(r["chosen"] for r in rows) == 2


# ---- the thesis' experiments (Tables 4.31, 4.32) -----------------------------------------------------------------
def thesis_cluster(taints=True):
    extra = {} if taints else {"taints": []}
    return cluster_from_dict(
        {
            "nodes": [
                {"name": "J", "cpu": 8, "rt": True, "criticality": "C", **extra},
                {"name": "I", "cpu": 16, "rt": True, "criticality": "A", **extra},  # spec 03 #17: M = 16
                {"name": "R", "cpu": 8, "rt": False},
            ]
        }
    )


def deployment(n_a, n_b, n_c):
    docs = []
    for cls, n, period in (("A", n_a, 24.2), ("B", n_b, 18.1), ("C", n_c, 14.5)):
        for i in range(n):
            docs.append({"name": f"{cls}{i}", "criticality": cls, "period": period, "deadline": period,
                         "wcet": {"J": 2.9, "I": 2.9, "R": 2.9}})  # fmt: skip
    docs.append({"name": "stress", "criticality": None})
    return rtset_from_dict({"containers": docs})


@pytest.mark.parametrize("mix", [(32, 24, 16), (16, 24, 32)])
def test_table_4_31_rt_kube_placement(mix):
    plan = schedule(deployment(*mix), thesis_cluster())
    by_node = placements_by_node(plan)
    assert sorted(by_node["J"]) == sorted(f"C{i}" for i in range(mix[2]))
    assert len(by_node["I"]) == mix[0] + mix[1] and all(n[0] in "AB" for n in by_node["I"])
    assert by_node["R"] == ["stress"] and plan.to_dict()["pending"] == []
    assert plan.metrics["utilization"]["J"] <= 7.6


def cyclic(name, nodes, arrival=0):
    return rtc(name, "A", {n: 3.8 for n in nodes}, 4.0, arrival=arrival)


def test_table_4_32_rt_kube_rows():
    n1, n2 = node("N1"), node("N2")
    # both full: the new container stays pending
    ledger = Ledger.for_nodes([n1, n2])
    for i in range(8):
        ledger.reserve(cyclic(f"a{i}", ["N1"]), "N1")
        ledger.reserve(cyclic(f"b{i}", ["N2"]), "N2")
    plan = schedule([cyclic("new", ["N1", "N2"])], [n1, n2], ledger=ledger)
    assert plan.placed() == {} and set(plan.to_dict()["pending"][0]["reasons"]) == {"N1", "N2"}
    # N2 empty: always N2
    ledger = Ledger.for_nodes([n1, n2])
    for i in range(8):
        ledger.reserve(cyclic(f"a{i}", ["N1"]), "N1")
    assert schedule([cyclic("new", ["N1", "N2"])], [n1, n2], ledger=ledger).placed() == {"new": "N2"}


def test_native_kubernetes_picks_the_empty_node_half_of_the_time():
    n1, n2 = node("N1", taints=[]), node("N2", taints=[])
    picks = 0
    for seed in range(1000):
        ledger = Ledger.for_nodes([n1, n2])
        for i in range(8):
            ledger.reserve(cyclic(f"a{i}", ["N1"]), "N1")
        plan = kube_default([cyclic("new", ["N1", "N2"])], [n1, n2], ledger, random.Random(seed))
        picks += plan.placed()["new"] == "N2"
    assert 450 <= picks <= 550


def test_kube_default_pins_and_ignores_rt_utilization():
    nodes = thesis_cluster(taints=False)
    plan = kube_default(deployment(32, 24, 16), nodes, pin="J")
    assert set(plan.placed().values()) == {"J"} and plan.metrics["utilization"]["J"] > 7.6
    with pytest.raises(InputError, match="pinned node 'X'"):
        kube_default([], nodes, pin="X")


# ---- properties on generated inputs -------------------------------------------------------------------------------
@st.composite
def clusters_and_sets(draw):
    n_nodes = draw(st.integers(1, 4))
    nodes = []
    for i in range(n_nodes):
        nodes.append(
            {
                "name": f"n{i}",
                "cpu": draw(st.integers(1, 8)),
                "rt": draw(st.booleans()),
                "criticality": draw(st.sampled_from(["A", "B", "C", None])),
                "memory_mib": draw(st.sampled_from([512, 4096])),
            }
        )
    containers = []
    for j in range(draw(st.integers(1, 25))):
        crit = draw(st.sampled_from(["A", "B", "C", "NONE"]))
        period = draw(st.integers(2, 100))
        wcet = {f"n{i}": draw(st.integers(1, period)) for i in range(n_nodes) if draw(st.booleans())} or {"n0": 1}
        containers.append({"name": f"c{j}", "criticality": crit, "period": period, "deadline": period, "wcet": wcet,
                           "cpu": draw(st.sampled_from([None, 0.5, 2])),
                           "memory_mib": draw(st.sampled_from([None, 256])), "arrival": j})  # fmt: skip
    return cluster_from_dict({"nodes": nodes}), rtset_from_dict({"containers": containers})


@settings(max_examples=150, deadline=None)
@given(clusters_and_sets(), st.sampled_from(["free", "load"]))
def test_every_placement_respects_the_filters(data, b_arg):
    nodes, containers = data
    plan = schedule(containers, nodes, RTKubeParams(b_score_argument=b_arg))
    by_name = {c.name: c for c in containers}
    by_node = {n.name: n for n in nodes}
    for d in plan.decisions:
        assert sorted(v.node for v in d.verdicts) == sorted(by_node)  # every node judged
        c = by_name[d.item]
        if d.node is None:
            assert set(d.reasons()) == set(by_node)
            continue
        n = by_node[d.node]
        assert not untolerated(n.taints, c.tolerations)
        if c.is_rt:
            assert n.rt and d.node in c.wcet
            assert (c.criticality == "C") == n.is_c_node
            assert 0.0 <= d.score <= 1.0 + 1e-9
    util = plan.metrics["utilization"]
    for n in nodes:
        assert util[n.name] <= n.rt_threshold * (1 + 1e-9)
        placed = [by_name[i] for i, where in plan.placed().items() if where == n.name]
        assert sum(c.cpu for c in placed) <= n.cpu + 1e-9
        assert sum(c.memory_mib for c in placed) <= n.memory_mib
    order = [by_name[d.item] for d in plan.decisions]
    assert [c.rank for c in order] == sorted((c.rank for c in order), reverse=True)


def test_a_ledger_built_at_once_equals_one_built_by_reserve():
    nodes = [node("N1"), node("N2")]
    placed = [
        (rtc(f"c{i}", "AB"[i % 2], {"N1": 1 + i % 3, "N2": 2}, cpu=0.1 * (i + 1)), f"N{1 + i % 2}") for i in range(9)
    ]
    one_by_one = Ledger.for_nodes(nodes)
    for c, n in placed:
        one_by_one.reserve(c, n)
    at_once = Ledger.with_reservations(nodes, placed)
    assert at_once.bindings == one_by_one.bindings
    assert at_once.utilization() == one_by_one.utilization()
    assert [at_once.cpu_used(n) for n in ("N1", "N2")] == [one_by_one.cpu_used(n) for n in ("N1", "N2")]
    with pytest.raises(InputError, match="already bound"):
        Ledger.with_reservations(nodes, [placed[0], (placed[0][0], "N2")])

"""The cluster graph G^c: continuum.cluster/v1 -> Platform, routing (latency / OSPF), node removal."""

import pytest

from continuum.engine import InputError, Platform
from continuum.engine.core.cluster import Cluster, cluster_platform
from continuum.engine.core.platform import Link, Processor


def doc(**extra):
    base = {
        "format": "continuum.cluster/v1",
        "nodes": [
            {"name": "jetson", "arch": "arm64", "cpu": 6, "memory_mib": 8192, "class": "arm", "speed": 0.5},
            {"name": "mcb", "cpu": 4},
            {"name": "server", "cpu": 2.5},
        ],
        "links": [
            {"src": "jetson", "dst": "mcb", "bandwidth_mbps": 1000, "latency_ms": 0.5},
            {"src": "mcb", "dst": "server", "bandwidth_mbps": 250, "latency_ms": 2.0},
        ],
    }
    base.update(extra)
    return base


def test_nodes_become_multicore_processors():
    p = cluster_platform(doc())
    assert [(q.id, q.cls, q.speed, q.cores) for q in p.processors] == [
        ("jetson", "arm", 0.5, 6),
        ("mcb", "cpu", 1.0, 4),
        ("server", "cpu", 1.0, 2),
    ]
    assert p.route and p.routing == "ospf"


def test_link_units_mbit_and_ms():
    p = cluster_platform(doc())
    # 1000 Mbit/s moves 1 Mbit per ms: 2 Mbit take 2 ms plus the 0.5 ms latency.
    assert p.comm_time("jetson", "mcb", 2.0) == pytest.approx(2.5)
    assert p.comm_time("mcb", "server", 1.0) == pytest.approx(2.0 + 4.0)
    assert p.comm_time("mcb", "mcb", 5.0) == 0.0


def test_unlinked_nodes_store_and_forward_over_the_ospf_path():
    p = cluster_platform(doc())
    # jetson -> mcb -> server: latencies add, and so do the per-hop transfer times.
    assert p.comm_time("jetson", "server", 1.0) == pytest.approx(0.5 + 2.0 + 1.0 + 4.0)


def test_latency_routing_uses_the_bottleneck_bandwidth():
    p = cluster_platform(doc(), routing="latency")
    assert p.comm_time("jetson", "server", 1.0) == pytest.approx(0.5 + 2.0 + 4.0)


def test_ospf_prefers_two_fast_hops_to_a_slow_direct_link():
    procs = [Processor("a"), Processor("b"), Processor("c")]
    links = [Link("a", "b", 2.0, 1.0), Link("b", "c", 1.0, 1.0), Link("a", "c", 0.5, 0.5)]
    ospf = Platform(procs, links=links, route=True, routing="ospf")
    assert ospf.comm_time("a", "c", 1.0) == pytest.approx(2.0 + 0.5 + 1.0)  # via b: sum 1/bw = 1.5
    latency = Platform(procs, links=links, route=True)
    assert latency.comm_time("a", "c", 1.0) == pytest.approx(0.5 + 2.0)  # the direct link always wins


def test_latency_routing_breaks_ties_by_the_wider_path():
    procs = [Processor(x) for x in "abcd"]
    links = [Link("a", "b", 1.0), Link("b", "d", 1.0), Link("a", "c", 4.0), Link("c", "d", 4.0)]
    p = Platform(procs, links=links, route=True)
    assert p.comm_time("a", "d", 4.0) == pytest.approx(1.0)  # via c, bottleneck 4


def test_default_bandwidth_for_disconnected_nodes():
    d = doc(links=[], default_bandwidth_mbps=500, default_latency_ms=1.0)
    p = cluster_platform(d)
    assert p.comm_time("jetson", "server", 1.0) == pytest.approx(3.0)
    free = cluster_platform(doc(links=[]))
    assert free.comm_time("jetson", "server", 100.0) == 0.0


def test_without_removes_nodes_and_reroutes():
    p = cluster_platform(doc())
    q = p.without(["mcb"])
    assert [x.id for x in q.processors] == ["jetson", "server"]
    assert q.links == []
    assert q.comm_time("jetson", "server", 3.0) == 0.0  # no path left and no default: free, as the clusters app
    with pytest.raises(InputError, match="unknown processor 'nope'"):
        p.without(["nope"])
    with pytest.raises(InputError, match="no processor is left"):
        p.without(["jetson", "mcb", "server"])


def test_platform_cores_round_trip():
    p = cluster_platform(doc())
    again = Platform.from_dict(p.to_dict())
    assert [x.cores for x in again.processors] == [6, 4, 2]
    assert again.routing == "ospf"
    with pytest.raises(InputError, match="invalid cores 0"):
        Platform.from_dict({"processors": [{"id": "x", "cores": 0}]})


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"nodes": []}, "'nodes' must be a non-empty list"),
        ({"nodes": [{"name": "a"}, {"name": "a"}]}, "duplicate node name 'a'"),
        ({"nodes": [{"cpu": 2}]}, r"nodes\[0\] has no string 'name'"),
        ({"nodes": [{"name": "a", "cpu": 0}]}, "node 'a' cpu must be a positive number"),
        ({"links": [{"src": "jetson", "dst": "moon", "bandwidth_mbps": 5}]}, "unknown node 'moon'"),
        ({"links": [{"src": "jetson", "dst": "mcb"}]}, "link jetson-mcb has no 'bandwidth_mbps'"),
        ({"links": [{"src": "jetson", "dst": "mcb", "bandwidth_mbps": -1}]}, "bandwidth_mbps must be a positive"),
        ({"links": [{"src": "mcb", "dst": "mcb", "bandwidth_mbps": 1}]}, "joins node 'mcb' to itself"),
        ({"format": "continuum.dag/v1"}, "unsupported format"),
    ],
)
def test_bad_cluster_documents_name_the_problem(change, message):
    with pytest.raises(InputError, match=message):
        cluster_platform(doc(**change))


# ---- one parser of continuum.cluster/v1 (issue 11) ------------------------------------------------------
@pytest.mark.parametrize("raw", ["false", "true", "yes", 0, 1, None])
def test_rt_must_be_a_json_boolean(raw):
    from continuum.engine.rtkube.rt_model import cluster_from_dict as rt_cluster_from_dict

    doc = {"nodes": [{"name": "n", "rt": raw}]}
    for parse in (Cluster.from_dict, rt_cluster_from_dict):
        with pytest.raises(InputError, match=r"node 'n': rt must be true or false \(a JSON boolean\)") as err:
            parse(doc)
        assert repr(raw) in str(err.value)


def test_rt_view_is_built_from_the_core_parse():
    from continuum.engine.core.cluster import RT_FRACTION, default_rt_threshold
    from continuum.engine.rtkube.rt_model import RT_TAINT, cluster_from_dict, rt_nodes

    doc = {
        "nodes": [
            {"name": "j", "cpu": 8, "rt": True, "criticality": "C", "sched_rt_runtime_us": 900_000},
            {"name": "s", "cpu": 4, "rt": False, "memory_mib": 512, "taints": []},
        ]
    }
    cluster = Cluster.from_dict(doc)
    assert cluster.nodes["j"].extra == {} and cluster.nodes["j"].sched_rt_runtime_us == 900_000
    assert rt_nodes(cluster) == cluster_from_dict(doc)
    j, s = rt_nodes(cluster)
    assert j.rt_threshold == pytest.approx(7.2) and j.taints == (RT_TAINT,)
    assert s.rt_threshold == pytest.approx(default_rt_threshold(4)) == pytest.approx(4 * RT_FRACTION) == 3.8
    assert Cluster.from_dict(cluster.to_dict()).nodes == cluster.nodes
    with pytest.raises(InputError, match="sched_rt_runtime_us exceeds sched_rt_period_us"):
        Cluster.from_dict({"nodes": [{"name": "n", "sched_rt_runtime_us": 2_000_000}]})

import pytest

pytestmark = pytest.mark.django_db


def test_import_cluster_document(cluster):
    assert sorted(cluster.nodes.values_list("name", flat=True)) == ["node0", "node1", "node2", "node3"]
    assert cluster.links.count() == 3
    platform = cluster.to_platform()
    # node0 -> node3 has no direct link: three store-and-forward hops of 0.5 ms at 1000 Mbit/s = 1 Mbit/ms.
    assert platform.comm_time("node0", "node3", 2.0) == pytest.approx(3 * (0.5 + 2.0))
    assert [p.cores for p in platform.processors] == [4, 4, 4, 4]


@pytest.mark.parametrize(
    ("change", "field"),
    [
        (lambda d: d["links"].append({"src": "node0", "dst": "ghost", "bandwidth_mbps": 1}), "links"),
        (lambda d: d["nodes"].append(dict(d["nodes"][0])), "nodes"),
        (lambda d: d["nodes"][0].update(arch="sparc"), "nodes"),
        (lambda d: d["nodes"][0].update(cpu=-1), "nodes"),
        (lambda d: d["links"][0].update(bandwidth_mbps=0), "links"),
    ],
)
def test_bad_cluster_document_is_rejected_and_nothing_stored(api, cluster_doc, change, field):
    from apps.clusters.models import Cluster, ComputeNode

    change(cluster_doc)
    response = api.post("/api/v1/clusters/import/", {"name": "bad", **cluster_doc}, format="json")
    assert response.status_code == 400
    assert field in response.data
    assert not Cluster.objects.filter(name="bad").exists() and ComputeNode.objects.count() == 0


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda d: d["nodes"][0].update(rt="false"), "rt must be true or false (a JSON boolean), not 'false'"),
        (lambda d: d["nodes"][0].update(cpu=0), "node 'node0' cpu must be a positive number, not 0"),
        (lambda d: d.update(format="continuum.cluster/v2"), "unsupported format 'continuum.cluster/v2'"),
    ],
)
def test_the_api_reads_a_cluster_document_with_the_engines_one_parser(api, cluster_doc, change, message):
    """What a placer or command would refuse in the file, the API refuses too (it took "rt": "false" as false)."""
    from apps.clusters.models import Cluster

    change(cluster_doc)
    response = api.post("/api/v1/clusters/import/", {"name": "bad", **cluster_doc}, format="json")
    assert response.status_code == 400, response.data
    assert any(message in str(e) for errors in response.data.values() for e in errors), response.data
    assert not Cluster.objects.filter(name="bad").exists()


def test_the_api_stores_what_the_file_means(api, cluster_doc):
    """The format's ``class`` is the node's processor class, and ``sched_rt_*`` set the RT threshold, as the
    engine reads the same file (the API used to drop both)."""
    from apps.clusters.models import Cluster
    from continuum.engine.core.cluster import Cluster as EngineCluster

    cluster_doc["nodes"][0].update({"class": "gpu"})
    cluster_doc["nodes"][1].update({"rt": True, "sched_rt_runtime_us": 500_000, "sched_rt_period_us": 1_000_000})
    response = api.post("/api/v1/clusters/import/", {"name": "file", **cluster_doc}, format="json")
    assert response.status_code == 201, response.data
    nodes = {n.name: n for n in Cluster.objects.get(name="file").nodes.all()}
    engine = EngineCluster.from_dict(cluster_doc).nodes
    assert nodes["node0"].processor_class == engine["node0"].cls == "gpu"
    assert nodes["node1"].rt_capacity == pytest.approx(engine["node1"].rt_capacity) == pytest.approx(4 * 0.5)
    assert nodes["node2"].processor_class == "cpu" and nodes["node2"].rt_threshold is None


def test_link_must_stay_inside_its_cluster(api, cluster, cluster_doc):
    other = api.post("/api/v1/clusters/import/", {"name": "other", **cluster_doc}, format="json").data
    foreign = api.get(f"/api/v1/nodes/?cluster={other['id']}").data["results"][0]["id"]
    mine = cluster.nodes.first().pk
    response = api.post(
        "/api/v1/links/", {"cluster": cluster.pk, "src": mine, "dst": foreign, "bandwidth_mbps": 10}, format="json"
    )
    assert response.status_code == 400 and "dst" in response.data


def test_one_rule_for_nodes_that_are_not_ready(cluster):
    """Cluster.to_engine keeps every node; one that is not Ready carries the taint Kubernetes gives it, so the
    placers exclude it with that reason; the DAG schedulers' platform leaves it out (issue 11)."""
    from apps.clusters.models import ComputeNode
    from apps.containers.services import engine_cluster
    from apps.realtime.planning import db_rt_nodes
    from continuum.engine.core.errors import InputError
    from continuum.engine.core.taints import NOT_READY, UNREACHABLE

    cluster.nodes.filter(name="node1").update(status=ComputeNode.Status.NOT_READY)
    cluster.nodes.filter(name="node2").update(status=ComputeNode.Status.UNKNOWN)
    engine = cluster.to_engine()
    assert list(engine.nodes) == ["node0", "node1", "node2", "node3"]
    assert NOT_READY in engine.nodes["node1"].taints and UNREACHABLE in engine.nodes["node2"].taints
    assert not engine.nodes["node0"].taints and not engine.nodes["node3"].taints
    assert [p.id for p in cluster.to_platform().processors] == ["node0", "node3"]
    assert [p.id for p in cluster.to_platform(ready_only=False).processors] == ["node0", "node1", "node2", "node3"]
    # the other adapters are this one
    assert engine_cluster(cluster).nodes == engine.nodes
    rt = {n.name: n for n in db_rt_nodes(cluster)}
    assert list(rt) == ["node0", "node1", "node2", "node3"]
    assert NOT_READY in rt["node1"].taints and UNREACHABLE in rt["node2"].taints
    cluster.nodes.update(status=ComputeNode.Status.NOT_READY)
    with pytest.raises(InputError, match="has no node its pods may be placed on"):
        cluster.to_platform()


def test_rt_capacity_is_the_engines_default(cluster):
    from continuum.engine.core.cluster import RT_FRACTION

    node = cluster.nodes.get(name="node0")
    assert node.rt_threshold is None and node.rt_capacity == node.cpu * RT_FRACTION == 4 * 0.95
    assert cluster.to_engine().nodes["node0"].rt_capacity == node.rt_capacity
    node.rt_threshold = 2.5
    assert node.rt_capacity == 2.5

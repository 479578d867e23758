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


def test_link_must_stay_inside_its_cluster(api, cluster, cluster_doc):
    other = api.post("/api/v1/clusters/import/", {"name": "other", **cluster_doc}, format="json").data
    foreign = api.get(f"/api/v1/nodes/?cluster={other['id']}").data["results"][0]["id"]
    mine = cluster.nodes.first().pk
    response = api.post(
        "/api/v1/links/", {"cluster": cluster.pk, "src": mine, "dst": foreign, "bandwidth_mbps": 10}, format="json"
    )
    assert response.status_code == 400 and "dst" in response.data

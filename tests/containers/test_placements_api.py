"""Placements through the API: super-clustering and the default-Kubernetes baseline as jobs, the "why" table
of every container, bad requests, idempotent jobs."""

import json

import pytest
from django.core.files.uploadedfile import SimpleUploadedFile

from apps.containers.kinds import ContainersJob
from apps.containers.models import Placement
from apps.jobs.models import Job
from apps.jobs.registry import HANDLERS
from tests.conftest import DATA

pytestmark = pytest.mark.django_db

# Spec 02 section 5.3: Fig. 3.28 with the reconstructed weights and priorities C4 > C0 > C1 > C2 > C3.
FIG_3_28 = {
    "format": "continuum.containers/v1",
    "containers": [
        {"name": c, "priority": p, "cpu": 2 if c == "C4" else 1}
        for c, p in {"C4": 5, "C0": 4, "C1": 3, "C2": 2, "C3": 1}.items()
    ],
    "bandwidth": [
        {"a": a, "b": b, "bytes_per_s": w}
        for a, b, w in [
            ("C0", "C1", 2),
            ("C1", "C4", 1),
            ("C1", "C2", 1),
            ("C2", "C4", 2),
            ("C1", "C3", 4),
            ("C2", "C3", 3),
        ]
    ],
}


def run(api, url: str, body: dict | None = None) -> dict:
    response = api.post(url, body or {}, format="json")
    assert response.status_code == 202, response.data
    job = api.get(f"/api/v1/jobs/{response.data['id']}/").data
    assert job["state"] in ("succeeded", "failed"), job
    return job


def import_cluster(api, name: str, doc: dict):
    response = api.post("/api/v1/clusters/import/", {"name": name, **doc}, format="json")
    assert response.status_code == 201, response.data
    return response.data["id"]


def why(api, placement: int, container: str) -> dict:
    response = api.get(f"/api/v1/placements/{placement}/why/", {"container": container})
    assert response.status_code == 200, response.data
    return response.data


@pytest.fixture
def autoware_clustering(api):
    content = (DATA / "autoware_reference_system.json").read_bytes()
    response = api.post(
        "/api/v1/rosgraphs/import/", {"file": SimpleUploadedFile("aw.json", content)}, format="multipart"
    )
    assert response.status_code == 201, response.data
    job = run(api, f"/api/v1/rosgraphs/{response.data['id']}/cluster/", {"containers": 4})
    assert job["state"] == "succeeded", job["error"]
    return api.get(job["result_url"]).data


# ---- worked examples --------------------------------------------------------------------------------------
def test_fig_3_28_through_the_api_explains_every_rank(api):
    cluster = import_cluster(api, "fig-3-28", {"nodes": [{"name": "node1", "cpu": 4}, {"name": "node2", "cpu": 5}]})
    job = run(api, "/api/v1/placements/run/", {"cluster": cluster, "containers": FIG_3_28})
    assert job["state"] == "succeeded", job["error"]
    assert job["kind"] == "place" and job["progress"] == 100
    placement = job["result"]["placement"]
    data = api.get(f"/api/v1/placements/{placement}/").data
    assert {p["container"]: p["node"] for p in data["plan"]["placements"]} == {
        "C4": "node2", "C0": "node1", "C1": "node1", "C2": "node2", "C3": "node1",
    }  # fmt: skip
    assert data["inter_node_bandwidth"] == 1 + 1 + 3 and data["node_traffic"] == [
        {"a": "node1", "b": "node2", "bytes_per_s": 5.0}
    ]
    assert data["baseline"]["policy"] == "default-kubernetes" and "inter_node_bandwidth" in data["baseline"]
    # Eq. 3.15 of the printed raw ranks: C1 (2, 1) -> (100, 50), C3 (4, 3) -> (100, 75).
    c1 = why(api, placement, "C1")
    assert (c1["node"], c1["position"], c1["pending"], c1["policy"]) == ("node1", 3, False, "superclustering")
    assert c1["policies"] == ["bandwidth", "node_affinity", "free_resources"]
    assert [(r["node"], r["verdict"], r["scores"]["bandwidth"], r["total"]) for r in c1["rows"]] == [
        ("node1", "chosen", 100.0, 100.0),
        ("node2", "feasible", 50.0, 50.0),
    ]
    c3 = why(api, placement, "C3")
    assert {r["node"]: r["scores"]["bandwidth"] for r in c3["rows"]} == {"node1": 100.0, "node2": 75.0}
    # C0's ranks are all 0: the free-resource policy picks the freer node1 (4 free cores against 3).
    c0 = why(api, placement, "C0")
    assert {r["node"]: (r["scores"]["bandwidth"], r["total"]) for r in c0["rows"]} == {
        "node1": (0.0, 0.0),
        "node2": (0.0, 0.0),
    }
    free = {r["node"]: r["scores"]["free_resources"] for r in c0["rows"]}
    assert c0["node"] == "node1" and free["node1"] > free["node2"]
    every = api.get(f"/api/v1/placements/{placement}/why/").data
    assert [t["container"] for t in every["containers"]] == ["C4", "C0", "C1", "C2", "C3"]
    assert api.get(f"/api/v1/placements/{placement}/why/", {"container": "C9"}).status_code == 404


def test_kairos_keeps_the_heavy_group_on_the_jetson_and_says_why_drivers_stay_on_the_mcb(api):
    cluster = import_cluster(api, "rb-kairos", json.loads((DATA / "kairos_synthetic.cluster.json").read_text()))
    containers = json.loads((DATA / "kairos_synthetic.containers.json").read_text())
    job = run(api, "/api/v1/placements/run/", {"cluster": cluster, "containers": containers})
    assert job["state"] == "succeeded", job["error"]
    row = Placement.objects.get(pk=job["result"]["placement"])
    where = row.placed()
    assert {where[c] for c in ("map-nav-manager-rb", "navigation-rb", "local-control-rb", "perception-rb")} == {
        "jetson"
    }
    assert where["main-rb"] == where["arm-rb"] == "mcb" and where["hmi-rb"] == "server"
    assert row.inter_node_bandwidth < row.baseline["inter_node_bandwidth"]
    main = why(api, row.pk, "main-rb")
    rows = {r["node"]: r for r in main["rows"]}
    assert rows["mcb"]["verdict"] == "chosen"
    assert rows["jetson"]["rejected_by"] == "NodeAffinity"
    assert rows["jetson"]["reason"] == (
        "required node affinity kubernetes.io/hostname In [mcb] not matched (kubernetes.io/hostname=jetson)"
    )
    assert [r["verdict"] for r in main["rows"]] == ["chosen", "rejected", "rejected"]


# ---- a clustering's containers ----------------------------------------------------------------------------
def test_place_a_clustering_with_overrides_arch_and_not_ready_nodes(api, cluster, autoware_clustering):
    names = [c["name"] for c in autoware_clustering["containers"]]
    cluster.nodes.filter(name="node3").update(status="NotReady")
    overrides = {name: {"cpu": 3, "priority": i} for i, name in enumerate(names)}
    overrides[names[0]] = {"archs": ["riscv64"]}
    job = run(
        api,
        f"/api/v1/clusterings/{autoware_clustering['id']}/place/",
        {"cluster": cluster.pk, "overrides": overrides, "overhead_mib": 39},
    )
    assert job["state"] == "succeeded", job["error"]
    data = api.get(job["result_url"]).data
    assert (data["clustering"], data["cluster"], data["policy"]) == (
        autoware_clustering["id"],
        cluster.pk,
        "superclustering",
    )
    placed = {p["container"]: p["node"] for p in data["plan"]["placements"]}
    # 3 cores each on 4-core nodes: one container per node, and node3 is not Ready.
    assert sorted(placed.values()) == ["node0", "node1", "node2"] and names[0] not in placed
    assert data["pending_count"] == 1 and data["plan"]["pending"][0]["container"] == names[0]
    specs = {c["name"]: c for c in data["containers"]["containers"]}
    assert specs[names[1]]["cpu"] == 3 and specs[names[0]]["archs"] == ["riscv64"]
    assert specs[names[0]]["nodes"] == autoware_clustering["containers"][0]["nodes"]
    assert data["params"]["overhead_mib"] == 39
    pending = why(api, data["id"], names[0])
    assert pending["pending"] and pending["node"] is None
    # Filters run in order (architecture first), and the first that rejects a node names it.
    assert {r["rejected_by"] for r in pending["rows"]} == {"NodeArch"} and len(pending["rows"]) == 4
    assert pending["rows"][0]["reason"] == "node arch amd64 not among the image's platforms [riscv64]"
    placed_why = why(api, data["id"], names[1])
    rows = {r["node"]: r for r in placed_why["rows"]}
    assert (rows["node3"]["rejected_by"], rows["node3"]["reason"]) == (
        "TaintToleration",
        "taint node.kubernetes.io/not-ready:NoSchedule not tolerated",
    )
    assert placed_why["rows"][0]["verdict"] == "chosen" and placed_why["rows"][-1]["verdict"] == "rejected"


def test_default_kubernetes_policy_and_no_comparison(api, cluster, autoware_clustering):
    job = run(
        api,
        f"/api/v1/clusterings/{autoware_clustering['id']}/place/",
        {"cluster": cluster.pk, "policy": "k8s", "compare": False, "seed": 3},
    )
    assert job["state"] == "succeeded", job["error"]
    data = api.get(job["result_url"]).data
    assert data["policy"] == "default-kubernetes" and data["baseline"] is None
    assert data["params"]["seed"] == 3
    table = why(api, data["id"], autoware_clustering["containers"][0]["name"])
    assert table["policies"] == ["least_allocated", "balanced_allocation", "node_affinity", "taint_toleration"]


@pytest.mark.parametrize(
    ("body", "field", "message"),
    [
        ({"overrides": {"ghost": {"cpu": 1}}}, "overrides", "unknown container 'ghost'"),
        ({"overrides": {"FIRST": {"nodes": ["x"]}}}, "overrides", "cannot change 'nodes'"),
        ({"overrides": {"FIRST": {"cpu": -2}}}, "containers", "has invalid cpu -2"),
        ({"overrides": {"FIRST": {"archs": ["sparc"]}}}, "arch", "unknown architecture 'sparc'"),
        ({"policy": "random"}, "policy", "is not a valid choice"),
        ({"weights": {"luck": 1}}, "weights", "unknown scoring policy 'luck'"),
        ({"containers": {"containers": [{"name": "x"}]}}, "clustering", "exactly one of"),
        ({"cluster": 999999}, "cluster", "Invalid pk"),
    ],
)
def test_bad_place_requests_start_no_job(api, cluster, autoware_clustering, body, field, message):
    first = autoware_clustering["containers"][0]["name"]
    body = json.loads(json.dumps(body).replace("FIRST", first))
    response = api.post(
        f"/api/v1/clusterings/{autoware_clustering['id']}/place/", {"cluster": cluster.pk, **body}, format="json"
    )
    assert response.status_code == 400, response.data
    assert message in json.dumps(response.data[field]), response.data
    assert not Job.objects.filter(kind="place").exists()


@pytest.mark.parametrize(
    ("body", "field", "message"),
    [
        ({}, "clustering", "exactly one of"),
        ({"containers": {"containers": []}}, "containers", "'containers' must be a non-empty list"),
        ({"containers": {"containers": [{"name": "a"}], "bandwidth": [{"a": "a", "b": "z", "bytes_per_s": 1}]}},
         "bandwidth", "unknown container 'z'"),
        ({"containers": {"containers": [{"name": "a", "image": ""}]}}, "containers", "'image' must be"),
        ({"containers": {"containers": [{"name": "a"}]}, "overrides": {"a": {"cpu": 1}}}, "overrides", "go with a"),
    ],
)  # fmt: skip
def test_bad_container_documents(api, cluster, body, field, message):
    response = api.post("/api/v1/placements/run/", {"cluster": cluster.pk, **body}, format="json")
    assert response.status_code == 400, response.data
    assert message in json.dumps(response.data[field]), response.data
    assert not Job.objects.exists()


def test_push_needs_a_kubeconfig(api, cluster):
    job = run(api, "/api/v1/placements/run/", {"cluster": cluster.pk, "containers": FIG_3_28})
    response = api.post(f"/api/v1/placements/{job['result']['placement']}/push/")
    assert response.status_code == 400 and "no Kubernetes API" in str(response.data["cluster"])
    assert not Job.objects.filter(kind="push_placement").exists()


def test_a_redelivered_place_job_replaces_its_placement(api, cluster):
    job_data = run(api, "/api/v1/placements/run/", {"cluster": cluster.pk, "containers": FIG_3_28})
    job = Job.objects.get(pk=job_data["id"])
    first = Placement.objects.get(job=job)
    result, url = HANDLERS["place"](job, lambda percent, message: None)
    assert Placement.objects.filter(job=job).count() == 1
    again = Placement.objects.get(job=job)
    assert again.pk != first.pk and again.plan == first.plan
    assert url == f"/api/v1/placements/{again.pk}/" and result["placement"] == again.pk


def test_a_failed_place_job_records_the_reason(api, cluster, fleet):
    from apps.jobs.services import start_job

    job = start_job(ContainersJob.PLACE, fleet, {"cluster": cluster.pk, "containers": {"containers": []}})
    assert job.state == "failed" and "'containers' must be a non-empty list" in job.error
    job = start_job(ContainersJob.PLACE, fleet, {"cluster": 987654, "containers": FIG_3_28})
    assert job.state == "failed" and job.error == "cluster 987654 does not exist"
    assert not Placement.objects.exists()


def test_the_stored_plan_reads_back_as_the_engine_type(api):
    """Placement.plan is PlacementPlan.to_dict(); it is read back through PlacementPlan.from_dict (issue 11)."""
    from apps.containers.services import why_table

    cluster = import_cluster(api, "rb-kairos", json.loads((DATA / "kairos_synthetic.cluster.json").read_text()))
    containers = json.loads((DATA / "kairos_synthetic.containers.json").read_text())
    job = run(api, "/api/v1/placements/run/", {"cluster": cluster, "containers": containers})
    row = Placement.objects.get(pk=job["result"]["placement"])
    plan = row.engine_plan()
    assert plan.to_dict() == row.plan and plan.policy == row.policy
    assert row.placed() == {p["container"]: p["node"] for p in row.plan["placements"]}
    assert why_table(plan, "main-rb") == why_table(row.plan, "main-rb") == why(api, row.pk, "main-rb")


def test_a_large_cluster_stores_bounded_explanations_and_gives_every_verdict_on_demand(api):
    """Issue 29: on more than 32 nodes the stored plan keeps each container's best candidates and the count
    of nodes per filter; ``full=1`` recomputes every node's verdict from the stored inputs, same decision."""
    nodes = [{"name": f"n{i:02d}", "cpu": 4 if i % 3 else 1, "arch": "arm64" if i % 5 == 0 else "amd64"}
             for i in range(40)]  # fmt: skip
    cluster = import_cluster(api, "forty", {"nodes": nodes})
    containers = {
        **FIG_3_28,
        "containers": [{**c, "cpu": 3} if c["name"] == "C4" else c for c in FIG_3_28["containers"]],
    }
    job = run(api, "/api/v1/placements/run/", {"cluster": cluster, "containers": containers})
    row = Placement.objects.get(pk=job["result"]["placement"])
    for d in row.plan["decisions"]:
        assert len(d["verdicts"]) <= 5 + len(d.get("rejections", {}))
    bounded = why(api, row.pk, "C4")
    assert bounded["bounded"] and bounded["rows"][0]["verdict"] == "chosen"
    assert bounded["rejections"]["NodeResourcesFit"] >= 13  # the 1-CPU nodes (and the full ones)
    response = api.get(f"/api/v1/placements/{row.pk}/why/", {"container": "C4", "full": "1"})
    assert response.status_code == 200, response.data
    full = response.data
    assert not full["bounded"] and len(full["rows"]) == 40 and full["node"] == bounded["node"]
    assert full["rows"][0] == bounded["rows"][0]
    counts = {}
    for r in full["rows"]:
        if r["rejected_by"]:
            counts[r["rejected_by"]] = counts.get(r["rejected_by"], 0) + 1
    assert counts == bounded["rejections"]

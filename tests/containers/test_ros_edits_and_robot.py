"""The ROS graph page's node and topic forms (PATCH's contract), drivers held on the robot with warnings in the
page, API and job, containers' CPU/memory requests from the resource model, the Dockerfile preview."""

import gzip
import io
import json
import tarfile

import pytest
from django.urls import reverse
from django.utils.html import escape

from apps.containers.kinds import ContainersJob
from apps.containers.models import Clustering, Placement, RosGraph
from apps.jobs.services import start_job
from tests.conftest import DATA
from tests.containers.test_pages import cluster_it, make_graph
from tests.containers.test_rosgraphs_api import CONTRACT

pytestmark = pytest.mark.django_db

HARDWARE = ("FrontLidarDriver", "RearLidarDriver", "VehicleDBWSystem")
ROBOT_AND_CLOUD = {
    "nodes": [
        {"name": "mcb", "arch": "amd64", "cpu": 4, "memory_mib": 8192, "labels": {"zone": "robot"}},
        {"name": "cloud-vm", "arch": "amd64", "cpu": 32, "memory_mib": 65536, "labels": {"zone": "cloud"}},
    ],
    "links": [{"src": "mcb", "dst": "cloud-vm", "bandwidth_mbps": 100, "latency_ms": 20}],
}


@pytest.fixture
def autoware(fleet):
    return make_graph(fleet, (DATA / "autoware_reference_system.json").read_bytes())


@pytest.fixture
def robot_cluster(api):
    from apps.clusters.models import Cluster

    response = api.post("/api/v1/clusters/import/", {"name": "robot+cloud", **ROBOT_AND_CLOUD}, format="json")
    assert response.status_code == 201, response.data
    return Cluster.objects.get(pk=response.data["id"])


def place(clustering, cluster, **extra) -> Placement:
    job = start_job(
        ContainersJob.PLACE, clustering.fleet, {"clustering": clustering.pk, "cluster": cluster.pk, **extra}
    )
    assert job.state == "succeeded", job.error
    return Placement.objects.get(job=job)


def hosts(placement: Placement) -> dict[str, str]:
    placed = placement.placed()
    return {ros: placed[c["name"]] for c in placement.containers["containers"] for ros in c["nodes"]}


# ---- the page's row forms ------------------------------------------------------------------------------
def test_topic_row_form_edits_rate_and_size(member, autoware):
    page = member.get(reverse("containers:rosgraph", args=[autoware.pk])).content.decode()
    assert 'data-topic="FrontLidarDriver"' in page and "Rate (Hz)" in page and "Message (bytes)" in page
    url = reverse("containers:rosgraph-topic", args=[autoware.pk])
    response = member.post(url, {"topic": "FrontLidarDriver", "rate_hz": "25", "msg_bytes": "8192"})
    assert response.status_code == 302 and response["Location"].endswith("#topics")
    topic = RosGraph.objects.get(pk=autoware.pk).graph.topics["FrontLidarDriver"]
    assert topic.rates == {"FrontLidarDriver": 25.0} and topic.msg_bytes == 8192


@pytest.mark.parametrize(
    ("data", "message"),
    [
        ({"rate_hz": "-1", "msg_bytes": "10"}, "must be at least 0 Hz"),
        ({"rate_hz": "1e9", "msg_bytes": "10"}, "rate_hz: at most 100,000 Hz"),
        ({"rate_hz": "10", "msg_bytes": "5e9"}, "msg_bytes: at most 1,073,741,824 bytes"),
        ({"rate_hz": "fast", "msg_bytes": "10"}, "Enter a number."),
    ],
)
def test_bad_topic_values_are_refused_with_the_unit_and_nothing_changes(member, autoware, data, message):
    before = RosGraph.objects.get(pk=autoware.pk).document
    url = reverse("containers:rosgraph-topic", args=[autoware.pk])
    response = member.post(url, {"topic": "FrontLidarDriver", **data})
    body = response.content.decode()
    assert response.status_code == 400 and message in body
    assert "Not saved — topic <strong>FrontLidarDriver</strong>" in body  # summarised above the table
    assert RosGraph.objects.get(pk=autoware.pk).document == before


def test_the_page_and_patch_refuse_the_same_value_with_the_same_message(member, api, autoware):
    page = member.post(
        reverse("containers:rosgraph-topic", args=[autoware.pk]),
        {"topic": "FrontLidarDriver", "rate_hz": "1e9", "msg_bytes": "1"},
    ).content.decode()
    answer = api.patch(
        f"/api/v1/rosgraphs/{autoware.pk}/", {"topics": {"FrontLidarDriver": {"rate_hz": 1e9}}}, format="json"
    )
    assert answer.status_code == 400
    message = answer.json()["topics"]["FrontLidarDriver"]["rate_hz"][0]
    assert message == "rate_hz: at most 100,000 Hz" and message in page


def test_node_row_form_sets_level_pin_and_profile(member, autoware):
    url = reverse("containers:rosgraph-node", args=[autoware.pk])
    data = {"node": "FrontLidarDriver", "level": "driver", "pin": "free", "cpu": "0.25", "memory_mib": "64"}
    assert member.post(url, data).status_code == 302
    node = RosGraph.objects.get(pk=autoware.pk).graph.nodes["FrontLidarDriver"]
    assert (node.level, node.pin, node.cpu, node.memory_mib) == ("driver", "free", 0.25, 64.0)
    bad = member.post(url, {**data, "cpu": "5000"})
    assert bad.status_code == 400 and "cpu: at most 1,024 cores" in bad.content.decode()
    assert member.post(url, {**data, "node": "ghost"}).status_code == 404
    # Back to "by level": the pin is dropped from the document.
    assert member.post(url, {**data, "pin": ""}).status_code == 302
    assert RosGraph.objects.get(pk=autoware.pk).graph.nodes["FrontLidarDriver"].pin is None


def test_another_fleets_graph_answers_404_and_is_not_changed(member, fleets):
    other = make_graph(fleets[1], json.dumps({**CONTRACT, "name": "beta-secret-graph"}))
    before = other.document
    for name, data in (
        ("containers:rosgraph-topic", {"topic": "/scan", "rate_hz": "1", "msg_bytes": "1"}),
        ("containers:rosgraph-node", {"node": "amcl", "pin": "free", "cpu": "1", "memory_mib": "1"}),
    ):
        assert member.post(reverse(name, args=[other.pk]), data).status_code == 404
    assert RosGraph.objects.get(pk=other.pk).document == before


# ---- drivers on the robot ------------------------------------------------------------------------------
def test_drivers_stay_on_the_robot_board_and_unpinned_ones_are_reported(member, api, autoware, robot_cluster):
    clustering = cluster_it(autoware)
    pinned = place(clustering, robot_cluster)
    assert {hosts(pinned)[d] for d in HARDWARE} == {"mcb"}
    answer = api.get(f"/api/v1/placements/{pinned.pk}/").json()
    assert answer["warnings"] == [] and answer["params"]["drivers_on_robot"] is True
    page = member.get(reverse("containers:placement", args=[pinned.pk])).content.decode()
    assert 'id="placement-warnings"' not in page

    # The operator unpins every driver (the page's node form), clusters again and places again.
    url = reverse("containers:rosgraph-node", args=[autoware.pk])
    graph = RosGraph.objects.get(pk=autoware.pk).graph
    for name, node in graph.nodes.items():
        if graph.levels()[name] == "driver":
            data = {"node": name, "level": node.level or "", "pin": "free", "cpu": node.cpu, "memory_mib": 0}
            assert member.post(url, data).status_code == 302
    moved = place(cluster_it(RosGraph.objects.get(pk=autoware.pk)), robot_cluster)
    assert {hosts(moved)[d] for d in HARDWARE} == {"cloud-vm"}
    answer = api.get(f"/api/v1/placements/{moved.pk}/").json()
    warned = {d for w in answer["warnings"] for d in w["drivers"]}
    assert set(HARDWARE) <= warned and all("off the robot" in w["message"] for w in answer["warnings"])
    assert moved.job.result["warnings"]  # the job's summary says it too
    page = member.get(reverse("containers:placement", args=[moved.pk])).content.decode()
    assert 'id="placement-warnings"' in page and "FrontLidarDriver" in page and "off robot</span>" in page


def test_the_constraint_can_be_turned_off_per_request_and_is_then_reported(api, autoware, robot_cluster):
    clustering = cluster_it(autoware)
    response = api.post(
        f"/api/v1/clusterings/{clustering.pk}/place/",
        {"cluster": robot_cluster.pk, "drivers_on_robot": False},
        format="json",
    )
    assert response.status_code == 202, response.data
    placement = Placement.objects.get(job_id=response.data["id"])
    assert {hosts(placement)[d] for d in HARDWARE} == {"cloud-vm"}
    assert api.get(f"/api/v1/placements/{placement.pk}/").json()["warnings"]
    bad = api.post(
        f"/api/v1/clusterings/{clustering.pk}/place/", {"cluster": robot_cluster.pk, "robot_label": "robot"},
        format="json",
    )  # fmt: skip
    assert bad.status_code == 400 and "key=value" in bad.json()["robot_label"][0]


# ---- container requests ---------------------------------------------------------------------------------
def test_containers_request_cpu_and_memory_from_the_ros_nodes(member, autoware, robot_cluster):
    clustering = cluster_it(autoware)
    placement = place(clustering, robot_cluster)
    specs = placement.containers["containers"]
    # Not the former 0.0133 cores and 0 MiB: every ROS node costs a base share and a process, plus its traffic.
    for c in specs:
        assert c["cpu"] >= 0.005 * len(c["nodes"]) and c["memory_mib"] >= 20 * len(c["nodes"])
    assert len({round(c["cpu"], 6) for c in specs}) == len(specs)
    page = member.get(reverse("containers:clustering", args=[clustering.pk])).content.decode()
    assert "CPU request (cores)" in page and "Memory request (MiB)" in page
    # Faster lidars cost more CPU: the request follows the rates.
    url = reverse("containers:rosgraph-topic", args=[autoware.pk])
    assert member.post(url, {"topic": "FrontLidarDriver", "rate_hz": "100", "msg_bytes": "4096"}).status_code == 302
    faster = place(cluster_it(RosGraph.objects.get(pk=autoware.pk)), robot_cluster)

    def cpu_of(p, ros):
        return next(c["cpu"] for c in p.containers["containers"] if ros in c["nodes"])

    assert cpu_of(faster, "FrontLidarDriver") > cpu_of(placement, "FrontLidarDriver")


def test_the_deployment_sets_the_resource_model(settings, autoware, robot_cluster):
    """CONTINUUM_RESOURCE_MODEL overrides the engine's proposed constants for every placement; a bad value is
    a start-up error naming it."""
    from django.core import checks

    clustering = cluster_it(autoware)
    default = place(clustering, robot_cluster).containers["containers"]
    settings.CONTINUUM_RESOURCE_MODEL = json.dumps({"process_mib": 50, "per_message_us": 100})
    heavier = {c["name"]: c for c in place(clustering, robot_cluster).containers["containers"]}
    for c in default:
        assert heavier[c["name"]]["memory_mib"] == pytest.approx(c["memory_mib"] + 30 * len(c["nodes"]))
        assert heavier[c["name"]]["cpu"] > c["cpu"]
    settings.CONTINUUM_RESOURCE_MODEL = '{"process_mb": 50}'
    errors = [e for e in checks.run_checks() if e.id == "containers.E001"]
    assert [e.msg for e in errors] == ["CONTINUUM_RESOURCE_MODEL: resource model: unknown parameter 'process_mb'"]
    settings.CONTINUUM_RESOURCE_MODEL = "{"
    assert [e.id for e in checks.run_checks() if e.id == "containers.E001"] == ["containers.E001"]


# ---- Dockerfile preview -------------------------------------------------------------------------------------
def test_dockerfile_preview_matches_the_archive(member, fleet):
    row = make_graph(fleet, json.dumps(CONTRACT))
    clustering = cluster_it(row, 2)
    page = member.get(reverse("containers:clustering", args=[clustering.pk])).content.decode()
    archive = member.get(reverse("containers:clustering-dockerfiles", args=[clustering.pk]) + "?archive=tar.gz")
    with tarfile.open(fileobj=io.BytesIO(gzip.decompress(archive.content))) as tar:
        files = {m.name: tar.extractfile(m).read().decode() for m in tar.getmembers() if m.name.endswith("Dockerfile")}
    assert files
    for path, text in files.items():
        image = path.split("/")[0]
        assert f'data-image="{image}"' in page
        assert escape(text) in page
    assert Clustering.objects.get(pk=clustering.pk).images

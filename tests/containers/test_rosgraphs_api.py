"""ROS graphs through the API: import in every format, bad files, edits, fleet scoping, clustering jobs, the
Dockerfiles archive."""

import gzip
import io
import json
import tarfile
import zipfile

import pytest
from django.core.files.uploadedfile import SimpleUploadedFile

from apps.containers.models import Clustering, RosGraph
from apps.jobs.models import Job
from tests.conftest import DATA

pytestmark = pytest.mark.django_db

CONTRACT = {
    "format": "continuum.rosgraph/v1",
    "name": "mini robot",
    "nodes": [
        {"name": "laser_driver", "level": "driver", "cpu": 0.1, "memory_mib": 30, "packages": ["urg_node", "rclcpp"]},
        {"name": "move_base", "level": "macro", "memory_mib": 120, "cpu": 0.4, "packages": ["nav2_core", "rclcpp"]},
        {"name": "amcl", "cpu": 0.2, "memory_mib": 60, "packages": ["nav2_amcl", "nav2_core", "rclcpp"]},
        {"name": "rviz", "cpu": 0.5, "memory_mib": 300, "packages": ["rviz2", "rclcpp"]},
    ],
    "topics": [
        {"name": "/scan", "publishers": ["laser_driver"], "subscribers": ["move_base", "amcl"], "rate_hz": 10,
         "msg_bytes": 8192},
        {"name": "/pose", "publishers": ["amcl"], "subscribers": ["move_base", "rviz"], "rate_hz": 5, "msg_bytes": 100},
        {"name": "/plan", "publishers": ["move_base"], "subscribers": ["rviz"], "rate_hz": 1, "msg_bytes": 2000},
    ],
    "packages": {"rclcpp": 50, "urg_node": 3, "nav2_core": 40, "nav2_amcl": 8, "rviz2": 200},
}  # fmt: skip


def upload(api, filename: str, content, **fields):
    if isinstance(content, str):
        content = content.encode()
    data = {"file": SimpleUploadedFile(filename, content), **fields}
    return api.post("/api/v1/rosgraphs/import/", data, format="multipart")


def run(api, url: str, body: dict | None = None) -> dict:
    """POST an action that starts a job; return the finished job (jobs run in-process in the tests)."""
    response = api.post(url, body or {}, format="json")
    assert response.status_code == 202, response.data
    job = api.get(f"/api/v1/jobs/{response.data['id']}/").data
    assert job["state"] in ("succeeded", "failed"), job
    return job


@pytest.fixture
def contract_graph(api):
    response = upload(api, "mini.json", json.dumps(CONTRACT))
    assert response.status_code == 201, response.data
    return RosGraph.objects.get(pk=response.data["id"])


@pytest.fixture
def autoware(api):
    response = upload(api, "autoware_reference_system.json", (DATA / "autoware_reference_system.json").read_bytes())
    assert response.status_code == 201, response.data
    return RosGraph.objects.get(pk=response.data["id"])


# ---- import ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("filename", "fmt", "nodes", "topics", "name"),
    [
        ("autoware_reference_system.json", "autoware", 24, 23, "autoware_reference_system"),
        ("autoware_reference_system.dot", "dot", 24, 22, "autoware_reference_system"),
        ("irobot_sierra_nevada.json", "irobot", 10, 13, "irobot_sierra_nevada"),
    ],
)
def test_import_each_dataset_format(api, fleet, filename, fmt, nodes, topics, name):
    response = upload(api, filename, (DATA / filename).read_bytes())
    assert response.status_code == 201, response.data
    data = response.data
    assert (data["source_format"], data["node_count"], data["topic_count"], data["name"]) == (fmt, nodes, topics, name)
    row = RosGraph.objects.get(pk=data["id"])
    assert row.fleet == fleet and row.document["format"] == "continuum.rosgraph/v1"
    assert len(row.graph.nodes) == nodes
    assert set(data["effective_levels"].values()) <= {"mission", "macro", "functionality", "driver"}


def test_import_the_contract_with_explicit_format_and_name(api):
    response = upload(api, "g.json", json.dumps(CONTRACT), format="rosgraph", name="renamed", description="lab")
    assert response.status_code == 201, response.data
    data = response.data
    assert (data["name"], data["source_format"], data["description"]) == ("renamed", "rosgraph", "lab")
    assert data["effective_levels"]["laser_driver"] == "driver" and data["effective_levels"]["move_base"] == "macro"
    assert data["document"]["packages"]["rviz2"] == {"size_mib": 200.0}
    # Eq. 3.12 on the stored document: /scan to move_base, 10 Hz x 8192 bytes.
    assert RosGraph.objects.get(pk=data["id"]).graph.bandwidth("laser_driver", "move_base") == 81920


BAD_FILES = [
    ("malformed.json", '{"format": "continuum.rosgraph/v1",\n "nodes": [\n  {"name": "a",, }]}',
     "malformed JSON at line 3"),
    ("bad.dot", 'digraph G {\n  "a" -> "b";\n  "c" -> ;\n}\n', "line 3: expected a node id"),
    ("edge.dot", 'digraph G {\n  "a" -> "b" [rate_hz=fast];\n}\n', "line 2: invalid rate_hz 'fast'"),
    ("size.json", json.dumps({**CONTRACT, "topics": [{**CONTRACT["topics"][0], "msg_bytes": -1}]}),
     "topic '/scan' has invalid msg_bytes -1"),
    ("level.json", json.dumps({**CONTRACT, "nodes": [{"name": "x", "level": "boss"}]}),
     "ROS node 'x' has unknown level 'boss'"),
    ("irobot.json", json.dumps({"nodes": [{"node_name": "n", "publishers": [{"topic_name": "t", "msg_type": "weird",
                                                                              "period_ms": 10}]}]}),
     "node 'n' publishers[0] (topic 't'): unknown msg_type"),
    ("binary.json", b"\xff\xfe\x00garbage", "not UTF-8"),
    ("what.json", '{"hello": 1}', "cannot tell the ROS graph format"),
]  # fmt: skip


@pytest.mark.parametrize(("filename", "content", "message"), BAD_FILES, ids=[b[0] for b in BAD_FILES])
def test_bad_files_answer_400_naming_the_culprit_and_store_nothing(api, filename, content, message):
    response = upload(api, filename, content)
    assert response.status_code == 400
    errors = response.data["file"]
    text = str(errors[0])
    assert text.startswith(f"{filename}: "), errors
    assert message in text, errors
    assert RosGraph.objects.count() == 0


def test_import_needs_a_file_and_a_known_format(api):
    assert api.post("/api/v1/rosgraphs/import/", {}, format="multipart").status_code == 400
    response = upload(api, "g.json", json.dumps(CONTRACT), format="yaml")
    assert response.status_code == 400 and "format" in response.data
    assert RosGraph.objects.count() == 0


# ---- edits ----------------------------------------------------------------------------------------------
def test_patch_edits_levels_rates_sizes_and_packages(api, contract_graph):
    url = f"/api/v1/rosgraphs/{contract_graph.pk}/"
    body = {
        "levels": {"amcl": "macro_functionality", "move_base": None},
        "topics": {"/scan": {"rate_hz": 20, "msg_bytes": 4096}, "/pose": {"publisher_rates_hz": {"amcl": 2}}},
        "nodes": {"rviz": {"memory_mib": 256, "packages": ["rviz2"]}},
        "packages": {"rviz2": {"size_mib": 180, "archs": ["amd64"]}, "urg_node": None},
    }
    response = api.patch(url, body, format="json")
    assert response.status_code == 200, response.data
    graph = RosGraph.objects.get(pk=contract_graph.pk).graph
    assert graph.nodes["amcl"].level == "macro" and graph.nodes["move_base"].level is None
    assert response.data["effective_levels"]["amcl"] == "macro"
    assert graph.bandwidth("laser_driver", "move_base") == 20 * 4096
    assert graph.topics["/pose"].rate("amcl") == 2
    assert graph.nodes["rviz"].memory_mib == 256 and graph.nodes["rviz"].packages == ("rviz2",)
    assert graph.packages["rviz2"] == {"size_mib": 180.0, "archs": ["amd64"]} and "urg_node" not in graph.packages
    assert api.patch(url, {"name": "renamed"}, format="json").data["name"] == "renamed"


@pytest.mark.parametrize(
    ("body", "field", "message"),
    [
        ({"levels": {"ghost": "driver"}}, "levels", "unknown ROS node 'ghost'"),
        ({"levels": {"amcl": "boss"}}, "levels", "ROS node 'amcl': unknown level 'boss'"),
        ({"topics": {"/nope": {"rate_hz": 1}}}, "topics", "unknown topic '/nope'"),
        ({"topics": {"/scan": {"rate_hz": -5}}}, "topics", "{'/scan': {'rate_hz': ['rate_hz: must be at least 0 Hz']"),
        ({"topics": {"/scan": {"rate_hz": 1e9}}}, "topics", "'rate_hz': ['rate_hz: at most 100,000 Hz']"),
        (
            {"topics": {"/scan": {"msg_bytes": 2e9}}},
            "topics",
            "'msg_bytes': ['msg_bytes: at most 1,073,741,824 bytes']",
        ),
        ({"topics": {"/scan": {"rate_hz": 1, "period_ms": 10}}}, "topics", "give one of rate_hz, period_ms"),
        (
            {"topics": {"/scan": {"publishers": ["x"]}}},
            "topics",
            "{'/scan': {'publishers': [\"cannot change 'publishers'",
        ),
        ({"nodes": {"amcl": {"cpu": "lots"}}}, "nodes", "{'amcl': {'cpu': ['A valid number is required.']"),
        ({"nodes": {"amcl": {"pin": "board"}}}, "nodes", "{'amcl': {'pin': ['\"board\" is not a valid choice.']"),
        ({"packages": {"rviz2": {"size_mib": -1}}}, "packages", "package 'rviz2' has invalid size_mib -1"),
    ],
)
def test_bad_edits_answer_400_and_change_nothing(api, contract_graph, body, field, message):
    before = RosGraph.objects.get(pk=contract_graph.pk).document
    response = api.patch(f"/api/v1/rosgraphs/{contract_graph.pk}/", body, format="json")
    assert response.status_code == 400, response.data
    errors = response.json()[field]  # per item and field when the contract refuses a value, else a list
    assert message in str(errors if isinstance(errors, dict) else errors[0])
    assert RosGraph.objects.get(pk=contract_graph.pk).document == before


# ---- scoping --------------------------------------------------------------------------------------------
def test_other_fleets_graphs_and_results_answer_404(api, other_api, contract_graph, cluster):
    job = run(api, f"/api/v1/rosgraphs/{contract_graph.pk}/cluster/", {"containers": 2})
    clustering = job["result"]["clustering"]
    placed = run(api, f"/api/v1/clusterings/{clustering}/place/", {"cluster": cluster.pk})
    placement = placed["result"]["placement"]
    urls = [
        f"/api/v1/rosgraphs/{contract_graph.pk}/",
        f"/api/v1/clusterings/{clustering}/",
        f"/api/v1/clusterings/{clustering}/dockerfiles/",
        f"/api/v1/placements/{placement}/",
        f"/api/v1/placements/{placement}/why/",
    ]
    for url in urls:
        assert other_api.get(url).status_code == 404, url
    jobs_before = Job.objects.count()
    posts = [
        (f"/api/v1/rosgraphs/{contract_graph.pk}/cluster/", {"containers": 2}),
        (f"/api/v1/clusterings/{clustering}/place/", {"cluster": cluster.pk}),
        (f"/api/v1/placements/{placement}/push/", {}),
    ]
    for url, body in posts:
        assert other_api.post(url, body, format="json").status_code == 404, url
    assert other_api.patch(f"/api/v1/rosgraphs/{contract_graph.pk}/", {"name": "x"}, format="json").status_code == 404
    # Nor may another fleet place its own containers on our cluster.
    doc = {"containers": [{"name": "c"}]}
    response = other_api.post("/api/v1/placements/run/", {"cluster": cluster.pk, "containers": doc}, format="json")
    assert response.status_code == 400 and "cluster" in response.data
    assert Job.objects.count() == jobs_before
    for collection in ("rosgraphs", "clusterings", "placements"):
        assert other_api.get(f"/api/v1/{collection}/").data["count"] == 0, collection
        assert api.get(f"/api/v1/{collection}/").data["count"] == 1, collection


def test_the_api_needs_authentication(client, contract_graph):
    assert client.get("/api/v1/rosgraphs/").status_code in (401, 403)
    assert client.get(f"/api/v1/rosgraphs/{contract_graph.pk}/").status_code in (401, 403)


# ---- clustering jobs ------------------------------------------------------------------------------------
def test_cluster_job_on_autoware(api, autoware):
    job = run(api, f"/api/v1/rosgraphs/{autoware.pk}/cluster/", {"containers": 4})
    assert job["state"] == "succeeded", job["error"]
    assert job["kind"] == "cluster_ros" and job["progress"] == 100
    clustering = Clustering.objects.get(pk=job["result"]["clustering"])
    assert job["result_url"] == f"/api/v1/clusterings/{clustering.pk}/"
    assert job["result"]["page"] == f"/ros/clusterings/{clustering.pk}/"
    data = api.get(job["result_url"]).data
    assert data["container_count"] == 4 and len(data["containers"]) == 4
    assert sorted(n for c in data["containers"] for n in c["nodes"]) == sorted(autoware.graph.nodes)
    assert data["inter_container_bandwidth"] > 0 and data["intra_container_bandwidth"] > 0
    # The bandwidth left between containers is the sum over container pairs (Definition 3.2.1).
    assert sum(b["bytes_per_s"] for b in data["container_bandwidth"]) == pytest.approx(
        data["inter_container_bandwidth"]
    )
    assert data["images"] is None and data["dockerfiles"] is None
    assert data["result"]["passes"] and data["result"]["requested_containers"] == 4
    listed = api.get("/api/v1/clusterings/", {"rosgraph": autoware.pk}).data
    assert listed["count"] == 1 and "result" not in listed["results"][0]


def test_cluster_by_the_eq_3_13_bound(api, autoware):
    job = run(api, f"/api/v1/rosgraphs/{autoware.pk}/cluster/", {"memory_mib": 120, "overhead_mib": 39})
    assert job["state"] == "succeeded", job["error"]
    clustering = Clustering.objects.get(pk=job["result"]["clustering"])
    assert clustering.requested_containers == 3 and clustering.container_count == 3


@pytest.mark.parametrize(
    ("body", "field", "message"),
    [
        ({}, "containers", "give the number of containers"),
        ({"containers": 0}, "containers", "greater than or equal to 1"),
        ({"containers": 5, "memory_mib": 100, "overhead_mib": 39}, "containers", "exceed the Eq. 3.13 bound"),
        ({"memory_mib": 20, "overhead_mib": 29}, "memory", "cannot hold one container"),
        ({"memory_mib": 100}, "memory_mib", "needs both"),
        ({"containers": 2, "mode": "both"}, "mode", "is not a valid choice"),
        ({"containers": 2, "images": {"platforms": ["sparc"]}}, "images", "unknown architecture 'sparc'"),
    ],
)
def test_bad_cluster_requests_start_no_job(api, autoware, body, field, message):
    response = api.post(f"/api/v1/rosgraphs/{autoware.pk}/cluster/", body, format="json")
    assert response.status_code == 400, response.data
    assert message in json.dumps(response.data[field]), response.data
    assert Job.objects.count() == 0 and Clustering.objects.count() == 0


# ---- images and the Dockerfiles archive -----------------------------------------------------------------
def test_image_plan_disk_figures_and_dockerfiles_archives(api, contract_graph):
    job = run(api, f"/api/v1/rosgraphs/{contract_graph.pk}/cluster/", {"containers": 2, "images": {"tag": "v1"}})
    assert job["state"] == "succeeded", job["error"]
    data = api.get(job["result_url"]).data
    groups = {c["name"]: c["nodes"] for c in data["containers"]}
    # /scan (81920 B/s to each subscriber) pulls amcl and laser_driver together, move_base takes rviz (2000 B/s).
    assert groups == {"amcl": ["amcl", "laser_driver"], "move_base": ["move_base", "rviz"]}
    assert data["inter_container_bandwidth"] == 81920 + 500 + 500  # /scan to move_base, /pose to both
    # Container images alone: {nav2_amcl, nav2_core, rclcpp, urg_node} = 101 MiB and {nav2_core, rclcpp, rviz2}
    # = 290 MiB; with inheritance nav2_core and rclcpp (90) sit once in the base image: 391 -> 301 MiB.
    assert (data["disk_before_mib"], data["disk_after_mib"]) == (391.0, 301.0)
    assert job["result"]["disk"] == {"before_mib": 391.0, "after_mib": 301.0}
    images = {im["name"]: im for im in data["images"]["images"]}
    assert images["base"]["packages"] == ["nav2_core", "rclcpp"] and images["amcl"]["parent"] == "base"
    assert images["move_base"]["packages"] == ["rviz2"] and images["move_base"]["parent"] == "base"
    assert data["images"]["references"] == {"amcl": "continuum/amcl:v1", "move_base": "continuum/move_base:v1"}
    links = data["dockerfiles"]
    assert links["tar.gz"].endswith(f"/api/v1/clusterings/{data['id']}/dockerfiles/?archive=tar.gz")

    response = api.get(f"/api/v1/clusterings/{data['id']}/dockerfiles/", {"archive": "tar.gz"})
    assert response.status_code == 200 and response["Content-Type"] == "application/gzip"
    assert response["Content-Disposition"] == f'attachment; filename="mini-robot-{data["id"]}-dockerfiles.tar.gz"'
    with tarfile.open(fileobj=io.BytesIO(gzip.decompress(response.content))) as tar:
        names = sorted(tar.getnames())
        files = {n: tar.extractfile(n).read().decode() for n in names}
    assert names == ["amcl/Dockerfile", "base/Dockerfile", "build.sh", "move_base/Dockerfile", "plan.json"]
    assert "FROM ros:humble-ros-base" in files["base/Dockerfile"]
    assert "ros-humble-nav2-core ros-humble-rclcpp" in files["base/Dockerfile"]
    assert "FROM continuum/base:v1" in files["amcl/Dockerfile"]
    assert "ros-humble-nav2-amcl" in files["amcl/Dockerfile"] and "ros-humble-urg-node" in files["amcl/Dockerfile"]
    assert 'ENV CONTINUUM_ROS_NODES="amcl laser_driver"' in files["amcl/Dockerfile"]
    assert (
        "FROM continuum/base:v1" in files["move_base/Dockerfile"]
        and "ros-humble-rviz2" in files["move_base/Dockerfile"]
    )
    assert "--platform linux/amd64,linux/arm64 -t continuum/base:v1" in files["build.sh"]
    assert json.loads(files["plan.json"])["after_mib"] == 301.0
    # Same plan, same bytes.
    assert api.get(f"/api/v1/clusterings/{data['id']}/dockerfiles/").content == response.content

    zipped = api.get(f"/api/v1/clusterings/{data['id']}/dockerfiles/", {"archive": "zip"})
    assert zipped.status_code == 200 and zipped["Content-Type"] == "application/zip"
    with zipfile.ZipFile(io.BytesIO(zipped.content)) as zf:
        assert sorted(zf.namelist()) == names
        assert zf.read("move_base/Dockerfile").decode() == files["move_base/Dockerfile"]
    bad = api.get(f"/api/v1/clusterings/{data['id']}/dockerfiles/", {"archive": "rar"})
    assert bad.status_code == 400 and "archive" in bad.data


def test_no_packages_no_archive(api, autoware):
    job = run(api, f"/api/v1/rosgraphs/{autoware.pk}/cluster/", {"containers": 2})
    response = api.get(f"/api/v1/clusterings/{job['result']['clustering']}/dockerfiles/")
    assert response.status_code == 404 and "no image plan" in str(response.data)

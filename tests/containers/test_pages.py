"""Dashboard pages of ROS graphs -> containers -> nodes: login, fleet scoping, forms, charts, the why table."""

import gzip
import io
import json
import tarfile

import pytest
from django.core.files.uploadedfile import SimpleUploadedFile
from django.urls import reverse

from apps.containers import charts
from apps.containers.kinds import ContainersJob
from apps.containers.models import Clustering, Placement, RosGraph
from apps.containers.services import read_graph
from apps.jobs.models import Job
from apps.jobs.registry import HANDLERS
from apps.jobs.services import start_job
from tests.conftest import DATA
from tests.containers.test_rosgraphs_api import CONTRACT

pytestmark = pytest.mark.django_db


def make_graph(fleet, content: bytes | str, name: str = "") -> RosGraph:
    graph, fmt = read_graph(content, name=name)
    row = RosGraph(fleet=fleet, source_format=fmt, name=graph.name)
    row.set_graph(graph)
    row.save()
    return row


def cluster_it(row: RosGraph, n: int = 4) -> Clustering:
    job = start_job(ContainersJob.CLUSTER_ROS, row.fleet, {"rosgraph": row.pk, "containers": n})
    assert job.state == "succeeded", job.error
    return Clustering.objects.get(job=job)


def place_it(clustering: Clustering, cluster, **extra) -> Placement:
    arguments = {"clustering": clustering.pk, "cluster": cluster.pk, **extra}
    job = start_job(ContainersJob.PLACE, clustering.fleet, arguments)
    assert job.state == "succeeded", job.error
    return Placement.objects.get(job=job)


@pytest.fixture
def autoware(fleet):
    return make_graph(fleet, (DATA / "autoware_reference_system.json").read_bytes())


@pytest.fixture
def mini(fleet):
    return make_graph(fleet, json.dumps(CONTRACT))


@pytest.fixture
def placed(autoware, cluster):
    clustering = cluster_it(autoware)
    overrides = {c["name"]: {"cpu": 1.5} for c in clustering.containers}
    return place_it(clustering, cluster, overrides=overrides)


@pytest.fixture
def foreign_ros(fleets):
    """A ROS graph, clustering and placement of the second fleet (the operator is not in it)."""
    from apps.clusters.models import Cluster, ComputeNode

    other = fleets[1]
    cluster = Cluster.objects.create(fleet=other, name="beta-secret-cluster")
    ComputeNode.objects.create(cluster=cluster, name="beta-node", cpu=8, memory_mib=8192)
    row = make_graph(other, json.dumps({**CONTRACT, "name": "beta-secret-graph"}))
    clustering = cluster_it(row, 2)
    return {"rosgraph": row, "clustering": clustering, "placement": place_it(clustering, cluster), "cluster": cluster}


def page_urls(placed) -> list[str]:
    clustering = placed.clustering
    return [
        reverse("containers:rosgraphs"),
        reverse("containers:rosgraph", args=[clustering.rosgraph_id]),
        reverse("containers:clustering", args=[clustering.pk]),
        reverse("containers:placement", args=[placed.pk]),
    ]


# ---- login and scoping ------------------------------------------------------------------------------------
def test_every_page_and_form_requires_login(client, placed, mini):
    clustering = cluster_it(mini, 2)
    urls = [*page_urls(placed), reverse("containers:clustering-dockerfiles", args=[clustering.pk])]
    for url in urls:
        response = client.get(url)
        assert response.status_code == 302 and response["Location"].startswith(reverse("login") + "?next="), url
    before = (RosGraph.objects.count(), Job.objects.count())
    posts = [
        (reverse("containers:rosgraphs"), {"file": SimpleUploadedFile("g.json", json.dumps(CONTRACT).encode())}),
        (reverse("containers:rosgraph-levels", args=[mini.pk]), {"level:amcl": "driver"}),
        (reverse("containers:rosgraph-cluster", args=[mini.pk]), {"containers": 2}),
        (reverse("containers:clustering-place", args=[clustering.pk]), {"cluster": placed.cluster_id}),
        (reverse("containers:placement-push", args=[placed.pk]), {}),
    ]
    for url, data in posts:
        response = client.post(url, data)
        assert response.status_code == 302 and response["Location"].startswith(reverse("login")), url
    assert (RosGraph.objects.count(), Job.objects.count()) == before
    assert RosGraph.objects.get(pk=mini.pk).graph.nodes["amcl"].level is None


def test_pages_render_for_a_member_with_the_nav_entry(member, placed):
    for url in page_urls(placed):
        response = member.get(url)
        assert response.status_code == 200, url
        body = response.content.decode()
        assert f'href="{reverse("containers:rosgraphs")}" class="active">ROS graphs</a>' in body, url
    assert "ROS graphs</a>" in member.get(reverse("dashboard:home")).content.decode()


def test_other_fleets_objects_answer_404(member, foreign_ros, cluster):
    gets = [
        reverse("containers:rosgraph", args=[foreign_ros["rosgraph"].pk]),
        reverse("containers:clustering", args=[foreign_ros["clustering"].pk]),
        reverse("containers:clustering-dockerfiles", args=[foreign_ros["clustering"].pk]),
        reverse("containers:placement", args=[foreign_ros["placement"].pk]),
    ]
    for url in gets:
        assert member.get(url).status_code == 404, url
    jobs_before = Job.objects.count()
    posts = [
        (reverse("containers:rosgraph-levels", args=[foreign_ros["rosgraph"].pk]), {}),
        (reverse("containers:rosgraph-cluster", args=[foreign_ros["rosgraph"].pk]), {"containers": 2}),
        (reverse("containers:clustering-place", args=[foreign_ros["clustering"].pk]), {"cluster": cluster.pk}),
        (reverse("containers:placement-push", args=[foreign_ros["placement"].pk]), {}),
    ]
    for url, data in posts:
        assert member.post(url, data).status_code == 404, url
    assert Job.objects.count() == jobs_before
    listing = member.get(reverse("containers:rosgraphs")).content.decode()
    assert "beta-secret" not in listing


# ---- upload, levels, cluster --------------------------------------------------------------------------------
def test_upload_then_set_levels(member, fleet):
    content = (DATA / "autoware_reference_system.dot").read_bytes()
    response = member.post(reverse("containers:rosgraphs"), {"file": SimpleUploadedFile("aw.dot", content)})
    row = RosGraph.objects.get()
    assert response.status_code == 302 and response["Location"] == reverse("containers:rosgraph", args=[row.pk])
    assert (row.fleet, row.source_format, row.node_count) == (fleet, "dot", 24)
    page = member.get(response["Location"]).content.decode()
    assert "Imported" in page and 'id="rosgraph-chart"' in page and "Not clustered yet." in page
    assert "proposed: mission" in page  # the Behavior Planner, from the graph's structure

    url = reverse("containers:rosgraph-levels", args=[row.pk])
    response = member.post(url, {"level:Visualizer": "functionality", "level:Behavior Planner": "macro"})
    assert response.status_code == 302
    graph = RosGraph.objects.get(pk=row.pk).graph
    assert graph.nodes["Visualizer"].level == "functionality" and graph.nodes["Behavior Planner"].level == "macro"
    assert graph.nodes["Vehicle Interface"].level is None
    bad = member.post(url, {"level:Visualizer": "boss"})
    assert bad.status_code == 400 and "Select a valid choice" in bad.content.decode()
    assert RosGraph.objects.get(pk=row.pk).graph.nodes["Visualizer"].level == "functionality"


def test_bad_upload_shows_the_error_and_stores_nothing(member):
    bad = 'digraph G {\n  "a" -> "b";\n  "c" -> ;\n}\n'
    response = member.post(reverse("containers:rosgraphs"), {"file": SimpleUploadedFile("bad.dot", bad.encode())})
    assert response.status_code == 400
    body = response.content.decode()
    assert "Nothing was imported" in body and "bad.dot: line 3: expected a node id" in body
    assert RosGraph.objects.count() == 0


def test_cluster_form_starts_a_job_that_links_the_clustering(member, autoware):
    url = reverse("containers:rosgraph-cluster", args=[autoware.pk])
    data = {"containers": 3, "mode": "per_topic", "distro_image": "ros:humble-ros-base", "ros_distro": "humble",
            "distro_mib": 0, "platforms": ["amd64", "arm64"], "repository": "continuum", "tag": "latest"}  # fmt: skip
    response = member.post(url, data)
    job = Job.objects.get(kind="cluster_ros")
    assert response.status_code == 302 and response["Location"] == reverse("jobs:job", args=[job.pk])
    clustering = Clustering.objects.get(job=job)
    assert clustering.container_count == 3
    job_page = member.get(response["Location"]).content.decode()
    assert reverse("containers:clustering", args=[clustering.pk]) in job_page
    graph_page = member.get(reverse("containers:rosgraph", args=[autoware.pk])).content.decode()
    assert f"clustering #{clustering.pk}</a> (3 containers)" in graph_page


@pytest.mark.parametrize(
    ("data", "message"),
    [
        ({}, "give the number of containers"),
        ({"containers": 5, "memory_mib": 100, "overhead_mib": 39}, "exceed the Eq. 3.13 bound"),
        ({"memory_mib": 20, "overhead_mib": 29}, "cannot hold one container"),
        ({"containers": 2, "platforms": ["sparc"]}, "Select a valid choice"),
    ],
)
def test_bad_cluster_forms_start_no_job(member, autoware, data, message):
    base = {"mode": "per_topic", "distro_image": "ros:humble-ros-base", "ros_distro": "humble", "distro_mib": 0,
            "platforms": ["amd64"], "tag": "latest"}  # fmt: skip
    response = member.post(reverse("containers:rosgraph-cluster", args=[autoware.pk]), {**base, **data})
    assert response.status_code == 400
    assert message in response.content.decode()
    assert not Job.objects.exists()


# ---- clustering page, images, place form --------------------------------------------------------------------
def test_clustering_page_shows_graphs_images_and_downloads(member, mini):
    clustering = cluster_it(mini, 2)
    body = member.get(reverse("containers:clustering", args=[clustering.pk])).content.decode()
    for chart in ("rosgraph-chart", "container-chart", "disk-chart"):
        assert f'id="{chart}"' in body, chart
    assert "391 MiB" in body and "301 MiB" in body and "23 %" in body  # 1 - 301/391
    download = reverse("containers:clustering-dockerfiles", args=[clustering.pk])
    assert f'href="{download}?archive=tar.gz"' in body and f'href="{download}?archive=zip"' in body
    response = member.get(download, {"archive": "tar.gz"})
    assert response.status_code == 200 and response["Content-Type"] == "application/gzip"
    with tarfile.open(fileobj=io.BytesIO(gzip.decompress(response.content))) as tar:
        assert "base/Dockerfile" in tar.getnames()
    assert member.get(download, {"archive": "rar"}).status_code == 404


def test_clustering_without_packages_says_how_to_add_them(member, autoware):
    clustering = cluster_it(autoware)
    body = member.get(reverse("containers:clustering", args=[clustering.pk])).content.decode()
    assert "No image plan" in body and 'id="disk-chart"' not in body
    assert member.get(reverse("containers:clustering-dockerfiles", args=[clustering.pk])).status_code == 404


def test_place_form_runs_the_job_and_opens_the_placement(member, autoware, cluster, foreign_ros):
    clustering = cluster_it(autoware)
    page = member.get(reverse("containers:clustering", args=[clustering.pk])).content.decode()
    assert f'value="{cluster.pk}"' in page and "beta-secret-cluster" not in page
    overrides = json.dumps({c["name"]: {"cpu": 3} for c in clustering.containers})
    url = reverse("containers:clustering-place", args=[clustering.pk])
    response = member.post(
        url,
        {
            "cluster": cluster.pk,
            "policy": "superclustering",
            "overhead_mib": 39,
            "seed": 0,
            "compare": "on",
            "overrides": overrides,
        },
    )
    job = Job.objects.get(kind="place", fleet=clustering.fleet)
    assert response.status_code == 302 and job.state == "succeeded", job.error
    placement = Placement.objects.get(job=job)
    assert len(set(placement.placed().values())) == 4 and placement.baseline is not None
    assert reverse("containers:placement", args=[placement.pk]) in member.get(response["Location"]).content.decode()
    # Another fleet's cluster is not a choice, and bad overrides are refused.
    other = member.post(url, {"cluster": foreign_ros["cluster"].pk, "policy": "superclustering", "overhead_mib": 0,
                              "seed": 0})  # fmt: skip
    assert other.status_code == 400 and "Select a valid choice" in other.content.decode()
    for text, message in [("{oops", "not JSON"), ('{"ghost": {"cpu": 1}}', "unknown container &#x27;ghost&#x27;")]:
        bad = member.post(url, {"cluster": cluster.pk, "policy": "superclustering", "overhead_mib": 0, "seed": 0,
                                "overrides": text})  # fmt: skip
        assert bad.status_code == 400 and message in bad.content.decode()
    assert Job.objects.filter(kind="place", fleet=clustering.fleet).count() == 1


# ---- placement page -----------------------------------------------------------------------------------------
def test_placement_page_map_and_why_table(member, placed):
    url = reverse("containers:placement", args=[placed.pk])
    body = member.get(url).content.decode()
    assert 'id="placement-chart"' in body and "Between nodes" in body and "default-kubernetes on the same input" in body
    first = placed.plan["decisions"][0]
    assert f"Why {first['item']} went to {first['node']}" in body
    assert body.count('<span class="badge placement-not_pushed">not pushed</span>') == 4
    chosen = next(d for d in placed.plan["decisions"] if d["item"] == placed.plan["decisions"][2]["item"])
    body = member.get(url, {"container": chosen["item"]}).content.decode()
    table = body[body.index('id="why-table"') :]
    assert f"Why {chosen['item']} went to {chosen['node']}" in body
    assert table.count("<tr>") == 1 + 4  # header + one row per node
    assert '<th class="num">bandwidth</th>' in table and '<th class="num">free_resources</th>' in table
    assert '<span class="badge ok">chosen</span>' in table
    assert member.get(url, {"container": "ghost"}).status_code == 404


def test_placement_page_names_the_rejecting_filter(member, autoware, cluster):
    cluster.nodes.filter(name="node2").update(status="NotReady")
    clustering = cluster_it(autoware)
    placement = place_it(clustering, cluster)
    body = member.get(reverse("containers:placement", args=[placement.pk])).content.decode()
    table = body[body.index('id="why-table"') :]
    assert "TaintToleration" in table and "taint node.kubernetes.io/not-ready:NoSchedule not tolerated" in table


def test_push_button_only_with_a_kubeconfig_and_push_starts_a_job(member, placed, monkeypatch):
    url = reverse("containers:placement", args=[placed.pk])
    push = reverse("containers:placement-push", args=[placed.pk])
    page = member.get(url).content.decode()  # shown disabled, saying why
    assert f'action="{push}"' not in page and "its cluster has no Kubernetes API configured" in page
    response = member.post(push, follow=True)
    assert "no Kubernetes API configured" in response.content.decode()
    assert not Job.objects.filter(kind="push_placement").exists()
    placed.cluster.kubeconfig = "apiVersion: v1\nkind: Config\n"
    placed.cluster.save()
    body = member.get(url).content.decode()
    assert "Push to Kubernetes" in body and f'action="{push}"' in body
    seen = []

    def fake_push(job, progress):
        seen.append(dict(job.arguments))
        return {"placement": placed.pk, "page": url}, f"/api/v1/placements/{placed.pk}/"

    monkeypatch.setitem(HANDLERS, "push_placement", fake_push)
    response = member.post(push)
    job = Job.objects.get(kind="push_placement")
    assert response["Location"] == reverse("jobs:job", args=[job.pk]) and seen == [{"placement": placed.pk}]
    assert f'href="{url}"' in member.get(response["Location"]).content.decode()


# ---- charts -------------------------------------------------------------------------------------------------
def test_rosgraph_figure_colours_by_container_and_draws_levels():
    graph, _ = read_graph((DATA / "autoware_reference_system.json").read_bytes())
    groups = {"A": ["FrontLidarDriver", "PointsTransformerFront"], "B": sorted(set(graph.nodes) - {"FrontLidarDriver",
              "PointsTransformerFront"})}  # fmt: skip
    fig = charts.rosgraph_figure(graph, groups)
    node_traces = [t for t in fig.data if t.name in groups]
    assert [t.name for t in node_traces] == ["A", "B"]
    assert len({t.marker.color for t in node_traces}) == 2
    assert sum(len(t.x) for t in node_traces) == 24
    assert list(fig.layout.yaxis.ticktext) == ["driver", "functionality / controller", "macro-functionality", "mission"]
    levels = graph.levels()
    a = node_traces[0]
    row = {"driver": 0, "functionality": 1, "macro": 2, "mission": 3}
    for name, y in zip(a.text, a.y, strict=True):
        assert round(y) == row[levels[name]]
    lines = [t for t in fig.data if t.mode == "lines"]
    widths = {t.line.width for t in lines}
    assert len(widths) > 1 and max(widths) == 9.0  # the heaviest edge is drawn widest
    assert charts.INTER_COLOUR in {t.line.color for t in lines}  # edges crossing containers stand out


def test_container_and_placement_figures():
    containers = [{"name": "a", "nodes": ["x", "y"]}, {"name": "b", "nodes": ["z"]}]
    fig = charts.container_figure(containers, [{"a": "a", "b": "b", "bytes_per_s": 1000.0}])
    assert fig.data[-1].text == ("a (2)", "b (1)")
    cluster_doc = {"nodes": [{"name": "n1", "arch": "amd64"}, {"name": "n2", "arch": "arm64"}], "links": []}
    plan = {"placements": [{"container": "a", "node": "n1", "score": 100.0}], "pending": [{"container": "b"}]}
    fig = charts.placement_figure(cluster_doc, plan, [{"a": "n1", "b": "n2", "bytes_per_s": 10.0}], ["a", "b"])
    dots = {t.name: t for t in fig.data if t.legendgroup == "containers"}
    assert list(dots) == ["a", "b"]  # one legend entry per container, in the container colours
    assert dots["a"].hovertext == ("<b>a</b><br>on n1, score 100",)
    assert dots["b"].hovertext == ("<b>b</b><br>pending: no node passed the filters",)
    assert dots["a"].marker.color != dots["b"].marker.color and dots["b"].marker.line.color == charts.PENDING_COLOUR
    assert any(t.mode == "lines" and t.line.color == charts.INTER_COLOUR for t in fig.data)  # n1-n2 traffic
    assert charts.rate(1_250_000) == "1.25 MB/s (10 Mbit/s)" and charts.rate(12) == "12 B/s (9.6e-05 Mbit/s)"

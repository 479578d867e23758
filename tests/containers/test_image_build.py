"""Images built for real by inheritance (issue 32): a clustering's image plan built with buildah from
``continuum/base:bookworm``, each child ``FROM`` its parent, measured layer by layer, stored and shown.

Needs root and buildah (CI runs as root; scripts/build-images.sh installs buildah and builds the base image,
which this test builds when it is missing). Small Debian packages keep it to a minute or two.
"""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import pytest
from django.urls import reverse

from apps.containers.imagebuild import BASE_IMAGE, BuildError, image_layers, remove
from apps.containers.models import Clustering
from apps.ui.templatetags.ui import num
from tests.containers.test_pages import cluster_it, make_graph

pytestmark = pytest.mark.django_db
ROOT = Path(__file__).resolve().parents[2]

#: Two containers sharing python3-six (the base region), each with a package of its own.
GRAPH = {
    "format": "continuum.rosgraph/v1",
    "name": "debian robot",
    "nodes": [
        {"name": "talker", "cpu": 0.1, "memory_mib": 30, "packages": ["python3-six", "python3-yaml"]},
        {"name": "listener", "cpu": 0.1, "memory_mib": 30, "packages": ["python3-six", "python3-idna"]},
    ],
    "topics": [{"name": "/chatter", "publishers": ["talker"], "subscribers": ["listener"], "rate_hz": 1,
                "msg_bytes": 10}],
}  # fmt: skip


@pytest.fixture(scope="module")
def base_image():
    if os.geteuid() != 0:
        pytest.fail("building images needs root (buildah's storage; CI runs as root)")
    try:
        image_layers(BASE_IMAGE)
    except BuildError:  # not there yet
        # Missing buildah or base image: the script installs buildah and debootstrap, and builds the base.
        subprocess.run(["bash", str(ROOT / "scripts" / "build-images.sh"), "base"], check=True, timeout=1800)
    return BASE_IMAGE


def test_a_clustering_is_built_by_inheritance_and_measured(base_image, fleet, api, client, operator, request):
    clustering = cluster_it(make_graph(fleet, json.dumps(GRAPH)), n=2)
    assert clustering.container_count == 2 and clustering.images
    response = api.post(f"/api/v1/clusterings/{clustering.pk}/build-images/", {}, format="json")
    assert response.status_code == 202, response.data
    job = api.get(f"/api/v1/jobs/{response.data['id']}/").data
    assert job["state"] == "succeeded", job
    built = Clustering.objects.get(pk=clustering.pk).images["built"]
    request.addfinalizer(lambda: remove(im["reference"] for im in built["images"]))
    images = {im["name"]: im for im in built["images"]}
    kinds = sorted(im["kind"] for im in images.values())
    assert kinds == ["base", "container", "container"], images
    base = next(im for im in images.values() if im["kind"] == "base")
    assert base["parent"] == BASE_IMAGE and base["packages"] == ["python3-six"]
    base_layers = [layer["digest"] for layer in built["base"]["layers"]]
    for im in images.values():
        digests = [layer["digest"] for layer in im["layers"]]
        parent = base_layers if im["parent"] == BASE_IMAGE else [x["digest"] for x in images[base["name"]]["layers"]]
        assert digests[: len(parent)] == parent and len(digests) == len(parent) + 1  # FROM its parent, one layer
        assert im["own_mib"] > 0 and im["size_mib"] == pytest.approx(sum(x["mib"] for x in im["layers"]), abs=0.01)
        # What buildah says is in the image: the region's packages, installed.
        assert image_layers(im["reference"]) == digests
    # The disk figures from the layers: each container alone vs. everything once.
    containers = [im for im in images.values() if im["kind"] == "container"]
    assert built["before_mib"] == pytest.approx(sum(im["size_mib"] for im in containers), abs=0.01)
    after = built["base"]["size_mib"] + sum(im["own_mib"] for im in images.values())
    assert built["after_mib"] == pytest.approx(after, abs=0.01)
    assert 0 < built["saved"] < 1 and 0 < built["predicted_saved"] < 1 and built["thesis_saved"] == 0.832
    # The page shows each image's layers and size.
    client.force_login(operator)
    page = client.get(reverse("containers:clustering", args=[clustering.pk])).content.decode()
    assert "Built with buildah" in page
    for im in images.values():
        assert im["reference"] in page and f">{num(im['size_mib'], 1)}<" in page


def test_a_clustering_without_packages_is_a_400(fleet, api):
    graph = json.loads(json.dumps(GRAPH))
    for node in graph["nodes"]:
        node.pop("packages")
    clustering = cluster_it(make_graph(fleet, json.dumps(graph)), n=2)
    response = api.post(f"/api/v1/clusterings/{clustering.pk}/build-images/", {}, format="json")
    assert response.status_code == 400 and "clustering" in response.data
    response = api.post(f"/api/v1/clusterings/{clustering.pk}/build-images/", {"export": "maybe"}, format="json")
    assert response.status_code == 400 and "export" in response.data

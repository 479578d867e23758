"""Names that reach ``build.sh`` and the Dockerfiles are hostile until checked (issue 10, trust boundary).

Two layers: the API, the dashboard form and the CLI refuse an image repository, tag, base image, ROS
distribution or package name outside its grammar (OCI distribution reference, Debian/ROS package names);
and the generators quote what they write, which is shown here by running the generated shell code with a
fake ``docker``/``apt-get`` and checking that no injected command ran.
"""

import dataclasses
import io
import json
import os
import subprocess
import tarfile
from pathlib import Path

import pytest
from django.core.files.uploadedfile import SimpleUploadedFile

from apps.containers.management.commands import cluster_ros
from apps.containers.models import Clustering, RosGraph
from apps.jobs.models import Job
from continuum.engine.containers import image_inheritance
from continuum.engine.containers.image_inheritance import plan_images
from continuum.engine.core.errors import InputError

pytestmark = pytest.mark.django_db

GRAPH = {
    "format": "continuum.rosgraph/v1",
    "name": "mini",
    "nodes": [
        {"name": "drv", "packages": ["urg_node", "rclcpp"]},
        {"name": "ui", "packages": ["rviz2", "rclcpp"]},
    ],
    "topics": [{"name": "/scan", "publishers": ["drv"], "subscribers": ["ui"], "rate_hz": 10, "msg_bytes": 800}],
    "packages": {"rclcpp": 50, "urg_node": 3, "rviz2": 200},
}


def upload(api, document: dict):
    data = {"file": SimpleUploadedFile("g.json", json.dumps(document).encode())}
    return api.post("/api/v1/rosgraphs/import/", data, format="multipart")


@pytest.fixture
def graph(api):
    response = upload(api, GRAPH)
    assert response.status_code == 201, response.data
    return RosGraph.objects.get(pk=response.data["id"])


def fake_bin(tmp_path: Path, *commands: str) -> Path:
    """A directory of stand-ins that log their arguments (one per line, then a blank line) to ``calls.log``."""
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    for name in commands:
        script = bin_dir / name
        script.write_text(f'#!/bin/sh\nfor a in "$@"; do printf "%s\\n" "$a"; done >> "{tmp_path}/calls.log"\n'
                          f'echo >> "{tmp_path}/calls.log"\n')  # fmt: skip
        script.chmod(0o755)
    return bin_dir


def calls(tmp_path: Path) -> list[list[str]]:
    text = (tmp_path / "calls.log").read_text()
    return [block.split("\n") for block in text.strip("\n").split("\n\n")]


# ---- input: 400 / form error / exit 2 ---------------------------------------------------------------------
@pytest.mark.parametrize(
    ("images", "field", "message"),
    [
        ({"repository": "x;touch p;#"}, "repository", "is not an image repository"),
        ({"repository": "Registry/UPPER"}, "repository", "is not an image repository"),
        ({"tag": "v1 && touch p"}, "tag", "is not an image tag"),
        ({"tag": "-v1"}, "tag", "is not an image tag"),
        ({"distro_image": "ubuntu\nRUN touch /p"}, "distro_image", "is not an image reference"),
        ({"distro_image": "ros:humble$(id)"}, "distro_image", "is not an image reference"),
        ({"ros_distro": "humble;id"}, "ros_distro", "is not a ROS distribution name"),
    ],
)
def test_bad_image_options_are_a_400_naming_the_field(api, graph, images, field, message):
    response = api.post(f"/api/v1/rosgraphs/{graph.pk}/cluster/", {"containers": 2, "images": images}, format="json")
    assert response.status_code == 400, response.data
    assert message in str(response.data["images"][field]), response.data
    assert Job.objects.count() == 0 and Clustering.objects.count() == 0


def test_valid_references_with_registry_port_and_digest_are_accepted(api, graph):
    images = {"repository": "registry.local:5000/team/robots", "tag": "v1.2_rc-3",
              "distro_image": "docker.io/library/ros@sha256:" + "ab" * 32}  # fmt: skip
    response = api.post(f"/api/v1/rosgraphs/{graph.pk}/cluster/", {"containers": 2, "images": images}, format="json")
    assert response.status_code == 202, response.data
    job = api.get(f"/api/v1/jobs/{response.data['id']}/").data
    assert job["state"] == "succeeded", job
    clustering = Clustering.objects.get()
    assert set(clustering.images["references"].values()) == {
        "registry.local:5000/team/robots/drv:v1.2_rc-3", "registry.local:5000/team/robots/ui:v1.2_rc-3"
    }  # fmt: skip


def test_bad_package_names_are_refused_on_import_and_edit(api, graph):
    hostile = json.loads(json.dumps(GRAPH))
    hostile["nodes"][0]["packages"] = ["urg_node", "pkg$(touch p)"]
    response = upload(api, hostile)
    assert response.status_code == 400
    assert "'pkg$(touch p)' is not a package name" in str(response.data["file"]), response.data
    hostile = json.loads(json.dumps(GRAPH))
    hostile["packages"]["rviz2 ;id"] = 1
    response = upload(api, hostile)
    assert response.status_code == 400 and "'rviz2 ;id' is not a package name" in str(response.data["file"])
    assert RosGraph.objects.count() == 1
    before = RosGraph.objects.get(pk=graph.pk).document
    for body, field in (
        ({"nodes": {"drv": {"packages": ["rclcpp", "a`touch p`"]}}}, "nodes"),
        ({"packages": {"pkg$(touch p)": 5}}, "packages"),
    ):
        response = api.patch(f"/api/v1/rosgraphs/{graph.pk}/", body, format="json")
        assert response.status_code == 400, response.data
        assert "is not a package name" in str(response.data[field]), response.data
    assert RosGraph.objects.get(pk=graph.pk).document == before


def test_a_placement_image_override_must_be_an_image_reference(api, graph, cluster):
    job = api.post(f"/api/v1/rosgraphs/{graph.pk}/cluster/", {"containers": 2}, format="json")
    assert job.status_code == 202, job.data
    clustering = Clustering.objects.get()
    name = clustering.containers[0]["name"]
    body = {"cluster": cluster.pk, "overrides": {name: {"image": "x;touch p"}}}
    response = api.post(f"/api/v1/clusterings/{clustering.pk}/place/", body, format="json")
    assert response.status_code == 400, response.data
    assert "'image' must be an image reference: 'x;touch p' is not" in str(response.data), response.data


def test_the_dashboard_form_shows_the_grammar_error(graph):
    from apps.containers.forms import ClusterForm

    data = {"containers": 2, "mode": "per_topic", "distro_image": "ros:humble", "ros_distro": "humble",
            "distro_mib": 0, "platforms": ["amd64"], "repository": "x;touch p;#", "tag": "latest"}  # fmt: skip
    form = ClusterForm(data=data)
    assert not form.is_valid()
    assert "is not an image repository" in str(form.errors["repository"])


def test_cli_refuses_a_bad_package_name_with_exit_2(tmp_path, capsys):
    hostile = json.loads(json.dumps(GRAPH))
    hostile["nodes"][1]["packages"] = ["rviz2", "pkg$(touch p)"]
    path = tmp_path / "g.json"
    path.write_text(json.dumps(hostile))
    with pytest.raises(SystemExit) as exc:
        cluster_ros.Command().run_from_argv(["manage.py", "cluster_ros", str(path), "--containers", "2",
                                             "--images", str(tmp_path / "x.tar"), "--skip-checks"])  # fmt: skip
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "'pkg$(touch p)' is not a package name" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "x.tar").exists()


def test_the_engine_refuses_bad_names_too():
    deps = {"a": ["rclcpp", "x"], "b": ["rclcpp"]}
    for kwargs, field in (
        ({"repository": "x;touch p;#"}, "repository"),
        ({"tag": "$(id)"}, "tag"),
        ({"distro_image": "ros humble"}, "distro_image"),
        ({"apt_names": {"x": "libx; id"}}, "packages"),
    ):
        with pytest.raises(InputError) as exc:
            plan_images(deps, **kwargs)
        assert exc.value.field == field
    with pytest.raises(InputError, match="is not a package name"):
        plan_images({"a": ["pkg$(cmd)"]})


# ---- output: what is written is quoted ----------------------------------------------------------------------
def test_build_sh_quotes_every_value_even_unchecked_ones(tmp_path):
    """The reproduction: ``images.repository = "x;touch p;#"`` used to land unquoted in build.sh. The planner
    refuses it now; the script is also safe on its own, which is shown with a plan whose checks are skipped."""
    plan = plan_images({"a": ["rclcpp", "x"], "b": ["rclcpp"]}, {"rclcpp": 1})
    plan = dataclasses.replace(plan, repository="x;touch p;#", tag="$(touch q)`touch r`")
    with tarfile.open(fileobj=io.BytesIO(plan.archive("tar"))) as tar:
        script = tar.extractfile("build.sh").read().decode()
    work = tmp_path / "work"
    work.mkdir()
    (work / "build.sh").write_text(script)
    assert subprocess.run(["bash", "-n", "build.sh"], cwd=work).returncode == 0
    env = {**os.environ, "PATH": f"{fake_bin(tmp_path, 'docker')}:{os.environ['PATH']}"}
    result = subprocess.run(["sh", "build.sh"], cwd=work, env=env, capture_output=True, text=True, timeout=30)
    assert result.returncode == 0, result.stderr
    assert sorted(p.name for p in work.iterdir()) == ["build.sh"]  # no marker file p, q or r
    builds = calls(tmp_path)
    assert [b[b.index("-t") + 1] for b in builds] == [
        f"x;touch p;#/{name}:$(touch q)`touch r`" for name in ("base", "a", "b")
    ]
    assert all(b[:3] == ["buildx", "build", "--platform"] and b[-2:-1] == ["--push"] for b in builds)


def test_dockerfile_run_lines_quote_package_names_and_labels_stay_on_one_line(tmp_path, monkeypatch):
    """The reproduction: a package named ``pkg$(cmd)`` used to land in a Dockerfile RUN line as shell code."""
    monkeypatch.setattr(image_inheritance, "check_plan_inputs", lambda *args: None)
    hostile = "pkg$(touch p)`touch q`"
    plan = plan_images(
        {'c"\nRUN touch /pwned': [hostile, "rclcpp"], "d": ["rclcpp"]},
        ros_nodes={'c"\nRUN touch /pwned': ['n1"\nRUN touch /pwned #', "$HOME"]},
    )
    for text in plan.dockerfiles.values():
        instructions = [ln for ln in text.split("\n") if ln and not ln.startswith((" ", "#"))]
        assert all(ln.split()[0] in ("FROM", "LABEL", "RUN", "ENV") for ln in instructions), text
        assert not any(ln.startswith("RUN touch") for ln in text.split("\n"))
    [container] = [im for im in plan.images if hostile in im.packages]
    dockerfile = plan.dockerfiles[container.name]
    assert 'ENV CONTINUUM_ROS_NODES="n1\\"?RUN touch /pwned # \\$HOME"' in dockerfile
    [run] = [ln for ln in dockerfile.replace("\\\n", " ").split("\n") if ln.startswith("RUN ")]
    work = tmp_path / "work"
    work.mkdir()
    bin_dir = fake_bin(tmp_path, "apt-get", "rm")
    (bin_dir / "touch").symlink_to("/usr/bin/touch")  # an injected `touch p` would find it
    result = subprocess.run(["/bin/sh", "-c", run.removeprefix("RUN ")], cwd=work, env={"PATH": str(bin_dir)},
                            capture_output=True, text=True, timeout=30)  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert list(work.iterdir()) == []
    update, install, rm = calls(tmp_path)
    assert update == ["update"] and rm[0] == "-rf"
    assert install == ["install", "-y", "--no-install-recommends", f"ros-humble-{hostile}"]


def test_an_archive_of_options_stored_before_the_checks_is_refused(api, graph, client, operator):
    """A clustering stored before names were checked (here: edited in the database) gets no build script."""
    response = api.post(f"/api/v1/rosgraphs/{graph.pk}/cluster/", {"containers": 2}, format="json")
    assert response.status_code == 202, response.data
    clustering = Clustering.objects.get()
    clustering.params["images"]["repository"] = "x;touch p;#"
    clustering.save(update_fields=["params"])
    response = api.get(f"/api/v1/clusterings/{clustering.pk}/dockerfiles/?archive=zip")
    assert response.status_code == 409
    assert "is not an image repository" in str(response.data["images"])
    client.force_login(operator)
    page = client.get(f"/ros/clusterings/{clustering.pk}/dockerfiles/?archive=zip")
    assert page.status_code == 409 and b"is not an image repository" in page.content

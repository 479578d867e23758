"""``manage.py register_cluster`` (what ``./scripts/cluster up --register`` runs) against the session's live
multi-node cluster: the cluster row with the file's nodes and the kubeconfig, then the nodes synced Ready."""

import json
from io import StringIO
from pathlib import Path

import pytest
from django.core.management import CommandError, call_command

from apps.clusters.models import Cluster
from tests.kube.conftest import MULTINODE_CLUSTER, MULTINODE_VICTIM

pytestmark = pytest.mark.django_db


@pytest.fixture
def files(tmp_path, kube_multinode):
    kubeconfig = tmp_path / "kubeconfig"
    kubeconfig.write_text(kube_multinode.kubeconfig())
    cluster_file = tmp_path / "testbed.json"
    cluster_file.write_text(json.dumps({**MULTINODE_CLUSTER, "links": [
        {"src": "hollow-a", "dst": "hollow-b", "bandwidth_mbps": 1000, "latency_ms": 0.2}]}))  # fmt: skip
    return str(kubeconfig), str(cluster_file)


def register(*args: str) -> dict:
    out = StringIO()
    call_command("register_cluster", *args, "--json", stdout=out)
    return json.loads(out.getvalue())


def test_registers_the_live_cluster_and_syncs_its_nodes_ready(fleet, files):
    kubeconfig, cluster_file = files
    result = register("--kubeconfig", kubeconfig, "--cluster-file", cluster_file, "--fleet", fleet.slug)
    assert result["cluster_created"] and result["synced"] and result["name"] == "testbed"
    cluster = Cluster.objects.get(pk=result["cluster"], fleet=fleet)
    assert cluster.kubeconfig == Path(kubeconfig).read_text()
    nodes = {n.name: n for n in cluster.nodes.all()}
    assert set(nodes) == {n["name"] for n in MULTINODE_CLUSTER["nodes"]}
    # Every node but the one other tests kill is Ready, as the API says.
    assert {n for n in nodes if n != MULTINODE_VICTIM} <= set(result["ready"])
    # What Kubernetes says wins (arch, labels, taints); the hollow node's fixed capacity is stored as reported...
    assert nodes["hollow-b"].arch == "arm64" and nodes["hollow-a"].labels["zone"] == "edge"
    assert (nodes["hollow-a"].reported_cpu, nodes["hollow-a"].reported_memory_mib) == (1.0, 3840)
    assert any(t["key"] == "RealTime" for t in nodes["hollow-rt"].taints)
    # ...Continuum's own attributes, and the capacity it plans with, come from the file.
    assert (nodes["hollow-a"].cpu, nodes["hollow-a"].memory_mib, nodes["hollow-a"].capacity_source) == (
        4.0,
        8192,
        "declared",
    )
    assert nodes["hollow-rt"].rt and nodes["hollow-rt"].rt_threshold == 7.6 and nodes["hollow-rt"].criticality == "C"
    assert cluster.links.get().bandwidth_mbps == 1000
    assert cluster.last_synced is not None


def test_registering_again_updates_the_same_cluster(fleet, files):
    kubeconfig, cluster_file = files
    first = register("--kubeconfig", kubeconfig, "--cluster-file", cluster_file, "--fleet", fleet.slug, "--name", "x")
    again = register("--kubeconfig", kubeconfig, "--cluster-file", cluster_file, "--fleet", fleet.slug, "--name", "x")
    assert again["cluster"] == first["cluster"] and first["cluster_created"] and not again["cluster_created"]
    assert again["created"] == 0 and again["nodes"] == len(MULTINODE_CLUSTER["nodes"])
    assert Cluster.objects.filter(fleet=fleet, name="x").get().nodes.count() == len(MULTINODE_CLUSTER["nodes"])


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"fleet": "nope"}, "fleet 'nope' does not exist"),
        ({"kubeconfig": "missing"}, "no such file"),
        ({"cluster_file": "missing"}, "no such file"),
        ({"kubeconfig_text": "server: http://10.0.0.1"}, "kubeconfig"),
        ({"doc": {"format": "continuum.cluster/v1", "nodes": [{"name": "a", "cpu": 0}]}}, "bad.json: nodes:"),
        ({"doc": {"format": "continuum.cluster/v1", "nodes": [{"name": "a", "rt": "false"}]}}, "bad.json: nodes:"),
    ],
)
def test_bad_input_exits_2_with_one_line(fleet, files, tmp_path, change, message):
    kubeconfig, cluster_file = files
    if "kubeconfig_text" in change:
        text = Path(kubeconfig).read_text()
        kubeconfig = str(tmp_path / "bad-kubeconfig")
        server = next(line.split("server: ")[1] for line in text.splitlines() if "server: " in line)
        Path(kubeconfig).write_text(text.replace(server, "http://10.0.0.1"))
    if "doc" in change:
        cluster_file = str(tmp_path / "bad.json")
        Path(cluster_file).write_text(json.dumps(change["doc"]))
    if change.get("kubeconfig") == "missing":
        kubeconfig = str(tmp_path / "absent")
    if change.get("cluster_file") == "missing":
        cluster_file = str(tmp_path / "absent.json")
    fleet_slug = change.get("fleet", fleet.slug)
    with pytest.raises(CommandError) as err:
        register("--kubeconfig", kubeconfig, "--cluster-file", cluster_file, "--fleet", fleet_slug)
    assert err.value.returncode == 2
    assert message in str(err.value) and "\n" not in str(err.value)
    assert not Cluster.objects.filter(fleet=fleet).exists()


def test_check_only_needs_no_kubeconfig_and_writes_nothing(fleet, files):
    _, cluster_file = files
    result = register("--check-only", "--cluster-file", cluster_file, "--fleet", fleet.slug)
    assert result == {
        "name": "testbed",
        "fleet": fleet.slug,
        "nodes": len(MULTINODE_CLUSTER["nodes"]),
        "check_only": True,
    }
    assert not Cluster.objects.exists()


@pytest.mark.parametrize("text", ["{{{ not yaml", "[1, 2]", "a: b\n---\nc: d\n", "[" * 100_000])
def test_a_malformed_cluster_file_is_one_line_on_stderr_no_traceback(fleet, tmp_path, capsys, text):
    from django.core.management import get_commands, load_command_class

    path = tmp_path / "bad.yaml"
    path.write_text(text)
    cmd = load_command_class(get_commands()["register_cluster"], "register_cluster")
    with pytest.raises(SystemExit) as exc:
        cmd.run_from_argv(["manage.py", "register_cluster", "--check-only", "--cluster-file", str(path),
                           "--fleet", fleet.slug, "--skip-checks"])  # fmt: skip
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err

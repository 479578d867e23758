"""One test per crash or unbounded cost found on main (issue 10, "Trust boundary"): each answered HTTP 500,
a CLI traceback, a RecursionError or ran without end; each must now be a 400 naming the field (or exit
status 2 with one line on stderr), with nothing stored."""

import json
from pathlib import Path

import pytest
from django.core.files.uploadedfile import SimpleUploadedFile
from django.core.management import get_commands, load_command_class

from apps.clusters.models import Cluster, ComputeNode, Link
from apps.jobs.models import Job
from apps.workloads.models import Application
from continuum.engine.core import limits

DATA = Path(__file__).resolve().parents[1] / "data"


def deep_json(levels: int) -> str:
    return "[" * levels + "]" * levels


# ---- cost-driving inputs ------------------------------------------------------------------------------------
def test_generate_with_a_huge_out_degree_is_refused_naming_the_field(api):
    response = api.post("/api/v1/applications/generate/", {"generator": "layered", "out_degree": 1e300}, format="json")
    assert response.status_code == 400
    assert "out_degree" in response.data and "at most 100" in str(response.data["out_degree"])
    assert not Application.objects.exists()


def test_generate_n_times_processors_is_bounded(api):
    body = {"generator": "layered", "n": 20000, "processors": 1024}
    response = api.post("/api/v1/applications/generate/", body, format="json")
    assert response.status_code == 400 and "processors" in response.data, response.data


def test_frames_in_params_obey_the_frames_limit(api, cluster):
    app = api.post("/api/v1/applications/generate/", {"generator": "layered", "n": 10}, format="json").data
    body = {"algorithm": "heft", "cluster": cluster.pk, "params": {"frames": 100_000_000}}
    response = api.post(f"/api/v1/applications/{app['id']}/schedule/", body, format="json")
    assert response.status_code == 400, response.data
    assert "frames: at most 1000" in json.dumps(response.data)
    assert not Job.objects.exists()


def test_batch_in_params_obeys_the_frames_limit(api, cluster):
    app = api.post("/api/v1/applications/generate/", {"generator": "layered", "n": 10}, format="json").data
    body = {"algorithm": "heft", "cluster": cluster.pk, "params": {"batch": 10**9, "frames": 2}}
    response = api.post(f"/api/v1/applications/{app['id']}/schedule/", body, format="json")
    assert response.status_code == 400 and "batch" in json.dumps(response.data), response.data


def test_a_cluster_document_past_the_node_limit_is_refused_before_validation(api):
    doc = {"name": "big", "nodes": [{"name": f"n{i}"} for i in range(limits.get().nodes + 1)]}
    response = api.post("/api/v1/clusters/import/", doc, format="json")
    assert response.status_code == 400
    assert f"nodes: at most {limits.get().nodes:,}" in str(response.data["nodes"])
    assert not Cluster.objects.exists()


def test_a_cluster_document_past_the_link_limit_is_refused(api):
    with limits.override(links=3):
        doc = {"name": "c", "nodes": [{"name": "a"}, {"name": "b"}],
               "links": [{"src": "a", "dst": "b", "bandwidth_mbps": 1}] * 4}  # fmt: skip
        response = api.post("/api/v1/clusters/import/", doc, format="json")
    assert response.status_code == 400 and "links: at most 3" in str(response.data["links"])


def test_deep_json_body_is_a_400_not_a_recursion_error(api):
    response = api.generic("POST", "/api/v1/clusters/import/", deep_json(100_000), content_type="application/json")
    assert response.status_code == 400 and "nested too deeply" in str(response.data)


def test_deep_json_upload_is_a_400_naming_the_file(api):
    upload = SimpleUploadedFile("deep.json", deep_json(100_000).encode())
    response = api.post("/api/v1/applications/import/", {"file": upload}, format="multipart")
    assert response.status_code == 400 and "nested too deeply" in str(response.data["file"])


def test_deep_yaml_is_refused(api, rt_cluster_id):
    text = "a: " + "[" * 20_000 + "]" * 20_000
    response = api.post("/api/v1/realtimes/import/", {"cluster": rt_cluster_id, "yaml": text}, format="json")
    assert response.status_code == 400 and "nested too deeply" in json.dumps(response.data), response.data


def test_deeply_nested_assertion_is_refused(api, cluster):
    body = {"name": "deep", "text": "G(" + "!" * 2000 + "a)"}
    response = api.post("/api/v1/assertions/", body, format="json")
    assert response.status_code == 400 and "levels of nesting" in json.dumps(response.data), response.data


def test_an_upload_past_the_size_limit_is_refused(api):
    with limits.override(upload_bytes=100):
        upload = SimpleUploadedFile("big.json", b" " * 101 + b"{}")
        response = api.post("/api/v1/applications/import/", {"file": upload}, format="multipart")
    assert response.status_code == 400 and "file: at most 100 bytes" in str(response.data["file"])


# ---- causes of HTTP 500 ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("value", ["99999999999999999999", "-1", "abc", "1e3", "0"])
def test_bad_limit_is_a_400_naming_it(api, value):
    response = api.get(f"/api/v1/applications/?limit={value}")
    assert response.status_code == 400 and "limit" in response.data


def test_limit_above_the_page_size_is_refused_and_offset_is_bounded(api):
    assert api.get("/api/v1/applications/?limit=1000").status_code == 200
    assert api.get("/api/v1/applications/?limit=1001").status_code == 400
    assert api.get("/api/v1/jobs/?offset=99999999999999999999").status_code == 400


def test_null_accelerators_on_a_node_patch(api, cluster):
    node = ComputeNode.objects.filter(cluster_id=cluster.pk).first()
    response = api.patch(f"/api/v1/nodes/{node.pk}/", {"accelerators": "null"}, format="multipart")
    assert response.status_code in (200, 400), response.data  # a form field "null" is a name, not JSON null
    node.refresh_from_db()
    assert isinstance(node.accelerators, list)
    response = api.patch(f"/api/v1/nodes/{node.pk}/", {"accelerators": None}, format="json")
    assert response.status_code == 400 and "accelerators" in response.data, response.data


def test_a_second_rt_policy_for_a_cluster_is_a_400(api, cluster):
    first = api.post("/api/v1/rt-policies/", {"cluster": cluster.pk}, format="json")
    assert first.status_code == 201, first.data
    second = api.post("/api/v1/rt-policies/", {"cluster": cluster.pk}, format="json")
    assert second.status_code == 400 and "cluster" in second.data, second.data


def test_a_duplicate_link_in_a_cluster_document(api):
    link = {"src": "a", "dst": "b", "bandwidth_mbps": 1}
    doc = {"name": "dup", "nodes": [{"name": "a"}, {"name": "b"}], "links": [link, {**link, "bandwidth_mbps": 2}]}
    response = api.post("/api/v1/clusters/import/", doc, format="json")
    assert response.status_code == 400 and "links[1]" in str(response.data["links"]), response.data
    assert not Cluster.objects.exists() and not Link.objects.exists()


@pytest.mark.parametrize("path", ["/api/v1/clusters/?fleet__slug=a%00b", "/api/v1/applications/?search=%00"])
def test_nul_in_a_query_parameter(api, path):
    response = api.get(path)
    assert response.status_code == 400


def test_nul_in_a_fleet_slug_and_in_text(api):
    doc = {"name": "c", "fleet": "al\x00pha", "nodes": [{"name": "a"}]}
    response = api.post("/api/v1/clusters/import/", doc, format="json")
    assert response.status_code == 400
    response = api.post("/api/v1/clusters/", {"name": "x\x00y"}, format="multipart")
    assert response.status_code == 400 and "name" in response.data
    assert not Cluster.objects.exists()


def test_sent_at_far_in_the_future(api, rt_cluster_id):
    spec = {"node": "node0", "containerName": "slam", "missedDeadlinesPeriod": 0, "missedDeadlinesTotal": 0,
            "sentAt": 1e20}  # fmt: skip
    report = {"apiVersion": "rt.monitoring/v1alpha1", "kind": "Monitoring", "metadata": {"name": "slam"}, "spec": spec}
    response = api.post("/api/v1/rt-reports/", {"cluster": rt_cluster_id, "reports": [report]}, format="json")
    assert response.status_code == 400 and "sentAt" in json.dumps(response.data), response.data


def test_nan_in_a_ros_graph_meta(api):
    doc = json.loads((DATA / "autoware_reference_system.json").read_text())
    text = json.dumps(doc)[:-1] + ', "meta": {"x": NaN}}'
    upload = SimpleUploadedFile("g.json", text.encode())
    response = api.post("/api/v1/rosgraphs/import/", {"file": upload}, format="multipart")
    assert response.status_code == 400 and "NaN" in json.dumps(response.data), response.data


def test_infinite_eq_3_13_bound(api):
    upload = SimpleUploadedFile("g.json", (DATA / "irobot_sierra_nevada.json").read_bytes())
    graph = api.post("/api/v1/rosgraphs/import/", {"file": upload}, format="multipart").data
    body = {"memory_mib": 1e308, "overhead_mib": 1e-308}
    response = api.post(f"/api/v1/rosgraphs/{graph['id']}/cluster/", body, format="json")
    assert response.status_code == 400 and "not a finite number" in str(response.data["memory"]), response.data


# ---- CLI tracebacks ------------------------------------------------------------------------------------------
def run_cli(name: str, *argv: str, capsys) -> str:
    """Run a command as ``manage.py`` would; it must exit 2 with one line on stderr and no traceback."""
    cmd = load_command_class(get_commands()[name], name)
    with pytest.raises(SystemExit) as exc:
        cmd.run_from_argv(["manage.py", name, *argv, "--skip-checks"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    return err


def test_cli_deep_json(tmp_path, capsys):
    path = tmp_path / "deep.json"
    path.write_text(deep_json(100_000))
    assert "nested too deeply" in run_cli("schedule", str(path), "--cpus", "2", capsys=capsys)


def wfformat(tmp_path, mutate) -> str:
    doc = json.loads((DATA / "montage-chameleon-2mass-005d-001.json").read_text())
    mutate(doc["workflow"]["specification"]["tasks"][1])
    path = tmp_path / "wf.json"
    path.write_text(json.dumps(doc))
    return str(path)


def test_cli_wfformat_parents_minus_one(tmp_path, capsys):
    path = wfformat(tmp_path, lambda t: t.update(parents=-1))
    assert "parents" in run_cli("schedule", path, "--cpus", "2", capsys=capsys)


def test_cli_wfformat_nested_input_files(tmp_path, capsys):
    path = wfformat(tmp_path, lambda t: t.update(inputFiles=[["a"], ["b"]]))
    assert "inputFiles" in run_cli("schedule", path, "--cpus", "2", capsys=capsys)


def test_cli_irobot_period_1e400(tmp_path, capsys):
    text = (DATA / "irobot_sierra_nevada.json").read_text()
    doc = json.loads(text)
    path = tmp_path / "irobot.json"
    path.write_text(_set_first_period(doc))
    err = run_cli("cluster_ros", str(path), "--containers", "2", capsys=capsys)
    assert "1e400" in err or "finite" in err


def _set_first_period(doc) -> str:
    text = json.dumps(doc)
    return text.replace('"period_ms": ', '"period_ms": 1e400, "x_": ', 1)


def test_cli_deep_stl(capsys):
    trace = str(DATA / "verification" / "speed_trace.csv")
    err = run_cli("stl_check", trace, "--assertion", "G(" + "!" * 2000 + "a)", capsys=capsys)
    assert "levels of nesting" in err


@pytest.fixture
def rt_cluster_id(api, cluster):
    return cluster.pk


# ---- found by the mutation fuzz (tests/fuzz/test_mutation_fuzz.py) -------------------------------------------
def test_memory_beyond_a_32_bit_column_is_a_400(api):
    doc = {"name": "big", "nodes": [{"name": "a", "memory_mib": 2**40}]}
    response = api.post("/api/v1/clusters/import/", doc, format="json")
    assert response.status_code == 400 and "memory_mib" in json.dumps(response.data)


def test_cpu_cores_are_bounded(api, tmp_path, capsys):
    doc = {"name": "big", "nodes": [{"name": "a", "cpu": 1e300}]}
    response = api.post("/api/v1/clusters/import/", doc, format="json")
    assert response.status_code == 400 and "cpu: at most 1024" in json.dumps(response.data)
    cluster = json.loads((DATA / "heft4k-mini.cluster.json").read_text())
    cluster["nodes"][0]["cpu"] = 1e300
    path = tmp_path / "c.json"
    path.write_text(json.dumps(cluster))
    assert "cpu: at most 1024" in run_cli("heft4k", str(DATA / "heft4k-mini.dag.json"), "--cluster", str(path),
                                          capsys=capsys)  # fmt: skip


def test_nul_in_a_text_dag_file(api):
    text = (DATA / "orb_graph.csv").read_text().replace(",", ",\x00", 1)
    response = api.post("/api/v1/applications/import/", {"file": SimpleUploadedFile("g.csv", text.encode())})
    assert response.status_code == 400 and "NUL" in str(response.data["file"])
    assert not Application.objects.exists()


def test_nul_in_a_multipart_json_field(api, cluster):
    node = ComputeNode.objects.filter(cluster=cluster).first()
    response = api.patch(f"/api/v1/nodes/{node.pk}/", {"labels": '{"a": "\\u0000"}'}, format="multipart")
    assert response.status_code == 400 and "labels" in json.dumps(response.data), response.data


def test_platform_numbers_of_the_wrong_type(api, cluster):
    app = api.post("/api/v1/applications/generate/", {"generator": "layered", "n": 10}, format="json").data
    platform = {"processors": [{"id": "p0", "speed": [1]}], "latency": [0.0]}
    response = api.post(f"/api/v1/applications/{app['id']}/schedule/", {"platform": platform}, format="json")
    assert response.status_code == 400 and "speed" in json.dumps(response.data), response.data


def test_a_refused_what_if_leaves_no_rt_policy_behind(api, cluster):
    from apps.realtime.models import RTPolicy

    response = api.post("/api/v1/rt-plans/whatif/", {"cluster": cluster.pk, "containers": 1e300}, format="json")
    assert response.status_code == 400
    assert not RTPolicy.objects.exists()


def test_autoware_topic_lists_of_lists(tmp_path, capsys):
    doc = json.loads((DATA / "autoware_reference_system.json").read_text())
    doc["nodes"][0]["publishes"] = [["a"]]
    path = tmp_path / "g.json"
    path.write_text(json.dumps(doc))
    assert "topic names" in run_cli("cluster_ros", str(path), "--containers", "2", capsys=capsys)


def test_monitorstats_current_node_of_the_wrong_type(tmp_path, capsys):
    doc = json.loads((DATA / "verification" / "case_study_1.monitorstats.json").read_text())
    doc["monitors"][0]["current"] = ["edge"]
    path = tmp_path / "s.json"
    path.write_text(json.dumps(doc))
    assert "current node" in run_cli("allocate_monitors", str(path), "--time-limit", "1", capsys=capsys)


def test_cli_cpus_are_bounded(capsys):
    err = run_cli("schedule", str(DATA / "topcuoglu.dag.json"), "--cpus", "1000000000", capsys=capsys)
    assert "processors: at most 1024" in err


def test_limits_can_be_overridden_from_the_environment():
    lim = limits.Limits.from_env({"CONTINUUM_MAX_FRAMES": "2000", "CONTINUUM_MAX_OUT_DEGREE": "7.5"})
    assert (lim.frames, lim.out_degree, lim.tasks) == (2000, 7.5, limits.Limits().tasks)
    with pytest.raises(ValueError, match="CONTINUUM_MAX_FRAMES"):
        limits.Limits.from_env({"CONTINUUM_MAX_FRAMES": "-3"})


def test_a_refused_json_value_is_a_field_error_naming_its_path(api):
    body = '{"name": "c", "nodes": [{"name": "a", "cpu": 1e400}]}'
    response = api.generic("POST", "/api/v1/clusters/import/", body, content_type="application/json")
    assert response.status_code == 400
    assert "nodes[0].cpu: the number 1e400 is out of range" in str(response.data["nodes"])


BAD_QUERIES = [
    "limit=99999999999999999999", "offset=-1", "cluster=99999999999999999999", "application=1e400",
    "fleet__slug=%00", "ordering=-nonexistent", "search=" + "x" * 5000, "state=%3Cscript%3E", "id=NaN",
]  # fmt: skip


@pytest.mark.parametrize("query", BAD_QUERIES)
def test_every_list_answers_hostile_query_parameters_without_a_500(api, cluster, query):
    from continuum.urls import router

    for prefix, _viewset, _basename in router.registry:
        response = api.get(f"/api/v1/{prefix}/?{query}")
        assert response.status_code in (200, 400, 404, 405), (prefix, query, response.status_code)

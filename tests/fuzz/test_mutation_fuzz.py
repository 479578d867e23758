"""Mutation fuzz over every real sample file (tests/data), through the API and the management commands.

Each sample is mutated once per example (tests/fuzz/mutation.py) and
* posted to the API endpoint that imports it: the answer is never a 500 (the test client re-raises a
  server error, so an exception fails the example), a 4xx leaves every table's row count unchanged, and a
  job started by a 2xx that failed records a reason, not a traceback;
* run through the management command that reads it, in-process: it succeeds, or exits with status 2 and
  one line on stderr; any other exception (a traceback) fails the example.
Examples are derandomized (the same ones on every run) and bounded: the whole module takes well under two
minutes on the CI machine.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
from pathlib import Path

import pytest
from django.apps import apps as django_apps
from django.core.files.uploadedfile import SimpleUploadedFile
from django.core.management import get_commands, load_command_class
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from .mutation import mutated_json, mutated_text

DATA = Path(__file__).resolve().parents[1] / "data"
# CONTINUUM_FUZZ_EXAMPLES=500 explores further (random, not derandomized) when hunting for new crashes.
EXPLORE = int(os.environ.get("CONTINUUM_FUZZ_EXAMPLES", "0"))
FUZZ = settings(
    max_examples=EXPLORE or 30,
    deadline=None,
    derandomize=not EXPLORE,
    database=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow, HealthCheck.data_too_large],
)
FEW = settings(FUZZ, max_examples=EXPLORE or 15)

DAG_JSON = ["topcuoglu.dag.json", "fig31.dag.json", "heft4k-mini.dag.json", "montage-chameleon-2mass-005d-001.json"]
DAG_TEXT = ["robot.stg", "diamond.dax", "orb_graph.csv"]
CLUSTERS = ["fig-3.29.cluster.json", "heft4k-mini.cluster.json", "kairos_synthetic.cluster.json", "rtkube.cluster.json"]
ROSGRAPHS_JSON = ["autoware_reference_system.json", "irobot_sierra_nevada.json"]
ASSERTIONS = [
    "G(speed > 0 -> F[0,5000](arrived))",
    "G[0,10]({a && !b} -> X(c) && (d U[0,3] e))",
    "always (x + 2 * y <= 9 xor eventually[1:2](!z))",
]


def text(name: str) -> str:
    return (DATA / name).read_text()


def doc(name: str):
    return json.loads(text(name))


def row_counts() -> dict[str, int]:
    """Rows of every project table (apps.*)."""
    return {
        m._meta.label: m.objects.count()
        for m in django_apps.get_models()
        if m.__module__.startswith("apps.") and not m._meta.proxy
    }


def post_and_check(client, path: str, data, fmt: str = "json"):
    """POST; never a 500 (raised by the test client); a 4xx stores nothing; a started job fails cleanly.
    ``data`` may be raw JSON text (it can hold NaN or 1e400, which no Python value serializes to)."""
    before = row_counts()
    if isinstance(data, str):
        response = client.generic("POST", path, data, content_type="application/json")
    else:
        response = client.post(path, data, format=fmt)
    assert response.status_code < 500
    if 400 <= response.status_code < 500:
        assert row_counts() == before, f"{path} answered {response.status_code} but stored rows"
        assert isinstance(response.data, dict) and response.data, response.data
    if response.status_code == 202 and "state" in response.data:
        from apps.jobs.models import Job

        job = Job.objects.get(pk=response.data["id"])
        # A failure must be an input error's message, never a crash (a traceback, or main's "internal error").
        crashed = (job.result or {}).get("traceback") or job.error.startswith("internal error")
        assert not crashed, f"job {job.kind} crashed: {job.error}"
    return response


def upload(name: str, content: str | bytes) -> SimpleUploadedFile:
    return SimpleUploadedFile(name, content.encode("utf-8", "surrogatepass") if isinstance(content, str) else content)


# ---- API ---------------------------------------------------------------------------------------------------------
@pytest.mark.django_db
@FUZZ
@given(data=st.data())
def test_applications_import(api, data):
    name = data.draw(st.sampled_from(DAG_JSON + DAG_TEXT))
    body = data.draw(mutated_json(doc(name)) if name.endswith(".json") else mutated_text(text(name)))
    post_and_check(api, "/api/v1/applications/import/", {"file": upload(name, body)}, "multipart")


@pytest.mark.django_db
@FUZZ
@given(data=st.data())
def test_clusters_import(api, data):
    name = data.draw(st.sampled_from(CLUSTERS))
    original = {**doc(name), "name": f"fuzz-{data.draw(st.integers(0, 10**9))}"}
    body = data.draw(mutated_json(original))
    before = row_counts()
    response = api.generic("POST", "/api/v1/clusters/import/", body, content_type="application/json")
    assert response.status_code < 500
    if response.status_code >= 400:
        assert row_counts() == before


@pytest.mark.django_db
@FUZZ
@given(data=st.data())
def test_rosgraphs_import(api, data):
    name = data.draw(st.sampled_from([*ROSGRAPHS_JSON, "autoware_reference_system.dot"]))
    body = data.draw(mutated_json(doc(name)) if name.endswith(".json") else mutated_text(text(name)))
    post_and_check(api, "/api/v1/rosgraphs/import/", {"file": upload(name, body)}, "multipart")


@pytest.fixture
def rt_cluster(api):
    response = api.post("/api/v1/clusters/import/", {**doc("rtkube.cluster.json"), "name": "rt"}, format="json")
    assert response.status_code == 201, response.data
    return response.data["id"]


@pytest.mark.django_db
@FUZZ
@given(data=st.data())
def test_realtimes_import_yaml(api, rt_cluster, data):
    body = data.draw(mutated_text(text("listing_3_33.yaml")))
    post_and_check(api, "/api/v1/realtimes/import/", {"cluster": rt_cluster, "yaml": body})


@pytest.mark.django_db
@FEW
@given(data=st.data())
def test_rt_whatif_with_an_rtset(api, rt_cluster, data):
    containers = data.draw(mutated_json(doc("rtkube.rtset.json")))
    post_and_check(api, "/api/v1/rt-plans/whatif/", f'{{"cluster": {rt_cluster}, "containers": {containers}}}')


@pytest.mark.django_db
@FEW
@given(data=st.data())
def test_allocations_with_monitorstats(api, data):
    stats = data.draw(mutated_json(doc("verification/case_study_1.monitorstats.json")))
    post_and_check(api, "/api/v1/allocations/", f'{{"stats": {stats}, "time_limit": 1}}')


@pytest.mark.django_db
@FUZZ
@given(data=st.data())
def test_assertions(api, data):
    body = data.draw(mutated_text(data.draw(st.sampled_from(ASSERTIONS))))
    post_and_check(api, "/api/v1/assertions/", {"name": f"a{data.draw(st.integers(0, 10**9))}", "text": body})


@pytest.fixture
def topcuoglu_app(api):
    response = api.post("/api/v1/applications/import/", {"file": upload("t.json", text("topcuoglu.dag.json"))})
    assert response.status_code == 201, response.data
    return response.data["id"]


@pytest.mark.django_db
@FEW
@given(data=st.data())
def test_schedule_on_a_platform_document(api, topcuoglu_app, data):
    platform = data.draw(mutated_json(doc("topcuoglu.platform.json")))
    frames = data.draw(st.sampled_from([None, 2, 10**8, -1, "x", 1e300]))
    params = json.dumps({} if frames is None else {"frames": frames})
    body = f'{{"algorithm": "heft", "platform": {platform}, "params": {params}}}'
    post_and_check(api, f"/api/v1/applications/{topcuoglu_app}/schedule/", body)


# ---- commands -------------------------------------------------------------------------------------------------
def run_command(name: str, *argv: str) -> None:
    """Run ``manage.py name argv`` in-process: success, or exit status 2 with exactly one line on stderr."""
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        cmd = load_command_class(get_commands()[name], name)
        try:
            cmd.run_from_argv(["manage.py", name, *argv, "--skip-checks"])
        except SystemExit as exc:
            assert exc.code == 2, f"exit status {exc.code}: {err.getvalue()[-2000:]}"
            lines = err.getvalue().strip().splitlines()
            assert len(lines) == 1 and "Traceback" not in err.getvalue(), err.getvalue()[-2000:]


def write(tmp_path: Path, name: str, content: str) -> str:
    path = tmp_path / name
    path.write_text(content, encoding="utf-8", errors="surrogatepass")
    return str(path)


@pytest.fixture(scope="module")
def files(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("fuzz")


@FUZZ
@given(data=st.data())
def test_cli_schedule(files, data):
    name = data.draw(st.sampled_from(DAG_JSON + DAG_TEXT))
    body = data.draw(mutated_json(doc(name)) if name.endswith(".json") else mutated_text(text(name)))
    run_command("schedule", write(files, name, body), "--cpus", "2")


@FEW
@given(data=st.data())
def test_cli_schedule_platform(files, data):
    platform = write(files, "p.json", data.draw(mutated_json(doc("topcuoglu.platform.json"))))
    run_command("schedule", str(DATA / "topcuoglu.dag.json"), "--platform", platform)


@FUZZ
@given(data=st.data())
def test_cli_cluster_ros(files, data):
    name = data.draw(st.sampled_from([*ROSGRAPHS_JSON, "autoware_reference_system.dot"]))
    body = data.draw(mutated_json(doc(name)) if name.endswith(".json") else mutated_text(text(name)))
    run_command("cluster_ros", write(files, name, body), "--containers", "3")


@FEW
@given(data=st.data())
def test_cli_place(files, data):
    which = data.draw(st.sampled_from(["containers", "cluster"]))
    containers, cluster = "kairos_synthetic.containers.json", "kairos_synthetic.cluster.json"
    mutated = data.draw(mutated_json(doc(containers if which == "containers" else cluster)))
    path = write(files, f"{which}.json", mutated)
    run_command(
        "place",
        path if which == "containers" else str(DATA / containers),
        "--cluster",
        path if which == "cluster" else str(DATA / cluster),
    )


@FEW
@given(data=st.data())
def test_cli_heft4k(files, data):
    which = data.draw(st.sampled_from(["dag", "cluster"]))
    dag, cluster = "heft4k-mini.dag.json", "heft4k-mini.cluster.json"
    path = write(files, f"{which}.json", data.draw(mutated_json(doc(dag if which == "dag" else cluster))))
    dag_path = path if which == "dag" else str(DATA / dag)
    run_command("heft4k", dag_path, "--cluster", path if which == "cluster" else str(DATA / cluster))


@FEW
@given(data=st.data())
def test_cli_rt_schedule(files, data):
    which = data.draw(st.sampled_from(["rtset", "cluster", "yaml"]))
    if which == "yaml":
        rtset = write(files, "rt.yaml", data.draw(mutated_text(text("listing_3_33.yaml"))))
        cluster = str(DATA / "rtkube.cluster.json")
    else:
        mutated = data.draw(mutated_json(doc(f"rtkube.{which}.json")))
        path = write(files, f"{which}.json", mutated)
        rtset = path if which == "rtset" else str(DATA / "rtkube.rtset.json")
        cluster = path if which == "cluster" else str(DATA / "rtkube.cluster.json")
    run_command("rt_schedule", rtset, "--cluster", cluster)


@FUZZ
@given(data=st.data())
def test_cli_stl_check(files, data):
    if data.draw(st.booleans()):
        trace = write(files, "trace.csv", data.draw(mutated_text(text("verification/speed_trace.csv"))))
        assertion = ASSERTIONS[0]
    else:
        trace = str(DATA / "verification" / "speed_trace.csv")
        assertion = data.draw(mutated_text(data.draw(st.sampled_from(ASSERTIONS))))
    run_command("stl_check", trace, "--assertion", assertion.replace("\x00", ""))


@FEW
@given(data=st.data())
def test_cli_allocate_monitors(files, data):
    stats = write(files, "stats.json", data.draw(mutated_json(doc("verification/case_study_1.monitorstats.json"))))
    run_command("allocate_monitors", stats, "--time-limit", "1")

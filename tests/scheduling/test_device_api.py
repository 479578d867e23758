"""Device-level scheduling through the API: every import format, generated DAGs, frames, comparisons."""

import json

import pytest
from django.core.files.uploadedfile import SimpleUploadedFile

from apps.jobs.models import Job
from apps.scheduling.models import Comparison, Schedule
from apps.workloads.models import Application
from continuum.engine import TaskGraph
from continuum.engine.core.schedule import Schedule as EngineSchedule
from continuum.engine.device.board import board
from continuum.engine.device.pipeline import frame_violations, releases
from tests.conftest import DATA

pytestmark = pytest.mark.django_db

BOARD_1 = board(1).to_dict()  # 1 CPU core + 1 GPU sharing memory: the thesis' Fig. 3.1 board


def upload(api, filename, content, **extra):
    if isinstance(content, str):
        content = content.encode()
    return api.post(
        "/api/v1/applications/import/", {"file": SimpleUploadedFile(filename, content), **extra}, format="multipart"
    )


def fig31_app(api):
    response = upload(api, "fig31.dag.json", (DATA / "fig31.dag.json").read_bytes())
    assert response.status_code == 201, response.data
    return response.data


def finished_job(api, response):
    assert response.status_code == 202, response.data
    job = api.get(f"/api/v1/jobs/{response.data['id']}/").data
    assert job["state"] == "succeeded", job
    return job


# ---- import ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("filename", "extra", "fmt", "tasks"),
    [
        ("topcuoglu.dag.json", {}, "continuum", 10),
        ("montage-chameleon-2mass-005d-001.json", {}, "wfformat", 58),
        ("diamond.dax", {}, "dax", 4),
        ("robot.stg", {}, "stg", 90),
        ("orb_graph.csv", {}, "thesis_csv", None),
        ("robot.stg", {"format": "stg", "name": "robot"}, "stg", 90),
    ],
)
def test_every_format_imports(api, filename, extra, fmt, tasks):
    response = upload(api, filename, (DATA / filename).read_bytes(), **extra)
    assert response.status_code == 201, response.data
    assert response.data["source_format"] == fmt
    if tasks is not None:
        assert response.data["task_count"] == tasks
    assert response.data["task_count"] == len(response.data["dag"]["tasks"]) > 0
    if "name" in extra:
        assert response.data["name"] == extra["name"]


def test_format_from_extension_not_content(api):
    # A DAX file called .xml; its content would also sniff as XML, so call a CSV ".txt" to force sniffing.
    dax = upload(api, "workflow.xml", (DATA / "diamond.dax").read_bytes())
    assert dax.status_code == 201 and dax.data["source_format"] == "dax"
    stg = upload(api, "graph.txt", (DATA / "robot.stg").read_bytes())
    assert stg.status_code == 201 and stg.data["source_format"] == "stg"
    # The extension decides: an STG file named .csv is read as the thesis CSV and refused as such.
    wrong = upload(api, "graph.csv", (DATA / "robot.stg").read_bytes())
    assert wrong.status_code == 400 and "thesis CSV line" in str(wrong.data["file"])
    # The format by name wins over the extension (the same file read the same way as above: a re-upload,
    # stored only when asked for).
    named = upload(api, "graph.csv", (DATA / "robot.stg").read_bytes(), format="stg")
    assert named.status_code == 400 and "uploaded already" in str(named.data["file"])
    named = upload(api, "graph.csv", (DATA / "robot.stg").read_bytes(), format="stg", duplicate="allow")
    assert named.status_code == 201 and named.data["source_format"] == "stg"


def test_stg_reader_options_reach_the_reader(api):
    plain = upload(api, "robot.stg", (DATA / "robot.stg").read_bytes()).data
    assert all(set(t["cost"]) == {"cpu"} for t in plain["dag"]["tasks"])
    assert all(e.get("data", 0) == 0 for e in plain["dag"]["edges"])
    options = {"ccr": 1.0, "processors": 4, "heterogeneity": 0.5, "seed": 3}
    response = upload(api, "robot.stg", (DATA / "robot.stg").read_bytes(), options=json.dumps(options))
    assert response.status_code == 201, response.data
    dag = TaskGraph.from_dict(response.data["dag"])
    assert all(set(t.cost) == {"p0", "p1", "p2", "p3"} for t in dag.tasks.values())
    assert any(e.data > 0 for e in dag.edges)
    assert dag.meta["ccr"] == 1.0 and dag.meta["heterogeneity"] == 0.5


@pytest.mark.parametrize(
    ("filename", "content", "extra", "field", "needle"),
    [
        ("bad.stg", "3\n0 0 0\n1 2 1 0\n", {}, "file", "bad.stg: STG: line 1 announces 3 tasks"),
        ("bad.stg", "2\n0 0 0\n1 x 1 0\n2 1 1 0\n3 0 1 2\n", {}, "file", "STG line 3: non-integer field"),
        ("bad.dax", '<adag><job id="a" runtime="-1"/></adag>', {}, "file", "bad.dax: DAX"),
        ("bad.dax", "<adag><job id='a'>\n<uses</adag>", {}, "file", "malformed XML at line 2"),
        ("bad.csv", "a,1,x,-1,0\n", {}, "file", "thesis CSV line 1"),
        ("bad.json", '{"tasks": [\n  {"id": "a",, }\n]}', {}, "file", "line 2"),
        ("r.stg", (DATA / "robot.stg").read_text(), {"options": '{"ccr": 1,}'}, "options", "not JSON"),
        ("r.stg", (DATA / "robot.stg").read_text(), {"options": "[1]"}, "options", "JSON object"),
        ("r.stg", (DATA / "robot.stg").read_text(), {"options": '{"colour": 1}'}, "options", "no option 'colour'"),
        ("r.stg", (DATA / "robot.stg").read_text(), {"options": '{"ccr": "lots"}'}, "options", "'ccr' must be"),
        ("r.stg", (DATA / "robot.stg").read_text(), {"options": '{"heterogeneity": 5}'}, "file", "[0, 2]"),
        ("t.json", (DATA / "topcuoglu.dag.json").read_text(), {"options": '{"ccr": 1}'}, "options", "no options"),
    ],
)
def test_bad_files_and_options_answer_400_naming_the_culprit(api, filename, content, extra, field, needle):
    response = upload(api, filename, content, **extra)
    assert response.status_code == 400, response.data
    assert needle in str(response.data[field]), response.data
    assert Application.objects.count() == 0


# ---- generated DAGs -------------------------------------------------------------------------------------
def test_generate_thesis_dag_is_reproducible_from_its_seed(api):
    body = {"generator": "thesis", "seed": 11, "n": 40, "dag_class": "tree"}
    first = api.post("/api/v1/applications/generate/", body, format="json")
    again = api.post("/api/v1/applications/generate/", body, format="json")
    assert first.status_code == again.status_code == 201, first.data
    assert first.data["dag"] == again.data["dag"] and first.data["task_count"] == 40
    assert first.data["source_format"] == "generator:thesis"
    assert first.data["dag"]["meta"]["generator"] == "thesis" and first.data["dag"]["meta"]["shape"] == "tree"
    other = api.post("/api/v1/applications/generate/", {**body, "seed": 12}, format="json").data
    assert other["dag"] != first.data["dag"]


def test_generate_layered_dag_with_unrelated_costs(api):
    body = {"generator": "layered", "n": 200, "seed": 1, "ccr": 2, "processors": 3, "heterogeneity": 1, "name": "L"}
    response = api.post("/api/v1/applications/generate/", body, format="json")
    assert response.status_code == 201, response.data
    dag = TaskGraph.from_dict(response.data["dag"])
    assert (len(dag), response.data["name"]) == (200, "L")
    assert all(set(t.cost) == {"p0", "p1", "p2"} for t in dag.tasks.values())
    assert dag.meta["ccr"] == 2


@pytest.mark.parametrize(
    ("body", "field"),
    [
        ({"generator": "random"}, "generator"),
        ({"generator": "thesis", "n": 1}, "n"),
        ({"generator": "thesis", "dag_class": "star"}, "dag_class"),
        ({"generator": "thesis", "shape": 1.0}, "shape"),
        ({"generator": "layered", "dag_class": "tree"}, "dag_class"),
        ({"generator": "layered", "heterogeneity": 3}, "heterogeneity"),
        ({"generator": "layered", "n": 10**6}, "n"),
    ],
)
def test_bad_generator_requests_answer_400(api, body, field):
    response = api.post("/api/v1/applications/generate/", body, format="json")
    assert response.status_code == 400 and field in response.data, response.data
    assert Application.objects.count() == 0


# ---- frames -----------------------------------------------------------------------------------------------
def test_schedule_with_frames_through_the_api(api):
    app = fig31_app(api)
    response = api.post(
        f"/api/v1/applications/{app['id']}/schedule/",
        {"algorithm": "xeft", "platform": BOARD_1, "frames": 4, "period": 10},
        format="json",
    )
    job = finished_job(api, response)
    schedule = api.get(job["result_url"]).data
    engine = EngineSchedule.from_dict(schedule)
    dag = TaskGraph.from_dict(app["dag"])
    assert len(engine.assignments) == 32 and {a.frame for a in engine.assignments} == {0, 1, 2, 3}
    assert engine.violations(dag, board(1)) == []
    assert frame_violations(engine, dag, releases(4, period=10)) == []
    assert schedule["params"]["frames"] == 4 and schedule["params"]["period"] == 10
    metrics = schedule["metrics"]
    assert metrics["frames"] == 4 and len(metrics["frame_latency"]) == 4
    assert metrics["throughput"] == pytest.approx(4 / schedule["makespan"])
    assert set(metrics["idle_per_processor"]) == {"cpu0", "gpu0"} and metrics["buffers_used"] >= 1


def test_batched_frames_through_params_still_work(api):
    app = fig31_app(api)
    response = api.post(
        f"/api/v1/applications/{app['id']}/schedule/",
        {"algorithm": "gfl", "platform": BOARD_1, "params": {"frames": 2}},
        format="json",
    )
    schedule = api.get(finished_job(api, response)["result_url"]).data
    assert schedule["makespan"] == 44  # spec 01 section 7.5: G-FL batched, 2 frames


@pytest.mark.parametrize(
    ("body", "field"),
    [
        ({"frames": 0}, "frames"),
        ({"frames": 2, "fps": 30, "period": 5}, "fps"),
        ({"fps": -1}, "fps"),
        ({"batch": 0}, "batch"),
        ({"frames": 2, "params": {"frames": 3}}, "frames"),
    ],
)
def test_bad_frame_options_answer_400(api, body, field):
    app = fig31_app(api)
    response = api.post(f"/api/v1/applications/{app['id']}/schedule/", {"platform": BOARD_1, **body}, format="json")
    assert response.status_code == 400 and field in response.data, response.data
    assert not Job.objects.exists()


# ---- comparison -------------------------------------------------------------------------------------------
def test_compare_stores_every_schedule_and_the_figures(api):
    app = fig31_app(api)
    response = api.post(
        f"/api/v1/applications/{app['id']}/compare/",
        {"algorithms": ["heft", "xeft", "gfl"], "platform": BOARD_1},
        format="json",
    )
    job = finished_job(api, response)
    assert job["kind"] == "compare" and job["progress"] == 100
    comparison = api.get(job["result_url"]).data
    assert comparison["algorithms"] == ["heft", "xeft", "gfl"] and comparison["best"] == "xeft"
    figures = comparison["figures"]
    assert {n: r["makespan"] for n, r in figures.items()} == {"heft": 25, "xeft": 17, "gfl": 28}
    assert comparison["reference_makespan"] == 29  # VisionWorks, run as the reference
    assert round(100 * figures["xeft"]["speedup_vs_visionworks"], 1) == 41.4
    for key in ("slr", "overlap", "xo", "idle", "idle_per_processor"):
        assert key in figures["heft"]
    assert comparison["relative"]["xeft"]["heft"] == pytest.approx(25 / 17 - 1)
    # Each algorithm's schedule is a normal stored schedule, in the order asked.
    assert [s["algorithm"] for s in comparison["schedules"]] == ["heft", "xeft", "gfl"]
    dag = TaskGraph.from_dict(app["dag"])
    for row in comparison["schedules"]:
        stored = api.get(row["url"]).data
        assert stored["comparison"] == comparison["id"] and stored["makespan"] == figures[row["algorithm"]]["makespan"]
        assert EngineSchedule.from_dict(stored).violations(dag, board(1)) == []
    assert Schedule.objects.count() == 3


class _ProgressLog:
    """The (percent, message) lines the jobs' logs hold, read when iterated (after the job ran)."""

    def __iter__(self):
        from apps.jobs.models import JobLogLine

        rows = JobLogLine.objects.filter(progress__isnull=False).order_by("id").values_list("progress", "text")
        return iter(list(rows))


@pytest.fixture
def progress_log(monkeypatch):
    """Every (percent, message) a job reports, none dropped by the write throttle: each new message is a line
    of the job's log (apps.jobs.joblog)."""
    from apps.jobs import tasks

    monkeypatch.setattr(tasks, "PROGRESS_INTERVAL", 0)
    return _ProgressLog()


def test_schedule_job_reports_progress_over_every_frame(api, progress_log):
    app = fig31_app(api)
    body = {"algorithm": "gfl", "platform": BOARD_1, "frames": 50}
    finished_job(api, api.post(f"/api/v1/applications/{app['id']}/schedule/", body, format="json"))
    texts = [m for _, m in progress_log]
    assert "placed 400/400 tasks (50 frames of 8 tasks)" in texts
    assert sum("placed" in m for m in texts) >= 10  # about a hundred steps, not one at the end
    percents = [p for p, _ in progress_log]
    assert percents == sorted(percents) and percents[-1] == 100


def test_compare_with_frames_and_per_algorithm_progress(api, progress_log):
    messages = progress_log
    app = fig31_app(api)
    response = api.post(
        f"/api/v1/applications/{app['id']}/compare/",
        {"algorithms": ["xeft", "heft"], "platform": BOARD_1, "frames": 2},
        format="json",
    )
    job = finished_job(api, response)
    comparison = Comparison.objects.get(pk=job["result"]["comparison"])
    assert comparison.params["frames"] == 2
    assert {n: r["makespan"] for n, r in comparison.result["results"].items()} == {"xeft": 34, "heft": 50}
    assert all({a.frame for a in s.assignments.all()} == {0, 1} for s in comparison.schedules.all())
    texts = [m for _, m in messages]
    assert "xeft (1/3): placed 16/16 tasks" in texts and "heft (2/3): placed 16/16 tasks" in texts
    assert "visionworks (3/3): placed 16/16 tasks" in texts  # the reference is part of the work
    percents = [p for p, _ in messages]
    assert percents == sorted(percents)


def test_compare_is_idempotent_when_the_job_runs_again(api):
    from apps.jobs.registry import HANDLERS

    app = fig31_app(api)
    response = api.post(
        f"/api/v1/applications/{app['id']}/compare/", {"algorithms": ["heft"], "platform": BOARD_1}, format="json"
    )
    job = Job.objects.get(pk=finished_job(api, response)["id"])
    HANDLERS["compare"](job, lambda *a: None)  # a redelivered job runs from the start
    assert Comparison.objects.count() == 1 and Schedule.objects.count() == 1


@pytest.mark.parametrize(
    ("body", "field"),
    [
        ({"algorithms": []}, "algorithms"),
        ({"algorithms": ["heft", "nope"]}, "algorithms"),
        ({"algorithms": ["heft", "heft"]}, "algorithms"),
        ({"algorithms": ["heft"], "rank_mode": "median"}, "rank_mode"),
        ({"algorithms": ["heft"], "frames": 0}, "frames"),
        ({"algorithms": ["heft"], "platform": None}, "platform"),
    ],
)
def test_bad_compare_requests_answer_400(api, body, field):
    app = fig31_app(api)
    response = api.post(f"/api/v1/applications/{app['id']}/compare/", {"platform": BOARD_1, **body}, format="json")
    assert response.status_code == 400 and field in response.data, response.data
    assert not Job.objects.exists() and not Comparison.objects.exists()


def test_compare_needs_exactly_one_target_of_the_same_fleet(api, other_api, cluster):
    app = fig31_app(api)
    url = f"/api/v1/applications/{app['id']}/compare/"
    assert api.post(url, {"algorithms": ["heft"]}, format="json").status_code == 400
    both = {"algorithms": ["heft"], "platform": BOARD_1, "cluster": cluster.pk}
    assert api.post(url, both, format="json").status_code == 400
    theirs = other_api.post(
        "/api/v1/applications/import/",
        {"file": SimpleUploadedFile("f.json", (DATA / "fig31.dag.json").read_bytes())},
        format="multipart",
    ).data
    refused = other_api.post(
        f"/api/v1/applications/{theirs['id']}/compare/", {"cluster": cluster.pk, "algorithms": ["heft"]}, format="json"
    )
    assert refused.status_code == 400 and "cluster" in refused.data


def test_comparisons_are_scoped_to_the_fleet(api, other_api):
    app = fig31_app(api)
    job = finished_job(
        api,
        api.post(
            f"/api/v1/applications/{app['id']}/compare/", {"algorithms": ["heft"], "platform": BOARD_1}, format="json"
        ),
    )
    pk = job["result"]["comparison"]
    assert api.get("/api/v1/comparisons/").data["count"] == 1
    assert other_api.get("/api/v1/comparisons/").data["count"] == 0
    assert other_api.get(f"/api/v1/comparisons/{pk}/").status_code == 404
    assert other_api.delete(f"/api/v1/comparisons/{pk}/").status_code == 404
    assert other_api.post(f"/api/v1/applications/{app['id']}/compare/", {}, format="json").status_code == 404
    # Deleting a comparison deletes the schedules it made.
    assert api.delete(f"/api/v1/comparisons/{pk}/").status_code == 204
    assert not Schedule.objects.exists()


def test_schedule_round_trip_through_the_database(api):
    """Schedule.store(s, ...).to_engine() == s: one adapter each way, the fields by name (issue 11)."""
    from continuum.engine.core.schedule import Assignment as EngineAssignment
    from continuum.engine.device.algorithms import run
    from continuum.engine.heft4k.heft4k import heft4k

    application = Application.objects.get(pk=fig31_app(api)["id"])
    platform = board(1)
    frames = run("xeft", application.graph, platform, frames=3, period=10)
    nice = heft4k(application.graph, platform)
    manual = EngineSchedule("manual", [EngineAssignment("0", "cpu0", 0.5, 1.25, 2, -3, 1)], {"0": 1.0}, {"k": 1})
    for engine in (frames, nice, manual):
        back = Schedule.store(engine, application=application, platform=platform).to_engine()
        assert back.assignments == sorted(engine.assignments, key=lambda a: (a.start, a.processor, a.task))
        assert (back.algorithm, back.ranks, back.params, back.metrics, back.makespan) == (
            engine.algorithm, engine.ranks, engine.params, engine.metrics, engine.makespan
        )  # fmt: skip


def test_a_schedule_job_names_a_missing_or_foreign_row(fleet, foreign, topcuoglu_platform):
    """The job reads its rows among its own fleet's only; a missing one is a failure that names it (it was an
    unexplained internal error)."""
    from apps.jobs.services import start_job
    from apps.scheduling.kinds import SchedulingJob

    args = {"algorithm": "heft", "platform": topcuoglu_platform}
    job = start_job(SchedulingJob.SCHEDULE, fleet, {**args, "application": 987654})
    assert job.state == "failed" and job.error == "application 987654 does not exist"
    other = foreign["application"]  # another fleet's application
    job = start_job(SchedulingJob.COMPARE, fleet, {**args, "algorithms": ["heft"], "application": other.pk})
    assert job.state == "failed" and job.error == f"application {other.pk} does not exist"
    assert not Schedule.objects.filter(application=other, job=job).exists()

"""The generated client is what the API's schema generates today (the CI check), and its names are usable."""

from __future__ import annotations

import importlib.machinery
import importlib.util
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "gen-client"


def load_script():
    loader = importlib.machinery.SourceFileLoader("gen_client", str(SCRIPT))
    spec = importlib.util.spec_from_loader("gen_client", loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


def test_checked_in_client_matches_a_fresh_generation():
    """Regenerates from the current apps/ into a temporary directory and compares file by file: a serializer
    or view changed without ``scripts/gen-client`` fails here, with the diff."""
    run = subprocess.run([sys.executable, str(SCRIPT), "--check"], cwd=ROOT, capture_output=True, text=True,
                         timeout=300)  # fmt: skip
    assert run.returncode == 0, run.stdout[-4000:] + run.stderr[-2000:]
    assert run.stdout.strip() == "continuum/client/ is up to date"


def test_drift_is_reported_file_by_file(tmp_path):
    gen = load_script()
    old, new = tmp_path / "old", tmp_path / "new"
    for root in (old, new):
        (root / "models").mkdir(parents=True)
        (root / "models" / "job.py").write_text("class Job:\n    state: str\n")
    (old / "models" / "gone.py").write_text("x = 1\n")
    (new / "models" / "job.py").write_text("class Job:\n    state: str\n    progress: int\n")
    (new / "models" / "added.py").write_text("y = 2\n")
    lines = gen.compare(new, old)
    assert "only in the checked-in copy: models/gone.py" in lines
    assert "missing from the checked-in copy: models/added.py" in lines
    assert "+    progress: int" in lines
    assert gen.compare(old, old) == []


def test_request_bodies_are_json_unless_a_file_is_uploaded():
    gen = load_script()
    ref = {"schema": {"$ref": "#/components/schemas/X"}}
    schema = {"paths": {
        "/a/": {"post": {"requestBody": {"content": {"application/json": ref, "multipart/form-data": ref,
                                                     "application/x-www-form-urlencoded": ref}}}},
        "/b/import/": {"post": {"requestBody": {"content": {"multipart/form-data": ref,
                                                            "application/x-www-form-urlencoded": ref}}}},
        "/c/": {"get": {"responses": {}}, "parameters": []},
    }}  # fmt: skip
    out = gen.one_body_type(schema)["paths"]
    assert list(out["/a/"]["post"]["requestBody"]["content"]) == ["application/json"]
    assert list(out["/b/import/"]["post"]["requestBody"]["content"]) == ["multipart/form-data"]


def test_generated_names_are_by_resource():
    from continuum.client import AuthenticatedClient
    from continuum.client.api.events import events_create
    from continuum.client.api.jobs import jobs_list, jobs_retrieve
    from continuum.client.api.rt_reports import rt_reports_create
    from continuum.client.models import Job, ReportBatchRequest

    for module in (events_create, jobs_list, jobs_retrieve, rt_reports_create):
        assert callable(module.sync_detailed) and callable(module.asyncio_detailed)
    assert {"state", "progress", "message", "result_url", "error"} <= set(Job.__annotations__)
    assert ReportBatchRequest.from_dict({"reports": [{"node": "n"}]}).to_dict() == {"reports": [{"node": "n"}]}
    client = AuthenticatedClient(base_url="http://127.0.0.1:1", token="t", prefix="Token")
    assert client.get_httpx_client().headers["Authorization"] == "Token t"


def test_the_client_and_fleet_layer_import_no_django():
    code = (
        "import sys, continuum.client, continuum.fleet.cli, continuum.fleet.rosbag; "
        "print(sorted(m for m in sys.modules if m.split('.')[0] in ('django', 'rest_framework', 'apps')))"
    )
    run = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120,
                         env={"PATH": "/usr/bin:/bin", "PYTHONPATH": str(ROOT)})  # fmt: skip
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "[]"

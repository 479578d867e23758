"""STG files whose first line counts the two dummy tasks (as several published copies do).

Kasahara's format excludes the dummies from the count; a copy that includes them is accepted when the lines
that follow make the reading unambiguous (exactly that many task lines, ids 0..n-1, zero-cost entry and exit)
and says so in a warning that the CLI prints on stderr and the API returns as ``warnings``.
"""

import re
import subprocess
import sys
from pathlib import Path

import pytest
from django.core.files.uploadedfile import SimpleUploadedFile

from continuum.engine.core.errors import InputError
from continuum.engine.formats import load_dag

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "data"


def counting_dummies(name: str) -> str:
    """The sample with its first line raised by 2, as the published copies write it."""
    lines = (DATA / name).read_text().splitlines()
    return "\n".join([f"{int(lines[0]) + 2:>11}", *lines[1:]]) + "\n"


@pytest.mark.parametrize("name", ["sample00.stg", "robot.stg"])
def test_a_count_including_the_dummies_reads_the_same_graph(name):
    standard = load_dag((DATA / name).read_text(), "stg")
    variant = load_dag(counting_dummies(name), "stg")
    assert variant.to_dict()["tasks"] == standard.to_dict()["tasks"]
    assert variant.to_dict()["edges"] == standard.to_dict()["edges"]
    assert "warnings" not in standard.meta
    n = len(standard)
    assert variant.meta["warnings"] == [
        f"STG line 1: {n} counts the two dummy tasks (the format excludes them); "
        f"read as {n - 2} tasks plus the dummies 0 and {n - 1}"
    ]
    # reader options still apply
    plain = load_dag(counting_dummies(name), "stg", options={"dummies": False})
    assert len(plain) == n - 2 and "0" not in plain.tasks and str(n - 1) not in plain.tasks


@pytest.mark.parametrize(
    ("content", "needle"),
    [
        # three lines after "3" whose ends are not zero-cost dummies: neither reading fits
        ("3\n0 0 0\n1 2 1 0\n2 1 1 1\n", "announces 3 tasks (+2 dummies) but 3 follow; nor does it count the dummies"),
        ("3\n0 2 0\n1 2 1 0\n2 0 1 1\n", "tasks 0 and 2 are not of cost 0"),
        # ids beyond n-1 under the dummies-counting reading
        ("3\n0 0 0\n1 2 1 0\n4 0 1 1\n", "task id 4 outside 0..2 (3 task lines after a count of 3"),
        # neither n nor n+2 lines
        ("3\n0 0 0\n1 2 1 0\n2 2 1 0\n3 0 2 1 2\n", "announces 3 tasks (+2 dummies) but 4 follow"),
        ("2\n0 0 0\n1 0 1 0\n", "announces 2 tasks (+2 dummies) but 2 follow"),  # no real task: not accepted
    ],
)
def test_ambiguous_counts_are_still_rejected(content, needle):
    with pytest.raises(InputError, match=re.escape(needle)):
        load_dag(content, "stg")


def test_the_schedule_command_prints_the_warning_on_stderr(tmp_path):
    path = tmp_path / "sample.stg"
    path.write_text(counting_dummies("sample00.stg"))
    out = subprocess.run(
        [sys.executable, "manage.py", "schedule", str(path), "--cpus", "2", "--json"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 0, out.stderr
    assert out.stderr.strip() == (
        "warning: STG line 1: 10 counts the two dummy tasks (the format excludes them); "
        "read as 8 tasks plus the dummies 0 and 9"
    )
    assert '"makespan"' in out.stdout


@pytest.mark.django_db
def test_the_api_returns_the_warning_and_stores_a_clean_dag(api):
    response = api.post(
        "/api/v1/applications/import/",
        {"file": SimpleUploadedFile("s.stg", counting_dummies("sample00.stg").encode())},
        format="multipart",
    )
    assert response.status_code == 201, response.data
    assert response.data["task_count"] == 10
    assert len(response.data["warnings"]) == 1 and "counts the two dummy tasks" in response.data["warnings"][0]
    assert "warnings" not in (response.data["dag"].get("meta") or {})
    stored = api.get(f"/api/v1/applications/{response.data['id']}/").data
    assert "warnings" not in stored and "warnings" not in (stored["dag"].get("meta") or {})
    standard = api.post(
        "/api/v1/applications/import/",
        {"file": SimpleUploadedFile("s.stg", (DATA / "sample00.stg").read_bytes())},
        format="multipart",
    )
    assert standard.status_code == 201 and standard.data["warnings"] == []

"""``python manage.py schedule`` as the contracts describe it, run as a real process."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "data"


def manage(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "manage.py", *args], cwd=ROOT, capture_output=True, text=True, timeout=120)


def test_topcuoglu_json_prints_makespan_80():
    out = manage(
        "schedule",
        str(DATA / "topcuoglu.dag.json"),
        "--platform",
        str(DATA / "topcuoglu.platform.json"),
        "--algorithm",
        "heft",
        "--json",
    )
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)
    assert doc["format"] == "continuum.schedule/v1" and doc["makespan"] == 80.0
    assert len(doc["assignments"]) == 10 and doc["ranks"]["0"] == 108.0


def test_wfformat_on_cpus_human_summary():
    out = manage("schedule", str(DATA / "montage-chameleon-2mass-005d-001.json"), "--cpus", "4")
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith("heft: makespan ")
    assert out.stdout.count(" on cpu") == 58


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["missing.json"], "no such file"),
        ([str(DATA / "README.md")], "malformed JSON at line 1"),
        ([str(DATA / "topcuoglu.dag.json"), "--algorithm", "nope"], "unknown algorithm 'nope'"),
        ([str(DATA / "topcuoglu.dag.json"), "--cpus", "0"], "at least one processor"),
        (
            [str(DATA / "topcuoglu.dag.json"), "--platform", str(DATA / "topcuoglu.platform.json"), "--cpus", "2"],
            "not both",
        ),
    ],
)
def test_bad_input_exits_2_with_one_line(args, needle):
    out = manage("schedule", *args)
    assert out.returncode == 2
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0], out.stderr
    assert "Traceback" not in out.stderr


def test_task_no_processor_can_run(tmp_path):
    dag = tmp_path / "gpu.json"
    dag.write_text(json.dumps({"tasks": [{"id": "k", "cost": {"gpu": 1}}], "edges": []}))
    out = manage("schedule", str(dag), "--cpus", "2")
    assert out.returncode == 2 and "'k' cannot run" in out.stderr


@pytest.mark.parametrize("algorithm", ["gfl", "xeft"])
def test_progress_on_stderr_for_many_frames(algorithm):
    out = manage(
        "schedule", str(DATA / "orb_graph.csv"), "--cpus", "4", "--gpus", "1", "--algorithm", algorithm,
        "--frames", "10", "--progress", "--json",
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)  # stdout stays pure JSON
    lines = out.stderr.splitlines()
    total = len(doc["assignments"])
    assert lines[-1] == f"{algorithm}, tasks placed: {total}/{total} (100%)"
    assert 5 <= len(lines) <= 12  # a line per tenth of the work, not one per task


def test_no_progress_without_a_terminal_unless_asked():
    out = manage("schedule", str(DATA / "topcuoglu.dag.json"), "--platform", str(DATA / "topcuoglu.platform.json"))
    assert out.returncode == 0 and out.stderr == ""

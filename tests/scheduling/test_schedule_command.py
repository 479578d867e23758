"""``manage.py schedule`` with the new formats, algorithms and --frames/--fps/--batch (no database needed)."""

import io
import json
from pathlib import Path

import pytest
from django.core.management import call_command
from django.core.management.base import CommandError

DATA = Path(__file__).resolve().parents[1] / "data"


def schedule(*args: str) -> str:
    out = io.StringIO()
    call_command("schedule", *args, stdout=out, skip_checks=True)
    return out.getvalue()


def schedule_json(*args: str) -> dict:
    return json.loads(schedule(*args, "--json"))


@pytest.mark.parametrize("algorithm", ["heft", "xeft", "gfl", "gfl_c", "visionworks", "visionworks_overlap"])
def test_every_algorithm_runs_frames(algorithm):
    doc = schedule_json(
        str(DATA / "fig31.dag.json"), "--cpus", "2", "--gpus", "1", "--shared-memory", "--algorithm", algorithm,
        "--frames", "3", "--fps", "30", "--batch", "2",
    )  # fmt: skip
    assert doc["format"] == "continuum.schedule/v1" and doc["algorithm"] == algorithm
    assert sorted({a["frame"] for a in doc["assignments"]}) == [0, 1, 2] and len(doc["assignments"]) == 24
    assert doc["metrics"]["releases"] == [0.0, 0.0, pytest.approx(2000 / 30)]  # batches of 2 at 30 FPS
    assert doc["params"]["batch"] == 2 and 1 <= doc["metrics"]["buffers_used"] <= 3
    assert set(doc["metrics"]["idle_per_processor"]) == {"cpu0", "cpu1", "gpu0"}
    assert doc["metrics"]["mean_latency"] > 0 and doc["metrics"]["throughput_per_s"] > 0


def test_gfl_streaming_at_45_fps():
    doc = schedule_json(str(DATA / "fig31.dag.json"), "--platform", str(DATA / "board-1core.platform.json"),
                        "--algorithm", "gfl", "--frames", "2", "--period", "22")  # fmt: skip
    assert doc["makespan"] == 56.0


def test_orb_graph_by_extension_with_xeft():
    doc = schedule_json(
        str(DATA / "orb_graph.csv"), "--cpus", "4", "--gpus", "1", "--shared-memory", "--algorithm", "xeft"
    )
    assert len(doc["assignments"]) == 161 and doc["metrics"]["xo"] > 0
    assert doc["params"]["rank_mode"] == "max"


def test_stg_and_dax_human_summary():
    out = schedule(str(DATA / "robot.stg"), "--cpus", "3", "--reader-option", "ccr=0.5")
    assert out.startswith("heft: makespan ") and out.count(" on cpu") == 90
    out = schedule(str(DATA / "diamond.dax"), "--cpus", "2", "--algorithm", "gfl_c")
    assert out.startswith("gfl_c: makespan 125500,")


def test_params_and_cpu_speeds():
    doc = schedule_json(str(DATA / "fig31.dag.json"), "--cpus", "2", "--gpus", "1", "--cpu-speed", "2,1",
                        "--algorithm", "heft", "--param", "insertion=false", "--rank-mode", "max")  # fmt: skip
    assert doc["params"] == {"rank_mode": "max", "insertion": False}
    on_fast = [a for a in doc["assignments"] if a["processor"] == "cpu0"]
    assert on_fast and all(a["finish"] - a["start"] in (0.5, 2.0, 3.0) for a in on_fast)


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["--frames", "0"], "frames must be a positive integer"),
        (["--fps", "-3", "--frames", "2"], "fps must be a positive number"),
        (["--fps", "30", "--period", "2"], "either fps or period"),
        (["--param", "bogus=1"], "unexpected keyword argument 'bogus'"),
        (["--param", "oops"], "--param expects KEY=VALUE"),
        (["--reader-option", "ccr=1"], "takes no options"),
        (["--cpu-speed", "a,b", "--cpus", "2"], "--cpu-speed expects numbers"),
        (["--cpu-speed", "1,1,1", "--cpus", "2"], "cpu_speed has 3 values for 2 cores"),
        (["--algorithm", "gfl", "--param", "mapping=random"], "unknown G-FL mapping 'random'"),
        (["--algorithm", "xeft", "--rank-mode", "median"], "unknown rank mode 'median'"),
    ],
)
def test_bad_input_is_a_clean_error(args, needle):
    with pytest.raises(CommandError) as info:
        schedule(str(DATA / "fig31.dag.json"), "--gpus", "1", *args)
    assert info.value.returncode == 2 and needle in str(info.value)


def test_malformed_stg_names_the_line(tmp_path):
    bad = tmp_path / "bad.stg"
    bad.write_text("2\n0 0 0\n1 4 1 0\n2 x 1 1\n3 0 1 2\n")
    with pytest.raises(CommandError, match="STG line 4: non-integer"):
        schedule(str(bad), "--cpus", "2")

"""Several schedulers side by side (Table 4.1 and 4.3 conventions)."""

import json
from pathlib import Path

import pytest

from continuum.engine import InputError, TaskGraph
from continuum.engine.device.board import board
from continuum.engine.device.compare import compare

DATA = Path(__file__).resolve().parents[2] / "data"


@pytest.fixture
def fig31() -> TaskGraph:
    return TaskGraph.from_dict(json.loads((DATA / "fig31.dag.json").read_text()))


def test_fig31_side_by_side(fig31):
    out = compare(fig31, board(1))
    json.dumps(out)
    makespans = {name: row["makespan"] for name, row in out["results"].items()}
    assert makespans == {"visionworks": 29, "gfl": 28, "gfl_c": 25, "heft": 25, "xeft": 17}
    assert out["best"] == "xeft" and out["reference_makespan"] == 29
    assert round(100 * out["results"]["heft"]["speedup_vs_visionworks"], 1) == 13.8
    assert round(100 * out["results"]["xeft"]["speedup_vs_visionworks"], 1) == 41.4
    assert out["results"]["xeft"]["xo"] == 10 and out["results"]["xeft"]["xo_efficiency"] == 1.0
    assert out["results"]["heft"]["idle"] == pytest.approx(0.26)
    assert round(out["results"]["xeft"]["slr"], 2) == 1.55
    # Table 4.3: row XEFT against column HEFT is 25/17 - 1
    assert out["relative"]["xeft"]["heft"] == pytest.approx(25 / 17 - 1)
    assert out["relative"]["heft"]["xeft"] == pytest.approx(17 / 25 - 1)


def test_pipelined_comparison_without_reference_in_the_list(fig31):
    out = compare(fig31, board(1), ["heft", "xeft", "gfl"], frames=2)
    assert list(out["results"]) == ["heft", "xeft", "gfl"]
    assert out["reference_makespan"] == 58  # VW runs anyway: two frames one after the other
    assert {n: r["makespan"] for n, r in out["results"].items()} == {"heft": 50, "xeft": 34, "gfl": 44}
    assert out["results"]["gfl"]["buffers_used"] == 2
    assert out["results"]["xeft"]["pipeline_gain"] == pytest.approx((2 * 17 - 34) / 34)


def test_unknown_algorithm(fig31):
    with pytest.raises(InputError, match="unknown algorithm 'cpop'"):
        compare(fig31, board(1), ["heft", "cpop"])


def test_progress_per_algorithm_and_every_schedule_handed_over(fig31):
    seen = []
    schedules = {}
    out = compare(
        fig31,
        board(1),
        ["heft", "xeft"],
        frames=3,
        progress=lambda *args: seen.append(args),
        on_schedule=schedules.__setitem__,
    )
    # The reference runs last, after the listed algorithms, and reports too.
    assert [s[:3] for s in seen if s[3:] == (0, 0)] == [("heft", 0, 3), ("xeft", 1, 3), ("visionworks", 2, 3)]
    for name in ("heft", "xeft", "visionworks"):
        done = [(d, t) for n, _, _, d, t in seen if n == name and t]
        assert done and done[-1] == (24, 24), name  # 8 tasks x 3 frames
        assert [d for d, _ in done] == sorted(d for d, _ in done)
    assert set(schedules) == {"heft", "xeft", "visionworks"}
    assert {n: s.makespan for n, s in schedules.items() if n in out["results"]} == {
        n: r["makespan"] for n, r in out["results"].items()
    }
    assert all({a.frame for a in s.assignments} == {0, 1, 2} for s in schedules.values())


@pytest.mark.parametrize("algorithm", ["gfl", "gfl_c", "visionworks", "visionworks_overlap", "heft", "xeft"])
def test_every_native_multi_frame_scheduler_reports_progress(fig31, algorithm):
    from continuum.engine.device.algorithms import run

    calls = []
    schedule = run(algorithm, fig31, board(2), progress=lambda d, t: calls.append((d, t)), frames=5)
    assert calls and calls[-1] == (40, 40) and len(schedule.assignments) == 40
    single = []
    run(algorithm, fig31, board(2), progress=lambda d, t: single.append((d, t)))
    assert single[-1] == (8, 8)

"""The thesis' running example (Fig. 3.1-3.5) with the numbers of spec 01 section 7 and acceptance 1-8."""

import json
from pathlib import Path

import pytest

from continuum.engine import TaskGraph
from continuum.engine.device import overlap as ov
from continuum.engine.device.board import board
from continuum.engine.device.gfl import gfl
from continuum.engine.device.heft import compile_problem, compiled_ranks, heft, priority_list, upward_ranks
from continuum.engine.device.pipeline import frame_violations, pipeline, releases
from continuum.engine.device.visionworks import visionworks
from continuum.engine.device.xeft import build_cluster, xeft

DATA = Path(__file__).resolve().parents[2] / "data"


@pytest.fixture
def fig31() -> TaskGraph:
    return TaskGraph.from_dict(json.loads((DATA / "fig31.dag.json").read_text()))


@pytest.fixture
def fig35() -> TaskGraph:
    """Fig. 3.5: every node but 0 gets a GPU time one unit below its CPU time (node 1: CPU 11, spec 7.6)."""
    times = {0: (1, None), 1: (11, 10), 2: (4, 3), 3: (4, 3), 4: (6, 5), 5: (4, 3), 6: (4, 3), 7: (6, 5)}
    edges = [(0, 1), (0, 2), (0, 5), (2, 3), (3, 4), (5, 6), (6, 7)]
    return TaskGraph.from_dict(
        {
            "tasks": [
                {"id": str(k), "cost": {c: v for c, v in zip(("cpu", "gpu"), cg, strict=True) if v is not None}}
                for k, cg in times.items()
            ],
            "edges": [{"src": str(a), "dst": str(b)} for a, b in edges],
        }
    )


def placements(schedule):
    return {a.task: (a.processor, a.start, a.finish) for a in schedule.assignments}


def test_ranks_and_heft_list(fig31):
    assert upward_ranks(fig31, board(1), "max", comm_mode="impl") == {
        "0": 15,
        "1": 10,
        "2": 14,
        "3": 10,
        "4": 6,
        "5": 14,
        "6": 10,
        "7": 6,
    }
    mean = upward_ranks(fig31, board(1), "mean", comm_mode="impl")
    assert [mean[str(i)] for i in range(8)] == [12.5, 10, 11.5, 8.5, 6, 11.5, 8.5, 6]
    prob = compile_problem(fig31, board(1))
    for mode in ("max", "mean"):
        order = priority_list(prob, compiled_ranks(prob, mode, "impl"))
        assert [prob.ids[t] for t in order] == ["0", "2", "5", "1", "3", "6", "4", "7"]


def test_build_cluster_steps(fig31):
    prob = compile_problem(fig31, board(1))
    heft_list = priority_list(prob, compiled_ranks(prob, "max", "impl"))
    trace: list[dict] = []
    order = build_cluster(prob, heft_list, trace=trace)
    assert order == [0, 2, 5, 3, 6, 1, 4, 7]
    (step,) = trace
    assert step["candidates"] == [1, 4, 7]
    assert (step["total_cpu"], step["total_gpu"]) == (12, 10)
    assert step["cluster"] == [1, 4, 7]
    assert step["steps"] == [
        [0, 2, 5, 1, 3, 4, 6, 7],  # (b) 4 moves up past 6
        [0, 2, 5, 3, 1, 4, 6, 7],  # (c) the block moves down past 3
        [0, 2, 5, 3, 6, 1, 4, 7],  # (d) ... and past 6 to join 7
    ]


def test_heft_schedule(fig31):
    platform = board(1)
    s = heft(fig31, platform, rank_mode="max")
    assert placements(s) == {
        "0": ("cpu0", 0, 1),
        "2": ("gpu0", 1, 3),
        "5": ("cpu0", 1, 5),
        "1": ("gpu0", 3, 13),
        "3": ("cpu0", 5, 9),
        "6": ("cpu0", 9, 13),
        "4": ("cpu0", 13, 19),
        "7": ("cpu0", 19, 25),
    }
    m = ov.schedule_metrics(s, fig31, platform)
    assert m["makespan"] == 25 and m["overlap"] == 12 and m["xo"] == 0
    assert max(a.finish for a in s.assignments if a.processor == "gpu0") == 13  # GPU idle over [13, 25]
    assert m["idle"] == pytest.approx(0.26)
    assert m["slr"] == pytest.approx(25 / 11)


def test_xeft_schedule(fig31):
    platform = board(1)
    s = xeft(fig31, platform)
    assert s.metrics["priority_list"] == ["0", "2", "5", "3", "6", "1", "4", "7"]
    assert placements(s) == {
        "0": ("cpu0", 0, 1),
        "2": ("gpu0", 1, 3),
        "5": ("cpu0", 1, 5),
        "3": ("gpu0", 3, 4),
        "6": ("gpu0", 5, 6),
        "1": ("gpu0", 6, 16),
        "4": ("cpu0", 5, 11),
        "7": ("cpu0", 11, 17),
    }
    m = ov.schedule_metrics(s, fig31, platform)
    assert m["makespan"] == 17 and m["overlap"] == 14 and m["xo"] == 10
    assert m["max_xo"] == 10 and m["xo_efficiency"] == 1.0
    assert round(m["idle"], 3) == 0.088 and round(m["slr"], 2) == 1.55


def test_visionworks(fig31):
    serial = visionworks(fig31, board(1))
    assert serial.makespan == 29
    on_gpu = {a.task for a in serial.assignments if a.processor == "gpu0"}
    assert on_gpu == {"1", "2", "3", "5", "6"}
    assert [a.task for a in serial.assignments] == ["0", "1", "2", "5", "3", "6", "4", "7"]  # breadth first
    assert visionworks(fig31, board(1), overlap=True).makespan == 28


def test_table41_speedup_convention(fig31):
    vw, h, x = 29, heft(fig31, board(1), rank_mode="max").makespan, xeft(fig31, board(1)).makespan
    assert round(100 * ov.reduction(vw, h), 1) == 13.8
    assert round(100 * ov.reduction(vw, x), 1) == 41.4
    assert round(100 * ov.reduction(h, x), 1) == 32.0


def test_more_cores(fig31):
    two = board(2)
    h2, x2 = heft(fig31, two, rank_mode="max"), xeft(fig31, two)
    assert h2.makespan == 15 and ov.exclusive_overlap(h2, fig31, two) == 10
    assert x2.metrics["priority_list"] == ["0", "2", "5", "3", "6", "1", "4", "7"]
    assert x2.makespan == 16  # the small case where XEFT loses
    three = board(3)
    prob = compile_problem(fig31, three)
    trace: list[dict] = []
    order = build_cluster(prob, priority_list(prob, compiled_ranks(prob, "max", "impl")), trace=trace)
    assert [step["cluster"] for step in trace] == [[4, 7]]
    assert order == [0, 2, 5, 1, 3, 6, 4, 7]
    assert xeft(fig31, three).makespan == heft(fig31, three, rank_mode="max").makespan == 15


@pytest.mark.parametrize(
    ("algorithm", "single", "streaming", "batched", "buffers"),
    [
        ("gfl", 28, 56, 44, 2),
        ("gfl_c", 25, 50, 50, 1),
        ("heft", 25, 50, 50, 1),
        ("xeft", 17, 39, 34, 1),
    ],
)
def test_pipelines(fig31, algorithm, single, streaming, batched, buffers):
    platform = board(1)
    kw = {"rank_mode": "max", "comm_mode": "impl"} if algorithm == "heft" else {}
    one = pipeline(algorithm, fig31, platform, frames=1, **kw)
    assert one.makespan == single and one.metrics["buffers_used"] == 1
    stream = pipeline(algorithm, fig31, platform, frames=2, period=22, **kw)
    batch = pipeline(algorithm, fig31, platform, frames=2, **kw)
    assert stream.makespan == streaming
    assert batch.makespan == batched
    assert batch.metrics["buffers_used"] == buffers
    for s, rel in ((stream, releases(2, period=22)), (batch, releases(2))):
        assert s.violations(fig31, platform) == []
        assert frame_violations(s, fig31, rel) == []
    assert min(a.start for a in stream.assignments if a.frame == 1) >= 22  # Eq. 3.7
    if algorithm == "xeft":
        assert min(a.start for a in stream.assignments if a.frame == 1) == 22


def test_gfl_batched_details(fig31):
    platform = board(1)
    two = pipeline("gfl", fig31, platform, frames=2)
    where = {(a.task, a.frame): (a.start, a.finish) for a in two.assignments}
    assert where[("0", 1)] == (1, 2)  # 0' runs at [1, 2]
    three, five = pipeline("gfl", fig31, platform, frames=3), pipeline("gfl", fig31, platform, frames=5)
    assert (three.makespan, three.metrics["buffers_used"]) == (60, 3)
    assert (five.makespan, five.metrics["buffers_used"]) == (92, 5)
    assert two.metrics["pipeline_gain"] == pytest.approx((2 * 28 - 44) / (2 * 28))


def test_fps_gives_the_period(fig31):
    s = pipeline("xeft", fig31, board(1), frames=2, fps=1000 / 22)
    assert s.makespan == pytest.approx(39)
    assert releases(3, fps=30)[1] == pytest.approx(33.333, abs=1e-3)


@pytest.mark.parametrize("tie", ["id", "rank"])
def test_gfl_tie_rules_agree_here(fig31, tie):
    platform = board(1)
    assert gfl(fig31, platform, tie=tie).makespan == 28
    assert gfl(fig31, platform, mapping="heft", tie=tie).makespan == 25
    assert pipeline("gfl", fig31, platform, frames=2, tie=tie).makespan == 44


def test_fig35(fig35):
    platform = board(1)
    assert pipeline("gfl", fig35, platform, frames=1).makespan == 33
    assert pipeline("gfl", fig35, platform, frames=2).makespan == 65
    h1 = pipeline("heft", fig35, platform, frames=1, rank_mode="max")
    h2 = pipeline("heft", fig35, platform, frames=2, rank_mode="max")
    assert (h1.makespan, h2.makespan) == (19, 38)
    assert pipeline("xeft", fig35, platform, frames=2).makespan == 38


def test_per_core_speed_for_denver_cores(fig31):
    # Two cores, the first twice as fast (a Denver core next to an A57): costs halve there.
    platform = board(2, cpu_speed=[2.0, 1.0])
    s = heft(fig31, platform, rank_mode="max")
    assert s.violations(fig31, platform) == []
    fast = [a for a in s.assignments if a.processor == "cpu0"]
    assert fast and all(a.finish - a.start == fig31.tasks[a.task].cost["cpu"] / 2 for a in fast)


def test_board_transfers_only_between_cpu_and_gpu():
    dag = TaskGraph.from_dict(
        {
            "tasks": [
                {"id": "a", "cost": {"cpu": 1}},
                {"id": "b", "cost": {"cpu": 1}},
                {"id": "c", "cost": {"gpu": 1}},
            ],
            "edges": [{"src": "a", "dst": "b", "data": 5}, {"src": "a", "dst": "c", "data": 3}],
        }
    )
    platform = board(2)
    assert platform.comm_time("cpu0", "cpu1", 5) == 0
    assert platform.comm_time("cpu1", "gpu0", 3) == 3
    s = heft(dag, platform)
    where = placements(s)
    assert where["c"][1] == where["a"][2] + 3


def test_idle_counts_every_cpu_of_a_multi_core_processor():
    """A 2-CPU node running two tasks side by side is not idle (busy time may exceed the makespan)."""
    from continuum.engine.core.platform import Platform, Processor
    from continuum.engine.core.schedule import Assignment, Schedule

    platform = Platform([Processor("node0", cores=2), Processor("gpu0", "gpu")])
    schedule = Schedule(
        "manual",
        [Assignment("a", "node0", 0, 4, 0), Assignment("b", "node0", 0, 2, 0), Assignment("c", "gpu0", 1, 4, 0)],
    )
    # node0: 2 CPUs x 4 - (4 + 2) busy = 2 idle; gpu0: 4 - 3 = 1; idle = 1 - 9 / (3 CPUs x 4).
    assert ov.idle_per_processor(schedule, platform) == {"node0": 2.0, "gpu0": 1.0}
    assert ov.idle_fraction(schedule, platform) == pytest.approx(0.25)

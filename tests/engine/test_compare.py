"""Several schedulers side by side (Table 4.1 and 4.3 conventions)."""

import json
from pathlib import Path

import pytest

from continuum.engine import InputError, TaskGraph
from continuum.engine.board import board
from continuum.engine.compare import compare

DATA = Path(__file__).resolve().parent.parent / "data"


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

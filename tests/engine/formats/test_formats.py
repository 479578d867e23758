"""The DAX, STG and thesis-simulator CSV importers: real files, options, sniffing and precise errors."""

from pathlib import Path

import pytest

from continuum.engine import InputError, Platform
from continuum.engine.device.board import board
from continuum.engine.device.heft import heft
from continuum.engine.device.overlap import cp_min
from continuum.engine.formats import format_for_path, load_dag, sniff_text

DATA = Path(__file__).resolve().parents[2] / "data"


def text(name: str) -> str:
    return (DATA / name).read_text()


# ---- Pegasus DAX ----------------------------------------------------------------------------------------
def test_dax_diamond():
    dag = load_dag(text("diamond.dax"), "dax")
    assert dag.name == "diamond" and dag.meta["source_format"] == "dax"
    assert {t: c.cost["cpu"] for t, c in dag.tasks.items()} == {
        "ID0000001": 60000.0,  # pegasus runtime profile, s -> ms
        "ID0000002": 45500.0,
        "ID0000003": 30000.0,
        "ID0000004": 20000.0,
    }
    data = {(e.src, e.dst): e.data for e in dag.edges}
    # f.b1 (2 MB) and f.b2 (3 MB) from preprocess; f.c1 (0.5 MB), f.c2 (0.25 MB) into analyze; in Mbit
    assert data == {
        ("ID0000001", "ID0000002"): 16.0,
        ("ID0000001", "ID0000003"): 24.0,
        ("ID0000002", "ID0000004"): 4.0,
        ("ID0000003", "ID0000004"): 2.0,
    }
    assert dag.tasks["ID0000004"].name == "analyze"


DAX_HEAD = '<adag xmlns="http://pegasus.isi.edu/schema/DAX" version="3.6" name="x">'


@pytest.mark.parametrize(
    ("body", "needle"),
    [
        ('<adag><job id="a" runtime="1">', "malformed XML at line 1"),
        ("<workflow/>", "root element is <workflow>"),
        (DAX_HEAD + "</adag>", "no <job>"),
        (DAX_HEAD + '<job runtime="1"/></adag>', "<job> number 1 has no id"),
        (DAX_HEAD + '<job id="a"/></adag>', "job 'a' has no runtime"),
        (DAX_HEAD + '<job id="a" runtime="fast"/></adag>', "job 'a' runtime is not a number"),
        (DAX_HEAD + '<job id="a" runtime="1"/><job id="a" runtime="2"/></adag>', "duplicate job id 'a'"),
        (
            DAX_HEAD + '<job id="a" runtime="1"><uses name="f" link="input" size="-3"/></job></adag>',
            "file 'f' size must be a non-negative",
        ),
        (DAX_HEAD + '<job id="a" runtime="1"><uses name="f" link="sideways"/></job></adag>', "unknown link"),
        (DAX_HEAD + '<job id="a" runtime="1"/><child ref="b"><parent ref="a"/></child></adag>', "<child ref='b'>"),
        (
            DAX_HEAD + '<job id="a" runtime="1"/><child ref="a"><parent ref="z"/></child></adag>',
            "<parent ref='z'> of child 'a'",
        ),
    ],
)
def test_dax_errors_name_the_element(body, needle):
    with pytest.raises(InputError, match=None) as info:
        load_dag(body, "dax")
    assert needle in str(info.value)


def test_dax_2_file_attribute_and_cycle():
    doc = (
        '<adag name="old" version="2.1"><job id="a" runtime="2"><uses file="f" link="output" size="1000000"/></job>'
        '<job id="b" runtime="3"><uses file="f" link="input" size="1000000"/></job>'
        '<child ref="b"><parent ref="a"/></child><child ref="a"><parent ref="b"/></child></adag>'
    )
    with pytest.raises(InputError, match="cycle"):
        load_dag(doc)


# ---- Kasahara STG ---------------------------------------------------------------------------------------
def test_stg_sample_and_robot():
    sample = load_dag(text("sample00.stg"))
    assert len(sample) == 10 and sample.tasks["0"].cost == {"cpu": 0.0} and sample.tasks["6"].cost == {"cpu": 7.0}
    assert {(e.src, e.dst) for e in sample.edges} >= {("3", "5"), ("4", "5"), ("7", "9"), ("8", "9")}
    platform = Platform.homogeneous(2, bandwidth=None)
    s = heft(sample, platform)
    assert s.violations(sample, platform) == [] and s.makespan >= 16  # the optimum is 16
    robot = load_dag(text("robot.stg"), "stg")
    assert len(robot) == 90 and len(robot.edges) == 135  # 88 tasks + 2 dummies; 131 + 4 dummy edges
    assert cp_min(robot, platform) == 569  # the trailer's "CP Length"


def test_stg_options():
    plain = load_dag(text("sample00.stg"), "stg", options={"dummies": False})
    assert len(plain) == 8 and "0" not in plain.tasks
    ccr = load_dag(text("sample00.stg"), "stg", options={"ccr": 2.0, "seed": 3})
    mean_cost = sum(t.cost["cpu"] for t in ccr.tasks.values()) / len(ccr)
    datas = [e.data for e in ccr.edges]
    assert all(0 <= d <= 4 * mean_cost for d in datas) and any(d > 0 for d in datas)
    assert ccr.to_dict() == load_dag(text("sample00.stg"), "stg", options={"ccr": 2.0, "seed": 3}).to_dict()
    het = load_dag(text("sample00.stg"), "stg", options={"processors": 3, "heterogeneity": 1.0})
    six = het.tasks["6"].cost
    assert set(six) == {"p0", "p1", "p2"} and all(3.5 <= c <= 10.5 for c in six.values())
    assert len(set(six.values())) == 3


@pytest.mark.parametrize(
    ("content", "needle"),
    [
        ("", "empty"),
        ("x\n", "line 1: expected the number of tasks"),
        ("2\n0 0 0\n1 3 1 0\n", "announces 2 tasks (+2 dummies) but 2 follow"),
        ("1\n0 0 0\n1 a 1 0\n2 0 1 1\n", "STG line 3: non-integer"),
        ("1\n0 0 0\n1 3 2 0\n2 0 1 1\n", "STG line 3: task 1 announces 2 predecessors but lists 1"),
        ("1\n0 0 0\n5 3 1 0\n2 0 1 1\n", "STG line 3: task id 5 outside 0..2"),
        ("1\n0 0 0\n1 3 1 7\n2 0 1 1\n", "STG line 3: task 1 has unknown predecessor 7"),
        ("1\n0 0 0\n0 3 0\n2 0 1 1\n", "STG line 3: task 0 already defined on line 2"),
        ("1\n0 0 0\n1 -3 1 0\n2 0 1 1\n", "negative cost"),
    ],
)
def test_stg_errors_name_the_line(content, needle):
    with pytest.raises(InputError) as info:
        load_dag(content, "stg")
    assert needle in str(info.value)


def test_stg_bad_option():
    with pytest.raises(InputError, match="has no option 'colour'"):
        load_dag(text("sample00.stg"), "stg", options={"colour": 1})
    with pytest.raises(InputError, match="heterogeneity must lie"):
        load_dag(text("sample00.stg"), "stg", options={"processors": 2, "heterogeneity": 5})


# ---- the thesis simulator's CSV -------------------------------------------------------------------------
def test_orb_graph():
    dag = load_dag(text("orb_graph.csv"))
    assert dag.meta["source_format"] == "thesis_csv"
    # 4 pyramids x 5 nodes x 8 levels + the DL node: the "4-stereo" size of Table 4.1
    assert len(dag) == 161
    assert dag.tasks["grid0_3"].cost == {"cpu": 3.58}  # -1: no GPU implementation
    assert dag.tasks["deep_learning"].cost == {"gpu": 15.0}
    edges = {(e.src, e.dst): e.data for e in dag.edges}
    assert ("scale0_2", "scale0_3") in edges and ("scale0_0", "scale0_0") not in edges  # level offset -1
    assert edges[("fast0_3", "grid0_3")] == 0.26  # grid's copy time at level 3
    assert ("gauss0_5", "orb0_5") in edges and ("grid0_5", "orb0_5") in edges
    assert ("scale0_0", "deep_learning") in edges
    assert len(dag.edges) == 4 * (7 + 8 + 8 + 8 + 16) + 1
    platform = board(4)
    assert heft(dag, platform).violations(dag, platform) == []


@pytest.mark.parametrize(
    ("content", "needle"),
    [
        ("a,x,1,1,0\n", "line 1: node 'a' needs a positive level count"),
        ("a,2,1,1,1\n", "line 1: node 'a' with 2 levels needs 8 fields"),
        ("a,1,1,1,0,b\n", "line 1: node 'a' with 1 levels needs 5 fields plus"),
        ("a,1,-1,-1,0\n", "line 1: node 'a' level 0 has neither a CPU nor a GPU time"),
        ("a,1,fast,1,0\n", "line 1: a cpu time is not a number"),
        ("a,1,-5,1,0\n", "line 1: a cpu time must be >= 0 or -1"),
        ("a,1,1,1,0\nb,1,1,1,0,c,0\n", "line 2: node 'b' depends on unknown node 'c'"),
        ("a,1,1,1,0\na,1,1,1,0\n", "line 2: node 'a' already defined on line 1"),
        ("a,1,1,1,0,a,0\n", "self-loop"),
        ("a,1,1,1,0,b,x\nb,1,1,1,0\n", "non-integer level offset 'x'"),
    ],
)
def test_thesis_csv_errors_name_the_line(content, needle):
    with pytest.raises(InputError) as info:
        load_dag(content, "thesis_csv")
    assert needle in str(info.value)


# ---- picking the reader ---------------------------------------------------------------------------------
def test_format_from_path_and_content():
    assert format_for_path("x/robot.STG") == "stg"
    assert format_for_path("w.xml") == format_for_path("w.dax") == "dax"
    assert format_for_path("orb_graph.csv") == "thesis_csv"
    assert format_for_path("dag.json") is None
    assert sniff_text(text("diamond.dax")) == "dax"
    assert sniff_text(text("robot.stg")) == "stg"
    assert sniff_text(text("orb_graph.csv")) == "thesis_csv"
    assert sniff_text(text("fig31.dag.json")) is None
    assert len(load_dag(text("fig31.dag.json"))) == 8
    with pytest.raises(InputError, match="takes no options"):
        load_dag(text("fig31.dag.json"), options={"ccr": 1})

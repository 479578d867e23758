"""``manage.py rt_schedule`` (CONTRACTS.md): output keys, explanations and exit status 2 on bad input."""

import json
from io import StringIO
from pathlib import Path

import pytest
from django.core.management import call_command
from django.core.management.base import CommandError

from apps.realtime.management.commands.rt_schedule import Command

DATA = Path(__file__).resolve().parents[1] / "data"
RTSET = str(DATA / "rtkube.rtset.json")
CLUSTER = str(DATA / "rtkube.cluster.json")


def options(**kw):
    base = {"rtset": RTSET, "cluster": CLUSTER, "json": True, "k": None, "b_score_argument": None,
            "sort_tiebreak": None, "explain": None}  # fmt: skip
    base.update(kw)
    return base


def test_run_returns_the_contract_keys():
    result = Command().run(**options())
    placed = {p["container"]: (p["node"], p["score"]) for p in result["placements"]}
    assert placed["arm-driver"][0] == "jetson"  # C -> the C node
    assert placed["slam-mapper"][0] == "server" and placed["lidar-driver"][0] == "server"
    assert placed["dashboard"][0] == "robot-pc"  # standard container: not on RT-tainted nodes
    # arm-driver: U = 7.6/8.33 on 7.6 -> C score nRank = 1 - 0.91236/7.6
    assert placed["arm-driver"][1] == pytest.approx(1 - (7.6 / 8.33) / 7.6)
    [pending] = result["pending"]
    assert pending == {
        "container": "planner",
        "reasons": {
            "jetson": "non-C container on a C node",
            "robot-pc": "node has no real-time kernel",
            "server": "no WCET given for this node",
        },
    }
    assert result["utilization"] == pytest.approx({"jetson": 7.6 / 8.33, "server": 0.33, "robot-pc": 0.0})
    json.dumps(result)  # serialisable


def test_options_reach_the_scheduler():
    result = Command().run(**options(b_score_argument="load", k=4.0, sort_tiebreak="utilization", explain="*"))
    assert result["params"]["b_score_argument"] == "load" and result["params"]["k"] == 4.0
    assert {"container", "node", "chosen", "rejected_by", "reason", "score"} <= set(result["explain"][0])


def test_call_command_prints_json_and_summary():
    out = StringIO()
    call_command(Command(), RTSET, "--cluster", CLUSTER, "--json", stdout=out)
    assert json.loads(out.getvalue())["pending"][0]["container"] == "planner"
    out = StringIO()
    call_command(Command(), RTSET, "--cluster", CLUSTER, stdout=out)
    text = out.getvalue()
    assert "RT-Kube: 4 placed, 1 pending" in text and "planner pending" in text and "jetson: non-C" in text


def test_realtime_yaml_input(tmp_path):
    cluster = tmp_path / "c.json"
    nodes = [{"name": n, "cpu": 1, "rt": True, "criticality": "C"} for n in ("nodeA", "nodeB")]
    cluster.write_text(json.dumps({"nodes": nodes}))
    result = Command().run(**options(rtset=str(DATA / "listing_3_33.yaml"), cluster=str(cluster)))
    # C spreads to the node left with most headroom: 1 - 0.5/0.95 beats 1 - 0.6/0.95.
    assert result["placements"] == [
        {"container": "example-realtime-data", "node": "nodeA", "score": pytest.approx(1 - 0.5 / 0.95)}
    ]


@pytest.mark.parametrize(
    ("rtset", "cluster", "message"),
    [
        ({"containers": [{"name": "x", "criticality": "D"}]}, None, "requires ASIL-D"),
        (
            {"containers": [{"name": "x", "criticality": "A", "period": 10, "deadline": 10, "wcet": {"mars": 1}}]},
            None,
            "unknown node 'mars'",
        ),
        (
            {"containers": [{"name": "x", "criticality": "A", "period": 10, "deadline": 10, "wcet": {"jetson": 11}}]},
            None,
            "wcet 11 on node 'jetson' exceeds deadline 10",
        ),
        ("{not json", None, "malformed JSON at line 1"),
        ({"containers": []}, {"nodes": []}, "'nodes' must be a non-empty list"),  # the one cluster parser's wording
    ],
)
def test_bad_input_exits_2_with_one_line(tmp_path, rtset, cluster, message):
    rt_path = tmp_path / "rt.json"
    rt_path.write_text(rtset if isinstance(rtset, str) else json.dumps(rtset))
    cl_path = tmp_path / "cl.json"
    cl_path.write_text(json.dumps(cluster) if cluster else Path(CLUSTER).read_text())
    with pytest.raises(CommandError, match=message) as err:
        call_command(Command(), str(rt_path), "--cluster", str(cl_path), "--json", stdout=StringIO())
    assert err.value.returncode == 2 and "\n" not in str(err.value)


def test_missing_file_exits_2(tmp_path):
    with pytest.raises(CommandError, match="no such file") as err:
        call_command(Command(), str(tmp_path / "none.json"), "--cluster", CLUSTER, stdout=StringIO())
    assert err.value.returncode == 2


def big_cluster(tmp_path, n=60):
    """``n`` RT nodes (more than FULL_UP_TO) and three containers: two fit, one fits nowhere (deadline)."""
    nodes = [
        {"name": f"n{i:03d}", "cpu": 4, "rt": True, "rt_threshold": 0.95, "criticality": "C" if i % 10 == 0 else "A"}
        for i in range(n)
    ]
    wcet = {f"n{i:03d}": 1.0 + (i % 7) / 10 for i in range(n)}
    containers = [
        {"name": "a1", "criticality": "A", "period": 10, "deadline": 10, "wcet": wcet},
        {"name": "c1", "criticality": "C", "period": 10, "deadline": 10, "wcet": wcet},
        {"name": "huge", "criticality": "A", "period": 10, "deadline": 10, "wcet": {k: 9.9 for k in wcet}},
    ]
    cluster, rtset = tmp_path / "cluster.json", tmp_path / "rtset.json"
    cluster.write_text(json.dumps({"nodes": nodes}))
    rtset.write_text(json.dumps({"containers": containers}))
    return str(rtset), str(cluster)


def test_large_cluster_output_is_bounded_with_counts_per_reason(tmp_path):
    rtset, cluster = big_cluster(tmp_path)
    result = Command().run(**options(rtset=rtset, cluster=cluster))
    [pending] = result["pending"]
    # huge: 9.9/10 > 0.95 on every node; the C nodes reject it first (XOR criticality comes after admission)
    assert pending["container"] == "huge"
    assert sum(pending["rejections"].values()) == 60 and pending["rejections"]["RealTimeAdmission"] == 60
    assert len(pending["reasons"]) == 1  # one example node per filter, not 60
    for d in result["decisions"]:
        assert len(d["verdicts"]) <= 5 + len(d.get("rejections", {}))
    out = StringIO()
    call_command(Command(), rtset, "--cluster", cluster, stdout=out)
    assert "60 nodes: RealTimeAdmission" in out.getvalue()


def test_explain_one_pod_gives_its_verdict_on_every_node_and_the_same_choices(tmp_path):
    rtset, cluster = big_cluster(tmp_path)
    plain = Command().run(**options(rtset=rtset, cluster=cluster))
    explained = Command().run(**options(rtset=rtset, cluster=cluster, explain="c1"))
    assert explained["placements"] == plain["placements"]
    rows = explained["explain"]
    assert {r["container"] for r in rows} == {"c1"} and len(rows) == 60
    [chosen] = [r for r in rows if r["chosen"]]
    assert chosen["node"] == next(p["node"] for p in plain["placements"] if p["container"] == "c1")
    assert sum(1 for r in rows if r["rejected_by"] == "RealTimeCriticality") == 54  # the 54 non-C nodes
    with pytest.raises(CommandError, match="no container named 'nope'") as err:
        call_command(Command(), rtset, "--cluster", cluster, "--explain", "nope", stdout=StringIO())
    assert err.value.returncode == 2

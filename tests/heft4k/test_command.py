"""``manage.py heft4k``: the CONTRACTS.md keys, the remap report, and exit status 2 on bad input."""

import json
from pathlib import Path

import pytest

from apps.heft4k.management.commands.heft4k import Command

DATA = Path(__file__).resolve().parents[1] / "data"
DAG = str(DATA / "heft4k-mini.dag.json")
CLUSTER = str(DATA / "heft4k-mini.cluster.json")


def run(**options):
    return Command().run(**{**_defaults(), **options})


def test_mapping_with_niceness():
    out = run()
    assert out["makespan"] == 15
    assert [(p["task"], p["node"], p["niceness"], p["start"], p["finish"]) for p in out["placements"]] == [
        ("A", "N1", 0, 0, 4),
        ("C", "N1", 8, 4, 12),
        ("B", "N2", 11, 6, 11),
        ("D", "N1", 16, 13, 15),
    ]
    assert "remap" not in out
    json.dumps(out)


def test_partial_remap_report():
    out = run(fail=["N2"])
    assert out["remap"]["mode"] == "partial"
    assert out["remap"]["lost"] == ["B"] and out["remap"]["moved"] == ["B"]
    assert out["makespan"] == 17 and out["initial"]["makespan"] == 15
    assert {p["node"] for p in out["placements"]} == {"N1"}


def test_total_remap_report():
    out = run(fail=["N1"])
    assert out["remap"]["mode"] == "total"
    assert sorted(out["remap"]["lost"]) == ["A", "C", "D"]
    assert out["makespan"] == 21


def test_simulated_makespans_and_summary():
    cmd = Command()
    out = cmd.run(**{**_defaults(), "simulate": True, "fail": ["N2"]})
    assert set(out["simulated"]) == {"k8s-default", "heft-k8s", "heft4k", "heft-ideal"}
    text = cmd.summary(out)
    assert text.startswith("partial remap after losing N2") and "simulated heft4k" in text


def _defaults():
    return {
        "dag": DAG,
        "dag_format": None,
        "cluster": CLUSTER,
        "fail": [],
        "threshold": 0.2,
        "nice_high": 0,
        "nice_low": 19,
        "plain": False,
        "routing": "ospf",
        "simulate": False,
        "json": True,
    }


def test_json_output_through_argv(capsys):
    Command().run_from_argv(
        ["manage.py", "heft4k", "--skip-checks", DAG, "--cluster", CLUSTER, "--fail", "N2", "--json"]
    )
    out = json.loads(capsys.readouterr().out)
    assert out["remap"]["mode"] == "partial" and out["makespan"] == 17


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--fail", "N7"], "unknown node 'N7'"),
        (["--fail", "N1", "N2"], "no processor is left"),
        (["--nice-high", "5", "--nice-low", "1"], "must not exceed nice_low"),
        (["--threshold", "3"], "--threshold must be a fraction"),
    ],
)
def test_bad_input_exits_2_with_one_line(argv, message, capsys):
    with pytest.raises(SystemExit) as exit_:
        Command().run_from_argv(["manage.py", "heft4k", "--skip-checks", DAG, "--cluster", CLUSTER, *argv])
    assert exit_.value.code == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "\n" not in err and "Traceback" not in err


def test_bad_files_exit_2(tmp_path, capsys):
    bad_cluster = tmp_path / "cluster.json"
    bad_cluster.write_text('{"format": "continuum.cluster/v1", "nodes": [{"name": "N1"}], "links": [{"src": "N1"}]}')
    bad_dag = tmp_path / "dag.json"
    bad_dag.write_text('{"tasks": [{"id": "a", "cost": {"gpu": 1}}], "edges": []}')
    cases = [
        ([DAG, "--cluster", str(bad_cluster)], "links[0] needs 'src' and 'dst' node names"),
        ([str(bad_dag), "--cluster", CLUSTER], "task 'a' cannot run on any processor"),
        ([str(tmp_path / "missing.json"), "--cluster", CLUSTER], "no such file"),
    ]
    for argv, message in cases:
        with pytest.raises(SystemExit) as exit_:
            Command().run_from_argv(["manage.py", "heft4k", "--skip-checks", *argv])
        assert exit_.value.code == 2
        assert message in capsys.readouterr().err

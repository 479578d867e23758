"""The ``cluster_ros`` and ``place`` management commands (contract keys, exit status 2 on bad input).

The containers app is not registered in INSTALLED_APPS yet, so the commands are instantiated directly.
"""

import json
import tarfile
from pathlib import Path

import pytest

from apps.containers.management.commands import cluster_ros, place

DATA = Path(__file__).resolve().parents[1] / "data"


def run(module, *argv):
    cmd = module.Command()
    options = vars(cmd.create_parser("manage.py", module.__name__.rsplit(".", 1)[-1]).parse_args(list(argv)))
    return cmd, cmd.run(**options)


def test_cluster_ros_contract_keys_on_autoware():
    cmd, out = run(cluster_ros, str(DATA / "autoware_reference_system.json"), "--containers", "4", "--json")
    assert len(out["containers"]) == 4
    assert all(set(c) == {"name", "nodes"} for c in out["containers"])
    assert sum(len(c["nodes"]) for c in out["containers"]) == 24
    assert out["inter_container_bandwidth"] > 0 and out["intra_container_bandwidth"] > 0
    assert out["levels"]["BehaviorPlanner"] == "mission"
    text = cmd.summary(out)
    assert "24 ROS nodes -> 4 containers" in text


def test_cluster_ros_reads_dot_and_irobot_and_uses_eq_3_13():
    _, dot = run(cluster_ros, str(DATA / "autoware_reference_system.dot"), "--containers", "3")
    assert len(dot["containers"]) == 3 and dot["graph"]["name"] == "autoware_reference_system"
    _, sierra = run(cluster_ros, str(DATA / "irobot_sierra_nevada.json"), "--memory-mib", "120", "--overhead-mib", "39")
    assert sierra["params"]["eq_3_13_bound"] == 3 and len(sierra["containers"]) == 3


PATH_GRAPH = {
    "format": "continuum.rosgraph/v1",
    "nodes": [{"name": n} for n in "abc"],
    "topics": [
        {"name": "ab", "publishers": ["a"], "subscribers": ["b"], "rate_hz": 1, "msg_bytes": 1},
        {"name": "bc", "publishers": ["b"], "subscribers": ["c"], "rate_hz": 1, "msg_bytes": 100},
    ],
}


def test_cluster_ros_method_is_the_setting(tmp_path, settings):
    """Issue 27's minimal case: the default refines Listing 3.20's {a,b},{c} (cut 100) to {a},{b,c} (cut 1)."""
    path = tmp_path / "path.json"
    path.write_text(json.dumps(PATH_GRAPH))
    _, refined = run(cluster_ros, str(path), "--containers", "2")
    assert refined["params"]["method"] == "refined" and refined["inter_container_bandwidth"] == 1
    settings.CONTINUUM_ROS_CLUSTERING = "thesis"
    _, thesis = run(cluster_ros, str(path), "--containers", "2")
    assert thesis["params"]["method"] == "thesis" and thesis["inter_container_bandwidth"] == 100
    from apps.containers.resources import check_clustering_method

    assert check_clustering_method() == []
    settings.CONTINUUM_ROS_CLUSTERING = "metis"
    assert [e.id for e in check_clustering_method()] == ["containers.E002"]


def test_cluster_ros_writes_the_dockerfiles(tmp_path):
    graph = {
        "format": "continuum.rosgraph/v1",
        "nodes": [
            {"name": "drv", "packages": ["urg_node", "rclcpp"]},
            {"name": "slam", "packages": ["slam_toolbox", "rclcpp"]},
            {"name": "ui", "packages": ["rviz2", "rclcpp"]},
        ],
        "topics": [
            {"name": "/scan", "publishers": ["drv"], "subscribers": ["slam"], "rate_hz": 10, "msg_bytes": 8000},
            {"name": "/map", "publishers": ["slam"], "subscribers": ["ui"], "rate_hz": 1, "msg_bytes": 100},
        ],
        "packages": {"rclcpp": 50, "urg_node": 3, "slam_toolbox": 40, "rviz2": 200},
    }
    path = tmp_path / "g.json"
    path.write_text(json.dumps(graph))
    archive = tmp_path / "images.tar"
    _, out = run(cluster_ros, str(path), "--containers", "2", "--images", str(archive))
    assert out["containers"] == [{"name": "drv", "nodes": ["drv", "slam"]}, {"name": "ui", "nodes": ["ui"]}]
    assert out["inter_container_bandwidth"] == 100
    assert out["images"]["before_mib"] == 93 + 250 and out["images"]["after_mib"] == 293
    with tarfile.open(archive) as tar:
        assert "base/Dockerfile" in tar.getnames() and "ui/Dockerfile" in tar.getnames()


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["missing.json", "--containers", "2"], "missing.json: no such file"),
        (["BAD", "--containers", "0"], "the number of containers must be a positive integer"),
        (["BAD", "--memory-mib", "20", "--overhead-mib", "29"], "cannot hold one container"),
        (["BAD"], "give --containers N"),
        (["MALFORMED", "--containers", "2"], "malformed JSON at line 1"),
    ],
)
def test_cluster_ros_bad_input_exits_2(argv, message, tmp_path, capsys):
    good = str(DATA / "irobot_sierra_nevada.json")
    malformed = tmp_path / "m.json"
    malformed.write_text("{oops")
    argv = [good if a == "BAD" else str(malformed) if a == "MALFORMED" else a for a in argv]
    cmd = cluster_ros.Command()
    with pytest.raises(SystemExit) as exc:
        cmd.run_from_argv(["manage.py", "cluster_ros", *argv, "--skip-checks"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_place_contract_keys_and_comparison():
    cmd, out = run(
        place,
        str(DATA / "kairos_synthetic.containers.json"),
        "--cluster",
        str(DATA / "kairos_synthetic.cluster.json"),
        "--policy",
        "superclustering",
        "--compare",
        "--json",
    )
    assert {p["container"]: p["node"] for p in out["placements"]}["map-nav-manager-rb"] == "jetson"
    assert out["pending"] == []
    assert set(out["placements"][0]) == {"container", "node", "score"}
    other = out["comparison"]["default-kubernetes"]
    assert out["inter_node_bandwidth"] < other["inter_node_bandwidth"]
    assert "inter-node bandwidth" in cmd.summary(out)


def test_place_takes_cluster_ros_output_with_the_graph(tmp_path):
    _, clustered = run(cluster_ros, str(DATA / "autoware_reference_system.json"), "--containers", "4")
    containers = tmp_path / "containers.json"
    containers.write_text(json.dumps({"containers": clustered["containers"]}))
    cluster = tmp_path / "cluster.json"
    cluster.write_text(
        json.dumps({"nodes": [{"name": "ecu1", "arch": "arm64", "cpu": 4}, {"name": "ecu2", "arch": "riscv64"}]})
    )
    _, out = run(
        place, str(containers), "--cluster", str(cluster), "--graph", str(DATA / "autoware_reference_system.json")
    )
    # Default images are amd64+arm64: nothing can go to the RISC-V ECU and the verdicts say so.
    assert {p["node"] for p in out["placements"]} == {"ecu1"}
    riscv = [v for d in out["decisions"] for v in d["verdicts"] if v["node"] == "ecu2"]
    assert all(v["rejected_by"] == "NodeArch" for v in riscv)
    assert out["inter_node_bandwidth"] == 0


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--policy", "magic"], "unknown placement policy 'magic'"),
        (["--weights", "bandwidth"], "--weights: expected policy=weight pairs"),
        (["--weights", "luck=2"], "unknown scoring policy 'luck'"),
    ],
)
def test_place_bad_input_exits_2(extra, message, capsys):
    argv = [str(DATA / "kairos_synthetic.containers.json"), "--cluster", str(DATA / "kairos_synthetic.cluster.json")]
    with pytest.raises(SystemExit) as exc:
        place.Command().run_from_argv(["manage.py", "place", *argv, *extra, "--skip-checks"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


def test_place_bad_cluster_exits_2(tmp_path, capsys):
    bad = tmp_path / "cluster.json"
    bad.write_text(json.dumps({"nodes": [{"name": "x", "arch": "sparc"}]}))
    with pytest.raises(SystemExit) as exc:
        place.Command().run_from_argv(
            ["manage.py", "place", str(DATA / "kairos_synthetic.containers.json"), "--cluster", str(bad),
             "--skip-checks"]
        )  # fmt: skip
    assert exc.value.code == 2
    assert "node 'x': unknown architecture 'sparc'" in capsys.readouterr().err


def test_place_holds_drivers_on_the_robot_unless_freed(tmp_path, capsys):
    graph = str(DATA / "autoware_reference_system.json")
    _, clustered = run(cluster_ros, graph, "--containers", "4")
    containers = tmp_path / "containers.json"
    containers.write_text(json.dumps({"containers": clustered["containers"]}))
    cluster = tmp_path / "cluster.json"
    cluster.write_text(
        json.dumps(
            {"nodes": [{"name": "mcb", "cpu": 4, "labels": {"zone": "robot"}},
                       {"name": "vm", "cpu": 32, "labels": {"zone": "cloud"}}]}
        )
    )  # fmt: skip
    owner = {n: c["name"] for c in clustered["containers"] for n in c["nodes"]}
    _, held = run(place, str(containers), "--cluster", str(cluster), "--graph", graph)
    hosts = {p["container"]: p["node"] for p in held["placements"]}
    assert hosts[owner["FrontLidarDriver"]] == hosts[owner["VehicleDBWSystem"]] == "mcb"
    assert held["off_robot_drivers"] == []
    cmd, freed = run(place, str(containers), "--cluster", str(cluster), "--graph", graph, "--free-drivers")
    hosts = {p["container"]: p["node"] for p in freed["placements"]}
    assert hosts[owner["FrontLidarDriver"]] == "vm"
    assert "warning: driver-level ROS nodes" in cmd.summary(freed)
    with pytest.raises(SystemExit) as exc:
        place.Command().run_from_argv(
            ["manage.py", "place", str(containers), "--cluster", str(cluster), "--robot-label", "robot",
             "--skip-checks"]
        )  # fmt: skip
    assert exc.value.code == 2 and "robot label must be key=value" in capsys.readouterr().err

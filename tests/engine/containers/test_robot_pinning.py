"""Driver-level ROS nodes stay on the robot's boards (robot_pinning; thesis Fig. 3.19, Table 4.26)."""

from pathlib import Path

import pytest

from continuum.engine import InputError
from continuum.engine.containers.robot_pinning import parse_label, pinned
from continuum.engine.containers.ros_clustering import cluster_ros
from continuum.engine.containers.rosgraph import RosGraph, load_rosgraph
from continuum.engine.containers.superclustering import default_kubernetes, load_workload, superclustering
from continuum.engine.core.cluster import Cluster

DATA = Path(__file__).resolve().parents[2] / "data"
HARDWARE = {"FrontLidarDriver", "RearLidarDriver", "VehicleDBWSystem"}


def autoware(**pins: str | None) -> RosGraph:
    graph = load_rosgraph((DATA / "autoware_reference_system.json").read_text())
    doc = graph.to_dict()
    for node in doc["nodes"]:
        if pins.get(node["name"]):
            node["pin"] = pins[node["name"]]
    return RosGraph.from_dict(doc)


def robot_and_cloud(robot_cpu: float = 4) -> Cluster:
    # The operators' case: a small robot board and a large cloud VM (the freest node wins ties).
    return Cluster.from_dict(
        {
            "nodes": [
                {"name": "mcb", "cpu": robot_cpu, "memory_mib": 4096, "labels": {"zone": "robot"}},
                {"name": "cloud-vm", "cpu": 32, "memory_mib": 65536, "labels": {"zone": "cloud"}},
            ]
        }
    )


def workload(graph: RosGraph, n: int = 4):
    groups = {c.name: list(c.nodes) for c in cluster_ros(graph, n).containers}
    containers = [{"name": name, "nodes": nodes} for name, nodes in groups.items()]
    return load_workload({"containers": containers}, graph), groups


def host_of(plan, groups) -> dict[str, str | None]:
    placed = plan.placed()
    return {ros: placed.get(c) for c, members in groups.items() for ros in members}


def test_the_autoware_dataset_marks_its_sensors_and_commands_as_drivers():
    graph = autoware()
    given = {n for n, node in graph.nodes.items() if node.level == "driver"}
    assert given >= HARDWARE
    assert "PointCloudFusion" not in given and graph.nodes["PointCloudFusion"].level is None


def test_without_the_constraint_superclustering_puts_the_drivers_on_the_cloud_vm_and_says_so():
    graph = autoware()
    wl, groups = workload(graph)
    plan = superclustering(wl, robot_and_cloud(), drivers_on_robot=False)
    hosts = host_of(plan, groups)
    assert {hosts[d] for d in HARDWARE} == {"cloud-vm"}  # the operators' observation
    warned = {d for w in plan.metrics["off_robot_drivers"] for d in w["drivers"]}
    assert warned >= HARDWARE
    assert all("off the robot" in w["message"] and w["node"] == "cloud-vm" for w in plan.metrics["off_robot_drivers"])


@pytest.mark.parametrize("policy", [superclustering, default_kubernetes])
def test_pinned_drivers_stay_on_the_robot_board(policy):
    graph = autoware()
    wl, groups = workload(graph)
    plan = policy(wl, robot_and_cloud())
    hosts = host_of(plan, groups)
    drivers = {n for n, node in graph.nodes.items() if node.level == "driver"}
    assert {hosts[d] for d in drivers} == {"mcb"}
    assert plan.metrics["off_robot_drivers"] == []
    assert plan.params["drivers_on_robot"] is True and plan.params["robot_label"] == "zone=robot"
    # The cloud VM's verdict for a driver container names the filter and the drivers.
    owner = next(c for c, ms in groups.items() if "FrontLidarDriver" in ms)
    verdict = next(v for v in plan.decision(owner).verdicts if v.node == "cloud-vm")
    assert verdict.rejected_by == "RobotBoard" and "FrontLidarDriver" in verdict.reason


def test_unpinned_drivers_may_move_off_robot_and_the_plan_warns():
    drivers = {n for n, node in autoware().nodes.items() if node.level == "driver"}
    graph = autoware(**dict.fromkeys(drivers, "free"))
    wl, groups = workload(graph)
    owner = next(c for c, ms in groups.items() if "FrontLidarDriver" in ms)
    spec = next(c for c in wl.containers if c.name == owner)
    assert "FrontLidarDriver" in spec.drivers and spec.on_robot == ()
    plan = superclustering(wl, robot_and_cloud())
    hosts = host_of(plan, groups)
    assert {hosts[d] for d in HARDWARE} == {"cloud-vm"}
    warned = {d for w in plan.metrics["off_robot_drivers"] for d in w["drivers"]}
    assert warned >= HARDWARE
    # Pinning one back keeps its container on the robot.
    graph = autoware(**{**dict.fromkeys(drivers, "free"), "VehicleDBWSystem": None})
    wl, groups = workload(graph)
    assert host_of(superclustering(wl, robot_and_cloud()), groups)["VehicleDBWSystem"] == "mcb"


def test_a_full_robot_leaves_the_driver_container_pending_with_the_reason():
    graph = autoware()
    wl, _groups = workload(graph)
    plan = superclustering(wl, robot_and_cloud(robot_cpu=0.001))
    pending = [d for d in plan.decisions if d.pending]
    assert pending, "a robot board of 1 millicore cannot hold the driver containers"
    for d in pending:
        reasons = {v.rejected_by for v in d.verdicts}
        assert reasons == {"NodeResourcesFit", "RobotBoard"}


def test_a_cluster_without_robot_nodes_places_freely_and_reports_every_driver():
    graph = autoware()
    wl, _groups = workload(graph)
    cloud = Cluster.from_dict({"nodes": [{"name": "vm", "cpu": 8, "labels": {"zone": "cloud"}}]})
    plan = superclustering(wl, cloud)
    assert plan.metrics["robot_nodes"] == [] and not [d for d in plan.decisions if d.pending]
    warned = {d for w in plan.metrics["off_robot_drivers"] for d in w["drivers"]}
    assert warned == {n for n, node in graph.nodes.items() if node.level == "driver"}


def test_pins_and_labels():
    levels = {"a": "driver", "b": "driver", "c": "macro", "d": "macro"}
    assert pinned(levels, {"b": "free", "d": "robot"}) == {"a", "d"}
    assert parse_label("site = robot-1") == ("site", "robot-1")
    with pytest.raises(InputError, match="key=value"):
        parse_label("robot")
    with pytest.raises(InputError, match="unknown pin 'board'"):
        RosGraph.from_dict({"nodes": [{"name": "a", "pin": "board"}], "topics": []})


def test_pins_survive_the_resolved_workload_round_trip():
    graph = autoware(FrontLidarDriver="free")
    wl, _ = workload(graph)
    again = load_workload(wl.to_dict())
    assert again.containers == wl.containers

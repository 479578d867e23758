"""The ROS nodes' CPU and memory requests (resource_model): hand-computed values and the Autoware case."""

from pathlib import Path

import pytest

from continuum.engine import InputError
from continuum.engine.containers.resource_model import ResourceModel, profiles
from continuum.engine.containers.ros_clustering import cluster_ros
from continuum.engine.containers.rosgraph import RosGraph, load_rosgraph
from continuum.engine.containers.superclustering import load_workload

DATA = Path(__file__).resolve().parents[2] / "data"


def test_hand_computed_profile():
    g = RosGraph.from_dict(
        {
            "nodes": [{"name": "lidar"}, {"name": "filter", "cpu": 0.2}, {"name": "map", "memory_mib": 300}],
            "topics": [
                {"name": "/scan", "publishers": ["lidar"], "subscribers": ["filter", "map"], "rate_hz": 10,
                 "msg_bytes": 102400},
                {"name": "/points", "publishers": ["filter"], "subscribers": ["map"], "rate_hz": 5, "msg_bytes": 1024},
            ],
        }
    )  # fmt: skip
    model = ResourceModel(base_cores=0.01, per_message_us=20, per_kib_us=1, process_mib=15, history_depth=10)
    p = profiles(g, model)
    scan_s, points_s = (20 + 100 * 1) / 1e6, (20 + 1) / 1e6  # seconds of middleware per message
    assert p["lidar"].cpu == pytest.approx(0.01 + 10 * scan_s)
    assert p["filter"].cpu == pytest.approx(0.2 + 0.01 + 10 * scan_s + 5 * points_s)
    assert p["filter"].work_cores == 0.2 and p["filter"].messages_per_s == 15
    assert p["map"].cpu == pytest.approx(0.01 + 10 * scan_s + 5 * points_s)
    # Memory: the process plus 10 queued messages per endpoint, unless profiled.
    assert p["lidar"].memory_mib == pytest.approx(15 + 10 * 102400 / 2**20)
    assert p["filter"].memory_mib == pytest.approx(15 + 10 * (102400 + 1024) / 2**20)
    assert p["map"].memory_mib == 300 and p["map"].memory_profiled
    # More data, more CPU: the estimate follows the inputs.
    faster = RosGraph.from_dict({**g.to_dict(), "topics": [{**g.to_dict()["topics"][0], "rate_hz": 20},
                                                           g.to_dict()["topics"][1]]})  # fmt: skip
    assert profiles(faster, model)["lidar"].cpu > p["lidar"].cpu


def test_autoware_containers_get_meaningful_distinct_requests():
    g = load_rosgraph((DATA / "autoware_reference_system.json").read_text())
    groups = {c.name: list(c.nodes) for c in cluster_ros(g, 4).containers}
    wl = load_workload({"containers": [{"name": k, "nodes": v} for k, v in groups.items()]}, g)
    for c in wl.containers:
        work = sum(g.nodes[n].cpu for n in c.nodes)
        assert c.cpu > work + 0.005 * len(c.nodes) - 1e-12  # work + at least the base share per ROS node
        assert c.memory_mib >= 20 * len(c.nodes)  # one process per ROS node
    assert len({round(c.cpu, 6) for c in wl.containers}) == len(wl.containers)


def test_model_parameters_are_checked():
    with pytest.raises(InputError, match="per_message_us must be a non-negative number"):
        ResourceModel(per_message_us=-1)
    with pytest.raises(InputError, match="unknown parameter 'cores'"):
        ResourceModel.from_dict({"cores": 1})

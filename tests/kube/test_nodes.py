"""What the gateway reads from a Node object's JSON (apps/kube/nodes.py): pure functions, no API."""

from apps.kube import gateway
from continuum.engine.core.taints import Taint


def test_fields_from_a_cordoned_arm_node_without_arch_label():
    obj = {
        "metadata": {"name": "jetson", "labels": {"zone": "robot"}},
        "spec": {"unschedulable": True, "taints": [{"key": "gpu", "effect": "NoSchedule"}]},
        "status": {
            "capacity": {"cpu": "1500m", "memory": "8Gi", "ephemeral-storage": "1Gi"},
            "allocatable": {"cpu": "1", "memory": "4Gi"},
            "conditions": [{"type": "MemoryPressure", "status": "False"}, {"type": "Ready", "status": "False"}],
            "nodeInfo": {"architecture": "aarch64"},
        },
    }
    assert gateway.node_fields(obj) == {
        "labels": {"zone": "robot"},
        "taints": [
            {"key": "gpu", "value": "", "effect": "NoSchedule"},
            {"key": "node.kubernetes.io/unschedulable", "value": "", "effect": "NoSchedule"},
        ],
        "status": "NotReady",
        "arch": "arm64",
        "cpu": 1.5,
        "memory_mib": 8192,
        "storage_mib": 1024,
    }
    assert gateway.taints_of(obj) == [Taint("gpu"), Taint("node.kubernetes.io/unschedulable")]
    assert gateway.allocatable(obj) == (1.0, 4096.0)


def test_a_node_without_conditions_is_unknown_and_labels_name_the_arch():
    obj = {"metadata": {"name": "x", "labels": {"kubernetes.io/arch": "x86_64"}}}
    assert gateway.node_status(obj) == gateway.UNKNOWN
    assert gateway.node_fields(obj) == {"labels": obj["metadata"]["labels"], "taints": [], "status": "Unknown",
                                        "arch": "amd64"}  # fmt: skip
    ready = {"status": {"conditions": [{"type": "Ready", "status": "True"}]}}
    assert gateway.node_status(ready) == gateway.READY
    assert gateway.allocatable(ready) == (0.0, 0.0)

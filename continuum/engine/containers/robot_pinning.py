"""Driver-level ROS nodes stay on the robot's boards (thesis 3.2.1 Fig. 3.19 and 3.3.1 Table 4.26).

The thesis' reading, as the spec restates it:

* Fig. 3.19 (spec 02, 1.2): a ``driver`` "talks to HW/engines" -- it is bound to the hardware it drives
  (the lidar, the drive-by-wire interface), which is wired to the robot.
* Table 4.26 (spec 02, 5.4): in the real case the containers holding drivers (``main-rb``, ``arm-rb``) carry a
  *required* affinity to the robot's main board (MCB, "required; drivers"); the others may go anywhere.

So super-clustering (and the default-Kubernetes baseline, for a fair comparison) gets one more filter:
a container that holds a **pinned** ROS node may only be bound to a node of the robot. A ROS node is pinned
when its pin is ``robot``, or when it has no pin and its level (given, else proposed) is ``driver``; the
operator unpins a driver with pin ``free``. The robot's boards are the cluster nodes carrying the label
``zone=robot`` (what the thesis testbeds' cluster files use; a parameter). A cluster without a robot node
cannot honour the constraint: the filter is then not applied, and every driver is reported.

Whatever the options, the plan says when a driver-level ROS node (pinned or not) ends up off the robot:
:func:`off_robot` lists them, and the placement's metrics carry that list as ``off_robot_drivers``.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

from continuum.engine.core.cluster import Cluster, ClusterNode
from continuum.engine.core.errors import InputError

__all__ = [
    "ROBOT_LABEL",
    "drivers",
    "is_robot",
    "off_board_reason",
    "off_robot",
    "parse_label",
    "pinned",
    "reject_reason",
    "robot_nodes",
]

#: The label of the robot's boards in the cluster files (``clusters/rb-kairos.json``: mcb and jetson-nano).
ROBOT_LABEL = ("zone", "robot")


def parse_label(raw: str | tuple[str, str] | None) -> tuple[str, str]:
    """``"key=value"`` (or a pair) as a label pair; ``None``: :data:`ROBOT_LABEL`."""
    if raw is None:
        return ROBOT_LABEL
    if isinstance(raw, tuple):
        key, value = raw
    else:
        key, sep, value = str(raw).partition("=")
        if not sep:
            raise InputError(f"robot label must be key=value, got {raw!r}", "robot_label")
    if not key.strip() or not value.strip():
        raise InputError(f"robot label must be key=value, got {raw!r}", "robot_label")
    return key.strip(), value.strip()


def drivers(levels: Mapping[str, str]) -> set[str]:
    """The driver-level ROS nodes (``levels``: each node's given or proposed level)."""
    return {n for n, level in levels.items() if level == "driver"}


def pinned(levels: Mapping[str, str], pins: Mapping[str, str | None]) -> set[str]:
    """ROS nodes that must stay on the robot: pin ``robot``, or no pin and level ``driver``."""
    return {n for n, level in levels.items() if pins.get(n) == "robot" or (pins.get(n) is None and level == "driver")}


def is_robot(node: ClusterNode, label: tuple[str, str] = ROBOT_LABEL) -> bool:
    return node.all_labels().get(label[0]) == label[1]


def robot_nodes(cluster: Cluster, label: tuple[str, str] = ROBOT_LABEL) -> list[str]:
    return [name for name, node in cluster.nodes.items() if is_robot(node, label)]


def reject_reason(on_robot: Iterable[str], node: ClusterNode, label: tuple[str, str] = ROBOT_LABEL) -> str | None:
    """Why a container holding the pinned ROS nodes ``on_robot`` may not go to ``node`` (``None``: it may)."""
    held = sorted(on_robot)
    if not held or is_robot(node, label):
        return None
    return off_board_reason(held, label)


def off_board_reason(on_robot: Iterable[str], label: tuple[str, str] = ROBOT_LABEL) -> str:
    """The reason :func:`reject_reason` gives for every node that is not one of the robot's boards."""
    held = sorted(on_robot)
    shown = ", ".join(held[:3]) + (f" and {len(held) - 3} more" if len(held) > 3 else "")
    return (
        f"holds driver-level ROS node{'s' if len(held) > 1 else ''} {shown}, pinned to the robot's boards "
        f"({label[0]}={label[1]}); this node is not one (unpin them to allow it)"
    )


def off_robot(
    placed: Mapping[str, str],
    driver_nodes: Mapping[str, Iterable[str]],
    cluster: Cluster,
    label: tuple[str, str] = ROBOT_LABEL,
) -> list[dict[str, Any]]:
    """One warning per container that holds driver-level ROS nodes and was bound off the robot.

    ``driver_nodes``: container -> its driver-level ROS nodes. Pending containers are not placed anywhere, so
    they are not reported here.
    """
    out = []
    for container, ros_nodes in driver_nodes.items():
        names = sorted(ros_nodes)
        node = placed.get(container)
        if not names or node is None or node not in cluster.nodes or is_robot(cluster.nodes[node], label):
            continue
        out.append(
            {
                "container": container,
                "node": node,
                "drivers": names,
                "message": f"driver-level ROS node{'s' if len(names) > 1 else ''} {', '.join(names)} "
                f"(container {container}) placed on {node}, off the robot ({label[0]}={label[1]})",
            }
        )
    return out

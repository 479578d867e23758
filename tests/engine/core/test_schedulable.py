"""One taint/toleration filter for every placement method (issue 28): the DAG schedulers' cluster is the nodes a
pod without tolerations may be placed on; RT-Kube and super-clustering read the same effective taints."""

from __future__ import annotations

import pytest

from continuum.engine.core.cluster import Cluster
from continuum.engine.core.errors import InputError
from continuum.engine.core.taints import REALTIME, Toleration
from continuum.engine.rtkube.rt_model import rt_node


def cluster(nodes):
    return Cluster.from_dict({"format": "continuum.cluster/v1", "name": "c", "nodes": nodes,
                              "links": [{"src": "a", "dst": "b", "bandwidth_mbps": 100}]})  # fmt: skip


def test_rt_only_tainted_and_not_ready_nodes_are_barred_unless_tolerated():
    c = cluster([
        {"name": "a", "cpu": 4},
        {"name": "b", "cpu": 4, "rt": True, "criticality": "A"},  # RT-only: RealTime=RT:NoSchedule implied
        {"name": "c", "cpu": 4, "taints": ["gpu=only:NoSchedule"]},
        {"name": "d", "cpu": 4, "taints": ["node.kubernetes.io/unreachable:NoSchedule"]},
        {"name": "e", "cpu": 4, "taints": ["soft=x:PreferNoSchedule"]},  # a preference, not a bar
    ])  # fmt: skip
    assert sorted(c.schedulable().nodes) == ["a", "e"]
    assert not c.schedulable().links  # b's link went with b
    rt = Toleration("RealTime", "Equal", "RT", "NoSchedule")
    assert sorted(c.schedulable([rt]).nodes) == ["a", "b", "e"]
    assert sorted(c.schedulable([Toleration(operator="Exists")]).nodes) == ["a", "b", "c", "d", "e"]
    # RT-Kube reads the very same taints.
    assert rt_node(c.nodes["b"]).taints == (REALTIME,) and rt_node(c.nodes["a"]).taints == ()


def test_nothing_left_is_an_input_error():
    with pytest.raises(InputError, match="no node its pods may be placed on"):
        cluster([{"name": "a", "rt": True}, {"name": "b", "taints": ["x=y:NoExecute"]}]).schedulable()

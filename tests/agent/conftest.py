"""The node agent's tests reuse the RT-Kube app's RT cluster (node0/node1: A/B nodes, node2: C, node3: no RT)."""

from tests.realtime.conftest import rt_cluster  # noqa: F401

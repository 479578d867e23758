"""The demo's cluster (``load_demo``): robot board, Jetson, edge server and cloud VM in a chain."""

from apps.tenancy.demo import Demo

from .models import Cluster, ComputeNode, Link


def demo_cluster(demo: Demo) -> None:
    """Create the ``edge-cloud`` cluster of the demo fleet unless it exists; ``demo.objects["cluster"]``."""
    cluster, created = Cluster.objects.get_or_create(
        fleet=demo.fleet, name="edge-cloud", defaults={"description": "robot, edge and cloud"}
    )
    if created:
        spec = [
            ("robot-board", "arm64", 4, 4096, 1.0),
            ("jetson", "arm64", 8, 16384, 1.5),
            ("edge-server", "amd64", 16, 65536, 2.5),
            ("cloud-vm", "amd64", 32, 131072, 3.0),
        ]
        nodes = {
            name: ComputeNode.objects.create(
                cluster=cluster, name=name, arch=arch, cpu=cpu, memory_mib=mem, speed=speed
            )
            for name, arch, cpu, mem, speed in spec
        }
        for a, b, mbps, ms in [
            ("robot-board", "jetson", 1000, 0.2),
            ("jetson", "edge-server", 866, 2.0),
            ("edge-server", "cloud-vm", 100, 20.0),
        ]:
            Link.objects.create(cluster=cluster, src=nodes[a], dst=nodes[b], bandwidth_mbps=mbps, latency_ms=ms)
    demo.objects["cluster"] = cluster

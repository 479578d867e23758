"""``python manage.py cluster_ros GRAPH --containers N [--json]``: ROS nodes into containers (Listing 3.20, then
the refinement of ``settings.CONTINUUM_ROS_CLUSTERING``)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from apps.containers.resources import clustering_method
from apps.containers.serializers import ClusterRequestSerializer
from apps.tenancy.api import contract_error
from continuum.commands import EngineCommand
from continuum.engine.containers.image_inheritance import plan_from_graph
from continuum.engine.containers.ros_clustering import cluster_ros, max_containers
from continuum.engine.containers.rosgraph import MODES, READERS, load_rosgraph
from continuum.engine.core.errors import InputError


class Command(EngineCommand):
    help = (
        "Group the ROS nodes of a graph (continuum.rosgraph/v1, Autoware reference-system JSON, iRobot "
        "ros2-performance topology, rqt_graph .dot) into containers and report the bandwidth left between them."
    )

    def add_arguments(self, parser) -> None:
        super().add_arguments(parser)
        parser.add_argument("graph", help="ROS graph file")
        parser.add_argument("--containers", type=int, default=None, help="number of containers N")
        parser.add_argument("--format", dest="graph_format", choices=READERS, default=None, help="default: guessed")
        parser.add_argument("--mode", choices=MODES, default="per_topic", help="Eq. 3.12 reading (default per_topic)")
        parser.add_argument("--memory-mib", type=float, default=None, help="memory available for containers (Eq. 3.13)")
        parser.add_argument("--overhead-mib", type=float, default=None, help="memory overhead of one container")
        parser.add_argument("--max-share", type=float, default=None, help="split heavy nodes out of larger clusters")
        parser.add_argument("--max-memory-mib", type=float, default=None, help="split clusters above this memory")
        parser.add_argument("--images", default=None, help="write the Dockerfiles archive here (.tar or .zip)")

    def run(self, **options: Any) -> dict:
        path = options["graph"]
        graph = load_rosgraph(self.read_text(path), options.get("graph_format"), name=Path(path).stem)
        n = options.get("containers")
        memory, overhead = options.get("memory_mib"), options.get("overhead_mib")
        if n is None and (memory is None or overhead is None):
            raise InputError("give --containers N, or --memory-mib and --overhead-mib to use the Eq. 3.13 bound")
        # The API's request contract checks the options, with the API's messages.
        request = {
            "containers": n,
            "memory_mib": memory,
            "overhead_mib": overhead,
            "mode": options.get("mode") or "per_topic",
            "max_cluster_share": options.get("max_share"),
            "max_cluster_memory_mib": options.get("max_memory_mib"),
        }
        contract = ClusterRequestSerializer(data={k: v for k, v in request.items() if v is not None})
        if not contract.is_valid():
            raise contract_error(contract.errors)
        if n is None:
            n = max_containers(memory, overhead)
        result = cluster_ros(
            graph,
            n,
            mode=options.get("mode") or "per_topic",
            available_mib=memory,
            overhead_mib=overhead,
            max_cluster_share=options.get("max_share"),
            max_cluster_memory_mib=options.get("max_memory_mib"),
            method=clustering_method(),
        )
        out = result.to_dict()
        out["bandwidth_unit"] = "bytes/s"
        out["graph"] = {"name": graph.name, "nodes": len(graph.nodes), "topics": len(graph.topics)}
        out["levels"] = graph.levels()
        if any(node.packages for node in graph.nodes.values()):
            plan = plan_from_graph(graph, {c.name: c.nodes for c in result.containers})
            out["images"] = plan.to_dict()
            if options.get("images"):
                target = Path(options["images"])
                fmt = "zip" if target.suffix == ".zip" else "tar"
                target.write_bytes(plan.archive(fmt))
                out["images"]["archive"] = str(target)
        elif options.get("images"):
            raise InputError("--images needs a graph whose ROS nodes list their packages")
        return out

    def summary(self, result: dict) -> str:
        total = result["inter_container_bandwidth"] + result["intra_container_bandwidth"]
        share = result["inter_container_bandwidth"] / total * 100 if total else 0.0
        lines = [
            f"{result['graph']['name']}: {result['graph']['nodes']} ROS nodes -> {len(result['containers'])} "
            f"containers (asked {result['requested_containers']})",
            f"  between containers: {result['inter_container_bandwidth']:.1f} B/s ({share:.1f}% of "
            f"{total:.1f} B/s); inside: {result['intra_container_bandwidth']:.1f} B/s",
        ]
        if result["guard_fired"]:
            lines.append("  disconnected parts could not merge further (termination guard)")
        for c in result["containers"]:
            lines.append(f"  {c['name']}: {', '.join(c['nodes'])}")
        if result["culled"]:
            lines.append(f"  edgeless ROS nodes attached afterwards: {', '.join(result['culled'])}")
        if "images" in result:
            im = result["images"]
            lines.append(
                f"  images: {len(im['images'])}, disk {im['before_mib']:.1f} -> {im['after_mib']:.1f} MiB "
                f"({im['saved'] * 100:.1f}% saved)"
            )
        return "\n".join(lines)

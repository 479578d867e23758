"""``python manage.py place CONTAINERS --cluster FILE --policy superclustering [--json]`` (Eqs. 3.14-3.15)."""

from __future__ import annotations

from typing import Any

from django.conf import settings

from apps.containers.resources import resource_model
from continuum.commands import EngineCommand
from continuum.engine.containers.rosgraph import load_rosgraph
from continuum.engine.containers.superclustering import ALIASES, POLICIES, load_workload, place
from continuum.engine.core.cluster import Cluster
from continuum.engine.core.errors import InputError


class Command(EngineCommand):
    help = "Map containers to cluster nodes: super-clustering (bandwidth-aware) or the default-Kubernetes-like policy."

    def add_arguments(self, parser) -> None:
        super().add_arguments(parser)
        parser.add_argument("containers", help="continuum.containers/v1 file (or cluster_ros --json output)")
        parser.add_argument("--cluster", required=True, help="continuum.cluster/v1 file")
        parser.add_argument("--policy", default="superclustering", help=f"one of {', '.join([*POLICIES, *ALIASES])}")
        parser.add_argument("--graph", default=None, help="ROS graph: container bandwidth by Definition 3.2.1")
        parser.add_argument("--weights", default=None, help="scoring weights, e.g. bandwidth=1,node_affinity=1")
        parser.add_argument("--seed", type=int, default=0, help="tie-break seed of the default-Kubernetes policy")
        parser.add_argument("--overhead-mib", type=float, default=0.0, help="runtime memory per container")
        parser.add_argument("--compare", action="store_true", help="also report the other policy's traffic")
        parser.add_argument(
            "--free-drivers",
            action="store_true",
            help="let driver-level ROS nodes leave the robot's boards (default: CONTINUUM_DRIVERS_ON_ROBOT)",
        )
        parser.add_argument("--robot-label", default=None, help="key=value of the robot's boards (default zone=robot)")

    def run(self, **options: Any) -> dict:
        graph = load_rosgraph(self.read_text(options["graph"])) if options.get("graph") else None
        workload = load_workload(self.read_json(options["containers"]), graph, resource_model())
        cluster = Cluster.from_dict(self.read_json(options["cluster"]))
        params: dict[str, Any] = {
            "overhead_mib": options.get("overhead_mib") or 0.0,
            "seed": options.get("seed", 0),
            "drivers_on_robot": settings.CONTINUUM_DRIVERS_ON_ROBOT and not options.get("free_drivers"),
            "robot_label": options.get("robot_label") or settings.CONTINUUM_ROBOT_LABEL,
        }
        if options.get("weights"):
            params["weights"] = parse_weights(options["weights"])
        policy = options.get("policy") or "superclustering"
        plan = place(policy, workload, cluster, **params)
        out = plan.to_dict()
        out["bandwidth_unit"] = "bytes/s"
        if options.get("compare"):
            other = "default-kubernetes" if plan.policy == "superclustering" else "superclustering"
            params.pop("weights", None)
            alt = place(other, workload, cluster, **params)
            out["comparison"] = {
                other: {
                    "inter_node_bandwidth": alt.metrics["inter_node_bandwidth"],
                    "placements": alt.to_dict()["placements"],
                    "pending": [d.item for d in alt.decisions if d.pending],
                }
            }
        return out

    def summary(self, result: dict) -> str:
        lines = [f"{result['policy']}: {len(result['placements'])} placed, {len(result['pending'])} pending"]
        for p in result["placements"]:
            lines.append(f"  {p['container']:>24} -> {p['node']:<16} score {p['score']:g}")
        for p in result["pending"]:
            lines.append(f"  {p['container']:>24} pending:")
            for node, reason in p["reasons"].items():
                lines.append(f"  {'':>26}{node}: {reason}")
        inter = result["inter_node_bandwidth"]
        lines.append(f"  inter-node bandwidth: {inter:.1f} B/s ({inter * 8 / 1e6:.3f} Mbps)")
        for name, alt in result.get("comparison", {}).items():
            lines.append(f"  {name} would leave {alt['inter_node_bandwidth']:.1f} B/s between nodes")
        for warning in result.get("off_robot_drivers", []):
            lines.append(f"  warning: {warning['message']}")
        return "\n".join(lines)


def parse_weights(text: str) -> dict[str, float]:
    weights = {}
    for part in text.split(","):
        key, sep, value = part.partition("=")
        try:
            weights[key.strip()] = float(value)
        except ValueError:
            sep = ""
        if not sep or not key.strip():
            raise InputError(f"--weights: expected policy=weight pairs, got {part!r}", "weights")
    return weights

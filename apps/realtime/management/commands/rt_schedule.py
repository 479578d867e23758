"""``python manage.py rt_schedule RTSET --cluster FILE [--json]``: RT-Kube's sort/filter/score/bind (thesis 3.4).

The output is bounded whatever the cluster's size: on more than ``rt_kube_vec.FULL_UP_TO`` (32) nodes each
decision keeps its best candidates with their scores, the count of nodes each filter rejected
(``rejections``, also on every ``pending`` entry) and one example node per filter (the ``reasons``); on a
smaller cluster every node's reason for the pending containers, as before. ``--explain POD`` adds one
container's verdict on every node (``explain``), taken at its turn in the queue; ``--explain`` alone, every
container's on every node (for small clusters: 1,000 pods on 5,000 nodes make millions of rows).

With ``--cluster-id ID`` instead of ``--cluster FILE`` the what-if runs on a stored cluster: its nodes (RT
attributes, taints, the monitor's active taints), the reservations of its bound pods, and its RealTime
objects when no RTSET is given (the same pass as the ``rt_whatif`` job, without storing the plan).
"""

from __future__ import annotations

from typing import Any

from continuum.commands import EngineCommand
from continuum.engine.core.errors import InputError
from continuum.engine.rtkube import rt_kube, rt_kube_vec
from continuum.engine.rtkube.rt_model import cluster_from_dict, realtime_from_yaml, rtset_from_dict, rtset_to_dict


class Command(EngineCommand):
    help = (
        "Place real-time containers (continuum.rtset/v1, or RealTime YAML) on a cluster (continuum.cluster/v1) "
        "with RT-Kube's admission test, criticality separation and scores; unfit containers stay pending."
    )

    def add_arguments(self, parser) -> None:
        super().add_arguments(parser)
        parser.add_argument(
            "rtset", nargs="?", help="continuum.rtset/v1 JSON file, or a YAML file of RealTime resources"
        )
        target = parser.add_mutually_exclusive_group(required=True)
        target.add_argument("--cluster", help="continuum.cluster/v1 file")
        target.add_argument("--cluster-id", type=int, help="a stored cluster (default RTSET: its RealTime objects)")
        parser.add_argument(
            "--fresh", action="store_true", help="with --cluster-id: ignore the pods bound now (empty ledger)"
        )
        parser.add_argument("--k", type=float, default=None, help="Eq. 3.18's K (default 2)")
        parser.add_argument(
            "--b-score-argument",
            choices=("free", "load"),
            default=None,
            help="argument of h/g for criticality B: free capacity nRank (Eq. 3.18, default) or load 1 - nRank",
        )
        parser.add_argument(
            "--sort-tiebreak",
            choices=("arrival", "utilization"),
            default=None,
            help="queue order within a criticality class (default: arrival)",
        )
        parser.add_argument(
            "--explain",
            nargs="?",
            const=EVERY,
            default=None,
            metavar="POD",
            help="POD's filter or score on every node (without POD: every container's, only for small clusters)",
        )

    def run(self, **options: Any) -> dict:
        if options.get("cluster_id") is not None:
            return self.run_stored(**options)
        if not options.get("rtset"):
            raise InputError("give the RTSET file (or --cluster-id to use a stored cluster's RealTime objects)")
        nodes = cluster_from_dict(self.read_json(options["cluster"]))
        names = [n.name for n in nodes]
        path = options["rtset"]
        if path.endswith((".yaml", ".yml")):
            containers = realtime_from_yaml(self.read_text(path), names)
        else:
            containers = rtset_from_dict(self.read_json(path), names)
        if not containers:
            raise InputError(f"{path}: no containers")
        kwargs = {}
        for opt, key in (("k", "k"), ("b_score_argument", "b_score_argument"), ("sort_tiebreak", "sort_tiebreak")):
            if options.get(opt) is not None:
                kwargs[key] = options[opt]
        explain = _explained(options.get("explain"), [c.name for c in containers])
        plan = rt_kube_vec.schedule(
            containers, nodes, rt_kube.RTKubeParams(**kwargs), full=_full(options, len(nodes)), explain=explain
        )
        return _result(plan, options.get("explain"))

    def run_stored(self, **options: Any) -> dict:
        from apps.clusters.models import Cluster
        from apps.realtime import planning

        cluster = Cluster.objects.filter(pk=options["cluster_id"]).first()
        if cluster is None:
            raise InputError(f"cluster {options['cluster_id']} does not exist", "cluster")
        rtset = None
        path = options.get("rtset")
        if path and path.endswith((".yaml", ".yml")):
            names = [n.name for n in cluster.nodes.all()]
            rtset = rtset_to_dict(realtime_from_yaml(self.read_text(path), names))
        elif path:
            rtset = self.read_json(path)
        params = {k: options[k] for k in ("k", "b_score_argument", "sort_tiebreak") if options.get(k) is not None}
        full = _full(options, cluster.nodes.count())
        explain = options.get("explain")
        plan = planning.whatif(
            cluster,
            rtset=rtset,
            params=params,
            with_bound=not options.get("fresh"),
            full=full,
            explain=None if explain == EVERY else explain,
        )
        return _result(plan, options.get("explain"))

    def summary(self, result: dict) -> str:
        lines = [f"RT-Kube: {len(result['placements'])} placed, {len(result['pending'])} pending"]
        for p in result["placements"]:
            lines.append(f"  {p['container']:>24} -> {p['node']:<16} score {p['score']:.4f}")
        for p in result["pending"]:
            counts = p.get("rejections")
            lines.append(f"  {p['container']:>24} pending:")
            if counts:
                lines.append(f"  {'':>26}" + ", ".join(f"{n} nodes: {f}" for f, n in counts.items()))
            for node, reason in p["reasons"].items():
                lines.append(f"  {'':>26}{node}: {reason}" + (" (example)" if counts else ""))
        thresholds = result.get("thresholds", {})
        lines.append("utilization:")
        for node, u in result["utilization"].items():
            lines.append(f"  {node:<16} {u:.4f} of {thresholds.get(node, float('nan')):.4f}")
        return "\n".join(lines)


#: ``--explain`` without a pod: every container.
EVERY = "*"


def _full(options: dict[str, Any], n_nodes: int) -> str:
    """Every node's verdict for every container with a bare ``--explain``; for the pending ones on a small
    cluster (the contract's ``reasons``); otherwise the bounded form, whose size does not grow with nodes."""
    if options.get("explain") == EVERY:
        return "all"
    return "pending" if n_nodes <= rt_kube_vec.FULL_UP_TO else "none"


def _explained(pod: str | None, names: list[str]) -> str | None:
    if pod is None or pod == EVERY:
        return None
    if pod not in names:
        raise InputError(f"--explain: no container named {pod!r} in the RT set", "explain")
    return pod


def _result(plan: Any, explain: str | None) -> dict:
    result = plan.to_dict()
    if explain == EVERY:
        result["explain"] = rt_kube.explain(plan)
    elif explain is not None:
        decision = plan.decision(explain)
        if decision is None:
            raise InputError(f"--explain: no container named {explain!r} in the RT set", "explain")
        result["explain"] = rt_kube.explain(type(plan)(plan.policy, [decision]))
    return result

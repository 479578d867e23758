"""``python manage.py heft4k DAG --cluster FILE [--fail NODE ...] [--json]`` (thesis 3.3.2, Algorithm 2)."""

from __future__ import annotations

from typing import Any

from continuum.commands import EngineCommand
from continuum.engine.core.cluster import cluster_platform
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import ROUTINGS
from continuum.engine.formats import load_dag
from continuum.engine.heft4k.heft4k import heft4k, placements
from continuum.engine.heft4k.k8s_baselines import Unschedulable, run_heft4k, run_heft_k8s, run_k8s_default
from continuum.engine.heft4k.remap import remap


class Command(EngineCommand):
    help = (
        "Map a DAG on a cluster with HEFT4K: HEFT (look-ahead) task-to-node mapping and Eq. 3.16 niceness; "
        "with --fail, remap after those nodes go offline (Algorithm 2: partial or total)."
    )

    def add_arguments(self, parser) -> None:
        super().add_arguments(parser)
        parser.add_argument("dag", help="DAG file (continuum.dag/v1, WfFormat, ...); task costs name nodes or classes")
        parser.add_argument("--format", dest="dag_format", default=None, help="DAG format (default: guessed)")
        parser.add_argument("--cluster", required=True, help="continuum.cluster/v1 file")
        parser.add_argument(
            "--fail", nargs="+", action="extend", default=[], metavar="NODE", help="nodes that went offline"
        )
        parser.add_argument("--threshold", type=float, default=0.2, help="lost HEFT-rank share for a total remap")
        parser.add_argument("--nice-high", type=int, default=0, help="niceness of the top-ranked task (Eq. 3.16)")
        parser.add_argument("--nice-low", type=int, default=19, help="niceness of a rank-0 task (Eq. 3.16)")
        parser.add_argument("--plain", action="store_true", help="plain HEFT instead of the look-ahead variant")
        parser.add_argument("--routing", choices=ROUTINGS, default="ospf", help="path rule between unlinked nodes")
        parser.add_argument(
            "--simulate",
            action="store_true",
            help="also run the CFS simulator: default Kubernetes, HEFT on Kubernetes and HEFT4K makespans",
        )

    def run(self, **options: Any) -> dict:
        if not 0.0 <= options["threshold"] <= 1.0:
            raise InputError(f"--threshold must be a fraction in [0, 1], not {options['threshold']!r}", "threshold")
        dag = load_dag(self.read_text(options["dag"]), options["dag_format"])
        self.warn_about(dag)
        platform = cluster_platform(self.read_json(options["cluster"]), routing=options["routing"])
        nice = {"nice_high": options["nice_high"], "nice_low": options["nice_low"]}
        plan = heft4k(dag, platform, lookahead=not options["plain"], **nice)
        result: dict[str, Any] = {"algorithm": "heft4k", "params": plan.params}
        current, cluster = plan, platform
        if options["fail"]:
            done = remap(
                plan,
                dag,
                platform,
                options["fail"],
                threshold=options["threshold"],
                lookahead=not options["plain"],
                **nice,
            )
            current, cluster = done.schedule, platform.without(done.failed)
            result["remap"] = done.to_dict()
            result["initial"] = {"placements": placements(plan), "makespan": plan.makespan}
        result["placements"] = placements(current)
        result["makespan"] = current.makespan
        result["ranks"] = dict(current.ranks)
        if options["simulate"]:
            result["simulated"] = _simulate(dag, cluster, current)
        return result

    def summary(self, result: dict) -> str:
        lines = []
        if "remap" in result:
            r = result["remap"]
            lines.append(
                f"{r['mode']} remap after losing {', '.join(r['failed'])}: {r['reason']}; "
                f"lost {len(r['lost'])} tasks, moved {len(r['moved'])}; makespan {r['makespan_before']:g} -> "
                f"{r['makespan_after']:g} (computed in {r['elapsed_ms']:.1f} ms)"
            )
        lines.append(f"heft4k: predicted makespan {result['makespan']:g}, {len(result['placements'])} tasks")
        for p in result["placements"]:
            lines.append(
                f"  {p['task']:>20} on {p['node']:<12} cpu {p['core']} nice {p['niceness']:>3} "
                f"[{p['start']:g}, {p['finish']:g})"
            )
        for name, value in (result.get("simulated") or {}).items():
            lines.append(f"  simulated {name}: {'unschedulable' if value is None else f'{value:g}'}")
        return "\n".join(lines)


def _simulate(dag, platform, plan) -> dict[str, float | None]:
    try:
        k8s: float | None = run_k8s_default(dag, platform).makespan
    except Unschedulable:
        k8s = None
    except InputError:
        raise
    return {
        "k8s-default": k8s,
        "heft-k8s": run_heft_k8s(dag, platform, plan).makespan,
        "heft4k": run_heft4k(dag, platform, plan).makespan,
        "heft-ideal": plan.makespan,
    }

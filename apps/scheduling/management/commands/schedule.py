"""``python manage.py schedule DAG [--platform FILE | --cpus N --gpus M] --algorithm NAME [--json]``."""

from __future__ import annotations

from typing import Any

from apps.scheduling.jobs import with_defaults
from continuum.commands import EngineCommand
from continuum.engine import algorithms
from continuum.engine.errors import InputError
from continuum.engine.formats import load_dag
from continuum.engine.platform import Platform


class Command(EngineCommand):
    help = "Statically schedule a DAG (continuum JSON, WfFormat JSON, ...) on a platform."

    def add_arguments(self, parser) -> None:
        super().add_arguments(parser)
        parser.add_argument("dag", help="DAG file")
        parser.add_argument("--format", dest="dag_format", default=None, help="DAG format (default: guessed)")
        parser.add_argument("--platform", help="continuum.platform/v1 file")
        parser.add_argument("--cpus", type=int, default=None, help="number of CPU processors (class cpu)")
        parser.add_argument("--gpus", type=int, default=0, help="number of GPU processors (class gpu)")
        parser.add_argument("--algorithm", default="heft", help=f"one of {', '.join(sorted(algorithms.SCHEDULERS))}")
        parser.add_argument("--rank-mode", default=None, help="HEFT rank: mean or max")
        parser.add_argument("--frames", type=int, default=None, help="number of frames (pipelined)")
        parser.add_argument("--fps", type=float, default=None, help="camera rate for pipelined frames")
        parser.add_argument("--batch", type=int, default=None, help="frames buffered per batch")

    def run(self, **options: Any) -> dict:
        dag = load_dag(self.read_text(options["dag"]), options["dag_format"])
        if options["platform"]:
            if options["cpus"] is not None:
                raise InputError("give either --platform or --cpus/--gpus, not both")
            platform = Platform.from_dict(self.read_json(options["platform"]))
        else:
            platform = Platform.homogeneous(options["cpus"] if options["cpus"] is not None else 1, options["gpus"])
        params = {k: options[k] for k in ("rank_mode", "frames", "fps", "batch") if options[k] is not None}
        params = with_defaults(options["algorithm"], params)
        progress = self.progress_printer("scheduling")
        schedule = algorithms.run(options["algorithm"], dag, platform, progress=progress, **params)
        return schedule.to_dict()

    def summary(self, result: dict) -> str:
        lines = [f"{result['algorithm']}: makespan {result['makespan']:g}, {len(result['assignments'])} assignments"]
        for a in sorted(result["assignments"], key=lambda a: (a["start"], a["processor"])):
            lines.append(f"  {a['task']:>20} f{a['frame']} on {a['processor']:<12} [{a['start']:g}, {a['finish']:g})")
        return "\n".join(lines)

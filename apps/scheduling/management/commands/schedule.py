"""``python manage.py schedule DAG [--platform FILE | --cpus N --gpus M] --algorithm NAME [--frames N --fps F
--batch B] [--json]``.

The DAG may be continuum JSON, WfFormat JSON, a Kasahara STG file, a Pegasus DAX or the thesis
simulator's CSV; the format follows from ``--format``, else the file name (``.stg``, ``.xml``/``.dax``,
``.csv``), else the content. ``--frames/--fps/--batch`` schedule several frames with any algorithm
(:mod:`continuum.engine.device.pipeline`).
"""

from __future__ import annotations

import json
from typing import Any

from apps.scheduling.jobs import with_defaults
from apps.scheduling.serializers import FRAME_OPTIONS, ScheduleRequestSerializer
from apps.tenancy.api import contract_error
from continuum.commands import EngineCommand
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Platform
from continuum.engine.device import algorithms
from continuum.engine.device.board import board, shared_memory
from continuum.engine.formats import format_for_path, load_dag


def _key_values(pairs: list[str] | None, flag: str) -> dict[str, Any]:
    """``KEY=VALUE`` pairs; a value is read as JSON when it parses (numbers, true/false), else as text."""
    out: dict[str, Any] = {}
    for pair in pairs or []:
        key, sep, raw = pair.partition("=")
        if not sep or not key:
            raise InputError(f"{flag} expects KEY=VALUE, got {pair!r}", flag.lstrip("-"))
        try:
            out[key.replace("-", "_")] = json.loads(raw)
        except json.JSONDecodeError:
            out[key.replace("-", "_")] = raw
    return out


class Command(EngineCommand):
    help = "Statically schedule a DAG (continuum JSON, WfFormat, STG, DAX, thesis CSV) on a platform."

    def add_arguments(self, parser) -> None:
        super().add_arguments(parser)
        parser.add_argument("dag", help="DAG file")
        parser.add_argument(
            "--format", dest="dag_format", default=None, help="DAG format: continuum, wfformat, stg, dax, thesis_csv"
        )
        parser.add_argument(
            "--reader-option", action="append", metavar="KEY=VALUE", help="importer option, e.g. ccr=1 (STG)"
        )
        parser.add_argument("--platform", help="continuum.platform/v1 file")
        parser.add_argument("--cpus", type=int, default=None, help="number of CPU processors (class cpu)")
        parser.add_argument("--gpus", type=int, default=0, help="number of GPU processors (class gpu)")
        parser.add_argument("--cpu-speed", default=None, help="comma-separated speed per CPU core (with --cpus)")
        parser.add_argument(
            "--shared-memory",
            action="store_true",
            help="processors of one class share memory: only CPU<->GPU transfers cost (the thesis' board)",
        )
        parser.add_argument("--algorithm", default="heft", help=f"one of {', '.join(sorted(algorithms.SCHEDULERS))}")
        parser.add_argument("--rank-mode", default=None, help="upward rank cost: mean or max")
        parser.add_argument("--comm-mode", default=None, help="upward rank transfer: pairs or impl")
        parser.add_argument("--frames", type=int, default=None, help="number of frames (pipelined)")
        parser.add_argument("--fps", type=float, default=None, help="camera rate for pipelined frames")
        parser.add_argument("--period", type=float, default=None, help="frame period in the DAG's time unit")
        parser.add_argument("--batch", type=int, default=None, help="frames buffered per batch")
        parser.add_argument("--param", action="append", metavar="KEY=VALUE", help="algorithm parameter")
        parser.add_argument(
            "--progress",
            action="store_true",
            help="report progress on stderr even when it is not a terminal (always shown on a terminal)",
        )

    def run(self, **options: Any) -> dict:
        path = options["dag"]
        fmt = options["dag_format"] or format_for_path(path)
        reader_options = _key_values(options["reader_option"], "--reader-option")
        dag = load_dag(self.read_text(path), fmt, options=reader_options or None)
        self.warn_about(dag)
        platform = self._platform(options)
        # The API's request contract checks the algorithm and the frame options, with the API's messages.
        request = {k: options[k] for k in FRAME_OPTIONS if options[k] is not None}
        params = {k: options[k] for k in ("rank_mode", "comm_mode") if options[k] is not None}
        params.update(_key_values(options["param"], "--param"))
        request |= {"algorithm": options["algorithm"], "platform": platform.to_dict(), "params": params}
        contract = ScheduleRequestSerializer(data=request)
        if not contract.is_valid():
            raise contract_error(contract.errors)
        params = with_defaults(options["algorithm"], contract.validated_data["params"])
        progress = self.progress_printer(f"{options['algorithm']}, tasks placed", force=options["progress"])
        schedule = algorithms.run(options["algorithm"], dag, platform, progress=progress, **params)
        return schedule.to_dict()

    def _platform(self, options: dict[str, Any]) -> Platform:
        if options["platform"]:
            if options["cpus"] is not None or options["cpu_speed"]:
                raise InputError("give either --platform or --cpus/--gpus, not both")
            platform = Platform.from_dict(self.read_json(options["platform"]))
            return shared_memory(platform) if options["shared_memory"] else platform
        cpus = options["cpus"] if options["cpus"] is not None else 1
        speeds = None
        if options["cpu_speed"]:
            try:
                speeds = [float(x) for x in options["cpu_speed"].split(",")]
            except ValueError:
                raise InputError(f"--cpu-speed expects numbers, got {options['cpu_speed']!r}", "cpu_speed") from None
        if options["shared_memory"] or speeds:
            platform = board(cpus, options["gpus"], cpu_speed=speeds)
            return platform if options["shared_memory"] else _all_links_cost(platform)
        return Platform.homogeneous(cpus, options["gpus"])

    def summary(self, result: dict) -> str:
        lines = [f"{result['algorithm']}: makespan {result['makespan']:g}, {len(result['assignments'])} assignments"]
        metrics = result.get("metrics") or {}
        extra = [
            f"{k} {metrics[k]:.4g}"
            for k in ("mean_latency", "throughput_per_s", "xo", "idle", "slr")
            if isinstance(metrics.get(k), (int, float))
        ]
        if "buffers_used" in metrics and metrics.get("frames", 1) > 1:
            extra.append(f"buffers {metrics['buffers_used']}")
        if extra:
            lines.append("  " + ", ".join(extra))
        for a in sorted(result["assignments"], key=lambda a: (a["start"], a["processor"])):
            lines.append(f"  {a['task']:>20} f{a['frame']} on {a['processor']:<12} [{a['start']:g}, {a['finish']:g})")
        return "\n".join(lines)


def _all_links_cost(platform: Platform) -> Platform:
    """``platform`` without the board's free same-class links (``--cpu-speed`` without ``--shared-memory``)."""
    return Platform(list(platform.processors), bandwidth=1.0, latency=0.0)

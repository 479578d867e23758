"""``python manage.py allocate_monitors STATS.json [MORE.json ...] [--json]``.

Solves the monitor placement MILP (thesis §3.5, Eqs. 3.21-3.22) from handler statistics in the
``continuum.monitorstats/v1`` format. Several files are read as consecutive statistics periods: the
SMA filter averages them and the allocation is computed for the last one.
"""

from __future__ import annotations

import math
from typing import Any

from continuum.commands import EngineCommand
from continuum.engine.core.errors import InputError
from continuum.engine.verification.monitor_milp import DEFAULT_WORK_LIMIT, MonitorStats, StatsFilter, allocate


class Command(EngineCommand):
    help = "Place monitors on computing units with the Eq. 3.21-3.22 MILP from handler statistics."

    def add_arguments(self, parser) -> None:
        super().add_arguments(parser)
        parser.add_argument("stats", nargs="+", help="continuum.monitorstats/v1 file(s), oldest first")
        parser.add_argument("--window", type=int, default=10, help="SMA filter window over the files (default 10)")
        parser.add_argument("--epsilon", type=float, default=1e-3, help="migration penalty (default 1e-3)")
        parser.add_argument(
            "--work-limit",
            type=int,
            default=DEFAULT_WORK_LIMIT,
            help="branch-and-bound nodes per solve (the same allocation under any load)",
        )
        parser.add_argument(
            "--time-limit", type=float, default=None, help="optional wall-clock cap in seconds (load-dependent)"
        )
        parser.add_argument("--literal-topic-coupling", action="store_true", help="Eq. 3.21 read literally")
        parser.add_argument("--max-candidates", type=int, default=None, help="candidate units per monitor")

    def run(self, **options: Any) -> dict:
        smoother = StatsFilter(options["window"])
        observed: dict[tuple[str, str], float] = {}
        filtered = None
        for path in options["stats"]:
            stats = _load(self, path)
            filtered = smoother.update(stats)
            for monitor, per_node in filtered.monitor_cpu.items():
                for node, value in per_node.items():
                    observed[(monitor, node)] = value
        result = allocate(
            filtered,
            epsilon=options["epsilon"],
            literal_topic_coupling=options["literal_topic_coupling"],
            observed=observed,
            time_limit=math.inf if options.get("time_limit") is None else options["time_limit"],
            work_limit=_work_limit(options.get("work_limit")),
            max_candidates=options["max_candidates"],
        )
        return result.to_dict()

    def summary(self, result: dict) -> str:
        state = "feasible" if result["feasible"] else "OVERLOADED"
        lines = [
            f"{state} ({result['status']}): total delay {result['objective']:g} ms, "
            f"{len(result['migrations'])} migration(s), solved in {result['solve_time_ms']:g} ms"
        ]
        for node, share in result["cpu"].items():
            count = sum(1 for n in result["allocation"].values() if n == node)
            over = f"  over by {result['overloaded'][node]:g}" if node in result["overloaded"] else ""
            lines.append(f"  {node:<16} {count:>5} monitors  {share:7.2f} % of {result['capacity'][node]:.2f} %{over}")
        if result["drop_events"]:
            lines.append(f"  drop events and reset: {', '.join(result['drop_events'])}")
        return "\n".join(lines)


def _load(command: EngineCommand, path: str) -> MonitorStats:
    try:
        return MonitorStats.from_dict(command.read_json(path))
    except InputError as exc:
        if str(exc).startswith(path):
            raise
        raise InputError(f"{path}: {exc}", field=exc.field) from None


def _work_limit(value: int | None) -> int:
    if value is None:
        return DEFAULT_WORK_LIMIT
    if value < 1:
        raise InputError(f"--work-limit must be at least 1, got {value}", "work_limit")
    return value

"""``python manage.py stl_check --assertion TEXT TRACE.csv [--const NAME=VALUE ...] [--json]``.

Evaluates an assertion of the Fig. 3.40 grammar over a trace (a ``time`` column in milliseconds plus one
column per signal) and reports each violation with its time (thesis §3.5; CONTRACTS.md).
"""

from __future__ import annotations

from typing import Any

from continuum.commands import EngineCommand
from continuum.engine.core.errors import InputError
from continuum.engine.verification.stl_monitor import check_trace, parse_trace_csv, synthesize


class Command(EngineCommand):
    help = "Check an STL assertion (Fig. 3.40 grammar) over a CSV trace and report its violations."

    def add_arguments(self, parser) -> None:
        super().add_arguments(parser)
        parser.add_argument("trace", help="CSV file: a 'time' column (ms) and one column per signal")
        parser.add_argument("--assertion", required=True, help="e.g. 'G(speed > 0 -> F[0,5000](arrived))'")
        parser.add_argument(
            "--const", action="append", default=[], metavar="NAME=VALUE", help="a named number (repeatable)"
        )
        parser.add_argument(
            "--instant-mode",
            choices=["timestamp", "event"],
            default="timestamp",
            help="one instant per timestamp (default) or per event",
        )
        parser.add_argument("--until-inclusive", action="store_true", help="U also needs its left side at t'")

    def run(self, **options: Any) -> dict:
        constants = _constants(options["const"])
        program = synthesize(options["assertion"], constants)
        events, signals = parse_trace_csv(self.read_text(options["trace"]), source=options["trace"])
        missing = sorted(program.variables - set(signals))
        if missing:
            raise InputError(
                f"signal {missing[0]!r} used by the assertion is not a column of {options['trace']} "
                f"(columns: {', '.join(signals) or 'none'})",
                field="assertion",
            )
        result = check_trace(
            program, events, instant_mode=options["instant_mode"], until_inclusive=options["until_inclusive"]
        )
        out = result.to_dict()
        out.update(
            assertion=program.text,
            skeleton=program.skeleton,
            placeholders={p.name: p.text for p in program.placeholders},
        )
        return out

    def summary(self, result: dict) -> str:
        violations = result["violations"]
        head = f"{result['verdict']}: {len(violations)} violation(s) over {result['events']} events"
        head += f" ({result['instants']} instants, {result['pending']} pending at the end)"
        lines = [head, f"  monitor: {result['skeleton']}"]
        lines += [f"    {name} = {text}" for name, text in result["placeholders"].items()]
        for v in violations[:50]:
            lines.append(f"  t={v['time']:g}: instance started at t={v['instance_start']:g} failed")
        if len(violations) > 50:
            lines.append(f"  ... and {len(violations) - 50} more")
        return "\n".join(lines)


def _constants(items: list[str]) -> dict[str, float]:
    out = {}
    for item in items:
        name, sep, value = item.partition("=")
        if not sep or not name.strip():
            raise InputError(f"--const {item!r}: expected NAME=VALUE", field="const")
        try:
            out[name.strip()] = float(value)
        except ValueError:
            raise InputError(f"--const {item!r}: {value!r} is not a number", field="const") from None
    return out

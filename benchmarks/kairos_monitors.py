"""The thesis's two ABV case studies, simulated (continuum/engine/verification/abv_simulation.py), next to the thesis's
figures.

    python benchmarks/kairos_monitors.py [--scenario kairos|synthetic|both] [--time-limit S] [--json FILE]

* RB-Kairos (§4.5.2, Fig. 4.24): MCB / Jetson Xavier NX / server with 40 / 60 / 90 % thresholds, 201
  monitors that start on the Jetson; the navigation chain's makespan (spec 03 §13.2's contention model)
  against the 125 ms requirement, the navigation assertion checked on the robot's pose trace.
* Synthetic three-level cluster (§4.5.1, Fig. 4.22): edge / desktop / server, 50 monitors, the testbench
  load profile; the thesis reports 27 ms of MILP per 1 s period.

Prints a timeline (monitors and CPU per node every few seconds, migrations) and the summary against the
thesis. Every figure printed is from this run; the thesis's are labelled.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from continuum.engine.verification.abv_simulation import scenario, simulate

THESIS = {
    "kairos": {
        "makespan without verification": "115 ms (8.7 Hz)",
        "makespan, 201 monitors on the Jetson": "140 ms (7.1 Hz)",
        "makespan after the migration": "125 ms (8 Hz), 150 monitors moved Jetson -> server",
        "navigation assertion": "fails with every monitor on the Jetson, holds after the migration",
    },
    "synthetic": {
        "edge -> desktop": "20 monitors at 22 s, the other 30 at 23 s",
        "desktop -> server": "all 50 at once after 40 s",
        "overload": "65-87 s: 8 % available, 18 % needed, events dropped, verification 7.5 % on average",
        "back to the edge": "all 50 at 105 s",
        "MILP": "27 ms per 1 s period on average",
    },
}


def timeline(result, every: int) -> None:
    nodes = result.nodes
    head = f"{'t (s)':>6}  " + "  ".join(f"{n:>14}" for n in nodes)
    extra = "  makespan" if result.requirement_ms else ""
    print(head + extra + "   migrations")
    moved: dict[float, list] = {}
    for m in result.migrations:
        moved.setdefault(m.t, []).append(m)
    for p in result.periods:
        ms = moved.get(p.t, [])
        if p.t % every and not ms:
            continue
        cells = "  ".join(f"{p.monitors[n]:>4} @ {p.cpu[n]:5.1f} %" for n in nodes)
        span = f"  {p.makespan_ms:6.1f} ms" if p.makespan_ms is not None else ""
        flows: dict[tuple[str, str], int] = {}
        for m in ms:
            flows[(m.source, m.target)] = flows.get((m.source, m.target), 0) + 1
        note = ", ".join(f"{n} {a}->{b}" for (a, b), n in sorted(flows.items()))
        drop = {n: v for n, v in p.dropped.items() if v}
        if drop:
            note += "  dropping " + ", ".join(f"{n} {v:.0%}" for n, v in drop.items())
        print(f"{p.t:6.0f}  {cells}{span}   {note}")


def report(name: str, time_limit: float, every: int) -> dict:
    sc = scenario(name, time_limit=time_limit)
    started = time.perf_counter()
    result = simulate(sc)
    elapsed = time.perf_counter() - started
    print(f"\n=== {sc.name}: {len(sc.monitors)} monitors on {', '.join(result.nodes)} "
          f"(thresholds {result.thresholds}), simulated in {elapsed:.1f} s ===")  # fmt: skip
    timeline(result, every)
    summary = result.summary()
    print("\nmeasured:")
    for key, value in summary.items():
        print(f"  {key:<32} {value}")
    if result.violations:
        print("  navigation violations at", ", ".join(f"{v['time'] / 1000:g} s" for v in result.violations))
    print("thesis:")
    for key, value in THESIS[name].items():
        print(f"  {key:<32} {value}")
    return result.to_dict()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenario", choices=["kairos", "synthetic", "both"], default="both")
    parser.add_argument("--time-limit", type=float, default=0.9, help="MILP budget per 1 s period")
    parser.add_argument("--every", type=int, default=5, help="print a period every N seconds")
    parser.add_argument("--json", help="write the full results here")
    args = parser.parse_args()
    names = ["synthetic", "kairos"] if args.scenario == "both" else [args.scenario]
    out = {name: report(name, args.time_limit, args.every) for name in names}
    if args.json:
        Path(args.json).write_text(json.dumps(out))


if __name__ == "__main__":
    main()

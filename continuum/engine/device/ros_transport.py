"""ROS-compliant CPU-iGPU communication: which ROS transport to use (thesis 3.1.3, 4.1.3, Fig. 3.10-3.17).

Porting CUDA code to ROS nodes naively (ROS-SC: every message is serialised and copied, Fig. 3.10-3.11)
costs hundreds to thousands of per cent (Tables 4.11-4.14); native intra-process ROS zero copy (ROS-ZC,
Fig. 3.12/3.16) cuts that about 100x but works only inside one process, for one subscriber, and stops
CPU/GPU overlap; the proposed ROS-SHM-ZC (Fig. 3.13-3.14, 3.17) keeps the data in one OS shared-memory
segment and sends only synchronisation messages, and is the best choice everywhere (2-14 % with 2-3
nodes). Rules [PROPOSAL of spec 01 section 10.5]:
1. if any communicating node is off the UMA board, use ROS-SC over a topic (M1 with workers, else A1);
2. otherwise ROS-SHM-ZC over a topic: with N + M >= 2 workers sharing the buffer, the scheduler-node
   architecture M3 (Fig. 3.17), else the two-node A4 (CUDA SC/UM, Fig. 3.13) or A5 (CUDA ZC, Fig. 3.14);
3. never a service when a topic is possible (services were always slower);
4. native ROS-ZC only for exactly one subscriber inside one process (offered as an alternative).
The node count is the producer (or scheduler) plus the N CPU and M GPU workers; the topic count is
``1 + N + M``; data instances: ROS-SC one per node plus a GPU copy per GPU worker, native ROS-ZC ``N + M - 1``
with several receivers (1 with one), ROS-SHM-ZC 1. The expected overhead is looked up in Tables 4.11-4.14
(``data/ros_transport.json``) as a prior: the row of the same architecture, CUDA model and transport with
the nearest node count (2, 3 or 5).
"""

from __future__ import annotations

import json
from functools import cache
from pathlib import Path
from typing import Any

from continuum.engine.core.errors import InputError

__all__ = ["BOARDS", "DATA", "ros_overhead", "ros_transport_advice", "table"]

DATA = Path(__file__).resolve().parent / "data"
#: Device profile ids -> the board columns of Tables 4.10-4.14 (the Nano was excluded: "equivalent to TX2").
BOARDS = {"tx2": "tx2", "jetson-tx2": "tx2", "xavier": "xavier", "jetson-agx-xavier": "xavier", "jetson-nano": "tx2"}


@cache
def table() -> dict[str, Any]:
    """Tables 4.10-4.14 as published (``data/ros_transport.json``)."""
    return json.loads((DATA / "ros_transport.json").read_text())


def ros_overhead(time_ms: float, reference_ms: float) -> float:
    """The overhead convention of Tables 4.11-4.14, in %: ``(T - T_ref) / T_ref``."""
    if reference_ms <= 0:
        raise InputError("the reference time must be positive", "reference_ms")
    return 100.0 * (time_ms - reference_ms) / reference_ms


def _prior(nodes: int, cuda: str, ros_copy: str, board: str | None) -> dict[str, Any] | None:
    rows = [r for r in table()["rows"] if r["ros_copy"] == ros_copy and r["ros_type"] == "topic"]
    if not rows:
        return None
    sizes = sorted({r["nodes"] for r in rows})
    size = min(sizes, key=lambda s: (abs(s - nodes), -s))
    same_size = [r for r in rows if r["nodes"] == size]
    row = next((r for r in same_size if r["cuda"] == cuda), same_size[0])
    pct = row["overhead_pct"] if board is None else {board: row["overhead_pct"][board]}
    return {
        "overhead_pct": pct,
        "from": f"{row['nodes']} nodes, Fig. {row['figure']}, CUDA {row['cuda']}, {row['ros_copy']} {row['ros_type']}",
        "extrapolated": size != nodes,
    }


def ros_transport_advice(
    cpu_workers: int,
    gpu_workers: int,
    *,
    cuda_model: str = "SC",
    off_board: bool = False,
    single_process: bool = False,
    board: str | None = None,
) -> dict[str, Any]:
    """Advise the ROS transport for N CPU and M GPU tasks sharing one buffer (see the module docstring).

    ``off_board``: some communicating node runs off the UMA board; ``single_process``: all nodes are
    threads of one process; ``cuda_model``: SC, UM, ZC or ZC_CONDITIONAL (the UMA advisor's output);
    ``board``: a device id or ``tx2``/``xavier`` to pick that board's priors.
    """
    n, m = cpu_workers, gpu_workers
    if isinstance(n, bool) or isinstance(m, bool) or not isinstance(n, int) or not isinstance(m, int):
        raise InputError("cpu_workers and gpu_workers must be integers", "workers")
    if n < 0 or m < 0 or n + m == 0:
        raise InputError("need at least one CPU or GPU worker sharing the buffer", "workers")
    model = str(cuda_model).upper().replace("ZC_CONDITIONAL", "ZC").replace("SC/UM", "SC")
    if model not in ("SC", "UM", "ZC"):
        raise InputError(f"unknown CUDA model {cuda_model!r} (SC, UM or ZC)", "cuda_model")
    cuda = "ZC" if model == "ZC" else "SC"
    column = None
    if board is not None:
        if board not in BOARDS:
            raise InputError(f"no ROS measurements for board {board!r} (known: {', '.join(BOARDS)})", "board")
        column = BOARDS[board]
    workers = n + m
    nodes = 1 + workers
    instances = {
        "ROS-SC": nodes + m,
        "ROS-ZC": workers - 1 if workers >= 2 else 1,
        "ROS-SHM-ZC": 1,
    }
    reasons = []
    if off_board:
        transport = "ROS-SC"
        architecture, figure = ("M1", "3.15") if workers >= 2 else ("A1", "3.10")
        reasons.append("a communicating node runs off the UMA board: shared memory cannot reach it")
        if cuda == "ZC":
            reasons.append("ROS-SC falls back to copies; the CUDA ZC buffer stays local to the board")
    else:
        transport = "ROS-SHM-ZC"
        if workers >= 2:
            architecture, figure = "M3", "3.17"
            reasons.append(f"{workers} workers share the buffer: a scheduler node sends sync messages (M3)")
        else:
            architecture, figure = ("A5", "3.14") if cuda == "ZC" else ("A4", "3.13")
        reasons.append("all nodes share the UMA board: one shared-memory segment, topics carry only references")
    reasons.append("a topic, never a service: services were always slower (Tables 4.11-4.14)")
    alternatives = []
    if not off_board and single_process and workers == 1:
        alternatives.append(
            {
                "transport": "ROS-ZC",
                "architecture": "A3",
                "figure": "3.12",
                "data_instances": 1,
                "note": "native intra-process zero copy: one subscriber only, and CPU and GPU cannot overlap",
                "prior": _prior(nodes, cuda, "ROS-ZC", column),
            }
        )
    if not off_board and single_process and workers >= 2:
        alternatives.append(
            {
                "transport": "ROS-ZC",
                "architecture": "M2",
                "figure": "3.16",
                "data_instances": instances["ROS-ZC"],
                "note": "only one receiver gets zero copy, unpredictably which; not with CUDA ZC",
                "prior": _prior(nodes, "SC", "ROS-ZC", column),
            }
        )
    return {
        "transport": transport,
        "ros_type": "topic",
        "architecture": architecture,
        "figure": figure,
        "cuda_model": model,
        "nodes": nodes,
        "topics": 1 + workers,
        "data_instances": instances[transport],
        "data_instances_by_transport": instances,
        "expected_overhead": _prior(nodes, cuda, transport, column),
        "alternatives": alternatives,
        "reasons": reasons,
    }

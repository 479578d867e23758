"""Chapter 4.1.1 from the generators: Tables 4.1-4.4 and Figs. 4.1-4.3 (used by ``benchmarks/thesis.py``).

Inputs are untuned: the synthetic Tree/Linear DAGs of spec 01 section 8.2 (:func:`thesis_dag`, seeds 0..N-1,
each with 2-5 cores and 3, 5 or 10 frames taken in turn) and, for Table 4.1, the thesis authors' public ORB-SLAM
graph (``tests/data/orb_graph.csv``, their simulator's input, not a result). Everything runs in the engine's model
(``how = model``): HEFT's phase 2 with insertion, the thesis' ``max`` rank and implementation-kind transfers.
"""

from __future__ import annotations

import statistics
import sys
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from continuum.engine.device import overlap as ov  # noqa: E402
from continuum.engine.device.board import board  # noqa: E402
from continuum.engine.device.generators import thesis_dag  # noqa: E402
from continuum.engine.device.pipeline import pipeline  # noqa: E402
from continuum.engine.formats import load_dag  # noqa: E402

ALGORITHMS = ("gfl", "heft", "gfl_c", "xeft")
FRAMES = (3, 5, 10)
RANKS = {"rank_mode": "max", "comm_mode": "impl"}


def _params(name: str) -> dict[str, Any]:
    return RANKS if name in ("heft", "xeft", "gfl_c") else {}


def run_dags(count: int) -> list[dict[str, Any]]:
    """Per generated DAG: class, cores, frames and, per algorithm, the single-frame schedule's figures and the
    batched pipeline's makespan, gain and buffers."""
    out = []
    for seed in range(count):
        dag = thesis_dag(seed)
        cores, frames = 2 + seed % 4, FRAMES[(seed // 4) % 3]
        plat = board(cores)
        row: dict[str, Any] = {
            "seed": seed,
            "class": dag.meta["class"],
            "tasks": len(dag),
            "cores": cores,
            "frames": frames,
        }
        for name in ALGORITHMS:
            one = pipeline(name, dag, plat, frames=1, gain=False, **_params(name))
            many = pipeline(name, dag, plat, frames=frames, gain=False, **_params(name))
            m = ov.schedule_metrics(one, dag, plat)
            row[name] = {
                "makespan": one.makespan,
                "xo_efficiency": m["xo_efficiency"],
                "idle": m["idle"],
                "pipelined": many.makespan,
                "gain": (frames * one.makespan - many.makespan) / (frames * one.makespan),
                "buffers": many.metrics.get("buffers_used"),
            }
        out.append(row)
    return out


def _mean(xs: list[float]) -> float | None:
    return round(statistics.mean(xs), 2) if xs else None


def xeft_vs_heft(rows: list[dict[str, Any]], cls: str) -> dict[str, Any]:
    """Figs. 4.1/4.2: XEFT's gain over HEFT (%, single frame) per DAG of a class, with HEFT's XO efficiency and
    idle time (the scatter's axes), and the means below and above 80 % XO efficiency."""
    points = []
    for r in rows:
        if r["class"] != cls:
            continue
        h, x = r["heft"], r["xeft"]
        points.append(
            {
                "xo_efficiency": h["xo_efficiency"],
                "idle": h["idle"],
                "gain_pct": (h["makespan"] - x["makespan"]) / h["makespan"] * 100,
            }
        )
    gains = [p["gain_pct"] for p in points]
    low = [p["gain_pct"] for p in points if (p["xo_efficiency"] or 0) < 0.8]
    high = [p["gain_pct"] for p in points if (p["xo_efficiency"] or 0) >= 0.8]
    return {
        "dags": len(points),
        "mean_gain_pct": _mean(gains),
        "wins": sum(g > 1e-9 for g in gains),
        "losses": sum(g < -1e-9 for g in gains),
        "largest_loss_pct": round(min(gains), 2) if gains else None,
        "mean_gain_xo_eff_below_80_pct": _mean(low),
        "mean_gain_xo_eff_80_or_more_pct": _mean(high),
        "points": points,
    }


def table_4_2(rows: list[dict[str, Any]]) -> dict[str, dict[str, float | None]]:
    """Mean pipeline gain (%) per class and cores ("c-Any") or frames ("Any-f"), per algorithm."""
    table: dict[str, dict[str, float | None]] = {}
    for cls in ("linear", "tree"):
        for key, pick in [(f"{c}-Any", ("cores", c)) for c in (2, 3, 4, 5)] + [
            (f"Any-{f}", ("frames", f)) for f in FRAMES
        ]:
            sel = [r for r in rows if r["class"] == cls and r[pick[0]] == pick[1]]
            table[f"{cls} {key}"] = {a: _mean([r[a]["gain"] * 100 for r in sel]) for a in ALGORITHMS}
    return table


def table_4_3(rows: list[dict[str, Any]]) -> dict[str, float | None]:
    """Table 4.3's headline cells, ``M_B / M_A - 1`` (%) on mean makespans; (p) = batched pipeline per frame."""
    mean = {a: statistics.mean(r[a]["makespan"] for r in rows) for a in ALGORITHMS}
    per_frame = {a: statistics.mean(r[a]["pipelined"] / r["frames"] for r in rows) for a in ALGORITHMS}

    def faster(a: float, b: float) -> float:
        return round((b / a - 1) * 100, 2)

    return {
        "XEFT vs G-FL": faster(mean["xeft"], mean["gfl"]),
        "XEFT vs G-FL_c": faster(mean["xeft"], mean["gfl_c"]),
        "G-FL_c vs G-FL": faster(mean["gfl_c"], mean["gfl"]),
        "XEFT(p) vs XEFT": faster(per_frame["xeft"], mean["xeft"]),
        "XEFT(p) vs G-FL_c(p)": faster(per_frame["xeft"], per_frame["gfl_c"]),
        "XEFT vs HEFT": faster(mean["xeft"], mean["heft"]),
    }


def table_4_4(rows: list[dict[str, Any]]) -> dict[str, dict[str, str]]:
    """Mean frame buffers used per allocated frames, as 'at 2 cores - at 5 cores' like the thesis."""
    out: dict[str, dict[str, str]] = {}
    for f in FRAMES:
        out[str(f)] = {}
        for a in ALGORITHMS:
            ends = [_mean([r[a]["buffers"] for r in rows if r["frames"] == f and r["cores"] == c]) for c in (2, 5)]
            out[str(f)][a] = "-".join("?" if e is None else f"{e:.1f}" for e in ends)
    return out


def fig_4_3(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """Fig. 4.3 (4 cores, 5 frames, Linear): pipeline gain against the single-frame idle time, HEFT and XEFT."""
    sel = [r for r in rows if r["class"] == "linear" and r["cores"] == 4 and r["frames"] == 5]
    out: dict[str, Any] = {"dags": len(sel)}
    for a in ("heft", "xeft"):
        xs, ys = [r[a]["idle"] for r in sel], [r[a]["gain"] for r in sel]
        out[f"{a}_corr_idle_gain"] = round(statistics.correlation(xs, ys), 2) if len(sel) > 2 else None
    return out


def table_4_1() -> dict[str, Any]:
    """XEFT on HEFT, ``(M_H - M_X) / M_H`` (%), on the authors' ORB-SLAM graph (one frame), 2-5 cores."""
    dag = load_dag((ROOT / "tests" / "data" / "orb_graph.csv").read_bytes())
    out = {}
    for cores in (2, 3, 4, 5):
        plat = board(cores)
        h = pipeline("heft", dag, plat, gain=False, **RANKS).makespan
        x = pipeline("xeft", dag, plat, gain=False, **RANKS).makespan
        out[f"{cores} cores"] = round((h - x) / h * 100, 2)
    return out

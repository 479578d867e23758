"""Figures of the scheduling pages: a comparison's Gantt charts on one time axis and its figures as bars."""

from __future__ import annotations

import math
from collections.abc import Mapping

import plotly.graph_objects as go
from plotly.subplots import make_subplots

from apps.ui.charts import GanttPanel, base_layout, esc, escs, gantt_rows, stacked_gantt_figure
from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import Schedule


def comparison_figure(
    schedules: list[tuple[str, Schedule]],
    platform: Platform | None = None,
    dag: TaskGraph | None = None,
    time_unit: str | None = None,
) -> go.Figure:
    """One Gantt chart per (algorithm, schedule), stacked on a shared time axis by
    :func:`stacked_gantt_figure`: frames share their colours across the charts (one legend entry each) and
    every chart marks its critical path (when ``dag`` and ``platform`` are given) and its makespan."""
    panels = [
        GanttPanel(
            name.upper(),
            schedule,
            platform,
            schedule.critical_path(dag, platform) if dag is not None and platform is not None else (),
        )
        for name, schedule in schedules
    ]
    unit = time_unit or (dag.time_unit if dag is not None else "")
    fig = stacked_gantt_figure(panels, unit, title_sep=": ")
    keep_idle_rows(fig, panels)
    return fig


def keep_idle_rows(fig: go.Figure, panels: list[GanttPanel], lanes: bool = True, stacked: bool = True) -> None:
    """Every processor's row in every panel, idle ones too (a GPU that XEFT or HEFT leaves unused): a category
    axis shows only the categories some trace uses, so each panel gets an invisible marker per row.
    ``stacked``: ``fig`` has one subplot per panel (:func:`stacked_gantt_figure`), else it is one chart."""
    for i, panel in enumerate(panels, start=1):
        rows, _ = gantt_rows(panel.schedule, panel.platform, lanes)
        fig.add_trace(
            go.Scatter(
                x=[0.0] * len(rows),
                y=escs(rows),
                mode="markers",
                marker={"opacity": 0},
                hoverinfo="skip",
                showlegend=False,
                name="rows",
            ),
            **({"row": i, "col": 1} if stacked else {}),
        )


#: The figures drawn by :func:`comparison_bars_figure`: (result key, title, scale, unit); unit "time" is the
#: DAG's time unit, "rate" frames per second (or per time unit when it is not one of :data:`PER_SECOND`).
COMPARISON_FIGURES = [
    ("makespan", "makespan", 1.0, "time"),
    ("slr", "SLR (makespan / critical path)", 1.0, ""),
    ("speedup_vs_visionworks", "speedup vs VisionWorks", 100.0, "%"),
    ("overlap", "overlap O(A)", 1.0, "time"),
    ("xo", "exclusive overlap XO(A)", 1.0, "time"),
    ("idle", "idle time", 100.0, "%"),
    ("mean_latency", "mean frame latency", 1.0, "time"),
    ("throughput", "throughput", 1.0, "rate"),
]
ALGORITHM_COLOURS = ["#4c78a8", "#f58518", "#54a24b", "#b279a2", "#9d755d", "#72b7b2", "#eeca3b", "#79706e"]
#: Time units a throughput "frames per unit" converts from to frames/s (the unit's count in one second).
PER_SECOND = {"s": 1.0, "ms": 1e3, "us": 1e6, "µs": 1e6, "ns": 1e9}


def rate_unit(time_unit: str) -> tuple[str, float]:
    """The unit throughputs are shown in and the factor from "frames per ``time_unit``" to it: frames/s when
    the time unit converts, else frames per that unit (one spelling on every page)."""
    if time_unit in PER_SECOND:
        return "frames/s", PER_SECOND[time_unit]
    return f"frames per {time_unit or 'time unit'}", 1.0


def short_number(value: float) -> str:
    """A bar's label: four significant digits, never exponent notation for what an operator reads
    (55890 -> "55,890", 0.01234 -> "0.01234")."""
    if value == 0 or not math.isfinite(value):
        return f"{value:g}"
    if abs(value) >= 1000:
        return f"{value:,.0f}"
    if abs(value) >= 1e-4:
        return f"{value:.4g}" if "e" not in f"{value:.4g}" else f"{value:.6f}".rstrip("0")
    return f"{value:.3g}"


def normalisation_reference(results: Mapping[str, Mapping], algorithms: list[str]) -> str:
    """What ``normalise`` divides by: HEFT when compared, else the algorithm with the least makespan."""
    if "heft" in algorithms:
        return "heft"
    return min(algorithms, key=lambda a: results[a].get("makespan") or math.inf)


def comparison_bars_figure(
    results: Mapping[str, Mapping],
    algorithms: list[str] | None = None,
    time_unit: str = "",
    normalise: bool = False,
) -> go.Figure:
    """Bars per algorithm for each figure of a comparison (those present: latency and throughput with frames),
    with their units; ``normalise`` shows every figure relative to :func:`normalisation_reference`'s (x1 is
    the reference; figures it has as 0 or not at all are left out)."""
    names = list(algorithms or results)
    rate, per_s = rate_unit(time_unit)
    ref = normalisation_reference(results, names) if normalise and names else ""
    figures = []
    for key, title, scale, unit in COMPARISON_FIGURES:
        if not any(results[a].get(key) is not None for a in names):
            continue
        if ref and not results[ref].get(key):
            continue
        factor = per_s if unit == "rate" else scale
        shown = {"time": time_unit, "rate": rate}.get(unit, unit)
        if ref:  # a ratio has no unit (and no per-cent scale)
            factor, shown = 1.0 / results[ref][key], f"x {ref.upper()}"
        figures.append((key, f"{title} ({shown})" if shown else title, factor, shown))
    cols = 4 if len(figures) > 6 else 3
    rows = max(1, math.ceil(len(figures) / cols))
    fig = make_subplots(rows=rows, cols=cols, subplot_titles=[t for _, t, _, _ in figures], vertical_spacing=0.2)
    colours = {a: ALGORITHM_COLOURS[i % len(ALGORITHM_COLOURS)] for i, a in enumerate(names)}
    for i, (key, title, factor, unit) in enumerate(figures):
        values = [results[a].get(key) for a in names]
        scaled = [None if v is None else v * factor for v in values]
        suffix = f" {unit}" if unit and unit != "%" else unit
        fig.add_trace(
            go.Bar(
                x=[esc(a.upper()) for a in names],
                y=scaled,
                marker={"color": [colours[a] for a in names]},
                text=[short_number(v) if v is not None else "" for v in scaled],
                textposition="outside",
                cliponaxis=False,
                name=title,
                hovertemplate="%{x}: %{y:,.6~g}" + esc(suffix) + "<extra>" + esc(title) + "</extra>",
                showlegend=False,
            ),
            row=i // cols + 1,
            col=i % cols + 1,
        )
    base_layout(fig, height=170 + 250 * rows)
    fig.update_layout(margin={"l": 10, "r": 10, "t": 50, "b": 10})
    # Ticks keep Plotly's default (55k, 0.2); the bar labels are short_number's; the titles carry the units.
    fig.update_yaxes(
        showgrid=True, gridcolor="#e4e7eb", zeroline=True, zerolinecolor="#9aa5b1", rangemode="tozero", automargin=True
    )
    fig.update_annotations(font={"size": 13, "color": "#1f2933"})
    return fig

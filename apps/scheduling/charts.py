"""Figures of the scheduling pages: a comparison's Gantt charts on one time axis and its figures as bars."""

from __future__ import annotations

import math
from collections.abc import Mapping

import plotly.graph_objects as go
from plotly.subplots import make_subplots

from apps.ui.charts import GanttPanel, base_layout, esc, stacked_gantt_figure
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
    return stacked_gantt_figure(panels, unit, title_sep=": ")


#: The figures drawn by :func:`comparison_bars_figure`: (result key, title, scale).
COMPARISON_FIGURES = [
    ("makespan", "makespan", 1.0),
    ("slr", "SLR (makespan / critical path)", 1.0),
    ("speedup_vs_visionworks", "speedup vs VisionWorks (%)", 100.0),
    ("overlap", "overlap O(A)", 1.0),
    ("xo", "exclusive overlap XO(A)", 1.0),
    ("idle", "idle time (%)", 100.0),
    ("mean_latency", "mean frame latency", 1.0),
    ("throughput", "throughput (frames per time unit)", 1.0),
]
ALGORITHM_COLOURS = ["#4c78a8", "#f58518", "#54a24b", "#b279a2", "#9d755d", "#72b7b2", "#eeca3b", "#79706e"]


def comparison_bars_figure(results: Mapping[str, Mapping], algorithms: list[str] | None = None) -> go.Figure:
    """Bars per algorithm for each figure of a comparison (those present: latency and throughput with frames)."""
    names = list(algorithms or results)
    figures = [f for f in COMPARISON_FIGURES if any(results[a].get(f[0]) is not None for a in names)]
    cols = 4 if len(figures) > 6 else 3
    rows = max(1, math.ceil(len(figures) / cols))
    fig = make_subplots(rows=rows, cols=cols, subplot_titles=[t for _, t, _ in figures], vertical_spacing=0.2)
    colours = {a: ALGORITHM_COLOURS[i % len(ALGORITHM_COLOURS)] for i, a in enumerate(names)}
    for i, (key, title, scale) in enumerate(figures):
        values = [results[a].get(key) for a in names]
        fig.add_trace(
            go.Bar(
                x=[esc(a.upper()) for a in names],
                y=[None if v is None else v * scale for v in values],
                marker={"color": [colours[a] for a in names]},
                text=[f"{v * scale:.4g}" if v is not None else "" for v in values],
                textposition="outside",
                cliponaxis=False,
                name=title,
                hovertemplate="%{x}: %{y:.6~g}<extra>" + title + "</extra>",
                showlegend=False,
            ),
            row=i // cols + 1,
            col=i % cols + 1,
        )
    base_layout(fig, height=170 + 250 * rows)
    fig.update_layout(margin={"l": 10, "r": 10, "t": 50, "b": 10})
    fig.update_yaxes(showgrid=True, gridcolor="#e4e7eb", zeroline=True, zerolinecolor="#9aa5b1", rangemode="tozero")
    fig.update_annotations(font={"size": 13, "color": "#1f2933"})
    return fig

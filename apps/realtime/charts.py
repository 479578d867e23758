"""Plotly figures of the RT dashboard: node utilization against the threshold, the missed-deadline timeline
with eviction and taint markers, and the distribution of the recovery response time (Eq. 3.19).

Inputs are plain rows (dicts), so the functions need no database."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from datetime import datetime
from statistics import fmean, quantiles

import plotly.graph_objects as go

from apps.ui.charts import FONT, base_layout, cycle_colours, esc, stacked_panels

PALETTE = ["#4c78a8", "#f58518", "#54a24b", "#b279a2", "#e45756", "#72b7b2", "#eeca3b", "#9d755d", "#bab0ac"]
CLASS_COLOURS = {"C": "#b03a2e", "B": "#d68910", "A": "#2e86c1", "NONE": "#9aa1a9"}
EVICTION_COLOUR = "#d64545"
TAINT_FILL = "rgba(214, 69, 69, 0.10)"
#: Table 4.35 of the thesis (ms): the reference the dashboard prints next to ours.
TABLE_4_35 = {"mean": 92.03, "worst": 408.29}


def _kind(node: Mapping) -> str:
    return f"RT {esc(node['criticality'] or '')}".strip() if node["rt"] else "non-RT"


def utilization_figure(nodes: Sequence[Mapping]) -> go.Figure:
    """One row per node: reserved RT utilization (stacked by criticality) against the node's threshold.

    ``nodes``: ``{"name", "rt", "criticality", "threshold", "cpu", "by_class": {class: utilization},
    "tainted": bool}``.
    """
    names = [n["name"] for n in nodes]
    labels = [f"{esc(n['name'])}  ({_kind(n)}){'  ⚠ tainted' if n['tainted'] else ''}" for n in nodes]
    fig = go.Figure()
    for cls in ("C", "B", "A", "NONE"):
        values = [n["by_class"].get(cls, 0.0) for n in nodes]
        if not any(values):
            continue
        fig.add_trace(
            go.Bar(
                y=labels,
                x=values,
                orientation="h",
                name=f"class {cls}" if cls != "NONE" else "non-RT",
                marker={"color": CLASS_COLOURS[cls]},
                customdata=[[n["threshold"]] for n in nodes],
                hovertemplate="%{y}<br>%{x:.3f} cores reserved of %{customdata[0]:.3f}<extra>%{fullData.name}</extra>",
            )
        )
    thresholds = [n["threshold"] for n in nodes]
    fig.add_trace(
        go.Scatter(
            y=labels,
            x=thresholds,
            mode="markers",
            name="threshold (M x 0.95)",
            marker={"symbol": "line-ns-open", "size": 26, "color": "#1f2933", "line": {"width": 3, "color": "#1f2933"}},
            hovertemplate="%{y}<br>threshold %{x:.3f}<extra></extra>",
        )
    )
    base_layout(fig, height=max(200, 110 + 46 * len(names)))
    top = max([*thresholds, *(sum(n["by_class"].values()) for n in nodes), 1.0])
    fig.update_layout(
        barmode="stack",
        bargap=0.35,
        legend={"orientation": "h", "yanchor": "bottom", "y": 1.02, "xanchor": "left", "x": 0},
        margin={"l": 10, "r": 20, "t": 50, "b": 10},
    )
    fig.update_xaxes(title_text="RT utilization (cores, Σ WCET/P)", range=[0, top * 1.08], showgrid=True,
                     gridcolor="#e4e7eb", zeroline=False)  # fmt: skip
    fig.update_yaxes(autorange="reversed")
    return fig


def timeline_figure(
    reports: Sequence[Mapping],
    events: Sequence[Mapping],
    taints: Sequence[Mapping],
    threshold: int | None,
    now: datetime,
) -> go.Figure:
    """Missed deadlines per report, one panel per node and one line per container; evictions as markers,
    taints as shaded spans, the period threshold as a dashed line.

    ``reports``: ``{"node", "container", "time", "missed_period", "missed_total"}``; ``events``: ``{"node",
    "time", "kind", "victim", "container"}``; ``taints``: ``{"node", "start", "end"}``.
    """
    nodes = sorted({r["node"] for r in reports} | {e["node"] for e in events} | {t["node"] for t in taints})
    if not nodes:
        nodes = ["—"]
    fig = stacked_panels([esc(n) for n in nodes], len(nodes), 0.06)
    containers = sorted({r["container"] for r in reports})
    colour = cycle_colours(containers, PALETTE)
    shown: set[str] = set()
    for row, node in enumerate(nodes, 1):
        for c in containers:
            _add_container_trace(fig, row, node, c, colour[c], reports, shown)
        _add_event_trace(fig, row, node, reports, events, threshold, shown)
        for t in (t for t in taints if t["node"] == node):
            fig.add_vrect(x0=t["start"], x1=t["end"] or now, fillcolor=TAINT_FILL, line_width=0, layer="below",
                          row=row, col=1)  # fmt: skip
        if threshold is not None:
            fig.add_hline(y=threshold, line={"dash": "dash", "color": "#52606d", "width": 1}, row=row, col=1)
    if taints:
        _add_taint_legend(fig)
    _timeline_layout(fig, len(nodes))
    return fig


def _add_container_trace(
    fig: go.Figure, row: int, node: str, c: str, colour: str, reports: Sequence[Mapping], shown: set[str]
) -> None:
    """One container's missed-in-period line on its node's panel (one legend entry per container)."""
    pts = [r for r in reports if r["node"] == node and r["container"] == c]
    if not pts:
        return
    fig.add_trace(
        go.Scatter(
            x=[p["time"] for p in pts],
            y=[p["missed_period"] for p in pts],
            mode="lines+markers",
            line={"color": colour, "width": 1.5, "shape": "hv"},
            marker={"size": 4},
            name=esc(c),
            legendgroup=esc(c),
            showlegend=c not in shown,
            customdata=[[p["missed_total"]] for p in pts],
            hovertemplate=f"{esc(c)} on {esc(node)}<br>%{{x}}<br>missed in period %{{y}}, "
            "total %{customdata[0]}<extra></extra>",
        ),
        row=row,
        col=1,
    )
    shown.add(c)


def _event_text(e: Mapping) -> str:
    if e["kind"] == "eviction":
        return f"evicted {esc(e['victim'])} for {esc(e['container'])}"
    return f"alert: {esc(e['container'])}"


def _add_event_trace(
    fig: go.Figure,
    row: int,
    node: str,
    reports: Sequence[Mapping],
    events: Sequence[Mapping],
    threshold: int | None,
    shown: set[str],
) -> None:
    """A node's evictions (x) and alerts (triangles), drawn just above its highest report."""
    evs = [e for e in events if e["node"] == node]
    if not evs:
        return
    ymax = max([r["missed_period"] for r in reports if r["node"] == node] or [threshold or 1])
    fig.add_trace(
        go.Scatter(
            x=[e["time"] for e in evs],
            y=[ymax * 1.05 + 0.5] * len(evs),
            mode="markers",
            marker={
                "symbol": ["x" if e["kind"] == "eviction" else "triangle-down" for e in evs],
                "size": 11,
                "color": [EVICTION_COLOUR if e["kind"] == "eviction" else "#c98a0b" for e in evs],
            },
            name="eviction / alert",
            legendgroup="events",
            showlegend="events" not in shown,
            text=[_event_text(e) for e in evs],
            hovertemplate="%{x}<br>%{text}<extra></extra>",
        ),
        row=row,
        col=1,
    )
    shown.add("events")


def _add_taint_legend(fig: go.Figure) -> None:
    """A legend entry for the shaded taint spans (shapes have none of their own)."""
    fig.add_trace(
        go.Scatter(
            x=[None],
            y=[None],
            mode="markers",
            marker={"size": 12, "color": TAINT_FILL, "symbol": "square"},
            name="node tainted",
        )
    )


def _timeline_layout(fig: go.Figure, panels: int) -> None:
    height = max(280, 110 + 190 * panels)
    base_layout(fig, height=height)
    fig.update_layout(
        # Above the first panel's title (subplot titles sit just above their panel).
        legend={"orientation": "h", "yanchor": "bottom", "y": 1 + 40 / height, "xanchor": "left", "x": 0},
        margin={"l": 10, "r": 20, "t": 90, "b": 10},
    )
    fig.update_yaxes(title_text="missed / period", rangemode="tozero", gridcolor="#e4e7eb")
    fig.update_xaxes(gridcolor="#e4e7eb")
    fig.update_annotations(font={**FONT, "size": 12})


def response_figure(values_ms: Sequence[float], components: Mapping[str, float] | None = None) -> go.Figure:
    """Histogram of report-to-eviction times (ms), with their mean and 99th percentile marked."""
    fig = go.Figure()
    fig.add_trace(
        go.Histogram(
            x=list(values_ms),
            nbinsx=min(40, max(5, len(values_ms) // 2)),
            marker={"color": "#4c78a8"},
            name="evictions",
            hovertemplate="%{x} ms: %{y} evictions<extra></extra>",
        )
    )
    stats = summary(values_ms)
    for key, dash in (("mean", "dash"), ("p99", "dot")):
        if stats.get(key) is not None:
            fig.add_vline(x=stats[key], line={"dash": dash, "color": "#323f4b", "width": 1})
            fig.add_annotation(
                x=stats[key], y=1, yref="paper", xanchor="left", yanchor="bottom", showarrow=False,
                text=f"{key} {stats[key]:.1f} ms", font={"size": 11},
            )  # fmt: skip
    base_layout(fig, height=280)
    fig.update_layout(showlegend=False, margin={"l": 10, "r": 20, "t": 40, "b": 10}, bargap=0.05)
    fig.update_xaxes(title_text="report received → eviction sent (ms)", rangemode="tozero", gridcolor="#e4e7eb")
    fig.update_yaxes(title_text="evictions", gridcolor="#e4e7eb")
    return fig


def summary(values: Sequence[float]) -> dict[str, float | None]:
    vals = sorted(values)
    if not vals:
        return {"n": 0, "mean": None, "p50": None, "p99": None, "max": None}
    if len(vals) >= 2:
        q = quantiles(vals, n=100, method="inclusive")
        p50, p99 = q[49], q[98]
    else:
        p50 = p99 = vals[0]
    return {"n": len(vals), "mean": fmean(vals), "p50": p50, "p99": p99, "max": vals[-1]}

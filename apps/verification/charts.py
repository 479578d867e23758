"""Plotly figures of the verification pages: the Fig. 4.24-style migration timeline (CPU per node with its
threshold, monitors per node, migrations, and the navigation makespan against its requirement)."""

from __future__ import annotations

from collections.abc import Sequence

import plotly.graph_objects as go

from apps.ui.charts import FONT, cycle_colours, esc, stacked_panels

NODE_COLOURS = ["#2e9e5b", "#e0a526", "#4c78a8", "#b05fb0", "#e4572e", "#59a5a5", "#8c6d31", "#7f7f7f"]


def node_colours(nodes: Sequence[str]) -> dict[str, str]:
    return cycle_colours(nodes, NODE_COLOURS)


def timeline_figure(runs: Sequence, migrations: Sequence, requirement_ms: float | None = None) -> go.Figure:
    """``runs``: the AllocationRun rows of one series, in time order (their ``nodes`` hold cpu, background,
    monitors, threshold per node); ``migrations``: its MigrationEvent rows."""
    nodes = list(runs[0].nodes) if runs else []
    colours = node_colours(nodes)
    has_makespan = any(r.makespan_ms is not None for r in runs)
    rows = 3 if has_makespan else 2
    fig = stacked_panels(_panel_titles(has_makespan), rows, 0.07)
    t = [r.t for r in runs]
    for n in nodes:
        _add_node_traces(fig, runs, t, n, colours[n])
    _add_migration_bars(fig, migrations)
    if has_makespan:
        _add_makespan_traces(fig, runs, t, requirement_ms)
    _timeline_layout(fig, rows)
    return fig


def _panel_titles(has_makespan: bool) -> list[str]:
    titles = ["CPU per node (%) — dashed: threshold", "Monitors per node — grey bars: monitors migrated"]
    if has_makespan:
        titles.append("Navigation makespan (ms)")
    return titles


def _span(t: Sequence[float], y: float, **style) -> go.Scatter:
    """A horizontal line at ``y`` over the run's time span (a threshold or a requirement)."""
    return go.Scatter(x=[t[0], t[-1]], y=[y, y], hoverinfo="skip", **style)


def _add_node_traces(fig: go.Figure, runs: Sequence, t: list[float], n: str, c: str) -> None:
    """One node's CPU line (panel 1), its threshold (dashed, when below 100 %) and its monitors (panel 2)."""
    label = esc(n)
    cpu = [r.nodes[n]["cpu"] for r in runs]
    ver = [r.nodes[n].get("verification", 0.0) for r in runs]
    fig.add_trace(
        go.Scatter(
            x=t,
            y=cpu,
            name=f"{label} CPU",
            legendgroup=label,
            line={"color": c, "width": 2},
            customdata=ver,
            hovertemplate=f"{label}: %{{y:.1f}} %% (monitors %{{customdata:.1f}} %%)<extra></extra>",
        ),
        row=1,
        col=1,
    )
    thr = runs[0].nodes[n].get("threshold")
    if thr is not None and thr < 100:
        fig.add_trace(
            _span(t, thr, name=f"{label} threshold", legendgroup=label, showlegend=False,
                  line={"color": c, "dash": "dash", "width": 1}),
            row=1,
            col=1,
        )  # fmt: skip
    fig.add_trace(
        go.Scatter(
            x=t,
            y=[r.nodes[n]["monitors"] for r in runs],
            name=f"{label} monitors",
            legendgroup=label,
            line={"color": c, "width": 2, "shape": "hv"},
            hovertemplate=f"{label}: %{{y}} monitors<extra></extra>",
        ),
        row=2,
        col=1,
    )


def _add_migration_bars(fig: go.Figure, migrations: Sequence) -> None:
    """Grey bars on panel 2: how many monitors moved at each time."""
    moved: dict[float, int] = {}
    for m in migrations:
        moved[m.t] = moved.get(m.t, 0) + 1
    if moved:
        fig.add_trace(
            go.Bar(
                x=list(moved),
                y=list(moved.values()),
                name="migrations",
                marker={"color": "rgba(120,120,120,0.35)"},
                hovertemplate="t = %{x} s: %{y} monitors moved<extra></extra>",
            ),
            row=2,
            col=1,
        )


def _add_makespan_traces(fig: go.Figure, runs: Sequence, t: list[float], requirement_ms: float | None) -> None:
    """Panel 3: the navigation makespan per run and, when given, its requirement (dashed)."""
    fig.add_trace(
        go.Scatter(
            x=t,
            y=[r.makespan_ms for r in runs],
            name="makespan",
            line={"color": "#1f2933", "width": 2},
            hovertemplate="%{y:.1f} ms<extra></extra>",
        ),
        row=3,
        col=1,
    )
    if requirement_ms is not None:
        fig.add_trace(
            _span(t, requirement_ms, name=f"requirement {requirement_ms:g} ms",
                  line={"color": "#d64545", "dash": "dash", "width": 1.5}),
            row=3,
            col=1,
        )  # fmt: skip


def _timeline_layout(fig: go.Figure, rows: int) -> None:
    fig.update_yaxes(title_text="%", range=[0, 105], row=1, col=1)
    fig.update_yaxes(title_text="monitors", rangemode="tozero", row=2, col=1)
    fig.update_xaxes(title_text="time (s)", row=rows, col=1)
    fig.update_layout(
        height=260 * rows + 80,
        margin={"l": 10, "r": 10, "t": 40, "b": 10},
        font=FONT,
        plot_bgcolor="white",
        paper_bgcolor="white",
        hovermode="x unified",
        legend={"orientation": "h", "y": -0.08},
        bargap=0.2,
    )
    fig.update_xaxes(showgrid=True, gridcolor="#eef0f2")
    fig.update_yaxes(showgrid=True, gridcolor="#eef0f2")

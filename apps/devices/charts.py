"""Figures of the device pages: an application's CPU and GPU cache usage against a board's UMA zones."""

from __future__ import annotations

import plotly.graph_objects as go

from apps.ui.charts import base_layout, fmt

ZONE_COLOURS = {"zc": "#c7e9c0", "gap": "#fdd9a0", "sc": "#f4b6b6"}


def uma_zone_figure(
    cpu_threshold: float,
    gpu_low: float,
    gpu_high: float | None,
    cpu_usage: float | None = None,
    gpu_usage: float | None = None,
) -> go.Figure:
    """The board's zones (thesis Fig. 3.7): GPU zone 1 (ZC = SC), zone 2 (gap under 200 %), zone 3
    (cache-dependent); CPU not dependent / dependent. Markers show the application's Eq. 3.8-3.9 usages."""
    top = max(100.0, (cpu_usage or 0) * 1.1, (gpu_usage or 0) * 1.1)
    gpu_bands = [("zone 1: ZC = SC", 0.0, gpu_low, ZONE_COLOURS["zc"])]
    if gpu_high is not None:
        gpu_bands.append(("zone 2: gap < 200 %", gpu_low, gpu_high, ZONE_COLOURS["gap"]))
    zone3 = gpu_high if gpu_high is not None else gpu_low
    gpu_bands.append(("zone 3: cache-dependent", zone3, top, ZONE_COLOURS["sc"]))
    cpu_bands = [
        ("CPU not cache-dependent", 0.0, min(cpu_threshold, top), ZONE_COLOURS["zc"]),
        ("CPU cache-dependent", min(cpu_threshold, top), top, ZONE_COLOURS["sc"]),
    ]
    fig = go.Figure()
    for row, bands in (("GPU", gpu_bands), ("CPU", cpu_bands)):
        for label, lo, hi, colour in bands:
            if hi <= lo:
                continue
            fig.add_trace(
                go.Bar(
                    y=[row],
                    x=[hi - lo],
                    base=[lo],
                    orientation="h",
                    marker={"color": colour, "line": {"color": "white", "width": 2}},
                    text=[label],
                    textposition="inside",
                    insidetextanchor="middle",
                    textfont={"color": "#1f2933"},
                    hovertemplate=f"{label}: {fmt(lo)}-{fmt(hi)} %<extra></extra>",
                    showlegend=False,
                )
            )
    for row, value in (("GPU", gpu_usage), ("CPU", cpu_usage)):
        if value is not None:
            fig.add_trace(
                go.Scatter(
                    x=[value],
                    y=[row],
                    mode="markers+text",
                    marker={
                        "symbol": "diamond",
                        "size": 16,
                        "color": "#1f2933",
                        "line": {"color": "white", "width": 2},
                    },
                    text=[f"{fmt(round(value, 2))} %"],
                    textposition="top center",
                    name=f"{row} usage",
                    hovertemplate=f"{row} usage: %{{x:.4~g}} %<extra></extra>",
                    showlegend=False,
                )
            )
    base_layout(fig, height=230)
    fig.update_layout(barmode="overlay", bargap=0.35, margin={"l": 10, "r": 20, "t": 20, "b": 10})
    fig.update_xaxes(title_text="cache usage (% of the device's peak)", range=[0, top], showgrid=False)
    fig.update_yaxes(type="category", categoryorder="array", categoryarray=["GPU", "CPU"], autorange="reversed")
    return fig

"""Plotly figures of ROS graphs, containers and placements, drawn from engine objects and stored engine dicts
(no Django here). Rendered with :func:`apps.ui.charts.to_html` (plotly.js comes from static files).

- :func:`rosgraph_figure`: ROS nodes in rows by abstraction level (Fig. 3.19, mission on top, drivers at the
  bottom) and in columns by container, coloured by container; edge width grows with the bandwidth (Eq. 3.12),
  edges between containers are drawn in a warm colour, edges inside one in grey.
- :func:`container_figure`: the containers and the bandwidth between them (Definition 3.2.1).
- :func:`placement_figure`: the cluster's nodes, the containers on each, and the traffic between nodes.
- :func:`disk_figure`: each image's size alone (before) and what it adds on a shared device (after).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import plotly.graph_objects as go
from plotly.colors import qualitative

from apps.containers.resources import resource_model
from apps.ui.charts import EDGE_COLOUR, base_layout, cycle_colours, esc, escs
from continuum.engine.containers.resource_model import NodeProfile
from continuum.engine.containers.resource_model import profiles as resource_profiles
from continuum.engine.containers.rosgraph import LEVELS, RosGraph, natural_key

PALETTE = [*qualitative.T10, *qualitative.Pastel, *qualitative.Dark24]
INTER_COLOUR = "#e4572e"
NODE_COLOUR = "#52606d"
PENDING_COLOUR = "#d64545"
LEVEL_LABELS = {
    "mission": "mission",
    "macro": "macro-functionality",
    "functionality": "functionality / controller",
    "driver": "driver",
}
MAX_LABELLED = 60


def rate(bps: float) -> str:
    """Bytes per second for people: ``12.3 kB/s (0.098 Mbit/s)``."""
    if bps is None:
        return "—"
    for unit, scale in (("GB/s", 1e9), ("MB/s", 1e6), ("kB/s", 1e3)):
        if abs(bps) >= scale:
            text = f"{bps / scale:.3g} {unit}"
            break
    else:
        text = f"{bps:.3g} B/s"
    return f"{text} ({bps * 8 / 1e6:.3g} Mbit/s)"


def colours(names: Sequence[str]) -> dict[str, str]:
    """A stable colour per container, in the order given."""
    return cycle_colours(names, PALETTE)


def _width(w: float, top: float) -> float:
    """Line width 1..9 growing with the square root of the bandwidth, rounded to halves (few traces)."""
    if top <= 0 or w <= 0:
        return 1.0
    return round((1.0 + 8.0 * math.sqrt(w / top)) * 2) / 2


def _edge_traces(
    segments: list[tuple[tuple[float, float], tuple[float, float], float, str, str]], top: float
) -> list[go.Scatter]:
    """Lines grouped by (width, colour) plus invisible midpoint markers carrying the hover text."""
    groups: dict[tuple[float, str], tuple[list, list]] = {}
    mids: tuple[list, list, list] = ([], [], [])
    for (x0, y0), (x1, y1), w, colour, text in segments:
        xs, ys = groups.setdefault((_width(w, top), colour), ([], []))
        xs += [x0, x1, None]
        ys += [y0, y1, None]
        mids[0].append((x0 + x1) / 2)
        mids[1].append((y0 + y1) / 2)
        mids[2].append(text)
    traces = [
        go.Scatter(
            x=xs,
            y=ys,
            mode="lines",
            line={"color": colour, "width": width},
            opacity=0.75,
            hoverinfo="skip",
            showlegend=False,
        )
        for (width, colour), (xs, ys) in sorted(groups.items())
    ]
    traces.append(
        go.Scatter(
            x=mids[0],
            y=mids[1],
            mode="markers",
            marker={"size": 12, "color": EDGE_COLOUR, "opacity": 0},
            hovertext=mids[2],
            hoverinfo="text",
            showlegend=False,
            name="bandwidth",
        )
    )
    return traces


# ---- ROS graph ----------------------------------------------------------------------------------------
def rosgraph_layout(
    graph: RosGraph, levels: Mapping[str, str], groups: Mapping[str, Sequence[str]]
) -> dict[str, tuple[float, float]]:
    """(x, y): y is the level row (driver 0 .. mission 3); each container gets a band of columns as wide as
    its busiest level, bands left to right in container order; alternate nodes of a row are nudged up and
    down so that edges along a row do not run through the nodes between."""
    row = {lv: len(LEVELS) - 1 - i for i, lv in enumerate(LEVELS)}
    pos: dict[str, tuple[float, float]] = {}
    x0 = 0.0
    for members in groups.values():
        per_level: dict[str, list[str]] = {}
        for n in sorted(members, key=natural_key):
            per_level.setdefault(levels[n], []).append(n)
        width = max((len(v) for v in per_level.values()), default=1)
        for lv, names in per_level.items():
            offset = (width - len(names)) / 2
            for i, n in enumerate(names):
                nudge = 0.0 if len(names) < 2 else (0.14 if i % 2 else -0.14)
                pos[n] = (x0 + offset + i, row[lv] + nudge)
        x0 += width + 0.8
    return pos


def _label_side(xy: tuple[float, float]) -> str:
    """Above the node, or below it for nodes nudged down (so crowded rows label on both sides)."""
    return "bottom center" if xy[1] - round(xy[1]) < -0.01 else "top center"


def rosgraph_figure(
    graph: RosGraph, groups: Mapping[str, Sequence[str]] | None = None, mode: str = "per_topic"
) -> go.Figure:
    """The ROS graph by level and container (``groups``: container -> ROS nodes; none: one group). A dark rim
    marks a level set by the user, a white rim one proposed from the graph's structure."""
    levels = graph.levels()
    groups = dict(groups) if groups else {"ROS nodes": sorted(graph.nodes, key=natural_key)}
    palette = colours(list(groups))
    pos = rosgraph_layout(graph, levels, groups)
    weights = graph.weights(mode)
    top = max(weights.values(), default=0.0)
    fig = go.Figure(_edge_traces(_rosgraph_segments(graph, groups, pos, weights), top))
    labelled = len(graph.nodes) <= MAX_LABELLED
    requests = resource_profiles(graph, resource_model())  # what placement reserves, not only the profile
    for container, members in groups.items():
        trace = _ros_nodes_trace(graph, levels, requests, container, members, pos, palette[container], labelled)
        fig.add_trace(trace)
    _rosgraph_layout_axes(fig, pos)
    return fig


def _rosgraph_segments(
    graph: RosGraph,
    groups: Mapping[str, Sequence[str]],
    pos: Mapping[str, tuple[float, float]],
    weights: Mapping[tuple[str, str], float],
) -> list[tuple[tuple[float, float], tuple[float, float], float, str, str]]:
    """One segment per communicating pair: warm between containers (when there are several), grey inside one."""
    owner = {n: c for c, members in groups.items() for n in members}
    segments = []
    for (a, b), w in weights.items():
        inter = owner.get(a) != owner.get(b)
        topics = ", ".join(escs(graph.shared_topics(a, b)))
        where = "between containers" if inter and len(groups) > 1 else "inside a container"
        text = f"<b>{esc(a)} ↔ {esc(b)}</b><br>{rate(w)}<br>{where}<br>topics: {topics}"
        segments.append((pos[a], pos[b], w, INTER_COLOUR if inter and len(groups) > 1 else EDGE_COLOUR, text))
    return segments


def _ros_nodes_trace(
    graph: RosGraph,
    levels: Mapping[str, str],
    requests: Mapping[str, NodeProfile],
    container: str,
    members: Sequence[str],
    pos: Mapping[str, tuple[float, float]],
    colour: str,
    labelled: bool,
) -> go.Scatter:
    """One container's ROS nodes (its legend entry): a dark rim for a level the user set, white for a proposed one."""
    given = {n: node.level for n, node in graph.nodes.items()}
    names = sorted(members, key=natural_key)
    hover = []
    for n in names:
        node = graph.nodes[n]
        level = LEVEL_LABELS[levels[n]] + ("" if given[n] else " (proposed)")
        extra = f"<br>packages: {', '.join(escs(node.packages))}" if node.packages else ""
        req = requests[n]
        hover.append(
            f"<b>{esc(n)}</b><br>container: {esc(container)}<br>level: {level}"
            f"<br>requests CPU {req.cpu:.3g} cores (work {node.cpu:.3g}), memory {req.memory_mib:.4g} MiB{extra}"
        )
    return go.Scatter(
        x=[pos[n][0] for n in names],
        y=[pos[n][1] for n in names],
        mode="markers+text" if labelled else "markers",
        text=escs(names),
        # Neighbours in a row alternate label sides (the layout nudges them up and down to match).
        textposition=[_label_side(pos[n]) for n in names],
        textfont={"size": 10},
        marker={
            "size": 16,
            "color": colour,
            "line": {
                "color": ["#1f2933" if given[n] else "white" for n in names],
                "width": [2.5 if given[n] else 1.5 for n in names],
            },
        },
        hovertext=hover,
        hoverinfo="text",
        name=esc(container),
    )


def _rosgraph_layout_axes(fig: go.Figure, pos: Mapping[str, tuple[float, float]]) -> None:
    """Legend of containers on top; x hidden; y labelled with the abstraction levels, mission on top."""
    xs = [x for x, _ in pos.values()] or [0.0]
    base_layout(fig, height=560)
    fig.update_layout(
        legend={"orientation": "h", "yanchor": "bottom", "y": 1.02, "xanchor": "left", "x": 0, "title": "container"},
        margin={"l": 10, "r": 10, "t": 60, "b": 10},
    )
    fig.update_xaxes(visible=False, range=[min(xs) - 0.8, max(xs) + 0.8])
    fig.update_yaxes(
        tickmode="array",
        tickvals=list(range(len(LEVELS))),
        ticktext=[LEVEL_LABELS[lv] for lv in reversed(LEVELS)],
        range=[-0.5, len(LEVELS) - 0.3],
        showgrid=True,
        gridcolor="#eef0f2",
        zeroline=False,
    )


# ---- containers ---------------------------------------------------------------------------------------
def _circle(names: Sequence[str], radius: float = 1.0) -> dict[str, tuple[float, float]]:
    n = len(names)
    if n == 1:
        return {names[0]: (0.0, 0.0)}
    return {
        name: (
            radius * math.cos(2 * math.pi * i / n + math.pi / 2),
            radius * math.sin(2 * math.pi * i / n + math.pi / 2),
        )
        for i, name in enumerate(names)
    }


def container_figure(containers: Sequence[Mapping[str, Any]], bandwidth: Sequence[Mapping[str, Any]]) -> go.Figure:
    """Containers (size: number of ROS nodes) and the bandwidth left between them."""
    names = [c["name"] for c in containers]
    palette = colours(names)
    pos = _circle(names)
    top = max((b["bytes_per_s"] for b in bandwidth), default=0.0)
    segments = [
        (
            pos[b["a"]],
            pos[b["b"]],
            b["bytes_per_s"],
            INTER_COLOUR,
            f"<b>{esc(b['a'])} ↔ {esc(b['b'])}</b><br>{rate(b['bytes_per_s'])}",
        )
        for b in bandwidth
        if b["bytes_per_s"] > 0
    ]
    fig = go.Figure(_edge_traces(segments, top))
    sizes = [len(c["nodes"]) for c in containers]
    biggest = max(sizes, default=1)
    fig.add_trace(
        go.Scatter(
            x=[pos[n][0] for n in names],
            y=[pos[n][1] for n in names],
            mode="markers+text",
            text=[f"{esc(c['name'])} ({len(c['nodes'])})" for c in containers],
            textposition="bottom center",
            marker={
                "size": [18 + 30 * math.sqrt(s / biggest) for s in sizes],
                "color": [palette[n] for n in names],
                "line": {"color": "white", "width": 2},
            },
            hovertext=[
                f"<b>{esc(c['name'])}</b><br>{len(c['nodes'])} ROS nodes:<br>" + "<br>".join(escs(c["nodes"]))
                for c in containers
            ],
            hoverinfo="text",
            showlegend=False,
        )
    )
    base_layout(fig, height=440)
    lim = 1.5 if len(names) > 1 else 1.0
    fig.update_xaxes(visible=False, range=[-lim, lim])
    fig.update_yaxes(visible=False, range=[-lim, lim * 0.95], scaleanchor="x")
    return fig


# ---- placement ----------------------------------------------------------------------------------------
def placement_figure(
    cluster_doc: Mapping[str, Any],
    plan: Mapping[str, Any],
    traffic: Sequence[Mapping[str, Any]],
    container_order: Sequence[str],
) -> go.Figure:
    """Cluster nodes (squares) with their containers around them (dots, container colours); lines between
    nodes grow with the traffic that crosses them; physical links are thin dotted lines; pending containers
    sit in a column on the right."""
    nodes = [n["name"] for n in cluster_doc.get("nodes", [])]
    archs = {n["name"]: n.get("arch", "") for n in cluster_doc.get("nodes", [])}
    palette = colours(list(container_order))
    pos = _circle(nodes)
    fig = go.Figure()
    links = _link_trace(pos, cluster_doc.get("links", []))
    if links is not None:
        fig.add_trace(links)
    for trace in _traffic_traces(pos, traffic):
        fig.add_trace(trace)
    on_node, scores = _containers_by_node(nodes, plan)
    fig.add_trace(_node_trace(nodes, archs, pos, on_node))
    spots = _placed_spots(nodes, pos, on_node, scores)
    pending = [p["container"] for p in plan.get("pending", [])]
    spots.update(_pending_spots(pending))
    # One trace per container: the legend gives each container its colour, as on the ROS graph. Past
    # LEGEND_UP_TO containers a legend is unreadable and a trace each costs seconds (plotly builds and
    # validates every trace): one trace holds them all, each dot still in its colour with its hover text.
    order = [c for c in [*container_order, *(c for c in spots if c not in container_order)] if c in spots]
    if len(order) > LEGEND_UP_TO:
        fig.add_trace(_containers_trace(order, spots, palette, set(pending)))
    else:
        for c in order:
            fig.add_trace(_container_trace(c, spots[c], palette.get(c, NODE_COLOUR), c in pending))
    if pending:
        fig.add_annotation(x=1.75, y=1.15, text="<b>pending</b>", showarrow=False, font={"color": PENDING_COLOUR})
    _placement_layout(fig, bool(pending))
    return fig


def _link_trace(pos: Mapping[str, tuple[float, float]], links: Sequence[Mapping[str, Any]]) -> go.Scatter | None:
    """The physical network links as thin dotted lines (None: no link)."""
    link_x: list[float | None] = []
    link_y: list[float | None] = []
    for lk in links:
        (x0, y0), (x1, y1) = pos[lk["src"]], pos[lk["dst"]]
        link_x += [x0, x1, None]
        link_y += [y0, y1, None]
    if not link_x:
        return None
    return go.Scatter(
        x=link_x,
        y=link_y,
        mode="lines",
        line={"color": "#cbd2d9", "width": 1, "dash": "dot"},
        hoverinfo="skip",
        name="network links",
    )


def _traffic_traces(pos: Mapping[str, tuple[float, float]], traffic: Sequence[Mapping[str, Any]]) -> list[go.Scatter]:
    """The traffic between nodes: lines growing with the bandwidth, hover on their middles."""
    top = max((t["bytes_per_s"] for t in traffic), default=0.0)
    segments = [
        (
            pos[t["a"]],
            pos[t["b"]],
            t["bytes_per_s"],
            INTER_COLOUR,
            f"<b>{esc(t['a'])} ↔ {esc(t['b'])}</b><br>{rate(t['bytes_per_s'])}",
        )
        for t in traffic
    ]
    return _edge_traces(segments, top)


def _containers_by_node(nodes: Sequence[str], plan: Mapping[str, Any]) -> tuple[dict[str, list[str]], dict[str, float]]:
    """The plan's containers on each node (every node listed, empty ones too) and each placement's score."""
    on_node: dict[str, list[str]] = {n: [] for n in nodes}
    scores = {}
    for p in plan.get("placements", []):
        on_node.setdefault(p["node"], []).append(p["container"])
        scores[p["container"]] = p["score"]
    return on_node, scores


def _node_trace(
    nodes: Sequence[str],
    archs: Mapping[str, str],
    pos: Mapping[str, tuple[float, float]],
    on_node: Mapping[str, list[str]],
) -> go.Scatter:
    """The cluster's nodes as squares, labelled with their architecture; hover lists their containers."""
    return go.Scatter(
        x=[pos[n][0] for n in nodes],
        y=[pos[n][1] for n in nodes],
        mode="markers+text",
        text=[f"<b>{esc(n)}</b> ({esc(archs[n])})" for n in nodes],
        textposition="bottom center",
        marker={"size": 46, "symbol": "square", "color": "#f5f7fa", "line": {"color": NODE_COLOUR, "width": 2}},
        hovertext=[
            f"<b>{esc(n)}</b> ({esc(archs[n])})<br>containers: {', '.join(escs(on_node[n])) or 'none'}" for n in nodes
        ],
        hoverinfo="text",
        name="nodes",
        showlegend=False,
    )


def _placed_spots(
    nodes: Sequence[str],
    pos: Mapping[str, tuple[float, float]],
    on_node: Mapping[str, list[str]],
    scores: Mapping[str, float],
) -> dict[str, tuple[float, float, str]]:
    """(x, y, hover text) of every placed container: on a small circle around its node (alone: on it)."""
    spots: dict[str, tuple[float, float, str]] = {}
    for n in nodes:
        members = on_node[n]
        cx, cy = pos[n]
        for i, c in enumerate(members):
            angle = 2 * math.pi * i / max(len(members), 1) + math.pi / 2
            r = 0.0 if len(members) == 1 else 0.13
            spots[c] = (
                cx + r * math.cos(angle),
                cy + r * math.sin(angle),
                f"<b>{esc(c)}</b><br>on {esc(n)}, score {scores[c]:.4g}",
            )
    return spots


def _pending_spots(pending: Sequence[str]) -> dict[str, tuple[float, float, str]]:
    """(x, y, hover text) of the pending containers: a column on the right."""
    return {
        c: (1.75, 0.9 - 0.25 * i, f"<b>{esc(c)}</b><br>pending: no node passed the filters")
        for i, c in enumerate(pending)
    }


#: Containers drawn one trace (one legend entry) each; more are drawn as one trace.
LEGEND_UP_TO = 200


def _containers_trace(
    order: Sequence[str],
    spots: Mapping[str, tuple[float, float, str]],
    palette: Mapping[str, str],
    pending: set[str],
) -> go.Scatter:
    """Every container's dot in one trace (a large placement): the colours and rims of :func:`_container_trace`."""
    # numpy arrays: plotly validates a list element by element, an array at once.
    return go.Scatter(
        x=np.array([spots[c][0] for c in order]),
        y=np.array([spots[c][1] for c in order]),
        mode="markers",
        marker={
            "size": 9,
            "color": np.array([palette.get(c, NODE_COLOUR) for c in order]),
            "line": {
                "color": np.array([PENDING_COLOUR if c in pending else "white" for c in order]),
                "width": np.array([2.5 if c in pending else 1.0 for c in order]),
            },
        },
        hovertext=np.array([spots[c][2] for c in order]),
        hoverinfo="text",
        name=f"{len(order)} containers",
        legendgroup="containers",
    )


def _container_trace(c: str, spot: tuple[float, float, str], colour: str, pending: bool) -> go.Scatter:
    """One container's dot (its own legend entry); a pending one has a red rim."""
    x, y, text = spot
    return go.Scatter(
        x=[x],
        y=[y],
        mode="markers",
        marker={
            "size": 13,
            "color": colour,
            "line": {"color": PENDING_COLOUR if pending else "white", "width": 2.5 if pending else 1.5},
        },
        hovertext=[text],
        hoverinfo="text",
        name=esc(c),
        legendgroup="containers",
    )


def _placement_layout(fig: go.Figure, pending: bool) -> None:
    base_layout(fig, height=480)
    fig.update_layout(legend={"orientation": "v", "yanchor": "top", "y": 1, "xanchor": "left", "x": 1.01})
    fig.update_xaxes(visible=False, range=[-1.5, 2.1 if pending else 1.5])
    fig.update_yaxes(visible=False, range=[-1.4, 1.3], scaleanchor="x")


# ---- disk ---------------------------------------------------------------------------------------------
def disk_figure(images: Mapping[str, Any]) -> go.Figure:
    """Per image: its full size alone (containers only: what it costs without sharing) and the bytes it adds
    to a device holding every image (layers shared through inheritance counted once)."""
    rows = sorted(images.get("images", []), key=lambda im: (im["kind"] != "container", -im["size_mib"]))
    names = [f"{esc(im['name'])} ({esc(im['kind'])})" for im in rows]
    fig = go.Figure()
    fig.add_trace(
        go.Bar(
            name="alone (before)",
            orientation="h",
            y=names,
            x=[im["size_mib"] if im["kind"] == "container" else None for im in rows],
            marker={"color": "#9aa5b1"},
            hovertemplate="%{y}: %{x:.4g} MiB alone<extra></extra>",
        )
    )
    fig.add_trace(
        go.Bar(
            name="added on a shared device (after)",
            orientation="h",
            y=names,
            x=[im["unique_mib"] for im in rows],
            marker={"color": "#2e9e5b"},
            hovertemplate="%{y}: %{x:.4g} MiB of its own<extra></extra>",
        )
    )
    base_layout(fig, height=max(260, 90 + 34 * len(rows)))
    fig.update_layout(
        barmode="group",
        legend={"orientation": "h", "yanchor": "bottom", "y": 1.02, "xanchor": "left", "x": 0},
        margin={"l": 10, "r": 20, "t": 50, "b": 10},
    )
    fig.update_xaxes(title_text="MiB", showgrid=True, gridcolor="#e4e7eb", rangemode="tozero")
    fig.update_yaxes(autorange="reversed")
    return fig

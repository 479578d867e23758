"""The UI kit's Plotly figures, drawn from engine objects (TaskGraph, Schedule, Platform), with no Django in them.

Every page renders them with :func:`to_html`, which leaves plotly.js out: the page loads it from
``static/vendor/plotly.min.js`` (no CDN).

- :func:`gantt_figure`: one row per processor, one horizontal bar per assignment. Bars are ``go.Bar`` with
  ``base=start`` and ``x=duration`` on a numeric axis; ``px.timeline`` would force a date axis and make
  model-time bars zero-wide. The critical path is a separate trace with its own colour and legend entry.
  With several frames, bars are coloured by frame (one legend entry per frame, or a colour scale beyond
  :data:`MAX_FRAME_TRACES` frames); the critical path keeps its own colour. Optionally bars are coloured by
  niceness (HEFT4K) and multi-core nodes get one row per CPU. :func:`gantt_traces` alone draws the bars.
- :func:`stacked_gantt_figure`: several schedules on one shared time axis: a comparison's charts (one per
  algorithm, ``apps/scheduling/charts.py``), the HEFT4K plan and its simulated run, a schedule before and
  after a remap.
- :func:`dag_figure`: the DAG in layers by topological level (left to right), edges as lines.
- :func:`network_figure`: a cluster's nodes (coloured by status) and the links between them.
- :func:`base_layout`, :func:`to_html`, :func:`esc`/:func:`escs`, :func:`fmt`: what every chart builder of
  ``apps/*/charts.py`` shares (domain figures live in their app: comparisons in scheduling, UMA zones in
  devices, RT and container and verification figures in theirs).

Names (tasks, processors, nodes, containers, monitors, applications) come from users. Plotly renders a subset of
HTML in hover text, text, legend entries, titles and tick labels (``<a href=...>`` becomes a live link), so every
name goes through :func:`esc` before it reaches a figure: the one helper every chart builder in ``apps/*/charts.py``
uses. Plotly turns the entities back into the characters it shows.
"""

from __future__ import annotations

import html
import json
import math
import uuid
from collections.abc import Collection, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from functools import partial
from statistics import fmean

import numpy as np
import plotly.graph_objects as go
import plotly.io as pio
from plotly.colors import sample_colorscale
from plotly.subplots import make_subplots

from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import Assignment, Schedule

TASK_COLOUR = "#4c78a8"
CRITICAL_COLOUR = "#e4572e"
#: Frame colours (none close to the critical path's); light ones carry dark labels.
FRAME_COLOURS = ["#4c78a8", "#54a24b", "#b279a2", "#eeca3b", "#72b7b2", "#9d755d", "#ff9da6", "#79706e"]
LIGHT_COLOURS = {"#eeca3b", "#ff9da6", "#72b7b2"}
#: Beyond this many frames one trace with a colour scale replaces the per-frame traces and legend entries.
MAX_FRAME_TRACES = len(FRAME_COLOURS)
FRAME_SCALE = "Viridis"
STATUS_COLOURS = {"Ready": "#2e9e5b", "NotReady": "#d64545", "Unknown": "#9aa1a9"}
CLASS_SYMBOLS = {"cpu": "circle", "gpu": "square", "fpga": "diamond"}
EDGE_COLOUR = "#9aa5b1"
FONT = {"family": "system-ui, -apple-system, Segoe UI, Roboto, sans-serif", "size": 13, "color": "#1f2933"}
#: Above these sizes labels and arrow heads would only clutter the picture; hover still tells everything.
MAX_LABELLED_TASKS = 40
MAX_ARROWS = 150
#: Past this many tasks or edges a DAG or network is drawn with WebGL from numpy columns (add_edge_traces);
#: past MAX_EDGE_HOVER edges, edges have no hover markers of their own.
LARGE_GRAPH = 2000
MAX_EDGE_HOVER = 5000
#: Past this many bars a Gantt chart is drawn with WebGL (:func:`_gantt_gl_trace`): SVG bars, one DOM
#: element each, took the browser 72 s on a 1000-task x 10-frame schedule (issue 13).
WEBGL_BARS = 2000
#: Past this many bars in one SVG trace the white outline that separates neighbours is dropped: on bars a
#: few pixels wide it covered the colour (bleached bars).
OUTLINED_BARS = 300
#: The tallest WebGL canvas Chromium draws correctly (its MAX_VIEWPORT_DIMS, 8192 in headless Chromium and on many
#: GPUs). plotly.js sizes its WebGL canvas to the whole figure times ``plotGlPixelRatio`` (2 by default): past
#: this many device pixels the bars were drawn shifted against their rows (issue 30: four rows of bars above the
#: first label of a 4,550 px, 100-processor Gantt chart). :func:`gl_pixel_ratio` and :func:`gl_row_height` keep
#: every WebGL figure within it.
MAX_GL_PIXELS = 8192


CONFIG = {
    "displaylogo": False,
    "responsive": True,
    "modeBarButtonsToRemove": ["select2d", "lasso2d", "autoScale2d", "toggleSpikelines"],
}
#: JSON inside a <script> data block: these characters as JSON escapes, so no text can close the element.
_DATA_BLOCK_ESCAPES = {ord("<"): "\\u003C", ord(">"): "\\u003E", ord("&"): "\\u0026"}


def to_html(fig: go.Figure, div_id: str | None = None) -> str:
    """The figure as a ``<div>`` plus its JSON in a data block (``<script type="application/json">``, never
    executed); ``static/js/charts.js`` draws every such chart with plotly.js, both from static files. No inline
    script, so the Content-Security-Policy needs no 'unsafe-inline' (issue 25). A figure with WebGL Gantt bars
    is marked ``data-gl-gantt``: charts.js then expands their facts (:func:`gl_gantt_facts`)."""
    gl = any(isinstance(t.meta, dict) and "gantt" in t.meta for t in fig.data if hasattr(t, "meta"))
    div_id = div_id or f"chart-{uuid.uuid4().hex}"
    config: dict[str, object] = dict(CONFIG)
    if any(t.type.endswith("gl") for t in fig.data):
        config["plotGlPixelRatio"] = gl_pixel_ratio(fig)
    figure = pio.to_json(fig, validate=False, engine="json")  # {"data": ..., "layout": ...}
    payload = (figure.rstrip()[:-1] + ',"config":' + json.dumps(config) + "}").translate(_DATA_BLOCK_ESCAPES)
    marker = " data-gl-gantt" if gl else ""
    return (
        f'<div class="plotly-chart" id="{html.escape(div_id)}" data-figure="{html.escape(div_id)}-figure"{marker}'
        f' style="height:100%; width:100%;"></div>'
        f'<script type="application/json" id="{html.escape(div_id)}-figure">{payload}</script>'
    )


def gl_pixel_ratio(fig: go.Figure) -> int:
    """plotly.js's ``plotGlPixelRatio`` for ``fig``: 2 (its default, sharp lines) while the WebGL canvas stays
    within :data:`MAX_GL_PIXELS`, else 1."""
    height = fig.layout.height or 450
    return 2 if 2 * height <= MAX_GL_PIXELS else 1


def gl_row_height(rows: int, wanted: float, fixed: float) -> float:
    """The height of a Gantt row drawn with WebGL: ``wanted`` pixels unless the figure (``fixed`` pixels plus
    ``rows`` rows) would pass :data:`MAX_GL_PIXELS`, then as much as fits."""
    return min(wanted, (MAX_GL_PIXELS - fixed) / max(1, rows))


def esc(value: object) -> str:
    """A name as Plotly text: ``&``, ``<``, ``>`` and quotes become entities, so markup in a name is shown, not
    rendered (Plotly's hover, text, legend and tick labels understand ``<a href>``, ``<b>``, ``<br>``...)."""
    return html.escape(str(value))


def escs(values: Iterable[object]) -> list[str]:
    return [esc(v) for v in values]


def fmt(x: float) -> str:
    """A number in hover text: six significant digits."""
    return f"{x:.6g}"


#: Seconds per time unit, for the plain-words duration beside a large time (:func:`quantity`).
SECONDS_PER_UNIT = {"ns": 1e-9, "us": 1e-6, "µs": 1e-6, "ms": 1e-3, "s": 1.0, "min": 60.0, "h": 3600.0}


def quantity(x: float, unit: str = "") -> str:
    """A number for a title or label, with its unit: grouped digits, never an exponent for everyday sizes
    (``1,794,780 ms (29.9 min)``, not ``1.79478e+06``, issue 30); a time of a minute or more also in minutes or
    hours. Hover text keeps :func:`fmt`'s six significant digits."""
    if not math.isfinite(x):
        text = str(x)
    elif abs(x) >= 1000:
        text = f"{x:,.0f}"
    elif abs(x) >= 0.001 or x == 0:
        text = f"{x:.4g}" if abs(x) < 1 else f"{x:,.5g}"
    else:
        text = f"{x:.3g}"
    out = f"{text} {esc(unit)}" if unit else text
    seconds = x * SECONDS_PER_UNIT[unit] if unit in SECONDS_PER_UNIT and math.isfinite(x) else 0.0
    if abs(seconds) >= 3600:
        out += f" ({seconds / 3600:.1f} h)"
    elif abs(seconds) >= 60 and unit != "min":
        out += f" ({seconds / 60:.1f} min)"
    return out


def base_layout(fig: go.Figure, height: int) -> None:
    """The layout every dashboard figure shares: its height, margins, font and white background."""
    fig.update_layout(
        height=height,
        margin={"l": 10, "r": 10, "t": 40, "b": 10},
        font=FONT,
        plot_bgcolor="white",
        paper_bgcolor="white",
        hoverlabel={"bgcolor": "white", "font": FONT},
    )


def cycle_colours(keys: Iterable[str], palette: Sequence[str]) -> dict[str, str]:
    """A colour per key, in the order given, cycling through ``palette``."""
    return {k: palette[i % len(palette)] for i, k in enumerate(keys)}


def stacked_panels(titles: Sequence[str], rows: int, spacing: float) -> go.Figure:
    """Panels stacked in one column on a shared x axis (the timelines' layout), titled ``titles``."""
    return make_subplots(rows=rows, cols=1, shared_xaxes=True, vertical_spacing=spacing, subplot_titles=titles)


# ---- Gantt chart ------------------------------------------------------------------------------------
#: Niceness colours: the lowest niceness (the highest priority, HEFT4K's top-ranked tasks) darkest.
NICE_SCALE = [[0.0, "#08306b"], [0.5, "#4292c6"], [1.0, "#c6dbef"]]
MOVED_COLOUR = "#f2a541"
LOST_COLOUR = "#d64545"


@dataclass
class GanttPanel:
    """One schedule to draw: its rows come from ``platform`` (idle processors included) and its bars from
    ``schedule``; ``highlight`` (task, frame) pairs get their own trace called ``highlight_name``; ``notes``
    add a line to a bar's hover text."""

    title: str
    schedule: Schedule
    platform: Platform | None = None
    highlight: Collection[tuple[str, int]] = ()
    highlight_name: str = "critical path"
    highlight_colour: str = CRITICAL_COLOUR
    notes: Mapping[tuple[str, int], str] = field(default_factory=dict)


def frame_colour(frame: int) -> str:
    return FRAME_COLOURS[frame % len(FRAME_COLOURS)]


def gantt_traces(
    panel: GanttPanel,
    unit: str = "",
    *,
    row_of: Mapping[tuple[str, int], str] | None = None,
    nice: tuple[int, int] | None = None,
    frame_range: tuple[int, int] | None = None,
    thickness: float = 30,
) -> list[go.Bar | go.Scattergl]:
    """The bars of one schedule, the only place that decides how a Gantt bar looks.

    Past :data:`WEBGL_BARS` bars (and unless coloured by niceness) they are WebGL line segments
    ``thickness`` pixels thick (:func:`_gantt_gl_trace`), frames binned into at most
    :data:`MAX_FRAME_TRACES` colours; below, ``go.Bar`` as follows.

    Colour: by niceness when ``nice`` (the colour axis's range) is given; else by frame when the schedule has
    several (one trace per frame, or one trace on a colour scale over ``frame_range`` beyond
    :data:`MAX_FRAME_TRACES` frames); else one colour. The ``panel.highlight`` pairs (the critical path, lost
    or moved tasks) come last in their own trace: solid ``highlight_colour``, or outlined in it over their
    niceness colour. ``row_of`` puts a bar on its row (a CPU lane) instead of its processor's.
    """
    schedule = panel.schedule
    frames = sorted({a.frame for a in schedule.assignments})
    several = len(frames) > 1
    marked = set(panel.highlight)
    normal = [a for a in schedule.assignments if (a.task, a.frame) not in marked]
    highlighted = [a for a in schedule.assignments if (a.task, a.frame) in marked]

    # WebGL past WEBGL_BARS (niceness colours need a colour per bar, which WebGL lines do not have: SVG).
    webgl = nice is None and len(schedule.assignments) > WEBGL_BARS

    def bar(items: list[Assignment], name: str, colour: str | list, **style) -> go.Bar | go.Scattergl:
        if webgl:
            return _gantt_gl_trace(items, name, colour, unit, thickness, row_of=row_of, notes=panel.notes)
        return _gantt_trace(items, name, colour, several, unit, row_of=row_of, notes=panel.notes, **style)

    traces: list[go.Bar | go.Scattergl] = []
    if nice is not None:
        traces.append(bar(normal, "task", TASK_COLOUR, nice=nice))
    elif not several:
        traces.append(bar(normal, "task", TASK_COLOUR))
    elif len(frames) <= MAX_FRAME_TRACES:
        for f in frames:
            colour = frame_colour(f)
            text = "#1f2933" if colour in LIGHT_COLOURS else "white"
            traces.append(bar([a for a in normal if a.frame == f], f"frame {f}", colour, text_colour=text))
    elif webgl:  # a WebGL trace has one colour: frames binned into MAX_FRAME_TRACES colours of the scale
        lo, hi = frame_range or (frames[0], frames[-1])
        for group in _frame_bins(frames, lo, hi):
            colour = sample_colorscale(FRAME_SCALE, (group[0] - lo) / (hi - lo) if hi > lo else 0.0)[0]
            name = f"frame {group[0]}" if len(group) == 1 else f"frames {group[0]}-{group[-1]}"
            in_group = set(group)
            traces.append(bar([a for a in normal if a.frame in in_group], name, colour))
    else:
        lo, hi = frame_range or (frames[0], frames[-1])
        marker = {"colorscale": FRAME_SCALE, "cmin": lo, "cmax": hi, "showscale": True}
        marker["colorbar"] = {"title": {"text": "frame"}, "thickness": 12}
        # Viridis turns light in its upper third: dark labels there.
        cut = lo + 0.6 * (hi - lo)
        text = ["#1f2933" if a.frame > cut else "white" for a in normal]
        traces.append(bar(normal, "frames", [a.frame for a in normal], text_colour=text, marker_extra=marker))
    if highlighted:
        traces.append(bar(highlighted, panel.highlight_name, panel.highlight_colour, nice=nice, outline=True))
    return traces


def _frame_bins(frames: list[int], lo: int, hi: int) -> list[list[int]]:
    """``frames`` (sorted) in at most :data:`MAX_FRAME_TRACES` consecutive groups of equal span."""
    span = max(1, math.ceil((hi - lo + 1) / MAX_FRAME_TRACES))
    groups: dict[int, list[int]] = {}
    for f in frames:
        groups.setdefault((f - lo) // span, []).append(f)
    return list(groups.values())


def gantt_figure(
    schedule: Schedule,
    platform: Platform | None = None,
    dag: TaskGraph | None = None,
    critical: Iterable[tuple[str, int]] | None = None,
    time_unit: str | None = None,
    *,
    colour_by_niceness: bool = False,
    lanes: bool = False,
) -> go.Figure:
    """A Gantt chart of ``schedule``: one row per processor (in platform order, idle ones included).

    ``critical`` is the set of (task, frame) pairs to highlight; by default it is the schedule's critical
    path, computed when both ``dag`` and ``platform`` are given. ``colour_by_niceness`` colours the bars by
    their niceness (HEFT4K) and outlines the critical path instead; ``lanes`` gives every CPU of a multi-core
    processor its own row (see :func:`gantt_rows`).
    """
    if critical is None:
        critical = schedule.critical_path(dag, platform) if dag is not None and platform is not None else []
    unit = time_unit or (dag.time_unit if dag is not None else "")
    panel = GanttPanel("", schedule, platform, set(critical))
    rows, row_of = gantt_rows(schedule, platform, lanes)
    nice = _nice_range([schedule]) if colour_by_niceness else None
    fig = go.Figure()
    per_row: float = 30 if lanes else 44
    if nice is None and len(schedule.assignments) > WEBGL_BARS:
        per_row = gl_row_height(len(rows), per_row, 150)
    for trace in gantt_traces(panel, unit, row_of=row_of, nice=nice, thickness=per_row * 0.75 * 0.8):
        fig.add_trace(trace)
    makespan = schedule.makespan
    if schedule.assignments:
        _add_makespan_marker(fig, makespan, unit)
    base_layout(fig, height=max(260, int(150 + per_row * len(rows))))
    fig.update_layout(
        barmode="overlay",  # bars of both traces share a row's full height instead of splitting it
        bargap=0.25,
        # Legend top left, makespan label above the line: the mode bar keeps the top right corner.
        legend={"orientation": "h", "yanchor": "bottom", "y": 1.02, "xanchor": "left", "x": 0},
        margin={"l": 10, "r": 20, "t": 84, "b": 10},
        uniformtext={"minsize": 9, "mode": "hide"},
    )
    if nice is not None:
        _nice_axis(fig, nice)
    _gantt_axes(fig, unit, makespan, rows)
    return fig


def _add_makespan_marker(fig: go.Figure, makespan: float, unit: str = "") -> None:
    """A dashed line at the makespan, labelled above the plot area (where the label cannot hide a bar)."""
    fig.add_vline(x=makespan, line={"dash": "dash", "color": "#52606d", "width": 1})
    fig.add_annotation(
        x=makespan,
        y=1,
        xref="x",
        yref="paper",
        xanchor="right",
        yanchor="bottom",
        showarrow=False,
        text=f"makespan {quantity(makespan, unit)}",
        font={"size": 12, "color": "#323f4b"},
    )


def _gantt_axes(fig: go.Figure, unit: str, makespan: float, rows: Sequence[str]) -> None:
    """A linear time axis up to just past the makespan; one category row per processor (or CPU), top down."""
    fig.update_xaxes(
        type="linear",
        title_text=f"time ({esc(unit)})" if unit else "time",
        range=[0, makespan * 1.03 if makespan > 0 else 1],
        showgrid=True,
        gridcolor="#e4e7eb",
        zeroline=False,
        rangemode="tozero",
    )
    fig.update_yaxes(
        type="category",
        categoryorder="array",
        categoryarray=escs(rows),
        # An explicit reversed range, not autorange="reversed": autorange pads WebGL lines by 5 % of the rows,
        # blank rows above the first processor and below the last.
        range=[max(1, len(rows)) - 0.5, -0.5],
        title_text="processor",
        showgrid=False,
    )


def stacked_gantt_figure(
    panels: Sequence[GanttPanel],
    time_unit: str = "",
    *,
    colour_by_niceness: bool = False,
    lanes: bool = True,
    title_sep: str = " · ",
) -> go.Figure:
    """Several Gantt charts stacked on one shared time axis (``make_subplots(shared_xaxes=True)``): the
    algorithms of a comparison, a HEFT4K plan and its simulated run on Kubernetes, a schedule before and
    after a remap. Each panel has its own rows and a title ``"<title><title_sep>makespan <m>"``; bars are
    drawn by :func:`gantt_traces`, so frames and niceness get the same colours in every panel, and each
    legend entry (and colour bar) appears once."""
    layout = [gantt_rows(p.schedule, p.platform, lanes) for p in panels]
    heights = [max(2, len(rows)) for rows, _ in layout] or [1]
    per_row: float = 28 if lanes else 40
    fixed = 95 * max(1, len(panels)) + 60
    if not colour_by_niceness and any(len(p.schedule.assignments) > WEBGL_BARS for p in panels):
        per_row = gl_row_height(sum(heights), per_row, fixed)
    height = int(sum(heights) * per_row + fixed)
    fig = make_subplots(
        rows=max(1, len(panels)),
        cols=1,
        shared_xaxes=True,
        vertical_spacing=min(0.3, 80 / height),
        row_heights=heights,
        subplot_titles=[f"{esc(p.title)}{title_sep}makespan {quantity(p.schedule.makespan, time_unit)}" for p in panels]
        or None,
    )
    nice = _nice_range([p.schedule for p in panels]) if colour_by_niceness else None
    all_frames = [a.frame for p in panels for a in p.schedule.assignments]
    frame_range = (min(all_frames), max(all_frames)) if all_frames else None
    shown: set[str] = set()
    end = max((p.schedule.makespan for p in panels), default=0.0)
    for i, (panel, (rows, row_of)) in enumerate(zip(panels, layout, strict=True), start=1):
        traces = gantt_traces(
            panel, time_unit, row_of=row_of, nice=nice, frame_range=frame_range, thickness=per_row * 0.75 * 0.8
        )
        _add_gantt_panel(fig, i, panel, traces, rows, shown)
    base_layout(fig, height=height)
    fig.update_layout(
        barmode="overlay",
        bargap=0.25,
        # Legend in the top margin, left; each panel's title sits just above its own plot area.
        legend={"orientation": "h", "yanchor": "top", "y": 1.0, "yref": "container", "xanchor": "left", "x": 0},
        margin={"l": 10, "r": 20, "t": 76, "b": 10},
        uniformtext={"minsize": 9, "mode": "hide"},
    )
    fig.update_annotations(font={"size": 13, "color": "#323f4b"}, xanchor="left", x=0)
    if nice is not None:
        _nice_axis(fig, nice)
    fig.update_xaxes(
        type="linear",
        range=[0, end * 1.03 if end > 0 else 1],
        showgrid=True,
        gridcolor="#e4e7eb",
        zeroline=False,
    )
    fig.update_xaxes(title_text=f"time ({esc(time_unit)})" if time_unit else "time", row=max(1, len(panels)), col=1)
    return fig


def _add_gantt_panel(
    fig: go.Figure, i: int, panel: GanttPanel, traces: list[go.Bar], rows: Sequence[str], shown: set[str]
) -> None:
    """Panel ``i`` of a stacked Gantt: its bars (each legend entry and colour bar once in the figure), its
    makespan line, and its own processor rows."""
    for trace in traces:
        trace.showlegend = trace.name not in shown
        if trace.marker.showscale and trace.name in shown:
            trace.marker.showscale = False  # one colour bar for the whole figure
        shown.add(trace.name)
        fig.add_trace(trace, row=i, col=1)
    if panel.schedule.assignments:
        fig.add_vline(x=panel.schedule.makespan, line={"dash": "dash", "color": "#52606d", "width": 1}, row=i, col=1)
    fig.update_yaxes(
        type="category",
        categoryorder="array",
        categoryarray=escs(rows),
        range=[max(1, len(rows)) - 0.5, -0.5],  # explicit: see _gantt_axes
        showgrid=False,
        row=i,
        col=1,
    )


def gantt_rows(
    schedule: Schedule, platform: Platform | None = None, lanes: bool = False
) -> tuple[list[str], dict[tuple[str, int], str]]:
    """The rows of a Gantt chart, top to bottom, and the row of every (task, frame).

    Without ``lanes`` a row is a processor. With ``lanes`` a multi-core processor gets one row per CPU
    (``node · cpuK``, from the assignments' ``core``) or, when the assignments name no core (a simulated
    run, where tasks share CPUs), one row per overlapping lane (``node · #K``, first-fit by start time), so
    that bars never hide each other; a one-CPU processor with no overlap keeps a single row.
    """
    nodes = [p.id for p in platform.processors] if platform is not None else []
    nodes += sorted({a.processor for a in schedule.assignments} - set(nodes))
    if not lanes:
        return nodes, {(a.task, a.frame): a.processor for a in schedule.assignments}
    cores = {p.id: p.cores for p in platform.processors} if platform is not None else {}
    by_node: dict[str, list[Assignment]] = {}
    for a in sorted(schedule.assignments, key=lambda a: (a.start, a.finish, a.task, a.frame)):
        by_node.setdefault(a.processor, []).append(a)
    rows: list[str] = []
    row_of: dict[tuple[str, int], str] = {}
    for node in nodes:
        items = by_node.get(node, [])
        if items and all(a.core is not None for a in items):
            lane = {(a.task, a.frame): a.core for a in items}
            count = max(cores.get(node, 1), 1 + max(lane.values()))
            names = [f"{node} · cpu{k}" for k in range(count)]
        else:  # no core named (or an idle node): first-fit lanes, one row when nothing overlaps
            lane = _first_fit(items)
            count = 1 + max(lane.values(), default=0)
            names = [f"{node} · #{k + 1}" for k in range(count)]
        if count == 1:
            names = [node]
        rows += names
        for key, k in lane.items():
            row_of[key] = names[k]
    return rows, row_of


def _first_fit(items: list[Assignment]) -> dict[tuple[str, int], int]:
    ends: list[float] = []
    lane: dict[tuple[str, int], int] = {}
    for a in items:  # sorted by start
        k = next((i for i, end in enumerate(ends) if end <= a.start + 1e-9), len(ends))
        if k == len(ends):
            ends.append(a.finish)
        else:
            ends[k] = a.finish
        lane[(a.task, a.frame)] = k
    return lane


def _nice_range(schedules: Iterable[Schedule]) -> tuple[int, int]:
    values = [a.niceness for s in schedules for a in s.assignments if a.niceness is not None]
    lo, hi = (min(values), max(values)) if values else (0, 19)
    return (lo, hi if hi > lo else lo + 1)


def _nice_axis(fig: go.Figure, nice: tuple[int, int]) -> None:
    fig.update_layout(
        coloraxis={
            "colorscale": NICE_SCALE,
            "cmin": nice[0],
            "cmax": nice[1],
            "colorbar": {"title": {"text": "niceness", "side": "right"}, "thickness": 12, "len": 0.6},
        }
    )


def _gantt_trace(
    assignments: list[Assignment],
    name: str,
    colour: str | list,
    show_frame: bool,
    unit: str,
    *,
    row_of: Mapping[tuple[str, int], str] | None = None,
    notes: Mapping[tuple[str, int], str] | None = None,
    nice: tuple[int, int] | None = None,
    outline: bool = False,
    text_colour: str | list[str] = "white",
    marker_extra: dict | None = None,
) -> go.Bar:
    label = (lambda a: f"{esc(a.task)} [{a.frame}]") if show_frame else (lambda a: esc(a.task))
    # A time without a unit is ambiguous: say so rather than print a bare number.
    suffix = f" {esc(unit)}" if unit else " time units"
    row_of = row_of or {}
    notes = notes or {}
    has_nice = any(a.niceness is not None for a in assignments)
    outline_width = 1 if len(assignments) <= OUTLINED_BARS else 0
    marker: dict = {"color": colour, "line": {"color": "white", "width": outline_width}, **(marker_extra or {})}
    if nice is not None:
        values = [a.niceness if a.niceness is not None else nice[1] for a in assignments]
        marker = {"color": values, "coloraxis": "coloraxis", "line": {"color": "white", "width": outline_width}}
        if outline:  # a highlighted set keeps its colour as a thick outline
            marker["line"] = {"color": colour, "width": 3}
        # Light bars (high niceness) need dark text.
        text_colour = ["#1f2933" if (v - nice[0]) / (nice[1] - nice[0]) > 0.55 else "white" for v in values]
    name = esc(name)
    return go.Bar(
        name=name,
        legendgroup=name,
        orientation="h",
        y=[esc(row_of.get((a.task, a.frame), a.processor)) for a in assignments],
        base=[a.start for a in assignments],
        x=[a.finish - a.start for a in assignments],
        text=[label(a) for a in assignments],
        textposition="inside",
        insidetextanchor="middle",
        textfont={"color": text_colour},
        marker=marker,
        # The hover text is written here, not by a hovertemplate: with ``base=start`` Plotly's ``%{x}`` is the
        # bar's end in some cases, so a template's "duration" showed the finish time (issue 13).
        # customdata keeps each bar's facts for scripts (and tests) reading the figure.
        customdata=[_gantt_facts(a, notes) for a in assignments],
        hovertext=[_gantt_hover(a, suffix, has_nice, notes.get((a.task, a.frame))) for a in assignments],
        hovertemplate=f"%{{hovertext}}<extra>{name}</extra>",
        showlegend=True,
    )


def _gantt_gl_trace(
    assignments: list[Assignment],
    name: str,
    colour: str,
    unit: str,
    thickness: float,
    *,
    row_of: Mapping[tuple[str, int], str] | None = None,
    notes: Mapping[tuple[str, int], str] | None = None,
) -> go.Scattergl:
    """Bars as WebGL line segments ``thickness`` pixels thick, drawn by the GPU in one call: tens of thousands
    of bars stay fast and keep their colour at any width (an SVG bar's outline bleached thin ones).

    The trace carries its bars' facts once, compactly, in ``meta["gantt"]`` (:func:`gl_gantt_facts` as one
    JSON string), and ``static/js/charts.js`` (on charts :func:`to_html` marks ``data-gl-gantt``) expands them
    in the browser into the line points
    (start, middle, finish and a gap per bar: hover finds points, not lines) and their hover text, the
    same lines as :func:`_gantt_hover`'s with the duration written by Python (no ``%{x}``: the base/x
    pitfall of issue 13). Sent as text, the hover strings made a 1000 x 10 schedule page 5.7 MB and the
    server spent most of a second building them."""
    name = esc(name)
    return go.Scattergl(
        name=name,
        legendgroup=name,
        mode="lines",
        x=[],
        y=[],
        line={"color": colour, "width": thickness},
        connectgaps=False,
        hovertemplate=f"%{{hovertext}}<extra>{name}</extra>",
        # One JSON string: Plotly deep-copies a figure's lists element by element (half a second at 10,000 bars).
        meta={"gantt": json.dumps(gl_gantt_facts(assignments, unit, row_of or {}, notes or {}), separators=(",", ":"))},
        showlegend=True,
    )


def _round6(x: float) -> float:
    """``x`` to six significant digits (what :func:`fmt` prints), so that JSON carries no more."""
    return float(fmt(x))


def gl_gantt_facts(
    assignments: list[Assignment],
    unit: str,
    row_of: Mapping[tuple[str, int], str],
    notes: Mapping[tuple[str, int], str],
) -> dict:
    """The facts of WebGL Gantt bars, column by column (names escaped, times to six significant digits):
    ``rows`` and ``processors`` name lists, then per bar ``task``, ``frame``, ``row`` and ``processor``
    (indexes into those lists), ``start``, ``finish``, ``duration`` (``finish - start``, rounded after the
    subtraction) and ``note`` (when any bar has one); ``unit`` the suffix of every time."""
    rows: dict[str, int] = {}
    processors: dict[str, int] = {}
    names: dict[str, str] = {}  # escaped once per name: a task recurs in every frame
    facts: dict = {k: [] for k in ("task", "frame", "row", "processor", "start", "finish", "duration")}

    def name(value: str) -> str:
        return names.get(value) or names.setdefault(value, esc(value))

    for a in assignments:
        row = name(row_of.get((a.task, a.frame), a.processor))
        facts["task"].append(name(a.task))
        facts["frame"].append(a.frame)
        facts["row"].append(rows.setdefault(row, len(rows)))
        facts["processor"].append(processors.setdefault(name(a.processor), len(processors)))
        facts["start"].append(_round6(a.start))
        facts["finish"].append(_round6(a.finish))
        facts["duration"].append(_round6(a.finish - a.start))
    if any((a.task, a.frame) in notes for a in assignments):
        facts["note"] = [esc(notes.get((a.task, a.frame), "")) for a in assignments]
    suffix = f" {esc(unit)}" if unit else " time units"
    return {"unit": suffix, "rows": list(rows), "processors": list(processors)} | facts


def _gantt_facts(a: Assignment, notes: Mapping[tuple[str, int], str]) -> list:
    """One bar's customdata: task, frame, processor, start, finish, niceness and its note (names escaped)."""
    return [
        esc(a.task),
        a.frame,
        esc(a.processor),
        a.start,
        a.finish,
        "—" if a.niceness is None else a.niceness,
        f"<br>{esc(notes[(a.task, a.frame)])}" if (a.task, a.frame) in notes else "",
    ]


def _gantt_hover(a: Assignment, suffix: str, has_nice: bool, note: str | None) -> str:
    """One bar's hover text: task, frame, processor, start, finish and duration (``finish - start``), each
    time with its unit (``suffix``); names escaped."""
    lines = [
        f"<b>{esc(a.task)}</b> (frame {a.frame})",
        f"processor: {esc(a.processor)}",
        f"start: {fmt(a.start)}{suffix}",
        f"finish: {fmt(a.finish)}{suffix}",
        f"duration: {fmt(a.finish - a.start)}{suffix}",
    ]
    if has_nice:
        lines.append(f"niceness: {'—' if a.niceness is None else a.niceness}")
    if note:
        lines.append(esc(note))
    return "<br>".join(lines)


# ---- DAG ----------------------------------------------------------------------------------------------
def dag_levels(dag: TaskGraph) -> dict[str, int]:
    """Topological level of every task: 0 for entry tasks, else one more than its deepest predecessor."""
    pred = dag.predecessors()
    level: dict[str, int] = {}
    for t in dag.topological_order():
        level[t] = max((level[e.src] + 1 for e in pred[t]), default=0)
    return level


def dag_layout(dag: TaskGraph, sweeps: int = 2) -> dict[str, tuple[float, float]]:
    """(x, y) per task: x is the topological level; within a level tasks are centred and ordered by the
    barycentre heuristic (Sugiyama): alternate sweeps sort each level by the mean position of its
    neighbours in the previous level, down then up, which removes many edge crossings (``sweeps=0`` keeps
    the input order)."""
    level = dag_levels(dag)
    pred = dag.predecessors()
    succ = dag.successors()
    layers: dict[int, list[str]] = {}
    for t in dag.topological_order():
        layers.setdefault(level[t], []).append(t)
    index = {t: float(i) for members in layers.values() for i, t in enumerate(members)}

    def reorder(lv: int, neighbours: dict, end: str) -> None:
        members = layers[lv]
        key = {
            t: (fmean(index[getattr(e, end)] for e in neighbours[t]) if neighbours[t] else index[t], i)
            for i, t in enumerate(members)
        }
        layers[lv] = sorted(members, key=key.__getitem__)
        for i, t in enumerate(layers[lv]):
            index[t] = float(i) - (len(members) - 1) / 2.0

    for t_members in layers.values():
        for i, t in enumerate(t_members):
            index[t] = float(i) - (len(t_members) - 1) / 2.0
    order = sorted(layers)
    for _ in range(sweeps):
        for lv in order[1:]:
            reorder(lv, pred, "src")
        for lv in reversed(order[:-1]):
            reorder(lv, succ, "dst")
    if sweeps:
        for lv in order[1:]:
            reorder(lv, pred, "src")
    # y grows upwards in Plotly: negate so the first task of a level is drawn on top.
    return {t: (float(level[t]), -index[t]) for t in dag.tasks}


def _cost_colours(values: list[float]) -> tuple[list[float], dict]:
    """Marker colours for task costs: linear, or log10 when costs span more than 20x (a real workflow's
    long tasks would otherwise wash every short one out to white)."""
    scale = [[0.0, "#c6dbef"], [0.5, "#4292c6"], [1.0, "#08306b"]]
    positive = [v for v in values if v > 0]
    if len(positive) == len(values) and positive and max(positive) / min(positive) > 20:
        lo, hi = math.floor(math.log10(min(positive))), math.ceil(math.log10(max(positive)))
        ticks = list(range(lo, hi + 1))
        labels = [fmt(10.0**k) if k < 3 else f"{10 ** (k - 3):g}k" if k < 6 else f"1e{k}" for k in ticks]
        return [math.log10(v) for v in values], {
            "colorscale": scale,
            "colorbar_tickvals": ticks,
            "colorbar_ticktext": labels,
        }
    return values, {"colorscale": scale}


def add_edge_traces(
    fig: go.Figure,
    segments: Sequence[tuple[tuple[float, float], tuple[float, float], str]],
    *,
    name: str,
    hover_name: str,
    width: float,
    hover_size: int,
    large: bool | None = None,
) -> None:
    """Draw ``segments`` ((x0, y0), (x1, y1), hover text) as lines in one trace, with an invisible marker at
    each middle that carries the hover text (Plotly lines have no hover of their own between their points).

    ``large`` (by default: past :data:`LARGE_GRAPH` segments): both traces are WebGL and their columns numpy
    arrays (NaN between segments), which Plotly copies whole instead of validating point by point (seconds
    at 30,000 edges);
    past :data:`MAX_EDGE_HOVER` the hover markers are left out (the tasks' hover gives their degrees)."""
    large = len(segments) > LARGE_GRAPH if large is None else large
    xs: list[float | None] = []
    ys: list[float | None] = []
    for (x0, y0), (x1, y1), _ in segments:
        xs += [x0, x1, None]
        ys += [y0, y1, None]
    line = {"color": EDGE_COLOUR, "width": width}
    # Large: WebGL, and columns built here from checked values (Plotly's per-string check took most of a second).
    scatter = partial(go.Scattergl, _validate=False) if large else go.Scatter
    fig.add_trace(
        scatter(
            x=_column(xs, large),
            y=_column(ys, large),
            mode="lines",
            line=line,
            hoverinfo="skip",
            name=name,
            showlegend=False,
        )
    )
    if len(segments) > MAX_EDGE_HOVER:
        return
    fig.add_trace(
        scatter(
            x=_column([(a[0] + b[0]) / 2 for a, b, _ in segments], large),
            y=_column([(a[1] + b[1]) / 2 for a, b, _ in segments], large),
            mode="markers",
            marker={"size": hover_size, "color": EDGE_COLOUR, "opacity": 0},
            hovertext=_column([text for _, _, text in segments], large),
            hoverinfo="text",
            name=hover_name,
            showlegend=False,
        )
    )


def _column(values: Sequence, large: bool):
    """A trace's column: the list itself, or for a large figure a numpy array (floats with NaN for None, or
    strings), which Plotly takes whole."""
    if not large:
        return values
    if values and isinstance(values[0], str):
        return np.array(values)
    return np.array([np.nan if v is None else v for v in values], dtype=float)


def dag_figure(dag: TaskGraph) -> go.Figure:
    """The DAG drawn in layers by topological level; hover shows a task's costs or an edge's data."""
    pos = dag_layout(dag, sweeps=1 if len(dag.tasks) > LARGE_GRAPH else 2)  # a sweep: 0.4 s at 10,000 tasks
    fig = go.Figure()
    add_edge_traces(
        fig,
        [(pos[e.src], pos[e.dst], f"<b>{esc(e.src)} → {esc(e.dst)}</b><br>data: {fmt(e.data)}") for e in dag.edges],
        name="edges",
        hover_name="edge data",
        width=1.2,
        hover_size=10,
        large=len(dag.tasks) > LARGE_GRAPH,  # with the tasks: SVG edges under SVG tasks draw in order
    )
    labelled = len(dag.tasks) <= MAX_LABELLED_TASKS
    if len(dag.edges) <= MAX_ARROWS:
        _add_dag_arrows(fig, dag, pos)
    fig.add_trace(_dag_task_trace(dag, pos, labelled))  # last: tasks over edges and arrow heads
    _dag_axes(fig, pos, labelled)
    return fig


def _dag_task_trace(dag: TaskGraph, pos: Mapping[str, tuple[float, float]], labelled: bool) -> go.Scatter:
    """The tasks: coloured by mean cost (with its colour bar), diamonds for critical tasks, costs on hover."""
    unit = dag.time_unit
    tasks = list(dag.tasks.values())
    colours, colour_opts = _cost_colours([fmean(t.cost.values()) for t in tasks])
    colorbar = {"title": {"text": f"mean cost ({esc(unit)})", "side": "right"}, "thickness": 12}
    if "colorbar_tickvals" in colour_opts:
        colorbar["tickvals"] = colour_opts["colorbar_tickvals"]
        colorbar["ticktext"] = colour_opts["colorbar_ticktext"]
    large = len(tasks) > LARGE_GRAPH  # WebGL, numpy columns, no per-point validation (see add_edge_traces)
    scatter = partial(go.Scattergl, _validate=False) if large else go.Scatter
    return scatter(
        x=_column([pos[t.id][0] for t in tasks], large),
        y=_column([pos[t.id][1] for t in tasks], large),
        mode="markers+text" if labelled else "markers",
        text=None if large else [esc(t.id) for t in tasks],
        textposition=None if large else "top center",
        marker={
            "size": 18 if labelled else 12,
            "color": _column(colours, large),
            "colorscale": colour_opts["colorscale"],
            "showscale": True,
            "colorbar": colorbar,
            "symbol": _column(["diamond" if t.critical else "circle" for t in tasks], large),
            "line": {"color": "#1f2933", "width": 1},
        },
        hovertext=_column(_dag_task_hover(dag, pos, tasks), large),
        hoverinfo="text",
        name="tasks",
        showlegend=False,
    )


def _dag_task_hover(dag: TaskGraph, pos: Mapping[str, tuple[float, float]], tasks: Sequence) -> list[str]:
    """Per task: its id (and name), level, in/out degree, cost per processor class, and whether it is critical."""
    unit = dag.time_unit
    succ_count = {t: len(es) for t, es in dag.successors().items()}
    pred_count = {t: len(es) for t, es in dag.predecessors().items()}
    hover = []
    names: dict[str, str] = {}  # the processor classes' escaped names, once each
    suffix = f" {esc(unit)}"
    for t in tasks:
        costs = "<br>".join(
            f"  {names.get(k) or names.setdefault(k, esc(k))}: {fmt(v)}{suffix}" for k, v in sorted(t.cost.items())
        )
        title = f"<b>{esc(t.id)}</b>" + (f" ({esc(t.name)})" if t.name and t.name != t.id else "")
        flags = "<br><i>critical task</i>" if t.critical else ""
        hover.append(
            f"{title}<br>level {int(pos[t.id][0])}, {pred_count[t.id]} in / {succ_count[t.id]} out"
            f"<br>cost:<br>{costs}{flags}"
        )
    return hover


def _add_dag_arrows(fig: go.Figure, dag: TaskGraph, pos: Mapping[str, tuple[float, float]]) -> None:
    """An arrow head on every edge, 82 % of the way to its destination (clear of the task's marker), all in
    one marker trace: a point at each edge's source (size 0) then one at its head, an ``arrow`` symbol turned
    by ``angleref="previous"`` along the line from the point before it, in screen space, so it follows the
    edge at any zoom. One annotation per edge cost the server 17 ms each (plotly validates and copies the
    whole layout per ``add_annotation``: 1.85 s of CPU for a 58-task, 107-edge DAG, issue 30)."""
    xs: list[float] = []
    ys: list[float] = []
    for e in dag.edges:
        (x0, y0), (x1, y1) = pos[e.src], pos[e.dst]
        xs += [x0, x0 + 0.82 * (x1 - x0)]
        ys += [y0, y0 + 0.82 * (y1 - y0)]
    fig.add_trace(
        go.Scatter(
            x=xs,
            y=ys,
            mode="markers",
            marker={
                "symbol": "arrow",
                "angleref": "previous",
                "size": [0, 10] * len(dag.edges),
                "color": EDGE_COLOUR,
                "line": {"width": 0},
            },
            hoverinfo="skip",
            name="edge directions",
            showlegend=False,
        )
    )


def _dag_axes(fig: go.Figure, pos: Mapping[str, tuple[float, float]], labelled: bool) -> None:
    """Height from the tallest level; x ticks per level; y hidden, with room for the top row's labels."""
    width_levels = max((int(x) for x, _ in pos.values()), default=0) + 1
    tallest = max(
        (sum(1 for x, _ in pos.values() if int(x) == lv) for lv in range(width_levels)),
        default=1,
    )
    base_layout(fig, height=int(min(900, max(320, 60 + 34 * tallest))))
    fig.update_xaxes(
        title_text="topological level",
        tickmode="linear",
        dtick=1,
        showgrid=False,
        zeroline=False,
        range=[-0.5, width_levels - 0.5],
    )
    ys = [y for _, y in pos.values()]
    pad = 0.8 if labelled else 0.5  # room for the labels above the top row
    fig.update_yaxes(visible=False, showgrid=False, zeroline=False, range=[min(ys) - 0.5, max(ys) + pad])


# ---- Cluster network ----------------------------------------------------------------------------------
def network_layout(platform: Platform) -> dict[str, tuple[float, float]]:
    """Positions of the processors: on a circle for small clusters, a seeded spring layout otherwise."""
    ids = [p.id for p in platform.processors]
    if len(ids) <= 8 or not platform.links:
        n = len(ids)
        return {
            pid: (math.cos(2 * math.pi * i / n + math.pi / 2), math.sin(2 * math.pi * i / n + math.pi / 2))
            if n > 1
            else (0.0, 0.0)
            for i, pid in enumerate(ids)
        }
    import networkx as nx

    g = nx.Graph()
    g.add_nodes_from(ids)
    g.add_edges_from((lk.src, lk.dst) for lk in platform.links)
    return {k: (float(v[0]), float(v[1])) for k, v in nx.spring_layout(g, seed=7).items()}


def network_figure(
    platform: Platform,
    status: Mapping[str, str] | None = None,
    bandwidth_scale: float = 1.0,
    bandwidth_unit: str = "",
    latency_unit: str = "",
) -> go.Figure:
    """Nodes (colour = status, symbol = processor class) and links (hover: bandwidth, latency).

    ``bandwidth_scale`` converts the platform's bandwidth to the unit shown (a cluster platform stores
    Mbit per ms; times 1000 shows Mbit/s).
    """
    status = status or {}
    pos = network_layout(platform)
    fig = go.Figure()

    def link_hover(lk) -> str:
        bw = "unlimited" if lk.bandwidth is None else f"{fmt(lk.bandwidth * bandwidth_scale)} {bandwidth_unit}"
        return f"<b>{esc(lk.src)} ↔ {esc(lk.dst)}</b><br>bandwidth: {bw}<br>latency: {fmt(lk.latency)} {latency_unit}"

    add_edge_traces(
        fig,
        [(pos[lk.src], pos[lk.dst], link_hover(lk)) for lk in platform.links],
        name="links",
        hover_name="link data",
        width=2,
        hover_size=12,
    )
    # One trace per status so the legend explains the colours.
    for trace in _status_traces(platform, status, pos):
        fig.add_trace(trace)
    base_layout(fig, height=420)
    fig.update_layout(legend={"orientation": "h", "yanchor": "bottom", "y": 1.02, "xanchor": "right", "x": 1})
    fig.update_xaxes(visible=False, range=[-1.4, 1.4] if len(platform.processors) <= 8 else None)
    fig.update_yaxes(visible=False, range=[-1.35, 1.3] if len(platform.processors) <= 8 else None, scaleanchor="x")
    return fig


def _status_traces(
    platform: Platform, status: Mapping[str, str], pos: Mapping[str, tuple[float, float]]
) -> Iterator[go.Scatter]:
    """The processors, one trace per status (known statuses first): colour = status, symbol = class."""
    labelled = len(platform.processors) <= 50
    for state in [*STATUS_COLOURS, *sorted(set(status.values()) - set(STATUS_COLOURS))]:
        procs = [p for p in platform.processors if status.get(p.id, "Ready") == state]
        if not procs:
            continue
        yield go.Scatter(
            x=[pos[p.id][0] for p in procs],
            y=[pos[p.id][1] for p in procs],
            mode="markers+text" if labelled else "markers",
            text=[esc(p.id) for p in procs],
            textposition="bottom center",
            marker={
                "size": 24,
                "color": STATUS_COLOURS.get(state, "#9aa1a9"),
                "symbol": [CLASS_SYMBOLS.get(p.cls, "circle") for p in procs],
                "line": {"color": "white", "width": 2},
            },
            hovertext=[
                f"<b>{esc(p.id)}</b><br>class: {esc(p.cls)}<br>speed: {fmt(p.speed)}<br>{esc(state)}" for p in procs
            ],
            hoverinfo="text",
            name=esc(state),
        )

"""DAG drawings at scale (issue 13): edges in one trace whatever their number (the 58-task application page
added its edges one by one and took seconds); past LARGE_GRAPH tasks or edges, WebGL traces from numpy
columns that keep every task's hover text; stacked Gantt charts past WEBGL_BARS bars stay WebGL too."""

import math

import numpy as np
import pytest
from django.urls import reverse

from apps.ui import charts
from continuum.engine.device import algorithms
from continuum.engine.device.generators import layered_dag, related_platform
from tests.conftest import make_application


@pytest.mark.django_db
def test_the_montage_application_page_draws_its_edges_in_one_trace(member, fleet):
    app = make_application(fleet, "montage-chameleon-2mass-005d-001.json")
    graph = app.graph
    assert len(graph.tasks) == 58
    response = member.get(reverse("workloads:application", args=[app.pk]))
    assert response.status_code == 200
    fig = charts.dag_figure(graph)
    lines = [t for t in fig.data if t.mode == "lines"]
    assert len(lines) == 1 and len(fig.data) == 4  # edges, their hover markers, arrow heads, tasks
    assert sum(1 for x in lines[0].x if x is None) == len(graph.edges)
    assert fig.data[-1].name == "tasks"


@pytest.mark.parametrize("tasks", [12, 58])
def test_dag_arrow_heads_are_one_trace_not_an_annotation_per_edge(tasks):
    """Issue 30: one annotation per edge cost the 58-task page 1.2 s of server CPU (plotly copies the layout per
    add_annotation). The heads are one marker trace: one per edge, 82 % of the way along it, turned along it."""
    dag = layered_dag(tasks, seed=3, processors=8)
    assert len(dag.edges) <= charts.MAX_ARROWS
    fig = charts.dag_figure(dag)
    assert len(fig.layout.annotations) == 0
    [arrows] = [t for t in fig.data if t.name == "edge directions"]
    assert arrows.marker.symbol == "arrow" and arrows.marker.angleref == "previous"
    pos = charts.dag_layout(dag)
    heads = [(x, y) for x, y, size in zip(arrows.x, arrows.y, arrows.marker.size, strict=True) if size]
    assert len(heads) == len(dag.edges)
    for (hx, hy), e in zip(heads, dag.edges, strict=True):
        (x0, y0), (x1, y1) = pos[e.src], pos[e.dst]
        assert math.isclose(hx, x0 + 0.82 * (x1 - x0)) and math.isclose(hy, y0 + 0.82 * (y1 - y0))
    # Each head's "previous" point is its edge's source: the marker turns along the edge.
    sources = list(zip(arrows.x[::2], arrows.y[::2], strict=True))
    assert sources == [pos[e.src] for e in dag.edges]


def test_a_large_dag_is_webgl_with_every_task_hovered():
    dag = layered_dag(charts.LARGE_GRAPH + 500, seed=1, processors=3)
    fig = charts.dag_figure(dag)
    assert {t.type for t in fig.data} == {"scattergl"}
    edges = next(t for t in fig.data if t.mode == "lines")
    assert isinstance(edges.x, np.ndarray) and int(np.isnan(edges.x).sum()) == len(dag.edges)
    tasks = fig.data[-1]
    assert len(tasks.hovertext) == len(dag.tasks)
    first = dag.tasks[next(iter(dag.tasks))]
    assert tasks.hovertext[0].startswith(f"<b>{first.id}</b>")
    for k, v in first.cost.items():
        assert f"  {k}: {charts.fmt(v)} {dag.time_unit}" in tasks.hovertext[0]
    html = charts.to_html(fig)
    assert "scattergl" in html and math.isfinite(len(html))


def test_stacked_gantt_charts_past_webgl_bars_are_webgl_with_one_legend_entry_each():
    platform = related_platform(4, seed=2)
    dag = layered_dag(1300, seed=2, processors=4)
    panels = [
        charts.GanttPanel(name, algorithms.run(name, dag, platform, frames=2), platform) for name in ("heft", "gfl")
    ]
    fig = charts.stacked_gantt_figure(panels, dag.time_unit)
    assert {t.type for t in fig.data} == {"scattergl"}
    shown = [t.name for t in fig.data if t.showlegend]
    assert sorted(shown) == sorted(set(shown)) and {"frame 0", "frame 1"} <= set(shown)

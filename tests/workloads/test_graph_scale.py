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
    assert len(lines) == 1 and len(fig.data) == 3  # edges, their hover markers, tasks
    assert sum(1 for x in lines[0].x if x is None) == len(graph.edges)
    assert len(fig.layout.annotations) == (len(graph.edges) if len(graph.edges) <= charts.MAX_ARROWS else 0)


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

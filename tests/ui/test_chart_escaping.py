"""Names in Plotly figures are escaped (issue 10, trust boundary): Plotly renders a subset of HTML in hover text,
text, legend entries, titles and tick labels, so a task named ``<a href="javascript:alert(1)">x</a>`` would be a
live link on the page. Every chart builder of ``apps/*/charts.py`` goes through ``apps.ui.charts.esc``."""

import json
from datetime import UTC, datetime
from types import SimpleNamespace

import plotly.graph_objects as go
import pytest

from apps.containers import charts as container_charts
from apps.realtime import charts as rt_charts
from apps.scheduling import charts as scheduling_charts
from apps.ui import charts
from apps.verification import charts as verification_charts
from continuum.engine.containers.rosgraph import RosGraph
from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import Assignment, Schedule

EVIL = '<a href="javascript:alert(1)">x</a>'
EVIL2 = "<img src=x onerror=alert(2)>"


def plain_json(fig: go.Figure) -> str:
    """The figure's JSON with strings as they are (``to_json`` itself writes ``<`` as ``\\u003c``)."""
    return json.dumps(json.loads(fig.to_json()), ensure_ascii=False)


def assert_escaped(fig: go.Figure) -> dict:
    text = plain_json(fig)
    assert "&lt;a href=&quot;javascript:alert(1)&quot;&gt;x&lt;/a&gt;" in text
    assert "<a " not in text and "<img" not in text, text
    return json.loads(text)


def hover_strings(doc: dict) -> str:
    """Every hover text, hover template and custom data value of the figure, as one string."""
    parts = []
    for trace in doc["data"]:
        for key in ("hovertext", "hovertemplate", "customdata", "text"):
            if key in trace:
                parts.append(json.dumps(trace[key], ensure_ascii=False))
    return " ".join(parts)


def schedule() -> Schedule:
    return Schedule("heft", [Assignment(EVIL, EVIL2, 0.0, 2.0), Assignment("b", "cpu1", 2.0, 3.0),
                             Assignment(EVIL, EVIL2, 3.0, 4.0, frame=1)])  # fmt: skip


def test_a_task_named_like_a_link_is_escaped_in_the_gantt_hover_text():
    doc = assert_escaped(charts.gantt_figure(schedule(), time_unit=EVIL2))
    hover = hover_strings(doc)
    assert "&lt;a href" in hover and "<a " not in hover
    bars = [t for t in doc["data"] if t["type"] == "bar"]
    assert "&lt;img src=x onerror=alert(2)&gt;" in bars[0]["y"]  # the processor, a tick label
    assert "&lt;img src=x onerror=alert(2)&gt;" in doc["layout"]["yaxis"]["categoryarray"]


def test_stacked_gantt_titles_legend_and_notes_are_escaped():
    panel = charts.GanttPanel(EVIL, schedule(), highlight={(EVIL, 0)}, highlight_name=f"lost (on {EVIL2})",
                              notes={("b", 0): EVIL})  # fmt: skip
    doc = assert_escaped(charts.stacked_gantt_figure([panel], EVIL2))
    assert any(a["text"].startswith("&lt;a href") for a in doc["layout"]["annotations"])
    assert "lost (on &lt;img src=x onerror=alert(2)&gt;)" in {t.get("name") for t in doc["data"]}


def test_dag_and_network_figures_escape_task_processor_and_status_names():
    dag = TaskGraph.from_dict({"time_unit": EVIL2, "tasks": [{"id": EVIL, "name": EVIL2, "cost": {EVIL2: 1.0}},
                                                             {"id": "b", "cost": {EVIL2: 2.0}}],
                               "edges": [{"src": EVIL, "dst": "b", "data": 1.0}]})  # fmt: skip
    assert_escaped(charts.dag_figure(dag))
    platform = Platform.from_dict({"processors": [{"id": EVIL, "class": EVIL2}, {"id": "p2"}],
                                   "links": [{"src": EVIL, "dst": "p2", "bandwidth": 1.0}]})  # fmt: skip
    assert_escaped(charts.network_figure(platform, status={EVIL: EVIL2}))
    bars = plain_json(scheduling_charts.comparison_bars_figure({EVIL: {"makespan": 1.0}}))  # names shown upper-case
    assert "&lt;A HREF=&quot;JAVASCRIPT:ALERT(1)&quot;&gt;X&lt;/A&gt;" in bars and "<A " not in bars


def test_container_figures_escape_ros_node_topic_container_and_node_names():
    graph = RosGraph.from_dict({"format": "continuum.rosgraph/v1", "nodes": [{"name": EVIL}, {"name": "b"}],
                                "topics": [{"name": EVIL2, "publishers": [EVIL], "subscribers": ["b"],
                                            "rate_hz": 1, "msg_bytes": 10}]})  # fmt: skip
    assert_escaped(container_charts.rosgraph_figure(graph, {EVIL: [EVIL], "c2": ["b"]}))
    containers = [{"name": EVIL, "nodes": [EVIL2]}, {"name": "c2", "nodes": ["b"]}]
    assert_escaped(container_charts.container_figure(containers, [{"a": EVIL, "b": "c2", "bytes_per_s": 5.0}]))
    cluster = {"nodes": [{"name": EVIL, "arch": EVIL2}, {"name": "n2", "arch": "arm64"}], "links": []}
    plan = {"placements": [{"node": EVIL, "container": EVIL2, "score": 1.0}], "pending": [{"container": EVIL}]}
    traffic = [{"a": EVIL, "b": "n2", "bytes_per_s": 3.0}]
    assert_escaped(container_charts.placement_figure(cluster, plan, traffic, [EVIL2]))
    images = {"images": [{"name": EVIL, "kind": "container", "size_mib": 1.0, "unique_mib": 0.5}]}
    assert_escaped(container_charts.disk_figure(images))


def test_realtime_and_verification_figures_escape_node_and_container_names():
    nodes = [{"name": EVIL, "rt": True, "criticality": EVIL2, "threshold": 3.8, "cpu": 4, "by_class": {"A": 1.0},
              "tainted": True}]  # fmt: skip
    assert_escaped(rt_charts.utilization_figure(nodes))
    now = datetime(2026, 3, 1, tzinfo=UTC)
    reports = [{"node": EVIL, "container": EVIL2, "time": now, "missed_period": 3, "missed_total": 3}]
    events = [{"node": EVIL, "time": now, "kind": "eviction", "victim": EVIL2, "container": EVIL}]
    assert_escaped(rt_charts.timeline_figure(reports, events, [], 10, now))
    runs = [SimpleNamespace(t=float(t), nodes={EVIL: {"cpu": 10.0 * t, "monitors": t, "threshold": 80}},
                            makespan_ms=None) for t in range(3)]  # fmt: skip
    assert_escaped(verification_charts.timeline_figure(runs, []))


@pytest.mark.parametrize(("raw", "shown"), [("a&b", "a&amp;b"), ("plain_name-1", "plain_name-1"), (7, "7")])
def test_esc_is_html_escape(raw, shown):
    assert charts.esc(raw) == shown

"""Gantt hover text (issue 13): every bar's tooltip names the task, processor, start, finish, duration with its
unit and frame, computed in Python. A hovertemplate's ``%{x}`` on a ``base=start`` bar showed the finish time
as the duration."""

import json

import plotly.graph_objects as go
import pytest

from apps.ui import charts
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import Assignment, Schedule


def bar_hovers(fig: go.Figure) -> list[str]:
    doc = json.loads(fig.to_json())
    out: list[str] = []
    for trace in doc["data"]:
        if trace["type"] != "bar":
            continue
        # The template must not compute anything from the bar's geometry.
        assert "%{x" not in trace.get("hovertemplate", ""), trace["hovertemplate"]
        out += trace["hovertext"]
    return out


def the_hover(hovers: list[str], task: str, frame: int = 0) -> str:
    [text] = [h for h in hovers if h.startswith(f"<b>{task}</b> (frame {frame})")]
    return text


def small(frames: int = 1, niceness: int | None = None) -> Schedule:
    items = []
    for f in range(frames):
        items += [
            Assignment("a", "cpu0", 0.0 + 20 * f, 5.0 + 20 * f, frame=f, niceness=niceness),
            Assignment("b", "cpu1", 5.0 + 20 * f, 12.0 + 20 * f, frame=f, niceness=niceness),
        ]
    return Schedule("heft", items)


def assert_b(text: str, start: float = 5, finish: float = 12) -> None:
    assert "processor: cpu1" in text
    assert f"start: {start:g} ms" in text
    assert f"finish: {finish:g} ms" in text
    assert "duration: 7 ms" in text, text
    assert "duration: 12" not in text


@pytest.mark.parametrize("frames", [1, 3, charts.MAX_FRAME_TRACES + 2])
def test_a_bar_from_5_to_12_says_duration_7_with_its_unit(frames):
    hovers = bar_hovers(charts.gantt_figure(small(frames), time_unit="ms"))
    assert len(hovers) == 2 * frames
    assert_b(the_hover(hovers, "b"))
    if frames > 1:
        assert_b(the_hover(hovers, "b", 1), 25, 32)


def test_highlighted_niceness_coloured_and_laned_bars_say_the_same():
    platform = Platform.from_dict({"processors": [{"id": "cpu0", "cores": 2}, {"id": "cpu1", "cores": 2}], "links": []})
    fig = charts.gantt_figure(
        small(niceness=3), platform, critical=[("b", 0)], time_unit="ms", colour_by_niceness=True, lanes=True
    )
    text = the_hover(bar_hovers(fig), "b")
    assert_b(text)
    assert "niceness: 3" in text


def test_stacked_gantt_panels_say_duration_and_notes():
    panels = [
        charts.GanttPanel("plan", small(2)),
        charts.GanttPanel("run", small(2), highlight=[("b", 1)], notes={("b", 1): "moved <here>"}),
    ]
    hovers = bar_hovers(charts.stacked_gantt_figure(panels, "ms"))
    assert len(hovers) == 8
    noted = [h for h in hovers if "moved" in h]
    assert len(noted) == 1 and "moved &lt;here&gt;" in noted[0]
    assert_b(noted[0].split("<br>moved")[0], 25, 32)


def test_a_time_without_a_unit_says_it_has_none():
    text = the_hover(bar_hovers(charts.gantt_figure(small())), "b")
    assert "duration: 7 time units" in text

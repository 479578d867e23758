"""The Gantt chart draws every bar on its own row at scale (issue 30, item 1).

A 1000-task x 10-frame schedule on 100 processors drew four rows of bars above the first processor's label:
the figure was 4,550 px tall and plotly.js sizes its WebGL canvas to the figure times ``plotGlPixelRatio``
(2), past Chromium's 8,192-pixel viewport, so the GPU drew the bars shifted against the axis; and
``autorange="reversed"`` padded WebGL lines with blank rows above the first label. These tests read the figure
(its rows, ranges, heights and the page's plotly config); tests/dashboard/test_gantt_browser.py looks at
the pixels."""

import json

import pytest

from apps.ui import charts
from continuum.engine.core.platform import Platform, Processor
from continuum.engine.core.schedule import Assignment, Schedule

ROWS = 100


def wide_schedule(rows: int = ROWS, per_row: int = 30, frames: int = 1) -> tuple[Schedule, Platform]:
    """``rows`` processors each running ``per_row`` tasks per frame: past WEBGL_BARS bars in all."""
    platform = Platform([Processor(f"p{i}", "cpu") for i in range(rows)])
    items = [
        Assignment(f"t{i}-{k}", f"p{i}", 10.0 * k + 100 * f * per_row, 10.0 * k + 8 + 100 * f * per_row, frame=f)
        for f in range(frames)
        for i in range(rows)
        for k in range(per_row)
    ]
    return Schedule("heft", items), platform


def gl_bars(fig) -> list[dict]:
    return [json.loads(t.meta["gantt"]) for t in fig.data if isinstance(t.meta, dict) and "gantt" in t.meta]


def assert_rows_match(fig, yaxis: str, rows: list[str]) -> None:
    """Every bar's row is one of the axis's categories, and the axis shows exactly those rows top down: row
    k at position k, the range from the last row's bottom edge to the first row's top edge."""
    axis = fig.layout[yaxis]
    assert list(axis.categoryarray) == rows
    assert list(axis.range) == [len(rows) - 0.5, -0.5]
    assert axis.autorange in (None, False)
    for facts in gl_bars(fig):
        assert set(facts["rows"]) <= set(rows)


def page_config(fig) -> dict:
    html = charts.to_html(fig, div_id="g")
    start = html.index('{"displaylogo"')
    return json.JSONDecoder().raw_decode(html[start:])[0]


@pytest.mark.parametrize("frames", [1, 10])
def test_a_100_processor_webgl_gantt_fits_the_webgl_canvas_with_rows_matching_labels(frames):
    schedule, platform = wide_schedule(frames=frames)
    assert len(schedule.assignments) > charts.WEBGL_BARS
    fig = charts.gantt_figure(schedule, platform=platform, critical=[])
    assert gl_bars(fig), "drawn with WebGL"
    assert_rows_match(fig, "yaxis", [f"p{i}" for i in range(ROWS)])
    ratio = page_config(fig)["plotGlPixelRatio"]
    assert fig.layout.height * ratio <= charts.MAX_GL_PIXELS


def test_a_gantt_too_tall_for_webgl_shrinks_its_rows():
    schedule, platform = wide_schedule(rows=400, per_row=8)
    fig = charts.gantt_figure(schedule, platform=platform, critical=[])
    assert gl_bars(fig)
    assert fig.layout.height <= charts.MAX_GL_PIXELS
    assert_rows_match(fig, "yaxis", [f"p{i}" for i in range(400)])


def test_small_gantt_keeps_sharp_svg_bars_and_its_rows():
    schedule, platform = wide_schedule(rows=4, per_row=3)
    fig = charts.gantt_figure(schedule, platform=platform, critical=[])
    assert not gl_bars(fig)
    assert_rows_match(fig, "yaxis", ["p0", "p1", "p2", "p3"])
    assert "plotGlPixelRatio" not in page_config(fig)
    for bar in fig.data:
        assert set(bar.y) <= {"p0", "p1", "p2", "p3"}


def test_stacked_webgl_gantt_panels_fit_the_canvas_and_keep_their_rows():
    schedule, platform = wide_schedule()
    panels = [charts.GanttPanel(name, schedule, platform) for name in ("heft", "xeft", "cpop")]
    fig = charts.stacked_gantt_figure(panels, "ms", lanes=False)
    assert fig.layout.height * page_config(fig)["plotGlPixelRatio"] <= charts.MAX_GL_PIXELS
    for axis in ("yaxis", "yaxis2", "yaxis3"):
        assert_rows_match(fig, axis, [f"p{i}" for i in range(ROWS)])

"""Numbers people read in chart titles (issue 30: "makespan 1.79478e+06" on a comparison's chart) and the
explanation beside HEFT4K marked best against HEFT."""

import pytest

from apps.scheduling.views import _heft4k_note
from apps.ui import charts
from continuum.engine.core.schedule import Assignment, Schedule


@pytest.mark.parametrize(
    ("value", "unit", "text"),
    [
        (1794780.0, "ms", "1,794,780 ms (29.9 min)"),
        (1.79478e6, "", "1,794,780"),
        (7_200_000.0, "ms", "7,200,000 ms (2.0 h)"),
        (80.0, "ms", "80 ms"),
        (18.53219, "ms", "18.532 ms"),
        (0.25, "s", "0.25 s"),
        (0.0, "ms", "0 ms"),
        (90.0, "s", "90 s (1.5 min)"),
        (3.2e-5, "s", "3.2e-05 s"),
    ],
)
def test_quantity_groups_digits_and_adds_minutes_or_hours(value, unit, text):
    assert charts.quantity(value, unit) == text


def test_gantt_titles_show_the_makespan_with_grouped_digits_and_its_unit():
    long = Schedule("heft", [Assignment("a", "p0", 0.0, 1794780.0)])
    fig = charts.gantt_figure(long, time_unit="ms", critical=[])
    [label] = [a.text for a in fig.layout.annotations if a.text.startswith("makespan")]
    assert label == "makespan 1,794,780 ms (29.9 min)" and "e+" not in label
    stacked = charts.stacked_gantt_figure([charts.GanttPanel("HEFT", long)], "ms", title_sep=": ")
    assert [a.text for a in stacked.layout.annotations] == ["HEFT: makespan 1,794,780 ms (29.9 min)"]


def test_heft4k_best_against_heft_is_explained():
    results = {"heft": {"makespan": 100.0}, "heft4k": {"makespan": 90.0}}
    note = _heft4k_note(["heft", "heft4k"], results, "heft4k")
    assert "10.0% below HEFT" in note and "look-ahead" in note and "Kubernetes" in note
    tie = _heft4k_note(["heft4k", "heft"], {"heft": {"makespan": 90.0}, "heft4k": {"makespan": 90.0}}, "heft4k")
    assert "same makespan" in tie
    assert _heft4k_note(["heft", "heft4k"], results, "heft") == ""
    assert _heft4k_note(["heft4k", "xeft"], results, "heft4k") == ""
